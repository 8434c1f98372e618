"""``climb-ompl plan`` (multi-step climb query) and ``climb-ompl verify`` (independent check of a plan file).

Exit codes (``climb_ompl.cli``): ``plan``: 0 plan found and written, 1 no plan within the budget (the
reason is printed), 2 bad input; ``verify``: 0 valid, 1 violations (listed), 2 unreadable or
schema-invalid file (the message names the JSON path).
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import typer

from climb_ompl._options import check_out, check_positive, error
from climb_ompl.cli._app import app, load_wall, parse_pairs
from climb_ompl.climb.goal import (
    LEVEL,
    climb_height,
    goal_band_note,
    goal_statement,
    height_report,
    robot_reach,
    threshold_text,
    wall_slope,
)
from climb_ompl.climb.multistep import STEP_TIME_LIMIT
from climb_ompl.climb.status import ClimbStatus
from climb_ompl.settings import SEED_MAX, ClimbSettings, as_planned

#: The defaults shown in ``--help``: the settings' own (the dataclass's class attributes), not copies.
_D = ClimbSettings


def parse_settings(items: list[str]) -> dict[str, Any]:
    """``--set KEY=VALUE`` items as climb settings (:class:`~climb_ompl.settings.ClimbSettings`): each value read
    as YAML (``200``, ``0.15``, ``true``, ``null``, ``RRTConnect``).  The values are checked where the settings
    are built (:func:`settings_error` names the option).

    Raises:
        typer.Exit: a malformed item, an unknown setting, or one given twice.
    """
    import yaml

    from climb_ompl._io import loads_yaml, number_hint
    from climb_ompl.settings import NOT_GIVEN, unknown_setting

    out: dict[str, Any] = {}
    for item in items:
        key, eq, text = item.partition("=")
        key = key.strip()
        if not eq or not key or not text.strip():
            raise error(f"--set: expected KEY=VALUE, got {item!r}")
        if key in NOT_GIVEN:
            raise error(f"--set {key}: not a setting to give here (search: --search; tolerance: recorded, not a "
                        "choice)")
        unknown = unknown_setting(key)
        if unknown:
            raise error(f"--set {key}: {unknown}")
        if key in out:
            raise error(f"--set {key}: given twice")
        try:
            out[key] = loads_yaml(text)
            if isinstance(out[key], str) and number_hint(out[key]):
                out[key] = float(out[key])  # 1e-2: a number, which YAML 1.1 reads as text
        except yaml.YAMLError:
            out[key] = text.strip()
    return out


#: The setting named by :class:`~climb_ompl.errors.PlannerNotFound`'s ``kind``.
SETTING_OF_KIND = {"planner": "planner", "constrained space": "space", "sampler": "sampler"}

#: The settings ``plan`` and ``replan`` take as options of their own (the others come through ``--set``).
OPTION_OF = {"time_limit": "--time-limit", "step_time_limit": "--step-time-limit", "search": "--search",
             "heuristic_weight": "--heuristic-weight"}


def settings_error(exc: Exception, given: dict[str, Any]) -> Exception:
    """A settings error (``settings.<name>: reason``) re-worded to name ``--set <name>`` when that setting came
    from ``--set``; other errors unchanged."""
    from climb_ompl.errors import PlannerNotFound, QueryError
    from climb_ompl.settings import setting_error

    if isinstance(exc, QueryError):
        key, reason = setting_error(exc)
        if key in given:
            return error(f"--set {key}: {reason}")
        if key in OPTION_OF:  # given by its own option
            return error(f"{OPTION_OF[key]}: {reason}")
    if isinstance(exc, PlannerNotFound):  # --planner, --space, --sampler, or the same through --set
        key = SETTING_OF_KIND.get(exc.kind)
        if key is not None:
            return error(f"{'--set ' if key in given else '--'}{key}: {exc}")
    return exc


def plan_settings(plan: Any, path: Any, changes: dict[str, Any], given: dict[str, Any]) -> Any:
    """The settings of the plan file ``path`` with ``changes`` applied (from options such as ``--time-limit`` and
    from ``--set``, those in ``given``).

    Raises:
        typer.Exit: exit 2, naming the plan file and ``$.settings.<name>`` for a bad setting in the file, or the
            option for a bad one given.
    """
    from climb_ompl.errors import PlannerNotFound, QueryError
    from climb_ompl.settings import ClimbSettings, setting_error

    try:
        base = ClimbSettings.from_plan(plan.settings, source=f"{path}: $.settings")
    except QueryError as exc:
        key, reason = setting_error(exc)
        raise error(f"{path}: $.settings.{key}: {reason}" if key else str(exc)) from None
    except PlannerNotFound as exc:
        raise error(f"{path}: $.settings.{SETTING_OF_KIND.get(exc.kind, exc.kind)}: {exc}") from None
    try:
        return base.replace(**changes)
    except Exception as exc:
        raise settings_error(exc, given) from None


def _goal_hold(text: str) -> Any:
    """The goal of ``--goal-hold LIMB=HOLD`` (one limb on one hold)."""
    from climb_ompl.climb.goal import Goal

    pairs = parse_pairs(text, "--goal-hold")
    if len(pairs) != 1:
        raise error(f"--goal-hold: one LIMB=HOLD (a limb on a hold), got {len(pairs)} pairs: {text!r}")
    (limb, hold), = pairs.items()
    return Goal("hold", limb=limb, hold=hold)


def plan_seed(plan: Any, path: Any, seed: int | None) -> int:
    """The seed a re-run of the plan file ``path`` uses: ``seed`` if given, else the file's, which must be in
    0..``SEED_MAX`` (files written before the bound was checked may hold another).

    Raises:
        typer.Exit: exit 2 naming ``$.seed``.
    """
    if seed is not None:
        return seed
    if not 0 <= int(plan.seed) <= SEED_MAX:
        raise error(f"{path}: $.seed: {plan.seed} is not a seed (0 to {SEED_MAX}); give one with --seed")
    return int(plan.seed)


#: The settings that make the search try harder, as ``--set`` would give them, each with what it does (the
#: hints after a search that ended without a plan leave out those already in use).
EFFORT: tuple[tuple[str, Any, str], ...] = (
    ("transition_wide", 200, "draws about the nominal posture on the holds"),
    ("grab_reach", 0, "grabs beyond 1.5 limb reaches too"),
    ("reexpand", 6, "failed edges tried again more often"),
    ("transition_walk", 100, "the base walked towards the support region"),
)

#: The two orders of a stance's releases (``release_lookahead``), each as the hints describe it: neither is more
#: effort, and a climb one order misses the other may find (docs/robots.md), so the hints offer the one not in use.
RELEASE_ORDER: dict[bool, str] = {True: "a release ranked by the grab it makes possible",
                                  False: "a stance's releases tried in limb order"}


def hint(status: ClimbStatus, settings: dict[str, Any], climb_option: bool = True, at_start: bool = False,
         diagnosis: list[dict[str, Any]] | None = None) -> str | None:
    """The ``hint:`` line after a search that ended without a plan (``status``), or ``None``: after an exhausted
    stance graph the effort settings (:data:`EFFORT`; those already at the suggested value in ``settings``, the ones
    used, are left out), after a spent budget a larger one; both times the other order of the releases
    (:data:`RELEASE_ORDER`) where the search has a height heuristic, through which alone the order acts.  ``at_start``:
    the stance nearest the goal was the start itself (no step got the robot nearer): another start first.
    ``diagnosis``: the frontier's (:func:`climb_ompl.climb.frontier.diagnose_frontier`); when its every failed step is a
    grab the ``grab_reach`` prefilter left out, more time would not help and the hint says so."""
    from climb_ompl.climb.frontier import only_beyond_grab_reach
    from climb_ompl.settings import ClimbSettings

    if diagnosis and only_beyond_grab_reach(diagnosis) and settings.get("grab_reach") != 0:
        reach = settings.get("grab_reach", ClimbSettings.grab_reach)
        return ("hint: every step towards the goal listed from the stances nearest it is a grab beyond "
                f"{reach:g} limb reaches from where the robot stood, which the search does not propose (the "
                "grab_reach setting): more time alone may not get past them. --set grab_reach=0 proposes them too "
                "(slower; they rarely succeed); if the holds are that far apart, the gap may be more than the robot "
                "can cross.")

    other = not settings.get("release_lookahead", ClimbSettings.release_lookahead)
    # (the look-ahead acts through the height heuristic: without one, both orders are the same search)
    order = f"--set release_lookahead={str(other).lower()}: {RELEASE_ORDER[other]}" \
        if settings.get("heuristic_weight", ClimbSettings.heuristic_weight) else None
    if status == ClimbStatus.EXHAUSTED:
        more = [f"--set {k}={str(v).lower()}: {what}" for k, v, what in EFFORT if settings.get(k) != v]
        tries = ([f"more effort ({'; '.join(more)}; docs/climb.md)"] if more else []) \
            + ([f"the other order of the releases ({order})"] if order else [])
        return ("hint: the search samples, so an exhausted stance graph is not a proof. "
                + ("No step got the robot nearer the goal than its start stance: try another start (--start "
                   "LIMB=HOLD,...; `climb-ompl plan --help`). " if at_start else "")
                + (f"Try {', or '.join(tries)}, with a larger --time-limit; or another --seed." if tries else
                   "A larger --time-limit, or another --seed."))
    if status == ClimbStatus.BUDGET:
        return ("hint: the budget ran out before the goal: a larger --time-limit"
                + (f", or the other order of the releases ({order})" if order else "")
                + ("; a shorter climb (--climb M) shows how far the robot gets" if climb_option else "")
                + ". docs/climb.md lists the other settings.")
    return None


@app.command("plan")
def plan_cmd(
    out: Path = typer.Option(..., "--out", help="Plan file to write (JSON, written atomically)."),
    robot: str = typer.Option(None, "--robot", help="Robot name (bundled) or spec file."),
    terrain: str = typer.Option(None, "--terrain", help="Terrain name (bundled) or terrain file."),
    start: str = typer.Option(None, "--start", help="Start stance LIMB=HOLD,... (default: near the bottom)."),
    goal_height: float = typer.Option(None, "--goal-height", help="Goal: every contact hold >= H - reach (m)."),
    goal_hold: str = typer.Option(None, "--goal-hold", help="Goal: LIMB=HOLD."),
    climb: float = typer.Option(None, "--climb", help="Goal: every contact hold at least M metres up the wall's "
                                "slope above the start stance's highest hold (along the slope: on a ramp 20 degrees "
                                "from level, a metre is 0.34 m of height)."),
    climb_height_: float = typer.Option(None, "--climb-height", help="Goal: every contact hold at least H metres of "
                                        "height (along minus gravity) above the start stance's highest hold."),
    replay: Path = typer.Option(None, "--replay", help="Plan again from this plan file's query, seed and "
                                "settings (robot and terrain embedded in it); other options override."),
    search: str = typer.Option(None, "--search", help="guided (default) | paper (Bretl 2006, Fig. 16 as "
                               "published)."),
    planner: str = typer.Option(None, "--planner", help=f"OMPL planner of FIND-PATH [{_D.planner}]."),
    space: str = typer.Option(None, "--space", help=f"projected | atlas | tangent_bundle \\[{_D.space}]."),
    sampler: str = typer.Option(None, "--sampler", help=f"FIND-PATH sampler name(s), a+b \\[{_D.sampler}]."),
    time_limit: float = typer.Option(None, "--time-limit",
                                     help="Wall-clock budget of the climb search, s; the start finder tries no "
                                     "new candidate after as long, and the plan's assembly (or, with no plan, the "
                                     f"diagnosis) comes on top (a few seconds) [{_D.time_limit:g}]."),
    seed: int = typer.Option(None, "--seed", min=0, max=SEED_MAX, help="Seed: the same seed gives the same plan [0]."),
    step_time_limit: float = typer.Option(None, "--step-time-limit", help=f"Budget of one FIND-PATH call, s "
                                          f"[{STEP_TIME_LIMIT:g}]."),
    heuristic_weight: float = typer.Option(None, "--heuristic-weight",
                                           help="A* weight of the height/goal heuristic (1 = plain A*) "
                                           f"[{_D.heuristic_weight:g}]."),
    set_: list[str] = typer.Option([], "--set", help="KEY=VALUE: any other climb setting, e.g. "
                                   "transition_wide=200 or release_lookahead=false (repeatable; the names: "
                                   "docs/climb.md, or an unknown one lists them)."),
) -> None:
    """Plan a multi-step climb and write the plan file (exit 1 when no plan is found)."""
    from rich.console import Console

    overrides, given = _option_settings(planner, space, sampler, time_limit, step_time_limit, heuristic_weight,
                                        set_)
    check_out(out)
    console = Console(stderr=True)
    if replay is not None:
        if any(x is not None for x in (robot, terrain, start, goal_height, goal_hold, climb, climb_height_)):
            raise error("--replay takes the robot, terrain, start and goal from the plan file: drop "
                        "--robot/--terrain/--start/--goal-*/--climb/--climb-height")
        result, used, start_stance = _replay(console, replay, seed, search, overrides, given)
    else:
        result, used, start_stance = _plan_query(console, _Query(robot, terrain, start, goal_height, goal_hold,
                                                                 climb, search, seed, climb_height_), overrides, given)
    _guard_note(result.stats, used)
    if not result.found or result.plan is None:
        stop = error(f"no plan: {result.reason}", 1)
        first = result.diagnosis[0]["stance"] if result.diagnosis else None
        _print_hint(result.status, used, at_start=first is not None and dict(first) == dict(start_stance),
                    diagnosis=result.diagnosis)
        _older_file_note(out)
        raise stop
    path = result.plan.save(out)
    typer.echo(f"plan: {len(result.plan.steps)} steps -> {path}")


@dataclass(frozen=True)
class _Query:
    """The query options of ``plan`` (without ``--replay``), as given (``None``: not given)."""

    robot: str | None
    terrain: str | None
    start: str | None
    goal_height: float | None
    goal_hold: str | None
    climb: float | None
    search: str | None
    seed: int | None
    climb_height: float | None = None  # ``--climb-height``: metres of height, turned into ``climb`` on the wall


def _option_settings(planner: str | None, space: str | None, sampler: str | None, time_limit: float | None,
                     step_time_limit: float | None, heuristic_weight: float | None,
                     set_: list[str]) -> tuple[dict[str, Any], dict[str, Any]]:
    """The settings given on the command line: by their own options and by ``--set`` (all of them, and those of
    ``--set``).

    Raises:
        typer.Exit: exit 2 for a value out of range, a malformed ``--set``, or a setting given both ways.
    """
    overrides = {k: v for k, v in (("planner", planner), ("space", space), ("sampler", sampler),
                                   ("time_limit", time_limit), ("step_time_limit", step_time_limit),
                                   ("heuristic_weight", heuristic_weight)) if v is not None}
    for key in ("time_limit", "step_time_limit", "heuristic_weight"):
        if key in overrides:
            check_positive(overrides[key], OPTION_OF[key])
    given = parse_settings(set_)  # checked where the settings are built (settings_error names the option)
    both = sorted(set(given) & set(overrides))
    if both:
        raise error(f"--set {both[0]}: given by its own option too")
    overrides.update(given)
    return overrides, given


def _replay(console: Any, replay: Path, seed: int | None, search: str | None, overrides: dict[str, Any],
            given: dict[str, Any]) -> tuple[Any, dict[str, Any], dict[str, str]]:
    """``plan --replay``: plan again from the plan file's query, seed and settings, ``overrides`` over them; the
    result (its table printed), the settings it ran with and its start stance."""
    from climb_ompl.climb.multistep import replay as replay_plan
    from climb_ompl.plan.file import Plan

    old = Plan.load(replay)
    extra: dict[str, Any] = {"seed": plan_seed(old, replay, seed)}
    if search is not None:  # that mode's settings, with the plan's robot's own defaults (as ``plan``)
        from climb_ompl.plan.file import robot_from_plan

        extra["robot"] = robot_from_plan(old)  # built once, for the settings and the replay
        try:
            overrides = {**ClimbSettings.for_search(search, robot=extra["robot"]).to_dict(), **overrides}
        except Exception as exc:
            raise settings_error(exc, given) from None
    else:  # checked before the replay starts
        plan_settings(old, replay, overrides, given)
    used = {**as_planned(old.settings), **overrides}  # (what the replay ran with)
    t0 = time.perf_counter()
    result = _with_progress(console, replay_plan, old, **overrides, **extra)
    _print_table(console, result.found, result.stats, f"{old.robot['name']} on {old.terrain['name']} (replay of "
                 f"{replay})", t0)
    return result, used, old.query["start"]["stance"]


def _check_query(q: _Query) -> None:
    """Refuse a query without a robot and terrain, without exactly one goal, or with a goal that is not a
    finite, positive number of metres (exit 2)."""
    if q.robot is None or q.terrain is None:
        raise error("give --robot and --terrain (or --replay PLAN.json)")
    if sum(x is not None for x in (q.goal_height, q.goal_hold, q.climb, q.climb_height)) != 1:
        raise error("give exactly one goal: --goal-height H, --climb M, --climb-height H or --goal-hold LIMB=HOLD")
    if q.climb is not None:
        check_positive(q.climb, "--climb", "metres")
    if q.climb_height is not None:
        check_positive(q.climb_height, "--climb-height", "metres")
    if q.goal_height is not None and not math.isfinite(q.goal_height):
        raise error(f"--goal-height: must be a finite number of metres, got {q.goal_height}")


def _plan_query(console: Any, q: _Query, overrides: dict[str, Any],
                given: dict[str, Any]) -> tuple[Any, dict[str, Any], dict[str, str]]:
    """``plan`` with a robot, a terrain and a goal: the result (its table and heights printed), the settings it ran
    with and the start stance it climbed from."""
    from climb_ompl.climb.goal import Goal
    from climb_ompl.climb.multistep import check_dimensions
    from climb_ompl.errors import QueryError
    from climb_ompl.model.robot import RobotModel

    _check_query(q)
    model = RobotModel.load(q.robot)
    from climb_ompl.cli.robot import srdf_notes

    for note in srdf_notes(model):  # (robot check's other notes are about the posture and limits it reports)
        typer.echo(f"note: {note}", err=True)
    try:
        settings = ClimbSettings.for_search(q.search or "guided", robot=model, **overrides)
    except Exception as exc:
        raise settings_error(exc, given) from None
    seed = 0 if q.seed is None else q.seed
    goal = None if q.climb is not None or q.climb_height is not None else \
        Goal("height", height=q.goal_height) if q.goal_height is not None else \
        _goal_hold(q.goal_hold)  # type: ignore[arg-type]
    wall = load_wall(q.terrain)
    check_dimensions(model, wall)
    if q.climb_height is not None:  # metres of height as metres along the slope (level ground: refused as --climb)
        q = replace(q, climb=q.climb_height / max(wall_slope(wall), 0.5 * LEVEL))
    if goal is not None:
        try:
            goal.validate(model, wall)
        except QueryError as exc:
            raise error(f"--goal-hold: {str(exc).removeprefix('goal: ')}") from None
    _slow_note(model, wall)
    t0 = time.perf_counter()
    if q.start is None:
        result, stance, goal = _climb_from_found_start(console, q, model, wall, goal, settings, seed)
    else:
        result, stance, goal = _climb_from_given_start(console, q, model, wall, goal, settings, seed)
    _print_table(console, result.found, result.stats, f"{model.name} on {wall.name}, goal: "
                 f"{threshold_text(goal, model)}", t0)
    if goal.type == "height":
        typer.echo(height_report(goal, model, wall, stance, result.plan.final_stance
                                 if result.found and result.plan is not None else None, climb=_along(q)), err=True)
    return result, settings.to_dict(), stance


def _slow_note(model: Any, wall: Any) -> None:
    """Say before the wait when the start finder will probe limbs' reach numerically first (tens of seconds)."""
    from climb_ompl.cache import note as cache_note
    from climb_ompl.model.reach import maps_kept, probed_numerically

    slow = probed_numerically(model)
    if slow and not maps_kept(model, wall):  # tens of seconds before the first step: say so before the wait
        typer.echo(f"note: limb(s) {', '.join(slow)} have no closed-form inverse kinematics: the start finder "
                   "probes their reach numerically first (5-25 s per limb on a 2-core machine; "
                   f"{cache_note()} for the next run on a wall of this orientation)", err=True)


