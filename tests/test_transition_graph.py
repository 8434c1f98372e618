"""The cache of paths between transitions (:class:`climb_ompl.climb.transition_graph.TransitionGraph`): a failed
connection asked for again with more effort is planned again, FIND-PATH only; asked at the same effort, the
failure is returned without planning."""

from __future__ import annotations

import numpy as np
import pytest

from climb_ompl.climb.onestep import find_transition
from climb_ompl.climb.transition_graph import TransitionGraph
from climb_ompl.errors import QueryError
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.manifold.stance import Stance
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain
from climb_ompl.settings import ClimbSettings


@pytest.fixture(scope="module")
def unreachable():
    """The planar robot on two holds at a transition ``qa``, and ``qb``: the same posture with the base 0.5 m
    away, where no hand is on its hold (the direct path fails its inverse kinematics, FIND-PATH rejects the
    end: no path, whatever the budget)."""
    robot, terrain = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    s = Stance(limb1="L2", limb2="R2")
    qa = find_transition(robot, terrain, s, s.with_hold("limb3", "L4"), seed=0)
    assert qa is not None
    qb = qa.copy()
    qb[robot.base_indices[0]] += 0.5
    return robot, terrain, s, qa, qb


def test_a_failure_is_planned_again_only_with_more_effort(unreachable):
    robot, terrain, s, qa, qb = unreachable
    g = TransitionGraph(Feasibility(robot, terrain), ClimbSettings(), seed=0)
    assert g.connect(s, qa, qb, None) is None
    assert (g.path_calls, g.local_path.calls, g.retries) == (1, 1, 0)
    assert g.connect(s, qa, qb, None) is None  # the same effort: the cached failure
    assert (g.path_calls, g.local_path.calls, g.retries) == (1, 1, 0)
    assert g.connect(s, qa, qb, None, effort=2) is None  # more: FIND-PATH again, not the direct path
    assert (g.path_calls, g.local_path.calls, g.retries) == (2, 1, 1)
    assert g.connect(s, qa, qb, None, effort=2) is None
    assert g.connect(s, qa, qb, None, effort=1) is None
    assert (g.path_calls, g.local_path.calls, g.retries) == (2, 1, 1)


def test_a_found_path_is_returned_at_any_effort(unreachable):
    robot, terrain, s, qa, _ = unreachable
    qb = find_transition(robot, terrain, s, s.with_hold("limb3", "R4"), seed=0, near=qa)
    g = TransitionGraph(Feasibility(robot, terrain), ClimbSettings(), seed=0)
    path = g.connect(s, qa, qb, "limb3")
    assert path is not None and np.array_equal(path[0], qa) and np.array_equal(path[-1], qb)
    calls = (g.path_calls, g.local_path.calls)
    assert g.connect(s, qa, qb, "limb3", effort=4) is path and (g.path_calls, g.local_path.calls) == calls


def test_retry_growth_below_one_is_refused():
    with pytest.raises(QueryError, match="path_retry_growth"):
        ClimbSettings(path_retry_growth=0)
    assert ClimbSettings(path_retry_growth=1).path_retry_growth == 1


@pytest.mark.parametrize("growth", [1, 2])
def test_the_search_asks_again_with_more_effort_after_its_edge_failed(unreachable, growth):
    """``TransitionStage.connect`` (stage 2) asks for ``path_retry_growth ** failures of the edge``: after one failure
    of the edge, growth 2 plans the connection again and growth 1 (the default) returns the cached failure."""
    from climb_ompl.climb.goal import Goal
    from climb_ompl.climb.nodes import Node
    from climb_ompl.climb.search import StanceGraphSearch

    robot, terrain, s, qa, qb = unreachable
    search = StanceGraphSearch(robot, terrain, Goal("height", height=2.0), ClimbSettings(path_retry_growth=growth))
    u = Node((s, ()), qa, 0.0, None, None, ())
    v = Node((s, ()), qb, 1.0, u, None, ())
    assert search.stage2.connect(u, v) is None and search.stage2.connect(u, v) is None
    assert search.graph.path_calls == 1
    search.edges.path_failed(u, v.stance)
    assert search.stage2.connect(u, v) is None
    assert (search.graph.path_calls, search.graph.retries) == ((2, 1) if growth == 2 else (1, 0))
    assert search.summary()["path_retries"] == search.graph.retries


def test_a_spent_budget_names_the_steps_whose_path_was_not_found(unreachable):
    """The reason of a search stopped by its budget names the steps whose path was not found, most often first,
    and what stopped their paths (the direct local path's failures by reason, FIND-PATH's rejections)."""
    from climb_ompl.climb.goal import Goal
    from climb_ompl.climb.nodes import Node
    from climb_ompl.climb.search import StanceGraphSearch

    robot, terrain, s, qa, qb = unreachable
    search = StanceGraphSearch(robot, terrain, Goal("height", height=2.0), ClimbSettings())
    u = Node((s, ()), qa, 0.0, None, None, ())
    grab = s.with_hold("limb3", "L4")
    v = Node((grab, ()), qb, 1.0, u, ("grab", "limb3", "L4"), ())
    assert search.stage2.connect(u, v) is None  # no hand on its hold at qb: the direct path's inverse kinematics fails
    for nxt in (grab, grab, s.without("limb1")):
        search.edges.path_failed(u, nxt)
    search.stats.candidates = 1
    text = search.stats.candidates_text(search.graph)
    assert "the steps whose path was not found, most often: grab limb3 L4 (2 times), release limb1 L2 (1 time)" \
        in text
    assert "(over the whole search, the direct local path stopped on ik (1)" in text
