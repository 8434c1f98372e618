"""Re-planning when a hold fails: from the state a climb reached, on a changed terrain, to the same goal.

A climb does not go as planned: a hold breaks, turns out slippery, or sits a few centimetres from where the
map put it.  :func:`replan` takes a plan, the number of steps already executed and a :class:`TerrainChange`
(holds removed, moved, with another friction, or added), and plans from the state reached to the plan's
goal on the changed terrain.  The new plan keeps the executed steps unchanged: they are history, checked on
the terrain as it was when they were executed.  Only when the state reached relies on a changed hold (a hand on
it, or resting where it was after letting go of it) does the new plan back off, to the last state before that
which does not, and say so.  The new plan records the event (``events``: the changed holds as they were, so
that the terrain before the change can be rebuilt, :func:`terrain_before`) and passes
:func:`climb_ompl.verification.climb.verify`: the kept steps on the terrain before the change, the new ones on the
changed terrain.

**Warm start.**  The second search re-uses what the first one learned wherever the change leaves it valid,
and drops what touches a changed hold (:meth:`climb_ompl.climb.search.StanceGraphSearch.inherit`):

* from the first search itself, when the caller has it (``plan_climb(..., keep_search=True)`` returns it as
  ``ClimbResult.search``; pass it as ``warm``): every transition found, every path between transitions (or
  the knowledge that there is none), the components of single contacts; support regions are cached by contact
  geometry for the whole process anyway.  Its failed FIND-TRANSITION calls, lowered edge probabilities and
  failure counts are not kept: a failed call is a bounded number of random draws, and the new search draws again
  (:meth:`climb_ompl.climb.search.StanceGraphSearch.inherit`);
* from the plan file alone (the command line): the route of the plan, i.e. its transitions and the paths
  between them, so that a detour that rejoins the old route costs nothing after the rejoining step.

**The old route first.**  When the change moved holds of the old route or changed their friction but removed
none of them, the new search first follows the old route's grabs and releases (:func:`kept_route`), each step
planned again (FIND-TRANSITION, then the paths between transitions) up to where the route no longer relies on a
changed hold: a hold a few centimetres from where the map put it, or a little more slippery, usually keeps its
route, and that costs a few one-step plans instead of an exploration of the stance graph.  (A removed hold
has no such stand-in: its nearest free holds, tried in its place, rarely carry the other limbs' moves that
relied on it, and cost more than they save.)

**Rejoining the old route** (``rejoin``; by default only when the change removed no hold, since after a removed
hold the detour plus the rest of the old route is often longer than a new route; docs/climb.md gives the figures
of both ways).  The old route's steps after the last one that
relies on a changed hold
(:func:`rejoin_index`) hold on the changed terrain: a search aims at their stances, arriving only in the component
of the old route's configuration there (``WarmStart.joins``), and joins that configuration within the stance
(when it cannot, the warm search to the plan's goal follows, re-using what the rejoining search learned).
Rejoining the route gets a quarter of the time budget, and explores at most twice as many stances as the first
search did for the whole climb (:func:`rejoin_limit`), the warm search to the plan's goal the rest; only
when that one ends with the stance graph exhausted is a search from scratch tried with the time left
(``ReplanResult.used`` says which answered).
"""

from __future__ import annotations

import dataclasses
import math
import numbers
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from climb_ompl.climb.multistep import ClimbResult
from climb_ompl.climb.status import ClimbStatus
from climb_ompl.errors import QueryError
from climb_ompl.model.terrain import Terrain
from climb_ompl.plan.events import TerrainChange, change_event, terrain_before, well_formed_before
from climb_ompl.plan.file import Plan, Step

if TYPE_CHECKING:
    from climb_ompl.climb.search import StanceGraphSearch
    from climb_ompl.climb.warm import WarmStart

