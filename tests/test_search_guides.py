"""Guides of the stance-graph search: the ``grab_reach`` prefilter (grabs of holds far beyond the limb's reach
from where the robot stands are not proposed, and the frontier diagnosis says so), ``keep_shape`` and ``reexpand``
(when EXPLORE-STANCEGRAPH runs out of edges, an expanded node is reached again at another configuration of its
stance and expanded from there)."""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest

from climb_ompl.climb.frontier import _status
from climb_ompl.climb.goal import Goal
from climb_ompl.climb.nodes import Node
from climb_ompl.climb.search import StanceGraphSearch
from climb_ompl.climb.start import find_start
from climb_ompl.manifold.stance import Stance, StanceConstraint
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain
from climb_ompl.settings import ClimbSettings


def _grabs(robot, wall, stance, q, **settings):
    sg = StanceGraphSearch(robot, wall, Goal.parse(2.0), ClimbSettings(**settings), seed=0)
    node = Node((stance, ()), q, 0.0, None, None, ())
    return sg, node, {(limb, hold) for action, limb, hold, _ in sg.proposals(node) if action == "grab"}


def test_grabs_beyond_the_limbs_reach_where_the_robot_stands_are_not_proposed(lemur_start):
    """With one limb released at the start configuration, the grabs dropped by ``grab_reach=1.5`` are exactly
    those whose hold (a point contact: the hand target is the hold) lies farther than 1.5 reaches from the
    limb's first joint, computed here from Pinocchio's joint placement; the pair reach alone keeps them."""
    robot, wall, stance, q = lemur_start
    limb = stance.limbs[0]
    three = stance.without(limb)
    _, _, every = _grabs(robot, wall, three, q, grab_reach=0.0)
    sg, node, kept = _grabs(robot, wall, three, q, grab_reach=1.5)
    pin.forwardKinematics(robot.model, robot.data, q)
    shoulder = robot.data.oMi[robot.limb(limb).joint_ids[0]].translation
    limit = 1.5 * robot.limb(limb).reach
    far = {(limb, h) for lb, h in every if lb == limb and np.linalg.norm(wall.hold(h).p - shoulder) > limit}
    assert far, "the test wall must have holds within the pair reach but beyond 1.5 reaches"
    assert every - kept == far
    # the frontier diagnosis names the prefilter for such an edge
    lb, h = sorted(far)[0]
    why = _status(sg, [node.key], three.with_hold(lb, h))
    assert isinstance(why, list) and why[0].startswith("reach: not proposed")
    d = float(np.linalg.norm(wall.hold(h).p - shoulder))
    assert f"{d:.3f} m" in why[0] and f"{limit:.3f} m" in why[0]


def test_paper_search_keeps_the_pair_reach_alone():
    """Fig. 16 as published proposes every grab within the pair reach (Bretl 2006, sec. 4.3)."""
    assert ClimbSettings.for_search("paper").grab_reach == 0.0
    assert ClimbSettings().grab_reach == 1.5


def _rows_wall(n_rows: int = 12, n_cols: int = 7, spacing: float = 0.15) -> Terrain:
    holds = [{"id": f"h{r}_{c}", "position": [round(spacing * (c - (n_cols - 1) / 2), 4), 0.0, round(spacing * r, 4)],
              "normal": [0.0, 0.5, 0.866]} for r in range(n_rows) for c in range(n_cols)]
    return Terrain.from_dict({"name": "rows", "holds": holds,
                              "surfaces": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}]})


