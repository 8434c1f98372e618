"""``transition_failures``: FIND-TRANSITION is not called for an edge from a third component of a stance once it failed
for that edge from two others, and is called again once the search forgets the stance's failures (a reopened node).
An edge that needs no call (a release right where the robot stands) is never skipped."""

from __future__ import annotations

import dataclasses

import numpy as np

from climb_ompl.climb.goal import Goal
from climb_ompl.climb.nodes import Node
from climb_ompl.climb.search import StanceGraphSearch
from climb_ompl.climb.start import find_start
from climb_ompl.manifold.stance import Stance
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain
from climb_ompl.settings import ClimbSettings


def test_an_edge_failed_from_two_components_is_skipped_from_a_third(lemur_start):
    robot, wall, stance, q = lemur_start
    settings = ClimbSettings.for_search("guided", robot=robot)
    assert settings.transition_failures == 2 and ClimbSettings.for_search("paper").transition_failures == 0
    sg = StanceGraphSearch(robot, wall, Goal.parse(3.0), settings, seed=0)
    off = StanceGraphSearch(robot, wall, Goal.parse(3.0), dataclasses.replace(settings, transition_failures=0), seed=0)
    limb = stance.limbs[0]
    small = stance.without(limb)
    hand = np.asarray(robot.hand_positions(q))[[lb.name for lb in robot.limbs].index(limb)]
    far = max(wall.holds, key=lambda h: float(np.linalg.norm(h.p - hand)))  # a grab no draw reaches
    nxt = small.with_hold(limb, far.id)
    # three components of the same stance (the keys are what the search tells them apart by)
    a, b, c = (Node((small, (s,)), q, 0.0, None, None, ()) for s in (-1, 0, 1))
    for search in (sg, off):
        assert search.transitions.get(a, nxt, skip=True) is None
        elsewhere = search.transitions.failed_elsewhere
        assert not elsewhere(c, nxt) and not elsewhere(b, nxt)  # one: still tried
        assert search.transitions.get(b, nxt, skip=True) is None
    assert sg.transitions.failed_elsewhere(c, nxt)  # two: skipped
    assert not sg.transitions.failed_elsewhere(a, nxt)  # (its own failure does not count: one other)
    calls = sg.stats.transition_calls
    assert sg.transitions.get(c, nxt, skip=True) is None
    assert sg.stats.transition_calls == calls and sg.stats.transitions_skipped == 1
    assert (c.key, nxt) not in sg.transitions.by_edge  # not a failure of c's: tried if c is expanded again
    assert not off.transitions.failed_elsewhere(c, nxt)  # the setting at 0: always tried
    # a node reopened (``reexpand``): its stance's edges are tried again from everywhere
    sg.transitions.forget_failed(a.key)
    assert not sg.transitions.failed_elsewhere(c, nxt)


def test_a_release_where_the_robot_stands_is_never_skipped():
    """The planar robot of Bretl (2006) at its start may let any limb go where it stands: nothing to skip."""
    robot, wall = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    st = find_start(robot, wall, seed=0)
    assert st.found
    stance, q = Stance(st.stance), st.q
    sg = StanceGraphSearch(robot, wall, Goal.parse(3.0), ClimbSettings.for_search("guided", robot=robot), seed=0)
    node = Node(sg.components.key(None, stance, q), q, 0.0, None, None, ())
    back = next(stance.without(lb) for lb in stance.limbs if sg.feas.valid(stance.without(lb), q))
    # as if it failed from two other components
    sg.transitions.failed_from[(stance, back)] = {(stance, (9,)), (stance, (8,))}
    assert sg.transitions.failed_elsewhere(node, back)
    calls = sg.stats.transition_calls
    assert sg.transitions.get(node, back, skip=True) is q  # nothing to skip: the zero-length step
    assert sg.stats.transitions_skipped == 0 and sg.stats.transition_calls == calls
