"""EXPLORE-STANCEGRAPH and EXPLORE-TRANSITIONGRAPH: the two-stage search of Bretl (2006), Fig. 16.

A climb is a sequence of *steps*, each one grab or one release (Bretl 2006, sec. 2.1).  The search
alternates two stages:

1. **Stance graph** (EXPLORE-STANCEGRAPH, :mod:`climb_ompl.climb.stage1`).  Nodes are ``(stance, component)``
   pairs (:mod:`climb_ompl.climb.nodes`): a stance (limb -> hold) and the connected component of its feasible
   space, named by the bend sign of every contact limb's elbow (sec. 4.2.3).  Searching over pairs is what lets
   the double-link robot revisit stance 2 in another component (Fig. 13(b):
   ``F_1 -> F_2^1 -> F_3 -> F_2^3 -> F_4``).  Edges add or remove one contact and are proposed when the geometry
   allows it (:mod:`climb_ompl.climb.heuristic`); their probabilities and FIND-TRANSITION calls are kept by
   :mod:`climb_ompl.climb.edges`.  The queue is ordered by the cost ``n - sum ln P`` of sec. 3.3.3 plus, in the
   guided search, a weighted goal heuristic.
2. **Transition graph** (EXPLORE-TRANSITIONGRAPH, :mod:`climb_ompl.climb.stage2`).  When stage 1 reaches a goal node
   it returns the candidate sequence; consecutive transitions are connected from the start by the direct local
   path, then by FIND-PATH, with ``repairs``; an edge without a path has its probability ``P`` lowered.

The settings (:class:`climb_ompl.settings.ClimbSettings`) choose between Fig. 16 as published and the
guided search's departures (the A* heuristic, lazy transitions, dropping an edge after a few failures, resuming
from the farthest transition reached, reaching an expanded node again at another configuration when the stance
graph runs out of edges: :meth:`climb_ompl.climb.stage1.StanceGraphStage.reopen`; folding a limb's two successive
moves of a candidate into one before stage 2: :mod:`climb_ompl.climb.shortcut`).  A re-plan's search starts warm
(:mod:`climb_ompl.climb.warm`).  :class:`StanceGraphSearch` holds the parts and alternates the stages; its
:meth:`~StanceGraphSearch.run` returns a :class:`SearchOutcome` whose ``status`` says how it ended
(:class:`climb_ompl.climb.status.ClimbStatus`).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from climb_ompl.climb.budget import Budget, BudgetSpent
from climb_ompl.climb.edges import EdgeBook, TransitionCache
from climb_ompl.climb.goal import Goal
from climb_ompl.climb.heuristic import EdgeProposals, GoalHeuristic
from climb_ompl.climb.nodes import Action, Components, Node, NodeKey, after
from climb_ompl.climb.shortcut import shorten
from climb_ompl.climb.stage1 import StanceGraphStage
from climb_ompl.climb.stage2 import TransitionStage
from climb_ompl.climb.stats import SearchStats
from climb_ompl.climb.status import ClimbStatus
from climb_ompl.climb.transition import TransitionFinder
from climb_ompl.climb.transition_graph import TransitionGraph
from climb_ompl.climb.warm import WarmStart, follow_hints, inherit
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.model.terrain import Terrain
from climb_ompl.settings import ClimbSettings

#: Start of the reason given when the stance graph holds no route (:attr:`ClimbStatus.EXHAUSTED`).
EXHAUSTED = "the stance graph is exhausted"
#: Start of the reason given when the time budget is spent (:attr:`ClimbStatus.BUDGET`).
BUDGET_SPENT = "time budget of"

ProgressFn = Callable[[dict[str, Any]], None]


@dataclass
class SearchOutcome:
    """How :meth:`StanceGraphSearch.run` ended.

    Attributes:
        status: ``FOUND``, ``EXHAUSTED``, ``BUDGET`` or ``STANCE_LIMIT``
            (:class:`~climb_ompl.climb.status.ClimbStatus`).
        chain: the plan's nodes, start first (``FOUND``), else ``None``.
        paths: the path into each node of ``chain`` after the first.
        reason: why there is no plan, in words (``""`` when found).
    """

    status: ClimbStatus
    chain: list[Node] | None = None
    paths: list[list[np.ndarray]] = field(default_factory=list)
    reason: str = ""


class StanceGraphSearch:
    """The two-stage search (Bretl 2006, Fig. 16) of one climb query: its parts, caches and counters.

    Args:
        robot, terrain, goal: the query.
        settings: every setting of the climb.
        seed: seed of every random choice.
        progress: called with a dict (``phase, elapsed_s, stances_explored, onestep_calls, fraction``).
        t0: the query's start time (``time.perf_counter()``), shared with the start search.

    Attributes:
        robot, terrain, goal, settings, seed: the query's.
        feas: the feasibility tests; finder: FIND-TRANSITION; graph: the transition graph (paths, FIND-PATH).
        limbs: the robot's limb names; reach: its largest limb reach, m.
        explored: the ``(stance, component)`` keys of the nodes explored.
        budget: the time budget and limit of nodes (:class:`~climb_ompl.climb.budget.Budget`).
        stats: the counters (:class:`~climb_ompl.climb.stats.SearchStats`).
        components: the nodes' component labels (:class:`~climb_ompl.climb.nodes.Components`).
        heuristic: the goal heuristic, ``heuristic(stance, last)`` (:class:`~climb_ompl.climb.heuristic.GoalHeuristic`).
        proposals: the edges proposed out of a node (:class:`~climb_ompl.climb.heuristic.EdgeProposals`).
        edges: the edges' probabilities and failures (:class:`~climb_ompl.climb.edges.EdgeBook`).
        transitions: FIND-TRANSITION per edge (:class:`~climb_ompl.climb.edges.TransitionCache`).
        stage1, stage2: EXPLORE-STANCEGRAPH and EXPLORE-TRANSITIONGRAPH.
        warm: the warm start (:class:`~climb_ompl.climb.warm.WarmStart`; empty unless :meth:`inherit` gave one).
        joins: components a goal node must be in, by stance (:attr:`WarmStart.joins`; stances not listed: any).
        best: the node explored nearest the goal by the heuristic.
        stuck: stage-2 failures by the node where the candidate stopped.
        exhausted: the last run ended with no edge left to try (not by its budget).
    """

    def __init__(self, robot: Any, terrain: Terrain, goal: Goal, settings: ClimbSettings, *, seed: int = 0,
                 progress: ProgressFn | None = None, t0: float | None = None):
        self.settings = settings
        self.robot, self.terrain, self.goal, self.seed, self.progress = robot, terrain, goal, int(seed), progress
        self.feas = Feasibility.of(robot, terrain, settings)
        self.finder = TransitionFinder.of(self.feas, settings)
        self.graph = TransitionGraph(self.feas, settings, seed=seed)
        self.limbs = [lb.name for lb in robot.limbs]
        self.explored: set[NodeKey] = set()
        self.budget = Budget(settings.time_limit, t0, self.explored)
        self.stats = SearchStats()
        self.components = Components(robot)
        self.heuristic = GoalHeuristic(robot, terrain, goal, settings)
        self.reach = self.heuristic.reach
        self.proposals = EdgeProposals(robot, terrain, self.feas, settings, self.heuristic)
        self.edges = EdgeBook(settings, self.stats)
        self.transitions = TransitionCache(self.finder, self.feas, self.components, settings, self.stats,
                                           self.seed, self.budget.check)
        self.stage1 = StanceGraphStage(self)
        self.stage2 = TransitionStage(self)
        self.warm = WarmStart()
        self.joins: dict[Any, set[tuple[int, ...]]] = {}
        self.best: Node | None = None
        self.stuck: dict[NodeKey, int] = {}
        self.exhausted = False
        self._h0 = 0.0

    def inherit(self, warm: WarmStart) -> None:
        """Re-use an earlier search's knowledge where a terrain change leaves it valid
        (:func:`climb_ompl.climb.warm.inherit`)."""
        inherit(self, warm)

    # ---- nodes -------------------------------------------------------------------------------------------
    def follow(self, start: Node, actions: Sequence[Action], near: Sequence[Any] | None = None) -> Node | None:
        """The node reached by taking ``actions`` (``(grab|release, limb, hold)``) in turn from ``start``, one
        FIND-TRANSITION each, or ``None`` when a step has no transition or the end does not meet the goal.

        A given stance sequence needs no exploration: a re-plan follows the old route on holds that moved or
        changed friction before it searches.  ``near``: per action, a configuration the transition had before (the
        old route's): FIND-TRANSITION is drawn about it first (its first draw is that configuration with the chains
        re-closed onto the holds as they are now), then about the node reached, as the search does.  Grabs from a
        single contact onto a point stance (whose transitions are found as points) are left to stage 1.
        """
        node = self.take_steps(start, actions, near)
        return node if node is not None and self.arrived(node.key) else None

    def take_steps(self, start: Node, actions: Sequence[Action], near: Sequence[Any] | None = None,
                   *, record: bool = True) -> Node | None:
        """The node reached by taking ``actions`` in turn from ``start`` (as :meth:`follow`, wherever it ends), or
        ``None`` when a step has no transition.  ``record``: the nodes reached count as explored (:meth:`explore`);
        without it they are only built (a shortcut tried, :mod:`climb_ompl.climb.shortcut`, counts once kept)."""
        node = start
        for i, edge in enumerate(actions):
            # only an edge the search itself would propose (EdgeProposals)
            nxt = next((n for *e, n in self.proposals(node) if tuple(e) == tuple(edge)), None)
            if nxt is None or (edge[0] == "grab" and len(node.stance) == 1 and self.components.dim(nxt) <= 0):
                return None
            q = None
            if near is not None and i < len(near) and near[i] is not None \
                    and (node.key, nxt) not in self.transitions.by_edge:
                q = self.transitions.about(node, nxt, np.asarray(near[i], dtype=float))
            if q is None:
                q = self.transitions.get(node, nxt)
            if q is None:
                return None
            key = self.components.key(node, nxt, q)
            node = self.explore(node, key, q, tuple(edge)) if record else self.make_node(node, key, q, tuple(edge))
        return node

    def arrived(self, key: NodeKey) -> bool:
        """Whether the search node ``key`` meets the goal: its stance does and, for a stance with components to
        join (:attr:`joins`), it is in one of them."""
        stance, component = key
        return self.goal.met(stance, self.terrain, self.reach) and component in self.joins.get(stance, (component,))

    def make_node(self, node: Node, key: NodeKey, q: np.ndarray, edge: Action) -> Node:
        """The search node ``key`` reached at ``q`` from ``node`` by ``edge`` (``(action, limb, hold)``)."""
        return Node(key, q, node.g + self.edges.cost(node.key, key[0]), node, edge, after(node.last, *edge),
                    node.depth + 1)

    def explore(self, node: Node, key: NodeKey, q: np.ndarray, edge: Action) -> Node:
        """:meth:`make_node`, counted as explored and tracked as the best so far."""
        child = self.make_node(node, key, q, edge)
        self.record(child)
        return child

    def record(self, node: Node) -> None:
        """Count ``node`` as explored and track it as the best so far."""
        self.explored.add(node.key)
        if self.best is None or self.heuristic(node.stance, node.last) < self.heuristic(self.best.stance,
                                                                                        self.best.last):
            self.best = node
        self.report("stances")

    def report(self, phase: str, **extra: Any) -> None:
        """Call :attr:`progress`, if any, with the search's figures (``fraction``: of the start's heuristic
        covered by the best node's)."""
        if self.progress is None:
            return
        h0 = self._h0
        hb = self.heuristic(self.best.stance, self.best.last) if self.best is not None else h0
        frac = 0.0 if not h0 else max(0.0, min(1.0, 1.0 - (hb or 0.0) / h0))
        self.progress({"phase": phase, "elapsed_s": self.budget.elapsed(), "stances_explored": len(self.explored),
                       "onestep_calls": self.stats.transition_calls + self.graph.path_calls,
                       "candidates": self.stats.candidates, "fraction": frac, **extra})

    # ---- driver ------------------------------------------------------------------------------------------
    def run(self, start_stance: Any, q_start: np.ndarray) -> SearchOutcome:
        """Follow the warm start's hints, then alternate the two stages until a plan, an exhausted stance graph or
        the budget."""
        start = Node(self.components.key(None, start_stance, q_start), q_start, 0.0, None, None, ())
        self._h0 = self.heuristic(start_stance, ())
        self.best = start
        self.explored.add(start.key)
        try:
            found = follow_hints(self, start) or self._alternate(start)
        except BudgetSpent as stop:
            limit = bool(str(stop))
            why = f"{stop} reached" if limit else f"{BUDGET_SPENT} {self.settings.time_limit:g} s spent"
            text = f"{why} after {self.stats.candidates_text(self.graph)}; {self._frontier_text()}"
            return SearchOutcome(ClimbStatus.STANCE_LIMIT if limit else ClimbStatus.BUDGET, reason=text)
        if found is None:
            self.exhausted = True
            return SearchOutcome(ClimbStatus.EXHAUSTED, reason=f"{EXHAUSTED}: no sequence of feasible grabs and "
                                 f"releases reaches the goal; {self._frontier_text()}")
        return SearchOutcome(ClimbStatus.FOUND, *found)

    def _alternate(self, start: Node) -> tuple[list[Node], list[list[np.ndarray]]] | None:
        """Stage 1 to a goal node, then stage 2 along its candidate, until one connects (``(chain, paths)``) or stage
        1 finds no goal node from the start (``None``)."""
        root = start
        while True:
            goal_node = self.stage1.run(root)
            if goal_node is None:
                if root is not start:  # the verified prefix is a dead end: search again from the start
                    root = start
                    continue
                return None
            self.stats.candidates += 1
            chain = goal_node.chain()
            if self.settings.shortcuts and self.budget.max_stances is None:  # (a rejoining search's detours are short)
                short = shorten(self, chain)
                self.stats.shortcut_steps = len(chain) - len(short)
                chain = short
            reached, paths = self.stage2.run(chain)
            if reached == len(chain) - 1:
                return chain, paths
            if self.settings.resume == "queue":  # Fig. 16: EXPLORE-STANCEGRAPH goes on with its queue
                self.stage1.failed(goal_node.chain(), reached)
                continue
            root = self._resume_from(chain, reached)

    def _resume_from(self, chain: list[Node], reached: int) -> Node:
        """Where stage 1 resumes after a candidate stopped at node ``reached``: from the farthest transition reached
        (its prefix is verified); when candidates keep failing at the same node, from further back each time (2, 4,
        8 ... steps): the way out may need another hold a few steps earlier."""
        n = self.stuck[chain[reached].key] = self.stuck.get(chain[reached].key, 0) + 1
        if n > 1 and reached > 0:  # the node itself looks like a dead end: the edge into it loses P too
            self.edges.lower((chain[reached - 1].key, chain[reached].stance))
        return chain[max(0, reached - (2 ** (n - 1) if n > 1 else 0))]

    # ---- reports -----------------------------------------------------------------------------------------
    def frontier(self) -> list[Any]:
        """The stances explored, nearest the goal first: smallest heuristic, then highest hold, then name (what the
        no-plan reason names and :func:`climb_ompl.climb.frontier.diagnose_frontier` diagnoses)."""
        stances = dict.fromkeys(key[0] for key in self.explored)
        return sorted(stances, key=lambda s: (self.heuristic(s, ()),
                                              -max(self.terrain.height(h) for h in s.hold_ids), str(s)))

    def _frontier_text(self) -> str:
        ranked = self.frontier()
        where = "" if not ranked else (f"closest stance to the goal: {ranked[0]} (estimated "
                                       f"{self.heuristic(ranked[0], ()):.1f} steps away)")
        return f"{len(self.explored)} (stance, component) nodes explored; {where}"

    def summary(self) -> dict[str, Any]:
        """The counters as a dict (:meth:`SearchStats.to_dict`; the plan's ``totals`` take the reproducible ones)."""
        return self.stats.to_dict(self.graph, len(self.explored), self.budget.elapsed())

    def timings(self) -> dict[str, Any]:
        """Wall-clock figures (not reproducible; kept apart in the plan file)."""
        return self.stats.timings(self.graph, self.budget.elapsed())


__all__ = ["BUDGET_SPENT", "EXHAUSTED", "SearchOutcome", "StanceGraphSearch"]
