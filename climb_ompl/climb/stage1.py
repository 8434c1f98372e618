"""EXPLORE-STANCEGRAPH, stage 1 of the search of Bretl (2006), Fig. 16: best first over ``(stance, component)`` nodes
to a goal node, with the guided search's re-expansion of nodes when the graph runs out of edges.

The queue is ordered by the cost ``n - sum ln P`` of sec. 3.3.3 (``1 - ln P(e)`` per step,
:meth:`climb_ompl.climb.edges.EdgeBook.cost`) plus, in the guided search, the weighted goal heuristic
(:mod:`climb_ompl.climb.heuristic`); ties go to the deeper node, then to the edge queued first.  Edges are proposed
when the geometry allows them (:class:`climb_ompl.climb.heuristic.EdgeProposals`).  FIND-TRANSITION
(:class:`climb_ompl.climb.edges.TransitionCache`) is called when a node is expanded (``transitions = "eager"``, as in
Fig. 16 lines 10-12) or when the search pops the edge (``"lazy"``).  A grab from a single contact onto a point stance
is one edge per transition point (:meth:`climb_ompl.climb.transition.TransitionFinder.points`), each verified by a
path when popped (the component graph of Fig. 13(b), built as met).
"""

from __future__ import annotations

import heapq
from collections.abc import Callable
from typing import TYPE_CHECKING, Any

from climb_ompl.climb.nodes import Node, NodeKey, after
from climb_ompl.climb.transition_graph import qkey

if TYPE_CHECKING:
    from climb_ompl.climb.search import StanceGraphSearch

#: How many times the start's failed edges are tried again when the stance graph runs out of edges (with
#: ``reexpand`` > 0; :meth:`StanceGraphStage.reopen`); a round costs one FIND-TRANSITION call per edge out of the
#: start.  Why 30: docs/climb.md, "Settings and their defaults".
START_RETRIES: int = 30
#: Stride of the seeds of a node's re-expansion draws (FIND-TRANSITION's seed: the search's seed plus the stride
#: times the call count), apart from the other draws
REOPEN_STRIDE = 104729

#: A queue entry: ``(f, -depth, counter, node, (action, limb, hold, next stance, transition point index or None))``
Entry = tuple[float, int, int, Node, tuple[str, str, str, Any, int | None]]


