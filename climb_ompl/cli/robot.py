"""``climb-ompl robots`` and the ``climb-ompl robot`` group (``robot check``; ``robot show`` lives in viz)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
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
    for note in limit_notes(r) + posture_notes(r):  # warnings, not errors
        typer.echo(f"note: {note}", err=True)


#: Limits above these look like a URDF's placeholders (example-robot-data's Solo-12: +-10 rad, 1000 rad/s,
#: 1000 N m): joint speed (rad/s or m/s), torque (N m or N) and range (two whole turns).
PLACEHOLDER_SPEED, PLACEHOLDER_TORQUE, PLACEHOLDER_RANGE = 100.0, 1000.0, 4.0 * math.pi


def limit_notes(robot: Any) -> list[str]:
    """Joint limits that look like a URDF's placeholders (:data:`PLACEHOLDER_SPEED` and the others): the
    planner takes them at their word (a plan's execution times come from the speeds, its torque checks from the
    torques, its reach from the ranges), so the spec should give the real ones."""
    act = np.asarray(robot.actuated, dtype=bool)
    names = robot.joint_names
    out = []
    for what, values, bound, unit, field in (
            ("speed", robot.velocity_limits, PLACEHOLDER_SPEED, "rad/s or m/s", "velocity_limits"),
            ("torque", robot.torque_limits, PLACEHOLDER_TORQUE, "N m or N", "torque_limits"),
            ("range", np.asarray(robot.upper) - np.asarray(robot.lower), PLACEHOLDER_RANGE + 1e-9, "rad or m",
             "joint_limits")):
        big = [j for j in np.flatnonzero(act) if np.isfinite(values[j]) and values[j] >= bound]
        if big:
            shown = ", ".join(f"{names[j]} {values[j]:g}" for j in big[:4]) + (" ..." if len(big) > 4 else "")
            out.append(f"joint {what} limits above {bound:g} {unit} ({shown}) look like the URDF's placeholders: "
                       f"give the real ones in the spec's {field}")
    return out


def posture_notes(robot: Any) -> list[str]:
    """What the nominal posture says about the spec: links that collide there, and links closer there than the
    clearance every transition keeps (``ClimbSettings.clearance`` with the robot's climb defaults): a pair of
    links that close in every posture (a leg's upper link beside the base) makes every transition infeasible."""
    from ..settings import ClimbSettings

    clearance = ClimbSettings.for_search("guided", robot=robot).clearance
    touching = sorted({f"{a} with {b}" for a, b in robot.collisions(robot.nominal_q)})
    near = sorted({f"{a} with {b}" for a, b in robot.collisions(robot.nominal_q, clearance=clearance)} - set(touching))
    out = []
    if touching:
        out.append(f"the nominal posture self-collides: {_listed(touching)}; check the spec's nominal angles (the "
                   "knees' bend) and srdf/ignore_collision_pairs")
    if near:
        out.append(f"in the nominal posture {_listed(near)} are closer than the clearance of {clearance:g} m that "
                   "every transition keeps between links; if they are that close in every posture, list them "
                   "in ignore_collision_pairs (or the SRDF), or give the robot a smaller climb: {clearance: ...}")
    return out


def _listed(pairs: list[str]) -> str:
    return ", ".join(pairs[:6]) + (f" (+{len(pairs) - 6} more)" if len(pairs) > 6 else "")


def _contact(lb: Any) -> str:
    """A limb's contact for the check line: ``, sphere r=0.02 m``, or nothing for a point contact."""
    c = lb.contact
    return "" if c.type == "point" else f", {c.type} r={c.radius:g} m"