#: Share of the time budget given to rejoining the old route; the warm search to the plan's goal gets what is
#: left (and a search from scratch what that one leaves, when it exhausts the stance graph).
WARM_SHARE = 0.25
#: Rejoining searches tried when the detour found cannot join the old route where it arrives (each without
#: the stance it arrived at, each re-using what the previous one learned); then the warm search to the goal.
JOIN_ATTEMPTS = 1
#: A rejoining search explores at most this many times as many (stance, component) nodes as the first search
#: explored for the whole climb (the plan's ``totals``), and at least :data:`REJOIN_MIN_STANCES`: a detour that
#: costs more than the whole climb did is left to the warm search to the goal, which re-uses what it learned
#: (docs/climb.md, "Re-planning").
REJOIN_STANCES = 2.0
REJOIN_MIN_STANCES = 50


def rejoin_limit(plan: Plan) -> int | None:
    """The most (stance, component) nodes a rejoining search explores (:data:`REJOIN_STANCES`), or ``None``
    for a plan whose totals do not say how many its search explored."""
    n = plan.totals.get("stances_explored") if isinstance(plan.totals, dict) else None
    if not isinstance(n, numbers.Real) or n <= 0:
        return None
    return max(REJOIN_MIN_STANCES, int(math.ceil(REJOIN_STANCES * float(n))))


@dataclass
class ReplanResult:
    """Outcome of :func:`replan`.

    Attributes:
        found: whether a new plan was found.
        plan: the new plan (the kept steps, then the new ones), or ``None``.
        resumed_at: the number of executed steps kept (``at_step``, or fewer after a back-off).
        backed_off: whether the plan had to back off before ``at_step`` (a kept step or the state reached
            relied on a changed hold).
        climb: the result of the search that answered (:class:`~climb_ompl.climb.multistep.ClimbResult`: its
            ``status``, ``reason`` and frontier ``diagnosis`` when there is no new plan, its counters in ``stats``;
            its plan holds the new steps only); when no search ran (the start stance relies on a changed hold), a
            result with status ``NO_START`` saying so.
        used: ``warm`` or ``scratch``: which search answered (``""`` when none ran).
        stats: the re-plan's own figures: ``warm_s``, ``scratch_s`` (when it ran), ``steps`` (the new ones, when
            found), and ``searches``: every search run, in order (``search``: ``rejoin``, ``goal`` or ``scratch``;
            ``s``: its seconds; ``join_s``: for a rejoining search, the seconds spent joining the old route;
            ``found``; ``status``, how it ended, :class:`~climb_ompl.climb.status.ClimbStatus`; its one-step,
            transition and path calls, stances explored).  :meth:`figures` adds the
            answering search's counters.
    """

    found: bool
    plan: Plan | None
    resumed_at: int
    backed_off: bool
    climb: ClimbResult
    used: str = ""
    stats: dict[str, Any] = field(default_factory=dict)

    def figures(self) -> dict[str, Any]:
        """The answering search's counters (``climb.stats``) with the re-plan's own figures over them."""
        return {**self.climb.stats, **self.stats}


def uses_holds(step: Step) -> set[str]:
    """The holds a step relies on: those of its stance, and the one it grabs."""
    return {h for _, h in step.stance} | ({step.hold} if step.action == "grab" else set())


def relies(plan: Plan, i: int, touched: frozenset[str]) -> bool:
    """Whether step ``i`` relies on a changed hold: its stance holds one or it grabs one (:func:`uses_holds`),
    or it follows the release of one (its motion starts with that hand still resting where the hold was)."""
    before = plan.steps[i - 1] if i > 0 else None
    return bool(uses_holds(plan.steps[i]) & touched) or (
        before is not None and before.action == "release" and before.hold in touched)


def state_relies(plan: Plan, k: int, touched: frozenset[str]) -> bool:
    """Whether the state before step ``k`` (after ``k`` executed steps) relies on a changed hold: a hand on one,
    or resting where one was after letting go of it (the last step executed released it)."""
    return bool(relied_holds(plan, k, touched))


