"""Multi-step climbing: :func:`plan_climb`, the entry point of the climbing core (Bretl 2006, sec. 3.3).

The core, one operator of the paper per module:

==========================  ==================================================================
:mod:`climb_ompl.climb.goal`       the goal of a query (a height, a hold for a limb, a stance)
:mod:`climb_ompl.settings`   :class:`ClimbSettings`, every setting of a climb, and the search modes
:mod:`climb_ompl.contract`   what a valid plan is (tolerances, resolution, cone model), shared with verify
:mod:`climb_ompl.manifold.feasibility`  the checks of a stance and of a transition, cached
:mod:`climb_ompl.climb.transition` FIND-TRANSITION (Fig. 17)
:mod:`climb_ompl.climb.local_path` the direct local path between two transitions (lift, move, place)
:mod:`climb_ompl.climb.onestep`    FIND-PATH with any OMPL planner, constrained space and sampler (Fig. 17)
:mod:`climb_ompl.climb.search`     EXPLORE-STANCEGRAPH and EXPLORE-TRANSITIONGRAPH (Fig. 16)
:mod:`climb_ompl.climb.assembly`   the plan of a found climb (timing, forces, embedded robot and terrain)
==========================  ==================================================================

This module poses the query (start stance and configuration, goal, settings, seed), runs the search and
returns a :class:`ClimbResult`; :func:`replay` plans again from a plan file's query and settings.

Budgets: ``time_limit`` (wall clock) for the whole query, ``step_time_limit`` (CPU time) per FIND-PATH call,
and count budgets (``transition_attempts``, ``path_iterations``) that make seeded runs reproducible: the same
seed gives the same plan, byte for byte apart from ``timings``, as long as no time limit was hit.
"""

from __future__ import annotations

import itertools
import math
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from climb_ompl.climb.frontier import CUT_OFF, goal_beyond_reach, goal_beyond_terrain
from climb_ompl.climb.frontier import explain as explain_frontier
from climb_ompl.climb.goal import Goal, robot_reach
from climb_ompl.climb.start import diagnose_stance, find_start, start_configuration
from climb_ompl.climb.status import ClimbStatus
from climb_ompl.errors import QueryError
from climb_ompl.model.reach import pair_reach
from climb_ompl.model.terrain import Terrain
from climb_ompl.plan.file import Plan
from climb_ompl.settings import ClimbSettings

if TYPE_CHECKING:
    from climb_ompl.climb.search import StanceGraphSearch
    from climb_ompl.climb.warm import WarmStart
    from climb_ompl.manifold.stance import Stance

ProgressFn = Callable[[dict[str, Any]], None]

#: Default CPU-time budget of one FIND-PATH call, seconds (:attr:`ClimbSettings.step_time_limit`).
STEP_TIME_LIMIT = ClimbSettings.__dataclass_fields__["step_time_limit"].default


@dataclass
class ClimbResult:
    """Outcome of :func:`plan_climb` ("no plan" is a value, not an exception).

    Attributes:
        found: whether a plan was found.
        plan: the :class:`~climb_ompl.plan.file.Plan` when found, else ``None``.
        stats: ``steps, onestep_calls, transition_calls, path_calls, onestep_median_s, stances_explored,
            candidates, path_failures, total_s, rejections`` (by reason, summed over FIND-PATH calls), ...
            (:meth:`climb_ompl.climb.search.StanceGraphSearch.summary`).
        reason: why there is no plan, in words (budget, exhausted stance graph), with the frontier stances where the
            climb stopped and the checks their steps towards the goal failed (:mod:`climb_ompl.climb.frontier`).
        search: the search and its caches, with ``keep_search=True`` (for :func:`climb_ompl.climb.replan.replan`).
        diagnosis: the frontier stances of :attr:`reason` as dicts (:meth:`FrontierStance.to_dict`).
        status: how the query ended (:class:`~climb_ompl.climb.status.ClimbStatus`; ``FOUND`` when found): what
            callers decide on, :attr:`reason` being the sentence for people.
    """

    found: bool
    plan: Plan | None = None
    stats: dict[str, Any] = field(default_factory=dict)
    reason: str = ""
    search: StanceGraphSearch | None = None
    diagnosis: list[dict[str, Any]] = field(default_factory=list)
    status: ClimbStatus | None = None

    def __post_init__(self) -> None:
        if self.status is None:  # a result that names no status is found, or it must say why it is not
            if not self.found:
                raise ValueError("a ClimbResult without a plan needs its status (ClimbStatus)")
            self.status = ClimbStatus.FOUND


