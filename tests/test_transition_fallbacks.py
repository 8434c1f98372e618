"""FIND-TRANSITION's fallbacks when the draws about the configuration reached find nothing: the wide draws (a body
that must crouch towards the wall to balance) and the walk (a CoM that must move far to let go of a foot).

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

from climb_ompl.climb.start import find_start
from climb_ompl.climb.transition import TransitionFinder
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.manifold.stance import Stance
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain


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


def assert_transition(robot: RobotModel, terrain: Terrain, big: Stance, small: Stance, q: np.ndarray) -> None:
    """The oracles of a transition between ``big`` and ``small``: every foot of ``big`` on its hold by forward
    kinematics, the joint limits, no collision, and :func:`equilibrium_socp` on the holds of ``small``."""
    for lb, h in big.pairs:
        assert np.linalg.norm(robot.hand_position(q, lb) - robot.hand_target(lb, terrain.hold(h))) < 1e-3
    assert robot.within_limits(q)
    assert not robot.in_collision(q, terrain, contact_limbs=big.limbs)
    assert equilibrium_socp(terrain, list(small.hold_ids), robot.mass, robot.com(q))


@pytest.fixture(scope="module")
def anymal_on_slab():
    """ANYmal-C on the suite's slab, on its nominal layout stretched to 0.9 m (front feet six rows above the hind
    ones), where the start finder used to put it, in the configuration it gives that stance."""
    from climb_ompl.climb.start import StartResult, start_configuration

    robot = RobotModel.load("anymal-c")
    terrain = Terrain.load("slab")
    stance = {"lf": "h6_10", "lh": "h0_10", "rf": "h6_6", "rh": "h0_6"}
    q = start_configuration(robot, terrain, stance, seed=0)
    assert q is not None
    return robot, terrain, StartResult(stance, q, [], 0)


@pytest.mark.heavy
def test_wide_draws_crouch_to_a_grab_the_local_draws_miss(anymal_on_slab):
    robot, terrain, start = anymal_on_slab
    sigma = Stance(start.stance)
    assert sigma["lf"] == "h6_10"
    small = sigma.without("lf")
    big = small.with_hold("lf", "h8_10")
    feas = Feasibility.of(robot, terrain)
    local = TransitionFinder(feas)
    assert all(local.find(small, big, start.q, seed=s) is None for s in range(3))
    wide = TransitionFinder(feas, wide=300)
    found = []
    for s in range(8):  # seeds 2 and 4 succeed on the development machine; more, for another CPU's last bits
        q = wide.find(small, big, start.q, seed=s)
        if q is not None:
            assert wide.stats[-1][0] == local.attempts  # found by the wide draws, after the local ones
            found.append(q)
    assert found
    nominal_y = float(robot.nominal_q[1])
    for q in found:
        assert_transition(robot, terrain, big, small, q)
        assert q[1] < nominal_y - 0.05  # the trunk lowered towards the wall


def test_wide_draws_and_walk_off_by_default(anymal_on_slab):
    robot, terrain, start = anymal_on_slab
    finder = TransitionFinder(Feasibility.of(robot, terrain))
    assert finder.wide == 0 and finder.walk_steps == 0


def slab45() -> Terrain:
    """A user's 45-degree slab: shelves (normals straight up, against gravity) on a 0.15 m grid, friction 0.9, the
    slope expressed by tilting gravity (the frame convention of docs/terrain.md)."""
    c = float(np.sqrt(0.5))
    holds = [{"id": f"r{r}c{k}", "position": [round(-0.75 + 0.15 * k, 2), 0.0, round(0.15 * r, 2)],
              "normal": [0.0, c, c]} for r in range(12) for k in range(11)]
    return Terrain.from_dict({"name": "slab45", "dim": 3, "gravity": [0.0, -9.81 * c, -9.81 * c], "friction": 0.9,
                              "holds": holds})


def test_walk_lets_go_of_a_hind_foot_the_draws_cannot():
    """ANYmal-C at its start on a 45-degree slab (front feet 0.75 m above the hind ones): letting go of a hind foot
    needs the CoM 0.19 m from where it stands, into the three feet's support region.  The draws, each one jump from
    the configuration reached, close no chain that far and find nothing; the walk's small steps, each re-closing
    the chains, find a transition, checked against the same oracles as above."""
    robot, terrain = RobotModel.load("anymal-c"), slab45()
    start = find_start(robot, terrain, seed=0)
    assert start.found and {start.stance["lh"], start.stance["rh"]} <= {f"r0c{k}" for k in range(11)}
    sigma = Stance(start.stance)
    small = sigma.without("lh")
    feas = Feasibility.of(robot, terrain)
    assert feas.region(small).margin(robot.com(start.q)) < -0.1  # the CoM far outside where it stands
    local = TransitionFinder(feas)
    assert all(local.find(sigma, small, start.q, seed=s) is None for s in range(3))
    walker = TransitionFinder(feas, walk=100)
    found = [q for s in range(3) if (q := walker.find(sigma, small, start.q, seed=s)) is not None]
    assert found
    for q in found:
        assert_transition(robot, terrain, sigma, small, q)
