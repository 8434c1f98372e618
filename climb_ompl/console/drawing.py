"""The console's 3-D drawing in viser: the robot's Pinocchio geometry, the holds, the support region and the CoM.

The robot is drawn from its visual (else collision) geometry model: one frame per body, its shapes (boxes, cylinders,
spheres, capsules and meshes as triangle meshes) under it, so that a new configuration moves a handful of frames.
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: Colours (RGB 0-255), after MoveIt's motion-planning panel: the state the robot is in green, the goal orange,
#: what is invalid red.
COLORS = {"hold": (150, 150, 150), "held": (40, 170, 70), "selected": (255, 140, 0), "target": (255, 140, 0),
          "failed": (210, 30, 30), "robot": (110, 130, 170), "moving": (255, 140, 0), "support": (40, 170, 70),
          "com": (20, 20, 20), "wall": (235, 230, 220)}
#: Radius of a hold's clickable ball, m.
HOLD_RADIUS = 0.03


def shape_mesh(gobj: Any) -> tuple[np.ndarray, np.ndarray] | None:
    """Vertices ``(n, 3)`` and triangles ``(m, 3)`` of a Pinocchio ``GeometryObject`` in its own frame, or ``None``
    for a shape without a finite mesh (a plane)."""
    import coal
    import trimesh

    geo = gobj.geometry
    if isinstance(geo, coal.Box):
        m = trimesh.creation.box(extents=2 * np.asarray(geo.halfSide, dtype=float))
    elif isinstance(geo, coal.Sphere):
        m = trimesh.creation.icosphere(subdivisions=2, radius=float(geo.radius))
    elif isinstance(geo, coal.Capsule):
        m = trimesh.creation.capsule(height=2 * float(geo.halfLength), radius=float(geo.radius))
    elif isinstance(geo, coal.Cylinder):
        m = trimesh.creation.cylinder(radius=float(geo.radius), height=2 * float(geo.halfLength))
    elif isinstance(geo, coal.Cone):
        m = trimesh.creation.cone(radius=float(geo.radius), height=2 * float(geo.halfLength))
        m.apply_translation([0, 0, -float(geo.halfLength)])
    else:
        from climb_ompl.viz._geometry import _mesh_arrays, simplify_mesh

        verts, faces = _mesh_arrays(geo)
        if verts is None:
            return None
        return simplify_mesh(verts, faces, 4000)
    return np.asarray(m.vertices, dtype=np.float32), np.asarray(m.faces, dtype=np.uint32)


def wxyz(R: np.ndarray) -> np.ndarray:
    """A rotation matrix as a unit quaternion ``(w, x, y, z)``."""
    import pinocchio as pin

    q = pin.Quaternion(np.asarray(R, dtype=float))
    return np.array([q.w, q.x, q.y, q.z])


class RobotDrawing:
    """The robot in a viser scene: a frame per body with its shapes; :meth:`place` moves it to a configuration.

    Args:
        scene: the viser scene (``server.scene``).
        robot: the :class:`~climb_ompl.model.robot.RobotModel`.
        path: scene path of the robot.
    """

    def __init__(self, scene: Any, robot: Any, path: str = "/robot"):
        import pinocchio as pin

        self.robot, self.model = robot, robot.model
        self.data = self.model.createData()
        gm = robot.visual_model if robot.visual_model is not None and robot.visual_model.ngeoms else \
            robot.collision_model
        limb_of = {j: lb.name for lb in robot.limbs for j in lb.joint_ids}
        self.frames: dict[int, Any] = {}
        self.meshes: dict[str, list[Any]] = {}  # limb (or "") -> its shapes
        for i, g in enumerate(gm.geometryObjects):
            mesh = shape_mesh(g)
            if mesh is None:
                continue
            j = int(g.parentJoint)
            if j not in self.frames:
                self.frames[j] = scene.add_frame(f"{path}/j{j}", show_axes=False)
            T = g.placement
            h = scene.add_mesh_simple(f"{path}/j{j}/g{i}", mesh[0], mesh[1], color=COLORS["robot"],
                                      position=np.asarray(T.translation), wxyz=wxyz(T.rotation), cast_shadow=False,
                                      receive_shadow=False)
            self.meshes.setdefault(limb_of.get(j, ""), []).append(h)
        self._pin = pin

    def place(self, q: Any) -> None:
        """Move the drawing to configuration ``q``."""
        self._pin.forwardKinematics(self.model, self.data, np.asarray(q, dtype=float))
        for j, f in self.frames.items():
            M = self.data.oMi[j]
            f.position = np.asarray(M.translation, dtype=float)
            f.wxyz = wxyz(M.rotation)

    def highlight(self, limb: str | None) -> None:
        """Colour ``limb``'s shapes as the moving limb (``None``: none)."""
        for name, hs in self.meshes.items():
            for h in hs:
                h.color = COLORS["moving"] if name and name == limb else COLORS["robot"]


def region_loop(robot: Any, terrain: Any, stance: dict[str, str], com: np.ndarray) -> np.ndarray | None:
    """The support region of ``stance`` as line segments ``(k, 2, 3)`` on the plane normal to gravity through the
    CoM ``com`` (Bretl & Lall 2006: the CoM positions in static equilibrium), or ``None`` (an empty region, or a
    robot without the equilibrium check)."""
    from climb_ompl.viz._plans import support_region_of
    from climb_ompl.viz._scene import Scene, region_points

    if not stance or not getattr(robot, "equilibrium", True):
        return None
    region = support_region_of(robot, terrain, stance)
    if region is None or getattr(region, "is_empty", False):
        return None
    pts = region_points(region, terrain.gravity)
    if len(pts) < 2:
        return None
    pts = pts + Scene.plane_offset(com, terrain.gravity)[:3, 3]
    return np.stack([pts, np.roll(pts, -1, axis=0)], axis=1)


__all__ = ["COLORS", "HOLD_RADIUS", "RobotDrawing", "region_loop", "shape_mesh", "wxyz"]
