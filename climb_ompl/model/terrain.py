"""Holds, terrains and their YAML files; a seeded generator of climbing walls.

Conventions (one frame for every robot):

* World frame: ``z`` up (against gravity on an untilted wall), ``x`` horizontal along the wall.
* 2-D terrains (planar robots: Bretl, Latombe & Rock (2003); Bretl (2006)) live in the ``x``-``z`` plane: every vector
  of a 2-D file is written ``[x, z]`` and stored as the 3-vector ``(x, 0, z)``.
* 3-D walls are the plane ``y = 0`` with the climbing side towards ``+y`` (the wall's outward normal is
  ``+y``).  A tilted wall (slab or overhang) is expressed by tilting the *gravity* vector, not the wall,
  so robots whose base moves in the wall plane (LEMUR, Bretl et al. (2004)) need no change of frame.

A hold's ``normal`` points out of the hold's surface, towards the robot: a contact force pushes the
robot along it (Bretl, Latombe & Rock (2003), section 2.2).  ``friction`` is Coulomb's coefficient
(Bretl, Latombe & Rock (2003), Eq. 1). Contact ``type``: ``friction`` (a Coulomb cone), ``grasp`` (a peg held
in a gripper: any force up to ``max_force``, the double-link robot of Bretl (2006)) or ``adhesion`` (a Coulomb
cone shifted by a pull of at most ``max_force``: suction feet, Kim, Kang & Choi (MRWALLSPECT III)).

File format (YAML), documented in ``docs/terrain.md``::

    name: demo-wall
    description: free text        # optional, not part of the content hash
    dim: 3                        # 3 (walls) or 2 (planar robots, x-z plane); default 3
    gravity: [0, 0, -9.81]        # m/s^2; 2-D: [gx, gz]; default straight down
    friction: 1.0                 # default Coulomb coefficient of the holds; default 1.0
    holds:
      - id: h0
        position: [0.1, 0.0, 0.5]     # m; 2-D: [x, z]
        normal: [0.0, 0.7, 0.7]       # normalised on load; must be non-zero
        friction: 0.9                 # optional
        type: friction                # optional: friction | grasp | adhesion
        max_force: 50.0               # N; required for grasp and adhesion, refused for friction
    surfaces:                     # optional, for collision and drawing
      - {type: plane, point: [0, 0, 0], normal: [0, 1, 0], size: [3, 3]}  # 2-D: a line, [x, z], size [length]
      - {type: box, center: [0, 0.1, 1], size: [0.2, 0.2, 0.2]}          # 3-D only, axis-aligned
      - {type: circle, center: [0.5, 0.5], radius: 0.1}                  # 2-D only: a disc in x-z

A plane is a half-space for collision: the side its normal points to is free.  Every field is checked on
load; a bad one raises :class:`~climb_ompl.errors.TerrainError` naming the file, the field (e.g.
``holds[3].normal``) and the reason.
"""

from __future__ import annotations

import hashlib
import json
import math
import reprlib
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property
from pathlib import Path
from typing import Any, Literal

import numpy as np
import yaml

from climb_ompl._io import load_yaml, number_hint
from climb_ompl.errors import InputError, TerrainError
from climb_ompl.model.wall_frame import HOLD_OFFSET, PLANE_TOLERANCE_DEG, frame_of, to_wall_frame, wall_normal
from climb_ompl.resources import bundled, resolve, terrains_dir

ContactType = Literal["friction", "grasp", "adhesion"]

#: :meth:`Terrain.convention_notes`: a wall plane whose normal is farther than :data:`PLANE_TOLERANCE_DEG` from
#: ``+y`` (degrees), and holds or a plane farther than :data:`HOLD_OFFSET` from ``y = 0`` (metres), are noted as
#: departures from the frame convention (both in :mod:`climb_ompl.model.wall_frame`).
#: ... and a hold whose unit normal has a component along the wall normal below this (pointing into the wall).
INTO_WALL = -0.1
#: ... and holds whose median distance to their nearest neighbour exceeds this (metres): a file in millimetres?
SCALE_SUSPECT = 5.0
#: ... and holds whose friction coefficient exceeds this: a percentage?
FRICTION_SUSPECT = 5.0
CONTACT_TYPES: tuple[str, ...] = ("friction", "grasp", "adhesion")
SURFACE_TYPES: tuple[str, ...] = ("plane", "box", "circle")
#: Surface types allowed per terrain dimension.
SURFACES_BY_DIM: dict[int, tuple[str, ...]] = {2: ("plane", "circle"), 3: ("plane", "box")}

#: Why a ``friction`` hold refuses ``max_force``: the equilibrium tests would ignore it.
FRICTION_MAX_FORCE = ("a friction hold takes no max_force (its force is bounded only by its friction cone and the "
                      "robot's torque limits; hold strength is not modelled): remove it, or give the hold "
                      "type: grasp or type: adhesion")

# A normal closer than this to unit length is kept as written, so that writing and re-reading a terrain
# gives bit-identical numbers (and the same content hash).
_UNIT_TOL = 1e-9


#: Largest magnitude of a number in a terrain file (a coordinate in metres, a friction coefficient, a force in
#: newtons): a hold 1e308 m away is finite, but the geometry computed from it is not.
MAX_MAGNITUDE = 1e9


def _vec3(value: Any, src: str, fld: str) -> tuple[float, float, float]:
    """A finite 3-vector as a tuple of floats (for values built in Python, not read from files)."""
    try:
        arr = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise TerrainError(src, fld, f"expected 3 numbers, got {value!r}") from None
    if arr.shape != (3,) or not np.all(np.isfinite(arr)):
        raise TerrainError(src, fld, f"expected 3 finite numbers, got {value!r}")
    return (float(arr[0]), float(arr[1]), float(arr[2]))