class StanceGraphStage:
    """EXPLORE-STANCEGRAPH for one search (its queue is rebuilt at each :meth:`run`; what it learned is kept in the
    search's parts).

    Args:
        search: the search whose parts it uses (proposals, heuristic, edges, transitions, components, settings,
            budget and counters), and through which it records the nodes it reaches.

    Attributes:
        reopened: times each node was reached again at another configuration (``reexpand``, :meth:`reopen`).
    """

    def __init__(self, search: StanceGraphSearch):
        self.search = search
        self.reopened: dict[NodeKey, int] = {}
        #: the queue kept between runs (``resume = "queue"``): ``(start, closed nodes, queue, counter)``
        self.kept: tuple[Node, dict[NodeKey, Node], list[Entry], list[int]] | None = None

    def run(self, start: Node) -> Node | None:
        """Best first from ``start`` by cost plus the weighted heuristic; a goal node or ``None`` (no edge left).

        With ``resume = "queue"`` a run from the same start goes on with the queue the last run left (Fig. 16:
        after a failed candidate "EXPLORE-STANCEGRAPH resumes exploration"; :meth:`failed` prepares it)."""
        sg = self.search
        if sg.settings.resume == "queue" and self.kept is not None and self.kept[0] is start:
            _, closed, heap, counter = self.kept
        else:
            closed, heap, counter = {start.key: start}, [], [0]
            if sg.arrived(start.key):
                return start
            self._push(start, heap, counter)
            self.kept = (start, closed, heap, counter)

        def push(node: Node) -> None:
            self._push(node, heap, counter)

        while heap or self.reopen(closed, push, heap):
            sg.budget.check()
            _, _, _, node, (action, limb, hold, nxt, k) = heapq.heappop(heap)
            q = self._pop_transition(node, action, limb, hold, nxt, k)
            if q is None:
                continue
            key = sg.components.key(node, nxt, q)
            if key in closed:
                continue
            child = closed[key] = sg.explore(node, key, q, (action, limb, hold))
            if sg.arrived(key):
                return child
            push(child)
        return None

    def failed(self, chain: list[Node], reached: int) -> None:
        """Before the queue is resumed after the candidate ``chain`` stopped at ``reached`` (``resume = "queue"``): the
        nodes reached through the failed edge leave the closed set (other routes may reach them, as the stance graph
        of Fig. 16 keeps every edge to a stance not yet explored), the failed edge is queued again at its lowered
        ``P`` (sec. 3.3.3 reduces it rather than deleting it), and the queue is re-ordered by the costs as they now
        are (a node's cost is the sum of ``1 - ln P`` along its route)."""
        if self.kept is None or reached + 1 >= len(chain):
            return
        sg = self.search
        start, closed, heap, counter = self.kept
        cut = chain[reached + 1].key
        memo: dict[int, float] = {}

        def g(node: Node) -> float:
            if id(node) not in memo:
                memo[id(node)] = 0.0 if node.parent is None else g(node.parent) + sg.edges.cost(node.parent.key,
                                                                                                 node.stance)
            return memo[id(node)]

        def below_cut(node: Node | None) -> bool:
            while node is not None:
                if node.key == cut:
                    return True
                node = node.parent
            return False

        for key in [k for k, nd in closed.items() if below_cut(nd)]:
            del closed[key]
        u, v = chain[reached], chain[reached + 1]
        if u.key in closed and v.action is not None:
            counter[0] += 1
            heap.append((0.0, -u.depth, counter[0], closed[u.key], (*v.action, v.stance, None)))
        w = sg.settings.heuristic_weight
        heap[:] = [(g(nd) + sg.edges.cost(nd.key, e[3]) + (w * sg.heuristic(e[3], after(nd.last, *e[:3])) if w else 0),
                    d, c, nd, e) for _, d, c, nd, e in heap]
        heapq.heapify(heap)

    def _push(self, node: Node, heap: list[Entry], counter: list[int]) -> None:
        """Queue the edges out of ``node`` (Fig. 16 lines 8-13) that are neither known to have no transition nor
        dropped; in the eager mode only those whose transition FIND-TRANSITION finds."""
        sg = self.search
        s = sg.settings
        for action, limb, hold, nxt in sg.proposals(node):
            if (node.key, nxt) in sg.transitions.by_edge and sg.transitions.by_edge[(node.key, nxt)] is None:
                continue
            if sg.edges.dropped((node.key, nxt)):
                continue
            if s.transitions == "eager" and sg.transitions.get(node, nxt) is None:
                continue  # Fig. 16 lines 10-12: FIND-TRANSITION when the node is expanded
            lt = after(node.last, action, limb, hold)
            h = sg.proposals.release_heuristic(node, limb, nxt, lt) if action == "release" and s.release_lookahead \
                and s.heuristic_weight else sg.heuristic(nxt, lt)
            f = node.g + sg.edges.cost(node.key, nxt) + s.heuristic_weight * h
            # a grab from one contact onto a point stance: one edge per transition point, nearest first
            points = range(len(sg.transitions.points(node, nxt))) if action == "grab" and len(node.stance) == 1 \
                and sg.components.dim(nxt) <= 0 else [None]
            for k in points:
                counter[0] += 1
                heapq.heappush(heap, (f, -node.depth, counter[0], node, (action, limb, hold, nxt, k)))

    def _pop_transition(self, node: Node, action: str, limb: str, hold: str, nxt: Any, k: int | None) -> Any:
        """The transition of a popped edge: FIND-TRANSITION (skipping an edge failed from other components), or the
        ``k``-th transition point once a path to it is found (``None`` when there is none)."""
        sg = self.search
        if k is None:
            return sg.transitions.get(node, nxt, skip=True)
        # the component of a single contact is known only through the paths found in it: the edge
        # is verified when popped (the component graph of Bretl 2006, Fig. 13(b), built as met)
        if sg.edges.dropped((node.key, nxt)):
            return None
        q = sg.transitions.points(node, nxt)[k]
        if sg.stage2.connect(node, Node((nxt, ()), q, 0.0, node, (action, limb, hold), ())) is None:
            sg.edges.path_failed(node, nxt)
            return None
        sg.components.members.setdefault((node.stance, qkey(q)), node.key[1])
        return q

    def reopen(self, closed: dict[NodeKey, Node], push: Callable[[Node], None], heap: list[Any]) -> bool:
        """When EXPLORE-STANCEGRAPH has no edge left: reach an expanded node again at another configuration and
        expand it from there (the ``reexpand`` setting); whether edges were queued.

        A node keeps the configuration it was first reached at, and FIND-TRANSITION draws the base near it
        (:mod:`climb_ompl.climb.transition`): a posture at the edge of the joint limits or of the support region can
        close every edge out of a stance that another posture of the same stance leaves open.  The nodes are
        drawn again nearest the goal first (deepest first on ties), so the frontier where the search stopped
        comes first, and farther back only when no node nearer the goal opens an edge; the first node that
        does ends the call.  Each node is drawn again at most ``reexpand`` times: one FIND-TRANSITION from the
        parent's configuration onto the node's stance, skipping the draw that gave the first configuration; its
        edges' failed transitions are forgotten.  The start keeps its configuration (the robot is there): its
        failed edges are forgotten and tried again, FIND-TRANSITION drawing anew (its seed counts the calls), up to
        :data:`START_RETRIES` times: nothing can be explored before one of them opens, and a round costs one
        FIND-TRANSITION call per edge.  A start whose only way out is a transition found by one call in ten
        (LEMUR on a wall of holds leaning 35-65 degrees from the wall, seed 4) is otherwise a graph exhausted after
        one node.  Single contacts and point stances are named by their configuration
        (:meth:`~climb_ompl.climb.nodes.Components.key`) and are left alone.
        """
        sg = self.search
        if not sg.settings.reexpand or not closed:
            return False
        limit = sg.settings.reexpand
        order = sorted(((sg.heuristic(n.stance, n.last), -n.depth, i, n) for i, n in enumerate(closed.values())
                        if sg.components.bends_name(n.stance)
                        and self.reopened.get(n.key, 0) < (limit if n.parent is not None else START_RETRIES)))
        for *_, node in order:
            if node.parent is None:  # the start: its failed edges again, from where the robot stands
                if not sg.transitions.forget_failed(node.key):
                    continue
                self._count(node.key)
                push(node)
            elif not self._draw_again(node, closed, push):
                continue
            if heap:
                return True
        return False

    def _count(self, key: NodeKey) -> None:
        """Count a re-expansion of the node ``key``."""
        self.reopened[key] = self.reopened.get(key, 0) + 1
        self.search.stats.reexpanded += 1

    def _draw_again(self, node: Node, closed: dict[NodeKey, Node], push: Callable[[Node], None]) -> bool:
        """Reach ``node`` (not the start) again from its parent at another configuration and queue its edges;
        whether it was (a draw found, not in another component expanded already)."""
        sg = self.search
        self.reopened[node.key] = self.reopened.get(node.key, 0) + 1
        parent = node.parent
        assert parent is not None and node.action is not None
        q = sg.transitions.find(parent.stance, node.stance, parent.q, stride=REOPEN_STRIDE, skip_first=True)
        if q is None:
            return False
        key = sg.components.key(parent, node.stance, q)
        if key != node.key and key in closed:
            return False  # the other component was expanded already
        sg.transitions.forget_failed(key)
        sg.stats.reexpanded += 1
        child = closed[key] = sg.explore(parent, key, q, node.action)
        push(child)
        return True


__all__ = ["REOPEN_STRIDE", "START_RETRIES", "StanceGraphStage"]
