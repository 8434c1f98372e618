"""``climb-ompl demo``: the bundled default end to end (what the README's ``make demo`` runs).

LEMUR (Bretl et al. (2004)) climbs 2 m up the bundled ``demo-wall``: plan with the stance-graph planner, verify the
plan independently, write ``plan.json`` and the self-contained playback ``climb.html`` (and, with
``--png``, a screenshot of it).
"""

from __future__ import annotations

import time
from pathlib import Path

import typer

from climb_ompl._options import check_positive, error
from climb_ompl.cli._app import app, load_wall
from climb_ompl.cli.plan import plan_with_progress
from climb_ompl.settings import SEED_MAX


@app.command("demo")
def demo(
    out_dir: Path = typer.Option(Path("out"), "--out-dir", help="Folder for plan.json and climb.html."),
    robot: str = typer.Option("lemur", "--robot", help="Robot name or spec file."),
    terrain: str = typer.Option("demo-wall", "--terrain", help="Terrain name or file."),
    height: float = typer.Option(2.0, "--height", help="Goal height, metres above the start stance's highest hold "
                                 "along minus gravity (vertical, also on a slab or a ramp; `plan --climb` measures "
                                 "along the wall's slope): met with every contact hold within one limb reach of it."),
    seed: int = typer.Option(0, "--seed", min=0, max=SEED_MAX, help="Seed: the same seed gives the same plan."),
    time_limit: float = typer.Option(300.0, "--time-limit", help="Total planning budget, s."),
    png: bool = typer.Option(False, "--png", help="Also write a screenshot climb.png (needs chromium)."),
) -> None:
    """Plan LEMUR's 2 m climb on the demo wall, verify it, and write plan.json + climb.html."""
    from rich.console import Console

    from climb_ompl import viz
    from climb_ompl.climb.multistep import check_dimensions
    from climb_ompl.climb.start import find_start
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.verification.climb import verify

    console = Console(stderr=True)
    check_positive(height, "--height", "metres above the start")
    check_positive(time_limit, "--time-limit", "seconds")
    taken = next((p for p in (out_dir, *out_dir.parents) if p.exists()), None)  # the nearest existing ancestor
    if taken is not None and not taken.is_dir():
        raise error(f"--out-dir {out_dir}: {taken} is a file, not a folder")
    model = RobotModel.load(robot)
    wall = load_wall(terrain)
    check_dimensions(model, wall)
    start = find_start(model, wall, seed=seed)
    if start.stance is None or start.q is None:
        console.print(start.explain(model.name, wall.name), style="red", markup=False)
        raise typer.Exit(1)
    stance, q0 = start.stance, start.q
    z0 = max(wall.height(h) for h in stance.values())
    goal = z0 + height
    console.print(f"[bold]{model.name}[/] on [bold]{wall.name}[/]: start stance {dict(sorted(stance.items()))}, "
                  f"goal: every hand at or above {goal:.2f} m minus reach")
    t0 = time.perf_counter()
    result = plan_with_progress(console, model, wall, stance, goal, time_limit=time_limit, seed=seed, q_start=q0)
    if not result.found or result.plan is None:
        console.print(f"[red]no plan within {time_limit:.0f} s[/]: {result.reason}")
        raise typer.Exit(1)
    plan = result.plan
    out_dir.mkdir(parents=True, exist_ok=True)  # only now: a failed run leaves no empty folder behind
    plan_path = plan.save(out_dir / "plan.json")
    s = result.stats
    console.print(f"plan: {s.get('steps')} steps in {time.perf_counter() - t0:.1f} s "
                  f"({s.get('onestep_calls')} one-step calls, median {s.get('onestep_median_s', 0):.3f} s) "
                  f"-> {plan_path}")
    report = verify(plan)
    console.print(f"verify: {report.summary()}")
    html = viz.play(plan.to_dict(), html=out_dir / "climb.html")
    console.print(f"playback: {html} (open it in a browser)")
    if png:
        shot = viz.screenshot(html, out_dir / "climb.png")
        console.print(f"screenshot: {shot}")
    if not report.ok:
        for v in report.violations[:20]:
            console.print(f"  {v}")
        raise typer.Exit(1)