def _climb_from_found_start(console: Any, q: _Query, model: Any, wall: Any, goal: Any, settings: Any,
                            seed: int) -> tuple[Any, dict[str, str], Any]:
    """The climb from the start finder's start, and its next ones when the stance graph is exhausted from it
    (:func:`climb_ompl.climb.multistep.climb_from_start`): the result, the start stance and the goal (``--climb``:
    the height above that start).

    Raises:
        typer.Exit: exit 1 when no start is found, with the start finder's advice and diagnosis.
    """
    from climb_ompl.climb.goal import Goal
    from climb_ompl.climb.multistep import climb_from_start

    noted: set[str] = set()

    def run(robot: Any, terrain_: Any, stance_: Any, goal_: Any, *args: Any, **kwargs: Any) -> Any:
        _check_not_met(goal_, robot, terrain_, stance_, noted)
        _state_goal(goal_, robot, terrain_, stance_, _along(q), noted)
        return plan_with_progress(console, robot, terrain_, stance_, goal_, *args, **kwargs)

    # the start finder's start, and its next ones when the stance graph is exhausted from it
    result, found, _ = climb_from_start(model, wall, goal, settings, climb=q.climb, seed=seed, plan=run)
    if result is None:
        from climb_ompl.climb.start import facing_away

        advice, why = found.advice(model), found.explain(model.name, wall.name)
        flip = wall.gravity_note()
        if flip:  # a gravity written with the wrong sign is the cause of every failure listed: say it first
            advice = f"{q.terrain}: {flip}; a climb on it may be possible once gravity is right\n{advice}"
        # a posture facing away from the wall is the cause of every failure listed: say it first
        raise error(f"{advice}\n{why}" if facing_away(model) or flip else f"{why}\n{advice}", 1)
    stance = found.stance
    if goal is None:
        goal = Goal("height", height=climb_height(model, wall, stance, q.climb))  # type: ignore[arg-type]
    return result, stance, goal


