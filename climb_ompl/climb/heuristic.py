"""The guided search's goal heuristic (:class:`GoalHeuristic`) and the edges the search proposes out of a node
(:class:`EdgeProposals`: the geometric prefilters of Bretl (2006), sec. 4.3, and the guided search's ``grab_reach``).

**Height goal** (a guide, not a bound): ``2 * sum_l gap_l / stride`` where ``gap_l`` is how far limb ``l``'s hold
(its last hold while free) lies below ``h - reach``: each limb needs about one release and one grab per stride.
With ``keep_shape`` a limb's height counts only up to where the robot's nominal shape lets it be above each other
limb ``k``: at most ``z_k + max(0, n_l - n_k) + s``, where ``n`` are the nominal hand heights
(:attr:`GoalHeuristic.shape`) and ``s`` is a stride up the wall's slope.  A limb left far behind holds the body
back (the pair reach of the laggard and an empty support region without it end such climbs), so the others' gains
beyond it are not counted as progress and the laggard's grabs come first; a stance more compact than the nominal
one costs nothing.  The gaps are then measured to the goal stance in the nominal shape, each limb
``n_l - min_k n_k`` above ``h - reach``: the goal puts every hold at or above ``h - reach``, and the lowest limb
gets there only once the others are above it as the shape wants (without it the upper limbs stop at
``h - reach`` and the last grabs of the lower ones find the stance too compact).

The heuristic counts a free limb at its last hold, so every release of a stance gets the same value (one step
more) and the queue would try them in limb order.  With ``release_lookahead`` (the default) a release is queued
with one step plus the smallest heuristic over the grabs the search would propose for the freed limb from the
node's configuration (:meth:`EdgeProposals.release_heuristic`): the limb that can climb highest goes first, and a
limb whose best grab gains nothing (the others hold it back) comes after the stances that do make progress.

**Goal hold** (``limb`` on ``hold``): ``1 + [limb in contact] + (free other limbs) + 2 d / stride`` with ``d`` the
distance from the limb's own hold (its last one while free) to the goal hold: a free limb grabs again before the
goal limb lets go, as the height heuristic counts it.  (Measured from the nearest contact hold of any limb instead,
another limb stepping towards the goal hold would look like progress the goal limb cannot use: docs/climb.md.)

**Goal of stances** (a re-plan rejoining the route it repairs): a release and a grab per limb on another hold plus
the strides its hand travels, to the nearest target (:mod:`climb_ompl.climb.stance_gap`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from climb_ompl.climb.goal import Goal, robot_reach
from climb_ompl.climb.nodes import LastHolds, Node, after
from climb_ompl.climb.stance_gap import StanceGap
from climb_ompl.manifold.stance import limb_hold_targets
from climb_ompl.model.terrain import Terrain
from climb_ompl.settings import ClimbSettings

if TYPE_CHECKING:
    from climb_ompl.manifold.feasibility import Feasibility


def nominal_heights(robot: Any, terrain: Terrain) -> tuple[dict[str, float], float]:
    """The nominal hands' heights about their mean, by limb, metres, and the height gained per metre up the
    wall's slope (``up_wall . up``, :func:`climb_ompl.climb.start.wall_axes`)."""
    from climb_ompl.climb.start import wall_axes

    _, v = wall_axes(terrain)
    rise = float(abs(v @ terrain.up))
    hands = np.asarray(robot.hand_positions(np.asarray(robot.nominal_q, dtype=float)), dtype=float)
    along = (hands - hands.mean(axis=0)) @ v
    return {lb.name: float(a) * rise for lb, a in zip(robot.limbs, along, strict=True)}, rise


