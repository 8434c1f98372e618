"""EXPLORE-STANCEGRAPH and EXPLORE-TRANSITIONGRAPH: the two-stage search of Bretl (2006), Fig. 16.

A climb is a sequence of *steps*, each one grab or one release (Bretl 2006, sec. 2.1).  The search
alternates two stages:

1. **Stance graph** (EXPLORE-STANCEGRAPH).  Nodes are ``(stance, component)`` pairs: a stance
   (limb -> hold) and the connected component of its feasible space, named by the bend sign of every contact
   limb's elbow (sec. 4.2.3: "most of the time, connected components of ``F_sigma`` differ by an elbow
   bend").  Searching over pairs is what lets the double-link robot revisit stance 2 in another component
   (Fig. 13(b): ``F_1 -> F_2^1 -> F_3 -> F_2^3 -> F_4``).  Where elbow bends name nothing (a single
   contact, a zero-dimensional stance) the component is named by the point or the entry transition
   (:meth:`StanceGraphSearch._key`); a grab from a single contact onto a point stance is one edge per
   transition point (:meth:`climb_ompl.climb.transition.TransitionFinder.points`), each verified by a path when
   popped.  Edges add or remove one contact and are proposed when the geometry allows it (the new hold
   within reach of every contact hold, a non-empty support region after a release).  The queue is ordered
   by the cost ``n - sum ln P`` of sec. 3.3.3 (``1 - ln P(e)`` per step) plus, in the guided search, a
   weighted height heuristic.  FIND-TRANSITION (:mod:`climb_ompl.climb.transition`) is called when a node is
   expanded (``transitions = "eager"``, as in Fig. 16) or when the search pops the edge (``"lazy"``).
2. **Transition graph** (EXPLORE-TRANSITIONGRAPH).  When stage 1 reaches a goal node it returns the
   candidate sequence; consecutive transitions are connected from the start, first by the direct local
   path (:mod:`climb_ompl.climb.local_path`), then by FIND-PATH (:func:`climb_ompl.climb.onestep.find_path`, any OMPL
   planner) within ``step_time_limit``.  Paths found are kept, so a later candidate sharing a prefix costs
   nothing to re-check.  When an edge cannot be connected, ``repairs`` other transitions of that edge are
   tried (Fig. 16 line 2, "in each component"); if none connects, the edge's probability ``P`` is lowered
   (sec. 3.3.3: deleting edges makes the search "return failure incorrectly").

The settings (:class:`climb_ompl.settings.ClimbSettings`) choose between Fig. 16 as published and the
guided search's departures (the A* height heuristic, lazy transitions, dropping an edge after a few
failures, resuming from the farthest transition reached, reaching an expanded node again at another
configuration when the stance graph runs out of edges: :meth:`StanceGraphSearch._reopen`; folding a limb's two
successive moves of a candidate into one before stage 2: :mod:`climb_ompl.climb.shortcut`).

Heuristic of the guided search (a guide, not a bound): for the height goal, ``2 * sum_l gap_l / stride``
where ``gap_l`` is how far limb ``l``'s hold (its last hold while free) lies below ``h - reach``: each limb
needs about one release and one grab per stride.  With ``keep_shape`` a limb's height counts only up to where
the robot's nominal shape lets it be above each other limb ``k``: at most ``z_k + max(0, n_l - n_k) + s``,
where ``n`` are the nominal hand heights (:attr:`StanceGraphSearch.shape`) and ``s`` is a stride up the
wall's slope.  A limb left far behind holds the body back (the pair reach of the laggard and an empty support
region without it end such climbs), so the others' gains beyond it are not counted as progress and the
laggard's grabs come first; a stance more compact than the nominal one costs nothing.  The gaps are then
measured to the goal stance in the nominal shape, each limb ``n_l - min_k n_k`` above ``h - reach``: the goal
puts every hold at or above ``h - reach``, and the lowest limb gets there only once the others are above it as
the shape wants (without it the upper limbs stop at ``h - reach`` and the last grabs of the lower ones find
the stance too compact).

The heuristic counts a free limb at its last hold, so every release of a stance gets the same value (one step
more) and the queue would try them in limb order.  With ``release_lookahead`` (the default) a release is queued
with one step plus the smallest heuristic over the grabs the search would propose for the freed limb from the
node's configuration (:meth:`StanceGraphSearch._release_heuristic`): the limb that can climb highest goes first,
and a limb whose best grab gains nothing (the others hold it back) comes after the stances that do make progress.

For a goal hold (``limb`` on ``hold``), ``1 + [limb in contact] + (free other limbs) + 2 d / stride`` with ``d`` the
distance from the limb's own hold (its last one while free) to the goal hold: a free limb grabs again before the
goal limb lets go, as the height heuristic counts it.  (Measured from the nearest contact hold of any limb instead,
another limb stepping towards the goal hold would look like progress the goal limb cannot use: docs/climb.md.)

For a goal of stances (a re-plan rejoining the route it repairs), the heuristic counts a release and a grab per
limb on another hold plus the strides its hand travels, to the nearest target (:mod:`climb_ompl.climb.stance_gap`).
"""

from __future__ import annotations

import heapq
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from climb_ompl.climb.goal import Goal, robot_reach
from climb_ompl.climb.shortcut import shorten
from climb_ompl.climb.stance_gap import StanceGap
from climb_ompl.climb.transition import TransitionFinder
from climb_ompl.climb.transition_graph import TransitionGraph, qkey
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.manifold.stance import limb_hold_targets, manifold_dim
from climb_ompl.model.terrain import Terrain
from climb_ompl.settings import ClimbSettings

#: Probability of a stance-graph edge before it was tried (Bretl 2006, sec. 3.3.3).
P_INITIAL = 0.9
#: Factor applied to an edge's probability when no path connects it.
P_FAIL_FACTOR = 0.3
#: Start of the reason given when the stance graph holds no route (as opposed to a spent budget).
EXHAUSTED = "the stance graph is exhausted"
#: Start of the reason given when the time budget is spent.
BUDGET_SPENT = "time budget of"

ProgressFn = Callable[[dict[str, Any]], None]


