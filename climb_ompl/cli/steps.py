"""``climb-ompl steps PLAN``: a climb plan's steps as a table (or JSON), to choose a re-plan's ``--at-step`` and
``--remove-hold`` without reading the plan file by hand.

Each row is one step (:class:`~climb_ompl.plan.file.Step`): its index, action (grab or release), limb and hold, the
hold's height (metres along minus gravity, on the terrain the step was planned on: a re-planned plan's kept steps on
the terrain before its change, :func:`climb_ompl.plan.events.terrain_eras`), its equilibrium margin (metres: how far
the centre of mass stays inside the support region over the step, the smallest over its force samples), its
duration at the joint speed limits (seconds) and the holds the robot hangs from during its motion.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import typer

from climb_ompl.cli._app import app


def step_rows(plan: Any) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """The rows of ``plan``'s steps (a :class:`~climb_ompl.plan.file.Plan`) and its re-plan events, as JSON-able
    dicts: per step ``index``, ``action``, ``limb``, ``hold``, ``height`` (m), ``margin`` (m, ``None`` when not
    recorded), ``duration`` (s) and ``holds`` (the stance during its motion, ``{limb: hold}``); per event ``at_step``,
    ``resumed_at_step`` and its ``change``."""
    from climb_ompl.plan.events import terrain_eras

    eras = terrain_eras(plan)
    rows = []
    for s in plan.steps:
        terrain = eras.of_step(s.index)
        height = terrain.height(s.hold) if s.hold in terrain.hold_ids else None
        rows.append({"index": s.index, "action": s.action, "limb": s.limb, "hold": s.hold,
                     "height": None if height is None else round(float(height), 6),
                     "margin": None if not math.isfinite(s.margin) else round(float(s.margin), 6),
                     "duration": round(float(s.duration), 6), "holds": dict(s.stance)})
    events = [{"at_step": e.get("at_step"), "resumed_at_step": e.get("resumed_at_step"), "change": e.get("change")}
              for e in plan.events if isinstance(e, dict) and e.get("type") == "replan"]
    return rows, events


def _change_text(change: Any) -> str:
    """A re-plan's recorded change in words: ``removed g6_3; moved h4; friction of h9``."""
    if not isinstance(change, dict):
        return "a change"
    parts = [f"{what} {', '.join(map(str, ids))}" for what, ids in
             (("removed", change.get("remove") or ()), ("moved", change.get("move") or {}),
              ("friction changed of", change.get("friction") or {}),
              ("added", [h.get("id") for h in change.get("add") or () if isinstance(h, dict)])) if ids]
    return "; ".join(parts) or "no change"


def _num(x: float | None, fmt: str) -> str:
    return "-" if x is None else format(x, fmt)


@app.command("steps")
def steps_cmd(
    plan_file: Path = typer.Argument(..., help="Climb plan file (JSON)."),
    as_json: bool = typer.Option(False, "--json", help="Print JSON ({steps: [...], events: [...]}) instead."),
) -> None:
    """List a climb plan's steps: index, action, limb, hold, the hold's height (m), the equilibrium margin (m: how
    far the centre of mass stays inside the support region during the step), duration (s) and the holds the step
    hangs from; a re-plan's change is shown where its new steps begin. Use it to choose `replan --at-step N
    --remove-hold ID`."""
    from rich.console import Console
    from rich.table import Table

    from climb_ompl.plan.file import Plan

    plan = Plan.load(plan_file)
    rows, events = step_rows(plan)
    if as_json:
        typer.echo(json.dumps({"plan": str(plan_file), "steps": rows, "events": events}, indent=1))
        return
    table = Table(title=f"{plan_file}: {len(rows)} steps, {plan.robot.get('name')} on {plan.terrain.get('name')}")
    for name, justify in (("step", "right"), ("action", "left"), ("limb", "left"), ("hold", "left"),
                          ("height m", "right"), ("margin m", "right"), ("duration s", "right"),
                          ("hangs from", "left")):
        table.add_column(name, justify=justify)  # type: ignore[arg-type]
    resumed = {e["resumed_at_step"]: e for e in events}
    for r in rows:
        if r["index"] in resumed:
            e = resumed[r["index"]]
            table.add_section()
            table.add_row("", "re-plan", "", "", "", "", "",
                          f"after {e['at_step']} steps executed: {_change_text(e['change'])}")
        table.add_row(str(r["index"]), r["action"], r["limb"], r["hold"], _num(r["height"], ".3f"),
                      _num(r["margin"], ".3f"), _num(r["duration"], ".2f"),
                      " ".join(f"{k}:{v}" for k, v in sorted(r["holds"].items())))
    Console(width=max(120, Console().width)).print(table)


__all__ = ["step_rows", "steps_cmd"]