class GoalHeuristic:
    """Estimated number of steps from a stance to the goal (see the module docstring); called as
    ``heuristic(stance, last)`` with ``last`` the free limbs' last holds.

    Args:
        robot, terrain, goal: the query.
        settings: the climb's settings (``stride``, ``keep_shape``).

    Attributes:
        limbs: the robot's limb names.
        reach: the largest limb reach, m (a height goal's allowance, :func:`climb_ompl.climb.goal.robot_reach`).
        stride: height a hand gains per grab, m (``settings.stride``, default half the mean limb reach).
        shape: the nominal hands' heights along minus gravity when the nominal posture lies on the wall's plane
            with its up along the wall's slope (as :func:`climb_ompl.climb.start.lowest_stance` lays it out), by
            limb, m.
    """

    def __init__(self, robot: Any, terrain: Terrain, goal: Goal, settings: ClimbSettings):
        self.terrain, self.goal, self.keep_shape = terrain, goal, bool(settings.keep_shape)
        self.limbs = [lb.name for lb in robot.limbs]
        self.reach = robot_reach(robot)
        mean_reach = float(np.mean([lb.reach for lb in robot.limbs]))
        self.stride = float(settings.stride) if settings.stride is not None else 0.5 * mean_reach
        self.shape, self._shape_scale = nominal_heights(robot, terrain)
        self._cache: dict[Any, float] = {}
        self._gap: StanceGap | None = None  # the heuristic of a stance goal

    def __call__(self, stance: Any, last: LastHolds) -> float:
        g = self.goal
        if g.type == "height":
            return self._height(stance, last)
        if g.type == "hold":
            return self._hold(stance, last)
        key = (stance, last)
        h = self._cache.get(key)
        if h is None:
            if self._gap is None:
                self._gap = StanceGap(self.terrain, self.limbs, g.stances if g.type == "stances" else
                                      [g.stance or ()], self.stride)
            h = self._cache[key] = self._gap(stance, {**dict(last), **dict(stance.pairs)})
        return h

    def _height(self, stance: Any, last: LastHolds) -> float:
        """The height goal's estimate (module docstring)."""
        thr = float(self.goal.height) - self.reach  # type: ignore[arg-type]
        where = dict(last)
        where.update(dict(stance.pairs))
        low = min((self.terrain.height(x) for x in stance.hold_ids), default=0.0)
        z = {limb: self.terrain.height(where[limb]) if limb in where else low for limb in self.limbs}
        t = dict.fromkeys(self.limbs, thr)
        if self.keep_shape and len(z) > 1:
            z = self.shape_capped(z)
            low = min(self.shape.values())  # the goal stance in the nominal shape: its lowest limb at thr
            t = {lb: thr + self.shape[lb] - low for lb in self.limbs}
        return sum((0.0 if limb in stance else 1.0) + 2.0 * max(0.0, t[limb] - z[limb]) / self.stride
                   for limb in self.limbs)

    def _hold(self, stance: Any, last: LastHolds) -> float:
        """The goal hold's estimate (module docstring)."""
        g = self.goal
        if stance.get(g.limb) == g.hold:
            return 0.0
        target = self.terrain.hold(g.hold).p  # type: ignore[arg-type]
        own = stance.get(g.limb) or dict(last).get(g.limb)  # type: ignore[arg-type]  # its hold, or last one
        near = float(np.linalg.norm(self.terrain.hold(own).p - target)) if own is not None else \
            min(float(np.linalg.norm(self.terrain.hold(h).p - target)) for h in stance.hold_ids)
        free = sum(1.0 for lb in self.limbs if lb != g.limb and lb not in stance)  # each grabs again first
        return 1.0 + (1.0 if g.limb in stance else 0.0) + free + 2.0 * near / max(self.stride, 1e-9)

    def shape_capped(self, z: dict[str, float]) -> dict[str, float]:
        """Each limb's height capped at ``z_k + max(0, n_l - n_k) + s`` for every other limb ``k`` (the
        ``keep_shape`` term, see the module docstring); heights in metres, by limb."""
        n, slack = self.shape, self.stride * self._shape_scale
        return {lb: min(v, min(z[k] + max(0.0, n[lb] - n[k]) for k in z if k != lb) + slack) for lb, v in z.items()}


