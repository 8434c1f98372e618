"""``climb-ompl slope plan``: MRWALLSPECT III's transition gait between two planes (Kim, Kang & Choi)."""

from __future__ import annotations

from pathlib import Path

import typer

from climb_ompl._options import error
from climb_ompl.cli._app import app
from climb_ompl.settings import SEED_MAX

slope_app = typer.Typer(help="MRWALLSPECT III slope-transition gait (Kim, Kang & Choi).", no_args_is_help=True)
app.add_typer(slope_app, name="slope")


@slope_app.command("plan")
def plan(
    angle: float = typer.Option(..., "--angle", help="Slope angle between the two planes, degrees, in (0, 180)."),
    kind: str = typer.Option(..., "--kind", help="concave (uphill, floor to wall) or convex (downhill, over an edge)."),
    out: Path = typer.Option(..., "--out", help="Plan file (JSON, written atomically)."),
    seed: int = typer.Option(0, "--seed", min=0, max=SEED_MAX,
                             help="Recorded in the plan (the gait planner is deterministic)."),
    tilt: float = typer.Option(0.0, "--tilt", help="First plane's tilt from a floor, degrees (90: a wall, so a "
                                                   "90-degree concave transition is wall to ceiling)."),
    d: float = typer.Option(None, "--d", help="Marginal distance d, m (default: searched; Kim, Kang & Choi, "
                                               "Eq. 10, 22)."),
    robot: str = typer.Option("mrwallspect3", "--robot", help="Robot spec (bundled name or YAML path)."),
    figure: Path = typer.Option(None, "--figure", help="Also draw a side view (PNG) of the gait."),
) -> None:
    """Plan a transition gait; exit 0 found, 1 infeasible (with the failed check and where), 2 bad input."""
    from climb_ompl._io import atomic_write_json
    from climb_ompl.errors import ARGUMENT, InputError
    from climb_ompl.mrwallspect.slope import plan_slope

    try:
        res = plan_slope(angle, kind, seed=seed, tilt_deg=tilt, d=d, robot=robot)
    except InputError as exc:  # an argument of plan_slope: named by its option here
        if exc.path != ARGUMENT or exc.field not in ("angle", "kind", "d", "tilt"):
            raise
        raise error(f"--{exc.field}: {exc.reason}") from None
    if not res.found:
        error(f"infeasible: {kind} {angle:g} deg: {res.reason}", code=1)
        # SystemExit, not typer.Exit: cli.main() drops the code of a typer.Exit under standalone_mode=False.
        raise SystemExit(1)
    atomic_write_json(out, res.plan, allow_nan=False)
    if figure is not None:
        from climb_ompl.mrwallspect.plot import side_view

        side_view([res.plan], figure)
    st = res.stats
    eq = res.checks.get("equilibrium", {})
    margin = f", min equilibrium margin {eq['min_margin'] * 1000:.0f} mm" if eq.get("min_margin") is not None else ""
    typer.echo(f"wrote {out}: {kind} {angle:g} deg, d = {st['d']:.3f} m, R = {st['R']:.3f} m, {st['steps']} body "
               f"steps, {st['frames']} frames, {st['duration_s']:.1f} s of motion, min clearance "
               f"{res.checks['collision']['value'] * 1000:.1f} mm{margin}; planned in {st['total_time_s']:.2f} s")
