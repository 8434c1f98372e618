"""``reexpand``: when EXPLORE-STANCEGRAPH runs out of edges, an expanded node is reached again at another
configuration of its stance and expanded from there (:meth:`StanceGraphSearch._reopen`)."""

from __future__ import annotations

import numpy as np
import pytest

from climb_ompl.goal import Goal
from climb_ompl.robot import RobotModel
from climb_ompl.search import Node, StanceGraphSearch
from climb_ompl.settings import ClimbSettings
from climb_ompl.stance import Stance, StanceConstraint
from climb_ompl.start import find_start
from climb_ompl.terrain import Terrain


@pytest.fixture(scope="module")
def lemur_wall():
    robot, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    st = find_start(robot, wall, seed=0)
    assert st.found
    return robot, wall, Stance(st.stance), st.q


def _two_nodes(robot, wall, stance, q, **settings):
    """A search with its start node and the node after releasing the start's first limb."""
    sg = StanceGraphSearch(robot, wall, Goal.parse(2.0), ClimbSettings(**settings), seed=0)
    start = Node(sg._key(None, stance, q), q, 0.0, None, None, ())
    limb = stance.limbs[0]
    three = stance.without(limb)
    q1 = sg.transition(start, three)
    assert q1 is not None
    child = sg._reach(start, sg._key(start, three, q1), q1, ("release", limb, stance[limb]), three)
    return sg, start, child


def test_a_node_is_reached_again_at_another_configuration_of_its_stance(lemur_wall):
    """The released node comes back at a new configuration: hands on the four holds (a release is a transition,
    a configuration of both stances), feasible at the three-hold stance, not the first one; its failed
    transitions are forgotten, the others kept; each node is re-opened at most ``reexpand`` times and the start
    (the query's configuration) never."""
    robot, wall, stance, q = lemur_wall
    sg, start, child = _two_nodes(robot, wall, stance, q, reexpand=1)
    other = child.stance.with_hold(child.action[1], wall.holds[-1].id)
    sg.transitions[(child.key, other)] = None  # a grab that failed from the first configuration
    kept = (child.key, child.stance.without(child.stance.limbs[0]))
    sg.transitions[kept] = child.q
    closed = {start.key: start, child.key: child}
    pushed: list[Node] = []
    heap: list[int] = []

    def push(node):
        pushed.append(node)
        heap.append(len(pushed))

    assert sg._reopen(closed, push, heap)
    (again,) = pushed
    assert again.stance == child.stance and again.parent is start and again.action == child.action
    assert not np.allclose(again.q, child.q)
    assert StanceConstraint(robot, wall, stance, sg.s.tolerance).error(again.q) <= sg.s.tolerance
    assert sg.feas.why(sg.feas.transition_checks(child.stance, stance), again.q) is None
    assert closed[again.key] is again and sg.reexpanded == 1
    if again.key == child.key:
        assert (child.key, other) not in sg.transitions and sg.transitions[kept] is child.q
    heap.clear()
    assert not sg._reopen(closed, push, heap) and len(pushed) == 1  # once per node; never the start


def test_without_reexpand_a_node_keeps_its_first_configuration(lemur_wall):
    """``reexpand = 0`` (Fig. 16 as published): nothing is re-opened."""
    robot, wall, stance, q = lemur_wall
    sg, start, child = _two_nodes(robot, wall, stance, q, reexpand=0)
    heap: list[int] = []
    assert not sg._reopen({start.key: start, child.key: child}, lambda n: heap.append(1), heap) and not heap
    assert ClimbSettings.for_search("paper").reexpand == 0 and ClimbSettings().reexpand == 2
