"""``climb-ompl show``, ``climb-ompl play`` and ``climb-ompl robot show``: meshcat playback.

Each command writes a self-contained static HTML file with ``--html`` (atomically: no partial file on
error), else serves the scene live and prints the URL; a live run waits for Enter only when stdin is a
terminal, so scripts and CI never hang.  meshcat is imported inside the commands, not at CLI start-up.
"""

from __future__ import annotations

from pathlib import Path

import typer

from climb_ompl.cli._app import app, load_wall
from climb_ompl.cli.robot import robot_app

_HTML = typer.Option(None, "--html", help="Write a self-contained HTML file here (default: serve live).")


def _done(result: Path | str) -> None:
    if isinstance(result, Path):
        typer.echo(f"wrote {result}")


@app.command("show")
def show(
    terrain: str = typer.Option(..., "--terrain", help="Terrain file or bundled terrain name."),
    robot: str = typer.Option(None, "--robot", help="Robot spec file or bundled robot name (drawn at its nominal "
                              "configuration)."),
    html: Path = _HTML,
    cones: bool = typer.Option(True, "--cones/--no-cones", help="Draw the holds' friction cones."),
) -> None:
    """Show a terrain (wall, holds, friction cones), optionally with a robot."""
    from climb_ompl import viz

    t = load_wall(terrain)  # drawn as the file gives it; a robot placed as the specs expect (the wall frame)
    r = None
    if robot is not None:
        from climb_ompl.climb.multistep import check_dimensions
        from climb_ompl.model.robot import RobotModel

        r = RobotModel.load(robot)
        check_dimensions(r, t)  # a planar robot on a 3-D terrain, or the reverse: refused as plan refuses it
    _done(viz.show(t, r, html=html, cones=cones))


@app.command("play")
def play(
    plan: Path = typer.Argument(..., help="Plan file (JSON; kind climb, treebot or slope)."),
    html: Path = _HTML,
    speed: float = typer.Option(1.0, "--speed", help="Playback speed factor (0.001 to 1000)."),
    forces: bool = typer.Option(True, "--forces/--no-forces", help="Draw contact-force arrows."),
    png: Path = typer.Option(None, "--png", help="Also write a screenshot of the HTML page (needs --html and "
                             "Chromium)."),
    png_time: float = typer.Option(None, "--png-time", min=0.0,
                                   help="Animation time of the screenshot, s (default: end)."),
) -> None:
    """Play a plan as a 3-D animation with a time slider."""
    from climb_ompl import viz

    if not 1e-3 <= speed <= 1e3:  # (nan fails too)
        raise typer.BadParameter(f"must be between 0.001 and 1000 (a factor on the plan's times), got {speed}",
                                 param_hint="--speed")
    if png is not None and html is None:
        raise typer.BadParameter("a screenshot is taken of the HTML page: give --html too", param_hint="--png")
    if png is not None and png.suffix.lower() != ".png":
        raise typer.BadParameter(f"the screenshot is written as PNG: give a file name ending in .png, got {str(png)!r}",
                                 param_hint="--png")
    if png_time is not None and png is None:
        raise typer.BadParameter("the time of a screenshot: give --png FILE too", param_hint="--png-time")
    _done(viz.play(plan, html=html, speed=speed, forces=forces))
    if png is not None:
        _done(viz.screenshot(html, png, time=png_time,
                             note=lambda text: typer.echo(f"--png-time: {text}", err=True)))


@robot_app.command("show")
def robot_show(
    name: str = typer.Argument(..., help="Robot spec file or bundled robot name."),
    html: Path = _HTML,
    collision: bool = typer.Option(False, "--collision", help="Draw the collision geometry instead of the visual."),
) -> None:
    """Show a robot at its nominal configuration."""
    from climb_ompl import viz
    from climb_ompl.model.robot import RobotModel

    r = RobotModel.load(name)
    if collision:
        r = _CollisionView(r)
    _done(viz.show(None, r, html=html))


class _CollisionView:
    """A robot seen through its collision geometry (the viewer draws ``visual_model`` first)."""

    def __init__(self, robot: object):
        self.model = robot.model  # type: ignore[attr-defined]
        self.visual_model = robot.collision_model  # type: ignore[attr-defined]
        self.collision_model = None
        self.nominal_q = getattr(robot, "nominal_q", None)
        self.name = getattr(robot, "name", "robot")