def test_keep_shape_moves_the_limb_left_behind_first():
    """LEMUR with its upper-left limb (nw) four rows below the others: with ``keep_shape`` the heuristic counts
    the other limbs only up to one stride above nw (nominally level with ne, above se and sw), so nw's grab one
    row up gains more than ne's; without it both gains are equal (one row of one limb).  The heuristic is
    checked against the formula computed here from the nominal hand heights: capped heights, measured to the
    goal stance in the nominal shape (the lowest limb at the goal's hold height, the others above it as the
    nominal posture puts them)."""
    robot, wall = RobotModel.load("lemur"), _rows_wall()
    goal = Goal.parse(3.0)
    lag = Stance({"ne": "h6_4", "nw": "h2_2", "se": "h5_4", "sw": "h5_2"})
    on = {True: StanceGraphSearch(robot, wall, goal, ClimbSettings(keep_shape=True), seed=0),
          False: StanceGraphSearch(robot, wall, goal, ClimbSettings(keep_shape=False), seed=0)}
    hands = np.asarray(robot.hand_positions(np.asarray(robot.nominal_q, dtype=float)))
    n = dict(zip([lb.name for lb in robot.limbs], hands[:, 2] - hands[:, 2].mean(), strict=True))
    sg = on[True]
    stride, thr = sg.heuristic.stride, 3.0 - sg.reach

    def oracle(st: Stance) -> float:
        z = {lb: wall.hold(st[lb]).p[2] for lb in st.limbs}
        capped = {lb: min(z[lb], min(z[k] + max(0.0, n[lb] - n[k]) for k in z if k != lb) + stride) for lb in z}
        low = min(n.values())  # targets: the goal stance in the nominal shape, its lowest limb at thr
        return sum(2 * max(0.0, thr + n[lb] - low - v) / stride for lb, v in capped.items())

    assert sg.heuristic(lag, ()) == pytest.approx(oracle(lag), abs=1e-9)
    assert on[False].heuristic(lag, ()) == pytest.approx(
        sum(2 * max(0.0, thr - wall.hold(h).p[2]) / stride for h in lag.hold_ids), abs=1e-9)
    up_nw = Stance({**dict(lag), "nw": "h3_2"})
    up_ne = Stance({**dict(lag), "ne": "h7_4"})
    assert on[False].heuristic(up_nw, ()) == pytest.approx(on[False].heuristic(up_ne, ()), abs=1e-9)
    assert sg.heuristic(up_nw, ()) < sg.heuristic(up_ne, ()) - 1.0
    # a stance in the nominal shape (upper limbs a row above the lower ones) is not capped: only the targets
    # differ, each limb aiming at its nominal height above the lowest one
    level = Stance({"ne": "h6_4", "nw": "h6_2", "se": "h5_4", "sw": "h5_2"})
    assert all(wall.hold(h).p[2] < thr for h in level.hold_ids)
    assert sg.heuristic(level, ()) == pytest.approx(oracle(level), abs=1e-9)
    assert sg.heuristic(level, ()) - on[False].heuristic(level, ()) == pytest.approx(
        sum(2 * (v - min(n.values())) / stride for v in n.values()), abs=1e-9)
    assert max(n.values()) - min(n.values()) > 0.1


def _two_nodes(robot, wall, stance, q, **settings):
    """A search with its start node and the node after releasing the start's first limb."""
    sg = StanceGraphSearch(robot, wall, Goal.parse(2.0), ClimbSettings(**settings), seed=0)
    start = Node(sg.components.key(None, stance, q), q, 0.0, None, None, ())
    limb = stance.limbs[0]
    three = stance.without(limb)
    q1 = sg.transitions.get(start, three)
    assert q1 is not None
    child = sg.explore(start, sg.components.key(start, three, q1), q1, ("release", limb, stance[limb]))
    return sg, start, child


def test_a_node_is_reached_again_at_another_configuration_of_its_stance(lemur_start):
    """The released node comes back at a new configuration: hands on the four holds (a release is a transition,
    a configuration of both stances), feasible at the three-hold stance, not the first one; its failed
    transitions are forgotten, the others kept; each node is re-opened at most ``reexpand`` times and the start
    (the query's configuration), which has no failed edge here, is not drawn again; the node nearest the goal is
    drawn first, and one farther back when that one opens no edge."""
    robot, wall, stance, q = lemur_start
    sg, start, child = _two_nodes(robot, wall, stance, q, reexpand=1)
    other = child.stance.with_hold(child.action[1], wall.holds[-1].id)
    sg.transitions.by_edge[(child.key, other)] = None  # a grab that failed from the first configuration
    kept = (child.key, child.stance.without(child.stance.limbs[0]))
    sg.transitions.by_edge[kept] = child.q
    pushed: list[Node] = []
    heap: list[int] = []

    def push(node):
        pushed.append(node)
        heap.append(len(pushed))

    # a node far nearer the goal (the four highest holds) is drawn first; when its draw fails, the child, farther
    # back, is drawn next
    tops = sorted(wall.holds, key=lambda h: -wall.height(h))[:4]
    top = Stance({lb.name: h.id for lb, h in zip(robot.limbs, tops, strict=True)})
    far = Node((top, ()), q, 0.0, start, ("grab", robot.limbs[0].name, tops[0].id), ())
    assert sg.heuristic(top, ()) < sg.heuristic(child.stance, child.last) - 10
    drawn: list[Stance] = []
    find = sg.finder.find

    def spy(sigma, nxt, near, **kw):
        drawn.append(nxt)
        return None if nxt == top else find(sigma, nxt, near, **kw)

    sg.finder.find = spy
    closed = {start.key: start, child.key: child, far.key: far}
    assert sg.stage1.reopen(closed, push, heap)
    assert drawn == [top, child.stance] and sg.stage1.reopened == {far.key: 1, child.key: 1}
    (again,) = pushed
    assert again.stance == child.stance and again.parent is start and again.action == child.action
    assert not np.allclose(again.q, child.q)
    assert StanceConstraint(robot, wall, stance, sg.settings.tolerance).error(again.q) <= sg.settings.tolerance
    assert sg.feas.why(sg.feas.transition_checks(child.stance, stance), again.q) is None
    assert closed[again.key] is again and sg.stats.reexpanded == 1
    if again.key == child.key:
        assert (child.key, other) not in sg.transitions.by_edge and sg.transitions.by_edge[kept] is child.q
    heap.clear()
    assert not sg.stage1.reopen(closed, push, heap) and len(pushed) == 1  # once per node; the start has no failed edge


