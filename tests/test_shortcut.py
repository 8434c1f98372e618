"""Shortcuts of a candidate sequence (:mod:`climb_ompl.climb.shortcut`): a limb's two successive moves folded into one.

The routes are built here by hand, move by move, on the demo wall from LEMUR's start, so the sequence a shortcut
must give is known in advance: a limb's round trip around another limb's move disappears, and a limb that moves
twice moves once.  Stage 2 then plans the shortened sequence's paths: the shortcut is a route the robot can take.
"""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest

from climb_ompl.climb.goal import Goal
from climb_ompl.climb.nodes import Node
from climb_ompl.climb.search import StanceGraphSearch
from climb_ompl.climb.shortcut import moves, shorten
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain
from climb_ompl.settings import ClimbSettings


def _search(robot, wall):
    return StanceGraphSearch(robot, wall, Goal.parse(3.0), ClimbSettings.for_search("guided", robot=robot), seed=0)


def _move(sg, node, limb, skip=()):
    """The first move of ``limb`` from ``node`` (release, then a grab of another hold, in the search's own order of
    proposed grabs) whose transitions are found, as the node reached; ``None`` if none is."""
    rel = sg.take_steps(node, [("release", limb, node.stance[limb])])
    if rel is None:
        return None
    for action, lb, hold, _ in sg.proposals(rel):
        if action == "grab" and lb == limb and hold not in skip and hold != node.stance[limb]:
            end = sg.take_steps(rel, [("grab", limb, hold)])
            if end is not None:
                return end
    return None


def _actions(chain):
    return [n.action for n in chain[1:]]


def _route(lemur_start, back: bool):
    """LEMUR's start, then a move of limb x, a move of limb y, and a move of x: back to its first hold (``back``)
    or on to another one.  Returns the search, the chain of nodes and the shortened sequence expected: the first of
    the folds the module docstring lists whose steps are found again (walked here, before :func:`shorten`; the
    search keeps the transitions found, so :func:`shorten` meets the same ones) and end at the route's last node.
    Routes without one are passed over."""
    robot, wall, stance, q = lemur_start
    sg = _search(robot, wall)
    root = Node(sg.components.key(None, stance, q), q, 0.0, None, None, ())
    for x in stance.limbs:
        b = stance[x]
        n1 = _move(sg, root, x)
        if n1 is None:
            continue
        for y in (lb for lb in stance.limbs if lb != x):
            n2 = _move(sg, n1, y)
            if n2 is None:
                continue
            c = n1.stance[x]
            n3 = sg.take_steps(n2, [("release", x, c), ("grab", x, b)]) if back else _move(sg, n2, x, skip=(b,))
            if n3 is None:
                continue
            ys = _actions(n2.chain())[2:]
            x_once = [("release", x, b), ("grab", x, n3.stance[x])]
            for expected in ([ys] if back else [x_once + ys, ys + x_once]):
                end = sg.take_steps(root, expected)
                if end is not None and end.key == n3.key:
                    return sg, n3.chain(), expected
    pytest.fail("no route of three moves with a shortcut found from LEMUR's start on the demo wall")


def test_moves_pairs_each_release_with_the_grab_of_the_same_limb_after_it(lemur_start):
    sg, chain, _ = _route(lemur_start, back=True)
    acts = _actions(chain)
    found = moves(chain)
    assert [(i, limb, b, c) for i, limb, b, c in found] == [
        (i + 1, acts[i][1], acts[i][2], acts[i + 1][2]) for i in range(0, len(acts), 2)]


def test_a_limbs_round_trip_around_another_limbs_move_is_cut(lemur_start):
    """x: b -> c, y: y1 -> y2, x: c -> b becomes y: y1 -> y2 alone, ending at the same (stance, component) node;
    stage 2 finds every path of the shortened sequence."""
    sg, chain, expected = _route(lemur_start, back=True)
    acts = _actions(chain)
    assert len(acts) == 6 and acts[0][1] == acts[4][1] and acts[0][2] == acts[5][2]
    recorded = []
    record = sg.record
    sg.record = lambda n: (recorded.append(n), record(n))  # type: ignore[method-assign]
    short = shorten(sg, chain)
    assert _actions(short) == acts[2:4]
    assert short[-1].key == chain[-1].key
    assert short[0] is chain[0]
    assert len(chain) - len(short) == 4
    assert recorded == short[1:3]  # the kept shortcut's nodes, counted as explored once
    reached, paths = sg.stage2.run(short)
    assert reached == len(short) - 1 and len(paths) == 2


def test_a_shortcut_onto_an_edge_that_failed_in_stage_2_is_not_taken(lemur_start):
    """The same route with the shortcut's first edge marked as failed once (its ``P`` lowered): the candidate is
    planned as found."""
    sg, chain, _ = _route(lemur_start, back=True)
    y = chain[3].action[1]
    sg.edges.path_failed(chain[0], chain[0].stance.without(y))  # the shortcut's first step: y let go at the start
    assert shorten(sg, chain) == chain


