"""TreeBot continuum body (Lam et al., Eq. 1-3), plane/arc fits (Eq. 8-18), contraction (Eq. 19-20), motion."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy.optimize import minimize_scalar

from climb_ompl.treebot import Tree, generate_tree, plan_motion, plan_path
from climb_ompl.treebot.body import arc_end_tangent, arc_points, gripper_frame, posture
from climb_ompl.treebot.fit import (
    circle_through_ends,
    circle_through_ends_geometric,
    contraction,
    fit_segment,
    plane_angle,
    rear_direction,
)

coord = st.floats(-0.4, 0.4, allow_nan=False)


@settings(derandomize=True, deadline=None, max_examples=300)
@given(coord, coord, st.floats(0.01, 0.5))
def test_arc_ends_at_the_target(x, y, z):
    p = posture(np.array([x, y, z]))
    pts = arc_points(p, 2000)
    assert np.linalg.norm(pts[-1] - [x, y, z]) < 1e-9
    assert np.allclose(pts[0], 0.0)
    # S is the arc length (independent: the length of a fine polyline), and the arc leaves along +z
    assert np.sum(np.linalg.norm(np.diff(pts, axis=0), axis=1)) == pytest.approx(p.S, rel=1e-6, abs=1e-12)
    t0 = (pts[1] - pts[0]) / np.linalg.norm(pts[1] - pts[0])
    assert t0 @ [0, 0, 1] > 1 - 1e-5
    t_end = (pts[-1] - pts[-2]) / np.linalg.norm(pts[-1] - pts[-2])
    assert t_end @ arc_end_tangent(p) > 1 - 1e-5


def test_straight_posture():
    p = posture(np.array([0.0, 0.0, 0.3]))
    assert p.kappa == 0.0 and p.S == pytest.approx(0.3)


@settings(derandomize=True, deadline=None, max_examples=100)
@given(st.lists(st.tuples(coord, coord), min_size=3, max_size=20))
def test_plane_angle_minimises_eq8(xy):
    a = np.array(xy)
    x, y = a[:, 0], a[:, 1]
    tp = plane_angle(x, y)
    # oracle: the direction (cos tp, -sin tp) minimising the quadratic form is the scatter matrix's
    # eigenvector of the smallest eigenvalue
    w, _ = np.linalg.eigh(np.array([[x @ x, x @ y], [x @ y, y @ y]]))
    resid = np.sum((x * math.cos(tp) - y * math.sin(tp)) ** 2)
    assert resid == pytest.approx(w[0], abs=1e-9 * (1 + w[1]))


def random_arc(rng, n=15, noise=0.0):
    """Points of a random circular arc in a random 3-D plane, with its radius and plane."""
    R = float(rng.uniform(0.15, 1.0))
    ang = np.sort(rng.uniform(0, 1.2 * 0.3 / R, n))
    ang -= ang[0]
    loc = np.stack([R * (1 - np.cos(ang)), np.zeros(n), R * np.sin(ang)], 1)
    Q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
    pts = loc @ Q.T + rng.normal(size=3)
    pts[1:-1] += rng.normal(scale=noise, size=(n - 2, 3))
    return pts, R, Q, ang


def test_fits_recover_an_exact_arc():
    rng = np.random.default_rng(0)
    for _ in range(30):
        pts, R, Q, ang = random_arc(rng)
        for geometric in (True, False):
            f = fit_segment(pts, geometric=geometric)
            assert np.abs(f.local[:, 0]).max() < 1e-9  # the plane fit puts the arc in the y-z plane
            assert f.radius == pytest.approx(R, rel=1e-6)
            arc = f.arc_world(50)
            assert np.linalg.norm(arc[0] - pts[0]) < 1e-9 and np.linalg.norm(arc[-1] - pts[-1]) < 1e-9
        # Eq. 18: the rear direction is the circle's tangent s_min before the start
        v = rear_direction(fit_segment(pts), 0.12)
        a = -0.12 / R
        assert v @ (Q @ [math.sin(a), 0.0, math.cos(a)]) == pytest.approx(1.0, abs=1e-6)


def test_algebraic_circle_is_the_least_squares_minimiser():
    rng = np.random.default_rng(3)
    for _ in range(20):
        pts, *_ = random_arc(rng, noise=0.005)
        q = fit_segment(pts).local
        y, z = q[:, 1], q[:, 2]
        yc, zc, r = circle_through_ends(y, z)
        assert math.hypot(y[-1] - yc, z[-1] - zc) == pytest.approx(r, rel=1e-9)  # through both ends
        a = ((y[0] ** 2 + z[0] ** 2) - (y[-1] ** 2 + z[-1] ** 2)) / (2 * (z[0] - z[-1]))
        b = (y[0] - y[-1]) / (z[0] - z[-1])

        def obj(c, a=a, b=b, y=y, z=z):  # sum of the squared errors of Eq. 14 over the circles through both ends
            cz = a - b * c
            return np.sum(((y - c) ** 2 + (z - cz) ** 2 - ((y[0] - c) ** 2 + (z[0] - cz) ** 2)) ** 2)

        ref = minimize_scalar(obj, bracket=(yc - 1, yc + 1), tol=1e-12)
        assert obj(yc) <= obj(ref.x) * (1 + 1e-9) + 1e-30
        # the geometric fit is never worse in geometric error
        yg, zg, rg = circle_through_ends_geometric(y, z)

        def geo(cy, cz, rr, y=y, z=z):
            return np.sum((np.hypot(y - cy, z - cz) - rr) ** 2)
        assert geo(yg, zg, rg) <= geo(yc, zc, r) + 1e-15


def test_contraction_matches_eq19_20():
    rng = np.random.default_rng(4)
    for _ in range(50):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        d = np.cross(n, rng.normal(size=3))
        d /= np.linalg.norm(d)
        front = rng.normal(size=3)
        v = rng.normal(size=3)
        rear, rdir, th = contraction(front, d, n, v, 0.12)
        # Eq. 1-3 from the rear gripper reproduce the contracted body: S = S_min, kappa = |theta_rg| / S_min
        R = gripper_frame(rdir, n)
        p = posture(R.T @ (front - rear))
        assert p.S == pytest.approx(0.12, abs=1e-9)
        assert p.kappa == pytest.approx(abs(th) / 0.12, abs=1e-7)
        assert R @ arc_end_tangent(p) @ d == pytest.approx(1.0, abs=1e-9)  # the front keeps its direction
        # the rear direction is v projected on the surface's tangent plane
        vp = v - (v @ n) * n
        assert rdir @ vp / np.linalg.norm(vp) == pytest.approx(1.0, abs=1e-9)


def motions():
    for name in ("three-branch", "young-oak"):
        t = Tree.load(name)
        for b in t.branches[1:]:
            yield t, b.name
    for seed in range(4):
        t = generate_tree(100 + seed, n_branches=3)
        yield t, t.branches[-1].name


@pytest.mark.heavy
def test_motion_kinematics_on_trees():
    count = 0
    for t, target in motions():
        res = plan_path(t, target)
        if not res.found:
            continue
        P = np.array([p.position for p in res.path])
        N = np.array([p.normal for p in res.path])
        for method in ("proposed", "simple"):
            mo = plan_motion(P, N, t.robot, method)
            count += 1
            ext_ends = {}
            for f in mo.frames:
                assert np.linalg.norm(f.body[0] - f.rear) < 1e-9 and np.linalg.norm(f.body[-1] - f.front) < 1e-9
                if f.phase == "extend":
                    ext_ends[f.step] = f.front
            for s, tgt in enumerate(mo.targets[1:]):
                assert np.linalg.norm(ext_ends[s] - P[tgt]) < 1e-9  # the front gripper lands on the path
            # consecutive frames join: the holding gripper does not move
            for f, g in zip(mo.frames, mo.frames[1:], strict=False):
                held = f.rear if g.phase == "extend" else f.front
                assert np.linalg.norm(held - (g.rear if g.phase == "extend" else g.front)) < 1e-9
            if method == "proposed":
                S = mo.lengths()
                assert S.min() >= t.robot.s_min - 1e-9 and S.max() <= t.robot.s_max, (t.name, target)
    assert count >= 10