def test_the_starts_failed_edges_are_tried_again_from_where_the_robot_stands(lemur_start):
    """When the search runs out of edges and only the start is left, its failed edges are forgotten and queued
    again at its own configuration (the robot stands there; nothing is re-drawn), FIND-TRANSITION drawing anew
    (another seed), at most ``START_RETRIES`` times (nothing else can be explored before one opens); the edges
    that succeeded stay as they were."""
    from climb_ompl.climb.stage1 import START_RETRIES

    robot, wall, stance, q = lemur_start
    sg = StanceGraphSearch(robot, wall, Goal.parse(2.0), ClimbSettings(reexpand=2), seed=0)
    start = Node(sg.components.key(None, stance, q), q, 0.0, None, None, ())
    edges = [nxt for *_, nxt in sg.proposals(start)]
    failed, found = edges[:3], edges[3]
    for nxt in failed:
        sg.transitions.by_edge[(start.key, nxt)] = None
    sg.transitions.by_edge[(start.key, found)] = q
    pushed: list[Node] = []
    heap: list[int] = []

    def push(node):
        pushed.append(node)
        heap.append(len(pushed))

    assert START_RETRIES > 2  # more than another node's ``reexpand``
    for n in range(1, START_RETRIES + 1):
        assert sg.stage1.reopen({start.key: start}, push, heap)
        assert pushed[-1] is start and sg.stage1.reopened == {start.key: n} and sg.stats.reexpanded == n
        assert all((start.key, nxt) not in sg.transitions.by_edge for nxt in failed)
        assert sg.transitions.by_edge[(start.key, found)] is q
        for nxt in failed:  # they fail again
            sg.transitions.by_edge[(start.key, nxt)] = None
        heap.clear()
    assert not sg.stage1.reopen({start.key: start}, push, heap) and len(pushed) == START_RETRIES
    # a retried edge draws with another seed (the search's seed counts its FIND-TRANSITION calls): the release of
    # the start's first limb, from a child's configuration where that release is not a zero-length step
    sg2, start2, child = _two_nodes(robot, wall, stance, q, reexpand=2)
    seeds = []
    find = sg2.finder.find
    sg2.finder.find = lambda sigma, nxt, near, **kw: seeds.append(kw["seed"]) or find(sigma, nxt, near, **kw)
    grab = next(nxt for action, _, _, nxt in sg2.proposals(child) if action == "grab")
    sg2.transitions.get(child, grab)
    sg2.transitions.by_edge.pop((child.key, grab))
    sg2.transitions.get(child, grab)
    assert len(seeds) == 2 and seeds[0] != seeds[1]


def test_without_reexpand_a_node_keeps_its_first_configuration(lemur_start):
    """``reexpand = 0`` (Fig. 16 as published): nothing is re-opened."""
    robot, wall, stance, q = lemur_start
    sg, start, child = _two_nodes(robot, wall, stance, q, reexpand=0)
    heap: list[int] = []
    assert not sg.stage1.reopen({start.key: start, child.key: child}, lambda n: heap.append(1), heap) and not heap
    assert ClimbSettings.for_search("paper").reexpand == 0 and ClimbSettings().reexpand == 2


@pytest.mark.parametrize("goal", ["height", "hold"])
def test_a_release_looks_one_grab_ahead(lemur_start, goal):
    """``release_lookahead``: the heuristic of each release from the start equals one step plus the smallest
    heuristic over the grabs that :class:`EdgeProposals` proposes for the freed limb at the
    stance after the release (same configuration), enumerated here one by one (for a height goal only the
    highest hold is evaluated); it is never more than the plain heuristic (the released hold is among those
    grabs), and strictly less for a limb that can climb."""
    robot, wall, stance, q = lemur_start
    top = max(wall.holds, key=wall.height).id
    sg = StanceGraphSearch(robot, wall, Goal.parse(2.0 if goal == "height" else f"ne={top}"),
                           ClimbSettings(release_lookahead=True), seed=0)
    start = Node((stance, ()), q, 0.0, None, None, ())
    gains = 0
    for limb in stance.limbs:
        three, last = stance.without(limb), ((limb, stance[limb]),)
        after = Node((three, ()), q, 0.0, start, ("release", limb, stance[limb]), last)
        grabs = [h for a, lb, h, _ in sg.proposals(after) if a == "grab" and lb == limb]
        assert stance[limb] in grabs
        brute = 1.0 + min(sg.heuristic(three.with_hold(limb, h), ()) for h in grabs)
        look = sg.proposals.release_heuristic(start, limb, three, last)
        assert look == pytest.approx(brute, abs=1e-12)
        assert look <= sg.heuristic(three, last) + 1e-12
        gains += look < sg.heuristic(three, last) - 1e-9
    assert gains, "at the bottom of the wall some limb can climb"


