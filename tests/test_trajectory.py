"""Step timing (toppra) against closed forms, the dynamics slow-down against its exact scaling law, and the
verifier's timing checks on a timed plan and on corrupted copies of it."""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from climb_ompl.model.robot import RobotModel
from climb_ompl.plan.file import Plan
from climb_ompl.trajectory.dynamics import dynamic_torques, torque_allowance
from climb_ompl.trajectory.retime import time_plan, time_step
from climb_ompl.trajectory.timing import distinct, time_path
from climb_ompl.verification import timing as vtiming
from climb_ompl.verification.climb import verify

OLD = Path(__file__).parent / "data" / "plans" / "double-link-pegs-0.1.0.json"


def _line(d: float, n: int = 200) -> np.ndarray:
    return np.outer(np.linspace(0.0, 1.0, n), [d, 0.5 * d])


@pytest.mark.parametrize("d", [0.05, 0.3, 2.0])
def test_a_straight_line_takes_the_bang_coast_bang_time(d):
    # rest to rest over distance d with |v| <= V, |a| <= A: T = d/V + V/A when d >= V^2/A, else 2 sqrt(d/A)
    vmax, amax = np.array([0.8, 0.8]), np.array([3.0, 3.0])
    tp = time_path(_line(d), vmax, amax, np.array([True, True]))
    v, a = 0.8, 3.0
    want = d / v + v / a if d >= v * v / a else 2 * math.sqrt(d / a)
    assert tp.duration == pytest.approx(want, rel=0.02)
    assert np.all(np.abs(tp.velocities[:, 0]) <= v * (1 + 1e-6))
    assert np.all(tp.velocities[[0, -1]] == 0)
    assert np.max(np.abs(tp.velocities[:, 0])) == pytest.approx(min(v, math.sqrt(a * d)), rel=0.02)


def test_an_unactuated_coordinate_is_not_limited():
    # the second coordinate (a base) moves twice as far: only the first one's limits set the time
    q = np.outer(np.linspace(0, 1, 100), [1.0, 2.0])
    free = time_path(q, np.array([1.0, 0.1]), np.array([4.0, 0.4]), np.array([True, False]))
    assert free.duration == pytest.approx(1.0 + 0.25, rel=0.02)
    assert np.max(np.abs(free.velocities[:, 1])) == pytest.approx(2.0, rel=0.02)


def test_repeated_waypoints_share_a_time():
    q = np.repeat(_line(0.3, 50), 2, axis=0)
    r = RobotModel.load("double-link")
    wps = np.zeros((len(q), r.nq))
    act = np.nonzero(r.actuated)[0][:2]
    wps[:, act] = q
    ts = time_step(r, wps)
    assert len(ts.path.times) == len(wps) and len(distinct(wps)) == 50
    assert np.all(ts.path.times[1::2] == ts.path.times[0::2])


def test_the_dynamics_slow_down_meets_its_allowance_exactly():
    # M a + C v scales as 1/k^2 under a uniform slow-down by k: with a small allowance the step is slowed by the
    # square root of its torque ratio, and the verifier's own CRBA torques then sit at the allowance
    r = RobotModel.load("lemur")
    q0 = np.asarray(r.nominal_q, dtype=float)
    wps = np.repeat(q0[None, :], 60, axis=0)
    j = int(np.nonzero(r.actuated)[0][0])
    wps[:, j] += np.linspace(0.0, 0.8, 60)
    fast = time_step(r, wps, static_torques=[np.zeros(r.nq)], fraction=1.0)
    assert fast.slowdown == pytest.approx(1.0, abs=1e-6) and fast.dynamic_ratio < 1
    frac = 0.5 * fast.dynamic_ratio  # half the allowance the fast timing used
    slow = time_step(r, wps, static_torques=[np.zeros(r.nq)], fraction=frac)
    assert slow.by_dynamics and slow.slowdown == pytest.approx(math.sqrt(2.0), rel=1e-6)
    allow = torque_allowance(r, [np.zeros(r.nq)], frac)
    p = slow.path
    tau = vtiming.dynamic_torques(r, p.positions, p.velocities, p.accelerations)
    assert np.allclose(tau, dynamic_torques(r, p.positions, p.velocities, p.accelerations), atol=1e-9)
    lim = np.isfinite(allow)
    assert np.max(np.abs(tau[:, lim]) / allow[lim]) == pytest.approx(1.0, rel=1e-6)


def test_the_allowance_is_a_fraction_of_the_static_margin():
    r = RobotModel.load("lemur")
    static = np.zeros((2, r.nq))
    static[1, 3] = -4.0  # 5 N m limit: 1 N m of margin left
    allow = torque_allowance(r, static, 0.1)
    assert allow[3] == pytest.approx(0.1) and allow[4] == pytest.approx(0.5)
    assert np.all(np.isinf(allow[~r.actuated]))
    assert np.all(np.isinf(torque_allowance(r, [], 0.1)))  # no static torques stored: no bound


