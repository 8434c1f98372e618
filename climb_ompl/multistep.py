"""Multi-step climbing: the stance graph and the two-stage search of seed 001 (section 3.3, Fig. 16).

A climb is a sequence of *steps*, each one grab or one release (seed 001 section 2.1).  The planner
alternates two searches, as EXPLORE-STANCEGRAPH / EXPLORE-TRANSITIONGRAPH do (seed 001 Fig. 16):

1. **Stance graph** (stage 1).  Nodes are ``(stance, component)`` pairs: a stance (limb -> hold) and the
   connected component of its feasible space, identified by the bend sign of every contact limb's
   elbow (seed 001 section 4.2.3: "most of the time, connected components of ``F_sigma`` differ by an
   elbow bend").  Searching over pairs rather than stances is what lets the double-link robot revisit
   stance 2 in another component (seed 001 Fig. 13(b): ``F_1 -> F_2^1 -> F_3 -> F_2^3 -> F_4``).  Where
   elbow bends name nothing - a single contact, a zero-dimensional stance - the component is named by the
   point or the entry transition (:meth:`ClimbPlanner._key`); a grab from a single contact onto a point
   stance is one edge per transition point (:meth:`ClimbPlanner.transition_points`, whole-turn variants of
   joints bounded by +-2 pi included), each verified by a path when popped.  Edges
   add or remove one contact; the graph is built lazily: a neighbour is proposed when the geometry
   allows it (the new hold within reach of every contact hold, a non-empty support region after a
   release) and FIND-TRANSITION (seed 001 Fig. 17) is called only when the search *pops* that edge,
   starting near the configuration at which the search reached the node.  The queue is ordered by A*
   with the cost ``n - sum ln P`` of seed 001 section 3.3.3 (``1 - ln P(e)`` per step) plus a
   weighted height heuristic (below).
2. **Transition graph** (stage 2).  When stage 1 reaches a goal node it returns the candidate sequence;
   consecutive transitions are then connected from the start: first by the *direct local path*
   (:meth:`ClimbPlanner.direct_path`: PRM's local planner on the query itself - base and free limbs
   interpolated, contact limbs re-closed by inverse kinematics, the moving hand lifted off the wall,
   if needed through a few random via postures of the free limb), then by FIND-PATH
   (:func:`climb_ompl.onestep.find_path`, any OMPL planner) within ``step_time_limit``.  Paths found are
   kept (the transition graph), so a later candidate sharing a prefix costs nothing to re-check.  When
   an edge cannot be connected, ``repairs`` other transitions of that edge are tried ("for each
   component", Fig. 16 line 2); if none connects, the edge's probability ``P`` is lowered (not deleted,
   seed 001 section 3.3.3: deleting edges makes the search "return failure incorrectly"; an edge is
   dropped after ``max_edge_failures`` failures) and stage 1 resumes from the farthest transition
   reached - from 2, 4, 8, ... steps before it when candidates keep failing there (the edge into that node
   then loses probability too), from the start again if that prefix is a dead end.

Goals (:class:`Goal`): a target stance, a target hold for a limb, or *reach height h*: every contact
hold at or above ``h - reach`` (world ``z``, metres), where ``reach`` is the robot's largest limb reach
(:attr:`Limb.reach`, from its first joint to its hand).

Heuristic (a guide, not a bound): for the height goal, ``2 * sum_l gap_l / stride`` where ``gap_l`` is
how far limb ``l``'s hold (its last hold while free) lies below ``h - reach`` and ``stride`` is the
height a hand gains per grab (default ``0.5 * reach``): each limb needs about one release and one grab
per stride.  The A* weight ``heuristic_weight`` trades optimality for speed.

Budgets: ``time_limit`` for the whole query, ``step_time_limit`` per FIND-PATH call, and count budgets
(``transition_attempts``, ``path_iterations``) that make seeded runs reproducible (ARCHITECTURE.md,
"Reproducibility"): the same seed gives the same plan, byte for byte apart from ``timings``, as long as
no wall-clock limit was hit.
"""

from __future__ import annotations

import heapq
import itertools
import json
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from .errors import QueryError
from .plan import ForceSample, Plan, Step, library_versions, sha256_json, sha256_text
from .terrain import Terrain

#: Default probability of a stance-graph edge before it was tried (seed 001 section 3.3.3).
P_INITIAL = 0.9
#: Factor applied to an edge's probability when FIND-PATH fails along it.
P_FAIL_FACTOR = 0.3

#: Halvings of an interval of the direct local path before a jump counts as an IK branch switch.
REFINE_DEPTH = 4

#: Default wall-clock budget of one FIND-PATH call, seconds.  Most one-step paths come from the direct local
#: path; OMPL's successes take a median 0.24-0.8 s and a failing call spends its whole budget, so 0.5 s
#: found more 2 m climbs in 120 s than 1 s did (20/20 vs 19/20 on ten generated walls, seeds 0 and 1).
STEP_TIME_LIMIT = 0.5

#: Start of the reason given when the stance graph holds no route (as opposed to a spent budget).
EXHAUSTED = "the stance graph is exhausted"

#: A free hand may touch the wall within this distance of a hold (metres): it is leaving or reaching
#: the hold (the exemption ``verify`` applies too).
HAND_CONTACT_RADIUS = 0.05

ProgressFn = Callable[[dict[str, Any]], None]


# ---- query values --------------------------------------------------------------------------------
@dataclass(frozen=True)
class Goal:
    """The goal of a climb query.

    Attributes:
        type: ``"height"`` (every contact hold at or above ``height - reach``), ``"hold"`` (``limb`` on
            ``hold``) or ``"stance"`` (exactly :attr:`stance`).
        height: target height, metres (world ``z``), for ``type == "height"``.
        limb, hold: for ``type == "hold"``.
        stance: ``(limb, hold)`` pairs for ``type == "stance"``.
    """

    type: str
    height: float | None = None
    limb: str | None = None
    hold: str | None = None
    stance: tuple[tuple[str, str], ...] | None = None

    @classmethod
    def parse(cls, goal: Any) -> "Goal":
        """A goal from a :class:`Goal`, a number (height), ``"limb=hold"``, a stance mapping or a goal dict.

        Raises:
            QueryError: none of these.
        """
        if isinstance(goal, Goal):
            return goal
        if isinstance(goal, (int, float)) and not isinstance(goal, bool):
            return cls("height", height=float(goal))
        if isinstance(goal, str) and goal.count("=") == 1:
            limb, hold = (x.strip() for x in goal.split("="))
            if limb and hold:
                return cls("hold", limb=limb, hold=hold)
        if isinstance(goal, Mapping):
            if "type" in goal:
                t = goal["type"]
                if t == "height":
                    return cls("height", height=float(goal["height"]))
                if t == "hold":
                    return cls("hold", limb=str(goal["limb"]), hold=str(goal["hold"]))
                if t == "stance":
                    return cls("stance", stance=tuple(sorted((str(k), str(v)) for k, v in goal["stance"].items())))
            elif goal and all(isinstance(v, str) for v in goal.values()):
                return cls("stance", stance=tuple(sorted((str(k), str(v)) for k, v in goal.items())))
        raise QueryError(f"goal {goal!r}: expected a height (number), 'LIMB=HOLD', a stance mapping or a goal dict")

    def to_dict(self) -> dict[str, Any]:
        """The goal as in the plan file's ``query.goal``."""
        if self.type == "height":
            return {"type": "height", "height": self.height}
        if self.type == "hold":
            return {"type": "hold", "limb": self.limb, "hold": self.hold}
        return {"type": "stance", "stance": dict(self.stance or ())}

    def validate(self, robot: Any, terrain: Terrain) -> None:
        """Check limbs and holds exist.

        Raises:
            QueryError: naming the unknown limb or hold.
        """
        limbs = [lb.name for lb in robot.limbs]
        pairs = [(self.limb, self.hold)] if self.type == "hold" else list(self.stance or ())
        for limb, hold in pairs:
            if limb not in limbs:
                raise QueryError(f"goal: unknown limb {limb!r}; valid limbs: {', '.join(limbs)}")
            if hold not in terrain.hold_ids:
                raise QueryError(f"goal: no hold {hold!r} in terrain {terrain.name!r}")

    def met(self, stance: Mapping[str, str], terrain: Terrain, reach: float) -> bool:
        """Whether ``stance`` meets the goal (``reach``: the robot's largest limb reach, metres)."""
        if self.type == "height":
            assert self.height is not None
            return bool(stance) and all(terrain.hold(h).position[2] >= self.height - reach for h in stance.values())
        if self.type == "hold":
            return stance.get(self.limb) == self.hold  # type: ignore[arg-type]
        return dict(stance) == dict(self.stance or ())


