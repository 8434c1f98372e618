"""``climb-ompl robots`` and the ``climb-ompl robot`` group (``robot check``; ``robot show`` lives in viz)."""

from __future__ import annotations

from typing import Any

import typer

from . import app

robot_app = typer.Typer(help="Robot models: check a spec, show a robot.", no_args_is_help=True)
app.add_typer(robot_app, name="robot")


@app.command("robots")
def robots() -> None:
    """List the bundled robots with their number of configuration parameters and their limbs."""
    from ..errors import RobotModelError
    from ..robot import RobotModel, bundled_robots

    for name in bundled_robots():
        try:
            r = RobotModel.load(name)
        except RobotModelError as exc:  # e.g. a third-party robot whose package is not installed
            typer.echo(f"{name:14s} unavailable: {exc.reason}")
            continue
        limbs = ", ".join(f"{lb.name}({len(lb.joint_indices)})" for lb in r.limbs)
        typer.echo(f"{name:14s} nq {r.nq:2d}  mass {r.mass:5.2f} kg  {'planar' if r.planar else '3-D   '}  "
                   f"limbs: {limbs}")


@robot_app.command("check")
def check(spec: str = typer.Argument(..., help="Robot spec file or bundled robot name.")) -> None:
    """Load a robot spec and its URDF; exit 0 if valid, 2 with the file, field and reason if not.

    A valid spec also gets its limbs' reaches, and a note when its nominal posture collides with itself."""
    from ..robot import RobotModel

    r = RobotModel.load(spec)
    typer.echo(f"{r.spec_path}: ok: robot {r.name!r}, nq {r.nq}, mass {r.mass:.3f} kg, "
               f"limbs {', '.join(lb.name + ' (' + lb.ik + ' IK' + _contact(lb) + ')' for lb in r.limbs)}"
               + (f"; climb defaults {', '.join(f'{k}={v}' for k, v in r.climb.items())}" if r.climb else ""))
    typer.echo("reach (first joint to hand, m): " + ", ".join(f"{lb.name} {lb.reach:.3f}" for lb in r.limbs))
    pairs = sorted({f"{a} with {b}" for a, b in r.collisions(r.nominal_q)})
    if pairs:  # a warning, not an error: the planner never uses the nominal posture itself
        typer.echo(f"note: the nominal posture self-collides: {', '.join(pairs[:6])}"
                   + (f" (+{len(pairs) - 6} more)" if len(pairs) > 6 else "")
                   + "; check the spec's nominal angles (the knees' bend) and srdf/ignore_collision_pairs", err=True)


def _contact(lb: Any) -> str:
    """A limb's contact for the check line: ``, sphere r=0.02 m``, or nothing for a point contact."""
    c = lb.contact
    return "" if c.type == "point" else f", {c.type} r={c.radius:g} m"
