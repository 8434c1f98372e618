"""EXPLORE-TRANSITIONGRAPH, stage 2 of the search of Bretl (2006), Fig. 16: paths between the transitions of a
candidate sequence, with repairs.

When stage 1 (:mod:`climb_ompl.climb.stage1`) reaches a goal node it returns the candidate sequence; consecutive
transitions are connected from the start, first by the direct local path (:mod:`climb_ompl.climb.local_path`), then
by FIND-PATH (:func:`climb_ompl.climb.onestep.find_path`, any OMPL planner) within ``step_time_limit``
(:class:`climb_ompl.climb.transition_graph.TransitionGraph`).  Paths found are kept, so a later candidate sharing a
prefix costs nothing to re-check.  When an edge cannot be connected, ``repairs`` other transitions of that edge are
tried (Fig. 16 line 2, "in each component"); if none connects, the edge's probability ``P`` is lowered
(sec. 3.3.3, :meth:`climb_ompl.climb.edges.EdgeBook.path_failed`).  With ``stage2 = "recursive"`` the stage is
Fig. 16's recursive search with backtracking over the transitions of each edge (:meth:`TransitionStage.run_recursive`).
"""

from __future__ import annotations

from collections.abc import Iterator
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np

from climb_ompl.climb.nodes import Node
from climb_ompl.climb.transition_graph import qkey

if TYPE_CHECKING:
    from climb_ompl.climb.search import StanceGraphSearch

#: Stride of the seeds of stage 2's repair draws (FIND-TRANSITION's seed: the search's seed plus the stride times
#: the call count), apart from stage 1's
REPAIR_STRIDE = 7919


