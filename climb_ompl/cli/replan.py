"""``climb-ompl replan``: re-plan a climb from the step reached when the terrain changed (a hold failed).

Exit codes as ``climb-ompl plan``: 0 a new plan was found and written, 1 no plan (the reason is printed),
2 bad input (an unknown hold, a step past the end, a malformed value), with no output file left behind.
"""

from __future__ import annotations

import re
import time
from pathlib import Path
from typing import Any

import typer

from climb_ompl._options import check_out, check_positive, error
from climb_ompl.cli._app import app, refuse_friction
from climb_ompl.cli.plan import (
    _guard_note,
    _older_file_note,
    _print_hint,
    _print_table,
    _with_progress,
    parse_settings,
    plan_seed,
    plan_settings,
)
from climb_ompl.climb.goal import Goal, height_report
from climb_ompl.plan.file import Plan
from climb_ompl.settings import SEED_MAX, as_planned


def _pairs(items: list[str], what: str, parse: type) -> dict[str, object]:
    out: dict[str, object] = {}
    for item in items:
        if item.count("=") != 1 or not item.split("=")[0].strip():
            raise error(f"{what}: expected ID=VALUE, got {item!r}")
        k, v = (x.strip() for x in item.split("="))
        if k in out:
            raise error(f"{what} {k}: given twice")
        try:
            out[k] = parse(v)
        except ValueError:
            raise error(f"{what} {k}: cannot read {v!r}") from None
    return out


def _xyz(text: str) -> tuple[float, ...]:
    return tuple(float(x) for x in text.split(","))


@app.command("replan")
def replan_cmd(
    plan_file: Path = typer.Argument(..., help="The plan being executed (JSON plan file)."),
    at_step: int = typer.Option(..., "--at-step", help="Steps executed when the terrain changed (0 = none)."),
    out: Path = typer.Option(..., "--out", help="New plan file (JSON, written atomically)."),
    remove_hold: list[str] = typer.Option([], "--remove-hold", help="A hold that is gone (repeatable)."),
    move_hold: list[str] = typer.Option([], "--move-hold", help="ID=X,Y,Z: a hold elsewhere (repeatable)."),
    friction: list[str] = typer.Option([], "--friction", help="ID=MU: a hold's new friction (repeatable)."),
    add_holds: Path = typer.Option(None, "--add-holds", help="YAML file of new holds, in the terrain file's format "
                                   "(a list of holds, or a mapping with 'holds': id, position, normal, friction; "
                                   "and optionally a default 'friction'), in that file's coordinates."),
    seed: int = typer.Option(None, "--seed", min=0, max=SEED_MAX, help="Seed of the new search \\[the plan's]."),
    time_limit: float = typer.Option(None, "--time-limit", help="Budget of the new search, s \\[the plan's]."),
    set_: list[str] = typer.Option([], "--set", help="KEY=VALUE: another climb setting of the new search "
                                   "(repeatable; as for plan) \\[the plan's]."),
    rejoin: bool = typer.Option(None, "--rejoin/--no-rejoin", help="Search first for a way back onto the old "
                                "route (faster; the new steps may be longer than a new route's) \\[only when no "
                                "hold was removed]."),
    check: bool = typer.Option(False, "--check", help="Verify the plan file before re-planning even when its "
                               "steps_sha256 says it is as climb-ompl wrote it (a file edited since, or without "
                               "one, is always verified: about a second per three steps)."),
) -> None:
    """Plan from the state reached after --at-step steps to the plan's goal on the changed terrain.

    The new plan keeps the executed steps (or, when the state reached relies on a changed hold, backs off to the
    last state before it that does not, and says so), records the event, and passes ``climb-ompl verify``: the
    kept steps on the terrain before the change, the new ones on the changed terrain.  The search re-uses the
    old plan's route where the change leaves it valid.  The plan file's steps are kept or copied, so a file
    edited since climb-ompl wrote it (its steps_sha256 no longer matches) is verified first, and refused if it
    fails.
    """
    from rich.console import Console

    from climb_ompl.climb.replan import replan
    from climb_ompl.errors import QueryError

    check_out(out)
    change = _change(remove_hold, move_hold, friction, add_holds)
    if time_limit is not None:
        check_positive(time_limit, "--time-limit", "seconds")
        if time_limit < 1.0:  # replan gives each of its searches at least 1 s (replan.WARM_SHARE)
            raise error(f"--time-limit: {time_limit:g} s is too short: a re-plan gives each of its searches (rejoin "
                        "the old route, then the goal) at least 1 s; give 1 s or more")
    plan = Plan.load(plan_file)
    changed = _changed_terrain(plan, at_step, change, add_holds)
    console = Console(stderr=True)
    over = {} if time_limit is None else {"time_limit": time_limit}
    given = parse_settings(set_)
    if "time_limit" in given and over:
        raise error("--set time_limit: given by its own option too")
    over.update(given)
    plan_settings(plan, plan_file, over, given)
    if check or not plan.unchanged:  # re-planning keeps or copies the plan's steps: they must hold
        _verify_first(plan, plan_file, check)
    t0 = time.perf_counter()
    try:
        res = _with_progress(console, replan, plan, at_step, change, seed=plan_seed(plan, plan_file, seed),
                             rejoin=rejoin, **over)
    except QueryError as exc:
        raise error(_option_names(str(exc))) from None
    figures = res.figures()
    if res.found and res.plan is not None:  # the table's steps and execution time: the whole new plan's
        figures["steps"] = f"{res.resumed_at} kept + {len(res.plan.steps) - res.resumed_at} new"
        figures["execution_s"] = res.plan.execution_s
    if res.used:  # none ran when the start stance itself holds a changed hold
        _print_table(console, res.found, figures, f"replan of {plan_file} at step {at_step}", t0)
        _height_line(plan, res, changed)
        if res.backed_off:
            _backed_off_line(plan, res, at_step, change)
    _guard_note(figures, {**plan.settings, **over})
    if not res.found or res.plan is None:
        stop = error(f"no plan: {res.climb.reason}", 1)
        _print_hint(res.climb.status, {**as_planned(plan.settings), **over}, climb_option=False,
                    diagnosis=res.climb.diagnosis)
        _older_file_note(out)
        raise stop
    path = res.plan.save(out)
    new = len(res.plan.steps) - res.resumed_at
    tail = _copied_tail(plan, res.plan, res.resumed_at)
    typer.echo(f"replan: kept {res.resumed_at} step{'' if res.resumed_at == 1 else 's'}, {new} new"
               + (f" (the last {tail} of them the old plan's motions, kept on the changed terrain)" if tail else "")
               + f" -> {path} "
               f"({res.used} search, {res.stats.get('warm_s', 0.0) + res.stats.get('scratch_s', 0.0):.1f} s)")