def whole_turn_variants(robot: Any, q: np.ndarray, angles: list[bool]) -> list[np.ndarray]:
    """``q`` with its angle joints (``angles[j]``) shifted by whole turns within the joint bounds.

    The same posture at another point of the bounded joint space (joints whose range spans more than a
    turn, e.g. the double-link robot's +-2 pi).  One joint shifted first, then two, ...; ``q`` excluded.
    """
    from climb_ompl.model.limb_ik import wrap_into

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


def load_robot(robot: Any) -> Any:
    """A :class:`~climb_ompl.model.robot.RobotModel` from a model, a bundled robot name or a spec path."""
    if isinstance(robot, (str, Path)):
        from climb_ompl.model.robot import RobotModel

        return RobotModel.load(robot)
    return robot


def load_terrain(terrain: Any) -> Terrain:
    """A :class:`Terrain` from a terrain (as given), or from a dict in the terrain file format, a bundled name or
    a file path, turned into the wall frame when it does not follow the convention
    (:meth:`~climb_ompl.model.terrain.Terrain.in_wall_frame`)."""
    if isinstance(terrain, Terrain):
        return terrain
    if isinstance(terrain, Mapping):
        return Terrain.from_dict(terrain).in_wall_frame()
    return Terrain.load(terrain).in_wall_frame()


def _frame_hint(terrain: Terrain) -> str:
    """A sentence for a failure on a terrain that departs from the frame convention (a :class:`Terrain` given as
    loaded: names and files are turned by :func:`load_terrain`), else ``""``."""
    from climb_ompl.model.wall_frame import to_wall_frame

    if terrain.frame is not None or terrain.dim != 3:
        return ""
    turned, note = to_wall_frame(terrain)
    if not note:
        return ""
    if turned is terrain:  # box surfaces the turn cannot keep axis-aligned
        return f"; {note}"
    return ("; the terrain departs from the frame convention (the wall the plane y = 0 climbed from +y), which "
            "the robot specs expect: Terrain.in_wall_frame() turns it (docs/terrain.md)")


def check_dimensions(robot: Any, terrain: Terrain) -> None:
    """Refuse a planar robot on a 3-D terrain and a 3-D robot on a 2-D one.

    Raises:
        QueryError: naming the terrain's file and both dimensions.
    """
    want = 2 if robot.planar else 3
    if terrain.dim != want:
        raise QueryError(f"terrain {terrain.source}: dim {terrain.dim}, but robot {robot.name!r} is "
                         f"{'planar (it climbs 2-D terrains)' if robot.planar else '3-D (it climbs 3-D terrains)'}")


def default_start(robot: Any, terrain: Terrain, *, seed: int = 0) -> tuple[dict[str, str], np.ndarray] | None:
    """A start stance among the lowest holds with a feasible start configuration, or ``None``
    (:func:`climb_ompl.climb.start.find_start`, whose result also says why none was found).  ``robot`` and ``terrain``
    may be names or files, as for :func:`plan_climb`."""
    robot, terrain = load_robot(robot), load_terrain(terrain)
    check_dimensions(robot, terrain)
    found = find_start(robot, terrain, seed=seed)
    return (found.stance, found.q) if found.stance is not None and found.q is not None else None