@dataclass
class Node:
    """A node of the search: a ``(stance, component)`` key reached at configuration ``q``."""

    key: tuple[Any, tuple[Any, ...]]
    q: np.ndarray
    g: float
    parent: "Node | None"
    action: tuple[str, str, str] | None  # (grab|release, limb, hold) that led here
    last: tuple[tuple[str, str], ...]  # free limbs' last holds
    depth: int = 0

    @property
    def stance(self) -> Any:
        return self.key[0]

    def chain(self) -> list["Node"]:
        out, n = [], self
        while n is not None:
            out.append(n)
            n = n.parent
        return out[::-1]


@dataclass(frozen=True)
class WarmStart:
    """What a search may re-use from an earlier one on a terrain changed since (see :mod:`climb_ompl.climb.replan`).

    Attributes:
        search: the earlier :class:`StanceGraphSearch`, or ``None``.
        touched: ids of the holds the change altered: anything relying on them is dropped.
        route: steps of the earlier plan (:class:`~climb_ompl.plan.file.Step`) that rely on no touched hold: their
            transitions and paths.
        hints: routes to try, in order, before the search proper: each a sequence of ``(action, limb, hold)``
            from the start stance (:meth:`StanceGraphSearch.follow`); a re-plan gives the old route when
            the terrain change moved its holds or changed their friction.
        hint_configs: per hint (the same order; may be shorter), the configurations its transitions had, one per
            action: :meth:`StanceGraphSearch.follow` looks for each transition about it first (a re-plan: the old
            route's own transitions, re-closed onto holds that moved).
        joins: where a search whose goal is stances goes on from them, as ``(stance pairs, configuration)``: a
            goal node of a stance listed here must be in the component of one of its configurations (a re-plan
            rejoining the old route: the route goes on from its own configuration, and a detour arriving in
            another component of the stance has no path to it).
    """

    search: Any = None
    touched: frozenset[str] = frozenset()
    route: tuple[Any, ...] = ()
    hints: tuple[tuple[tuple[str, str, str], ...], ...] = ()
    hint_configs: tuple[tuple[Any, ...], ...] = ()
    joins: tuple[tuple[tuple[tuple[str, str], ...], Any], ...] = ()
    #: explore at most this many (stance, component) nodes (``None``: no limit), then stop as when the budget is
    #: spent: a re-plan's rejoining search, where a search to the goal does better than a long detour
    max_stances: int | None = None


def _nominal_heights(robot: Any, terrain: Terrain) -> tuple[dict[str, float], float]:
    """The nominal hands' heights about their mean, by limb, and the height gained per metre up the wall's
    slope (``up_wall . up``, :func:`climb_ompl.climb.start.wall_axes`)."""
    from climb_ompl.climb.start import wall_axes

    _, v = wall_axes(terrain)
    rise = float(abs(v @ terrain.up))
    hands = np.asarray(robot.hand_positions(np.asarray(robot.nominal_q, dtype=float)), dtype=float)
    along = (hands - hands.mean(axis=0)) @ v
    return {lb.name: float(a) * rise for lb, a in zip(robot.limbs, along, strict=True)}, rise


class _BudgetSpent(Exception):
    """Raised inside the search when the total time budget is spent (no message), or its limit of stances
    explored is reached (the message names it)."""


def _step_text(stance: Any, nxt: Any) -> str:
    """The step from ``stance`` to the adjacent ``nxt`` in words: ``"grab lh h9"`` or ``"release lh h9"``."""
    added, removed = set(nxt.limbs) - set(stance.limbs), set(stance.limbs) - set(nxt.limbs)
    if len(added) == 1 and not removed:
        (limb,) = added
        return f"grab {limb} {nxt[limb]}"
    if len(removed) == 1 and not added:
        (limb,) = removed
        return f"release {limb} {stance[limb]}"
    return f"to {nxt}"  # (not an edge of the stance graph)


def _counts_text(counts: dict[str, int]) -> str:
    """``{"collision": 12, "ik": 3}`` as ``"collision (12), ik (3)"``, most first, zeros left out."""
    return ", ".join(f"{k} ({n})" for k, n in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])) if n)


def _after(last: tuple[tuple[str, str], ...], action: str, limb: str, hold: str) -> tuple[tuple[str, str], ...]:
    """The limbs' last released holds after ``action``: a release records the hold, a grab forgets it."""
    d = dict(last)
    if action == "release":
        d[limb] = hold
    else:
        d.pop(limb, None)
    return tuple(sorted(d.items()))


#: How many times the start's failed edges are tried again when the stance graph runs out of edges (with
#: ``reexpand`` > 0; :meth:`StanceGraphSearch._reopen`); a round costs one FIND-TRANSITION call per edge out of the
#: start.  Why 30: docs/climb.md, "Settings and their defaults".
START_RETRIES: int = 30