def _change(remove_hold: list[str], move_hold: list[str], friction: list[str], add_holds: Path | None) -> Any:
    """The :class:`~climb_ompl.plan.events.TerrainChange` the options give (exit 2 for a hold removed twice or a
    malformed value)."""
    from climb_ompl.plan.events import TerrainChange

    twice = sorted({h for h in remove_hold if remove_hold.count(h) > 1})
    if twice:
        raise error(f"--remove-hold {twice[0]}: given twice")
    return TerrainChange(remove=tuple(remove_hold), move=_pairs(move_hold, "--move-hold", _xyz),  # type: ignore[arg-type]
                         friction=_pairs(friction, "--friction", float),  # type: ignore[arg-type]
                         add=_new_holds(add_holds) if add_holds is not None else ())


def _changed_terrain(plan: Plan, at_step: int, change: Any, add_holds: Path | None) -> Any:
    """The plan's terrain with ``change`` applied, once ``at_step`` is checked; its convention notes printed.

    Raises:
        typer.Exit: exit 2 naming the option of a change the terrain refuses, or ``--at-step`` out of range.
    """
    from climb_ompl.climb.replan import check_at_step
    from climb_ompl.errors import QueryError, TerrainError

    before = plan.embedded_terrain()
    try:
        changed = change.apply(before)
    except QueryError as exc:
        raise error(_option_names(str(exc), add_holds)) from None
    except TerrainError as exc:  # a new hold the terrain's own checks refuse (a zero normal, a bad field)
        if add_holds is None:
            raise error(str(exc)) from None
        # the changed terrain's holds[N] is the file's holds[N - (holds kept)]
        kept = len(before.holds) - len(change.remove)
        where = re.sub(r"^.*?: holds\[(\d+)\]", lambda m_: f"holds[{int(m_.group(1)) - kept}]", str(exc), count=1)
        raise error(f"--add-holds {add_holds}: {where}") from None
    try:
        check_at_step(plan, at_step)
    except QueryError as exc:
        raise error(_option_names(str(exc))) from None
    refuse_friction(changed, "the changed terrain")
    for note in changed.convention_notes():
        typer.echo(f"note: the changed terrain: {note}", err=True)
    return changed