def _climb_from_given_start(console: Any, q: _Query, model: Any, wall: Any, goal: Any, settings: Any,
                            seed: int) -> tuple[Any, dict[str, str], Any]:
    """The climb from ``--start``: the result, the start stance and the goal (``--climb``: the height above it).

    Raises:
        typer.Exit: exit 2 for a start stance naming unknown limbs or holds, or one that already meets the goal.
    """
    from climb_ompl.climb.goal import Goal
    from climb_ompl.errors import QueryError
    from climb_ompl.manifold.stance import Stance

    stance = parse_pairs(q.start, "--start")  # type: ignore[arg-type]
    try:
        Stance(stance).validate(model, wall)
    except QueryError as exc:
        raise error(f"--start: {exc}") from None
    if goal is None:
        goal = Goal("height", height=climb_height(model, wall, stance, q.climb))  # type: ignore[arg-type]
    _check_not_met(goal, model, wall, stance)
    _state_goal(goal, model, wall, stance, _along(q))
    # plan_climb finds the start posture itself, reports "no plan" when the stance has none, and may try
    # its whole-turn variants if the stance graph is exhausted from it
    return plan_with_progress(console, model, wall, stance, goal, settings, seed=seed), stance, goal


def _along(q: _Query) -> float | None:
    """The ``--climb`` given (metres along the wall's slope), ``None`` for any other goal (``--climb-height``
    included, though the query carries it as a climb along the slope too)."""
    return q.climb if q.climb_height is None else None


