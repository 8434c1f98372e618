"""Stance, stance constraint (analytic Jacobian vs finite differences) and space factory."""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from climb_ompl.errors import PlannerNotFound, QueryError
from climb_ompl.manifold.stance import (
    DEFAULT_TOLERANCE,
    SPACE_NAMES,
    Stance,
    StanceConstraint,
    make_space,
)
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import generate_wall

ROBOT = RobotModel.load("lemur")
WALL = generate_wall(0)


def test_stance_is_a_sorted_hashable_mapping():
    a = Stance({"sw": "h2", "ne": "h1"})
    b = Stance.of(ne="h1", sw="h2")
    assert a == b and hash(a) == hash(b) and a.limbs == ("ne", "sw") and a["sw"] == "h2"
    assert dict(a) == {"ne": "h1", "sw": "h2"}
    assert a.with_hold("nw", "h3").without("nw") == a
    assert a.free_limbs(ROBOT) == ("nw", "se")
    with pytest.raises(QueryError, match="same hold"):
        Stance(ne="h1", sw="h1")


def test_constraint_rows_and_tolerance():
    s = Stance(ne=WALL.holds[60].id, sw=WALL.holds[20].id, se=WALL.holds[22].id)
    c = StanceConstraint(ROBOT, WALL, s)
    assert c.getTolerance() == DEFAULT_TOLERANCE and c.co_dim == 9 and c.manifold_dim == 6


@settings(derandomize=True, deadline=None, max_examples=30)
@given(seed=st.integers(0, 10_000))
def test_jacobian_matches_finite_differences(seed):
    s = Stance(ne=WALL.holds[60].id, sw=WALL.holds[20].id)
    c = StanceConstraint(ROBOT, WALL, s)
    q = np.random.default_rng(seed).uniform(ROBOT.lower, ROBOT.upper)
    J = np.zeros((c.co_dim, c.nq))
    c.jacobian(q, J)
    h = 1e-6
    Jfd = np.array([(c.residual(q + h * e) - c.residual(q - h * e)) / (2 * h) for e in np.eye(c.nq)]).T
    assert np.allclose(J, Jfd, atol=1e-6)
    out = np.zeros(c.co_dim)
    c.function(q, out)
    assert np.allclose(out, c.residual(q))


def test_projection_lands_on_manifold():
    from climb_ompl.climb.multistep import default_start

    stance, q0 = default_start(ROBOT, WALL, seed=0)
    s = Stance(stance).without("se")
    c = StanceConstraint(ROBOT, WALL, s)
    q = np.asarray(q0, dtype=float) + np.random.default_rng(0).normal(0.0, 0.05, ROBOT.nq)  # off the manifold
    assert c.error(q) > DEFAULT_TOLERANCE
    p = c.project_q(q)
    assert p is not None and c.error(p) <= DEFAULT_TOLERANCE


@pytest.mark.parametrize("kind", SPACE_NAMES)
def test_space_factory(kind):
    c = StanceConstraint(ROBOT, WALL, Stance(ne=WALL.holds[60].id))
    b = make_space(c, kind)
    assert b.space.getAmbientDimension() == ROBOT.nq and b.space.getManifoldDimension() == ROBOT.nq - 3


@pytest.mark.parametrize("kind", ["atlas", "tangent_bundle"])
def test_chart_radius_is_ompls_unless_given(kind):
    """The atlas and tangent-bundle spaces keep OMPL's chart radius (0.25) unless ``rho`` is given."""
    c = StanceConstraint(ROBOT, WALL, Stance(ne=WALL.holds[60].id))
    assert make_space(c, kind).space.getRho() == pytest.approx(0.25)
    assert make_space(c, kind, rho=0.6).space.getRho() == pytest.approx(0.6)


def test_space_factory_errors():
    c = StanceConstraint(ROBOT, WALL, Stance(ne=WALL.holds[60].id))
    with pytest.raises(PlannerNotFound, match="tangent_bundle"):
        make_space(c, "bogus")
    with pytest.raises(QueryError, match="charts"):
        make_space(c, "atlas", sampler_allocator=object())


