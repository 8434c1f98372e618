"""TreeBot: rear gripper on the bark (Fig. 10), what the Fig. 13 figures measure, proposed vs. simple."""

from __future__ import annotations

import numpy as np
import pytest

from climb_ompl.bench.treebot import planar_path
from climb_ompl.treebot import RobotParams, Tree, plan_motion, plan_path
from climb_ompl.treebot.compare import compare_path, evaluate, point_polyline_distance, with_lead_in
from climb_ompl.treebot.fit import contraction


def test_contraction_lands_in_the_tangent_plane():
    """Fig. 10: normal on x, direction on z; the rear gripper lands on the front's tangent plane even when
    the body arrives tilted out of it (the old frame, normal orthogonalised against the tilted direction,
    put the rear gripper 1-2 cm inside or above the bark)."""
    rng = np.random.default_rng(7)
    for _ in range(50):
        n = rng.normal(size=3)
        n /= np.linalg.norm(n)
        t = np.cross(n, rng.normal(size=3))
        t /= np.linalg.norm(t)
        tilt = rng.uniform(-0.3, 0.3)
        d = np.cos(tilt) * t + np.sin(tilt) * n  # arrives up to 17 degrees out of the tangent plane
        front = rng.normal(size=3)
        for v in (d, rng.normal(size=3)):  # simple method (v = front direction) and an arbitrary v_rg
            rear, rdir, _ = contraction(front, d, n, v, 0.12)
            assert abs((rear - front) @ n) < 1e-12 and abs(rdir @ n) < 1e-12
            assert 0.12 * 2 / np.pi - 1e-12 <= np.linalg.norm(rear - front) <= 0.12 + 1e-12  # chord, bend <= pi
        rear, rdir, th = contraction(front, d, n, d, 0.12)  # simple: straight body along the seated direction
        assert th == pytest.approx(0.0, abs=1e-12) and rdir @ t == pytest.approx(1.0)


def test_rear_gripper_stays_on_the_bark_along_a_climb():
    t = Tree.load("three-branch")
    res = plan_path(t, "b2")
    P = np.array([p.position for p in res.path])
    N = np.array([p.normal for p in res.path])
    for method in ("proposed", "simple"):
        mo = plan_motion(P, N, t.robot, method)
        ends = [[f for f in mo.frames if f.phase == "contract" and f.step == s][-1] for s in range(len(mo.steps) - 1)]
        for s, f in enumerate(ends):
            assert abs((f.rear - f.front) @ N[mo.targets[s + 1]]) < 1e-9, (method, s)


def test_following_error_is_measured_on_the_drawn_postures():
    """Fig. 13 draws the body at the end of each extension; the shapes in between are interpolation."""
    t = Tree.load("three-branch")
    res = plan_path(t, "b2")
    P = np.array([p.position for p in res.path])
    N = np.array([p.normal for p in res.path])
    mo = plan_motion(P, N, t.robot, "simple")
    m = evaluate(mo, P, N, np.empty((0, 3)), t.robot.s_min, t.robot.s_max)
    ref = with_lead_in(P, N, t.robot.s_min)
    for k in range(len(mo.steps)):
        ext = [f for f in mo.frames if f.phase == "extend" and f.step == k]
        assert m.errors[k] == pytest.approx(point_polyline_distance(ext[-1].body, ref).max())
    assert m.swept_mean_error >= m.mean_error and m.swept_max_error >= m.max_error
    assert 0 < m.segment_mean_error <= m.mean_error + 1e-3


def test_proposed_wins_on_a_smooth_curved_path():
    """Where the paper's assumptions hold (a smooth path, fitted arcs that continue behind the segment), the
    proposed method follows far better than the simple one: Fig. 13's conclusion."""
    robot = RobotParams()
    P, N = planar_path(lambda s: 2.0 + 0.0 * s)
    c = compare_path(P, N, robot)
    assert c["proposed"].mean_error < 0.005 < c["simple"].mean_error
    assert max(c["proposed"].errors[3:]) < 0.002 < 0.005 < min(c["simple"].errors[3:])  # after the start-up
    assert c["proposed"].segment_mean_error < 0.5 * c["simple"].segment_mean_error
    assert c["proposed"].length_violations == c["simple"].length_violations == 0
