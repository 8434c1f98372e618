"""The independent verifier: a real plan passes; each kind of corruption is caught, named and located;
its per-point equilibrium programs agree with the equilibrium module's support regions."""

from __future__ import annotations

import dataclasses
import json
from functools import lru_cache

import numpy as np
import pytest

from climb_ompl.climb.multistep import default_start, plan_climb
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain
from climb_ompl.plan.file import ForceSample, Plan, Step
from climb_ompl.verification.climb import _ContactSet, _lp_feasible, _socp_feasible, verify


@lru_cache(maxsize=1)
def planar_plan() -> Plan:
    """A 5-step climb of the planar three-limbed robot on the bundled crack, as in Bretl, Latombe & Rock (2003)."""
    robot, wall = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    stance, q0 = default_start(robot, wall, seed=0)
    res = plan_climb(robot, wall, stance, 1.6, q_start=q0, time_limit=60, seed=0)
    assert res.found, res.reason
    return res.plan


def replace_step(plan: Plan, i: int, **kw) -> Plan:
    steps = list(plan.steps)
    steps[i] = dataclasses.replace(steps[i], **kw)
    return dataclasses.replace(plan, steps=tuple(steps))


def moving_step(plan: Plan) -> int:
    return next(s.index for s in plan.steps if len(s.waypoints) > 20)


@pytest.mark.climb
def test_real_plan_is_valid_from_its_file_alone(tmp_path):
    plan = planar_plan()
    f = plan.save(tmp_path / "p.json")
    rep = verify(f)
    assert rep.ok, [str(v) for v in rep.violations]
    assert rep.steps_checked == len(plan.steps) and rep.states_checked > sum(len(s.waypoints) for s in plan.steps)
    assert rep.lp_solves >= rep.states_checked


@pytest.mark.climb
def test_hand_off_its_hold_is_reported_at_that_waypoint():
    plan = planar_plan()
    i = moving_step(plan)
    w = [list(x) for x in plan.steps[i].waypoints]
    w[7][0] += 1e-3  # base x: every contact hand moves 1 mm
    rep = verify(replace_step(plan, i, waypoints=tuple(tuple(x) for x in w)))
    hits = [v for v in rep.violations if v.check == "hands_on_holds"]
    assert hits and {v.step for v in hits} == {i}
    assert any(v.waypoint == 7 for v in hits)
    assert all(6 < v.waypoint < 8 for v in hits)  # the waypoint and the motion next to it only


@pytest.mark.climb
def test_joint_limit_timing_continuity_and_integrity():
    plan = planar_plan()
    robot = RobotModel.load("planar-3limb")
    i = moving_step(plan)
    w = [list(x) for x in plan.steps[i].waypoints]
    j = robot.limbs[0].joint_indices[0]
    w[3][j] = float(robot.upper[j]) + 0.2
    rep = verify(replace_step(plan, i, waypoints=tuple(tuple(x) for x in w)))
    assert any(v.check == "joint_limits" and v.step == i and v.waypoint == 3 for v in rep.violations)

    fast = tuple(t * 0.5 for t in plan.steps[i].times)
    rep = verify(replace_step(plan, i, times=fast))
    assert {v.check for v in rep.violations} == {"timing"}
    # the joint is named, not only numbered
    assert all(any(f"joint {n!r}" in v.message for n in robot.joint_names if n) for v in rep.violations)

    w = [list(x) for x in plan.steps[i].waypoints]
    w[0][0] += 0.01
    rep = verify(replace_step(plan, i, waypoints=tuple(tuple(x) for x in w)))
    assert any(v.check == "continuity" and v.step == i for v in rep.violations)

    d = json.loads(plan.to_json())  # a deep copy: the cached plan stays intact
    d["terrain"]["data"]["holds"][0]["friction"] = 5.0
    rep = verify(Plan.from_dict(json.loads(json.dumps(d))))
    assert any(v.check == "integrity" and "terrain" in v.message for v in rep.violations)