def plan_climb(robot: Any, terrain: Any, start: Any, goal: Any, settings: ClimbSettings | None = None, *,
               seed: int = 0, q_start: Any = None, progress: ProgressFn | None = None,
               warm: WarmStart | None = None, keep_search: bool = False, started: float | None = None,
               **overrides: Any) -> ClimbResult:
    """Plan a multi-step climb (Bretl 2006, sec. 3.3, Fig. 16).

    Args:
        robot: a :class:`~climb_ompl.model.robot.RobotModel`, a bundled robot name or a spec path.
        terrain: a :class:`~climb_ompl.model.terrain.Terrain`, a bundled terrain name or a terrain file path.
        start: the start stance (``{limb: hold}`` or a :class:`~climb_ompl.manifold.stance.Stance`).
        goal: a :class:`Goal`, a height (number), ``"LIMB=HOLD"``, or a target stance mapping.
        settings: every setting of the climb (default: the guided search's, with the robot spec's ``climb``
            section over the library's defaults, :meth:`ClimbSettings.for_search`; given, it is used whole).
        seed: seed of every random choice (the same seed gives the same plan).
        q_start: start configuration; default: :func:`climb_ompl.climb.start.start_configuration` (FIND-TRANSITION on
            the start stance near the nominal pose, else from the posture bringing the CoM nearest the support
            region's centre; and, if the stance graph is exhausted from there, its :func:`whole_turn_variants`
            in turn).
        progress: called with a dict (``phase, elapsed_s, stances_explored, onestep_calls, fraction``) as
            the search advances.
        warm: a :class:`~climb_ompl.climb.warm.WarmStart`: what an earlier search on a since changed terrain
            learned (:func:`climb_ompl.climb.replan.replan`).
        keep_search: return the search (its caches) as ``ClimbResult.search``, for a warm re-plan later.
        started: when the query's budget began before this call (a start search took part of it), that moment on
            :func:`time.perf_counter`'s clock: the climb stops ``settings.time_limit`` seconds after it, and the
            plan file and the reason name that budget (default: now).
        **overrides: settings to change (``planner="RRTConnect"``, ``time_limit=60``, ``search="paper"``
            starts from that mode's settings, ...).

    Returns:
        A :class:`ClimbResult`; ``found`` is false, with ``status`` and ``reason``, when no plan was found.

    Raises:
        QueryError: unknown limb/hold or setting, a start configuration off its stance or infeasible.
        PlannerNotFound: unknown planner, space or sampler name.
    """
    from climb_ompl.climb.search import StanceGraphSearch

    t0 = time.perf_counter() if started is None else float(started)
    robot = load_robot(robot)
    if settings is None:
        settings = ClimbSettings.for_search(overrides.pop("search", "guided"), robot=robot, **overrides)
    elif overrides:
        settings = settings.replace(**overrides)
    terrain = load_terrain(terrain)
    check_dimensions(robot, terrain)
    goal = Goal.parse(goal)
    goal.validate(robot, terrain)
    sigma0 = _start_stance(robot, terrain, goal, start)
    if isinstance(sigma0, ClimbResult):  # answered before any search
        return sigma0

    def search() -> StanceGraphSearch:
        return StanceGraphSearch(robot, terrain, goal, settings, seed=seed, progress=progress, t0=t0)

    sg = search()
    if warm is not None:
        sg.inherit(warm)
    if q_start is None:
        q0 = start_configuration(robot, terrain, sigma0, seed=seed, feas=sg.feas)
        if q0 is None:
            why = diagnose_stance(robot, terrain, sigma0.to_dict(), sg.feas)
            return ClimbResult(False, None, sg.summary(), f"no feasible configuration found for the start stance "
                               f"{sigma0} (FIND-TRANSITION on that stance failed); at the nominal stand-off {why}"
                               + _frame_hint(terrain), status=ClimbStatus.NO_START)
    else:
        q0 = _given_start(robot, terrain, sigma0, q_start, settings, sg)
    outcome = sg.run(sigma0, q0)
    if outcome.status == ClimbStatus.EXHAUSTED and q_start is None:
        sg, outcome, q0 = _whole_turns(robot, sigma0, q0, search, sg, outcome)
    if outcome.chain is None:
        text, frontier = explain_frontier(sg)
        return ClimbResult(False, None, sg.summary(), outcome.reason + _frame_hint(terrain)
                           + ("\n" + text if text else ""), sg if keep_search else None,
                           [f.to_dict() for f in frontier], status=outcome.status)
    from climb_ompl.climb.assembly import assemble_plan

    query = {"start": {"stance": sigma0.to_dict(), "q": [float(x) for x in q0]}, "goal": goal.to_dict()}
    plan = assemble_plan(sg, outcome.chain, outcome.paths, query)
    return ClimbResult(True, plan, {**sg.summary(), "steps": len(plan.steps), "execution_s": plan.execution_s},
                       search=sg if keep_search else None)