def state_stance(plan: Plan, k: int) -> dict[str, str]:
    """The stance of the state before step ``k`` (after ``k`` executed steps)."""
    return dict(plan.start_stance) if k == 0 else dict(plan.steps[k].stance) if k < len(plan.steps) else \
        dict(plan.steps[-1].stance_after)


def relied_holds(plan: Plan, k: int, touched: frozenset[str]) -> set[str]:
    """The changed holds the state before step ``k`` relies on (:func:`state_relies`)."""
    before = plan.steps[k - 1] if k > 0 else None
    out = set(state_stance(plan, k).values()) & touched
    if before is not None and before.action == "release" and before.hold in touched:
        out.add(before.hold)
    return out


def resume_point(plan: Plan, at_step: int, touched: frozenset[str]) -> int:
    """How many executed steps a re-plan keeps: ``at_step``, or fewer when the state reached relies on a changed
    hold (:func:`state_relies`): then the last state before it that does not.  Executed steps that used a
    changed hold earlier are history and are kept (they verify on the terrain before the change)."""
    k = at_step
    while k > 0 and state_relies(plan, k, touched):
        k -= 1
    return k


def state_before(plan: Plan, k: int) -> tuple[dict[str, str], np.ndarray]:
    """Stance and configuration before step ``k`` (the plan's start for ``k = 0``)."""
    if k == 0:
        return state_stance(plan, 0), np.asarray(plan.query["start"]["q"], dtype=float)
    return state_stance(plan, k), np.asarray(plan.steps[k].waypoints[0], dtype=float)


def rejoin_index(plan: Plan, k: int, touched: frozenset[str]) -> int:
    """The first step from which the old route relies on no changed hold (:func:`relies`; at least ``k + 1``),
    or the number of steps when its last step still does (the route cannot be rejoined)."""
    r0 = len(plan.steps)
    while r0 > k + 1 and not relies(plan, r0 - 1, touched):
        r0 -= 1
    return r0


def kept_route(plan: Plan, k: int, end: int, change: TerrainChange) -> tuple[tuple[str, str, str], ...] | None:
    """The old route's grabs and releases from step ``k`` to step ``end`` (excluded) as ``(action, limb,
    hold)``, when the change removed none of their holds (moved holds and holds with a new friction keep their
    ids: the same route on the changed terrain); ``None`` otherwise."""
    steps = plan.steps[k:end]
    if any(uses_holds(s) & set(change.remove) for s in steps):
        return None
    return tuple((s.action, s.limb, s.hold) for s in steps)


def check_at_step(plan: Plan, at_step: Any) -> int:
    """``at_step`` as an int when it is a point of ``plan`` to re-plan from (0 to the number of steps - 1).

    Raises:
        QueryError: not a whole number, or out of range.
    """
    n = len(plan.steps)
    if isinstance(at_step, bool) or not isinstance(at_step, numbers.Integral):
        raise QueryError(f"at_step: expected a whole number of executed steps, got {at_step!r}")
    if n == 0:
        raise QueryError("at_step: the plan has no steps (its start already meets its goal): nothing to re-plan")
    if not 0 <= int(at_step) < n:
        raise QueryError(f"at_step: {at_step} steps executed is not a point to re-plan from: give 0 to {n - 1} "
                         f"(after all {n} steps the climb is over)")
    return int(at_step)