class StanceGraphSearch:
    """The two-stage search (Bretl 2006, Fig. 16) of one climb query; holds its caches and counters.

    Args:
        robot, terrain, goal: the query.
        settings: every setting of the climb.
        seed: seed of every random choice.
        progress: called with a dict (``phase, elapsed_s, stances_explored, onestep_calls, fraction``).
        t0: the query's start time (``time.perf_counter()``), shared with the start search.
    """

    def __init__(self, robot: Any, terrain: Terrain, goal: Goal, settings: ClimbSettings, *, seed: int = 0,
                 progress: ProgressFn | None = None, t0: float | None = None):
        from climb_ompl.model.reach import pair_reach

        s = self.s = settings
        self.robot, self.terrain, self.goal, self.seed, self.progress = robot, terrain, goal, int(seed), progress
        self.feas = Feasibility.of(robot, terrain, s)
        self.finder = TransitionFinder.of(self.feas, s)
        self.graph = TransitionGraph(self.feas, s, seed=seed)
        self.limbs = [lb.name for lb in robot.limbs]
        self.reach = robot_reach(robot)
        mean_reach = float(np.mean([lb.reach for lb in robot.limbs]))
        self.stride = float(s.stride) if s.stride is not None else 0.5 * mean_reach
        self.pair_reach = pair_reach(robot)
        #: the nominal hands' heights along minus gravity when the nominal posture lies on the wall's plane with
        #: its up along the wall's slope (as :func:`climb_ompl.climb.start.lowest_stance` lays it out), by limb
        self.shape, self._shape_scale = _nominal_heights(robot, terrain)
        #: grabs not proposed by the ``grab_reach`` prefilter: (node key, next stance) -> (distance of the hold's
        #: hand target from the limb's first joint, largest distance proposed), for the frontier diagnosis
        self.beyond: dict[tuple[Any, Any], tuple[float, float]] = {}
        self._targets: dict[str, np.ndarray] = {}  # each limb's hand target on every hold
        self._hold_dist: dict[str, np.ndarray] = {}  # each hold's distance to every hold
        # caches
        self.prob: dict[tuple[Any, Any], float] = {}
        self.fails: dict[tuple[Any, Any], int] = {}
        self.transitions: dict[tuple[Any, Any], np.ndarray | None] = {}
        self.point_sets: dict[tuple[Any, Any], list[np.ndarray]] = {}
        #: single-contact component labels by configuration (see :meth:`_key`)
        self.members: dict[tuple[Any, bytes], tuple[Any, ...]] = {}
        self.explored: set[Any] = set()
        #: the nodes from which FIND-TRANSITION failed, by edge between stances (``transition_failures``)
        self.failed_from: dict[tuple[Any, Any], set[Any]] = {}
        self.reopened: dict[Any, int] = {}  # times a node was reached again at another configuration (``reexpand``)
        self.stuck: dict[Any, int] = {}  # stage-2 failures by the node where the candidate stopped
        # counters
        self.transition_calls = self.candidates = self.path_failures = self.repaired = self.reexpanded = 0
        self.transitions_skipped = 0  # edges ``transition_failures`` skipped
        self.shortcut_steps = 0  # steps the shortcuts removed from the last candidate
                                 # (:mod:`climb_ompl.climb.shortcut`)
        #: the steps (``"grab lh h9"``) whose path was not found, with how often (for the no-plan reason)
        self.failed_steps: dict[str, int] = {}
        self.transition_times: list[float] = []
        self.best: Node | None = None
        self._h0 = 0.0
        self._h_cache: dict[Any, float] = {}
        self._gap: StanceGap | None = None  # the heuristic of a stance goal
        self.hints: tuple[tuple[tuple[str, str, str], ...], ...] = ()
        self.hint_configs: tuple[tuple[Any, ...], ...] = ()
        self.max_stances: int | None = None  # (:attr:`WarmStart.max_stances`)
        self.exhausted = False  # the last run ended with no edge left to try (not by its budget)
        #: components a goal node must be in, by stance (:attr:`WarmStart.joins`; stances not listed: any)
        self.joins: dict[Any, set[tuple[int, ...]]] = {}
        self.t0 = time.perf_counter() if t0 is None else float(t0)

    def inherit(self, warm: WarmStart) -> None:
        """Re-use an earlier search's knowledge where a terrain change leaves it valid (see :class:`WarmStart`).

        Kept: the transitions found, transition points, single-contact components and paths between
        transitions (or the knowledge that none was found), of stances that rely on no touched hold; the
        transitions and paths of ``warm.route``.  Support regions need nothing: they are cached by contact
        geometry.

        Not kept: the first search's failed FIND-TRANSITION calls, its lowered edge probabilities and failure
        counts.  A failed call is a bounded number of random draws, not a proof that the edge has no transition;
        a search from scratch draws again, and a warm search that took the first one's failures as facts was
        steered away from the edges near the goal: along LEMUR's demo climb, failures at steps 56 and 57 took
        1.8 and 2.9 s warm against 0.7 s from scratch, and 0.7 and 0.9 s once the failures were dropped.
        """
        from climb_ompl.manifold.stance import Stance

        self.hints = tuple(warm.hints)
        self.hint_configs = tuple(warm.hint_configs)
        self.max_stances = warm.max_stances
        for pairs, q in warm.joins:
            stance = Stance(dict(pairs))
            if self._bends_name(stance):
                self.joins.setdefault(stance, set()).add(self.signature(stance, np.asarray(q, dtype=float)))

        def ok(stance: Any) -> bool:
            return not set(stance.hold_ids) & warm.touched

        old = warm.search
        if old is not None:
            # the transitions found only: failures, lowered probabilities and failure counts are drawn anew
            for mine, theirs in ((self.transitions, old.transitions), (self.point_sets, old.point_sets)):
                mine.update({k: v for k, v in theirs.items() if v is not None and ok(k[0][0]) and ok(k[1])})
            self.members.update({k: v for k, v in old.members.items() if ok(k[0])})
            self.graph.paths.update({k: v for k, v in old.graph.paths.items() if ok(k[0])})
        for step in warm.route:
            stance = Stance(dict(step.stance))
            if not self._bends_name(stance) or not ok(stance):
                continue  # single contacts and points are named by their history (:meth:`_key`)
            wps = [np.asarray(w, dtype=float) for w in step.waypoints]
            nxt = stance.with_hold(step.limb, step.hold) if step.action == "grab" else stance.without(step.limb)
            self.transitions.setdefault(((stance, self.signature(stance, wps[0])), nxt), wps[-1])
            self.graph.paths.setdefault((stance, qkey(wps[0]), qkey(wps[-1])), wps)

    def _points(self, node: Node, nxt: Any) -> list[np.ndarray]:
        """The transition points from ``node``'s single contact onto the point stance ``nxt`` (cached)."""
        ck = (node.key, nxt)
        if ck not in self.point_sets:
            self.point_sets[ck] = self.finder.points(node.q, node.stance, nxt)
        return self.point_sets[ck]

    def signature(self, stance: Any, q: np.ndarray) -> tuple[int, ...]:
        """Elbow-bend signs of the contact limbs: the component label (Bretl 2006, sec. 4.2.3)."""
        out = []
        for limb in stance.limbs:
            idx, straight = (self.robot.limb(limb).elbow_index, self.robot.limb(limb).elbow_straight)
            if idx is not None:
                out.append(int(np.sign(q[idx] - (straight or 0.0))))
        return tuple(out)

    def _key(self, parent: "Node | None", stance: Any, q: np.ndarray) -> tuple[Any, tuple[Any, ...]]:
        """The ``(stance, component)`` key of a search node reached at ``q`` from ``parent``.

        With two or more contacts on a manifold of positive dimension, the elbow bends of the contact limbs
        (:meth:`signature`).  Two cases where they name nothing, both met by the double-link robot of Bretl
        (2006), sec. 2.1 (Fig. 5, 13(b)):

        * a zero-dimensional stance (both hands on pegs) is a finite set of points, each its own component:
          the key is the point (in bounded joint space a whole-turn variant is another point);
        * a single contact closes no chain, the elbow of the limb on the hold bends freely: the component is
          named by the transition it was entered through (``("via", parent key)``, ``("start",)`` for the
          root), or by the component of an earlier node in which a path to ``q`` was found
          (:attr:`members`), so ``F_2^1`` entered from peg 1 and ``F_2^3`` entered from peg 3 stay apart
          while re-entering a visited component is recognised.
        """
        if self._manifold_dim(stance) <= 0:
            return (stance, ("at", *(round(float(x), 6) for x in q)))
        if len(stance) == 1:
            label = ("via", parent.key) if parent is not None else ("start",)
            return (stance, self.members.setdefault((stance, qkey(q)), label))
        return (stance, self.signature(stance, q))

    def _manifold_dim(self, stance: Any) -> int:
        return manifold_dim(self.robot, stance)

    def _hold_z(self, hold: str) -> float:
        return self.terrain.height(hold)  # along minus gravity

    # ---- heuristic -------------------------------------------------------------------------------------
    def heuristic(self, stance: Any, last: tuple[tuple[str, str], ...]) -> float:
        """Estimated number of steps from ``stance`` to the goal (see the module docstring)."""
        g = self.goal
        if g.type == "height":
            thr = float(g.height) - self.reach  # type: ignore[arg-type]
            where = dict(last)
            where.update(dict(stance.pairs))
            low = min((self._hold_z(x) for x in stance.hold_ids), default=0.0)
            z = {limb: self._hold_z(where[limb]) if limb in where else low for limb in self.limbs}
            t = dict.fromkeys(self.limbs, thr)
            if self.s.keep_shape and len(z) > 1:
                z = self._shape_capped(z)
                low = min(self.shape.values())  # the goal stance in the nominal shape: its lowest limb at thr
                t = {lb: thr + self.shape[lb] - low for lb in self.limbs}
            return sum((0.0 if limb in stance else 1.0) + 2.0 * max(0.0, t[limb] - z[limb]) / self.stride
                       for limb in self.limbs)
        if g.type == "hold":
            if stance.get(g.limb) == g.hold:
                return 0.0
            target = self.terrain.hold(g.hold).p  # type: ignore[arg-type]
            own = stance.get(g.limb) or dict(last).get(g.limb)  # type: ignore[arg-type]  # its hold, or last one
            near = float(np.linalg.norm(self.terrain.hold(own).p - target)) if own is not None else \
                min(float(np.linalg.norm(self.terrain.hold(h).p - target)) for h in stance.hold_ids)
            free = sum(1.0 for lb in self.limbs if lb != g.limb and lb not in stance)  # each grabs again first
            return 1.0 + (1.0 if g.limb in stance else 0.0) + free + 2.0 * near / max(self.stride, 1e-9)
        key = (stance, last)
        h = self._h_cache.get(key)
        if h is None:
            if self._gap is None:
                self._gap = StanceGap(self.terrain, self.limbs, g.stances if g.type == "stances" else
                                      [g.stance or ()], self.stride)
            h = self._h_cache[key] = self._gap(stance, {**dict(last), **dict(stance.pairs)})
        return h

    def _shape_capped(self, z: dict[str, float]) -> dict[str, float]:
        """Each limb's height capped at ``z_k + max(0, n_l - n_k) + s`` for every other limb ``k`` (the
        ``keep_shape`` term of the heuristic, see the module docstring)."""
        n, slack = self.shape, self.stride * self._shape_scale
        return {lb: min(v, min(z[k] + max(0.0, n[lb] - n[k]) for k in z if k != lb) + slack) for lb, v in z.items()}

    # ---- stance graph ------------------------------------------------------------------------------------
    def neighbours(self, node: Node) -> list[tuple[str, str, str, Any]]:
        """Candidate edges out of ``node``: ``(action, limb, hold, next stance)``, geometry-filtered."""
        s = node.stance
        out = []
        for limb in s.limbs:  # releases
            nxt = s.without(limb)
            if len(nxt) and self.feas.region_ok(nxt):
                out.append(("release", limb, s[limb], nxt))
        used = set(s.hold_ids)
        free = [limb for limb in self.limbs if limb not in s]
        near = self._near_reach(node.q, free)
        holds = self.terrain.holds
        for limb in free:  # grabs
            for i in np.flatnonzero(self._pair_reach_mask(s, limb)).tolist():
                h = holds[i]
                if h.id not in used:
                    nxt = s.with_hold(limb, h.id)
                    if limb in near and near[limb][0][i] > near[limb][1]:
                        self.beyond[(node.key, nxt)] = (float(near[limb][0][i]), near[limb][1])
                        continue
                    out.append(("grab", limb, h.id, nxt))
        return out

    def _pair_reach_mask(self, stance: Any, limb: str) -> np.ndarray:
        """Mask of the terrain's holds within the pair reach of ``limb`` from every contact hold of ``stance``
        (Bretl 2006, sec. 4.3); each hold's distances to every hold are computed once."""
        ok = np.ones(len(self.terrain.holds), dtype=bool)
        for k, h in stance.pairs:
            d = self._hold_dist.get(h)
            if d is None:
                d = self._hold_dist[h] = np.linalg.norm(self.terrain.positions - self.terrain.hold(h).p, axis=1)
            ok &= d <= self.pair_reach[(limb, k)]
        return ok

    def _release_heuristic(self, node: Node, limb: str, nxt: Any, last: tuple[tuple[str, str], ...]) -> float:
        """The heuristic of releasing ``limb`` from ``node`` onto ``nxt``, one grab ahead (``release_lookahead``):
        one step for the grab plus the smallest heuristic of the grabs :meth:`neighbours` would propose for the
        freed limb where the robot stands (the pair reach of ``nxt``'s contacts and ``grab_reach`` at ``node.q``),
        or :meth:`heuristic` when none is.  Never more than :meth:`heuristic`: the released hold is one of those
        grabs.  The height heuristic gives every release of a stance the same value (the freed limb counted at
        its last hold), so without it the releases are tried in limb order; with it, first the limb that can
        climb highest (see the module docstring)."""
        ok = self._pair_reach_mask(nxt, limb)
        near = self._near_reach(node.q, [limb])
        if limb in near:
            ok &= near[limb][0] <= near[limb][1]
        used, holds = set(nxt.hold_ids), self.terrain.holds
        ids = [holds[i].id for i in np.flatnonzero(ok).tolist() if holds[i].id not in used]
        if ids and self.goal.type == "height":  # the height heuristic never grows with the grabbed hold's height
            ids = [max(ids, key=self._hold_z)]
        best = min((self.heuristic(nxt.with_hold(limb, h), _after(last, "grab", limb, h)) for h in ids), default=None)
        return self.heuristic(nxt, last) if best is None else 1.0 + best

    def _near_reach(self, q: np.ndarray, limbs: list[str]) -> dict[str, tuple[np.ndarray, float]]:
        """For the grab prefilter ``grab_reach``: per free limb moved by its own joints only, the distance of
        every hold's hand target from the limb's first joint at ``q``, and the largest distance proposed
        (``grab_reach`` times the limb's reach).  Empty when the prefilter is off.

        FIND-TRANSITION draws the base near the node's configuration (:mod:`climb_ompl.climb.transition`), so a
        hold far beyond the limb's reach from where the robot stands needs a body motion the other contacts
        rarely allow: on the suite's terrains no grab was found beyond 1.27 reaches (LEMUR on the slab; 1.08
        for ANYmal-C on the ramp, 0.8 for Go1 on the slab), and FIND-TRANSITION calls beyond 1.5 reaches were
        about a fifth of all, each a failure (docs/climb.md).
        """
        from climb_ompl.model.reach import shoulders

        if not self.s.grab_reach or not limbs:
            return {}
        base = {int(j) for j in self.robot.base_indices}
        mine = [lb for lb in limbs if self.robot.limb(lb).joint_ids and not set(self.robot.limb(lb).joint_indices)
                & base]
        if not mine:
            return {}
        sh = shoulders(self.robot, q)
        out = {}
        for lb in mine:
            if lb not in self._targets:
                self._targets[lb] = limb_hold_targets(self.robot, self.terrain, lb)
            out[lb] = (np.linalg.norm(self._targets[lb] - sh[lb], axis=1),
                       float(self.s.grab_reach) * float(self.robot.limb(lb).reach))
        return out

    def transition(self, node: Node, nxt: Any, *, skip: bool = False) -> np.ndarray | None:
        """FIND-TRANSITION between ``node``'s stance and ``nxt``, near ``node.q`` (cached per edge).  ``skip``
        (stage 1): ``None``, not cached and not called, when the edge failed from ``transition_failures`` other
        components of the stance (:meth:`_failed_elsewhere`)."""
        ck = (node.key, nxt)
        if ck in self.transitions:
            return self.transitions[ck]
        q: np.ndarray | None = None
        small = nxt if len(nxt) < len(node.stance) else node.stance
        if len(nxt) < len(node.stance) and self.feas.valid(small, node.q):
            q = node.q  # a release right where we are: a zero-length step
        elif self._manifold_dim(node.stance) > 0 or len(nxt) > len(node.stance):
            if skip and self._failed_elsewhere(node, nxt):
                self.transitions_skipped += 1
                return None  # (tried again if the node is expanded again: :meth:`_reopen`)
            q = self._find(node.stance, nxt, node.q)
            if q is None and self._bends_name(node.stance):
                self.failed_from.setdefault((node.stance, nxt), set()).add(node.key)
            if q is not None and self._manifold_dim(node.stance) == 0 and len(nxt) < len(node.stance):
                q = None  # a point stance cannot move to another transition
        self.transitions[ck] = q
        return q

    def _find(self, stance: Any, nxt: Any, near: np.ndarray, *, stride: int = 1,
              skip_first: bool = False) -> np.ndarray | None:
        """One FIND-TRANSITION call between ``stance`` and ``nxt`` drawn about ``near``, counted, timed and seeded by
        its count times ``stride`` (the budget checked first).  A node reached again (:meth:`_reopen`) and stage 2's
        repairs draw with their own strides, ``skip_first``: another transition than the one ``near`` closes to."""
        self._check_time()
        t = time.perf_counter()
        self.transition_calls += 1
        q = self.finder.find(stance, nxt, near, seed=self.seed + stride * self.transition_calls, skip_first=skip_first)
        self.transition_times.append(time.perf_counter() - t)
        return q

    def _transition_about(self, node: Node, nxt: Any, ref: np.ndarray) -> np.ndarray | None:
        """FIND-TRANSITION between ``node``'s stance and ``nxt`` drawn about ``ref`` (a configuration this transition
        had before), kept as the edge's transition when found and in ``node``'s component; ``None`` otherwise (the
        edge is left to :meth:`transition`)."""
        if self._manifold_dim(node.stance) <= 0 and len(nxt) <= len(node.stance):
            return None
        if len(nxt) < len(node.stance) and self.feas.valid(nxt, node.q):
            return None  # a release right where the robot is: :meth:`transition` takes it, a zero-length step
        q = self._find(node.stance, nxt, ref)
        if q is None or (self._bends_name(node.stance)
                         and self.signature(node.stance, q) != self.signature(node.stance, node.q)):
            return None  # another component of the node's stance: no path to it
        self.transitions[(node.key, nxt)] = q
        return q

    def _edge_cost(self, key: Any, nxt: Any) -> float:
        return 1.0 - math.log(self.prob.get((key, nxt), P_INITIAL))

    def stage1(self, start: Node) -> Node | None:
        """EXPLORE-STANCEGRAPH (Bretl 2006, Fig. 16), best first by cost plus the weighted heuristic;
        returns a goal node or ``None``."""
        closed: dict[Any, Node] = {start.key: start}
        if self.arrived(start.key):
            return start
        heap: list[tuple[float, int, int, Node, tuple[str, str, str, Any, int | None]]] = []
        counter = 0

        def push(node: Node) -> None:
            nonlocal counter
            for action, limb, hold, nxt in self.neighbours(node):
                if (node.key, nxt) in self.transitions and self.transitions[(node.key, nxt)] is None:
                    continue
                if self._dropped((node.key, nxt)):
                    continue
                if self.s.transitions == "eager" and self.transition(node, nxt) is None:
                    continue  # Fig. 16 lines 10-12: FIND-TRANSITION when the node is expanded
                lt = _after(node.last, action, limb, hold)
                h = self._release_heuristic(node, limb, nxt, lt) if action == "release" and self.s.release_lookahead \
                    and self.s.heuristic_weight else self.heuristic(nxt, lt)
                f = node.g + self._edge_cost(node.key, nxt) + self.s.heuristic_weight * h
                # a grab from one contact onto a point stance: one edge per transition point, nearest first
                points = range(len(self._points(node, nxt))) if action == "grab" and len(node.stance) == 1 \
                    and self._manifold_dim(nxt) <= 0 else [None]
                for k in points:
                    counter += 1
                    heapq.heappush(heap, (f, -node.depth, counter, node, (action, limb, hold, nxt, k)))

        push(start)
        while heap or self._reopen(closed, push, heap):
            self._check_time()
            _, _, _, node, (action, limb, hold, nxt, k) = heapq.heappop(heap)
            if k is None:
                q = self.transition(node, nxt, skip=True)
            else:
                # the component of a single contact is known only through the paths found in it: the edge
                # is verified when popped (the component graph of Bretl 2006, Fig. 13(b), built as met)
                if self._dropped((node.key, nxt)):
                    continue
                q = self._points(node, nxt)[k]
                if self.connect(node, Node((nxt, ()), q, 0.0, node, (action, limb, hold), ())) is None:
                    self._path_failed(node, nxt)
                    continue
                self.members.setdefault((node.stance, qkey(q)), node.key[1])
            if q is None:
                continue
            key = self._key(node, nxt, q)
            if key in closed:
                continue
            child = closed[key] = self._reach(node, key, q, (action, limb, hold))
            if self.arrived(key):
                return child
            push(child)
        return None

    def _reopen(self, closed: dict[Any, Node], push: Callable[[Node], None], heap: list[Any]) -> bool:
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
        one node.  Single contacts and point
        stances are named by their configuration (:meth:`_key`) and are left alone.
        """
        if not self.s.reexpand or not closed:
            return False
        order = sorted(((self.heuristic(n.stance, n.last), -n.depth, i, n) for i, n in enumerate(closed.values())
                        if self._bends_name(n.stance)
                        and self.reopened.get(n.key, 0) < (self.s.reexpand if n.parent is not None else START_RETRIES)))
        for *_, node in order:
            if node.parent is None:  # the start: its failed edges again, from where the robot stands
                if not self._forget_failed(node.key):
                    continue
                self.reopened[node.key] = self.reopened.get(node.key, 0) + 1
                self.reexpanded += 1
                push(node)
                if heap:
                    return True
                continue
            self.reopened[node.key] = self.reopened.get(node.key, 0) + 1
            parent = node.parent
            q = self._find(parent.stance, node.stance, parent.q, stride=104729, skip_first=True)  # type: ignore[union-attr]
            if q is None:
                continue
            key = self._key(parent, node.stance, q)
            if key != node.key and key in closed:
                continue  # the other component was expanded already
            self._forget_failed(key)
            self.reexpanded += 1
            child = closed[key] = self._reach(parent, key, q, node.action)  # type: ignore[arg-type]
            push(child)
            if heap:
                return True
        return False

    def _forget_failed(self, key: Any) -> int:
        """Forget the failed transitions out of the node ``key`` (tried again when met), and the failures of its
        stance's edges from every component (``transition_failures`` skips none of them until they fail again); how
        many failed transitions there were out of ``key``."""
        failed = [e for e, v in self.transitions.items() if e[0] == key and v is None]
        for e in failed:
            del self.transitions[e]
        for e in [e for e in self.failed_from if e[0] == key[0]]:
            del self.failed_from[e]
        return len(failed)

    def _failed_elsewhere(self, node: Node, nxt: Any) -> bool:
        """Whether FIND-TRANSITION failed for the edge ``node.stance -> nxt`` from ``transition_failures`` components of
        the stance other than ``node``'s (the setting; 0: never).  Only stances whose components the elbow bends name
        (:meth:`_bends_name`) count: a single contact's component is named by the route it was entered through."""
        k = self.s.transition_failures
        return bool(k) and len(self.failed_from.get((node.stance, nxt), set()) - {node.key}) >= k

    def _bends_name(self, stance: Any) -> bool:
        """Whether the components of ``stance`` are named by the contact limbs' elbow bends (:meth:`_key`)."""
        return len(stance) > 1 and self._manifold_dim(stance) > 0

    def follow(self, start: Node, actions: Sequence[tuple[str, str, str]],
               near: Sequence[Any] | None = None) -> Node | None:
        """The node reached by taking ``actions`` (``(grab|release, limb, hold)``) in turn from ``start``, one
        FIND-TRANSITION each, or ``None`` when a step has no transition or the end does not meet the goal.

        A given stance sequence needs no exploration: a re-plan follows the old route on holds that moved or
        changed friction before it searches.  ``near``: per action, a configuration the transition had before (the
        old route's): FIND-TRANSITION is drawn about it first (its first draw is that configuration with the chains
        re-closed onto the holds as they are now), then about the node reached, as the search does.  Grabs from a
        single contact onto a point stance (whose transitions are found as points, :meth:`_points`) are left to
        :meth:`stage1`.
        """
        node = self.take_steps(start, actions, near)
        return node if node is not None and self.arrived(node.key) else None

    def take_steps(self, start: Node, actions: Sequence[tuple[str, str, str]], near: Sequence[Any] | None = None,
                   *, record: bool = True) -> Node | None:
        """The node reached by taking ``actions`` in turn from ``start`` (as :meth:`follow`, wherever it ends), or
        ``None`` when a step has no transition.  ``record``: the nodes reached count as explored (:meth:`_reach`);
        without it they are only built (a shortcut tried, :mod:`climb_ompl.climb.shortcut`, counts once kept)."""
        node = start
        for i, edge in enumerate(actions):
            # only an edge the search itself would propose (:meth:`neighbours`)
            nxt = next((n for *e, n in self.neighbours(node) if tuple(e) == tuple(edge)), None)
            if nxt is None or (edge[0] == "grab" and len(node.stance) == 1 and self._manifold_dim(nxt) <= 0):
                return None
            q = None
            if near is not None and i < len(near) and near[i] is not None and (node.key, nxt) not in self.transitions:
                q = self._transition_about(node, nxt, np.asarray(near[i], dtype=float))
            if q is None:
                q = self.transition(node, nxt)
            if q is None:
                return None
            key = self._key(node, nxt, q)
            node = self._reach(node, key, q, tuple(edge)) if record else self.make_node(node, key, q, tuple(edge))
        return node

    def arrived(self, key: tuple[Any, tuple[Any, ...]]) -> bool:
        """Whether the search node ``key`` meets the goal: its stance does and, for a stance with components to
        join (:attr:`joins`), it is in one of them."""
        stance, component = key
        return self.goal.met(stance, self.terrain, self.reach) and component in self.joins.get(stance, (component,))

    def make_node(self, node: Node, key: Any, q: np.ndarray, edge: tuple[str, str, str]) -> Node:
        """The search node ``key`` reached at ``q`` from ``node`` by ``edge`` (``(action, limb, hold)``)."""
        return Node(key, q, node.g + self._edge_cost(node.key, key[0]), node, edge, _after(node.last, *edge),
                    node.depth + 1)

    def _reach(self, node: Node, key: Any, q: np.ndarray, edge: tuple[str, str, str]) -> Node:
        """:meth:`make_node`, counted as explored and tracked as the best so far."""
        child = self.make_node(node, key, q, edge)
        self.record(child)
        return child

    def record(self, node: Node) -> None:
        """Count ``node`` as explored and track it as the best so far."""
        self.explored.add(node.key)
        self._track(node)

    def stage2(self, chain: list[Node]) -> tuple[int, list[list[np.ndarray]]]:
        """EXPLORE-TRANSITIONGRAPH along a candidate (Bretl 2006, Fig. 16): paths between its transitions.

        Connects consecutive transitions by :meth:`connect` (the direct local path, then FIND-PATH).  When
        an edge cannot be connected, up to ``repairs`` other transitions of the same edge are sampled
        near the configuration reached (Fig. 16 line 2 tries the transitions "in each component"); the
        candidate is updated in place when one connects.  Otherwise the edge's probability is lowered.

        Returns:
            The index of the farthest node reached and the paths up to it.
        """
        paths: list[list[np.ndarray]] = []
        for i in range(len(chain) - 1):
            u, v = chain[i], chain[i + 1]
            if i > 0 and v.action is not None and v.action[0] == "release" and not np.array_equal(u.q, v.q) \
                    and self.feas.valid(v.stance, u.q):
                v = chain[i + 1] = replace(v, q=u.q, parent=u)  # zero-length again
            path = self.connect(u, v)
            rep = 0
            while path is None and rep < self.s.repairs:
                rep += 1
                q_new = self._find(u.stance, v.stance, u.q, stride=7919, skip_first=True)
                if q_new is None:
                    continue
                cand = replace(v, key=self._key(u, v.stance, q_new), q=q_new, parent=u)
                path = self.connect(u, cand)
                if path is not None:
                    v = chain[i + 1] = cand
                    self.repaired += 1
            if path is None:
                self._path_failed(u, v.stance)
                return i, paths
            if i + 2 < len(chain):
                w = chain[i + 2]
                chain[i + 2] = replace(w, parent=v)
            paths.append(path)
        return len(chain) - 1, paths

    def _path_failed(self, u: Node, nxt: Any) -> None:
        """No path from ``u`` to a transition onto ``nxt``: lower the edge's ``P`` (Bretl 2006 sec. 3.3.3;
        in the guided search the edge is dropped after ``max_edge_failures``)."""
        e = (u.key, nxt)
        self.fails[e] = self.fails.get(e, 0) + 1
        step = _step_text(u.stance, nxt)
        self.failed_steps[step] = self.failed_steps.get(step, 0) + 1
        self._lower(e)
        self.path_failures += 1

    def _dropped(self, edge: tuple[Any, Any]) -> bool:
        """Whether ``edge`` failed ``max_edge_failures`` times (never with ``max_edge_failures = 0``)."""
        k = self.s.max_edge_failures
        return k > 0 and self.fails.get(edge, 0) >= k

    def _lower(self, edge: tuple[Any, Any]) -> None:
        """Multiply the probability of a stance-graph edge by :data:`P_FAIL_FACTOR` (Bretl 2006, sec. 3.3.3)."""
        self.prob[edge] = self.prob.get(edge, P_INITIAL) * P_FAIL_FACTOR

    def connect(self, u: Node, v: Node) -> list[np.ndarray] | None:
        """A path in ``F_sigma(u)`` from ``u.q`` to ``v.q`` (:meth:`TransitionGraph.connect`)."""
        moving = v.action[1] if v.action is not None and v.action[0] == "grab" else None
        # a connection that failed before is planned again with more effort while its edge is not dropped
        effort = self.s.path_retry_growth ** self.fails.get((u.key, v.stance), 0)
        path = self.graph.connect(u.stance, u.q, v.q, moving, self._check_time,
                                  max(0.1, self.s.time_limit - self.elapsed()), effort)
        self._report("path")
        return path

    # ---- driver ----------------------------------------------------------------------------------------
    def elapsed(self) -> float:
        """Seconds since the query started."""
        return time.perf_counter() - self.t0

    def _check_time(self) -> None:
        if self.elapsed() > self.s.time_limit:
            raise _BudgetSpent()
        if self.max_stances is not None and len(self.explored) > self.max_stances:
            raise _BudgetSpent(f"the limit of {self.max_stances} (stance, component) nodes explored")

    def _track(self, node: Node) -> None:
        if self.best is None or self._progress_value(node) > self._progress_value(self.best):
            self.best = node
        self._report("stances")

    def _progress_value(self, node: Node) -> float:
        return -self.heuristic(node.stance, node.last)

    def _report(self, phase: str, **extra: Any) -> None:
        if self.progress is None:
            return
        h0 = getattr(self, "_h0", None)
        hb = self.heuristic(self.best.stance, self.best.last) if self.best is not None else h0
        frac = 0.0 if not h0 else max(0.0, min(1.0, 1.0 - (hb or 0.0) / h0))
        self.progress({"phase": phase, "elapsed_s": self.elapsed(), "stances_explored": len(self.explored),
                       "onestep_calls": self.transition_calls + self.graph.path_calls, "candidates": self.candidates,
                       "fraction": frac, **extra})

    def run(self, start_stance: Any, q_start: np.ndarray) -> tuple[list[Node] | None, list[list[np.ndarray]],
                                                                       str]:
        """Alternate the two stages until a plan, an exhausted stance graph or the budget."""
        start = Node(self._key(None, start_stance, q_start), q_start, 0.0, None, None, ())
        self._h0 = self.heuristic(start_stance, ())
        self.best = start
        self.explored.add(start.key)
        reason = ""
        root = start
        try:
            for i, hint in enumerate(self.hints):  # given routes first: a plan along one needs no exploration
                end = self.follow(start, hint, self.hint_configs[i] if i < len(self.hint_configs) else None)
                if end is not None:
                    self.candidates += 1
                    chain = end.chain()
                    reached, paths = self.stage2(chain)
                    if reached == len(chain) - 1:
                        return chain, paths, ""
            while True:
                goal_node = self.stage1(root)
                if goal_node is None:
                    if root is not start:  # the verified prefix is a dead end: search again from the start
                        root = start
                        continue
                    self.exhausted = True
                    reason = self._why_exhausted()
                    return None, [], reason
                self.candidates += 1
                chain = goal_node.chain()
                if self.s.shortcuts and self.max_stances is None:  # (a rejoining search's detours are short)
                    chain = shorten(self, chain)
                reached, paths = self.stage2(chain)
                if reached == len(chain) - 1:
                    return chain, paths, ""
                # resume EXPLORE-STANCEGRAPH from the farthest transition reached (its prefix is verified); when
                # candidates keep failing at the same node, from further back each time (2, 4, 8 ... steps):
                # the way out may need another hold a few steps earlier
                if self.s.resume == "queue":  # Fig. 16: EXPLORE-STANCEGRAPH goes on with its queue
                    continue
                n = self.stuck[chain[reached].key] = self.stuck.get(chain[reached].key, 0) + 1
                if n > 1 and reached > 0:  # the node itself looks like a dead end: the edge into it loses P too
                    self._lower((chain[reached - 1].key, chain[reached].stance))
                root = chain[max(0, reached - (2 ** (n - 1) if n > 1 else 0))]
        except _BudgetSpent as stop:
            why = f"{stop} reached" if str(stop) else f"{BUDGET_SPENT} {self.s.time_limit:g} s spent"
            return None, [], f"{why} after {self._candidates_text()}; {self._frontier()}"

    def _candidates_text(self) -> str:
        """The candidate sequences of a search stopped by its budget, in words: each reached the goal in the
        stance graph (stage 1) and stopped at a step whose path was not found (stage 2)."""
        g = self.graph
        if not self.candidates:
            return "0 candidate sequences (no sequence of stances to the goal found yet)"
        text = (f"{self.candidates} candidate sequence(s): sequences of stances that reach the goal, each stopped "
                f"at a step whose path was not found, or by the budget ({g.path_calls} FIND-PATH calls, "
                f"{g.path_timeouts} of them stopped by a time guard)")
        if self.failed_steps:
            top = sorted(self.failed_steps.items(), key=lambda kv: (-kv[1], kv[0]))[:3]
            text += "; the steps whose path was not found, most often: " + ", ".join(
                f"{k} ({n} time{'s' if n > 1 else ''})" for k, n in top)
            why = [f"the direct local path stopped on {_counts_text(g.local_path.failures)}"] \
                if g.local_path.failures else []
            if any(g.rejections.values()):
                why.append(f"FIND-PATH's samples were rejected for {_counts_text(g.rejections)}")
            text += (" (over the whole search, " + "; ".join(why) + ")") if why else ""
        return text

    def frontier(self) -> list[Any]:
        """The stances explored, nearest the goal first: smallest height heuristic, then highest hold, then
        name (what the no-plan reason names and :func:`climb_ompl.climb.frontier.diagnose_frontier` diagnoses)."""
        stances = dict.fromkeys(key[0] for key in self.explored)
        return sorted(stances, key=lambda s: (self.heuristic(s, ()),
                                              -max(self.terrain.height(h) for h in s.hold_ids), str(s)))

    def _frontier(self) -> str:
        ranked = self.frontier()
        where = "" if not ranked else (f"closest stance to the goal: {ranked[0]} (estimated "
                                       f"{self.heuristic(ranked[0], ()):.1f} steps away)")
        return f"{len(self.explored)} (stance, component) nodes explored; {where}"

    def _why_exhausted(self) -> str:
        return f"{EXHAUSTED}: no sequence of feasible grabs and releases reaches the goal; " + self._frontier()

    def stats(self) -> dict[str, Any]:
        """Counters of the search (the plan's ``totals`` take the reproducible ones)."""
        g = self.graph
        return {"onestep_calls": self.transition_calls + g.path_calls, "transition_calls": self.transition_calls,
                "path_calls": g.path_calls, "path_timeouts": g.path_timeouts, "path_retries": g.retries,
                "stances_explored": len(self.explored), "candidates": self.candidates,
                "path_failures": self.path_failures, "rejections": dict(sorted(g.rejections.items())),
                "onestep_median_s": float(np.median(g.step_times)) if g.step_times else 0.0,
                "step_times_s": list(g.step_times), "onestep_times_s": list(g.path_times),
                "transition_times_s": list(self.transition_times), "direct_calls": g.local_path.calls,
                "direct_found": g.local_path.found, "repaired": self.repaired, "reexpanded": self.reexpanded,
                "shortcut_steps": self.shortcut_steps, "transitions_skipped": self.transitions_skipped,
                "total_s": self.elapsed()}

    def timings(self) -> dict[str, Any]:
        """Wall-clock figures (not reproducible; kept apart in the plan file)."""
        return {"total_s": self.elapsed(),
                "onestep_median_s": float(np.median(self.graph.step_times)) if self.graph.step_times else 0.0,
                "step_s": [round(t, 6) for t in self.graph.step_times],
                "path_s": [round(t, 6) for t in self.graph.path_times],
                "transition_median_s": float(np.median(self.transition_times)) if self.transition_times else 0.0,
                "transition_total_s": float(sum(self.transition_times))}


__all__ = ["StanceGraphSearch", "WarmStart", "Node", "P_INITIAL", "P_FAIL_FACTOR", "EXHAUSTED"]
