"""The scene builder: terrain, robot, centre of mass, support polygon, contact forces, and their animation.

A :class:`Scene` wraps one meshcat ``Visualizer`` (a live server or the recorder behind a static HTML
export) and writes the scene tree::

    /meshcat/terrain/surfaces/<i>      wall planes (thin boxes), boxes, 2-D discs (cylinders along y)
    /meshcat/terrain/holds/<id>        holds (small spheres, coloured by contact type)
    /meshcat/terrain/cones/<id>        friction cones (half-angle atan(mu), along the hold normal)
    /meshcat/robot/<joint>             one node per moving body (Pinocchio joint), placed at its world pose
    /meshcat/robot/<joint>/<geometry>  its geometry objects, placed in the joint's frame (static)
    /meshcat/com                       centre of mass (point) with a line along gravity
    /meshcat/stance/<hold>             a hold in contact, highlighted with its friction cone (shown while held)
    /meshcat/support/s<k>              stance k's support polygon on the plane through the CoM
    /meshcat/forces/<limb>             a limb's contact force arrow (shown while the limb carries load)
    /meshcat/items/<name>              items of TreeBot / slope plans

Animated nodes get keyframes through :meth:`Scene.key`; :meth:`Scene.finish` sends the animation and
points the camera at the content.  Three.js's orbit camera always looks at the world origin, so the
content (``/meshcat``) and the floor grid are shifted to put the centre of the content there.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

import meshcat
import meshcat.geometry as mg
import numpy as np
from meshcat.animation import Animation

from climb_ompl.viz._geometry import (
    PALETTE,
    Part,
    UnsupportedGeometry,
    arrow_parts,
    cone_parts,
    geometry_parts,
    material,
    plane_frame,
    polygon_parts,
    pose,
    pose_keys,
    rotation_y_to,
    segment_parts,
    translation,
)


class RobotLike(Protocol):
    """What the viewer needs of a robot (``climb_ompl.model.robot.RobotModel`` provides it).

    ``model`` is a ``pinocchio.Model``; ``visual_model`` / ``collision_model`` are ``pinocchio.GeometryModel``
    (either may be ``None``).  Optional: ``nominal_q``, ``name``.
    """

    model: Any
    visual_model: Any
    collision_model: Any


def node_name(name: Any) -> str:
    """A scene-tree node name: ``/`` would split the path, so it becomes ``_``."""
    return str(name).replace("/", "_") or "_"


def _unique(name: str, used: set[str]) -> str:
    """``name``, with ``_`` appended until it is not in ``used`` (then added to it)."""
    while name in used:
        name += "_"
    used.add(name)
    return name


@dataclass
class RobotDrawing:
    """A robot drawn in a scene: its body and geometry nodes and how to place them for a configuration.

    Only the bodies move (:meth:`placements`); each geometry object hangs under its body at a fixed placement.
    A robot with many geometry objects per body (a quadruped's sensors and rotors) is animated with a few
    tracks, and a geometry node whose object arrives late in the browser (a large mesh) moves all the same: the
    animation drives the body group, which holds no object of its own to be replaced.

    Attributes:
        path: scene path of the robot group (``"robot"``).
        model, data: Pinocchio model and data.
        geom_model, geom_data: the drawn Pinocchio geometry model and its data.
        nodes: scene path of each drawn geometry object, in geometry-model order (``None`` if skipped).
        bodies: ``{joint index: scene path}`` of the bodies with a drawn geometry object.
        q: the configuration of the static pose last set.
    """

    path: str
    model: Any
    data: Any
    geom_model: Any
    geom_data: Any
    nodes: list[str | None] = field(default_factory=list)
    bodies: dict[int, str] = field(default_factory=dict)
    q: np.ndarray | None = None

    def placements(self, q: np.ndarray) -> list[tuple[str, np.ndarray]]:
        """``(body node path, 4x4 world pose)`` of every body with a drawn geometry object at configuration ``q``."""
        import pinocchio as pin

        pin.forwardKinematics(self.model, self.data, np.asarray(q, dtype=float))
        return [(n, self.data.oMi[j].homogeneous.copy()) for j, n in self.bodies.items()]

    def geometry_placements(self, q: np.ndarray) -> list[tuple[str, np.ndarray]]:
        """``(geometry node path, 4x4 world pose)`` of every drawn geometry object at configuration ``q``."""
        import pinocchio as pin

        q = np.asarray(q, dtype=float)
        pin.forwardKinematics(self.model, self.data, q)
        pin.updateGeometryPlacements(self.model, self.data, self.geom_model, self.geom_data)
        return [(n, self.geom_data.oMg[i].homogeneous.copy()) for i, n in enumerate(self.nodes) if n is not None]

    def com(self, q: np.ndarray) -> np.ndarray:
        """Centre of mass at ``q``, world frame, metres."""
        import pinocchio as pin

        return np.asarray(pin.centerOfMass(self.model, self.data, np.asarray(q, dtype=float)), dtype=float).copy()


def region_points(region: Any, gravity: Any) -> np.ndarray:
    """World points ``(k, 3)`` of a support region's vertices on the plane through the origin normal to gravity.

    ``region`` is a ``SupportRegion`` (``.vertices`` ``(k, 2)`` in its 2-D ``.basis``; planar regions: an
    interval of CoM x, ``(2,)`` or ``(2, 1)``), or an array of world points ``(k, 3)`` (projected here).
    """
    g = np.asarray(gravity, dtype=float)
    gh = g / np.linalg.norm(g)
    if hasattr(region, "vertices"):
        V = np.asarray(region.vertices, dtype=float)
        if V.size == 0:
            return np.zeros((0, 3))
        if V.ndim == 1:
            V = V[:, None]
        B = np.atleast_2d(np.asarray(region.basis, dtype=float))
        if B.shape[1] != 3 and B.shape[0] == 3:
            B = B.T
        pts = V @ B[: V.shape[1]]
    else:
        pts = np.asarray(region, dtype=float).reshape(-1, 3)
    return pts - np.outer(pts @ gh, gh)


class Scene:
    """Builds a climbing scene in a meshcat ``Visualizer``.

    Args:
        vis: a meshcat ``Visualizer`` (see :func:`climb_ompl.viz.open_visualizer`).
        speed: playback speed factor of the animation (2 = twice as fast).
    """

    def __init__(self, vis: meshcat.Visualizer, *, speed: float = 1.0):
        if not speed > 0:
            from climb_ompl.errors import VizError

            raise VizError(f"playback speed must be > 0, got {speed!r}")
        self.vis = vis
        self.speed = float(speed)
        self.animation: Animation | None = None
        self.duration = 0.0
        self._extent: list[np.ndarray] = []  # points the camera should see
        self._focus: list[np.ndarray] = []  # points it should look at first (robot, active holds)
        #: the motion from the scene's coordinates to those shown: a terrain turned into the wall frame is shown
        #: as its file gave it (the inverse of its recorded frame, :meth:`add_terrain`)
        self.view = np.eye(4)

    # ---- low level ------------------------------------------------------------------------------
    def put(self, path: str, parts: Sequence[Part], *, transform: np.ndarray | None = None,
            visible: bool | None = None) -> None:
        """Draw ``parts`` as children of node ``path`` and optionally place / hide the node."""
        for part in parts:
            child = self.vis[f"{path}/{part.name}"]
            child.set_object(part.object())
            if not np.allclose(part.transform, np.eye(4)):
                child.set_transform(part.transform)
        if transform is not None:
            self.vis[path].set_transform(transform)
        if visible is not None:
            self.vis[path].set_property("visible", bool(visible))

    def key(self, t: float, path: str, *, transform: np.ndarray | None = None, visible: bool | None = None,
            scale: Sequence[float] | None = None) -> None:
        """Add a keyframe at time ``t`` (seconds at speed 1) for node ``path``."""
        if self.animation is None:
            self.animation = Animation(default_framerate=self.speed)
        self.duration = max(self.duration, float(t))
        frame = self.animation.at_frame(self.vis, float(t))[path]
        if transform is not None:
            frame.set_transform(transform)
        if visible is not None:
            frame.set_property("visible", "boolean", bool(visible))
        if scale is not None:
            frame.set_property("scale", "vector3", [float(s) for s in scale])

    def key_poses(self, path: str, times: Sequence[float], mats: Sequence[np.ndarray]) -> None:
        """Key node ``path`` at ``mats[i]`` at ``times[i]``, leaving out the poses that the viewer's
        interpolation between the others reproduces (:func:`~climb_ompl.viz._geometry.pose_keys`)."""
        for i in pose_keys(times, mats):
            self.key(float(times[i]), path, transform=mats[i])

    def see(self, points: Any, *, focus: bool = False) -> None:
        """Ask the camera to keep ``points`` ``(n, 3)`` in view (``focus``: centre on them)."""
        pts = np.asarray(points, dtype=float).reshape(-1, 3)
        (self._focus if focus else self._extent).append(pts)

    # ---- terrain ----------------------------------------------------------------------------------
    def add_terrain(self, terrain: Any, *, cones: bool = True, cone_height: float = 0.05,
                    hold_radius: float = 0.018, path: str = "terrain") -> None:
        """Draw a :class:`~climb_ompl.model.terrain.Terrain`: surfaces, holds and (optionally) friction cones.

        Args:
            terrain: the terrain.
            cones: draw the friction cone of every friction/adhesion hold (half-angle atan(mu)).
            cone_height: cone height, metres.
            hold_radius: radius of the hold spheres, metres.
            path: scene path of the terrain group.
        """
        pos = terrain.positions
        self.see(pos)
        if getattr(terrain, "frame", None) is not None:  # shown in the coordinates of the user's file
            from climb_ompl.model.wall_frame import frame_of

            rot, t = frame_of(terrain)
            self.view = np.eye(4)
            self.view[:3, :3], self.view[:3, 3] = rot.T, -rot.T @ t
        lo, hi = (pos.min(axis=0), pos.max(axis=0)) if len(pos) else (np.zeros(3), np.zeros(3))
        for i, s in enumerate(terrain.surfaces):
            self._add_surface(f"{path}/surfaces/{i}", s, lo, hi, terrain.dim)
        colours = {"friction": PALETTE["hold_friction"], "grasp": PALETTE["hold_grasp"],
                   "adhesion": PALETTE["hold_adhesion"]}
        for h in terrain.holds:
            self.put(f"{path}/holds/{node_name(h.id)}",
                     [Part("sphere", mg.Sphere(hold_radius), material(colours.get(h.type, 0x888888)), np.eye(4))],
                     transform=translation(h.p))
            if cones and h.type != "grasp":
                self.put(f"{path}/cones/{node_name(h.id)}", self._cone(h, cone_height, 0.35))

    def _cone(self, hold: Any, height: float, opacity: float, color: int = PALETTE["cone"]) -> list[Part]:
        return cone_parts(hold.p, hold.n, math.atan(hold.friction), height, color, opacity)

    def _add_surface(self, path: str, s: Any, lo: np.ndarray, hi: np.ndarray, dim: int) -> None:
        c = np.asarray(s.center, dtype=float)
        if s.type == "plane":
            thickness = 0.02
            R = plane_frame(s.normal)
            if s.size is not None:
                w, h = (float(s.size[0]), float(s.size[-1]))
            else:  # cover the holds' extent in the plane, plus a margin
                span = np.abs(R[:, :2].T @ (hi - lo))
                w, h = span[0] + 1.0, span[1] + 1.0
            centre = c - R[:, 2] * thickness / 2
            if dim == 2:  # a 2-D ground/wall line seen edge-on: give it depth along y
                w, h = (w, 0.3) if abs(R[1, 0]) < 0.9 else (0.3, h)
            parts = [Part("slab", mg.Box([w, h, thickness]), material(PALETTE["wall"]), np.eye(4))]
            self.put(path, parts, transform=pose(R, centre))
            corners = [centre + R[:, 0] * a * w / 2 + R[:, 1] * b * h / 2 for a in (-1, 1) for b in (-1, 1)]
            self.see(np.array(corners))
        elif s.type == "box":
            size = np.asarray(s.size, dtype=float)
            parts = [Part("box", mg.Box(list(size)), material(PALETTE["obstacle"]), np.eye(4))]
            self.put(path, parts, transform=translation(c))
            self.see(np.array([c - size / 2, c + size / 2]))
        elif s.type == "circle":  # a disc in the x-z plane: a cylinder along y (three.js's cylinder axis)
            r = float(s.radius)
            parts = [Part("disc", mg.Cylinder(0.06, r), material(PALETTE["obstacle"]), np.eye(4))]
            self.put(path, parts, transform=translation(c))
            self.see(np.array([c - r, c + r]))

    # ---- robot ------------------------------------------------------------------------------------
    def add_robot(self, robot: RobotLike, q: Any = None, *, geometry: str = "visual",
                  path: str = "robot") -> RobotDrawing:
        """Draw a robot's Pinocchio geometry (``visual`` or ``collision``) at configuration ``q``.

        Falls back to the other geometry model when the chosen one is missing or empty.  ``q`` defaults to
        ``robot.nominal_q`` (else Pinocchio's neutral configuration).
        """
        import pinocchio as pin

        models = {"visual": getattr(robot, "visual_model", None), "collision": getattr(robot, "collision_model", None)}
        order = [geometry] + [k for k in models if k != geometry]
        gm = next((models[k] for k in order if models.get(k) is not None and models[k].ngeoms > 0), None)
        if gm is None:
            from climb_ompl.errors import VizError

            raise VizError(f"robot {getattr(robot, 'name', '?')!r} has no visual or collision geometry to draw")
        model = robot.model
        drawing = RobotDrawing(path, model, model.createData(), gm, pin.GeometryData(gm))
        used: set[str] = set()
        for gobj in gm.geometryObjects:
            try:
                parts = geometry_parts(gobj)
            except UnsupportedGeometry:
                drawing.nodes.append(None)
                continue
            j = int(gobj.parentJoint)
            if j not in drawing.bodies:
                drawing.bodies[j] = f"{path}/{_unique(node_name(model.names[j]), used)}"
            node = f"{drawing.bodies[j]}/{_unique(node_name(gobj.name), used)}"
            drawing.nodes.append(node)
            self.put(node, parts, transform=gobj.placement.homogeneous)
        if q is None:
            q = getattr(robot, "nominal_q", None)
        if q is None:
            q = pin.neutral(model)
        self.place_robot(drawing, q)
        return drawing

    def place_robot(self, drawing: RobotDrawing, q: Any) -> None:
        """Set the robot's static pose to configuration ``q``."""
        drawing.q = np.asarray(q, dtype=float).copy()
        for node, T in drawing.placements(np.asarray(q, dtype=float)):
            self.vis[node].set_transform(T)
            self.see(T[:3, 3], focus=True)

    # ---- equilibrium overlays ---------------------------------------------------------------------------
    def add_com(self, gravity: Any, *, com: Any = None, line_length: float = 0.5, radius: float = 0.02,
                path: str = "com") -> None:
        """The centre of mass as a point with a line along gravity (placed at ``com`` if given)."""
        g = np.asarray(gravity, dtype=float)
        parts = [Part("point", mg.Sphere(radius), material(PALETTE["com"]), np.eye(4))]
        parts += segment_parts(np.zeros(3), g / np.linalg.norm(g) * line_length, radius / 4, PALETTE["gravity"],
                               name="gravity")
        self.put(path, parts, transform=None if com is None else translation(com))

    def add_support(self, region: Any, gravity: Any, *, com: Any = None, path: str = "support",
                    visible: bool | None = None, color: int = PALETTE["support"], lift: float = 0.0) -> bool:
        """A support region drawn on the plane normal to gravity through ``com`` (the node's translation).

        Polygons (3-D) are filled; intervals (planar robots) are drawn as a bar.  ``lift`` (metres, against
        gravity) keeps a second region drawn on the same plane visible above the first.  Returns ``False``
        (and draws nothing) for an empty region.
        """
        pts = region_points(region, gravity)
        if len(pts) == 0 or getattr(region, "is_empty", False):
            return False
        if lift:
            g = np.asarray(gravity, dtype=float)
            pts = pts - lift * g / np.linalg.norm(g)
        if len(pts) >= 3:
            parts = polygon_parts(pts, color, name="polygon")
        else:
            ends = pts if len(pts) == 2 else np.vstack([pts, pts])
            parts = segment_parts(ends[0], ends[1], 0.008, color, name="interval")
            parts += [Part(f"end{i}", mg.Sphere(0.014), material(color), translation(e))
                      for i, e in enumerate(ends)]
        self.put(path, parts, transform=None if com is None else self.plane_offset(com, gravity), visible=visible)
        return True

    @staticmethod
    def plane_offset(com: Any, gravity: Any) -> np.ndarray:
        """Translation moving the plane through the origin (normal to gravity) to the plane through ``com``."""
        g = np.asarray(gravity, dtype=float)
        gh = g / np.linalg.norm(g)
        return translation(gh * float(np.asarray(com, dtype=float) @ gh))

    def add_held(self, terrain: Any, hold: str, *, path: str, cone_height: float = 0.1) -> None:
        """Highlight one hold in contact (a red ball and its friction cone) at node ``path``."""
        h = terrain.hold(hold)
        parts = [Part("sphere", mg.Sphere(0.03), material(PALETTE["active"], 0.8), translation(h.p))]
        if h.type != "grasp":
            parts += self._cone(h, cone_height, 0.5, PALETTE["active"])
        self.put(path, parts)
        self.see(h.p, focus=True)

    def add_arrow(self, path: str, origin: Any, vector: Any, *, color: int = PALETTE["force"],
                  visible: bool | None = None) -> None:
        """An arrow from ``origin`` along ``vector`` (its length is the vector's norm, metres)."""
        self.put(path, arrow_parts(color), transform=self.arrow_transform(origin, vector), visible=visible)

    @staticmethod
    def arrow_transform(origin: Any, vector: Any) -> np.ndarray:
        """The pose-and-scale of a unit arrow (along local y) drawn from ``origin`` along ``vector``."""
        v = np.asarray(vector, dtype=float)
        T = pose(rotation_y_to(v), origin)
        T[:3, 1] *= max(float(np.linalg.norm(v)), 1e-6)
        return T

    # ---- finishing ---------------------------------------------------------------------------------------
    def visibility_keys(self, path: str, intervals: Iterable[tuple[float, float]]) -> None:
        """Key node ``path`` visible during the half-open time ``intervals`` and hidden otherwise."""
        keys: dict[float, bool] = {0.0: False}
        for a, b in sorted(intervals):
            keys[float(a)] = True
            if math.isfinite(b):  # an open end: visible to the end of the animation
                keys.setdefault(float(b), False)
        for t in sorted(keys):
            self.key(t, path, visible=keys[t])

    def finish(self, *, play: bool = True, repetitions: int = 1) -> None:
        """Send the animation (if any keyframes were added) and aim the camera at the content."""
        if self.animation is not None:
            self._hold_to_end()
            self.vis.set_animation(self.animation, play=play, repetitions=repetitions)
        self.frame_camera()

    def _hold_to_end(self) -> None:
        """Key every track's last value again at the end of the animation.

        The viewer runs one three.js action per node, and an action whose clip ends before the animation
        does is "finished" and paused at its own end; when playback or a seek then moves past it, three.js
        may leave the node showing an earlier value (an early stance's highlight, support polygon and force
        arrows stayed visible at the end of a climb).  With every clip as long as the animation, all
        actions stay running to the end and a seek evaluates every track at the same time.
        """
        assert self.animation is not None
        end = self.duration
        for clip in self.animation.clips.values():
            for track in clip.tracks.values():
                if track.frames and track.frames[-1] < end:
                    track.set_property(end, track.values[-1])

    def frame_camera(self) -> None:
        """Centre the content at the world origin and move the camera back until it all fits."""
        rot, shift = self.view[:3, :3], self.view[:3, 3]
        focus = np.vstack(self._focus) @ rot.T + shift if self._focus else None
        pts = np.vstack(self._focus + self._extent) @ rot.T + shift if (self._focus or self._extent) else \
            np.zeros((1, 3))
        ref = focus if focus is not None else pts
        centre = (ref.min(axis=0) + ref.max(axis=0)) / 2
        if focus is not None:  # the robot's motion and the holds it uses; a little of the wall around
            radius = float(np.linalg.norm(ref.max(axis=0) - ref.min(axis=0))) / 2 + 0.35
        else:
            radius = float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0))) / 2 + 0.1
        radius = max(radius, 0.3)
        self.vis.set_transform(translation(-centre) @ self.view)
        self.vis["/Grid"].set_transform(translation(-centre))
        self.vis["/Axes"].set_property("visible", False)
        direction = rot @ np.array([0.25, 1.0, 0.2])  # in front of the wall, a little to the side and above
        offset = direction / np.linalg.norm(direction) * radius / math.tan(math.radians(37.5)) * 1.1
        # The camera sits in /Cameras/default/rotated, a frame turned a quarter turn about x (three.js's
        # y up): its point (a, b, c) is the world point (a, -c, b), so a world offset w is (w_x, w_z, -w_y).
        self.vis["/Cameras/default/rotated/<object>"].set_property(
            "position", [float(offset[0]), float(offset[2]), float(-offset[1])])