def _unit3(value: Any, src: str, fld: str) -> tuple[float, float, float]:
    v = np.array(_vec3(value, src, fld))
    big = float(np.max(np.abs(v)))
    if big > 1e100:  # only the direction matters: scaled first, so that the length does not overflow
        v = v / big
    n = float(np.linalg.norm(v))
    if n < 1e-9:
        raise TerrainError(src, fld, "zero normal (a normal must have non-zero length)")
    if abs(n - 1.0) > _UNIT_TOL:
        v = v / n
    return (float(v[0]), float(v[1]), float(v[2]))


def plane_axes(normal: Any) -> np.ndarray:
    """3x3 rotation whose columns are a 3-D plane's in-plane axes and its unit normal: the axes a plane surface's
    ``size`` (width, height) runs along.  Width runs along world ``x`` projected onto the plane (world ``y`` where
    ``x`` is all but normal to it), height along ``normal x width``: on a vertical wall with normal ``+y``, width
    along ``x`` and height along ``z``; on a ramp rising along ``x``, width up the slope and height across it."""
    n = np.asarray(normal, dtype=float)
    n = n / np.linalg.norm(n)
    ref = np.array([1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.array([0.0, 1.0, 0.0])
    x = ref - (ref @ n) * n
    x /= np.linalg.norm(x)
    return np.column_stack([x, np.cross(n, x), n])


def _turned_size(s: Surface, rot: np.ndarray) -> tuple[float, ...] | None:
    """A 3-D plane's ``size`` once ``rot`` turns it: (width, height) swapped when the turned plane's width axis
    (:func:`plane_axes`) runs along what was its height."""
    if s.type != "plane" or s.size is None or len(s.size) != 2 or s.normal is None:
        return s.size
    was = rot @ plane_axes(s.normal)[:, 0]
    now = plane_axes(rot @ np.asarray(s.normal, dtype=float))[:, 0]
    return s.size if abs(float(was @ now)) >= 0.5 ** 0.5 else (s.size[1], s.size[0])


def _box_axes(rot: np.ndarray) -> np.ndarray | None:
    """The permutation of axes ``rot`` maps boxes' axes by (an axis-aligned box stays one), or ``None``."""
    a = np.abs(rot)
    if not np.allclose(a, np.round(a), atol=1e-9):
        return None
    return np.argmax(a, axis=1)



def _read_only(a: np.ndarray) -> np.ndarray:
    """``a``, no longer writeable: a cached array shared by every caller."""
    a.flags.writeable = False
    return a


@dataclass(frozen=True)
class Hold:
    """A point where a hand may touch the terrain.

    Built from a file or directly; either way the fields are checked and coerced (tuples of floats,
    unit normal).

    Attributes:
        id: unique name within the terrain.
        position: contact point in the world frame, metres (3-vector).
        normal: unit outward surface normal at the hold (3-vector, world frame); normalised on creation.
        friction: Coulomb friction coefficient, >= 0.
        type: ``friction``, ``grasp`` or ``adhesion`` (see module docstring).
        max_force: force bound in newtons (> 0), required for ``grasp``/``adhesion`` contacts and refused on
            ``friction`` contacts (a Coulomb cone has no force bound: a hold's strength is not modelled, and a
            bound that was silently ignored would mislead).

    Raises:
        TerrainError: a field is invalid (zero normal, negative friction, unknown type, ...).
    """

    id: str
    position: tuple[float, float, float]
    normal: tuple[float, float, float]
    friction: float = 1.0
    type: ContactType = "friction"
    max_force: float | None = None

    def __post_init__(self) -> None:
        src = f"<hold {self.id!r}>"
        if not isinstance(self.id, str) or not self.id:
            raise TerrainError(src, "id", f"expected a non-empty string, got {self.id!r}")
        object.__setattr__(self, "position", _vec3(self.position, src, "position"))
        object.__setattr__(self, "normal", _unit3(self.normal, src, "normal"))
        mu = self.friction
        if isinstance(mu, bool) or not isinstance(mu, (int, float, np.floating)) or not math.isfinite(mu) or mu < 0:
            raise TerrainError(src, "friction", f"must be a finite number >= 0, got {mu!r}")
        object.__setattr__(self, "friction", float(mu))
        if self.type not in CONTACT_TYPES:
            raise TerrainError(src, "type", f"must be one of {', '.join(CONTACT_TYPES)}, got {self.type!r}")
        fmax = self.max_force
        if fmax is not None and self.type == "friction":
            raise TerrainError(src, "max_force", FRICTION_MAX_FORCE)
        if fmax is None:
            if self.type != "friction":
                raise TerrainError(src, "max_force", f"required for a {self.type} contact")
        elif isinstance(fmax, bool) or not isinstance(fmax, (int, float, np.floating)) or not fmax > 0 \
                or not math.isfinite(fmax):
            raise TerrainError(src, "max_force", f"must be a finite number > 0, got {fmax!r}")
        else:
            object.__setattr__(self, "max_force", float(fmax))

    @property
    def p(self) -> np.ndarray:
        """Position as a numpy array (metres)."""
        return np.asarray(self.position, dtype=float)

    @property
    def n(self) -> np.ndarray:
        """Unit normal as a numpy array."""
        return np.asarray(self.normal, dtype=float)


@dataclass(frozen=True)
class Surface:
    """A terrain surface for collision and drawing.

    ``plane``: a half-space through ``center`` (the file's ``point``) with unit outward ``normal``, drawn
    as a rectangle of ``size`` (width, height) in 3-D or a segment of ``size`` (length,) in 2-D, metres.
    ``box``: ``center``, full ``size`` (3-vector), axis-aligned (3-D terrains only).
    ``circle``: 2-D disc obstacle in the x-z plane, ``center`` (3-vector, y = 0) and ``radius``.
    """

    type: str
    center: tuple[float, float, float]
    normal: tuple[float, float, float] | None = None
    size: tuple[float, ...] | None = None
    radius: float | None = None


@dataclass(frozen=True)
class Terrain:
    """A climbing terrain: gravity, holds and surfaces.

    Attributes:
        name: terrain name.
        dim: 2 (planar robots, x-z plane) or 3.
        gravity: gravity vector, m/s^2, world frame (3-vector).
        holds: the holds, in file order.
        surfaces: collision/drawing surfaces.
        source: the file it was read from, or ``"<generated>"``/``"<dict>"``.
        description: free text (where the terrain comes from, how it was made); not part of
            :meth:`content_hash`.
        frame: ``None``, or the rigid motion that took the file's coordinates to these, as a 3 x 4 matrix
            ``[R | t]`` (a file's point ``p`` is ``R @ p + t`` here; written by :meth:`in_wall_frame`).

    Raises:
        TerrainError: ``dim`` is not 2 or 3, gravity is zero, two holds share an id, or a 2-D terrain
            has a hold off the x-z plane.
    """

    name: str
    dim: int
    gravity: tuple[float, float, float]
    holds: tuple[Hold, ...]
    surfaces: tuple[Surface, ...] = ()
    source: str = field(default="<dict>", compare=False)
    description: str = field(default="", compare=False)
    frame: tuple[tuple[float, ...], ...] | None = None

    def __post_init__(self) -> None:
        src = str(self.source)
        if self.dim not in (2, 3) or isinstance(self.dim, bool):
            raise TerrainError(src, "dim", f"must be 2 or 3, got {self.dim!r}")
        g = _vec3(self.gravity, src, "gravity")
        if math.hypot(*g) < 1e-9:
            raise TerrainError(src, "gravity", "zero gravity vector")
        object.__setattr__(self, "gravity", g)
        object.__setattr__(self, "holds", tuple(self.holds))
        object.__setattr__(self, "surfaces", tuple(self.surfaces))
        seen: set[str] = set()
        for i, h in enumerate(self.holds):
            if h.id in seen:
                raise TerrainError(src, f"holds[{i}].id", f"duplicate hold id {h.id!r}")
            seen.add(h.id)
            if self.dim == 2 and (h.position[1] != 0.0 or h.normal[1] != 0.0):
                raise TerrainError(src, f"holds[{i}]", "a 2-D terrain's holds must lie in the x-z plane (y = 0)")

    # ---- access -------------------------------------------------------------------------------
    def hold(self, hold_id: str) -> Hold:
        """The hold named ``hold_id``.

        Raises:
            TerrainError: no such hold.
        """
        try:
            return self._by_id[hold_id]
        except (KeyError, TypeError):
            raise TerrainError(self.source, "holds", self.no_hold(hold_id)) from None

    def no_hold(self, hold_id: object) -> str:
        """``no hold 'x' in terrain 'name'``, with the id ``hold_id`` most likely meant (``g12-5`` for ``g12_5``)."""
        from climb_ompl.errors import nearest_name

        near = nearest_name(hold_id, self.hold_ids)
        return f"no hold {hold_id!r} in terrain {self.name!r}" + (f" (did you mean {near!r}?)" if near else "")

    @cached_property
    def _by_id(self) -> dict[str, Hold]:
        return {h.id: h for h in self.holds}

    @cached_property
    def hold_ids(self) -> tuple[str, ...]:
        """Hold ids in file order."""
        return tuple(h.id for h in self.holds)

    @cached_property
    def hold_index(self) -> dict[str, int]:
        """Each hold id's place in file order (the row of :attr:`positions`)."""
        return {h: i for i, h in enumerate(self.hold_ids)}

    @cached_property
    def positions(self) -> np.ndarray:
        """``(n_holds, 3)`` array of hold positions, metres (read-only)."""
        return _read_only(np.array([h.position for h in self.holds], dtype=float).reshape(-1, 3))

    @property
    def g(self) -> np.ndarray:
        """Gravity as a numpy array, m/s^2."""
        return np.asarray(self.gravity, dtype=float)

    @cached_property
    def up(self) -> np.ndarray:
        """Unit vector against gravity (read-only)."""
        return _read_only(-self.g / np.linalg.norm(self.g))

    @cached_property
    def _heights(self) -> dict[str, float]:
        return {h.id: float(h.p @ self.up) for h in self.holds}

    def height(self, where: str | Hold | Sequence[float]) -> float:
        """Height of a hold (by id or itself) or a point along :attr:`up`, metres: "up" is minus gravity, so
        on a wall whose gravity is tilted (a slab, an overhang, a ramp) heights follow gravity, not ``z``."""
        if isinstance(where, str):
            known = self._heights.get(where)
            if known is not None:
                return known
            where = self.hold(where)
        p = where.p if isinstance(where, Hold) else np.asarray(where, dtype=float).reshape(3)
        return float(p @ self.up)

    # ---- (de)serialisation ----------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The terrain as a plain dict in the file format (3-D or 2-D coordinates as ``dim`` says)."""

        def vec(v: Sequence[float]) -> list[float]:
            return [float(v[0]), float(v[2])] if self.dim == 2 else [float(x) for x in v]

        holds = []
        for h in self.holds:
            d: dict[str, Any] = {"id": h.id, "position": vec(h.position), "normal": vec(h.normal),
                                 "friction": h.friction}
            if h.type != "friction":
                d["type"] = h.type
            if h.max_force is not None:
                d["max_force"] = h.max_force
            holds.append(d)
        surfaces = []
        for s in self.surfaces:
            d = {"type": s.type}
            if s.type == "circle":
                d.update(center=vec(s.center), radius=float(s.radius or 0.0))
            elif s.type == "plane":
                d.update(point=vec(s.center), normal=vec(s.normal or (0.0, 0.0, 0.0)))
                if s.size is not None:
                    d["size"] = [float(x) for x in s.size]
            else:
                d.update(center=[float(x) for x in s.center], size=[float(x) for x in s.size or ()])
            surfaces.append(d)
        out: dict[str, Any] = {"name": self.name}
        if self.description:
            out["description"] = self.description
        out.update(dim=self.dim, gravity=vec(self.gravity), holds=holds, surfaces=surfaces)
        if self.frame is not None:
            m = np.asarray(self.frame, dtype=float)
            out["frame"] = {"rotation": m[:, :3].tolist(), "translation": m[:, 3].tolist()}
        return out

    def in_wall_frame(self) -> Terrain:
        """This terrain turned, gravity and all, into the frame the robot specs expect (the wall the plane
        ``y = 0`` climbed from ``+y``, the climb up ``+z``; heights unchanged), with the motion recorded as
        :attr:`frame`; itself when it already follows the convention (:mod:`climb_ompl.model.wall_frame`)."""
        return to_wall_frame(self)[0]

    def moved(self, rot: np.ndarray, t: np.ndarray) -> Terrain:
        """This terrain under the rigid motion ``p -> rot @ p + t`` (gravity, holds, surfaces), the motion composed into
        its recorded :attr:`frame`.  A plan's own frame applied to the user's file gives
        back the terrain the plan embeds (``verify --terrain FILE``), whatever
        :func:`~climb_ompl.model.wall_frame.wall_motion` would find today.

        Raises:
            ValueError: the terrain has a box surface that ``rot`` would turn off the axes.
        """
        perm = _box_axes(rot)
        if perm is None and any(s.type == "box" for s in self.surfaces):
            raise ValueError("a box surface cannot be turned off the axes")
        old_r, old_t = frame_of(self)  # motions compose: file -> (recorded frame) -> wall frame

        def pt(p: Any) -> tuple[float, float, float]:
            return tuple(float(x) for x in rot @ np.asarray(p, dtype=float) + t)  # type: ignore[return-value]

        def vec(v: Any) -> tuple[float, float, float]:
            return tuple(float(x) for x in rot @ np.asarray(v, dtype=float))  # type: ignore[return-value]

        holds = tuple(Hold(h.id, pt(h.position), vec(h.normal), h.friction, h.type, h.max_force) for h in self.holds)
        surfaces = []
        for s in self.surfaces:
            if s.type == "box" and perm is not None and s.size is not None:
                size = tuple(float(s.size[int(j)]) for j in perm)
                surfaces.append(Surface("box", pt(s.center), size=size))
            else:
                surfaces.append(Surface(s.type, pt(s.center), None if s.normal is None else vec(s.normal),
                                        _turned_size(s, rot), s.radius))
        frame = np.hstack([rot @ old_r, (rot @ old_t + t)[:, None]])
        return Terrain(self.name, 3, vec(self.gravity), holds, tuple(surfaces), self.source,
                       self.description, tuple(tuple(float(x) for x in row) for row in frame))

    def hold_spacing(self) -> float | None:
        """Median distance of a hold to its nearest neighbour, metres (``None`` with fewer than two holds)."""
        if len(self.holds) < 2:
            return None
        from scipy.spatial import cKDTree

        d, _ = cKDTree(self.positions).query(self.positions, k=2)
        return float(np.median(d[:, 1]))

    def scale_note(self) -> str | None:
        """A sentence when the holds lie further apart than any climbing robot reaches (:data:`SCALE_SUSPECT`):
        positions written in millimetres or centimetres are read as metres."""
        spacing = self.hold_spacing()
        if spacing is None or spacing <= SCALE_SUSPECT:
            return None
        return (f"holds: neighbouring holds lie a median {spacing:.3g} m apart; positions are in metres (a file "
                "written in millimetres or centimetres needs its positions divided by 1000 or 100)")

    def friction_note(self) -> str | None:
        """A sentence when holds have a friction coefficient above :data:`FRICTION_SUSPECT` (a percentage?)."""
        mu = np.array([h.friction for h in self.holds], dtype=float)
        high = int(np.sum(mu > FRICTION_SUSPECT))
        if not high:
            return None
        return (f"holds: a friction coefficient above {FRICTION_SUSPECT:g} on {high} of {len(self.holds)} (up to "
                f"{mu.max():.3g}); a coefficient is a ratio of forces (rubber on rock about 0.6-1.2): a percentage "
                "needs dividing by 100")

    def gravity_note(self) -> str | None:
        """A sentence when gravity points up the file's last axis and most holds face down along it (a ceiling
        climbed from below, or a gravity written with the wrong sign).  Judged in the file's coordinates: a terrain
        turned into the wall frame is turned back by its recorded :attr:`frame`."""
        rot = self._file_rotation()
        g = rot.T @ np.asarray(self.gravity, dtype=float)  # 3-D (a planar terrain's file y is z)
        n = np.array([h.n for h in self.holds], dtype=float).reshape(-1, 3) @ rot
        if not len(n) or g[2] <= 0.5 * float(np.linalg.norm(g)):
            return None
        down = int(np.sum(n @ g > 0))
        if 2 * down <= len(n):
            return None
        shown = np.round(g if self.dim == 3 else g[[0, 2]], 9) + 0.0  # (a 2-D file writes [x, z]; no turn's dust)
        return (f"gravity: ({', '.join(f'{v:.3g}' for v in shown)}) points along +z, and {down} of {len(n)} hold "
                f"normals face down along it (the robot would hang from a ceiling); gravity is the acceleration "
                f"of a falling body: with z up it is ({'0, 0' if self.dim == 3 else '0'}, -9.81)")

    def _file_rotation(self) -> np.ndarray:
        """The rotation from the file's coordinates to these (the recorded :attr:`frame`'s; identity when unturned)."""
        return np.asarray(self.frame, dtype=float)[:, :3] if self.frame is not None else np.eye(3)

    def convention_notes(self) -> list[str]:
        """Where a 3-D terrain departs from the frame convention (the wall is the plane ``y = 0``, climbed from
        ``+y``; a slope is a tilted gravity): the file loads, but the robot specs expect the convention (LEMUR's
        base moves only in that plane, the quadrupeds' base bounds measure the stand-off from it), so a climb
        on it may find no start or stall.  One sentence per departure; empty when it follows the convention.
        """
        first = [x for x in (self.scale_note(), self.gravity_note(), self.friction_note()) if x]
        if self.dim != 3:
            return first
        out: list[str] = []
        planes = [s for s in self.surfaces if s.type == "plane" and s.normal is not None]
        where = f"surfaces[{self.surfaces.index(planes[0])}]: the wall plane's normal" if planes else \
            "holds: the normal of the wall they lie on"
        n = np.asarray(wall_normal(self), dtype=float) + 0.0  # (a terrain has at least one hold; + 0.0: no "-0")
        norm = float(np.linalg.norm(n))
        tilt = math.degrees(math.acos(max(-1.0, min(1.0, float(n[1]) / norm)))) if norm > 0 else 180.0
        if tilt > PLANE_TOLERANCE_DEG:
            out.append(f"{where} ({n[0]:.3g}, {n[1]:.3g}, {n[2]:.3g}) is {tilt:.0f} deg from +y")
        elif planes and abs(float(planes[0].center[1])) > HOLD_OFFSET:
            out.append(f"surfaces[{self.surfaces.index(planes[0])}]: the wall plane lies at "
                       f"y = {planes[0].center[1]:.3g}, not y = 0")
        y = self.positions[:, 1]
        far = int(np.sum(np.abs(y) > HOLD_OFFSET))
        if far:
            out.append(f"holds: {far} of {len(y)} lie more than {HOLD_OFFSET} m off the plane y = 0 "
                       f"(y from {y.min():.3g} to {y.max():.3g})")
        if out:
            out.append("3-D walls are the plane y = 0 climbed from +y, and a slab or an overhang is written by "
                       "tilting gravity (docs/terrain.md; the bundled terrain slab): the robot specs "
                       "expect it, and plan turns such a terrain into that frame (Terrain.in_wall_frame)")
        out = first + out
        into = _into_wall(self.holds, n / norm) if norm > 0 else []
        rot = self._file_rotation()
        if into:  # shown as the file gives them (a terrain turned into the wall frame records its frame)
            shown = ", ".join(f"{h.id} ({', '.join(f'{v:.3g}' for v in rot.T @ h.n + 0.0)})" for h in into[:4])
            out.append(f"holds: the normal of {len(into)} hold(s) points into the wall: {shown}"
                       f"{' ...' if len(into) > 4 else ''}; a normal points out of the rock towards the robot (into "
                       "the wall only on the back of a flake)")
        return out

    def content_hash(self) -> str:
        """SHA-256 of the canonical JSON of :meth:`to_dict` without ``description``.

        Identifies the terrain in plan files: equal for equal geometry (and recorded frame,
        :attr:`frame`), whatever file it came from.
        """
        d = self.to_dict()
        d.pop("description", None)
        blob = json.dumps(d, sort_keys=True, separators=(",", ":")).encode()
        return hashlib.sha256(blob).hexdigest()

    def to_yaml(self) -> str:
        """The terrain as YAML text in the file format (reads back to an equal terrain)."""
        return yaml.safe_dump(self.to_dict(), sort_keys=False, default_flow_style=None, width=100)

    @classmethod
    def from_dict(cls, data: Any, source: str = "<dict>") -> Terrain:
        """Build and validate a terrain from a dict in the file format.

        Raises:
            TerrainError: naming ``source``, the field and the reason.
        """
        return _parse(data, str(source))

    @classmethod
    def load(cls, name_or_path: str | Path) -> Terrain:
        """Load a bundled terrain by name (``"demo-wall"``) or a terrain file by path.

        Raises:
            TerrainError: the file is missing, not YAML, or malformed.
        """
        try:
            path = resolve(name_or_path, terrains_dir(), "terrain")
        except InputError as exc:
            raise TerrainError(exc.path, exc.field, exc.reason) from None
        return _parse(load_yaml(path, TerrainError), str(path))


def bundled_terrains() -> list[str]:
    """Names of the terrains shipped with the package (sorted)."""
    return bundled(terrains_dir())


# ---- validation of the file format ----------------------------------------------------------------
def _vec(value: Any, dim: int, src: str, fld: str, bounded: bool = True) -> np.ndarray:
    """A ``dim``-vector from a file, as a 3-vector (2-D ``[x, z]`` becomes ``(x, 0, z)``); ``bounded``: every
    component within :data:`MAX_MAGNITUDE` (a position; a direction may be written as long as it likes)."""
    if value is None:
        raise TerrainError(src, fld, "missing required field")
    if not isinstance(value, (list, tuple)) or len(value) != dim:
        raise TerrainError(src, fld, f"expected a list of {dim} numbers ({dim}-D terrain), got {value!r}")
    if any(isinstance(x, bool) or not isinstance(x, (int, float)) for x in value):
        hint = next((number_hint(x) for x in value if number_hint(x)), "")
        raise TerrainError(src, fld, f"expected numbers, got {value!r}{hint}")
    try:
        arr = np.array([float(x) for x in value], dtype=float)
    except OverflowError:
        arr = np.array([math.inf])
    if not np.all(np.isfinite(arr)):
        raise TerrainError(src, fld, f"non-finite value in {reprlib.repr(value)}")
    if bounded and float(np.max(np.abs(arr))) > MAX_MAGNITUDE:
        raise TerrainError(src, fld, f"a value beyond {MAX_MAGNITUDE:g} in {reprlib.repr(value)} (lengths are in "
                           "metres)")
    if dim == 2:
        arr = np.array([arr[0], 0.0, arr[1]])
    return arr


def _num(value: Any, src: str, fld: str, minimum: float | None = None, strict: bool = False) -> float:
    if value is None:
        raise TerrainError(src, fld, "missing required field")
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TerrainError(src, fld, f"expected a number, got {value!r}{number_hint(value)}")
    try:
        x = float(value)
    except OverflowError:
        x = math.inf
    if not math.isfinite(x):
        raise TerrainError(src, fld, f"non-finite value {reprlib.repr(value)}")
    if abs(x) > MAX_MAGNITUDE:
        raise TerrainError(src, fld, f"{reprlib.repr(value)} is beyond {MAX_MAGNITUDE:g} (lengths are in metres, "
                           "forces in newtons)")
    if minimum is not None and (x <= minimum if strict else x < minimum):
        raise TerrainError(src, fld, f"must be {'>' if strict else '>='} {minimum:g}, got {value!r}")
    return x


def _keys(d: dict[str, Any], allowed: set[str], src: str, prefix: str) -> None:
    unknown = sorted(str(k) for k in set(d) - allowed)
    if unknown:
        raise TerrainError(src, f"{prefix}{unknown[0]}", f"unknown field; known fields: {', '.join(sorted(allowed))}")


def _parse(data: Any, src: str) -> Terrain:
    if not isinstance(data, dict):
        raise TerrainError(src, "(top level)", "expected a mapping with name, dim, gravity, holds")
    _keys(data, {"name", "dim", "gravity", "friction", "holds", "surfaces", "description", "frame"}, src, "")
    for key in ("name", "holds"):
        if key not in data:
            raise TerrainError(src, key, "missing required field")
    name = data["name"]
    if not isinstance(name, str) or not name:
        raise TerrainError(src, "name", "must be a non-empty string")
    description = data.get("description", "") or ""
    if not isinstance(description, str):
        raise TerrainError(src, "description", "must be a string")
    dim = data.get("dim", 3)
    if isinstance(dim, bool) or dim not in (2, 3):
        raise TerrainError(src, "dim", f"must be 2 or 3, got {dim!r}")
    dim = int(dim)
    g = _vec(data.get("gravity", [0.0, -9.81] if dim == 2 else [0.0, 0.0, -9.81]), dim, src, "gravity", False)
    if not float(np.max(np.abs(g))) < 1e6:
        raise TerrainError(src, "gravity", f"implausible magnitude (components up to {float(np.max(np.abs(g))):.3g} "
                           "m/s^2; Earth's is 9.81)")
    if np.linalg.norm(g) < 1e-9:
        raise TerrainError(src, "gravity", "zero gravity vector")
    default_mu = _num(data.get("friction", 1.0), src, "friction", minimum=0.0)
    raw_holds = data["holds"]
    if not isinstance(raw_holds, list) or not raw_holds:
        raise TerrainError(src, "holds", "expected a non-empty list of holds")
    holds: list[Hold] = []
    seen: set[str] = set()
    for i, h in enumerate(raw_holds):
        f = f"holds[{i}]"
        if not isinstance(h, dict):
            raise TerrainError(src, f, "expected a mapping with id, position, normal")
        _keys(h, {"id", "position", "normal", "friction", "type", "max_force"}, src, f"{f}.")
        for key in ("id", "position", "normal"):
            if key not in h:
                raise TerrainError(src, f"{f}.{key}", "missing required field")
        hid = h["id"]
        if isinstance(hid, bool) or not isinstance(hid, (str, int)) or hid == "":
            raise TerrainError(src, f"{f}.id", f"expected a non-empty string, got {hid!r}")
        hid = str(hid)
        if any(c in hid for c in ",=") or not hid.isprintable() or hid != hid.strip():
            raise TerrainError(src, f"{f}.id", f"{hid!r}: a hold id is named on the command line in LIMB=HOLD pairs "
                               "separated by commas, so it may not hold ',' or '=', a line break or a tab, nor start "
                               "or end with a space")
        if hid in seen:
            raise TerrainError(src, f"{f}.id", f"duplicate hold id {hid!r}")
        seen.add(hid)
        try:
            holds.append(_hold(h, hid, dim, default_mu, src, f))
        except TerrainError as exc:  # the hold's id too: a list position is hard to find in a long file
            raise TerrainError(exc.path, exc.field, f"{exc.reason} (hold {hid!r})") from None
    surfaces = [_parse_surface(s, i, dim, src) for i, s in enumerate(_surface_list(data, src))]
    _check_wall_side(holds, surfaces, dim, src)
    if data.get("frame") is not None and dim != 3:
        raise TerrainError(src, "frame", "only a 3-D terrain is turned into the wall frame (a 2-D one is the x-z "
                           "plane)")
    frame = _frame(data["frame"], src) if data.get("frame") is not None else None
    return Terrain(name, dim, tuple(g), tuple(holds), tuple(surfaces), src, description,  # type: ignore[arg-type]
                   frame)


def _into_wall(holds: Sequence[Hold], normal: np.ndarray) -> list[Hold]:
    """The holds whose unit normal points into the wall of unit ``normal`` (component below :data:`INTO_WALL`)."""
    return [h for h in holds if float(np.asarray(h.normal, dtype=float) @ normal) < INTO_WALL]


def _check_wall_side(holds: list[Hold], surfaces: list[Surface], dim: int, src: str) -> None:
    """Refuse a 3-D wall plane whose normal opposes the normals of most holds: one of them is flipped, and the
    planner takes the plane's side for the robot's (a user's flipped plane sent LEMUR up the back of the wall)."""
    planes = [(i, s) for i, s in enumerate(surfaces) if s.type == "plane" and s.normal is not None]
    if dim != 3 or not planes:
        return
    i, plane = planes[0]
    into = len(_into_wall(holds, np.asarray(plane.normal, dtype=float)))
    if into > len(holds) / 2:
        raise TerrainError(src, f"surfaces[{i}].normal", f"the wall plane's normal and the normals of {into} of "
                           f"{len(holds)} holds point opposite ways, so one of them is flipped: a wall plane's normal "
                           "and a hold's point out of the wall, towards the robot")


def _frame(f: Any, src: str) -> tuple[tuple[float, ...], ...]:
    """The ``frame`` field (a rotation and a translation, :attr:`Terrain.frame`) as a 3 x 4 matrix."""
    if not isinstance(f, dict):
        raise TerrainError(src, "frame", "expected a mapping with rotation and translation")
    _keys(f, {"rotation", "translation"}, src, "frame.")
    rot = f.get("rotation")
    if not isinstance(rot, list) or len(rot) != 3:
        raise TerrainError(src, "frame.rotation", f"expected 3 rows of 3 numbers, got {rot!r}")
    r = np.array([_vec(row, 3, src, f"frame.rotation[{i}]") for i, row in enumerate(rot)])
    if not np.allclose(r @ r.T, np.eye(3), atol=1e-6) or np.linalg.det(r) < 0:
        raise TerrainError(src, "frame.rotation", "not a rotation (orthonormal rows, determinant +1)")
    t = _vec(f.get("translation"), 3, src, "frame.translation")
    return tuple(tuple(float(x) for x in row) for row in np.hstack([r, t[:, None]]))


def _hold(h: dict[str, Any], hid: str, dim: int, default_mu: float, src: str, f: str) -> Hold:
    """The hold ``hid`` of field ``f`` (its id already checked)."""
    pos = _vec(h["position"], dim, src, f"{f}.position")
    nrm = _unit3(_vec(h["normal"], dim, src, f"{f}.normal", False), src, f"{f}.normal")
    mu = _num(h.get("friction", default_mu), src, f"{f}.friction", minimum=0.0)
    ctype = h.get("type", "friction")
    if ctype not in CONTACT_TYPES:
        raise TerrainError(src, f"{f}.type", f"must be one of {', '.join(CONTACT_TYPES)}, got {ctype!r}")
    fmax = h.get("max_force")
    if fmax is not None and ctype == "friction":
        raise TerrainError(src, f"{f}.max_force", FRICTION_MAX_FORCE)
    if fmax is not None:
        fmax = _num(fmax, src, f"{f}.max_force", minimum=0.0, strict=True)
    elif ctype != "friction":
        raise TerrainError(src, f"{f}.max_force", f"required for a {ctype} contact")
    return Hold(hid, tuple(pos), nrm, mu, ctype, fmax)  # type: ignore[arg-type]


def _surface_list(data: dict[str, Any], src: str) -> list[Any]:
    raw = data.get("surfaces", []) or []
    if not isinstance(raw, list):
        raise TerrainError(src, "surfaces", "expected a list")
    return raw


def _parse_surface(s: Any, i: int, dim: int, src: str) -> Surface:
    f = f"surfaces[{i}]"
    if not isinstance(s, dict):
        raise TerrainError(src, f, "expected a mapping with a type")
    if "type" not in s:
        raise TerrainError(src, f"{f}.type", "missing required field")
    st = s["type"]
    if st not in SURFACES_BY_DIM[dim]:
        raise TerrainError(src, f"{f}.type",
                           f"must be one of {', '.join(SURFACES_BY_DIM[dim])} in a {dim}-D terrain, got {st!r}")
    if st == "circle":
        _keys(s, {"type", "center", "radius"}, src, f"{f}.")
        c = _vec(s.get("center"), 2, src, f"{f}.center")
        r = _num(s.get("radius"), src, f"{f}.radius", minimum=0.0, strict=True)
        return Surface("circle", tuple(c), radius=r)  # type: ignore[arg-type]
    if st == "plane":
        _keys(s, {"type", "point", "normal", "size"}, src, f"{f}.")
        c = _vec(s.get("point"), dim, src, f"{f}.point")
        n = _unit3(_vec(s.get("normal"), dim, src, f"{f}.normal", False), src, f"{f}.normal")
        size = s.get("size")
        size_t = None
        if size is not None:
            if not isinstance(size, list) or len(size) != dim - 1:
                want = "[length]" if dim == 2 else "[width, height]"
                raise TerrainError(src, f"{f}.size", f"expected {want}, got {size!r}")
            size_t = tuple(_num(x, src, f"{f}.size", minimum=0.0, strict=True) for x in size)
        return Surface("plane", tuple(c), normal=n, size=size_t)  # type: ignore[arg-type]
    _keys(s, {"type", "center", "size"}, src, f"{f}.")
    c = _vec(s.get("center"), 3, src, f"{f}.center")
    size3 = _vec(s.get("size"), 3, src, f"{f}.size")
    if np.any(size3 <= 0):
        raise TerrainError(src, f"{f}.size", "box sizes must be > 0")
    return Surface("box", tuple(c), size=tuple(float(x) for x in size3))  # type: ignore[arg-type]


# ---- generator ------------------------------------------------------------------------------------
#: Most holds :func:`generate_wall` makes (a 3 x 10 m wall at 5 cm spacing is 12261): a mistyped spacing is
#: refused instead of running for minutes.
MAX_GENERATED_HOLDS = 20000


#: Decimal places a generated hold normal's components are rounded to before it is made unit length again
#: (:func:`generate_wall`).
NORMAL_DECIMALS = 10


def stored_unit(v: Sequence[float]) -> tuple[float, float, float]:
    """The unit vector along ``v`` as :func:`generate_wall` stores it, the same on every machine: each component
    rounded to :data:`NORMAL_DECIMALS` decimal places (a last-bit difference in how ``v`` was computed, e.g. by
    another maths library's ``sin``, is rounded away), then divided by its length computed by correctly rounded
    scalar operations (``math.fsum``, ``math.sqrt``; no BLAS, whose sums depend on the CPU), so that it is unit to
    about 1e-16.  ``+ 0.0``: no ``-0.0`` in files."""
    r = [round(float(c), NORMAL_DECIMALS) for c in v]
    length = math.sqrt(math.fsum(c * c for c in r))
    return (r[0] / length + 0.0, r[1] / length + 0.0, r[2] / length + 0.0)


def generate_wall(
    seed: int = 0,
    *,
    width: float = 1.6,
    height: float = 3.0,
    spacing: float = 0.18,
    jitter: float = 0.4,
    friction: tuple[float, float] = (0.9, 1.2),
    tilt_deg: float = 0.0,
    normal_up_deg: tuple[float, float] = (55.0, 80.0),
    normal_side_deg: float = 20.0,
    name: str | None = None,
) -> Terrain:
    """A random climbing wall (3-D, the plane ``y = 0``), reproducible from ``seed``.

    Holds sit on a jittered grid (a gym wall's bolt pattern): about ``spacing`` metres apart,
    displaced by up to ``jitter * spacing``, numbered ``h0, h1, ...`` row by row from the bottom left.
    Each hold's normal leans from the wall normal ``+y`` upwards by an angle drawn from
    ``normal_up_deg`` and sideways by up to ``normal_side_deg`` (the top of a ledge: the holds of Bretl et al. (2004)
    are "small, artificial rock features" of arbitrary orientation).  The default lean, 55-80 degrees,
    makes friction-only stances feasible with the CoM a few centimetres off a vertical wall: with
    35-65 degrees only 18 % of LEMUR-like 3-hold stances hold a CoM 0.10 m off the wall, with 55-80
    degrees 70 % (docs/equilibrium.md, "Vertical walls"), and LEMUR's 2 m climb is
    found.  ``tilt_deg`` tilts the wall back
    (positive: a slab, easier) or over (negative: an overhang) by rotating gravity about ``x``.  The
    wall surface is a plane ``y = 0`` (normal ``+y``) drawn 0.3 m beyond the holds on each side.

    The file is the same wherever it is generated: the random draws depend only on the arguments (numpy's
    PCG64 stream, no hash-ordered containers), and what is stored is rounded, because the numbers computed
    from the draws (sines, cosines) may differ in the last bit between CPUs and maths libraries (SIMD and FMA
    code paths).  Positions are rounded to 1e-4 m (0.1 mm), the friction coefficients to 1e-3 and gravity to
    1e-6 m/s^2; each normal's components are rounded to 10 decimal places and the vector is then made unit length
    again by correctly rounded scalar operations (:func:`stored_unit`), which give the same bits on every IEEE 754
    machine.  Two machines can write different files only if a computed value lies within a last-bit error of a
    rounding boundary (about one chance in 10^6 per number).

    Args:
        seed: RNG seed (integer >= 0); the same seed gives the same wall.
        width: wall width in metres (hold grid spans ``x`` in [-width/2, width/2]).
        height: wall height in metres (hold grid spans ``z`` in [0, height]).
        spacing: mean hold spacing in metres (hold density ~ 1/spacing^2).
        jitter: grid jitter as a fraction of ``spacing`` (0 = regular grid), in [0, 0.5].
        friction: (low, high) range of Coulomb coefficients, drawn uniformly.
        tilt_deg: wall tilt from vertical, degrees, in (-90, 90).
        normal_up_deg: (low, high) range of the hold normals' upward lean, degrees, within [0, 90].
        normal_side_deg: maximal sideways lean of the hold normals, degrees, in [0, 90).
        name: terrain name (default ``wall-<seed>``).

    Raises:
        TerrainError: an argument is out of range (field ``generator.<argument>``).
    """
    src = "<generator>"

    def bad(arg: str, reason: str) -> TerrainError:
        return TerrainError(src, f"generator.{arg}", reason)

    if isinstance(seed, bool) or not isinstance(seed, (int, np.integer)) or seed < 0:
        raise bad("seed", f"must be an integer >= 0, got {seed!r}")
    for arg, val in (("width", width), ("height", height), ("spacing", spacing)):
        if not (math.isfinite(val) and val > 0):
            raise bad(arg, f"must be a finite number > 0 of metres, got {val!r}")
    cols, rows = width / spacing, height / spacing  # intervals of the grid (floats: a huge one does not overflow)
    n_holds = (cols + 1.0) * (rows + 1.0)
    if not n_holds <= MAX_GENERATED_HOLDS:
        raise bad("spacing", f"{spacing:g} m on a {width:g} x {height:g} m wall makes {n_holds:.3g} holds, more than "
                  f"{MAX_GENERATED_HOLDS}: give a larger spacing or a smaller wall")
    if name is not None and not str(name).strip():
        raise bad("name", "must not be empty (leave it out for wall-<seed>)")
    if not 0 <= jitter <= 0.5:
        raise bad("jitter", f"must be in [0, 0.5], got {jitter!r}")
    if not (len(friction) == 2 and 0 <= friction[0] <= friction[1] and math.isfinite(friction[1])):
        raise bad("friction", f"need 0 <= low <= high, got {friction!r}")
    if not -90 < tilt_deg < 90:
        raise bad("tilt_deg", f"must be in (-90, 90), got {tilt_deg!r}")
    if not (len(normal_up_deg) == 2 and 0 <= normal_up_deg[0] <= normal_up_deg[1] <= 90):
        raise bad("normal_up_deg", f"need 0 <= low <= high <= 90, got {normal_up_deg!r}")
    if not 0 <= normal_side_deg < 90:
        raise bad("normal_side_deg", f"must be in [0, 90), got {normal_side_deg!r}")
    rng = np.random.default_rng(int(seed))
    nx = max(1, int(round(cols)) + 1)
    nz = max(1, int(round(rows)) + 1)
    holds = []
    for iz in range(nz):
        for ix in range(nx):
            x = -width / 2 + ix * width / max(nx - 1, 1) + rng.uniform(-1, 1) * jitter * spacing
            z = iz * height / max(nz - 1, 1) + rng.uniform(-1, 1) * jitter * spacing
            up = math.radians(rng.uniform(*normal_up_deg))
            side = math.radians(rng.uniform(-normal_side_deg, normal_side_deg))
            mu = float(rng.uniform(*friction))
            holds.append(Hold(f"h{len(holds)}", (round(x, 4) + 0.0, 0.0, round(z, 4) + 0.0),
                              stored_unit((math.sin(side) * math.cos(up), math.cos(side) * math.cos(up),
                                           math.sin(up))), round(mu, 3)))
    t = math.radians(tilt_deg)
    g = (0.0, round(-9.81 * math.sin(t), 6) + 0.0, round(-9.81 * math.cos(t), 6) + 0.0)  # + 0.0: no -0.0 in files
    wall = Surface("plane", (0.0, 0.0, height / 2), normal=(0.0, 1.0, 0.0), size=(width + 0.6, height + 0.6))
    desc = (f"generate_wall(seed={int(seed)}, width={width:g}, height={height:g}, spacing={spacing:g}, "
            f"jitter={jitter:g}, friction=({friction[0]:g}, {friction[1]:g}), tilt_deg={tilt_deg:g}, "
            f"normal_up_deg=({normal_up_deg[0]:g}, {normal_up_deg[1]:g}), normal_side_deg={normal_side_deg:g})")
    return Terrain(name or f"wall-{int(seed)}", 3, g, tuple(holds), (wall,), "<generated>", desc)
