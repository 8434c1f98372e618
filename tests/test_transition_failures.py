"""``transition_failures``: FIND-TRANSITION is not called for an edge from a third component of a stance once it failed
for that edge from two others, and is called again once the search forgets the stance's failures (a reopened node)."""

from __future__ import annotations

import dataclasses

import numpy as np

from climb_ompl.goal import Goal
from climb_ompl.search import Node, StanceGraphSearch
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
        assert search.transition(a, nxt) is None
        assert not search._failed_elsewhere(c, nxt)  # one failure elsewhere: still tried
        assert search.transition(b, nxt) is None
    assert sg._failed_elsewhere(c, nxt)  # two: skipped
    assert not sg._failed_elsewhere(a, nxt)  # (from a, the edge's own failure is known: nothing to skip)
    assert not off._failed_elsewhere(c, nxt)  # the setting at 0: always tried
    sg._forget_failed(a.key)  # a node reopened (``reexpand``): its stance's edges are tried again from everywhere
    assert not sg._failed_elsewhere(c, nxt)