@pytest.mark.climb
def test_two_contacts_changed_at_once_is_a_stance_violation():
    plan = planar_plan()
    s0 = plan.steps[0]
    other = next(h.id for h in Terrain.load("planar-wall").holds if h.id not in dict(s0.stance).values())
    bad = dict(s0.stance)
    first = sorted(bad)[0]
    bad[first] = other  # the plan claims a stance that differs from the start stance
    rep = verify(replace_step(plan, 0, stance=tuple(sorted(bad.items()))))
    assert any(v.check == "stance_change" and v.step == 0 for v in rep.violations)


@pytest.mark.climb
def test_com_outside_support_is_an_equilibrium_violation():
    """Move the whole robot up to 0.3 m sideways with hands following: equilibrium (and hands) break.  The first
    waypoint of a moving step (every fifth from the fifth on) where some shift puts the CoM 2 cm or more outside
    the support interval with every hand closed on its hold is replaced by the worst such configuration."""
    plan = planar_plan()
    robot = RobotModel.load("planar-3limb")
    wall = Terrain.load("planar-wall")
    # a configuration of the same stance, hands on holds (closed by IK), with the pelvis moved sideways
    # until the CoM leaves the support interval (Bretl, Latombe & Rock (2003), Eq. 1)
    from climb_ompl.manifold.stance import Stance, stance_region

    def pushed_out(stance, q):
        region = stance_region(robot, wall, Stance(stance))
        best = None
        for dx in np.linspace(-0.3, 0.3, 61):
            y = q.copy()
            y[0] += dx
            for limb, hold in sorted(stance.items()):
                sols = robot.limb_ik(limb, y, wall.hold(hold).p)
                if not sols:
                    break
                y = sols[0]
            else:
                m = float(region.margin(robot.com(y)))
                if m < -0.02 and (best is None or m < best[0]):
                    best = (m, y)
        return best

    found = next(((s.index, k, b) for s in plan.steps if len(s.waypoints) > 20 for k in range(5, len(s.waypoints), 5)
                  if (b := pushed_out(dict(s.stance), np.array(s.waypoints[k]))) is not None), None)
    assert found is not None, "no configuration with the CoM outside the support interval"
    i, k, best = found
    w = [list(x) for x in plan.steps[i].waypoints]
    w[k] = list(best[1])
    rep = verify(replace_step(plan, i, waypoints=tuple(tuple(x) for x in w)))
    assert any(v.check == "equilibrium" and v.step == i and v.waypoint == k for v in rep.violations)


@pytest.mark.climb
def test_tampered_forces_are_caught():
    plan = planar_plan()
    s = plan.steps[moving_step(plan)]
    fs = s.forces[0]
    scaled = ForceSample(fs.waypoint, tuple((k, tuple(1.5 * x for x in v)) for k, v in fs.forces), fs.torques,
                         fs.margin)
    rep = verify(replace_step(plan, s.index, forces=(scaled,) + s.forces[1:]))
    msgs = [v.message for v in rep.violations if v.check == "forces" and v.step == s.index]
    assert any("balance gravity" in m for m in msgs)
    assert any("torques differ" in m for m in msgs)


@pytest.mark.climb
def test_goal_not_reached_is_reported():
    plan = planar_plan()
    q = dict(plan.query)
    q["goal"] = {"type": "height", "height": 3.5}
    rep = verify(dataclasses.replace(plan, query=q))
    assert [v.check for v in rep.violations] == ["goal"]


@pytest.mark.climb
def test_empty_step_list_still_checks_the_start():
    plan = planar_plan()
    rep = verify(dataclasses.replace(plan, steps=(), totals={**plan.totals, "steps": 0}))
    assert [v.check for v in rep.violations] == ["goal"]
    assert isinstance(Step, type)
    # with no step, the start configuration is the whole plan: a body 1 cm off takes every hand off its hold
    q = dict(plan.query)
    q["start"] = {**q["start"], "q": [float(x) + (0.01 if i == 0 else 0.0) for i, x in enumerate(q["start"]["q"])]}
    rep = verify(dataclasses.replace(plan, steps=(), query=q, totals={**plan.totals, "steps": 0}))
    assert sorted(set(v.check for v in rep.violations)) == ["goal", "hands_on_holds"], rep.violations
    assert rep.counts["hands_on_holds"] == len(plan.start_stance)


