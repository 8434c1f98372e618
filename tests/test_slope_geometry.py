"""Kim, Kang & Choi geometry (Eq. 1, 9-24) against independent constructions; numpy only, fast."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from climb_ompl.mrwallspect.geometry import (
    BodyTrajectory,
    arc_radius,
    edge_clearance,
    foot_on_plane,
    max_d_for_clearance,
    pitch_of,
    rot_y,
    step_schedule,
)

H_ANK, H_F, X_F = 0.12, 0.04, 0.40


def _dist_to_line(p: np.ndarray, a: np.ndarray, t: np.ndarray) -> float:
    v = p - a
    return float(np.linalg.norm(v - (v @ t) * t))


def _surface_distance(p: np.ndarray, tr: BodyTrajectory, length: float = 5.0) -> float:
    """Distance from p to the foot-surface polyline (plane 1 for u <= 0, plane 2 for u >= 0): brute force."""
    u = np.linspace(0.0, length, 20001)
    pts = np.concatenate([-u[:, None] * tr.t1, u[:, None] * tr.t2])
    return float(np.min(np.linalg.norm(pts - p, axis=1)))


def test_radius_formulas_and_pitch_by_hand():
    # Eq. (10)/(11) at 90 degrees: tan(45) = 1, so R = d -/+ h.
    assert arc_radius("concave", math.pi / 2, 0.1, 0.3) == pytest.approx(0.2)
    assert arc_radius("convex", math.pi / 2, 0.1, 0.3) == pytest.approx(0.4)
    # Eq. (15): direction x -> 0; uphill 30 deg -> -30 deg (nose up); straight down -> +90 deg.
    assert pitch_of(np.array([1.0, 0, 0])) == pytest.approx(0.0)
    assert pitch_of(np.array([math.cos(0.5), 0, math.sin(0.5)])) == pytest.approx(-0.5)
    assert pitch_of(np.array([0.0, 0, -1.0])) == pytest.approx(math.pi / 2)
    # R_Y(theta) x = (cos, 0, -sin) (the paper's body rotation)
    assert rot_y(0.3) @ np.array([1.0, 0, 0]) == pytest.approx([math.cos(0.3), 0, -math.sin(0.3)])


@settings(derandomize=True, deadline=None, max_examples=60)
@given(kind=st.sampled_from(["concave", "convex"]), angle_deg=st.floats(5.0, 150.0),
       extra=st.floats(0.02, 0.4))
def test_arc_is_tangent_to_both_body_lines(kind, angle_deg, extra):
    angle = math.radians(angle_deg)
    d = H_ANK * math.tan(angle / 2) + extra  # R > 0 for concave
    tr = BodyTrajectory(kind, angle, H_ANK, H_F, d, X_F)
    H = H_ANK + H_F
    # P_S on body line 1, P_E on body line 2 (Eq. 7-8: n_i . p = eta_i + h with eta_i = h_f)
    assert tr.n1 @ tr.P_S == pytest.approx(H, abs=1e-12)
    assert tr.n2 @ tr.P_E == pytest.approx(H, abs=1e-12)
    # both at distance R from the centre, radius perpendicular to the line there (tangency)
    assert np.linalg.norm(tr.P_S - tr.P_R) == pytest.approx(tr.R, rel=1e-12)
    assert np.linalg.norm(tr.P_E - tr.P_R) == pytest.approx(tr.R, rel=1e-12)
    assert abs((tr.P_S - tr.P_R) @ tr.t1) < 1e-12 and abs((tr.P_E - tr.P_R) @ tr.t2) < 1e-12
    # centre at distance R from both body lines
    assert _dist_to_line(tr.P_R, tr.P_S, tr.t1) == pytest.approx(tr.R, rel=1e-9)
    assert _dist_to_line(tr.P_R, tr.P_E, tr.t2) == pytest.approx(tr.R, rel=1e-9)
    # the arc turns by gamma and its end is P_E
    assert tr.arc_point(angle) == pytest.approx(tr.P_E, abs=1e-12)
    # d: the ankle under P_S is d before the ankle planes' boundary line (definition of d, Eq. 10-11)
    a1 = np.array([[tr.n1[0], tr.n1[2]], [tr.n2[0], tr.n2[2]]])
    vx, vz = np.linalg.solve(a1, [H_F, H_F])
    ankle_corner = np.array([vx, 0.0, vz])
    assert (ankle_corner - (tr.P_S - H_ANK * tr.n1)) @ tr.t1 == pytest.approx(d, rel=1e-9)


@pytest.mark.heavy
@settings(derandomize=True, deadline=None, max_examples=25)
@given(angle_deg=st.floats(10.0, 120.0), extra=st.floats(0.02, 0.3))
def test_concave_front_point_matches_a_brute_force_chord(angle_deg, extra):
    """Eq. (13)/(14) (circle-circle and line-circle) against bisection along the curve."""
    angle = math.radians(angle_deg)
    tr = BodyTrajectory("concave", angle, H_ANK, H_F, H_ANK * math.tan(angle / 2) + extra, X_F)
    for p in np.linspace(0.0, tr.p_end, 9):
        pose = tr.pose(float(p))
        o = tr.curve_point(float(p) - X_F)
        assert pose.origin == pytest.approx(o, abs=1e-12)
        # oracle: the first point along the curve (dense scan, then bisection) at distance X_f from O
        s_scan = np.linspace(float(p) - X_F, float(p) + 3 * X_F, 4001)
        dist = np.array([np.linalg.norm(tr.curve_point(float(s)) - o) for s in s_scan])
        k = int(np.argmax(dist >= X_F))
        lo, hi = float(s_scan[k - 1]), float(s_scan[k])
        for _ in range(100):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if np.linalg.norm(tr.curve_point(mid) - o) < X_F else (lo, mid)
        assert pose.front == pytest.approx(tr.curve_point(lo), abs=1e-9)
        assert np.linalg.norm(pose.front - pose.origin) == pytest.approx(X_F, rel=1e-12)
        # body height: every trajectory point is at least H above both foot planes (inside the wedge)
        for q in (pose.origin, pose.front):
            assert q @ tr.n1 >= H_ANK + H_F - 1e-9 and q @ tr.n2 >= H_ANK + H_F - 1e-9


def test_concave_cases_follow_the_paper_order():
    # 35 deg with a large d: the arc is longer than X_f, so case III occurs (Fig. 6, 9, 10)
    tr = BodyTrajectory("concave", math.radians(35), H_ANK, H_F, 0.4, X_F)
    cases = [tr.pose(float(p)).case for p in np.linspace(-0.1, tr.p_end + 0.1, 400)]
    order = [c for i, c in enumerate(cases) if i == 0 or c != cases[i - 1]]
    assert order == ["approach", "I", "III", "IV", "departure"]
    # small d at 90 deg: the arc is shorter than X_f, so case II instead of III (Fig. 7)
    tr = BodyTrajectory("concave", math.radians(90), H_ANK, H_F, 0.15, X_F)
    cases = [tr.pose(float(p)).case for p in np.linspace(-0.1, tr.p_end + 0.1, 400)]
    order = [c for i, c in enumerate(cases) if i == 0 or c != cases[i - 1]]
    assert order == ["approach", "I", "II", "IV", "departure"]


@pytest.mark.heavy
@settings(derandomize=True, deadline=None, max_examples=25)
@given(angle_deg=st.floats(10.0, 120.0), d=st.floats(0.03, 0.4))
def test_convex_body_is_tangent_to_the_arc_and_continuous(angle_deg, d):
    """Eq. (19)-(21): the body line touches the arc; O starts on line 1 and ends at P_E on line 2."""
    angle = math.radians(angle_deg)
    tr = BodyTrajectory("convex", angle, H_ANK, H_F, d, X_F)
    ps = np.linspace(-0.05, tr.p_end + 0.05, 301)
    poses = [tr.pose(float(p)) for p in ps]
    for pose in poses:
        u = (pose.front - pose.origin) / X_F
        assert np.linalg.norm(pose.front - pose.origin) == pytest.approx(X_F, rel=1e-12)
        assert pitch_of(u) == pytest.approx(pose.pitch, abs=1e-12)
        if 0 <= pose.pitch <= angle:
            assert _dist_to_line(tr.P_R, pose.origin, u) == pytest.approx(tr.R, rel=1e-9)
    start, end = tr.pose(0.0), tr.pose(tr.p_end)
    assert start.front == pytest.approx(tr.P_S, abs=1e-12) and start.origin @ tr.n1 == pytest.approx(H_ANK + H_F)
    assert end.origin == pytest.approx(tr.P_E, abs=1e-12) and end.front @ tr.n2 == pytest.approx(H_ANK + H_F)
    steps = [np.linalg.norm(b.origin - a.origin) for a, b in zip(poses, poses[1:], strict=False)]
    assert max(steps) < 5 * (ps[1] - ps[0]) * (1 + X_F / tr.R)  # no jumps between the cases


@settings(derandomize=True, deadline=None, max_examples=40)
@given(angle_deg=st.floats(10.0, 150.0), d=st.floats(0.02, 0.5))
def test_eq22_is_the_edge_distance_at_the_symmetric_moment_and_the_minimum(angle_deg, d):
    angle = math.radians(angle_deg)
    tr = BodyTrajectory("convex", angle, H_ANK, H_F, d, X_F)
    edge = np.zeros(3)  # the foot surfaces' boundary line passes through the origin

    def h_m(pose):
        u = (pose.front - pose.origin) / X_F
        normal = rot_y(pose.pitch) @ np.array([0.0, 0.0, 1.0])
        assert abs(normal @ u) < 1e-12
        return float((pose.origin - edge) @ normal)

    sym = tr.pose(tr.p_end / 2)
    assert edge_clearance(angle, H_ANK, H_F, d) == pytest.approx(h_m(sym), abs=1e-12)
    others = [h_m(tr.pose(float(p))) for p in np.linspace(0, tr.p_end, 101)]
    if d / math.tan(angle / 2) >= H_F:  # edge beyond the arc centre: Fig. 11's moment is the closest approach
        assert min(others) >= h_m(sym) - 1e-12
    # inverse: the largest d meeting a clearance
    need = 0.06
    dmax = max_d_for_clearance(angle, H_ANK, H_F, need)
    if math.isfinite(dmax) and dmax > 0:
        assert edge_clearance(angle, H_ANK, H_F, dmax) == pytest.approx(need, abs=1e-12)
        assert edge_clearance(angle, H_ANK, H_F, 0.9 * dmax) > need


def test_convex_trajectory_height_bounds():
    """Body points stay between h_m (at the edge) and H (on the lines) from the foot surfaces."""
    tr = BodyTrajectory("convex", math.radians(35), H_ANK, H_F, 0.1, X_F)
    lo = tr.R - float(np.linalg.norm(tr.P_R))  # closest an arc point gets to the edge
    for s in np.linspace(-0.2, tr.arc_len + 0.2, 41):
        dist = _surface_distance(tr.curve_point(float(s)), tr)
        assert lo - 1e-4 <= dist <= H_ANK + H_F + 1e-4


def test_step_schedule_stops_at_the_arc_ends():
    ps = step_schedule(0.0, 1.0, 0.3, (0.4, 0.65))
    assert ps == pytest.approx([0.0, 0.3, 0.4, 0.65, 0.95, 1.0])
    with pytest.raises(ValueError):
        step_schedule(0.0, 1.0, 0.0, ())


@pytest.mark.heavy
@settings(derandomize=True, deadline=None, max_examples=60)
@given(tilt=st.floats(-1.2, 1.2), depth=st.floats(0.05, 0.25), ups=st.floats(0.12, 0.35),
       lateral=st.floats(0.08, 0.25))
def test_foot_on_plane_roots_against_a_dense_scan(tilt, depth, ups, lateral):
    """Eq. (1) on the plane line (Eq. 23-24): every root satisfies Eq. (1); a sign-change scan finds no other."""
    L1 = 0.05
    hip = np.zeros(3)
    ax, la, az = np.array([1.0, 0, 0]), np.array([0, 1.0, 0]), np.array([0, 0, 1.0])
    n = rot_y(tilt) @ az
    t = rot_y(tilt) @ ax
    offset = -depth
    roots = foot_on_plane(hip, ax, az, lateral, la, ups, L1, n, offset, t)
    for p in roots:
        assert p @ n == pytest.approx(offset, abs=1e-12) and p[1] == pytest.approx(lateral, abs=1e-12)
        assert (math.hypot(p[0], p[1]) - L1) ** 2 + p[2] ** 2 == pytest.approx(ups**2, abs=1e-8)
    u = np.linspace(-1.5, 1.5, 300001)
    pts = offset * n + lateral * la + u[:, None] * t
    g = (np.hypot(pts[:, 0], pts[:, 1]) - L1) ** 2 + pts[:, 2] ** 2 - ups**2
    crossings = int(np.sum(np.sign(g[1:]) != np.sign(g[:-1])))
    if min(abs(g)) > 1e-6:  # skip tangency (double roots) where a scan cannot count
        assert len(roots) == crossings