class TransitionStage:
    """EXPLORE-TRANSITIONGRAPH along the candidates of one search.

    Args:
        search: the search whose parts it uses (its transition graph, edges, transitions, components, settings,
            budget and counters).
    """

    def __init__(self, search: StanceGraphSearch):
        self.search = search

    def run(self, chain: list[Node]) -> tuple[int, list[list[np.ndarray]]]:
        """Paths between the transitions of ``chain`` (a candidate, start first).

        Connects consecutive transitions by :meth:`connect` (the direct local path, then FIND-PATH).  When
        an edge cannot be connected, up to ``repairs`` other transitions of the same edge are sampled
        near the configuration reached (Fig. 16 line 2 tries the transitions "in each component"); the
        candidate is updated in place when one connects.  Otherwise the edge's probability is lowered.

        Returns:
            The index of the farthest node reached and the paths up to it.
        """
        sg = self.search
        if sg.settings.stage2 == "recursive":
            return self.run_recursive(chain)
        paths: list[list[np.ndarray]] = []
        for i in range(len(chain) - 1):
            u, v = chain[i], chain[i + 1]
            if i > 0 and v.action is not None and v.action[0] == "release" and not np.array_equal(u.q, v.q) \
                    and sg.feas.valid(v.stance, u.q):
                v = chain[i + 1] = replace(v, q=u.q, parent=u)  # zero-length again
            path, v = self._connect_or_repair(u, v)
            if path is None:
                sg.edges.path_failed(u, v.stance)
                return i, paths
            chain[i + 1] = v
            if i + 2 < len(chain):
                w = chain[i + 2]
                chain[i + 2] = replace(w, parent=v)
            paths.append(path)
        return len(chain) - 1, paths

    def run_recursive(self, chain: list[Node]) -> tuple[int, list[list[np.ndarray]]]:
        """EXPLORE-TRANSITIONGRAPH as Fig. 16 of Bretl (2006) has it: from the configuration reached at ``chain[i]``,
        each transition onto ``chain[i + 1]``'s stance in turn (:meth:`_transitions`: stage 1's, then ``repairs``
        drawn, one per component) whose path FIND-PATH finds is followed recursively; a branch that stops short of
        the goal is backtracked.  A configuration already explored at an index without reaching the goal is not
        explored again.  On success ``chain`` is updated in place; otherwise the edge out of the farthest node
        reached has its ``P`` lowered (sec. 3.3.3: "rather than delete (sigma, sigma'), we reduce its
        probability"), charged with the FIND-PATH budgets spent on that edge.

        Returns:
            The index of the farthest node reached and the paths up to it.
        """
        sg = self.search
        n = len(chain) - 1
        best: dict[int, list[list[np.ndarray]]] = {0: []}  # the farthest index reached: the paths to it
        dead: set[tuple[int, bytes]] = set()
        spent: dict[int, int] = {}
        nodes, paths = [chain[0]], []
        unit = float(sg.settings.path_iterations or 1)

        def explore(i: int) -> bool:
            u = nodes[i]
            if i > max(best):
                best[i] = list(paths)
            if i == n:
                return True
            mark = (i, qkey(u.q))
            if mark in dead:
                return False
            for v in self._transitions(u, chain[i + 1]):
                c0 = sg.graph.checks
                path = self.connect(u, v)
                spent[i] = spent.get(i, 0) + sg.graph.checks - c0
                if path is None:
                    continue
                nodes.append(v)
                paths.append(path)
                if explore(i + 1):
                    return True
                nodes.pop()
                paths.pop()
            dead.add(mark)
            return False

        if explore(0):
            chain[:] = nodes
            return n, paths
        i = max(best)
        sg.edges.path_failed(chain[i], chain[i + 1].stance, spent.get(i, 0) / unit)
        return i, best[i]

    def _transitions(self, u: Node, v: Node) -> Iterator[Node]:
        """The transitions from ``u`` (a node reached by stage 2) onto ``v``'s stance, as nodes whose parent is ``u``:
        a zero-length release where ``u`` stands, stage 1's transition, then up to ``repairs`` drawn about ``u``
        (Fig. 16 line 2, "in each component": a draw in a component already tried is skipped)."""
        sg = self.search
        seen: set[object] = set()
        if v.action is not None and v.action[0] == "release" and sg.feas.valid(v.stance, u.q):
            seen.add(v.key)
            yield replace(v, q=u.q, parent=u)
        if v.key not in seen:
            seen.add(v.key)
            yield replace(v, parent=u)
        for _ in range(sg.settings.repairs):
            q_new = sg.transitions.find(u.stance, v.stance, u.q, stride=REPAIR_STRIDE, skip_first=True)
            if q_new is None:
                continue
            key = sg.components.key(u, v.stance, q_new)
            if key in seen:
                continue
            seen.add(key)
            yield replace(v, key=key, q=q_new, parent=u)

    def _connect_or_repair(self, u: Node, v: Node) -> tuple[list[np.ndarray] | None, Node]:
        """A path from ``u`` to ``v``, or to another transition of the same edge (up to ``repairs`` drawn, the
        first that connects); the path (``None`` when none) and the node it reaches."""
        sg = self.search
        path = self.connect(u, v)
        rep = 0
        while path is None and rep < sg.settings.repairs:
            rep += 1
            q_new = sg.transitions.find(u.stance, v.stance, u.q, stride=REPAIR_STRIDE, skip_first=True)
            if q_new is None:
                continue
            cand = replace(v, key=sg.components.key(u, v.stance, q_new), q=q_new, parent=u)
            path = self.connect(u, cand)
            if path is not None:
                v = cand
                sg.stats.repaired += 1
        return path, v

    def connect(self, u: Node, v: Node) -> list[np.ndarray] | None:
        """A path in ``F_sigma(u)`` from ``u.q`` to ``v.q`` (:meth:`TransitionGraph.connect`); a connection that
        failed before is planned again with more effort (``path_retry_growth`` to the power of the edge's failures)
        while its edge is not dropped."""
        sg = self.search
        moving = v.action[1] if v.action is not None and v.action[0] == "grab" else None
        effort = sg.settings.path_retry_growth ** sg.edges.fails.get((u.key, v.stance), 0)
        path = sg.graph.connect(u.stance, u.q, v.q, moving, sg.budget.check,
                                max(0.1, sg.settings.time_limit - sg.budget.elapsed()), effort)
        sg.report("path")
        return path


__all__ = ["REPAIR_STRIDE", "TransitionStage"]