@dataclass
class PlanResult:
    """Outcome of :func:`plan_climb` (STYLE.md section 5: "no plan" is a value, not an exception).

    Attributes:
        status: ``"found"`` or ``"no-plan"``.
        plan: the :class:`~climb_ompl.plan.Plan` when found, else ``None``.
        stats: ``steps, onestep_calls, transition_calls, path_calls, onestep_median_s, stances_explored,
            candidates, path_failures, total_s, rejections`` (by reason, summed over FIND-PATH calls), ...
        reason: why there is no plan (budget, exhausted stance graph, with the explored frontier).
    """

    status: str
    plan: Plan | None = None
    stats: dict[str, Any] = field(default_factory=dict)
    reason: str = ""

    @property
    def found(self) -> bool:
        """Whether a plan was found."""
        return self.status == "found"


# ---- search nodes ----------------------------------------------------------------------------------
@dataclass
class _Node:
    key: tuple[Any, tuple[int, ...]]  # (Stance, elbow signature)
    q: np.ndarray
    g: float
    parent: "_Node | None"
    action: tuple[str, str, str] | None  # (grab|release, limb, hold) that led here
    last: tuple[tuple[str, str], ...]  # free limbs' last holds
    depth: int = 0

    @property
    def stance(self) -> Any:
        return self.key[0]

    def chain(self) -> list["_Node"]:
        out, n = [], self
        while n is not None:
            out.append(n)
            n = n.parent
        return out[::-1]


@dataclass
class OneStepFailure:
    """Stand-in result of a FIND-PATH call that refused its query."""

    reason: str
    status: str = "rejected"
    path: list[np.ndarray] = field(default_factory=list)
    stats: dict[str, Any] = field(default_factory=dict)
    solved: bool = False


def touching_hands(robot: Any, terrain: Terrain, q: np.ndarray, contact_limbs: Any = ()) -> list[str]:
    """Free limbs whose hand is within :data:`HAND_CONTACT_RADIUS` of a hold (it may touch the wall there)."""
    P = terrain.positions
    H = np.asarray(robot.hand_positions(q), dtype=float)
    out = []
    for i, lb in enumerate(robot.limbs):
        if lb.name not in contact_limbs and float(np.min(np.linalg.norm(P - H[i], axis=1))) <= HAND_CONTACT_RADIUS:
            out.append(lb.name)
    return out


class _Budget(Exception):
    """Raised inside the search when the total time budget is spent."""


_REACH_MAPS: dict[Any, dict[int, Any]] = {}


def _qkey(q: np.ndarray) -> bytes:
    return np.ascontiguousarray(q, dtype=float).tobytes()


