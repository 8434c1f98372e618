"""FIND-TRANSITION's wide draws: a body that must crouch towards the wall to balance.

On the suite's slab (15 degrees, ledges whose normals lean 70 degrees up from the wall, friction 0.9) the support
region lets the CoM stand off the wall at most ``0.553 L`` at the top holds and ``0.285 L`` at the bottom ones of a
stance ``L`` long (tests/test_equilibrium_standoff.py); ANYmal-C's nominal stand-off is 0.48 m.  From its start on
the slab, with the front left foot released, grabbing a hold two rows higher needs the trunk lowered by about 0.1 m
and moved up the wall: the draws about the configuration reached do not get there, the wide draws do.  The
transition found is checked against independent oracles: the feet on their holds by forward kinematics, the joint
limits, and static equilibrium with second-order friction cones solved by cvxpy (the planner's linearised cones are
inscribed in them).
"""

from __future__ import annotations

import warnings

import cvxpy as cp
import numpy as np
import pytest
from conftest import ROOT

from climb_ompl.feasibility import Feasibility
from climb_ompl.robot import RobotModel
from climb_ompl.stance import Stance
from climb_ompl.start import find_start
from climb_ompl.terrain import Terrain
from climb_ompl.transition import TransitionFinder, base_translations


def equilibrium_socp(terrain: Terrain, holds: list[str], mass: float, com: np.ndarray) -> bool:
    """Static equilibrium of a CoM at ``com`` on ``holds`` (Bretl 2006, eqs. (B1)-(B3), exact cones)."""
    f = cp.Variable((len(holds), 3))
    g = terrain.g
    cons = [cp.sum(f, axis=0) + mass * g == 0]
    ps = [terrain.hold(h).p for h in holds]
    moment = sum(cp.hstack([p[1] * f[i, 2] - p[2] * f[i, 1], p[2] * f[i, 0] - p[0] * f[i, 2],
                            p[0] * f[i, 1] - p[1] * f[i, 0]]) for i, p in enumerate(ps))
    cons.append(moment + np.cross(com, mass * g) == 0)
    for i, h in enumerate(holds):
        n = terrain.hold(h).n / np.linalg.norm(terrain.hold(h).n)
        cons.append(cp.norm((np.eye(3) - np.outer(n, n)) @ f[i]) <= terrain.hold(h).friction * (n @ f[i]))
    prob = cp.Problem(cp.Minimize(0), cons)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prob.solve(solver="CLARABEL")
    return prob.status == "optimal"


@pytest.fixture(scope="module")
def anymal_on_slab():
    robot = RobotModel.load("anymal-c")
    terrain = Terrain.load(ROOT / "climb_ompl" / "data" / "terrains" / "slab.yaml")
    start = find_start(robot, terrain, seed=0)
    assert start.found
    return robot, terrain, start


def test_wide_draws_crouch_to_a_grab_the_local_draws_miss(anymal_on_slab):
    robot, terrain, start = anymal_on_slab
    sigma = Stance(start.stance)
    assert sigma["lf"] == "h6_10"
    small = sigma.without("lf")
    big = small.with_hold("lf", "h8_10")
    feas = Feasibility.of(robot, terrain)
    local = TransitionFinder(feas)
    assert all(local.find(small, big, start.q, seed=s) is None for s in range(3))
    wide = TransitionFinder(feas, wide=150)
    found = []
    for s in range(8):  # seeds 2 and 3 succeed on the development machine; more, for another CPU's last bits
        q = wide.find(small, big, start.q, seed=s)
        if q is not None:
            assert wide.stats[-1][0] == local.attempts  # found by the wide draws, after the local ones
            found.append(q)
    assert found
    nominal_y = float(robot.nominal_q[1])
    for q in found:
        for lb, h in big.pairs:
            assert np.linalg.norm(robot.hand_position(q, lb) - robot.hand_target(lb, terrain.hold(h))) < 1e-3
        assert robot.within_limits(q)
        assert not robot.in_collision(q, terrain, contact_limbs=big.limbs)
        assert equilibrium_socp(terrain, list(small.hold_ids), robot.mass, robot.com(q))
        assert q[1] < nominal_y - 0.05  # the trunk lowered towards the wall


def test_wide_draws_off_by_default(anymal_on_slab):
    robot, terrain, start = anymal_on_slab
    assert TransitionFinder(Feasibility.of(robot, terrain)).wide == 0


@pytest.mark.parametrize("name, want", [("anymal-c", [0, 1, 2]), ("go1", [0, 1, 2]), ("lemur", [0, 1]),
                                        ("mrwallspect3", [0, 1])])
def test_base_translations(name, want):
    robot = RobotModel.load(name)
    idx, dirs = base_translations(robot)
    assert idx == want
    assert dirs.shape == (3, len(want))
    if want:
        assert np.allclose(np.abs(dirs).sum(axis=0), 1.0) and np.allclose(np.linalg.norm(dirs, axis=0), 1.0)