class _Popped(Exception):
    """Raised at the first edge stage 1 pops, naming the limb it releases."""


def _first_pop(sg: StanceGraphSearch) -> StanceGraphSearch:
    """``sg`` stopping stage 1 at the first edge it pops (FIND-TRANSITION is called on the popped edge only)."""

    def get(node, nxt, **_):
        raise _Popped(next(lb for lb in node.stance.limbs if lb not in nxt))

    sg.transitions.get = get
    return sg


@pytest.mark.parametrize("lookahead", [True, False])
def test_the_release_of_the_limb_that_can_climb_highest_is_tried_first(lookahead):
    """LEMUR on a grid with its lower-left limb (sw) three rows below the others: every release of the stance
    has the same plain heuristic (the freed limb counted at its hold), so without the look-ahead the first
    release popped is the first limb in order; with it, sw's (the others' grabs gain nothing while sw lags:
    ``keep_shape``).  The pair reach alone proposes the grabs (``grab_reach = 0``), so the configuration
    plays no part."""
    robot, wall = RobotModel.load("lemur"), _rows_wall()
    lag = Stance({"ne": "h6_4", "nw": "h6_2", "se": "h5_4", "sw": "h2_2"})
    sg = _first_pop(StanceGraphSearch(robot, wall, Goal.parse(3.0),
                                      ClimbSettings(grab_reach=0.0, release_lookahead=lookahead), seed=0))
    q = np.asarray(robot.nominal_q, dtype=float)
    start = Node((lag, ()), q, 0.0, None, None, ())
    plain = {sg.heuristic(lag.without(lb), ((lb, lag[lb]),)) for lb in lag.limbs}
    assert max(plain) - min(plain) < 1e-9
    look = {lb: sg.proposals.release_heuristic(start, lb, lag.without(lb), ((lb, lag[lb]),)) for lb in lag.limbs}
    assert min(look, key=look.get) == "sw" and look["sw"] < min(v for k, v in look.items() if k != "sw") - 1.0
    with pytest.raises(_Popped) as popped:
        sg.stage1.run(start)
    releasable = [lb for lb in lag.limbs if sg.feas.region_ok(lag.without(lb))]
    assert "sw" in releasable and releasable[0] != "sw"
    assert str(popped.value) == ("sw" if lookahead else releasable[0])


def test_release_lookahead_is_the_guided_default_and_not_the_papers():
    """On by default (for every bundled robot), off in the paper mode (Fig. 16 ranks no release by its next grab;
    see docs/climb.md)."""
    from climb_ompl.model.robot import RobotModel

    assert ClimbSettings().release_lookahead is True
    assert ClimbSettings.for_search("guided").release_lookahead is True
    assert ClimbSettings.for_search("paper").release_lookahead is False
    for name in ("lemur", "go1", "anymal-c", "planar-3limb"):
        assert ClimbSettings.for_search("guided", robot=RobotModel.load(name)).release_lookahead is True


@pytest.mark.climb
def test_a_start_with_one_rare_way_out_gets_going():
    """LEMUR on ``generate_wall(seed=4, normal_up_deg=(35, 65))`` (the climb suite's other parameters) starts where
    one release of four is possible, found by about one FIND-TRANSITION call in ten.  With the robot's defaults
    (the release look-ahead) the search was exhausted at its start after three tries per edge; it must get past
    the start and climb a little."""
    from climb_ompl.climb.multistep import plan_climb
    from climb_ompl.model.terrain import generate_wall

    robot = RobotModel.load("lemur")
    wall = generate_wall(seed=4, width=1.6, height=3, spacing=0.18, jitter=0.4, friction=(0.9, 1.2), tilt_deg=0,
                         normal_up_deg=(35, 65), normal_side_deg=20)
    st = find_start(robot, wall, seed=0)
    top = max(wall.height(h) for h in st.stance.values())
    res = plan_climb(robot, wall, st.stance, top + 0.2 + robot.limb("ne").reach, q_start=st.q, seed=0, time_limit=120)
    assert res.found, res.reason
    assert res.stats["stances_explored"] > 1