@pytest.mark.heavy
@pytest.mark.parametrize("seed", range(4))
def test_per_point_programs_agree_with_the_support_region(seed):
    """Oracle: verify's LP (inscribed pyramids) implies its SOCP (exact cones); the SOCP agrees with the
    equilibrium module's exact-cone support region away from the boundary (different method)."""
    from climb_ompl.equilibrium import Contact, support_region

    rng = np.random.default_rng(seed)
    wall = Terrain.load("demo-wall")
    ids = rng.choice(len(wall.holds), 3, replace=False)
    holds = [wall.holds[i] for i in sorted(ids)]
    if max(np.linalg.norm(a.p - b.p) for a in holds for b in holds) > 0.8:
        holds = [wall.holds[i] for i in (60, 61, 71)]
    mass, g = 7.0, wall.g
    region = support_region([Contact.from_hold(h) for h in holds], mass, g, exact=True)
    cs = _ContactSet(holds, 8)
    centre = np.mean([h.p for h in holds], axis=0)
    agree = 0
    for _ in range(40):
        com = centre + np.array([rng.uniform(-0.6, 0.6), rng.uniform(0.0, 0.2), rng.uniform(-0.3, 0.3)])
        lp = _lp_feasible(cs, mass, g, com, False, None)
        socp = _socp_feasible(holds, mass, g, com, False, None)
        if lp:
            assert socp
        m = float(region.margin(com))
        if abs(m) > 5e-3:
            assert socp == (m > 0), (com, m)
            agree += 1
    assert agree >= 20


@pytest.mark.parametrize("seed", range(3))
def test_per_point_lp_decides_as_scipy_linprog(seed):
    """Oracle: scipy's ``linprog`` (HiGHS behind its checks and conversions) on the same random systems, half of
    them feasible by construction; and a finer pyramid accepts every point the coarser one accepts."""
    from scipy.optimize import linprog

    from climb_ompl.verification.climb import _feasible

    rng = np.random.default_rng(seed)
    decided = set()
    for _ in range(60):
        n, m_eq, m_ub = rng.integers(4, 14), rng.integers(1, 5), rng.integers(0, 6)
        a_eq = rng.normal(size=(m_eq, n))
        lo = np.where(rng.random(n) < 0.8, 0.0, -rng.random(n))
        hi = np.where(rng.random(n) < 0.7, np.inf, rng.uniform(0.5, 2.0, n))
        x0 = np.clip(rng.uniform(0, 1.5, n), lo, hi)
        b_eq = a_eq @ x0 + (rng.normal(size=m_eq) * 5 if rng.random() < 0.5 else 0.0)
        a_ub = rng.normal(size=(m_ub, n)) if m_ub else None
        b_ub = a_ub @ x0 + rng.uniform(-1, 1, m_ub) if m_ub else None
        want = linprog(np.zeros(n), A_ub=a_ub, b_ub=b_ub, A_eq=a_eq, b_eq=b_eq,
                       bounds=list(zip(lo, [None if np.isinf(h) else h for h in hi], strict=True)),
                       method="highs").status == 0
        assert _feasible(a_eq, b_eq, a_ub, b_ub, lo, hi) == want
        decided.add(want)
    assert decided == {True, False}
    wall = Terrain.load("demo-wall")
    holds = [wall.holds[i] for i in (60, 61, 71)]
    centre = np.mean([h.p for h in holds], axis=0)
    coarse, fine = _ContactSet(holds, 8), _ContactSet(holds, 32)
    for _ in range(60):
        com = centre + np.array([rng.uniform(-0.6, 0.6), rng.uniform(0.0, 0.2), rng.uniform(-0.3, 0.3)])
        if _lp_feasible(coarse, 7.0, wall.g, com, False, None):
            assert _lp_feasible(fine, 7.0, wall.g, com, False, None)


@pytest.mark.climb
def test_package_exports_resolve_to_the_climb_modules():
    import climb_ompl
    import climb_ompl.verification as vpkg
    from climb_ompl.climb.multistep import plan_climb as pc

    assert climb_ompl.plan_climb is pc
    assert climb_ompl.verify is vpkg.verify  # a function: no submodule of that name shadows it
    assert climb_ompl.verify(planar_plan()).ok