def _state_goal(goal: Any, robot: Any, terrain: Any, stance: dict[str, str], climb: float | None,
                noted: set[str] | None = None) -> None:
    """Say the goal the search will pursue before it starts (:func:`~climb_ompl.climb.goal.goal_statement`), once per
    text in ``noted`` (a climb from several starts may pursue the same one again)."""
    text = goal_statement(goal, robot, terrain, stance, climb)
    if noted is None or text not in noted:
        if noted is not None:
            noted.add(text)
        typer.echo(text, err=True)


def _guard_note(stats: dict[str, Any], settings: dict[str, Any]) -> None:
    """Say on stderr when FIND-PATH calls stopped on a time guard (their CPU time, or the climb's budget left)
    before their validity-check budget: then the route, and so the plan, depends on the machine's speed and load
    (the same seed may give another plan elsewhere, or beside other jobs)."""
    n = int(stats.get("path_timeouts", 0) or 0)
    if n:
        typer.echo(f"note: {n} FIND-PATH call(s) stopped on a time guard (the CPU-time step_time_limit "
                   f"{settings.get('step_time_limit')} s, or the climb's budget left) before their "
                   f"{settings.get('path_iterations')} validity checks: the result depends on the machine's speed "
                   "and load; larger guards (--step-time-limit, --time-limit) make the seed alone decide it.",
                   err=True)