def _start_stance(robot: Any, terrain: Terrain, goal: Goal, start: Any) -> Stance | ClimbResult:
    """The start stance, checked, or the result of a query answered before any search: a goal no stance of the
    terrain meets (``INFEASIBLE_GOAL``), or one beyond a gap from the start's holds (``GOAL_UNREACHABLE``).

    Raises:
        QueryError: the start stance names an unknown limb or hold, puts two limbs on one hold, or is empty.
    """
    from climb_ompl.manifold.stance import Stance

    beyond = goal_beyond_terrain(goal, terrain, robot_reach(robot))
    if beyond is not None:
        return ClimbResult(False, None, {}, f"the goal cannot be met on this terrain: {beyond}",
                           status=ClimbStatus.INFEASIBLE_GOAL)
    sigma0 = start if isinstance(start, Stance) else Stance(dict(start))
    sigma0.validate(robot, terrain)
    if len(sigma0) == 0:
        raise QueryError("start stance: at least one limb must be on a hold")
    gap = goal_beyond_reach(goal, terrain, sigma0.to_dict(), pair_reach(robot), robot_reach(robot))
    if gap is not None:
        return ClimbResult(False, None, {}, f"{CUT_OFF}: {gap}", status=ClimbStatus.GOAL_UNREACHABLE)
    return sigma0


def _given_start(robot: Any, terrain: Terrain, sigma0: Stance, q_start: Any, settings: ClimbSettings,
                 sg: StanceGraphSearch) -> np.ndarray:
    """``q_start`` as the start configuration, once checked: ``nq`` finite values, the hands on the stance's holds
    (within ``settings.tolerance``, m) and feasible there.

    Raises:
        QueryError: naming what is wrong.
    """
    from climb_ompl.manifold.stance import StanceConstraint

    q0 = np.asarray(q_start, dtype=float).reshape(-1)
    if q0.shape != (robot.nq,) or not np.all(np.isfinite(q0)):
        raise QueryError(f"q_start: expected {robot.nq} finite values, got shape {q0.shape}")
    err = StanceConstraint(robot, terrain, sigma0, settings.tolerance).error(q0)
    if err > settings.tolerance:
        raise QueryError(f"q_start: a hand is {err:.3g} m from its hold in stance {sigma0}")
    bad = sg.feas.why_moving(sigma0, q0)  # a hand just released may still touch its hold
    if bad is not None:
        raise QueryError(f"q_start is infeasible at stance {sigma0}: fails the {bad} check")
    return q0


def _whole_turns(robot: Any, sigma0: Stance, q0: np.ndarray, search: Callable[[], StanceGraphSearch],
                 sg: StanceGraphSearch, outcome: Any) -> tuple[StanceGraphSearch, Any, np.ndarray]:
    """After the stance graph was exhausted from ``q0``: the start posture's angles a whole turn further, another
    point of bounded joint space from which a winding route may fit (the double-link robot's +-2 pi angles, Bretl
    2006 sec. 2.1), each with a new ``search()`` (one budget for all starts), until one finds a plan or ends
    otherwise than exhausted.  Returns the last search, its outcome and its start configuration."""
    for qv in whole_turn_variants(robot, q0, list(robot.angle_joints)):
        sg = search()
        outcome = sg.run(sigma0, qv)
        if outcome.chain is not None:
            return sg, outcome, qv
        if outcome.status != ClimbStatus.EXHAUSTED:
            break
    return sg, outcome, q0


def replay(plan: Plan | str | Path, *, seed: int | None = None, robot: Any = None, terrain: Any = None,
           progress: ProgressFn | None = None, **overrides: Any) -> ClimbResult:
    """Plan again from a plan file's query, seed and settings (same inputs: the same plan, timings aside).

    The robot and terrain are rebuilt from the plan's embedded copies unless given.  ``seed`` (default: the
    plan's) and ``overrides`` change the query (e.g. a longer ``time_limit`` on a slower machine).

    Raises:
        PlanFileError: an unreadable or invalid plan file.  QueryError: a plan of another kind, or
            settings this version does not know.
    """
    if not isinstance(plan, Plan):
        plan = Plan.load(plan)
    from climb_ompl.plan.file import robot_from_plan

    robot = robot if robot is not None else robot_from_plan(plan)
    terrain = terrain if terrain is not None else plan.embedded_terrain()
    settings = ClimbSettings.from_plan(plan.settings, source=f"{plan.source}: $.settings")
    if overrides:
        settings = settings.replace(**overrides)
    start = plan.query["start"]
    return plan_climb(robot, terrain, start["stance"], plan.query["goal"], settings,
                      seed=plan.seed if seed is None else int(seed),
                      q_start=start.get("q"), progress=progress)


