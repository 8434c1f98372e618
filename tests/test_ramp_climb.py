"""A third-party quadruped (Go1, example-robot-data) climbs a hand-written stepping-stone ramp whose gravity is
tilted: sphere feet touch the stones with their surface, contact torques go through the contact point, and the
goal height is measured along minus gravity."""

from __future__ import annotations

import copy

import numpy as np
import pytest
from conftest import DATA

from climb_ompl.climb.goal import Goal
from climb_ompl.climb.multistep import plan_climb
from climb_ompl.climb.start import find_start
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain
from climb_ompl.plan.file import Plan
from climb_ompl.verification.climb import verify

try:
    from importlib import metadata

    metadata.distribution("example-robot-data")
except metadata.PackageNotFoundError:  # pragma: no cover
    pytest.skip("example-robot-data not installed", allow_module_level=True)

#: Go1's sphere feet (robots/go1.yaml).
RADIUS = 0.02


@pytest.fixture(scope="module")
def ramp() -> Terrain:
    return Terrain.load(DATA / "stepping-stone-ramp.yaml")


def up_height(terrain: Terrain, hold: str) -> float:
    """Oracle: a hold's height along minus gravity, from the gravity vector as written in the file."""
    g = np.array([0.0, -9.476, -2.539])
    return float(terrain.hold(hold).p @ (-g / np.linalg.norm(g)))


@pytest.fixture(scope="module")
def go1_climb(ramp):
    """Go1 from the start finder's stance; the goal: every foot on the third row of stones or above (the rear
    feet start on the first row), as a height along minus gravity."""
    r = RobotModel.load("go1")
    start = find_start(r, ramp, seed=0)
    assert start.found, start.explain()
    reach = max(lb.reach for lb in r.limbs)
    goal = up_height(ramp, "s2_0") + reach - 1e-6
    return r, start, goal, plan_climb(r, ramp, start.stance, goal, q_start=start.q, seed=0, time_limit=120)


@pytest.mark.climb
def test_go1_climbs_the_ramp_and_verifies(go1_climb, ramp):
    r, start, goal, res = go1_climb
    assert res.found, res.reason
    plan = res.plan
    assert len(plan.steps) >= 2
    rep = verify(plan)
    assert rep.ok, [str(v) for v in rep.violations[:10]]
    # the start stance is on the lowest stones; the final one meets the goal along minus gravity
    assert min(up_height(ramp, h) for h in start.stance.values()) == pytest.approx(0.0)
    reach = max(lb.reach for lb in r.limbs)
    assert all(up_height(ramp, h) >= goal - reach for _, h in plan.final_stance)
    assert not all(up_height(ramp, h) >= goal - reach for _, h in plan.start_stance)


@pytest.mark.climb
def test_sphere_feet_touch_the_stones_with_their_surface(go1_climb, ramp):
    """At every waypoint each contact foot's contact point (sphere surface) is on its stone and its centre (the
    hand frame) is one radius off along the stone's normal: the foot does not sink into the stone."""
    r, _, _, res = go1_climb
    assert all(lb.contact.type == "sphere" and lb.contact.radius == RADIUS for lb in r.limbs)
    n_checked = 0
    for s in res.plan.steps:
        for q in s.q:
            for limb, hold in s.stance:
                h = ramp.hold(hold)
                centre = r.hand_position(q, limb)
                assert np.linalg.norm(r.contact_point(q, limb, h.n) - h.p) <= 1e-5
                assert np.linalg.norm(centre - (h.p + RADIUS * h.n)) <= 1e-5
                assert abs((centre - h.p) @ h.n - RADIUS) <= 1e-5
                n_checked += 1
    assert n_checked > 20


@pytest.mark.climb
def test_stored_torques_include_the_moment_about_the_sphere_centre(go1_climb, ramp):
    """The plan's feed-forward torques are g(q) - sum J_c^T f with J_c the Jacobian of the contact point (the
    sphere's surface): they differ from the hand-frame Jacobian's by the moment r n x f, which is not small."""
    r, _, _, res = go1_climb
    s = res.plan.steps[0]
    fs = s.forces[0]
    q = s.q[fs.waypoint]
    forces = dict(fs.forces)
    tau_c = r.gravity_torques(q, ramp.g)
    tau_h = tau_c.copy()
    for limb, hold in s.stance:
        f = np.asarray(forces[limb])
        tau_c = tau_c - r.contact_jacobian(q, limb, ramp.hold(hold).n).T @ f
        tau_h = tau_h - r.hand_jacobian(q, limb).T @ f
    assert np.allclose(fs.torques, tau_c, atol=1e-6)
    assert np.max(np.abs(tau_c - tau_h)) > 1e-3  # N m: the moment about the centre matters


@pytest.mark.climb
def test_verify_measures_the_goal_along_minus_gravity(go1_climb, ramp):
    """The same plan with a goal met in world z but not along minus gravity fails verification (goal)."""
    r, _, _, res = go1_climb
    reach = max(lb.reach for lb in r.limbs)
    final = [h for _, h in res.plan.final_stance]
    lowest_up = min(up_height(ramp, h) for h in final)
    lowest_z = min(ramp.hold(h).p[2] for h in final)
    assert lowest_z > lowest_up + 0.05  # tilted gravity: z and height differ on this ramp
    bad = copy.deepcopy(res.plan.to_dict())
    bad["query"]["goal"] = {"type": "height", "height": 0.5 * (lowest_up + lowest_z) + reach}
    rep = verify(Plan.from_dict(bad))
    assert [v.check for v in rep.violations] == ["goal"]
    assert not Goal.parse(bad["query"]["goal"]["height"]).met(dict(res.plan.final_stance), ramp, reach)