def replan(plan: Plan | str | Path, at_step: int, change: TerrainChange, *, warm: StanceGraphSearch | None = None,
           seed: int | None = None, robot: Any = None, fallback: bool = True, progress: Any = None,
           rejoin: bool | None = None, **overrides: Any) -> ReplanResult:
    """Plan from the state reached after ``at_step`` executed steps to the plan's goal on the changed terrain.

    Args:
        plan: the plan being executed (or its file).
        at_step: how many of its steps were executed (``0 <= at_step < len(plan.steps)``).
        change: what changed on the terrain.
        warm: the first search (``plan_climb(..., keep_search=True).search``) to re-use; default: the plan's
            own route only (see the module docstring).
        seed: seed of the new search (default: the plan's).
        robot: the robot model (default: rebuilt from the plan).
        fallback: when the warm search ends with the stance graph exhausted, search from scratch with the time left.
        progress: called with the searches' progress dicts (as :func:`climb_ompl.climb.multistep.plan_climb`).
        rejoin: search first for a way back onto the old route (fast, but the new steps are then a detour plus the
            rest of the old route, often longer than a new route); ``False``: the warm search to the plan's goal
            only (the new steps as short as a search from scratch finds).  Default (``None``): rejoin only when
            the change removed no hold (a hold moved or slippery keeps its route, :func:`kept_route`).
        **overrides: settings to change for the new search (e.g. ``time_limit``).

    Returns:
        A :class:`ReplanResult`; ``found`` is false, with ``climb.status`` and ``climb.reason``, when no new plan
        was found.

    Raises:
        PlanFileError: an unreadable plan file.  QueryError: ``at_step`` out of range, or a bad change.
    """
    from climb_ompl.climb.warm import WarmStart
    from climb_ompl.plan.file import robot_from_plan
    from climb_ompl.settings import ClimbSettings

    if not isinstance(plan, Plan):
        plan = Plan.load(plan)
    at_step = check_at_step(plan, at_step)
    terrain = change.apply(plan.embedded_terrain())
    robot = robot if robot is not None else robot_from_plan(plan)
    settings = ClimbSettings.from_plan(plan.settings, source=f"{plan.source}: $.settings")
    if overrides:
        settings = settings.replace(**overrides)
    seed = plan.seed if seed is None else int(seed)
    k = resume_point(plan, at_step, change.touched)
    stance, q = state_before(plan, k)
    if set(stance.values()) & change.touched:
        return ReplanResult(False, None, k, k < at_step, ClimbResult(False, reason="every state of the plan up to "
                            "that step relies on a changed hold (the start stance does)", status=ClimbStatus.NO_START))
    t0 = time.perf_counter()
    route = tuple(s for i, s in enumerate(plan.steps[k:], start=k) if not relies(plan, i, change.touched))
    r0 = rejoin_index(plan, k, change.touched)
    kept = kept_route(plan, k, r0, change)
    joins = tuple((s.stance, s.waypoints[0]) for s in plan.steps[r0:])  # where the old route goes on
    kept_qs = () if kept is None else (tuple(np.asarray(s.waypoints[-1], dtype=float) for s in plan.steps[k:r0]),)
    warm_start = WarmStart(warm, change.touched, route, () if kept is None else (kept,), kept_qs, joins)
    # rejoining the old route gets a share of the budget (WARM_SHARE); the warm search to the plan's goal what
    # is left; a search from scratch only if that one ends with the stance graph exhausted (it knows more
    # than a search from scratch, but inherits lowered edge probabilities that may have misled it)
    share = settings.replace(time_limit=max(1.0, WARM_SHARE * settings.time_limit))
    stats: dict[str, Any] = {"searches": []}
    query = _Query(plan, robot, terrain, stance, q, seed, progress, stats["searches"])
    if rejoin is None:
        rejoin = kept is not None
    res, steps = (_rejoin(query, k, r0, share, dataclasses.replace(warm_start, max_stances=rejoin_limit(plan)))
                  if rejoin else (None, None))
    if res is None or steps is None:  # no rejoining the old route: the plan's own goal, warm
        if res is not None and res.search is not None:  # with what the rejoining search learned too
            warm_start = WarmStart(res.search, change.touched, route)
        left = max(1.0, settings.time_limit - (time.perf_counter() - t0))
        res, steps = query.to_goal("goal", settings.replace(time_limit=left), warm_start)
    stats["warm_s"] = time.perf_counter() - t0
    used = "warm"
    left = settings.time_limit - stats["warm_s"]
    if steps is None and fallback and res.status == ClimbStatus.EXHAUSTED and left > 1.0:
        t1 = time.perf_counter()
        res, steps = query.to_goal("scratch", settings.replace(time_limit=left), None)
        stats["scratch_s"] = time.perf_counter() - t1
        used = "scratch"
    out = ReplanResult(False, None, k, k < at_step, res, used, stats)
    if steps is None or res.plan is None:
        return out
    out.found, out.plan = True, splice(plan, k, steps, res.plan, at_step, change, settings.to_dict())
    stats["steps"] = len(steps)
    return out