@pytest.fixture(scope="module")
def timed_old_plan():
    plan = Plan.load(OLD)
    assert not any(s.timed for s in plan.steps)
    timed, info = time_plan(plan)
    return plan, timed, info


def test_an_old_plan_is_timed_and_still_verifies(timed_old_plan, tmp_path):
    old, timed, info = timed_old_plan
    assert all(s.timed for s in timed.steps) and info["timing"] == "toppra"
    assert [s.waypoints for s in timed.steps] == [s.waypoints for s in old.steps]
    # never faster than every actuated joint at its speed limit all the way (the base is not limited)
    r = RobotModel.load("double-link")
    vmax, act = r.velocity_limits[r.actuated], r.actuated
    for t in timed.steps:
        floor = np.sum(np.max(np.abs(np.diff(t.q[:, act], axis=0)) / vmax, axis=1)) if len(t.q) > 1 else 0.0
        assert t.duration >= floor * (1 - 1e-9)
    f = timed.save(tmp_path / "timed.json")
    back = Plan.load(f)
    assert back.unchanged and back.steps == timed.steps
    rep = verify(back)
    assert rep.ok, rep.summary()


def _edit(plan: Plan, i: int, **kw) -> Plan:
    steps = list(plan.steps)
    steps[i] = dataclasses.replace(steps[i], **kw)
    return dataclasses.replace(plan, steps=tuple(steps))


def test_the_verifier_catches_a_velocity_jump_a_limit_and_motion_from_rest(timed_old_plan):
    _, timed, _ = timed_old_plan
    i = max(range(len(timed.steps)), key=lambda k: len(timed.steps[k].waypoints))
    s = timed.steps[i]
    v = np.array(s.velocities)
    k = len(v) // 2
    jumped = v.copy()
    jumped[k] *= 1.5
    rep = verify(_edit(timed, i, velocities=tuple(map(tuple, jumped))))
    assert {x.check for x in rep.violations} == {"timing"} and any(x.waypoint in (k, k + 1) for x in rep.violations)
    rep = verify(_edit(timed, i, times=tuple(t * 0.5 for t in s.times)))  # twice as fast, velocities as stored
    assert {x.check for x in rep.violations} == {"timing"}
    moving = v.copy()
    moving[0] = v[1]
    rep = verify(_edit(timed, i, velocities=tuple(map(tuple, moving))))
    assert any("not at rest" in x.message for x in rep.violations)


def test_a_timed_plan_plays_on_its_own_clock(timed_old_plan, tmp_path):
    from climb_ompl import viz
    from climb_ompl.viz._plans import parse_climb_steps, timeline

    old, timed, _ = timed_old_plan
    steps = parse_climb_steps(timed.to_dict(), 4)
    frames = timeline(steps, pause=0.0)
    assert frames[-1].t == pytest.approx(timed.execution_s, rel=1e-9)  # real time at speed 1
    for plan in (old, timed):  # a plan of either kind still plays
        assert viz.play(plan.to_dict(), html=tmp_path / "p.html").is_file()


@pytest.mark.climb
def test_a_planned_climb_is_timed_within_its_dynamics_bound():
    from test_verify import planar_plan  # (the same 5-step climb the verifier tests use)

    plan = planar_plan()
    assert all(s.timed for s in plan.steps if len(s.waypoints) > 1)
    assert plan.totals["timing"] == "toppra" and plan.totals["dynamic_ratio"] <= 1 + 1e-9
    assert plan.totals["execution_s"] == pytest.approx(plan.execution_s)
    rep = verify(plan)
    assert rep.ok and rep.counts.get("timing", 0) == 0 and rep.counts.get("dynamics", 0) == 0


def test_a_spec_gives_acceleration_limits_and_a_bad_one_is_named():
    import yaml

    from climb_ompl.errors import RobotModelError
    from climb_ompl.resources import robots_dir, urdf_dir

    spec = yaml.safe_load((robots_dir() / "lemur.yaml").read_text())
    r = RobotModel.from_spec({**spec, "acceleration_limits": {"ne_elbow": 1.5}}, base_dir=urdf_dir())
    j = r.joint_names.index("ne_elbow")
    assert r.acceleration_limits[j] == 1.5
    k = r.joint_names.index("ne_wrist")  # the default: 45 deg/s reached in 0.25 s (Bretl (2006), sec. 5.1)
    assert r.acceleration_limits[k] == pytest.approx(math.radians(45) / 0.25, rel=1e-5)
    with pytest.raises(RobotModelError, match="acceleration_limits.ne_elbow"):
        RobotModel.from_spec({**spec, "acceleration_limits": {"ne_elbow": -1}}, base_dir=urdf_dir())