# ---- the planner -------------------------------------------------------------------------------------
class ClimbPlanner:
    """The two-stage multi-step planner (seed 001 Fig. 16) for one robot on one terrain.

    Use :func:`plan_climb`; this class holds the caches (transitions, paths, edge probabilities) of a
    query and can be inspected after it.
    """

    def __init__(self, robot: Any, terrain: Terrain, goal: Goal, *, planner: str = "LazyPRM",
                 space: str = "projected", sampler: str = "uniform", time_limit: float = 120.0,
                 step_time_limit: float = STEP_TIME_LIMIT, seed: int = 0, path_iterations: int | None = 20000,
                 transition_attempts: int = 150, ik_tries: int = 60, heuristic_weight: float = 10.0,
                 stride: float | None = None,
                 max_edge_failures: int = 3, max_step: float = 0.02, force_every: int = 10,
                 torque: str = "final-path", margin: float = 0.0, fallback_attempts: int = 0, lift: float = 0.04,
                 spread_weight: float = 0.0, repairs: int = 3, via_points: int = 8, clearance: float = 0.01,
                 progress: ProgressFn | None = None):
        from .onestep import DEFAULT_TOLERANCE

        self.robot, self.terrain, self.goal = robot, terrain, goal
        self.planner, self.space, self.sampler = planner, space, sampler
        self.time_limit, self.step_time_limit, self.seed = float(time_limit), float(step_time_limit), int(seed)
        self.path_iterations, self.transition_attempts = path_iterations, int(transition_attempts)
        self.w, self.max_edge_failures = float(heuristic_weight), int(max_edge_failures)
        self.max_step, self.force_every, self.torque, self.margin = float(max_step), int(force_every), torque, margin
        self.tolerance = DEFAULT_TOLERANCE
        self.fallback_attempts = int(fallback_attempts)
        self.ik_tries = int(ik_tries)
        self.lift = float(lift)
        self.motion_tol = 1e-4
        self.direct_calls = self.direct_found = 0
        self.direct_fail: dict[str, int] = {}
        self.spread_weight = float(spread_weight)
        self.transition_fail: dict[str, int] = {}
        self.com_slack = 0.05
        self.repairs = int(repairs)
        self.clearance = float(clearance)
        self.repaired = 0
        self.ompl_rejected = 0
        self.step_times: list[float] = []
        self.via_points = int(via_points)
        self.transition_stats: list[tuple[int, int]] = []
        self.direct_times: list[float] = []
        self.progress = progress
        self.limbs = [lb.name for lb in robot.limbs]
        self.reach = max(float(lb.reach) for lb in robot.limbs)
        self.stride = float(stride) if stride is not None else 0.5 * float(np.mean([lb.reach for lb in robot.limbs]))
        self.elbow = {lb.name: (lb.elbow_index, lb.elbow_straight) for lb in robot.limbs}
        self.pair_reach = self._pair_reach()
        self._reach_key = (robot.name, getattr(robot, "urdf_path", None), float(lift))
        self.axes = np.array([0, 2]) if robot.planar else np.array([0, 1, 2])
        # caches and counters
        self.prob: dict[tuple[Any, Any], float] = {}
        self.fails: dict[tuple[Any, Any], int] = {}
        self.transitions: dict[tuple[Any, Any], np.ndarray | None] = {}
        self.point_sets: dict[tuple[Any, Any], list[np.ndarray]] = {}
        #: single-contact component labels by configuration (see :meth:`_key`)
        self.members: dict[tuple[Any, bytes], tuple[Any, ...]] = {}
        self.paths: dict[tuple[Any, bytes, bytes], list[np.ndarray] | None] = {}
        self.regions: dict[Any, bool] = {}
        self.checks: dict[Any, list[Any]] = {}
        self.explored: set[Any] = set()
        self.stuck: dict[Any, int] = {}  # stage-2 failures by the node where the candidate stopped
        self.transition_calls = self.path_calls = self.candidates = self.path_failures = 0
        self.path_times: list[float] = []
        self.transition_times: list[float] = []
        self.rejections: dict[str, int] = {}
        self.best: _Node | None = None
        self.t0 = time.perf_counter()

    # ---- geometry ---------------------------------------------------------------------------------
    def _pair_reach(self) -> dict[tuple[str, str], float]:
        """Largest distance between two hands: shoulder distance + both reaches (shoulders at nominal q)."""
        import pinocchio as pin

        r = self.robot
        q0 = np.asarray(r.nominal_q, dtype=float)
        pin.forwardKinematics(r.model, r.data, q0)
        sh = {}
        for lb in r.limbs:
            jid = lb.joint_ids[0] if lb.joint_ids else 0
            sh[lb.name] = np.asarray(r.data.oMi[jid].translation, dtype=float)
        return {(a, b): float(np.linalg.norm(sh[a] - sh[b])) + r.limb(a).reach + r.limb(b).reach
                for a in self.limbs for b in self.limbs}

    def _signature(self, stance: Any, q: np.ndarray) -> tuple[int, ...]:
        """Elbow-bend signs of the contact limbs: the component label (seed 001 section 4.2.3)."""
        out = []
        for limb in stance.limbs:
            idx, straight = self.elbow[limb]
            if idx is not None:
                out.append(int(np.sign(q[idx] - (straight or 0.0))))
        return tuple(out)

    def _key(self, parent: "_Node | None", stance: Any, q: np.ndarray) -> tuple[Any, tuple[Any, ...]]:
        """The ``(stance, component)`` key of a search node reached at ``q`` from ``parent``.

        With two or more contacts on a manifold of positive dimension, the elbow bends of the contact limbs
        (:meth:`_signature`).  Two cases where they name nothing, both met by the double-link robot of seed
        001 sec. 2.1 (Fig. 5, 13(b)):

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
            return (stance, self.members.setdefault((stance, _qkey(q)), label))
        return (stance, self._signature(stance, q))

    def transition_points(self, node: _Node, nxt: Any) -> list[np.ndarray]:
        """Every transition from ``node``'s single-contact stance to the zero-dimensional stance ``nxt``.

        Seed 001 Fig. 16 line 2 tries a transition "in each component" of ``F_sigma_i ∩ F_sigma_i+1``; for a
        zero-dimensional ``nxt`` each point is one (seed 001 sec. 2.1: "there are two configurations, q1 and
        q2, that place hands at both Holds 1 and 2", times the whole-turn variants of joints bounded by
        +-2 pi).  All are enumerated by inverse kinematics (base-moving limbs first), those passing the
        transition checks kept, nearest to ``node.q`` first (cached per node and stance).
        """
        ck = (node.key, nxt)
        if ck not in self.point_sets:
            r = self.robot
            base = set(int(j) for j in r.base_indices)
            qs = [node.q]
            for lb in sorted(nxt.limbs, key=lambda x: (not set(r.limb(x).joint_indices) & base, self.limbs.index(x))):
                qs = [s for q in qs for s in r.limb_ik(lb, q, self.terrain.hold(nxt[lb]).p)]
            checks = self._transition_checks(node.stance, nxt)
            self.point_sets[ck] = sorted((q for q in qs if all(c(q) for c in checks)),
                                         key=lambda q: float(np.sum((q - node.q) ** 2)))
        return self.point_sets[ck]

    def _transition_checks(self, small: Any, big: Any) -> list[Any]:
        """Checks of a transition: ``small``'s (collision aside), collision with ``big``'s hands exempt and
        the robot's links at least ``clearance`` apart."""
        key = ("transition", small, big)
        checks = self.checks.get(key)
        if checks is None:
            from .stance import CollisionCheck, make_checks

            checks = make_checks(self.robot, self.terrain, small, margin=self.margin, collision=False, torque="state")
            checks.append(CollisionCheck(self.robot, self.terrain, big.limbs, clearance=self.clearance))
            self.checks[key] = checks
        return checks

    def _manifold_dim(self, stance: Any) -> int:
        return int(self.robot.nq - len(stance) * len(self.axes))

    def _region_ok(self, stance: Any) -> bool:
        ok = self.regions.get(stance)
        if ok is None:
            from .stance import support_region

            ok = len(stance) > 0 and not support_region(self.robot, self.terrain, stance).is_empty
            self.regions[stance] = ok
        return ok

    def _valid(self, stance: Any, q: np.ndarray) -> bool:
        """All feasibility checks of ``stance`` at ``q`` (torque limits included)."""
        checks = self.checks.get(stance)
        if checks is None:
            from .stance import make_checks

            checks = make_checks(self.robot, self.terrain, stance, margin=self.margin, torque="state")
            self.checks[stance] = checks
        return all(c(q) for c in checks)

    def _hold_z(self, hold: str) -> float:
        return float(self.terrain.hold(hold).position[2])

    # ---- heuristic -------------------------------------------------------------------------------------
    def heuristic(self, stance: Any, last: tuple[tuple[str, str], ...]) -> float:
        """Estimated number of steps from ``stance`` to the goal (see the module docstring)."""
        g = self.goal
        if g.type == "height":
            thr = float(g.height) - self.reach  # type: ignore[arg-type]
            where = dict(last)
            where.update(dict(stance.pairs))
            zs = [self._hold_z(x) for x in stance.hold_ids]
            # a spread-out stance has to gather its hands before it can move up: penalise vertical spread
            h = self.spread_weight * max(0.0, max(zs) - min(zs) - self.reach) / self.stride
            for limb in self.limbs:
                if limb in stance:
                    h += 2.0 * max(0.0, thr - self._hold_z(stance[limb])) / self.stride
                else:
                    z = self._hold_z(where[limb]) if limb in where else min(
                        (self._hold_z(x) for x in stance.hold_ids), default=0.0)
                    h += 1.0 + 2.0 * max(0.0, thr - z) / self.stride
            return h
        if g.type == "hold":
            if stance.get(g.limb) == g.hold:
                return 0.0
            target = self.terrain.hold(g.hold).p  # type: ignore[arg-type]
            near = min(float(np.linalg.norm(self.terrain.hold(h).p - target)) for h in stance.hold_ids)
            return 1.0 + (1.0 if g.limb in stance else 0.0) + 2.0 * near / max(self.stride, 1e-9)
        want = dict(g.stance or ())
        return float(sum(1 for k in set(want) | set(stance) if want.get(k) != stance.get(k)))

    # ---- stance graph ------------------------------------------------------------------------------------
    def neighbours(self, node: _Node) -> list[tuple[str, str, str, Any]]:
        """Candidate edges out of ``node``: ``(action, limb, hold, next stance)``, geometry-filtered."""
        s = node.stance
        out = []
        for limb in s.limbs:  # releases
            nxt = s.without(limb)
            if len(nxt) and self._region_ok(nxt):
                out.append(("release", limb, s[limb], nxt))
        used = set(s.hold_ids)
        contacts = [(k, self.terrain.hold(h).p) for k, h in s.pairs]
        for limb in self.limbs:  # grabs
            if limb in s:
                continue
            for h in self.terrain.holds:
                if h.id in used:
                    continue
                if all(np.linalg.norm(h.p - p) <= self.pair_reach[(limb, k)] for k, p in contacts):
                    out.append(("grab", limb, h.id, s.with_hold(limb, h.id)))
        return out

    def transition(self, node: _Node, nxt: Any) -> np.ndarray | None:
        """FIND-TRANSITION between ``node``'s stance and ``nxt``, near ``node.q`` (cached per edge)."""
        ck = (node.key, nxt)
        if ck in self.transitions:
            return self.transitions[ck]
        q: np.ndarray | None = None
        small = nxt if len(nxt) < len(node.stance) else node.stance
        if len(nxt) < len(node.stance) and self._valid(small, node.q):
            q = node.q  # a release right where we are: a zero-length step
        elif self._manifold_dim(node.stance) > 0 or len(nxt) > len(node.stance):
            self._check_time()
            t = time.perf_counter()
            self.transition_calls += 1
            q = self.find_transition_near(node.stance, nxt, node.q, seed=self.seed + self.transition_calls)
            if q is None and self.fallback_attempts > 0:
                from .onestep import find_transition

                q = find_transition(self.robot, self.terrain, node.stance, nxt, seed=self.seed + self.transition_calls,
                                    attempts=self.fallback_attempts, margin=self.margin, torque=True,
                                    tolerance=self.tolerance, near=node.q)
            self.transition_times.append(time.perf_counter() - t)
            if q is not None and self._manifold_dim(node.stance) == 0 and len(nxt) < len(node.stance):
                q = None  # a point stance cannot move to another transition
        self.transitions[ck] = q
        return q

    def find_transition_near(self, sigma: Any, nxt: Any, near: np.ndarray, *, seed: int,
                             attempts: int | None = None, skip_first: bool = False) -> np.ndarray | None:
        """FIND-TRANSITION (seed 001 Fig. 17) started from the configuration the search is at.

        Seed 001 samples the pelvis position and closes every contact chain analytically (Fig. 17 lines
        1-5, appendix C).  Here the base coordinates are drawn around ``near`` - half of the draws shifted
        towards the centre of the smaller stance's support region, through a finite-difference Jacobian
        of the CoM with respect to the base - and each contact limb of the larger stance is closed by
        :meth:`RobotModel.limb_ik`, keeping the solution closest to ``near`` (so the elbow bends, hence
        the component, are kept).  The first draw passing the smaller stance's checks (joint limits,
        equilibrium, torque limits) and collision with the larger stance's hands exempt, the robot's links at
        least ``clearance`` apart (a transition is where a step starts: a posture whose links touch leaves
        no room to lift the next hand), is returned.

        Returns:
            The transition configuration, or ``None`` after ``attempts`` draws.
        """
        from .stance import support_region

        r = self.robot
        big, small = (sigma, nxt) if len(sigma) >= len(nxt) else (nxt, sigma)
        checks = self._transition_checks(small, big)
        rng = np.random.default_rng(seed)
        base = np.array(r.base_indices, dtype=int)
        lo, hi = np.asarray(r.lower, dtype=float), np.asarray(r.upper, dtype=float)
        targets = {lb: self.terrain.hold(big[lb]).p for lb in big.limbs}
        hands = np.asarray(r.hand_positions(near), dtype=float)
        on_hold = {lb for lb in big.limbs
                   if float(np.linalg.norm(hands[self.limbs.index(lb)] - targets[lb])) <= 0.5 * self.tolerance}
        # base-moving limbs first (their IK places the base), then the hand that is not yet on its hold
        limbs = sorted(big.limbs, key=lambda lb: (not set(r.limb(lb).joint_indices) & set(base.tolist()),
                                                  lb in on_hold, self.limbs.index(lb)))
        # direction towards the support region's centre, in base coordinates
        shift = np.zeros(len(base))
        region = support_region(r, self.terrain, small)
        if region.is_empty:
            return None
        if len(base) and len(region.vertices):
            c0 = np.asarray(r.com(near), dtype=float)
            jc = np.zeros((3, len(base)))
            for i, j in enumerate(base):
                dq = np.zeros(r.nq)
                dq[j] = 1e-6
                jc[:, i] = (np.asarray(r.com(near + dq)) - c0) / 1e-6
            centre = np.asarray(region.vertices, dtype=float).mean(axis=0)
            err = centre - region.coords(c0)[0]
            a = region.basis @ jc
            shift = np.linalg.lstsq(a, err, rcond=None)[0]
        prismatic = np.array([not self._is_angle(j) for j in base], dtype=bool)
        sd = np.where(prismatic, 0.04, 0.12)
        n_att = self.transition_attempts if attempts is None else int(attempts)
        # limbs whose chain starts after the base: reach prefilter from their shoulders (first joints)
        pre = [(r.limb(lb).joint_ids[0], targets[lb], float(r.limb(lb).reach)) for lb in big.limbs
               if r.limb(lb).joint_ids and not set(r.limb(lb).joint_indices) & set(base.tolist())]
        ik_tries = 0
        free_idx = np.array(sorted(j for lb in r.limbs if lb.name not in big for j in lb.joint_indices
                                   if j not in set(base.tolist())), dtype=int)
        for a_i in range(1 if skip_first else 0, n_att):
            q = near.copy()
            if a_i > 0 and len(base):
                grow = 1.0 + a_i / 20.0
                step = rng.normal(0.0, 1.0, len(base)) * sd * grow
                if a_i % 2 == 1:
                    step = step + shift * rng.uniform(0.3, 1.2)
                q[base] = np.clip(near[base] + step, lo[base], hi[base])
            if free_idx.size and a_i % 3 == 2:  # free limbs: a random posture within the joint limits
                q[free_idx] = rng.uniform(lo[free_idx], hi[free_idx])
            if pre and not self._shoulders_reach(q, pre):
                continue
            if a_i > 0 and region.margin(r.com(q)) < -self.com_slack:
                continue  # the CoM (limbs as in ``near``) is far outside the support region
            ik_tries += 1
            if ik_tries > self.ik_tries:
                break
            ok = True
            for lb in limbs:
                if a_i == 0 and lb in on_hold:
                    continue  # the base did not move: this hand is already on its hold
                sols = r.limb_ik(lb, q, targets[lb])
                if not sols:
                    ok = False
                    break
                idx = list(r.limb(lb).joint_indices)
                if lb in on_hold:  # stay in the component of ``near``: the same elbow bend (seed 001 sec. 4.2.3)
                    e, st = self.elbow[lb]
                    if e is not None:
                        sols = [x for x in sols if np.sign(x[e] - (st or 0.0)) == np.sign(near[e] - (st or 0.0))]
                        if not sols:
                            ok = False
                            break
                q = min(sols, key=lambda x: float(np.sum((x[idx] - near[idx]) ** 2)))
            if not ok:
                self.transition_fail["ik"] = self.transition_fail.get("ik", 0) + 1
                continue
            err_h = max(float(np.linalg.norm(r.hand_position(q, lb) - targets[lb])) for lb in big.limbs)
            if err_h > self.tolerance * 0.5:
                continue
            bad = next((c.name for c in checks if not c(q)), None)
            if bad is None:
                self.transition_stats.append((a_i, ik_tries))
                return q
            self.transition_fail[bad] = self.transition_fail.get(bad, 0) + 1
        self.transition_stats.append((-1, ik_tries))
        return None

    def direct_path(self, stance: Any, qa: np.ndarray, qb: np.ndarray, moving: str | None) -> list[np.ndarray] | None:
        """The direct local path between two configurations of ``stance``, or ``None`` if it is infeasible.

        PRM's local planner applied to the query itself (seed 001 section 3.3.2: "a feasible path often
        exists between two feasible transitions").  The base and the free limbs move linearly in joint
        space from ``qa`` to ``qb`` and each contact limb is re-closed on its hold by inverse kinematics
        (the solution nearest the previous waypoint).  On 3-D walls the hand of ``moving`` (the limb about
        to grab) first lifts ``lift`` metres off the wall, travels in a straight line to above its new
        hold while the body moves, and then comes down on it.  Waypoints are at most ``max_step`` apart
        in every coordinate and pass every check of the stance (joint limits, equilibrium, torque
        limits, collision, with a free hand allowed to touch the wall within :data:`HAND_CONTACT_RADIUS`
        of a hold).  OMPL's FIND-PATH is called only when this fails.
        """
        r = self.robot
        targets = {lb: self.terrain.hold(h).p for lb, h in stance.pairs}
        base = set(int(j) for j in r.base_indices)
        limbs = sorted(stance.limbs, key=lambda lb: (not set(r.limb(lb).joint_indices) & base, self.limbs.index(lb)))
        lift = self.lift if (moving is not None and not r.planar) else 0.0
        nrm = self._wall_normal()
        segments: list[tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]] = []
        if lift > 0 and moving is not None:
            pa = np.asarray(r.hand_position(qa, moving), dtype=float)
            pb = np.asarray(r.hand_position(qb, moving), dtype=float)
            la, qa_up = self._lift(moving, qa, pa, nrm, lift)
            lb_, qb_up = self._lift(moving, qb, pb, nrm, lift)
            if qa_up is None or qb_up is None:
                self._dfail("ik-lift")
                return None
            # lift straight off, move the lifted hand (in a straight line, else in joint space), come down;
            # or move the body first (the free limb's joints frozen, so the hand keeps its height off the
            # wall) and then the hand, or the hand first (body still) and then the body under it
            up, down = (qa, qa, pa, pa + la), (qb, qb, pb + lb_, pb)
            variants = [[up, (qa_up, qb_up, pa + la, pb + lb_), down]]
            idx_m = np.array(r.limb(moving).joint_indices, dtype=int)
            q_body = qb_up.copy()
            q_body[idx_m] = qa_up[idx_m]
            h_body = np.asarray(r.hand_position(q_body, moving), dtype=float)
            variants.append([up, (qa_up, q_body, None, None), (q_body, qb_up, h_body, pb + lb_), down])
            q_hand = self._ik_nearest(moving, qa_up, pb + lb_, qa_up)
            if q_hand is not None:
                variants.append([up, (qa_up, q_hand, pa + la, pb + lb_), (q_hand, qb_up, pb + lb_, pb + lb_), down])
            variants.append([up, (qa_up, qb_up, None, None), down])
        else:
            variants = [[(qa, qb, None, None)]]
        for segments in variants:
            path = self._follow(stance, qa, qb, moving, limbs, targets, segments)
            if path is not None:
                return self._thin(stance, path)
        if lift > 0 and moving is not None and self.via_points > 0:
            # the free limb swings around an obstacle (often another limb): through a random via posture
            rng = np.random.default_rng([self.seed, self.direct_calls])  # reproducible, no hash()
            r = self.robot
            idx = np.array(r.limb(moving).joint_indices, dtype=int)
            lo, hi = np.asarray(r.lower, dtype=float)[idx], np.asarray(r.upper, dtype=float)[idx]
            for _ in range(self.via_points):
                via = 0.5 * (qa_up + qb_up)
                via[idx] = rng.uniform(lo, hi)
                for lb in limbs:
                    via = self._ik_nearest(lb, via, targets[lb], 0.5 * (qa_up + qb_up))
                    if via is None:
                        break
                if via is None or not self._valid_free(stance, via):
                    continue
                segments = [(qa, qa, pa, pa + la), (qa_up, via, None, None), (via, qb_up, None, None),
                            (qb, qb, pb + lb_, pb)]
                path = self._follow(stance, qa, qb, moving, limbs, targets, segments)
                if path is not None:
                    return self._thin(stance, path)
        return None

    def _follow(self, stance: Any, qa: np.ndarray, qb: np.ndarray, moving: str | None, limbs: list[str],
                targets: dict[str, np.ndarray], segments: list[Any]) -> list[np.ndarray] | None:
        """Waypoints along ``segments`` (joint-space lines, the moving hand on a Cartesian line if given).

        Each waypoint re-closes the contact limbs (and places the moving hand) by inverse kinematics from
        the previous one.  Where the solution moves more than ``max_step`` in one interval (fast joint
        motion near a singular posture) the interval is halved, up to :data:`REFINE_DEPTH` times; a jump
        that survives the halvings is a switch between inverse-kinematics branches and fails the path.
        """
        out = [qa.copy()]
        prev = qa.copy()
        lim = self.max_step * (1 + 1e-9)
        for s_i, (q0, q1, h0, h1) in enumerate(segments):
            last_seg = s_i == len(segments) - 1
            span = float(np.max(np.abs(q1 - q0)))
            if h0 is not None and moving is not None:  # the joint travel of the straight hand motion
                q_end = self._ik_nearest(moving, q1, h1, q1 if last_seg else q0)
                if q_end is None:
                    self._dfail("ik-lift")
                    return None
                span = max(span, 1.5 * float(np.max(np.abs(q_end - prev))))
            n = max(1, int(math.ceil(span / (0.5 * self.max_step))))
            t_prev = 0.0
            for k in range(1, n + 1):
                pending = [k / n]
                while pending:
                    t = pending[-1]
                    if last_seg and t == 1.0:
                        q = qb.copy()
                    else:
                        q = (1 - t) * q0 + t * q1
                        if h0 is not None and moving is not None:
                            q = self._ik_nearest(moving, q, (1 - t) * h0 + t * h1, prev)
                            if q is None:
                                self._dfail("ik-moving")
                                return None
                        for lb in limbs:
                            q = self._ik_nearest(lb, q, targets[lb], prev)
                            if q is None:
                                self._dfail("ik")
                                return None
                    if float(np.max(np.abs(q - prev))) > lim:
                        if (t - t_prev) * n * 2 ** REFINE_DEPTH <= 1.0 + 1e-9:
                            self._dfail("jump")
                            return None  # a jump between IK branches
                        pending.append(0.5 * (t_prev + t))
                        continue
                    if not (last_seg and t == 1.0) and not self._valid_free(stance, q):
                        return None  # (qb is a transition, checked when it was found)
                    out.append(q)
                    prev, t_prev = q, t
                    pending.pop()
        return out

    def _lift(self, limb: str, q: np.ndarray, p: np.ndarray, nrm: np.ndarray, lift: float) -> tuple[np.ndarray,
                                                                                                     np.ndarray | None]:
        """The hand's lift-off offset (off the wall, possibly leaning towards or away from the body) and its IK."""
        import pinocchio as pin

        r = self.robot
        lbm = r.limb(limb)
        pin.forwardKinematics(r.model, r.data, q)
        sh = np.asarray(r.data.oMi[lbm.joint_ids[0]].translation, dtype=float) if lbm.joint_ids else p
        radial = (p - sh) - ((p - sh) @ nrm) * nrm
        radial = radial / np.linalg.norm(radial) if np.linalg.norm(radial) > 1e-9 else np.zeros(3)
        for d in (nrm, nrm - 0.7 * radial, nrm + 0.7 * radial, nrm - 1.5 * radial):
            off = lift * d / np.linalg.norm(d)
            sol = self._ik_nearest(limb, q, p + off, q)
            if sol is not None and float(np.max(np.abs(sol - q))) < 1.0:
                return off, sol
        return nrm * lift, None

    def _ik_nearest(self, limb: str, q: np.ndarray, target: np.ndarray, ref: np.ndarray) -> np.ndarray | None:
        sols = self.robot.limb_ik(limb, q, target)
        if not sols:
            return None
        idx = list(self.robot.limb(limb).joint_indices)
        return min(sols, key=lambda x: float(np.sum((x[idx] - ref[idx]) ** 2)))

    def _wall_normal(self) -> np.ndarray:
        for srf in self.terrain.surfaces:
            if srf.type == "plane" and srf.normal is not None:
                return np.asarray(srf.normal, dtype=float)
        n = np.mean([h.n for h in self.terrain.holds], axis=0)
        n = n - (n @ self.terrain.up) * self.terrain.up
        return n / np.linalg.norm(n) if np.linalg.norm(n) > 1e-9 else np.array([0.0, 1.0, 0.0])

    def _valid_free(self, stance: Any, q: np.ndarray) -> bool:
        """The stance's checks, where a free hand within :data:`HAND_CONTACT_RADIUS` of a hold may touch the wall."""
        key = ("no-collision", stance)
        checks = self.checks.get(key)
        if checks is None:
            from .stance import make_checks

            checks = make_checks(self.robot, self.terrain, stance, margin=self.margin, collision=False, torque="state")
            self.checks[key] = checks
        bad = next((c.name for c in checks if not c(q)), None)
        if bad is not None:
            self._dfail(bad)
            return False
        exempt = list(stance.limbs) + touching_hands(self.robot, self.terrain, q, stance.limbs)
        if self.robot.in_collision(q, self.terrain, contact_limbs=tuple(exempt)):
            self._dfail("collision")
            return False
        return True

    def _dfail(self, why: str) -> None:
        self.direct_fail[why] = self.direct_fail.get(why, 0) + 1

    def _thin(self, stance: Any, qs: list[np.ndarray]) -> list[np.ndarray]:
        r = self.robot
        targets = [(lb, self.terrain.hold(h).p) for lb, h in stance.pairs]
        out = [qs[0]]
        i = 0
        while i < len(qs) - 1:
            j = i + 1
            while j + 1 < len(qs) and float(np.max(np.abs(qs[j + 1] - qs[i]))) <= self.max_step:
                mid = 0.5 * (qs[i] + qs[j + 1])
                err = max(float(np.linalg.norm(r.hand_position(mid, lb) - p)) for lb, p in targets)
                if err > 0.2 * self.motion_tol:
                    break
                j += 1
            out.append(qs[j])
            i = j
        return out

    @property
    def reach_maps(self) -> dict[int, Any]:
        """The limbs' reach maps (:meth:`_reach_map`) by first joint id, probed once per robot when first needed."""
        if self._reach_key not in _REACH_MAPS:
            _REACH_MAPS[self._reach_key] = {lb.joint_ids[0]: t for lb in self.robot.limbs
                                            if (t := self._reach_map(lb)) is not None}
        return _REACH_MAPS[self._reach_key]

    def _shoulders_reach(self, q: np.ndarray, pre: list[tuple[int, np.ndarray, float]]) -> bool:
        """Necessary condition for closing the chains: each hold inside its limb's reach map (:meth:`_reach_map`)."""
        import pinocchio as pin

        r = self.robot
        maps = self.reach_maps
        pin.forwardKinematics(r.model, r.data, q)
        for jid, p, _ in pre:
            m = r.data.oMi[r.model.parents[jid]] * r.model.jointPlacements[jid]  # before the joint's own motion
            tab = maps.get(jid)
            d = p - m.translation
            if tab is None:
                continue
            e1, e2, radii = tab
            loc = m.rotation.T @ d
            ang = math.atan2(float(loc @ e2), float(loc @ e1))
            k = int(round((ang % (2 * math.pi)) / (2 * math.pi) * len(radii))) % len(radii)
            lim = max(radii[k - 1], radii[k], radii[(k + 1) % len(radii)])
            if float(np.hypot(loc @ e1, loc @ e2)) > lim + 0.01:
                return False
        return True

    def _reach_map(self, lb: Any, n_dir: int = 36,
                   dr: float = 0.02) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """Largest in-plane distance from a limb's first joint to a reachable hold, per direction.

        Probed once per robot with :meth:`RobotModel.limb_ik` at the nominal configuration, on the plane
        of the nominal hand perpendicular to the wall normal, in the first joint's frame (so it turns with
        the body).  Used only to skip base samples whose inverse kinematics would fail.
        """
        import pinocchio as pin

        r = self.robot
        if not lb.joint_ids or set(lb.joint_indices) & set(int(j) for j in r.base_indices):
            return None
        q0 = np.asarray(r.nominal_q, dtype=float)
        pin.forwardKinematics(r.model, r.data, q0)
        jid = lb.joint_ids[0]
        m = r.data.oMi[r.model.parents[jid]] * r.model.jointPlacements[jid]  # before the joint's own motion
        n = self._wall_normal()
        e1w = np.cross(n, [0.0, 0.0, 1.0]) if abs(n[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
        e1w /= np.linalg.norm(e1w)
        e2w = np.cross(n, e1w)
        hand = np.asarray(r.hand_position(q0, lb.name), dtype=float)
        centre = m.translation + ((hand - m.translation) @ n) * n  # shoulder projected on the hand plane
        radii = np.zeros(n_dir)
        for i in range(n_dir):
            a = 2 * math.pi * i / n_dir
            u = math.cos(a) * e1w + math.sin(a) * e2w
            rad = 0.0
            x = dr
            while x <= 1.2 * lb.reach + 1e-9:
                if r.limb_ik(lb.name, q0, centre + x * u):
                    rad = x
                x += dr
            radii[i] = rad
        # express the directions in the joint frame: bin k of the table covers local angle 2 pi k / n_dir
        e1 = m.rotation.T @ e1w
        e2 = m.rotation.T @ e2w
        return e1, e2, radii + dr

    def _is_angle(self, j: int) -> bool:
        names = getattr(self.robot, "joint_names", None)
        try:
            jid = self.robot.model.getJointId(names[j]) if names is not None else 0
            return "R" in self.robot.model.joints[jid].shortname()[-2:] or "Revolute" in \
                self.robot.model.joints[jid].shortname()
        except Exception:  # noqa: BLE001 - unknown joint kind: treat as an angle
            return True

    def _edge_cost(self, key: Any, nxt: Any) -> float:
        return 1.0 - math.log(self.prob.get((key, nxt), P_INITIAL))

    def stage1(self, start: _Node) -> _Node | None:
        """EXPLORE-STANCEGRAPH (seed 001 Fig. 16) as lazy weighted A*; returns a goal node or ``None``."""
        closed: dict[Any, _Node] = {start.key: start}
        if self.goal.met(start.stance, self.terrain, self.reach):
            return start
        heap: list[tuple[float, int, int, _Node, tuple[str, str, str, Any, int | None]]] = []
        counter = 0

        def push(node: _Node) -> None:
            nonlocal counter
            for action, limb, hold, nxt in self.neighbours(node):
                if (node.key, nxt) in self.transitions and self.transitions[(node.key, nxt)] is None:
                    continue
                if self.fails.get((node.key, nxt), 0) >= self.max_edge_failures:
                    continue
                lt = _after(node.last, action, limb, hold)
                f = node.g + self._edge_cost(node.key, nxt) + self.w * self.heuristic(nxt, lt)
                # a grab from one contact onto a point stance: one edge per transition point, nearest first
                points = range(len(self.transition_points(node, nxt))) if action == "grab" and len(node.stance) == 1 \
                    and self._manifold_dim(nxt) <= 0 else [None]
                for k in points:
                    counter += 1
                    heapq.heappush(heap, (f, -node.depth, counter, node, (action, limb, hold, nxt, k)))

        push(start)
        while heap:
            self._check_time()
            _, _, _, node, (action, limb, hold, nxt, k) = heapq.heappop(heap)
            if k is None:
                q = self.transition(node, nxt)
            else:
                # the component of a single contact is known only through the paths found in it: the edge
                # is verified when popped (the component graph of seed 001 Fig. 13(b), built as met)
                if self.fails.get((node.key, nxt), 0) >= self.max_edge_failures:
                    continue
                q = self.transition_points(node, nxt)[k]
                if self.connect(node, _Node((nxt, ()), q, 0.0, node, (action, limb, hold), ())) is None:
                    self._path_failed(node, nxt)
                    continue
                self.members.setdefault((node.stance, _qkey(q)), node.key[1])
            if q is None:
                continue
            key = self._key(node, nxt, q)
            if key in closed:
                continue
            child = _Node(key, q, node.g + self._edge_cost(node.key, nxt), node, (action, limb, hold),
                          _after(node.last, action, limb, hold), node.depth + 1)
            closed[key] = child
            self.explored.add(key)
            self._track(child)
            if self.goal.met(nxt, self.terrain, self.reach):
                return child
            push(child)
        return None

    def stage2(self, chain: list[_Node]) -> tuple[int, list[list[np.ndarray]]]:
        """EXPLORE-TRANSITIONGRAPH along a candidate (seed 001 Fig. 16): paths between its transitions.

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
                    and self._valid(v.stance, u.q):
                v = chain[i + 1] = _Node(v.key, u.q, v.g, u, v.action, v.last, v.depth)  # zero-length again
            path = self.connect(u, v)
            rep = 0
            while path is None and rep < self.repairs:
                rep += 1
                self._check_time()
                self.transition_calls += 1
                q_new = self.find_transition_near(u.stance, v.stance, u.q,
                                                  seed=self.seed + 7919 * self.transition_calls,
                                                  skip_first=True)
                if q_new is None:
                    continue
                cand = _Node(self._key(u, v.stance, q_new), q_new, v.g, u, v.action, v.last, v.depth)
                path = self.connect(u, cand)
                if path is not None:
                    v = chain[i + 1] = cand
                    self.repaired += 1
            if path is None:
                self._path_failed(u, v.stance)
                return i, paths
            if i + 2 < len(chain):
                w = chain[i + 2]
                chain[i + 2] = _Node(w.key, w.q, w.g, v, w.action, w.last, w.depth)
            paths.append(path)
        return len(chain) - 1, paths

    def _path_failed(self, u: _Node, nxt: Any) -> None:
        """No path from ``u`` to a transition onto ``nxt``: lower the edge's ``P`` (dropped after
        ``max_edge_failures``; seed 001 section 3.3.3)."""
        e = (u.key, nxt)
        self.fails[e] = self.fails.get(e, 0) + 1
        self._lower(e)
        self.path_failures += 1

    def _lower(self, edge: tuple[Any, Any]) -> None:
        """Multiply the probability of a stance-graph edge by :data:`P_FAIL_FACTOR` (seed 001 sec. 3.3.3)."""
        self.prob[edge] = self.prob.get(edge, P_INITIAL) * P_FAIL_FACTOR

    def connect(self, u: _Node, v: _Node) -> list[np.ndarray] | None:
        """A path in ``F_sigma(u)`` from ``u.q`` to ``v.q``: zero-length, direct, or OMPL's FIND-PATH (cached)."""
        from .onestep import find_path

        ck = (u.stance, _qkey(u.q), _qkey(v.q))
        if ck in self.paths:
            return self.paths[ck]
        if np.array_equal(u.q, v.q):
            self.paths[ck] = [u.q]
            return self.paths[ck]
        self._check_time()
        t = t_step = time.perf_counter()
        moving = v.action[1] if v.action is not None and v.action[0] == "grab" else None
        path = None
        # one contact (a free body swinging about one hold, seed 001 sec. 2.1): no chain to re-close, FIND-PATH
        # tries the straight line first itself, far cheaper than the inverse kinematics of the direct path
        if len(u.stance) > 1:
            self.direct_calls += 1
            path = self.direct_path(u.stance, u.q, v.q, moving)
            self.direct_times.append(time.perf_counter() - t)
        if path is not None:
            self.direct_found += 1
        elif self.step_time_limit > 0 and self._manifold_dim(u.stance) > 0:
            self.path_calls += 1
            budget = min(self.step_time_limit, max(0.1, self.time_limit - self.elapsed()))
            t = time.perf_counter()
            try:
                res = find_path(self.robot, self.terrain, u.stance, u.q, v.q, planner=self.planner, space=self.space,
                                sampler=self.sampler, time_limit=budget, seed=self.seed + 100003 * self.path_calls,
                                max_iterations=self.path_iterations, tolerance=self.tolerance, max_step=self.max_step,
                                margin=self.margin, torque=self.torque)
            except QueryError as exc:  # an end point the one-step checker rejects: no path from there
                res = OneStepFailure(str(exc))
            self.path_times.append(time.perf_counter() - t)
            for k, n in res.stats.get("rejections", {}).items():
                self.rejections[k] = self.rejections.get(k, 0) + int(n)
            if res.solved:
                path = [np.asarray(x, dtype=float) for x in res.path]
                # the one-step planner's densified waypoints are re-checked here (same rules as verify)
                if not all(self._valid_free(u.stance, x) for x in path[1:-1]):
                    self.ompl_rejected += 1
                    path = None
            self._report("path")
        self.paths[ck] = path
        self.step_times.append(time.perf_counter() - t_step)
        return path

    # ---- driver ----------------------------------------------------------------------------------------
    def elapsed(self) -> float:
        """Seconds since the query started."""
        return time.perf_counter() - self.t0

    def _check_time(self) -> None:
        if self.elapsed() > self.time_limit:
            raise _Budget()

    def _track(self, node: _Node) -> None:
        if self.best is None or self._progress_value(node) > self._progress_value(self.best):
            self.best = node
        self._report("stances")

    def _progress_value(self, node: _Node) -> float:
        return -self.heuristic(node.stance, node.last)

    def _report(self, phase: str, **extra: Any) -> None:
        if self.progress is None:
            return
        h0 = getattr(self, "_h0", None)
        hb = self.heuristic(self.best.stance, self.best.last) if self.best is not None else h0
        frac = 0.0 if not h0 else max(0.0, min(1.0, 1.0 - (hb or 0.0) / h0))
        self.progress({"phase": phase, "elapsed_s": self.elapsed(), "stances_explored": len(self.explored),
                       "onestep_calls": self.transition_calls + self.path_calls, "candidates": self.candidates,
                       "fraction": frac, **extra})

    def run(self, start_stance: Any, q_start: np.ndarray) -> tuple[list[_Node] | None, list[list[np.ndarray]],
                                                                       str]:
        """Alternate the two stages until a plan, an exhausted stance graph or the budget."""
        start = _Node(self._key(None, start_stance, q_start), q_start, 0.0, None, None, ())
        self._h0 = self.heuristic(start_stance, ())
        self.best = start
        self.explored.add(start.key)
        reason = ""
        root = start
        try:
            while True:
                goal_node = self.stage1(root)
                if goal_node is None:
                    if root is not start:  # the verified prefix is a dead end: search again from the start
                        root = start
                        continue
                    reason = self._why_exhausted()
                    return None, [], reason
                self.candidates += 1
                chain = goal_node.chain()
                reached, paths = self.stage2(chain)
                if reached == len(chain) - 1:
                    return chain, paths, ""
                # resume EXPLORE-STANCEGRAPH from the farthest transition reached (its prefix is verified); when
                # candidates keep failing at the same node, from further back each time (2, 4, 8 ... steps):
                # the way out may need another hold a few steps earlier
                n = self.stuck[chain[reached].key] = self.stuck.get(chain[reached].key, 0) + 1
                if n > 1 and reached > 0:  # the node itself looks like a dead end: the edge into it loses P too
                    self._lower((chain[reached - 1].key, chain[reached].stance))
                root = chain[max(0, reached - (2 ** (n - 1) if n > 1 else 0))]
        except _Budget:
            return None, [], (f"time budget of {self.time_limit:g} s spent after {self.candidates} candidate "
                              f"sequences; {self._frontier()}")

    def _frontier(self) -> str:
        b = self.best
        where = "" if b is None else (f"closest stance to the goal: {b.stance} (estimated "
                                      f"{self.heuristic(b.stance, b.last):.1f} steps away)")
        return f"{len(self.explored)} (stance, component) nodes explored; {where}"

    def _why_exhausted(self) -> str:
        return f"{EXHAUSTED}: no sequence of feasible grabs and releases reaches the goal; " + self._frontier()

    # ---- plan assembly ---------------------------------------------------------------------------------
    def build_plan(self, chain: list[_Node], paths: list[list[np.ndarray]], query: dict[str, Any],
                   settings: dict[str, Any]) -> Plan:
        """Assemble the :class:`Plan`: timing under the speed limits, forces on a thinned subset."""
        from . import __version__

        steps = []
        for i, (u, v, path) in enumerate(zip(chain[:-1], chain[1:], paths, strict=True)):
            action, limb, hold = v.action  # type: ignore[misc]
            wps = [np.asarray(x, dtype=float) for x in path]
            if not np.array_equal(wps[-1], v.q):
                wps.append(v.q)
            times = self._times(wps)
            forces = self._forces(u.stance, wps)
            margin = min((f.margin for f in forces), default=0.0)
            steps.append(Step(i, tuple(u.stance.pairs), action, limb, hold,  # type: ignore[arg-type]
                              tuple(tuple(float(x) for x in w) for w in wps), tuple(times), tuple(forces),
                              float(margin)))
        r = self.robot
        spec = json.loads(json.dumps(r.spec))
        urdf = Path(r.urdf_path).read_text()
        execution = float(sum(s.duration for s in steps))
        totals = {"steps": len(steps), "execution_s": execution,
                  "waypoints": int(sum(len(s.waypoints) for s in steps)),
                  "grabs": sum(1 for s in steps if s.action == "grab"),
                  "releases": sum(1 for s in steps if s.action == "release"),
                  "onestep_calls": self.transition_calls + self.path_calls,
                  "transition_calls": self.transition_calls, "path_calls": self.path_calls,
                  "stances_explored": len(self.explored), "candidates": self.candidates,
                  "path_failures": self.path_failures, "min_margin": min((s.margin for s in steps), default=0.0),
                  "rejections": dict(sorted(self.rejections.items()))}
        return Plan(
            robot={"name": r.name, "spec": spec, "spec_sha256": sha256_json(spec), "urdf": urdf,
                   "urdf_sha256": sha256_text(urdf)},
            terrain={"name": self.terrain.name, "data": self.terrain.to_dict(), "sha256": self.terrain.content_hash()},
            query=query, seed=self.seed, steps=tuple(steps), settings=settings, totals=totals,
            versions=library_versions(), timings=self.timings(), climb_ompl_version=__version__)

    def timings(self) -> dict[str, Any]:
        """Wall-clock figures (not reproducible; kept apart in the plan file)."""
        return {"total_s": self.elapsed(),
                "onestep_median_s": float(np.median(self.step_times)) if self.step_times else 0.0,
                "step_s": [round(t, 6) for t in self.step_times],
                "path_s": [round(t, 6) for t in self.path_times],
                "transition_median_s": float(np.median(self.transition_times)) if self.transition_times else 0.0,
                "transition_total_s": float(sum(self.transition_times))}

    def _times(self, wps: list[np.ndarray]) -> list[float]:
        """Waypoint times under the joint speed limits (seed 001 section 5.1: LEMUR 45 deg/s)."""
        vmax = np.asarray(self.robot.velocity_limits, dtype=float)
        t = [0.0]
        for a, b in zip(wps[:-1], wps[1:], strict=True):
            t.append(t[-1] + float(np.max(np.abs(b - a) / vmax)) * (1 + 1e-9))
        return t

    def _forces(self, stance: Any, wps: list[np.ndarray]) -> list[ForceSample]:
        """Contact forces and feed-forward torques on every ``force_every``-th waypoint (and the last).

        None for a robot without equilibrium condition (``equilibrium: false``, grabbing pegs, seed 001 sec. 2.1).
        """
        from .equilibrium import torque_feasible
        from .stance import support_region

        r = self.robot
        if not r.equilibrium:
            return []
        idx = sorted(set(range(0, len(wps), max(1, self.force_every))) | {len(wps) - 1})
        region = support_region(r, self.terrain, stance)
        contacts = stance.contacts(self.terrain)
        out = []
        for k in idx:
            q = wps[k]
            com = np.asarray(r.com(q), dtype=float)
            jac = np.array([r.hand_jacobian(q, lb) for lb in stance.limbs]).reshape(len(stance), 3, r.nq)
            res = torque_feasible(contacts, r.mass, self.terrain.g, com, jac, r.gravity_torques(q, self.terrain.g),
                                  r.torque_limits, r.actuated, planar=bool(r.planar))
            if res.forces is None:
                continue
            f = np.asarray(res.forces, dtype=float).reshape(len(stance), 3)
            tau = np.asarray(r.gravity_torques(q, self.terrain.g), dtype=float)
            for i, lb in enumerate(stance.limbs):
                tau = tau - np.asarray(r.hand_jacobian(q, lb)).T @ f[i]
            out.append(ForceSample(k, tuple((lb, tuple(float(x) for x in f[i])) for i, lb in enumerate(stance.limbs)),
                                   tuple(float(x) for x in tau), float(region.margin(com))))
        return out


def _after(last: tuple[tuple[str, str], ...], action: str, limb: str, hold: str) -> tuple[tuple[str, str], ...]:
    """The limbs' last released holds after ``action``: a release records the hold, a grab forgets it."""
    d = dict(last)
    if action == "release":
        d[limb] = hold
    else:
        d.pop(limb, None)
    return tuple(sorted(d.items()))


def whole_turn_variants(robot: Any, q: np.ndarray, angles: list[bool]) -> list[np.ndarray]:
    """``q`` with its angle joints (``angles[j]``) shifted by whole turns within the joint bounds.

    The same posture at another point of the bounded joint space (joints whose range spans more than a
    turn, e.g. the double-link robot's +-2 pi).  One joint shifted first, then two, ...; ``q`` excluded.
    """
    from .robot import wrap_into

    lo, hi = np.asarray(robot.lower, dtype=float), np.asarray(robot.upper, dtype=float)
    alts = [[(j, v) for v in wrap_into(float(q[j]), lo[j], hi[j]) if abs(v - q[j]) > 1e-9]
            for j in range(len(q)) if angles[j] and hi[j] - lo[j] > 2 * math.pi]
    out: list[tuple[int, np.ndarray]] = []
    for choice in itertools.product(*[[None, *a] for a in alts]):
        moved = [c for c in choice if c is not None]
        if moved:
            v = np.array(q, dtype=float)
            for j, x in moved:
                v[j] = x
            out.append((len(moved), v))
    return [v for _, v in sorted(out, key=lambda x: x[0])]


def _load_robot(robot: Any) -> Any:
    if isinstance(robot, (str, Path)):
        from .robot import RobotModel

        return RobotModel.load(robot)
    return robot


def _load_terrain(terrain: Any) -> Terrain:
    if isinstance(terrain, Terrain):
        return terrain
    if isinstance(terrain, Mapping):
        return Terrain.from_dict(terrain)
    return Terrain.load(terrain)


def start_configuration(robot: Any, terrain: Terrain, stance: Any, *, seed: int = 0, attempts: int = 400,
                        near: Any = None) -> np.ndarray | None:
    """A feasible configuration of ``stance`` (FIND-TRANSITION on the stance alone, seed 001 Fig. 17).

    Starts from ``near`` (default: the nominal configuration with its base moved so that the hands'
    centroid sits on the holds' centroid) and closes every contact limb by inverse kinematics (see
    :meth:`ClimbPlanner.find_transition_near`).
    """
    from .stance import Stance

    sigma = stance if isinstance(stance, Stance) else Stance(dict(stance))
    sigma.validate(robot, terrain)
    q = np.asarray(robot.nominal_q if near is None else near, dtype=float).copy()
    if near is None:
        base = np.array(robot.base_indices, dtype=int)
        idx = [[lb.name for lb in robot.limbs].index(x) for x in sigma.limbs]
        target = np.mean([terrain.hold(h).p for h in sigma.hold_ids], axis=0)
        for _ in range(3):
            h0 = np.asarray(robot.hand_positions(q), dtype=float)[idx].mean(axis=0)
            jac = np.zeros((3, len(base)))
            for i, j in enumerate(base):
                dq = np.zeros(robot.nq)
                dq[j] = 1e-6
                jac[:, i] = (np.asarray(robot.hand_positions(q + dq), dtype=float)[idx].mean(axis=0) - h0) / 1e-6
            q[base] += np.linalg.lstsq(jac, target - h0, rcond=None)[0]
        q = np.clip(q, robot.lower, robot.upper)
    cp = ClimbPlanner(robot, terrain, Goal("stance", stance=tuple(sigma.pairs)), seed=seed)
    return cp.find_transition_near(sigma, sigma, q, seed=seed, attempts=attempts)


def lowest_stance(robot: Any, terrain: Terrain, scale: float = 0.7) -> dict[str, str]:
    """A start stance near the bottom middle of the wall, shaped like the nominal pose.

    The nominal hand layout, shrunk by ``scale`` about its centroid, is placed at the median hold ``x``
    with its lowest hand just above the lowest hold there; each limb (in the robot's order) takes the
    nearest free hold.
    """
    q0 = np.asarray(robot.nominal_q, dtype=float)
    hands = np.asarray(robot.hand_positions(q0), dtype=float)
    hands = hands.mean(axis=0) + scale * (hands - hands.mean(axis=0))
    P = terrain.positions
    xc = float(np.median(P[:, 0]))
    near_x = np.abs(P[:, 0] - xc) <= np.ptp(hands[:, 0]) + 1e-9
    zlow = float(P[near_x, 2].min()) if near_x.any() else float(P[:, 2].min())
    shift = np.array([xc - hands[:, 0].mean(), 0.0, zlow - hands[:, 2].min() + 0.05])
    out: dict[str, str] = {}
    used: set[int] = set()
    for i, lb in enumerate(robot.limbs):
        target = hands[i] + shift
        d = np.linalg.norm((P - target)[:, [0, 2]], axis=1)
        for j in np.argsort(d, kind="stable"):
            if int(j) not in used:
                used.add(int(j))
                out[lb.name] = terrain.holds[int(j)].id
                break
    return out


def default_start(robot: Any, terrain: Terrain, *, seed: int = 0) -> tuple[dict[str, str], np.ndarray] | None:
    """A start stance (:func:`lowest_stance` at a few scales) with a feasible start configuration."""
    for scale in (0.7, 0.6, 0.8, 0.5, 0.9, 1.0):
        stance = lowest_stance(robot, terrain, scale)
        q = start_configuration(robot, terrain, stance, seed=seed)
        if q is not None:
            return stance, q
    return None


def plan_climb(robot: Any, terrain: Any, start: Any, goal: Any, planner: str = "LazyPRM", space: str = "projected",
               time_limit: float = 120.0, seed: int = 0, *, q_start: Any = None, sampler: str = "uniform",
               step_time_limit: float = STEP_TIME_LIMIT, progress: ProgressFn | None = None,
               **options: Any) -> PlanResult:
    """Plan a multi-step climb (seed 001 section 3.3, Fig. 16).

    Args:
        robot: a :class:`~climb_ompl.robot.RobotModel`, a bundled robot name or a spec path.
        terrain: a :class:`~climb_ompl.terrain.Terrain`, a bundled terrain name or a terrain file path.
        start: the start stance (``{limb: hold}`` or a :class:`~climb_ompl.stance.Stance`).
        goal: a :class:`Goal`, a height (number), ``"LIMB=HOLD"``, or a target stance mapping.
        planner: OMPL planner of the one-step FIND-PATH (default ``LazyPRM``, seed 002's lazy PRM).
        space: constrained space: ``projected``, ``atlas`` or ``tangent_bundle``.
        time_limit: total wall-clock budget, seconds.
        seed: seed of every random choice (the same seed gives the same plan).
        q_start: start configuration; default: FIND-TRANSITION on the start stance near the nominal pose
            (and, if the stance graph is exhausted from there, its :func:`whole_turn_variants` in turn).
        sampler: sampler of FIND-PATH (:mod:`climb_ompl.samplers`).
        step_time_limit: wall-clock budget of one FIND-PATH call, seconds.
        progress: called with a dict (``phase, elapsed_s, stances_explored, onestep_calls, fraction``) as
            the search advances.
        **options: further :class:`ClimbPlanner` settings (``heuristic_weight``, ``stride``,
            ``transition_attempts``, ``path_iterations``, ``max_step``, ``force_every``, ``torque``, ...).

    Returns:
        A :class:`PlanResult`; ``status == "no-plan"`` with ``reason`` when no plan was found.

    Raises:
        QueryError: unknown limb/hold, a start configuration off its stance or infeasible.
        PlannerNotFound: unknown planner, space or sampler name.
    """
    from .stance import Stance, StanceConstraint

    t0 = time.perf_counter()
    robot = _load_robot(robot)
    terrain = _load_terrain(terrain)
    goal = Goal.parse(goal)
    goal.validate(robot, terrain)
    sigma0 = start if isinstance(start, Stance) else Stance(dict(start))
    sigma0.validate(robot, terrain)
    if len(sigma0) == 0:
        raise QueryError("start stance: at least one limb must be on a hold")
    _check_names(planner, space, sampler)
    cp = ClimbPlanner(robot, terrain, goal, planner=planner, space=space, sampler=sampler, time_limit=time_limit,
                      step_time_limit=step_time_limit, seed=seed, progress=progress, **options)
    cp.t0 = t0
    if q_start is None:
        q0 = start_configuration(robot, terrain, sigma0, seed=seed)
        if q0 is None:
            return PlanResult("no-plan", None, _stats(cp), f"no feasible configuration found for the start stance "
                              f"{sigma0} (FIND-TRANSITION on that stance failed)")
    else:
        q0 = np.asarray(q_start, dtype=float).reshape(-1)
        if q0.shape != (robot.nq,) or not np.all(np.isfinite(q0)):
            raise QueryError(f"q_start: expected {robot.nq} finite values, got shape {q0.shape}")
        err = StanceConstraint(robot, terrain, sigma0, cp.tolerance).error(q0)
        if err > cp.tolerance:
            raise QueryError(f"q_start: a hand is {err:.3g} m from its hold in stance {sigma0}")
        if not cp._valid(sigma0, q0):
            raise QueryError(f"q_start is infeasible at stance {sigma0} (equilibrium, limits, torque or collision)")
    chain, paths, reason = cp.run(sigma0, q0)
    if chain is None and q_start is None and reason.startswith(EXHAUSTED):
        # the start posture's angles a whole turn further: another point of bounded joint space from which
        # a winding route may fit (the double-link robot's +-2 pi angles, seed 001 sec. 2.1)
        for qv in whole_turn_variants(robot, q0, [cp._is_angle(j) for j in range(robot.nq)]):
            cp = ClimbPlanner(robot, terrain, goal, planner=planner, space=space, sampler=sampler,
                              time_limit=time_limit, step_time_limit=step_time_limit, seed=seed, progress=progress,
                              **options)
            cp.t0 = t0  # one budget for all starts
            chain, paths, reason = cp.run(sigma0, qv)
            if chain is not None:
                q0 = qv
                break
            if not reason.startswith(EXHAUSTED):
                break
    if chain is None:
        return PlanResult("no-plan", None, _stats(cp), reason)
    query = {"start": {"stance": sigma0.to_dict(), "q": [float(x) for x in q0]}, "goal": goal.to_dict()}
    settings = {"planner": planner, "space": space, "sampler": sampler, "time_limit": float(time_limit),
                "step_time_limit": float(step_time_limit), "path_iterations": cp.path_iterations,
                "transition_attempts": cp.transition_attempts, "heuristic_weight": cp.w, "stride": cp.stride,
                "max_edge_failures": cp.max_edge_failures, "clearance": cp.clearance, "max_step": cp.max_step,
                "force_every": cp.force_every,
                "torque": cp.torque, "margin": cp.margin, "tolerance": cp.tolerance, "reach": cp.reach}
    plan = cp.build_plan(chain, paths, query, settings)
    return PlanResult("found", plan, _stats(cp, plan))


def _check_names(planner: str, space: str, sampler: str) -> None:
    from ._ompl import PLANNER_NAMES
    from .errors import PlannerNotFound
    from .samplers import parse_sampler
    from .stance import SPACE_NAMES

    if planner not in PLANNER_NAMES:
        raise PlannerNotFound("planner", planner, PLANNER_NAMES)
    if space not in SPACE_NAMES:
        raise PlannerNotFound("constrained space", space, SPACE_NAMES)
    parse_sampler(sampler)


def _stats(cp: ClimbPlanner, plan: Plan | None = None) -> dict[str, Any]:
    return {"steps": len(plan.steps) if plan else 0, "execution_s": plan.execution_s if plan else 0.0,
            "onestep_calls": cp.transition_calls + cp.path_calls, "transition_calls": cp.transition_calls,
            "path_calls": cp.path_calls, "stances_explored": len(cp.explored), "candidates": cp.candidates,
            "path_failures": cp.path_failures, "rejections": dict(sorted(cp.rejections.items())),
            "onestep_median_s": float(np.median(cp.step_times)) if cp.step_times else 0.0,
            "step_times_s": list(cp.step_times), "onestep_times_s": list(cp.path_times),
            "transition_times_s": list(cp.transition_times), "direct_calls": cp.direct_calls,
            "direct_found": cp.direct_found, "repaired": cp.repaired,
            "total_s": cp.elapsed()}


__all__ = ["Goal", "PlanResult", "ClimbPlanner", "plan_climb", "start_configuration", "lowest_stance", "default_start",
           "whole_turn_variants", "STEP_TIME_LIMIT",
           "P_INITIAL", "P_FAIL_FACTOR"]