def _older_file_note(out: Path) -> None:
    """After a search with no plan: say when ``out`` is a file from before, left as it was (nothing was written, and
    a plan file of that name is not this query's answer)."""
    if out.exists():
        typer.echo(f"note: nothing written; {out} is an older file, left as it was", err=True)


def _print_hint(status: ClimbStatus, settings: dict[str, Any], climb_option: bool = True, at_start: bool = False,
                diagnosis: list[dict[str, Any]] | None = None) -> None:
    """Print :func:`hint` on stderr, if any (``climb_option``: the command has ``--climb``; ``at_start`` and
    ``diagnosis``: see :func:`hint`)."""
    line = hint(status, settings, climb_option, at_start, diagnosis)
    if line:
        typer.echo(line, err=True)


def _check_not_met(goal: Any, robot: Any, terrain: Any, stance: dict[str, str], noted: set[str] | None = None) -> None:
    """Refuse a height goal the start stance already meets (the answer would be a plan of no steps); note one whose
    holds may not host every limb (:func:`~climb_ompl.climb.goal.goal_band_note`), before the search, once per text in
    ``noted`` (a climb from several starts may meet the same one again).

    Raises:
        typer.Exit: exit 2, the heights in the message.
    """
    if goal.type == "height" and goal.met(stance, terrain, robot_reach(robot)):
        above = min(terrain.height(h) for h in stance.values()) + robot_reach(robot)
        raise error(f"--goal-height {goal.height:g}: the start stance {stance} already meets it; "
                    f"{height_report(goal, robot, terrain, stance)}. Ask for a goal above {above:.3f} m, or a climb "
                    "of M metres above the start with --climb M")
    narrow = goal_band_note(goal, robot, terrain, stance)
    if narrow and (noted is None or narrow not in noted):  # before the wait (the heights line repeats it after)
        if noted is not None:
            noted.add(narrow)
        typer.echo(f"note: {narrow}; planning anyway", err=True)