class EdgeProposals:
    """The edges the search proposes out of a node, geometry-filtered: a release when the stance after it has a
    non-empty support region (Bretl 2006, appendix B), a grab of a hold within the pair reach of the grabbing limb
    and every limb on a hold (sec. 4.3), and, with ``grab_reach``, within that many limb reaches of the limb's first
    joint where the robot stands.

    Args:
        robot, terrain: the query's.
        feas: the feasibility tests (support regions).
        settings: the climb's settings (``grab_reach``).
        heuristic: the goal heuristic (for :meth:`release_heuristic`).

    Attributes:
        pair_reach: the largest distance between the holds of two limbs, by limb pair, m
            (:func:`climb_ompl.model.reach.pair_reach`).
        beyond: the grabs the ``grab_reach`` prefilter did not propose: ``(node key, next stance) -> (distance of
            the hold's hand target from the limb's first joint, largest distance proposed)``, m, for the frontier
            diagnosis (:mod:`climb_ompl.climb.frontier`).
    """

    def __init__(self, robot: Any, terrain: Terrain, feas: Feasibility, settings: ClimbSettings,
                 heuristic: GoalHeuristic):
        from climb_ompl.model.reach import pair_reach

        self.robot, self.terrain, self.feas, self.s, self.heuristic = robot, terrain, feas, settings, heuristic
        self.pair_reach = pair_reach(robot)
        self.beyond: dict[tuple[Any, Any], tuple[float, float]] = {}
        self._targets: dict[str, np.ndarray] = {}  # each limb's hand target on every hold
        self._hold_dist: dict[str, np.ndarray] = {}  # each hold's distance to every hold

    def __call__(self, node: Node) -> list[tuple[str, str, str, Any]]:
        """Candidate edges out of ``node``: ``(action, limb, hold, next stance)``, releases first."""
        s = node.stance
        out = []
        for limb in s.limbs:  # releases
            nxt = s.without(limb)
            if len(nxt) and self.feas.region_ok(nxt):
                out.append(("release", limb, s[limb], nxt))
        used = set(s.hold_ids)
        free = [limb for limb in self.heuristic.limbs if limb not in s]
        near = self.near_reach(node.q, free)
        holds = self.terrain.holds
        for limb in free:  # grabs
            for i in np.flatnonzero(self.pair_reach_mask(s, limb)).tolist():
                h = holds[i]
                if h.id not in used:
                    nxt = s.with_hold(limb, h.id)
                    if limb in near and near[limb][0][i] > near[limb][1]:
                        self.beyond[(node.key, nxt)] = (float(near[limb][0][i]), near[limb][1])
                        continue
                    out.append(("grab", limb, h.id, nxt))
        return out

    def pair_reach_mask(self, stance: Any, limb: str) -> np.ndarray:
        """Mask of the terrain's holds within the pair reach of ``limb`` from every contact hold of ``stance``
        (Bretl 2006, sec. 4.3); each hold's distances to every hold are computed once."""
        ok = np.ones(len(self.terrain.holds), dtype=bool)
        for k, h in stance.pairs:
            d = self._hold_dist.get(h)
            if d is None:
                d = self._hold_dist[h] = np.linalg.norm(self.terrain.positions - self.terrain.hold(h).p, axis=1)
            ok &= d <= self.pair_reach[(limb, k)]
        return ok

    def release_heuristic(self, node: Node, limb: str, nxt: Any, last: LastHolds) -> float:
        """The heuristic of releasing ``limb`` from ``node`` onto ``nxt``, one grab ahead (``release_lookahead``):
        one step for the grab plus the smallest heuristic of the grabs :meth:`__call__` would propose for the freed
        limb where the robot stands (the pair reach of ``nxt``'s contacts and ``grab_reach`` at ``node.q``), or the
        plain heuristic when none is.  Never more than the plain heuristic: the released hold is one of those grabs.
        The height heuristic gives every release of a stance the same value (the freed limb counted at its last
        hold), so without it the releases are tried in limb order; with it, first the limb that can climb highest
        (see the module docstring)."""
        ok = self.pair_reach_mask(nxt, limb)
        near = self.near_reach(node.q, [limb])
        if limb in near:
            ok &= near[limb][0] <= near[limb][1]
        used, holds = set(nxt.hold_ids), self.terrain.holds
        ids = [holds[i].id for i in np.flatnonzero(ok).tolist() if holds[i].id not in used]
        if ids and self.heuristic.goal.type == "height":  # the height heuristic never grows with the hold's height
            ids = [max(ids, key=self.terrain.height)]
        best = min((self.heuristic(nxt.with_hold(limb, h), after(last, "grab", limb, h)) for h in ids), default=None)
        return self.heuristic(nxt, last) if best is None else 1.0 + best

    def near_reach(self, q: np.ndarray, limbs: list[str]) -> dict[str, tuple[np.ndarray, float]]:
        """For the grab prefilter ``grab_reach``: per free limb moved by its own joints only, the distance of
        every hold's hand target from the limb's first joint at ``q``, and the largest distance proposed
        (``grab_reach`` times the limb's reach), m.  Empty when the prefilter is off.

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


__all__ = ["EdgeProposals", "GoalHeuristic", "nominal_heights"]