def test_planar_region_membership_and_torque_prefilter():
    """A planar (interval) support region answers contains/margin for (3,) and (N, 3) CoMs and serves
    TorqueChecker's prefilter (Bretl, Latombe & Rock (2003), sec. 3.3: the region is an interval of CoM x)."""
    from climb_ompl.equilibrium import TorqueChecker
    from climb_ompl.manifold.stance import EquilibriumCheck, stance_region
    from climb_ompl.model.terrain import Terrain

    robot = RobotModel.load("planar-3limb")
    terrain = Terrain.from_dict({"name": "p", "dim": 2, "friction": 0.8, "holds": [
        {"id": "a", "position": [-0.35, 0.8], "normal": [0.4, 1]},
        {"id": "b", "position": [0.35, 0.8], "normal": [-0.4, 1]}]})
    s = Stance(limb1="a", limb2="b")
    reg = stance_region(robot, terrain, s)
    lo, hi = reg.interval
    assert lo < 0 < hi
    C = np.array([[0.0, 0.0, 1.0], [hi + 0.01, 0.0, 1.0], [lo - 0.01, 0.0, 3.0]])
    assert reg.contains(C).tolist() == [True, False, False]
    assert reg.contains(C[0]) is True and reg.margin(C[0]) == pytest.approx(min(hi, -lo))
    q = np.array(robot.nominal_q, dtype=float)
    tc = TorqueChecker(s.contacts(terrain), robot.mass, terrain.g, robot.torque_limits, robot.actuated,
                       planar=True, region=reg)
    J = robot.hand_jacobians(q)[[0, 1]]
    g = robot.gravity_torques(q, terrain.g)
    tc(robot.com(q), J, g)  # runs without a shape error
    assert not tc(C[1], J, g)  # outside the interval: rejected by the prefilter
    assert EquilibriumCheck(robot, reg)(q) == bool(reg.contains(robot.com(q)))


def test_torque_check_builds_its_checker_at_the_first_call():
    """A TorqueCheck computes nothing when built (no support region of its own cone model, no LP tableau) and
    answers as an eagerly built TorqueChecker does, configuration by configuration."""
    from climb_ompl.climb.start import find_start
    from climb_ompl.equilibrium import TorqueChecker
    from climb_ompl.manifold.stance import TorqueCheck, _default_cache, limb_index, stance_region

    start = find_start(ROBOT, WALL, seed=0)
    s, q0 = Stance(start.stance), start.q
    reg8 = stance_region(ROBOT, WALL, s, cone_edges=8)
    cache = _default_cache()
    misses = cache.misses
    check = TorqueCheck(ROBOT, WALL, s, reg8, cone_edges=4)
    assert check._checker is None and cache.misses == misses  # nothing computed yet
    eager = TorqueChecker(s.contacts(WALL), ROBOT.mass, WALL.g, ROBOT.torque_limits, ROBOT.actuated,
                          region=stance_region(ROBOT, WALL, s, cone_edges=4), cone_edges=4)
    rng = np.random.default_rng(1)
    answers = []
    base = list(ROBOT.base_indices)
    for k in range(60):
        q = q0.copy()
        q[base] += rng.normal(0.0, 0.05 * (1 + k // 10), len(base))
        J = ROBOT.hand_jacobians(q)[[limb_index(ROBOT, lb) for lb in s.limbs]]
        want = bool(eager(ROBOT.com(q), J, ROBOT.gravity_torques(q, WALL.g)))
        assert check(q) is want
        answers.append(want)
    assert check._checker is not None and check.checker.cone_edges == 4
    assert True in answers and False in answers
    from climb_ompl.errors import EquilibriumError

    with pytest.raises(EquilibriumError, match="cone_edges"):  # a bad argument is refused at once
        TorqueCheck(ROBOT, WALL, s, reg8, cone_edges=2)