def _verify_first(plan: Plan, plan_file: Path, check: bool) -> None:
    """Verify the plan file before re-planning (its steps are kept or copied): exit 2 when it fails, else say so
    (``check``: asked for with ``--check``, else the file was edited or has no ``steps_sha256``)."""
    from climb_ompl.verification.climb import verify

    t_check = time.perf_counter()
    report = verify(plan)
    if not report.ok:
        raise error(f"{plan_file}: the plan fails verify ({report.summary()}; first: {report.violations[0]}): "
                    "re-planning would keep or copy its steps; check it with climb-ompl verify")
    why = "" if check else (" (edited since climb-ompl wrote it)" if plan.written_sha256 else
                            " (a file without steps_sha256)")
    typer.echo(f"checked {plan_file}{why}: {len(plan.steps)} steps valid ({time.perf_counter() - t_check:.1f} s)",
               err=True)


def _height_line(plan: Plan, res: Any, changed: Any) -> None:
    """For a height goal, the heights line as ``plan`` prints it, from the state the new plan starts from."""
    goal = Goal.parse(plan.query["goal"])
    if goal.type == "height":
        from climb_ompl.climb.replan import state_stance
        from climb_ompl.plan.file import robot_from_plan

        typer.echo(height_report(goal, robot_from_plan(plan), changed, state_stance(plan, res.resumed_at),
                                 res.plan.final_stance if res.found and res.plan is not None else None), err=True)


def _backed_off_line(plan: Plan, res: Any, at_step: int, change: Any) -> None:
    """Say that the re-plan backed off from ``at_step`` to the state it resumed at, and which changed holds the state
    reached relied on."""
    from climb_ompl.climb.replan import relied_holds

    gone = ", ".join(sorted(relied_holds(plan, at_step, change.touched),
                            key=lambda h: [int(x) if x.isdigit() else x for x in re.split(r"(\d+)", h)]))
    typer.echo(f"backed off: kept {res.resumed_at} of the {at_step} steps executed; the state after "
               f"{_steps(at_step)} relies on a changed hold ({gone}), so the new plan starts from the state after "
               f"{_steps(res.resumed_at)} (the robot must get back there)" if res.found else
               f"backed off to the state after {_steps(res.resumed_at)} (the state after {_steps(at_step)} relies "
               f"on a changed hold: {gone}), and found no plan from there", err=True)


def _copied_tail(old: Plan, new: Plan, kept: int) -> int:
    """How many of the new plan's new steps (after the ``kept`` ones) are the old plan's last steps, unchanged:
    the old route, rejoined."""
    n = 0
    while n < min(len(old.steps), len(new.steps) - kept) and \
            old.steps[-1 - n].waypoints == new.steps[-1 - n].waypoints:
        n += 1
    return n


def _new_holds(path: Path) -> tuple[dict[str, object], ...]:
    """The holds of an ``--add-holds`` file: a YAML list of holds, or a mapping whose ``holds`` is one (a terrain
    file); each a mapping, checked by the terrain's own rules when the change is applied."""
    from climb_ompl._io import load_yaml
    from climb_ompl.errors import InputError

    try:
        data = load_yaml(path, InputError)
    except InputError as exc:  # unreadable or not YAML: say which option gave the file
        raise error(f"--add-holds {path}: {exc.field}: {exc.reason}") from None
    if isinstance(data, dict):
        extra = sorted(str(k) for k in set(data) - {"holds", "friction", "name", "description"})
        if extra:
            raise error(f"--add-holds {path}: {extra[0]}: unknown field (the file gives holds and a default "
                        "friction; the rest of the terrain, gravity and surfaces included, is the plan's)")
    holds = data.get("holds") if isinstance(data, dict) else data
    if not isinstance(holds, list) or not holds or not all(isinstance(h, dict) for h in holds):
        raise error(f"--add-holds {path}: expected a list of holds (mappings with id, position, normal, friction), "
                    "or a mapping with 'holds'")
    default = data.get("friction") if isinstance(data, dict) else None  # as a terrain file's default friction
    return tuple(h if default is None or "friction" in h else {**h, "friction": default} for h in holds)


def _option_names(message: str, add_holds: Path | None = None) -> str:
    """A change or step error of :func:`climb_ompl.climb.replan.replan` with the options' names for the fields'."""
    if message.startswith("change: empty"):
        return "no change given: --remove-hold, --move-hold, --friction or --add-holds"
    if message.startswith("change: hold(s)") and "both removed and changed" in message:
        return message[len("change: "):].replace("both removed and changed",
                                                 "both removed (--remove-hold) and changed (--move-hold, --friction)")
    for field, option in (("change.remove", "--remove-hold"), ("change.move.", "--move-hold "),
                          ("change.move:", "--move-hold:"), ("change.friction.", "--friction "),
                          ("change.friction:", "--friction:"), ("at_step:", "--at-step:"),
                          ("change.add:", f"--add-holds {add_holds}:")):
        if message.startswith(field):
            return option + message[len(field):]
    return message


def _steps(n: int) -> str:
    """``"1 step"``, ``"3 steps"``."""
    return f"{n} step{'' if n == 1 else 's'}"
