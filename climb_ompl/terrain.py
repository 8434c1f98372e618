"""Holds, terrains and their YAML files; a seeded generator of climbing walls.

Conventions (one frame for every robot):

* World frame: ``z`` up (against gravity on an untilted wall), ``x`` horizontal along the wall.
* 2-D terrains (planar robots, seeds 000/001) live in the ``x``-``z`` plane: a 2-D position ``[x, z]``
  is stored as the 3-vector ``(x, 0, z)``, a 2-D normal ``[nx, nz]`` as ``(nx, 0, nz)``.
* 3-D walls are the plane ``y = 0`` with the climbing side towards ``+y`` (the wall's outward normal is
  ``+y``).  A tilted wall (slab or overhang) is expressed by tilting the *gravity* vector, not the wall,
  so robots whose base moves in the wall plane (LEMUR, seed 002) need no change of frame.

A hold's ``normal`` points out of the hold's surface, towards the robot: a contact force pushes the
robot along it (seed 000 section 2.2).  ``friction`` is Coulomb's coefficient (seed 000 Eq. 1).
Contact ``type``: ``friction`` (a Coulomb cone), ``grasp`` (a peg held in a gripper: any force up to
``max_force``, seed 001's double-link robot) or ``adhesion`` (a Coulomb cone shifted by a pull of at
most ``max_force``: suction feet, seed 003).

File format (YAML), documented in the README::

    name: demo-wall
    dim: 3                      # 3 (walls) or 2 (planar robots, x-z plane)
    gravity: [0, 0, -9.81]      # m/s^2; 2-D: [gx, gz]
    friction: 1.0               # default Coulomb coefficient of the holds
    holds:
      - id: h0
        position: [0.1, 0.0, 0.5]     # m; 2-D: [x, z]
        normal: [0.0, 0.7, 0.7]       # normalised on load; must be non-zero
        friction: 0.9                 # optional
        type: friction                # optional: friction | grasp | adhesion
        max_force: 50.0               # N; required for grasp and adhesion
    surfaces:                   # optional, for collision and drawing
      - {type: plane, point: [0, 0, 0], normal: [0, 1, 0], size: [3, 3]}
      - {type: box, center: [0, 0.1, 1], size: [0.2, 0.2, 0.2]}
      - {type: circle, center: [0.5, 0.5], radius: 0.1}   # 2-D obstacle (a disc in x-z)
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Literal

import numpy as np
import yaml

from .errors import TerrainError
from .resources import bundled, resolve, terrains_dir

ContactType = Literal["friction", "grasp", "adhesion"]
CONTACT_TYPES: tuple[str, ...] = ("friction", "grasp", "adhesion")
SURFACE_TYPES: tuple[str, ...] = ("plane", "box", "circle")


@dataclass(frozen=True)
class Hold:
    """A point where a hand may touch the terrain.

    Attributes:
        id: unique name within the terrain.
        position: contact point in the world frame, metres (3-vector).
        normal: unit outward surface normal at the hold (3-vector, world frame).
        friction: Coulomb friction coefficient, >= 0.
        type: ``friction``, ``grasp`` or ``adhesion`` (see module docstring).
        max_force: force bound in newtons for ``grasp``/``adhesion`` contacts, else ``None``.
    """

    id: str
    position: tuple[float, float, float]
    normal: tuple[float, float, float]
    friction: float = 1.0
    type: ContactType = "friction"
    max_force: float | None = None

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

    ``plane``: ``point``, unit ``normal``, drawing ``size`` (width, height) in metres.
    ``box``: ``center``, full ``size`` (3-vector), axis-aligned.
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
    """

    name: str
    dim: int
    gravity: tuple[float, float, float]
    holds: tuple[Hold, ...]
    surfaces: tuple[Surface, ...] = ()
    source: str = field(default="<dict>", compare=False)

    # ---- access -------------------------------------------------------------------------------
    def hold(self, hold_id: str) -> Hold:
        """The hold named ``hold_id``.

        Raises:
            TerrainError: no such hold.
        """
        for h in self.holds:
            if h.id == hold_id:
                return h
        raise TerrainError(self.source, "holds", f"no hold with id {hold_id!r} in terrain {self.name!r}")

    @property
    def hold_ids(self) -> tuple[str, ...]:
        """Hold ids in file order."""
        return tuple(h.id for h in self.holds)

    @property
    def positions(self) -> np.ndarray:
        """``(n_holds, 3)`` array of hold positions."""
        return np.array([h.position for h in self.holds], dtype=float).reshape(-1, 3)

    @property
    def g(self) -> np.ndarray:
        """Gravity as a numpy array."""
        return np.asarray(self.gravity, dtype=float)

    @property
    def up(self) -> np.ndarray:
        """Unit vector against gravity."""
        return -self.g / np.linalg.norm(self.g)

    # ---- (de)serialisation ----------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The terrain as a plain dict in the file format (3-D or 2-D coordinates as ``dim`` says)."""

        def vec(v: tuple[float, ...]) -> list[float]:
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
                d.update(center=vec(s.center), radius=s.radius)
            elif s.type == "plane":
                d.update(point=[float(x) for x in s.center], normal=[float(x) for x in s.normal or ()])
                if s.size is not None:
                    d["size"] = [float(x) for x in s.size]
            else:
                d.update(center=[float(x) for x in s.center], size=[float(x) for x in s.size or ()])
            surfaces.append(d)
        return {"name": self.name, "dim": self.dim, "gravity": vec(self.gravity), "holds": holds,
                "surfaces": surfaces}

    def content_hash(self) -> str:
        """SHA-256 of the canonical JSON of :meth:`to_dict` (identifies the terrain in plan files)."""
        blob = json.dumps(self.to_dict(), sort_keys=True, separators=(",", ":")).encode()
        return hashlib.sha256(blob).hexdigest()

    def to_yaml(self) -> str:
        """The terrain as YAML text in the file format."""
        return yaml.safe_dump(self.to_dict(), sort_keys=False, default_flow_style=None)

    @classmethod
    def from_dict(cls, data: Any, source: str = "<dict>") -> "Terrain":
        """Build and validate a terrain from a dict in the file format.

        Raises:
            TerrainError: naming ``source``, the field and the reason.
        """
        return _parse(data, source)

    @classmethod
    def load(cls, name_or_path: str | Path) -> "Terrain":
        """Load a bundled terrain by name (``"demo-wall"``) or a terrain file by path.

        Raises:
            TerrainError: the file is missing, not YAML, or malformed.
        """
        try:
            path = resolve(name_or_path, terrains_dir(), "terrain")
        except Exception as exc:  # InputError from resolve: re-raise as a TerrainError
            raise TerrainError(str(name_or_path), "terrain", getattr(exc, "reason", str(exc))) from None
        try:
            text = path.read_text()
        except (OSError, UnicodeDecodeError) as exc:
            raise TerrainError(path, "file", f"cannot read ({exc})") from None
        try:
            data = yaml.safe_load(text)
        except yaml.YAMLError as exc:
            mark = getattr(exc, "problem_mark", None)
            where = f"line {mark.line + 1}" if mark is not None else "file"
            raise TerrainError(path, where, f"invalid YAML ({getattr(exc, 'problem', exc)})") from None
        return _parse(data, str(path))


