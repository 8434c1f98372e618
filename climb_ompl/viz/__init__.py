"""3-D playback with meshcat: one scene builder for terrains, robots, climb plans, TreeBot and slope plans.

This package is the only place that imports meshcat; ``import climb_ompl`` does not import it, and
nothing here starts a server until a function below is called.

Entry points:

* :func:`show` - a terrain (wall, holds, friction cones) and/or a robot, static.
* :func:`play` - a plan (``kind`` ``climb``, ``treebot`` or ``slope``) as an animation with a time slider.
* Both write a **self-contained static HTML** file when given ``html=`` (meshcat's ``static_html()``,
  written atomically; it opens without a server or network), else serve live (print the URL; wait for
  Enter only when stdin is a terminal).
* :func:`screenshot` - a PNG of such a page from headless Chromium (for the README).
* :class:`Scene` - the builder itself, for notebooks and custom scenes.

What keeps a page small: each moving body (a Pinocchio joint) is one animated node, its geometry objects
children placed once; a body is keyed only where the viewer's interpolation would miss its pose by more than
0.2 mm or 1 mrad (``_geometry.pose_keys``); a URDF mesh of more than 8000 triangles, or in a file of more than
200 kB, is drawn from the Coal model (simplified by ``_geometry.simplify_mesh`` if need be); a hold in contact is
drawn once and shown while held, a limb's force arrow likewise (the pages' sizes: docs/climb.md, "Playback").
A re-planned climb's failed hold is named beside it (``h94 removed at step 19``).

Scene items (what ``climb_ompl.treebot.scene_items(plan)`` and ``climb_ompl.mrwallspect.slope.scene_items(plan)``
return; plain numpy / lists, no meshcat)::

    {"times": (T,) seconds, or "dt": seconds per frame (default 0.1),
     "terrain": optional Terrain or terrain dict (drawn first),
     "items": [
        {"name": "trunk", "kind": "polyline" | "points" | "box" | "sphere" | "cylinder",
         "color": "#8b5a2b" | 0x8b5a2b | [r, g, b] in [0, 1], "opacity": 1.0,
         # polyline / points: "points" (N, 3) static, or (T, N, 3) one set per frame; 2-D (.., 2) = x-z plane;
         #   "radius": sphere radius of points / tube radius of a static polyline, "closed": bool
         # box: "size" (3,); sphere: "radius"; cylinder: "radius", "length" (axis = local z)
         # pose of box/sphere/cylinder: "pose" (4, 4) or "position" (3,) static,
         #   "poses" (T, 4, 4) or "positions" (T, 3) per frame
         # "visible": optional (T,) booleans
        }, ...]}

A bare list of items is accepted too, and so is a dict of plain arrays read by shape (TreeBot's
``scene_items`` returns one: see ``climb_ompl.viz._plans.normalize_items``).  Per-frame values are
keyed at ``times`` and interpolated by the viewer (positions linearly, orientations by slerp);
per-frame point sets switch at each frame.
"""

from __future__ import annotations

from collections.abc import Callable
from pathlib import Path
from typing import Any

from climb_ompl.errors import VizError
from climb_ompl.viz._browser import open_page, screenshot  # noqa: E402
from climb_ompl.viz._plans import PLAN_KINDS, draw_climb, draw_items, draw_plan, load_plan, timeline  # noqa: E402
from climb_ompl.viz._scene import RobotDrawing, RobotLike, Scene, region_points  # noqa: E402
from climb_ompl.viz._server import open_visualizer, render_html, serve, write_html  # noqa: E402


def _output(build: Callable[[Any], object], html: str | Path | None, wait: bool | None) -> Path | str:
    if html is not None:
        return write_html(html, build)
    return serve(build, wait=wait)


def show(terrain: Any = None, robot: RobotLike | None = None, q: Any = None, *, html: str | Path | None = None,
         cones: bool = True, wait: bool | None = None) -> Path | str:
    """Draw a terrain (wall, holds, friction cones) and/or a robot at configuration ``q``.

    Args:
        terrain: a :class:`~climb_ompl.model.terrain.Terrain`, or ``None``.
        robot: a robot (``RobotModel`` or anything with ``model``/``visual_model``), or ``None``.
        q: the robot's configuration (default its ``nominal_q``, else Pinocchio's neutral one).
        html: write a static HTML file here; ``None``: serve live.
        cones: draw the holds' friction cones.
        wait: live mode only: keep serving until Enter (default: when stdin is a terminal).

    Returns:
        The HTML path, or the live viewer's URL.

    Raises:
        VizError: nothing to draw, or no meshcat server.
    """
    if terrain is None and robot is None:
        raise VizError("nothing to show: give a terrain and/or a robot")

    def build(vis: Any) -> None:
        scene = Scene(vis)
        if terrain is not None:
            scene.add_terrain(terrain, cones=cones)
        if robot is not None:
            drawing = scene.add_robot(robot, q)
            g = terrain.g if terrain is not None else [0.0, 0.0, -9.81]
            scene.add_com(g, com=drawing.com(drawing.q), line_length=0.3)
        scene.finish()

    return _output(build, html, wait)


def play(plan: dict[str, Any] | str | Path, *, html: str | Path | None = None, speed: float = 1.0,
         robot: RobotLike | None = None, forces: bool = True, wait: bool | None = None) -> Path | str:
    """Animate a plan (a dict, or a plan file path) with a time slider.

    Args:
        plan: plan dict or JSON file (``kind``: climb, treebot or slope).
        html: write a static HTML file here; ``None``: serve live.
        speed: playback speed factor.
        robot: override the plan's robot (climb plans; default ``RobotModel.load`` of its name).
        forces: draw contact-force arrows when the plan has forces.
        wait: live mode only: keep serving until Enter (default: when stdin is a terminal).

    Raises:
        PlanFileError: unreadable or malformed plan.
        VizError: no meshcat server.
    """
    source = "<plan>"
    if not isinstance(plan, dict):
        source = str(plan)
        plan = load_plan(plan)
    if not 1e-3 <= speed <= 1e3:  # an infinite factor made a page whose animation lasts 0 s
        raise VizError(f"playback speed must be between 0.001 and 1000, got {speed!r}")
    plan_dict: dict[str, Any] = plan
    # Validate and load everything that can fail on bad input before starting a server.
    if plan_dict.get("kind") == "climb" and robot is None:
        from climb_ompl.viz._plans import robot_from_plan

        robot = robot_from_plan(plan_dict, source)

    def build(vis: Any) -> None:
        draw_plan(Scene(vis, speed=speed), plan_dict, source=source, robot=robot, forces=forces)

    return _output(build, html, wait)


__all__ = [
    "PLAN_KINDS",
    "RobotDrawing",
    "RobotLike",
    "Scene",
    "VizError",
    "draw_climb",
    "draw_items",
    "draw_plan",
    "load_plan",
    "open_page",
    "open_visualizer",
    "play",
    "region_points",
    "render_html",
    "screenshot",
    "serve",
    "show",
    "timeline",
    "write_html",
]