def _print_table(console: Any, found: bool, s: dict[str, Any], title: str, t0: float) -> None:
    """A search's figures ``s`` (``ClimbResult.stats``; ``found``: whether it found a plan) as a table on
    ``console``, with the seconds since ``t0`` (:func:`time.perf_counter`)."""
    from rich.table import Table

    table = Table(title=title, min_width=len(title) + 4)  # the title on one line (it wrapped mid-phrase)
    table.add_column("quantity")
    table.add_column("value", justify="right")
    rows = [("result", "found" if found else "no plan"), ("steps", str(s.get("steps", 0))),
            ("planning time (s)", f"{time.perf_counter() - t0:.1f}"),
            ("climb duration, timed within the joint limits (s)", f"{s.get('execution_s', 0.0):.1f}"),
            ("one-step calls", str(s.get("onestep_calls", 0))),
            ("FIND-PATH calls (stopped by a time guard)", f"{s.get('path_calls', 0)} ({s.get('path_timeouts', 0)})"),
            ("stances explored", str(s.get("stances_explored", 0))),
            ("candidate sequences", str(s.get("candidates", 0)))]
    if s.get("shortcut_steps"):
        rows.append(("steps cut by shortcuts", str(s["shortcut_steps"])))
    rows += [(f"rejections: {k}", str(v)) for k, v in sorted(s.get("rejections", {}).items())]
    for row in rows:
        table.add_row(*row)
    console.print(table)