#: Start stances :func:`climb_from_start` climbs from at most: the next one when the stance graph is exhausted from
#: the one before (a start that can let go of a limb may still lead nowhere: Go1 crouched on a compact stance of the
#: suite's overhang was exhausted after 2 stances, a quadruped's start on a 35-65 wall after 10-30).
START_TRIES = 4
#: Seconds a climb from a further start needs at least; less left and the climb ends with the last result.
START_RETRY_MIN_S = 5.0


def climb_from_start(robot: Any, terrain: Terrain, goal: Any, settings: ClimbSettings | None = None, *,
                     climb: float | None = None,
                     seed: int = 0, tries: int = START_TRIES, plan: Callable[..., ClimbResult] | None = None
                     ) -> tuple[ClimbResult | None, Any, list[dict[str, Any]]]:
    """A climb from the start the start finder gives (:func:`climb_ompl.climb.start.find_start`), and from the next one
    when the stance graph is exhausted from it or the goal is out of its reach (``EXHAUSTED`` or
    ``GOAL_UNREACHABLE``, :class:`~climb_ompl.climb.status.ClimbStatus`), up to ``tries`` starts within
    ``settings.time_limit`` in all.

    Args:
        goal: the goal (as :func:`plan_climb`), or ``None`` with ``climb``: metres up the wall's slope above each
            start's highest hold (:func:`climb_ompl.climb.goal.climb_height`).
        settings: the climb's settings (default: the guided search's with the robot's own defaults); their
            ``time_limit`` is the budget of every start and climb together.
        plan: called as :func:`plan_climb` (default); e.g. the command line's, behind a progress bar.

    Returns:
        ``(result, start, tried)``: the last climb's result (``None`` when no start was found), the start it
        climbed from (a :class:`~climb_ompl.climb.start.StartResult`: its diagnoses when none was found), and per start
        tried ``{stance, found, status, stances_explored, reason}`` (``status``: the climb's
        :class:`~climb_ompl.climb.status.ClimbStatus`).  When several were tried, the result's reason says so.
    """
    from climb_ompl.climb.goal import climb_height

    plan = plan_climb if plan is None else plan
    settings = ClimbSettings.for_search("guided", robot=robot) if settings is None else settings
    t0 = time.perf_counter()
    tried: list[dict[str, Any]] = []
    res: ClimbResult | None = None
    start: Any = None
    for _ in range(max(1, int(tries))):
        left = settings.time_limit - (time.perf_counter() - t0)
        if tried and left < START_RETRY_MIN_S:
            break
        found = find_start(robot, terrain, seed=seed, time_limit=left if tried else settings.time_limit,
                           skip=[t["stance"] for t in tried])
        if not found.found:
            if start is None:
                start = found
            break
        start = found
        g = Goal("height", height=climb_height(robot, terrain, found.stance, climb)) if goal is None else goal
        # one budget from t0 for the start finder and every climb (at least a second left for this one)
        started = max(t0, time.perf_counter() + 1.0 - settings.time_limit)
        res = plan(robot, terrain, found.stance, g, settings, seed=seed, q_start=found.q, started=started)
        tried.append({"stance": dict(sorted(found.stance.items())), "found": res.found, "status": res.status,
                      "stances_explored": res.stats.get("stances_explored", 0), "reason": res.reason.split("\n")[0]})
        if res.status not in (ClimbStatus.EXHAUSTED, ClimbStatus.GOAL_UNREACHABLE):
            break
    if res is not None and len(tried) > 1:
        from climb_ompl.manifold.stance import Stance

        earlier = "; ".join(f"{Stance(t['stance'])}" + (" (cut off from the goal)"
                                                        if t["status"] == ClimbStatus.GOAL_UNREACHABLE
                                                        else f" ({t['stances_explored']} stances)") for t in tried[:-1])
        note = (f"(this climb was from start {len(tried)} of the start finder's, {Stance(tried[-1]['stance'])}; the "
                f"stance graph was exhausted, or the goal out of reach, from {earlier})")
        res.stats["starts_tried"] = tried
        if not res.found:
            res.reason = res.reason + "\n" + note
    return res, start, tried


__all__ = ["ClimbResult", "plan_climb", "climb_from_start", "START_TRIES", "replay", "default_start",
           "whole_turn_variants", "check_dimensions", "load_robot", "load_terrain", "STEP_TIME_LIMIT"]