def bundled_terrains() -> list[str]:
    """Names of the terrains shipped with the package."""
    return bundled(terrains_dir())


# ---- validation -----------------------------------------------------------------------------------
def _vec(value: Any, dim: int, src: str, fld: str) -> np.ndarray:
    if not isinstance(value, (list, tuple)) or len(value) != dim:
        raise TerrainError(src, fld, f"expected a list of {dim} numbers, got {value!r}")
    try:
        arr = np.array([float(x) for x in value], dtype=float)
    except (TypeError, ValueError):
        raise TerrainError(src, fld, f"expected numbers, got {value!r}") from None
    if not np.all(np.isfinite(arr)):
        raise TerrainError(src, fld, f"non-finite value in {value!r}")
    if dim == 2:
        arr = np.array([arr[0], 0.0, arr[1]])
    return arr


def _num(value: Any, src: str, fld: str, minimum: float | None = None, strict: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        raise TerrainError(src, fld, f"expected a number, got {value!r}")
    x = float(value)
    if not math.isfinite(x):
        raise TerrainError(src, fld, f"non-finite value {value!r}")
    if minimum is not None and (x <= minimum if strict else x < minimum):
        raise TerrainError(src, fld, f"must be {'>' if strict else '>='} {minimum}, got {value!r}")
    return x


def _unit(v: np.ndarray, src: str, fld: str) -> tuple[float, float, float]:
    n = float(np.linalg.norm(v))
    if n < 1e-9:
        raise TerrainError(src, fld, "zero normal (a normal must have non-zero length)")
    u = v / n
    return (float(u[0]), float(u[1]), float(u[2]))


def _parse(data: Any, src: str) -> Terrain:
    if not isinstance(data, dict):
        raise TerrainError(src, "(top level)", "expected a mapping with name, dim, gravity, holds")
    known = {"name", "dim", "gravity", "friction", "holds", "surfaces", "description"}
    extra = sorted(set(data) - known)
    if extra:
        raise TerrainError(src, extra[0], f"unknown field; known fields: {', '.join(sorted(known))}")
    for key in ("name", "holds"):
        if key not in data:
            raise TerrainError(src, key, "missing required field")
    name = data["name"]
    if not isinstance(name, str) or not name:
        raise TerrainError(src, "name", "must be a non-empty string")
    dim = data.get("dim", 3)
    if dim not in (2, 3) or isinstance(dim, bool):
        raise TerrainError(src, "dim", f"must be 2 or 3, got {dim!r}")
    g = _vec(data.get("gravity", [0.0, -9.81] if dim == 2 else [0.0, 0.0, -9.81]), dim, src, "gravity")
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
        unknown = sorted(set(h) - {"id", "position", "normal", "friction", "type", "max_force"})
        if unknown:
            raise TerrainError(src, f"{f}.{unknown[0]}", "unknown field")
        for key in ("id", "position", "normal"):
            if key not in h:
                raise TerrainError(src, f"{f}.{key}", "missing required field")
        hid = h["id"]
        if not isinstance(hid, (str, int)) or isinstance(hid, bool):
            raise TerrainError(src, f"{f}.id", f"expected a string, got {hid!r}")
        hid = str(hid)
        if hid in seen:
            raise TerrainError(src, f"{f}.id", f"duplicate hold id {hid!r}")
        seen.add(hid)
        pos = _vec(h["position"], dim, src, f"{f}.position")
        nrm = _unit(_vec(h["normal"], dim, src, f"{f}.normal"), src, f"{f}.normal")
        mu = _num(h.get("friction", default_mu), src, f"{f}.friction", minimum=0.0)
        ctype = h.get("type", "friction")
        if ctype not in CONTACT_TYPES:
            raise TerrainError(src, f"{f}.type", f"must be one of {', '.join(CONTACT_TYPES)}, got {ctype!r}")
        fmax = h.get("max_force")
        if fmax is not None:
            fmax = _num(fmax, src, f"{f}.max_force", minimum=0.0, strict=True)
        elif ctype != "friction":
            raise TerrainError(src, f"{f}.max_force", f"required for a {ctype} contact")
        holds.append(Hold(hid, tuple(float(x) for x in pos), nrm, mu, ctype, fmax))  # type: ignore[arg-type]
    surfaces: list[Surface] = []
    raw_surf = data.get("surfaces", []) or []
    if not isinstance(raw_surf, list):
        raise TerrainError(src, "surfaces", "expected a list")
    for i, s in enumerate(raw_surf):
        f = f"surfaces[{i}]"
        if not isinstance(s, dict) or "type" not in s:
            raise TerrainError(src, f"{f}.type", "missing required field")
        st = s["type"]
        if st not in SURFACE_TYPES:
            raise TerrainError(src, f"{f}.type", f"must be one of {', '.join(SURFACE_TYPES)}, got {st!r}")
        if st == "circle":
            if dim != 2:
                raise TerrainError(src, f"{f}.type", "circle obstacles are for 2-D terrains (use box in 3-D)")
            c = _vec(s.get("center"), 2, src, f"{f}.center")
            r = _num(s.get("radius"), src, f"{f}.radius", minimum=0.0, strict=True)
            surfaces.append(Surface("circle", tuple(c), radius=r))  # type: ignore[arg-type]
        elif st == "plane":
            c = _vec(s.get("point"), 3, src, f"{f}.point")
            n = _unit(_vec(s.get("normal"), 3, src, f"{f}.normal"), src, f"{f}.normal")
            size = s.get("size")
            if size is not None and not isinstance(size, (list, tuple)):
                raise TerrainError(src, f"{f}.size", f"expected [width, height], got {size!r}")
            size_t = tuple(_num(x, src, f"{f}.size", minimum=0.0, strict=True) for x in size) if size else None
            surfaces.append(Surface("plane", tuple(c), normal=n, size=size_t))  # type: ignore[arg-type]
        else:
            c = _vec(s.get("center"), 3, src, f"{f}.center")
            size = _vec(s.get("size"), 3, src, f"{f}.size")
            if np.any(size <= 0):
                raise TerrainError(src, f"{f}.size", "box sizes must be > 0")
            surfaces.append(Surface("box", tuple(c), size=tuple(size)))  # type: ignore[arg-type]
    return Terrain(name, int(dim), tuple(float(x) for x in g), tuple(holds), tuple(surfaces), src)  # type: ignore[arg-type]


# ---- generator ------------------------------------------------------------------------------------
def generate_wall(
    seed: int = 0,
    *,
    width: float = 1.6,
    height: float = 3.0,
    spacing: float = 0.18,
    jitter: float = 0.4,
    friction: tuple[float, float] = (0.9, 1.2),
    tilt_deg: float = 0.0,
    normal_up_deg: tuple[float, float] = (35.0, 65.0),
    normal_side_deg: float = 20.0,
    name: str | None = None,
) -> Terrain:
    """A random climbing wall (3-D, the plane ``y = 0``), reproducible from ``seed``.

    Holds sit on a jittered grid (a gym wall's bolt pattern): ``spacing`` metres apart,
    displaced by up to ``jitter * spacing``.  Each hold's normal leans from the wall normal ``+y``
    upwards by an angle drawn from ``normal_up_deg`` and sideways by up to ``normal_side_deg`` (the
    top of a ledge: seed 002's holds are "small, artificial rock features" of arbitrary orientation).
    ``tilt_deg`` tilts the wall back (positive: a slab, easier) or over (negative: an overhang) by
    rotating gravity about ``x``.

    Args:
        seed: RNG seed; the same seed gives the same wall.
        width, height: wall size in metres (holds span ``x`` in [-width/2, width/2], ``z`` in [0, height]).
        spacing: mean hold spacing in metres (hold density ~ 1/spacing^2).
        jitter: grid jitter as a fraction of ``spacing`` (0 = regular grid).
        friction: (low, high) range of Coulomb coefficients, drawn uniformly.
        tilt_deg: wall tilt from vertical, degrees.
        normal_up_deg: (low, high) range of the hold normals' upward lean, degrees.
        normal_side_deg: maximal sideways lean of the hold normals, degrees.
        name: terrain name (default ``wall-<seed>``).
    """
    if spacing <= 0 or width <= 0 or height <= 0:
        raise TerrainError("<generator>", "spacing/width/height", "must be > 0")
    if friction[0] < 0 or friction[1] < friction[0]:
        raise TerrainError("<generator>", "friction", f"need 0 <= low <= high, got {friction}")
    rng = np.random.default_rng(seed)
    nx = max(1, int(round(width / spacing)) + 1)
    nz = max(1, int(round(height / spacing)) + 1)
    holds = []
    for iz in range(nz):
        for ix in range(nx):
            x = -width / 2 + ix * width / max(nx - 1, 1) + rng.uniform(-1, 1) * jitter * spacing
            z = iz * height / max(nz - 1, 1) + rng.uniform(-1, 1) * jitter * spacing
            up = math.radians(rng.uniform(*normal_up_deg))
            side = math.radians(rng.uniform(-normal_side_deg, normal_side_deg))
            n = np.array([math.sin(side) * math.cos(up), math.cos(side) * math.cos(up), math.sin(up)])
            n /= np.linalg.norm(n)
            mu = float(rng.uniform(*friction))
            holds.append(Hold(f"h{len(holds)}", (round(x, 4), 0.0, round(z, 4)),
                              tuple(round(float(c), 6) for c in n), round(mu, 3)))  # type: ignore[arg-type]
    t = math.radians(tilt_deg)
    g = (0.0, round(-9.81 * math.sin(t), 6), round(-9.81 * math.cos(t), 6))
    wall = Surface("plane", (0.0, 0.0, height / 2), normal=(0.0, 1.0, 0.0), size=(width + 0.6, height + 0.6))
    return Terrain(name or f"wall-{seed}", 3, g, tuple(holds), (wall,), "<generated>")