def plan_with_progress(console: Any, *args: Any, **kwargs: Any) -> Any:
    """:func:`climb_ompl.climb.multistep.plan_climb` behind a rich progress bar on ``console`` (stderr)."""
    from climb_ompl.climb.multistep import plan_climb

    return _with_progress(console, plan_climb, *args, **kwargs)


def _with_progress(console: Any, fn: Any, *args: Any, **kwargs: Any) -> Any:
    """``fn(*args, progress=..., **kwargs)`` behind a rich progress bar on ``console`` (stderr)."""
    from rich.progress import BarColumn, Progress, TextColumn, TimeElapsedColumn

    with Progress(TextColumn("{task.description}"), BarColumn(), TextColumn("{task.fields[info]}"),
                  TimeElapsedColumn(), console=console, transient=True,
                  disable=not console.is_terminal) as bar:  # (off a terminal it left a blank line per bar)
        task = bar.add_task("planning", total=1.0, info="")

        def progress(info: dict) -> None:
            bar.update(task, completed=float(info.get("fraction", 0.0)),
                       info=f"{info.get('stances_explored', 0)} stances, {info.get('onestep_calls', 0)} one-step calls")

        return fn(*args, progress=progress, **kwargs)


@app.command("verify")
def verify_cmd(
    plan_file: Path = typer.Argument(..., help="Plan file (JSON) to check."),
    max_listed: int = typer.Option(50, "--max-listed", min=0, help="List at most this many violations."),
    terrain: str = typer.Option(None, "--terrain",
                                help="Also require the plan to be for this terrain (name or file)."),
    robot: str = typer.Option(None, "--robot",
                              help="Also require the plan to be for this robot (bundled name or spec file): "
                                   "the spec and URDF it embeds must be this robot's."),
) -> None:
    """Re-check a plan independently of the planner: exit 0 valid, 1 violations, 2 unreadable/invalid file.

    The checks use the robot and terrain the plan embeds.  With ``--terrain``, a plan made for another terrain
    (different content hash) is bad input (exit 2); with ``--robot``, so is a plan whose embedded robot spec or
    URDF is not that robot's.
    """
    from climb_ompl.errors import PlanFileError
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.plan.file import Plan, read_plan_dict
    from climb_ompl.verification import verify_plan_dict
    from climb_ompl.verification.climb import verify_dict

    d = read_plan_dict(plan_file)
    if d["kind"] != "climb":  # TreeBot and slope-transition plans (climb_ompl.verification.tree, verify_slope)
        if terrain is not None or robot is not None:
            raise PlanFileError(plan_file, "$.kind", f"--{'terrain' if terrain is not None else 'robot'} applies "
                                f"to climb plans, not to a {d['kind']!r} plan")
        _print_verdict(plan_file, verify_plan_dict(d, str(plan_file)), max_listed)
        return
    plan = Plan._from_valid(d, str(plan_file))
    if terrain is not None:
        t = Terrain.load(terrain)
        digest = t.content_hash()
        if digest != plan.terrain.get("sha256") and t.frame is None and t.dim == 3:
            digest = _in_plan_frame(t, plan.terrain.get("data")) or digest
        if digest != plan.terrain.get("sha256"):
            before = [e for e in plan.events if e.get("terrain_sha256_before") == digest]
            raise PlanFileError(plan_file, "$.terrain.sha256",
                                f"the plan is for terrain {plan.terrain.get('name')!r}, not for {t.source} "
                                f"({t.name!r}): content hashes differ"
                                + (f"; {t.source} is the terrain before the plan's re-plan at step "
                                   f"{before[0].get('at_step')} (the plan is for the changed terrain it embeds)"
                                   if before else ""))
    if robot is not None:
        _require_robot(plan_file, plan, robot)
    _print_verdict(plan_file, verify_dict(d, str(plan_file), validated=True), max_listed)  # the file as stored