@dataclass
class _Query:
    """What every search of one re-plan shares: the old plan, the robot on the changed terrain, the state it
    re-plans from (stance and configuration), the seed, the progress callback and the record of its searches
    (``ReplanResult.stats["searches"]``)."""

    plan: Plan
    robot: Any
    terrain: Terrain
    stance: dict[str, str]
    q: np.ndarray
    seed: int
    progress: Any
    searches: list[dict[str, Any]]

    def to_goal(self, kind: str, settings: Any, warm: Any) -> tuple[ClimbResult, list[Step] | None]:
        """A search to the plan's own goal (``kind``: ``goal`` warm, or ``scratch``), recorded; its result and new
        steps (``None`` when it found no plan)."""
        from climb_ompl.climb.multistep import plan_climb

        t1 = time.perf_counter()
        res = plan_climb(self.robot, self.terrain, self.stance, self.plan.query["goal"], settings, seed=self.seed,
                         q_start=self.q, warm=warm, progress=self.progress)
        self.searches.append(_record(kind, res, time.perf_counter() - t1))
        return res, list(res.plan.steps) if res.found and res.plan is not None else None


def _record(kind: str, res: Any, seconds: float, **extra: float) -> dict[str, Any]:
    """One entry of ``ReplanResult.stats["searches"]``."""
    keys = ("onestep_calls", "transition_calls", "path_calls", "stances_explored")
    return {"search": kind, "s": seconds, **extra, "found": bool(res.found), "status": res.status,
            **{x: res.stats.get(x) for x in keys}}


def _rejoin(query: _Query, k: int, r0: int, settings: Any, warm: WarmStart) -> tuple[ClimbResult | None,
                                                                                       list[Step] | None]:
    """Plan from the state before step ``k`` to a stance of the old route from step ``r0`` on (whose steps rely on
    no changed hold, :func:`rejoin_index`), then join that step's start configuration within its stance: the
    last search's result (``None`` when none ran) and the new steps up to the end of the old plan, or ``None``.
    Each search is recorded in ``query.searches``."""
    from climb_ompl.climb.goal import Goal
    from climb_ompl.climb.multistep import plan_climb

    plan, n = query.plan, len(query.plan.steps)
    if r0 >= n:
        return None, None
    targets = list(dict.fromkeys(plan.steps[r].stance for r in range(r0, n)))
    t0 = time.perf_counter()
    res = None
    for _ in range(JOIN_ATTEMPTS):
        left = settings.time_limit - (time.perf_counter() - t0)
        if left < 1.0 or not targets:
            return res, None
        t1 = time.perf_counter()
        res = plan_climb(query.robot, query.terrain, query.stance, Goal("stances", stances=tuple(targets)), settings,
                         seed=query.seed, q_start=query.q, warm=warm, keep_search=True, progress=query.progress,
                         time_limit=left)
        t2 = time.perf_counter()
        if not res.found or res.plan is None or res.search is None:
            query.searches.append(_record("rejoin", res, t2 - t1))
            return res, None
        new = list(res.plan.steps)
        q_end = np.asarray(new[-1].waypoints[-1] if new else query.q, dtype=float)
        r, path = _join(plan, r0, res.search, tuple(sorted(res.plan.final_stance)), q_end)
        query.searches.append(_record("rejoin", res, t2 - t1, join_s=time.perf_counter() - t2))
        if path is not None:
            break
        # no way from where the detour arrives to where the old route goes on: rejoin elsewhere, re-using
        # everything this attempt learned
        targets.remove(plan.steps[r].stance)
        warm = dataclasses.replace(warm, search=res.search, hints=(), hint_configs=())
    else:
        return res, None
    return res, new + [_joined_step(query, plan.steps[r], res.search, path, settings)] + list(plan.steps[r + 1:])


