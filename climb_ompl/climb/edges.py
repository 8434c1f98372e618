"""The stance graph's edges: their probabilities and stage-2 failures (:class:`EdgeBook`, Bretl 2006, sec. 3.3.3),
and the FIND-TRANSITION call behind each one, cached (:class:`TransitionCache`, Fig. 16 lines 10-12).

An edge is ``(node key, next stance)``: from a ``(stance, component)`` node (:mod:`climb_ompl.climb.nodes`) to a
stance one contact more or less.  Its cost in the search's queue is ``1 - ln P`` (sec. 3.3.3); ``P`` starts at
:data:`P_INITIAL` and is multiplied by :data:`P_FAIL_FACTOR` each time stage 2 finds no path to a transition of
the edge (deleting the edge would make the search "return failure incorrectly", sec. 3.3.3), or, with
``edge_p = "time"``, is inversely proportional to the effort spent on the edge (:meth:`EdgeBook.p`); the guided
search drops an edge after ``max_edge_failures`` such failures.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable
from typing import Any

import numpy as np

from climb_ompl.climb.nodes import Components, Node, NodeKey
from climb_ompl.climb.stats import SearchStats
from climb_ompl.climb.transition import TransitionFinder
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.settings import ClimbSettings

#: Probability of a stance-graph edge before it was tried (Bretl 2006, sec. 3.3.3).
P_INITIAL = 0.9
#: Factor applied to an edge's probability when no path connects it.
P_FAIL_FACTOR = 0.3

#: ``(node key, next stance)``
Edge = tuple[NodeKey, Any]


def step_text(stance: Any, nxt: Any) -> str:
    """The step from ``stance`` to the adjacent ``nxt`` in words: ``"grab lh h9"`` or ``"release lh h9"``."""
    added, removed = set(nxt.limbs) - set(stance.limbs), set(stance.limbs) - set(nxt.limbs)
    if len(added) == 1 and not removed:
        (limb,) = added
        return f"grab {limb} {nxt[limb]}"
    if len(removed) == 1 and not added:
        (limb,) = removed
        return f"release {limb} {stance[limb]}"
    return f"to {nxt}"  # (not an edge of the stance graph)


class EdgeBook:
    """Probabilities and stage-2 failures of the stance graph's edges (Bretl 2006, sec. 3.3.3).

    Args:
        settings: the climb's settings (``max_edge_failures``).
        stats: the search's counters (``path_failures``, ``failed_steps``).

    Attributes:
        prob: ``P`` of the edges whose path failed (others: :data:`P_INITIAL`).
        fails: stage-2 failures by edge.
    """

    def __init__(self, settings: ClimbSettings, stats: SearchStats):
        self.s, self.stats = settings, stats
        self.prob: dict[Edge, float] = {}
        self.fails: dict[Edge, int] = {}
        #: effort spent on the edges whose path failed, in FIND-PATH budgets (``edge_p = "time"``, :meth:`p`)
        self.spent: dict[Edge, float] = {}

    def p(self, edge: Edge) -> float:
        """``P`` of ``edge``: with ``edge_p = "prior"`` :data:`P_INITIAL` times :data:`P_FAIL_FACTOR` per failure;
        with ``edge_p = "time"`` inversely proportional to the effort spent on it, ``P_INITIAL / (1 + e)`` with ``e``
        the FIND-PATH budgets spent on its failed connections (Bretl 2006, sec. 3.3.3: "inversely proportional to
        the amount of time spent exploring the stance manifold and the transition"; effort, not seconds, so that a
        seed gives one plan)."""
        if self.s.edge_p == "time":
            return P_INITIAL / (1.0 + self.spent.get(edge, 0.0))
        return self.prob.get(edge, P_INITIAL)

    def cost(self, key: NodeKey, nxt: Any) -> float:
        """The cost ``1 - ln P`` of the edge from the node ``key`` to the stance ``nxt`` (Bretl 2006, sec. 3.3.3)."""
        return 1.0 - math.log(self.p((key, nxt)))

    def dropped(self, edge: Edge) -> bool:
        """Whether ``edge`` failed ``max_edge_failures`` times (never with ``max_edge_failures = 0``)."""
        k = self.s.max_edge_failures
        return k > 0 and self.fails.get(edge, 0) >= k

    def lower(self, edge: Edge) -> None:
        """Multiply the probability of ``edge`` by :data:`P_FAIL_FACTOR` (Bretl 2006, sec. 3.3.3)."""
        self.prob[edge] = self.prob.get(edge, P_INITIAL) * P_FAIL_FACTOR

    def path_failed(self, u: Node, nxt: Any, effort: float = 1.0) -> None:
        """No path from ``u`` to a transition onto ``nxt``: lower the edge's ``P`` (Bretl 2006 sec. 3.3.3;
        in the guided search the edge is dropped after ``max_edge_failures``).  ``effort``: the FIND-PATH budgets
        spent on it this time (``edge_p = "time"`` counts at least one per failure)."""
        e = (u.key, nxt)
        self.fails[e] = self.fails.get(e, 0) + 1
        step = step_text(u.stance, nxt)
        self.stats.failed_steps[step] = self.stats.failed_steps.get(step, 0) + 1
        self.lower(e)
        self.spent[e] = self.spent.get(e, 0.0) + max(1.0, float(effort))
        self.stats.path_failures += 1


class TransitionCache:
    """FIND-TRANSITION (:class:`~climb_ompl.climb.transition.TransitionFinder`) per stance-graph edge, cached.

    Args:
        finder: FIND-TRANSITION with the climb's settings.
        feas: the feasibility tests.
        components: the component labels of the search's nodes.
        settings: the climb's settings (``transition_failures``).
        stats: the search's counters (``transition_calls``: each call's seed; ``transitions_skipped``,
            ``transition_times``).
        seed: the search's seed.
        check: called before each FIND-TRANSITION call; raises when the budget is spent
            (:meth:`climb_ompl.climb.budget.Budget.check`).

    Attributes:
        by_edge: the transition found for each edge tried (a configuration), ``None`` when none was.
        point_sets: the transition points from a single contact onto a point stance, by edge (:meth:`points`).
        failed_from: the nodes from which FIND-TRANSITION failed, by edge between stances
            (``transition_failures``, :meth:`failed_elsewhere`).
    """

    def __init__(self, finder: TransitionFinder, feas: Feasibility, components: Components,
                 settings: ClimbSettings, stats: SearchStats, seed: int, check: Callable[[], None]):
        self.finder, self.feas, self.components, self.s, self.stats = finder, feas, components, settings, stats
        self.seed, self.check = int(seed), check
        self.by_edge: dict[Edge, np.ndarray | None] = {}
        self.point_sets: dict[Edge, list[np.ndarray]] = {}
        self.failed_from: dict[tuple[Any, Any], set[NodeKey]] = {}

    def get(self, node: Node, nxt: Any, *, skip: bool = False) -> np.ndarray | None:
        """FIND-TRANSITION between ``node``'s stance and ``nxt``, near ``node.q`` (cached per edge).  ``skip``
        (stage 1): ``None``, not cached and not called, when the edge failed from ``transition_failures`` other
        components of the stance (:meth:`failed_elsewhere`)."""
        ck = (node.key, nxt)
        if ck in self.by_edge:
            return self.by_edge[ck]
        q: np.ndarray | None = None
        small = nxt if len(nxt) < len(node.stance) else node.stance
        dim = self.components.dim(node.stance)
        if len(nxt) < len(node.stance) and self.feas.valid(small, node.q):
            q = node.q  # a release right where we are: a zero-length step
        elif dim > 0 or len(nxt) > len(node.stance):
            if skip and self.failed_elsewhere(node, nxt):
                self.stats.transitions_skipped += 1
                return None  # (tried again if the node is expanded again: climb_ompl.climb.stage1)
            q = self.find(node.stance, nxt, node.q)
            if q is None and self.components.bends_name(node.stance):
                self.failed_from.setdefault((node.stance, nxt), set()).add(node.key)
            if q is not None and dim == 0 and len(nxt) < len(node.stance):
                q = None  # a point stance cannot move to another transition
        self.by_edge[ck] = q
        return q

    def find(self, stance: Any, nxt: Any, near: np.ndarray, *, stride: int = 1,
             skip_first: bool = False) -> np.ndarray | None:
        """One FIND-TRANSITION call between ``stance`` and ``nxt`` drawn about ``near``, counted, timed and seeded by
        its count times ``stride`` (the budget checked first).  A node reached again (``reexpand``) and stage 2's
        repairs draw with their own strides, ``skip_first``: another transition than the one ``near`` closes to."""
        self.check()
        t = time.perf_counter()
        self.stats.transition_calls += 1
        q = self.finder.find(stance, nxt, near, seed=self.seed + stride * self.stats.transition_calls,
                             skip_first=skip_first)
        self.stats.transition_times.append(time.perf_counter() - t)
        return q

    def about(self, node: Node, nxt: Any, ref: np.ndarray) -> np.ndarray | None:
        """FIND-TRANSITION between ``node``'s stance and ``nxt`` drawn about ``ref`` (a configuration this transition
        had before), kept as the edge's transition when found and in ``node``'s component; ``None`` otherwise (the
        edge is left to :meth:`get`)."""
        if self.components.dim(node.stance) <= 0 and len(nxt) <= len(node.stance):
            return None
        if len(nxt) < len(node.stance) and self.feas.valid(nxt, node.q):
            return None  # a release right where the robot is: :meth:`get` takes it, a zero-length step
        q = self.find(node.stance, nxt, ref)
        c = self.components
        if q is None or (c.bends_name(node.stance) and c.signature(node.stance, q) != c.signature(node.stance, node.q)):
            return None  # another component of the node's stance: no path to it
        self.by_edge[(node.key, nxt)] = q
        return q

    def points(self, node: Node, nxt: Any) -> list[np.ndarray]:
        """The transition points from ``node``'s single contact onto the point stance ``nxt`` (cached)."""
        ck = (node.key, nxt)
        if ck not in self.point_sets:
            self.point_sets[ck] = self.finder.points(node.q, node.stance, nxt)
        return self.point_sets[ck]

    def forget_failed(self, key: NodeKey) -> int:
        """Forget the failed transitions out of the node ``key`` (tried again when met), and the failures of its
        stance's edges from every component (``transition_failures`` skips none of them until they fail again); how
        many failed transitions there were out of ``key``."""
        failed = [e for e, v in self.by_edge.items() if e[0] == key and v is None]
        for e in failed:
            del self.by_edge[e]
        for e in [e for e in self.failed_from if e[0] == key[0]]:
            del self.failed_from[e]
        return len(failed)

    def failed_elsewhere(self, node: Node, nxt: Any) -> bool:
        """Whether FIND-TRANSITION failed for the edge ``node.stance -> nxt`` from ``transition_failures`` components of
        the stance other than ``node``'s (the setting; 0: never).  Only stances whose components the elbow bends name
        (:meth:`~climb_ompl.climb.nodes.Components.bends_name`) count: a single contact's component is named by the
        route it was entered through."""
        k = self.s.transition_failures
        return bool(k) and len(self.failed_from.get((node.stance, nxt), set()) - {node.key}) >= k


__all__ = ["EdgeBook", "P_FAIL_FACTOR", "P_INITIAL", "TransitionCache", "step_text"]