def _require_robot(plan_file: Path, plan: Any, name_or_path: str) -> None:
    """Raise :class:`PlanFileError` unless the robot spec and URDF the plan embeds are those of ``name_or_path``
    (a bundled robot or a spec file), naming the spec's fields that differ."""
    from climb_ompl.errors import PlanFileError
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.plan.file import robot_record, sha256_json, sha256_text

    r = RobotModel.load(name_or_path)
    mine = robot_record(r)
    emb = plan.robot if isinstance(plan.robot, dict) else {}
    diffs = []
    if mine["spec_sha256"] != emb.get("spec_sha256") or sha256_json(emb.get("spec")) != emb.get("spec_sha256"):
        spec, theirs = mine["spec"], emb.get("spec") if isinstance(emb.get("spec"), dict) else {}
        fields = sorted(k for k in set(spec) | set(theirs) if spec.get(k) != theirs.get(k))
        diffs.append(f"spec ({', '.join(fields) or 'its digest'})")
    if mine["urdf_sha256"] != emb.get("urdf_sha256") or sha256_text(emb.get("urdf") or "") != emb.get("urdf_sha256"):
        diffs.append("URDF")
    if diffs:
        raise PlanFileError(plan_file, "$.robot", f"the plan's robot {emb.get('name')!r} is not {name_or_path} "
                            f"({r.name!r}): its {' and '.join(diffs)} {'differ' if len(diffs) > 1 else 'differs'}")


def _print_verdict(plan_file: Path, report: Any, max_listed: int) -> None:
    """Print a verify report: one line when valid, else the summary and the violations (then exit 1)."""
    if report.ok:
        typer.echo(f"{plan_file}: {report.summary()}")
        return
    typer.echo(f"{plan_file}: {report.summary()}", err=True)
    for v in report.violations[:max_listed]:
        typer.echo(f"  {v}", err=True)
    raise typer.Exit(1)


def _in_plan_frame(terrain: Any, data: Any) -> str | None:
    """The content hash of ``terrain`` (a user's file) moved by the frame recorded in a plan's terrain ``data``
    (the plan embeds the file turned into the wall frame, :mod:`climb_ompl.model.wall_frame`), or ``None`` when the
    plan records none (or one that cannot apply)."""

    from climb_ompl.errors import ClimbError
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.model.wall_frame import frame_of

    if not isinstance(data, dict) or not isinstance(data.get("frame"), dict):
        return None
    try:
        return terrain.moved(*frame_of(Terrain.from_dict(data))).content_hash()
    except (ClimbError, ValueError):  # a malformed frame, or boxes it cannot turn
        return None