def test_a_shortcut_ending_in_another_component_is_not_taken(lemur_start, monkeypatch):
    """When the steps taken again end in another component of the stance (here: the node's elbow bends said to be
    the other way), the rest of the candidate could not go on from there: it is left as found."""
    sg, chain, _ = _route(lemur_start, back=True)
    take = sg.take_steps

    def other_component(*args, **kw):
        node = take(*args, **kw)
        if node is None:
            return None
        stance, bends = node.key
        return dataclasses.replace(node, key=(stance, tuple(-b for b in bends)))

    monkeypatch.setattr(sg, "take_steps", other_component)
    assert shorten(sg, chain) == chain


def test_the_steps_between_are_drawn_about_their_old_transitions(lemur_start):
    """On a search that has found none of the shortcut's transitions yet, each step taken again is drawn about the
    configuration its old transition had (the order of :func:`shorten`'s sequences: the steps between, their old
    transitions)."""
    robot, wall, _, _ = lemur_start
    _, chain, _ = _route(lemur_start, back=True)
    fresh = _search(robot, wall)
    refs = []
    about = fresh.transitions.about

    def spy(node, nxt, ref):
        refs.append((node.stance, nxt, ref.copy()))
        return about(node, nxt, ref)

    fresh.transitions.about = spy
    shorten(fresh, chain)
    assert refs, "no step was drawn about an old transition"
    # the first: y's release from the start stance, about the old release of y (node 3)
    stance, nxt, ref = refs[0]
    assert stance == chain[0].stance and nxt == chain[0].stance.without(chain[3].action[1])
    assert np.array_equal(ref, chain[3].q)
    if len(refs) > 1:  # then y's grab, about the old grab (node 4)
        assert refs[1][1] == chain[4].stance.with_hold(chain[1].action[1], chain[0].stance[chain[1].action[1]])
        assert np.array_equal(refs[1][2], chain[4].q)


@pytest.mark.climb
def test_a_limb_that_moves_twice_moves_once(lemur_start):
    """x: b -> c, y: y1 -> y2, x: c -> d becomes one move of x from b to d and y's move (in either order), ending
    at the same node; stage 2 finds every path."""
    sg, chain, expected = _route(lemur_start, back=False)
    acts = _actions(chain)
    x, b, d = acts[0][1], acts[0][2], acts[5][2]
    assert len(expected) == 4 and {("release", x, b), ("grab", x, d)} <= set(expected)
    short = shorten(sg, chain)
    got = _actions(short)
    assert got == expected
    assert [a for a in got if a[1] != x] == acts[2:4]
    assert short[-1].key == chain[-1].key
    # the nodes after a fold follow on from it: parents, depths and the free limbs' last holds
    for u, v in itertools.pairwise(short):
        assert v.parent is u and v.depth == u.depth + 1
        free = dict(v.last)
        if v.action[0] == "release":
            assert free[v.action[1]] == v.action[2]
        else:
            assert v.action[1] not in free
    reached, _ = sg.stage2.run(short)
    assert reached == len(short) - 1


def test_a_sequence_without_two_moves_of_one_limb_is_left_alone(lemur_start):
    sg, chain, _ = _route(lemur_start, back=True)
    two = chain[:5]  # x's move and y's move
    assert shorten(sg, two) == two


@pytest.mark.climb
def test_a_climb_with_shortcuts_is_shorter_and_verified():
    """The planar robot's 1.6 m climb with and without shortcuts: :func:`shorten` runs only when they are on, the
    shortened plan takes fewer steps, and the verifier (which knows nothing of the search) accepts it; Fig. 16 as
    published (``paper``) has none."""
    from climb_ompl.climb import search
    from climb_ompl.climb.multistep import default_start, plan_climb
    from climb_ompl.verification.climb import verify

    robot, wall = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    stance, q0 = default_start(robot, wall, seed=0)
    calls = []
    real = search.shorten

    def spy(sg, chain):
        calls.append(len(chain))
        return real(sg, chain)

    plans = {}
    mp = pytest.MonkeyPatch()
    try:
        mp.setattr(search, "shorten", spy)
        for on in (False, True):
            res = plan_climb(robot, wall, stance, 1.6, q_start=q0, time_limit=60, seed=0, shortcuts=on)
            assert res.found, res.reason
            plans[on] = res.plan
            assert bool(calls) == on
    finally:
        mp.undo()
    assert len(plans[True].steps) < len(plans[False].steps)
    assert plans[True].totals["shortcut_steps"] > 0 == plans[False].totals["shortcut_steps"]  # in the plan file
    assert verify(plans[True]).ok
    assert ClimbSettings.for_search("paper").shortcuts is False
    assert ClimbSettings().shortcuts is True
