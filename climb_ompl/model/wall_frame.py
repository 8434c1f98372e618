"""A terrain turned into the frame the robot specs expect: the wall is the plane ``y = 0``, climbed from ``+y``.

A user writes a gym slab leaning back 30 degrees by tilting its holds, a wall that faces ``+x``, or a ramp of
stepping stones on a slope with gravity straight down: all natural, and all outside the frame convention of the
terrain files (docs/terrain.md), where a slab or a ramp is a tilted gravity, not a tilted wall.  The robot
specs assume the convention (LEMUR's base moves only in the plane ``y = 0``; the quadrupeds' base bounds measure
the stand-off from it), so such a file finds no start or stalls.  Statics do not depend on the frame they are
written in: turning the whole terrain, gravity included, by one rigid motion gives the same problem.
:func:`to_wall_frame` finds that motion and applies it:

1. the rotation taking the wall normal (:func:`wall_normal`: the first plane surface's, else the
   normal of the plane that best fits the holds) onto ``+y`` by the smallest angle;
2. then a turn about ``+y`` that points gravity's component along the wall down ``-z`` (so the climb goes up
   ``+z``, as the specs' nominal postures and base bounds expect); a wall already facing ``+y`` is not turned,
   whichever way gravity points along it (a file in the convention is planned as written);
3. then a translation putting the wall plane (its point, else the holds' mean) at ``y = 0``, taken along the
   wall so that every height (along minus gravity) stays what the file gives, and a ``--goal-height`` keeps its
   meaning (unless that shift exceeds :data:`KEEP_HEIGHTS`, on a gentle ramp: then the note gives the change of
   height); a turned wall is also centred across (``x``) on its holds, as the robot specs' base bounds expect
   (LEMUR's base moves 2 m either way of ``x = 0``).  Heights are kept, so a terrain whose holds start far above
   the file's origin stays there (the specs' base bounds reach about 3.5 m up the wall).

The turned terrain records the motion as its ``frame`` (``rotation``, ``translation``: a point ``p`` of the file is
``rotation @ p + translation`` here), so that a plan file says in which frame its configurations are, and a
re-plan's moved or added holds (:class:`climb_ompl.plan.events.TerrainChange`), written in the file's coordinates,
are turned the same way.  A terrain that already follows the convention is returned unchanged.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:
    from climb_ompl.model.terrain import Terrain

__all__ = ["HOLD_OFFSET", "PLANE_TOLERANCE_DEG", "frame_of", "to_wall_frame", "wall_motion", "wall_normal"]


#: A wall plane whose normal is farther than this from ``+y`` (degrees), and holds or a plane farther than this
#: from ``y = 0`` (metres), depart from the frame convention
# (:meth:`~climb_ompl.model.terrain.Terrain.convention_notes`).
PLANE_TOLERANCE_DEG = 2.0
HOLD_OFFSET = 0.3

#: Largest shift along the wall that keeps the file's heights (metres): on a gentle ramp, keeping them after
#: the wall plane moves to ``y = 0`` would take the holds far up the wall, beyond the specs' base bounds (stones
#: 0.3 m above the origin of a 3-degree ramp went 5.7 m up it).
KEEP_HEIGHTS = 1.0


def _rotation_onto(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """The rotation by the smallest angle taking the unit vector ``a`` onto the unit vector ``b``."""
    v, c = np.cross(a, b), float(a @ b)
    if c < -1.0 + 1e-12:  # opposite: half a turn about an axis across a
        axis = np.cross(a, [0.0, 0.0, 1.0] if abs(a[2]) < 0.9 else [1.0, 0.0, 0.0])
        axis /= np.linalg.norm(axis)
        return 2.0 * np.outer(axis, axis) - np.eye(3)
    vx = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return np.eye(3) + vx + vx @ vx / (1.0 + c)


def wall_motion(terrain: Terrain) -> tuple[np.ndarray, np.ndarray] | None:
    """The rigid motion ``(R, t)`` taking ``terrain`` into the wall frame (see the module docstring), or
    ``None`` when it already follows the convention (a 2-D terrain always does)."""
    if terrain.dim != 3:
        return None
    n = np.asarray(wall_normal(terrain), dtype=float)
    n = n / np.linalg.norm(n)
    tilted = math.degrees(math.acos(max(-1.0, min(1.0, float(n[1]))))) > PLANE_TOLERANCE_DEG
    rot = np.eye(3)
    if tilted:
        rot = _rotation_onto(n, np.array([0.0, 1.0, 0.0]))
        g = rot @ terrain.g
        along = np.array([g[0], 0.0, g[2]])
        if np.linalg.norm(along) > 1e-6 * np.linalg.norm(g):  # gravity has a component along the wall
            z = -along / np.linalg.norm(along)
            y = np.array([0.0, 1.0, 0.0])
            rot = np.vstack([np.cross(y, z), y, z]) @ rot
    planes = [s for s in terrain.surfaces if s.type == "plane" and s.normal is not None]
    anchor = np.asarray(planes[0].center, dtype=float) if planes else terrain.positions.mean(axis=0)
    depth = float((rot @ anchor)[1])
    if not tilted and abs(depth) <= HOLD_OFFSET:
        return None
    up = rot @ terrain.up
    # the wall plane to y = 0, moving along the wall as well so that heights (along up) do not change, unless
    # that takes more than KEEP_HEIGHTS metres (a gentle ramp: its heights change instead, and the note says so)
    along = depth * up[1] / up[2] if abs(up[2]) > 1e-9 else math.inf
    t = np.array([0.0, -depth, along if abs(along) <= KEEP_HEIGHTS else 0.0])
    if tilted and abs(up[0]) < 1e-9:  # a turned wall centred across (x) on its holds: the specs' base bounds
        t[0] = -float(np.mean(terrain.positions @ rot[0]))
    return rot, t


def frame_of(terrain: Terrain) -> tuple[np.ndarray, np.ndarray]:
    """The terrain's recorded motion from its file's coordinates ``(R, t)`` (the identity when it has none)."""
    if terrain.frame is None:
        return np.eye(3), np.zeros(3)
    m = np.asarray(terrain.frame, dtype=float)
    return m[:, :3], m[:, 3]


def to_wall_frame(terrain: Terrain) -> tuple[Terrain, str]:
    """``terrain`` in the wall frame (see the module docstring) and a sentence saying what was done: ``""`` when
    it already follows the convention; when a box surface would no longer be axis-aligned, ``terrain`` unchanged
    and a sentence saying why."""
    motion = wall_motion(terrain)
    if motion is None:
        return terrain, ""
    rot, t = motion
    try:
        turned = terrain.moved(rot, t)
    except ValueError:  # a box the turn would take off the axes
        return terrain, ("the wall is not the plane y = 0 climbed from +y, and its box surfaces cannot be turned "
                         "into that frame (boxes are axis-aligned): write the terrain in the convention "
                         "(docs/terrain.md)")
    angle = math.degrees(math.acos(max(-1.0, min(1.0, (float(np.trace(rot)) - 1.0) / 2.0))))
    what = f"turned by {angle:.0f} deg and moved {float(np.linalg.norm(t)):.2f} m" if angle > 1e-6 else \
        f"moved {float(np.linalg.norm(t)):.2f} m"
    rise = float(t @ (rot @ terrain.up))
    heights = "heights along minus gravity unchanged" if abs(rise) < 1e-9 else \
        f"heights along minus gravity {rise:+.3f} m (a --goal-height is in the new heights)"
    return turned, (f"turned into the wall frame (the wall the plane y = 0 climbed from +y; {heights}): the "
                    f"terrain was {what}, recorded as the terrain's frame")


#: The holds span a wall when the spread of their positions across the best-fitting plane is at most this
#: fraction of their spread along its second axis (a wall of holds a few centimetres proud of it, not a ladder's
#: line of rungs or a cloud).
WALL_FLATNESS = 0.25


def wall_normal(terrain: Terrain) -> np.ndarray:
    """The terrain's wall normal: its first plane surface; else the normal of the plane that best fits the holds'
    positions when they span one (:data:`WALL_FLATNESS`), turned out of the wall (towards the holds' mean normal
    made horizontal); else that mean normal itself.

    The fit follows the wall whichever way gravity points: an overhang written by tilting gravity about a wall of
    holds in the plane ``y = 0`` (the convention, docs/terrain.md) has the wall normal ``+y``, where the holds'
    mean normal made horizontal, across the tilted gravity, leans by the tilt."""
    for srf in terrain.surfaces:
        if srf.type == "plane" and srf.normal is not None:
            return np.asarray(srf.normal, dtype=float)
    mean = np.mean([h.n for h in terrain.holds], axis=0)
    n = mean - (mean @ terrain.up) * terrain.up
    n = n / np.linalg.norm(n) if np.linalg.norm(n) > 1e-9 else np.array([0.0, 1.0, 0.0])
    pos = np.asarray([h.p for h in terrain.holds], dtype=float)
    if len(pos) >= 3:
        _, spread, axes = np.linalg.svd(pos - pos.mean(axis=0), full_matrices=False)
        if len(spread) == 3 and spread[1] > 1e-9 and spread[2] <= WALL_FLATNESS * spread[1]:
            fit = np.asarray(axes[2], dtype=float)
            # out of the wall: towards the holds' normals made horizontal, or on a level floor (none is
            # horizontal) towards the normals themselves
            side = float(fit @ n) if abs(float(fit @ n)) > 1e-9 else float(fit @ mean)
            return fit if side >= 0.0 else -fit
    return n