def _join(plan: Plan, r0: int, search: StanceGraphSearch, end: tuple[tuple[str, str], ...],
          q_end: np.ndarray) -> tuple[int, list[np.ndarray] | None]:
    """The old step (from ``r0`` on) a detour arriving at stance ``end`` in configuration ``q_end`` joins: the first
    of that stance in the component arrived at, else the first of that stance; and a path in the stance from
    ``q_end`` to that step's start (``None`` when none is found)."""
    from climb_ompl.manifold.stance import Stance

    sigma, n = Stance(dict(end)), len(plan.steps)
    here = search.components.signature(sigma, q_end)
    r = next((i for i in range(r0, n) if plan.steps[i].stance == end and search.components.signature(
        sigma, np.asarray(plan.steps[i].waypoints[0], dtype=float)) == here),
        next(i for i in range(r0, n) if plan.steps[i].stance == end))
    return r, search.graph.connect(sigma, q_end, np.asarray(plan.steps[r].waypoints[0], dtype=float), None)


def _joined_step(query: _Query, old: Step, search: StanceGraphSearch, path: list[np.ndarray],
                 settings: Any) -> Step:
    """The old step ``old`` with ``path`` (from where the detour arrived to the step's start) before its motion,
    its timing (:mod:`climb_ompl.trajectory`), contact forces and margin computed again."""
    from climb_ompl.climb.assembly import force_samples
    from climb_ompl.manifold.stance import Stance
    from climb_ompl.trajectory.retime import step_fields, time_step

    robot, sigma = query.robot, Stance(dict(old.stance))
    wps = [np.asarray(x, dtype=float) for x in path] + [np.asarray(w, dtype=float) for w in old.waypoints[1:]]
    region = search.feas.region(sigma) if robot.equilibrium else None
    forces = force_samples(robot, query.terrain, sigma, wps, settings.force_every, region)
    timed = time_step(robot, np.array(wps), [f.torques for f in forces], float(settings.dynamic_fraction))
    return dataclasses.replace(old, waypoints=tuple(tuple(float(x) for x in w) for w in wps), **step_fields(timed),
                               forces=tuple(forces), margin=float(min((f.margin for f in forces), default=0.0)))


def splice(old: Plan, k: int, steps: list[Step], made: Plan, at_step: int, change: TerrainChange,
           settings: dict[str, Any] | None = None) -> Plan:
    """The old plan's first ``k`` steps, then ``steps``, with the event recorded (robot, terrain and versions
    from ``made``, the plan of the new search; ``settings``: those the re-plan was asked for, default
    ``made``'s, which for a rejoining search carry its share of the budget)."""
    steps = list(old.steps[:k]) + [dataclasses.replace(s, index=k + i) for i, s in enumerate(steps)]
    event = change_event(old.terrain, change, at_step, k)
    totals = {**made.totals, "steps": len(steps), "execution_s": float(sum(s.duration for s in steps)),
              "waypoints": int(sum(len(s.waypoints) for s in steps)),
              "grabs": sum(1 for s in steps if s.action == "grab"),
              "releases": sum(1 for s in steps if s.action == "release")}
    return dataclasses.replace(made, query=old.query, steps=tuple(steps), totals=totals,
                               events=(*old.events, event), settings=made.settings if settings is None else settings)


__all__ = ["TerrainChange", "ReplanResult", "kept_route", "relies", "replan", "rejoin_index", "resume_point", "splice",
           "state_relies", "terrain_before", "check_at_step",
           "state_before", "uses_holds", "well_formed_before"]
