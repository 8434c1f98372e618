"""The ``paper`` search mode: Bretl (2006), Fig. 16 and 17 as published (settings.py, docs/climb.md)."""

from __future__ import annotations

import numpy as np
import pytest

from climb_ompl.climb.edges import P_FAIL_FACTOR, P_INITIAL, EdgeBook
from climb_ompl.climb.multistep import default_start, plan_climb
from climb_ompl.climb.stats import SearchStats
from climb_ompl.climb.transition import TransitionFinder
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.manifold.stance import Stance
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain
from climb_ompl.settings import PAPER_SAMPLER, ClimbSettings
from climb_ompl.verification.climb import verify


def test_the_paper_mode_names_fig_16_and_the_guided_defaults_stay() -> None:
    p, g = ClimbSettings.for_search("paper"), ClimbSettings()
    assert (p.stage2, p.edge_p, p.transition_base, p.resume, p.direct_path) == (
        "recursive", "time", "holds", "queue", False)
    assert (p.planner, p.space, p.sampler, p.heuristic_weight, p.max_edge_failures) == (
        "SBL", "projected", PAPER_SAMPLER, 0.0, 0)
    assert (g.stage2, g.edge_p, g.transition_base, g.resume, g.direct_path, g.path_range) == (
        "repair", "prior", "near", "farthest", True, None)


def test_edge_probability_prior_and_time_based() -> None:
    """Sec. 3.3.3: the fixed prior lowers ``P`` by a factor per failure; the time-based ``P`` is inversely
    proportional to the effort spent on the edge (at least one FIND-PATH budget per failure)."""
    s, t = Stance(a="1", b="2"), Stance(a="1")
    u = type("U", (), {"key": (s, ()), "stance": s})()
    prior, timed = (EdgeBook(ClimbSettings(edge_p=e), SearchStats()) for e in ("prior", "time"))
    prior.path_failed(u, t)
    prior.path_failed(u, t)
    timed.path_failed(u, t, effort=0.25)  # less than a budget: counts as one
    timed.path_failed(u, t, effort=3.0)
    e = (u.key, t)
    assert prior.p(e) == pytest.approx(P_INITIAL * P_FAIL_FACTOR ** 2)
    assert timed.p(e) == pytest.approx(P_INITIAL / (1.0 + 4.0))
    assert timed.cost(u.key, t) == pytest.approx(1.0 - np.log(P_INITIAL / 5.0))
    assert timed.p((u.key, Stance(b="2"))) == P_INITIAL


def test_find_transition_draws_the_base_among_the_holds_as_fig_17() -> None:
    """Fig. 17 line 2 samples the pelvis "within distance 2L from holds j, k, g", not about where the robot stands:
    with ``transition_base = "holds"`` a release's transition (every limb on a hold, none free) is the same from a
    reference posture 0.3 m to the side as from the start, and it is a transition; the draws about the reference
    posture (``near``) give another."""
    robot, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    stance, q0 = default_start(robot, wall, seed=0)
    big = Stance(**dict(stance))
    limb = sorted(dict(stance))[0]
    small = Stance(**{k: v for k, v in dict(stance).items() if k != limb})
    q0 = np.asarray(q0, dtype=float)
    far = q0.copy()
    far[robot.base_indices[0]] += 0.3
    feas = Feasibility.of(robot, wall, ClimbSettings())
    holds = TransitionFinder.of(feas, ClimbSettings(transition_base="holds", elbow_bends="enumerate"))
    a, b = holds.find(big, small, q0, seed=3), holds.find(big, small, far, seed=3)
    assert a is not None and b is not None and np.allclose(a, b)
    assert feas.why(feas.transition_checks(small, big), a) is None
    near = TransitionFinder.of(feas, ClimbSettings()).find(big, small, q0, seed=3)
    assert near is None or not np.allclose(near, a)


@pytest.mark.climb
def test_the_paper_mode_finds_fig_13s_route_for_the_double_link_robot() -> None:
    """Bretl (2006), Fig. 13: 1 -> 2 -> 3 -> 2 -> 4, found by the search of Fig. 16 as published."""
    q0 = [1.70, 0.90, 0.5 - 2 * np.pi, 1.0]
    settings = ClimbSettings.for_search("paper", time_limit=240)
    res = plan_climb("double-link", "pegs", {"a": "1"}, "a=4", settings, q_start=q0, seed=0)
    assert res.found, res.reason
    assert [s.hold for s in res.plan.steps if s.action == "grab"] == ["2", "3", "2", "4"]
    assert verify(res.plan).ok


@pytest.mark.climb
def test_the_paper_mode_climbs_the_planar_robot_a_short_way() -> None:
    """Bretl, Latombe & Rock (2003): the planar three-limbed robot on its crack, planned by Fig. 16 as published
    (a 1 m goal: the paper mode's candidates up to 2 m mostly fail at FIND-PATH, docs/papers.md)."""
    robot, wall = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    stance, q0 = default_start(robot, wall, seed=0)
    res = plan_climb(robot, wall, stance, 1.0, ClimbSettings.for_search("paper", time_limit=90), q_start=q0, seed=0)
    assert res.found, res.reason
    assert len(res.plan.steps) >= 3 and {s.action for s in res.plan.steps} == {"grab", "release"}
    assert verify(res.plan).ok
