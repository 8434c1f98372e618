"""Contacts, input validation and the linear algebra shared by the equilibrium solvers.

Units: positions in metres, forces in newtons.  Internally every solver works in *weight units*
(forces divided by ``m * |g|``) with positions taken relative to the centroid of the contacts, which
keeps the LPs and SOCPs well scaled whatever the robot's mass.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np

from climb_ompl.errors import EquilibriumError

#: Default number of edges of the inscribed pyramids that replace the friction cones, shared by every
#: linearised test (support region, torque check, feasible region) so that they use one cone model.
CONE_EDGES = 8

ContactKind = Literal["friction", "grasp", "adhesion"]
CONTACT_KINDS: tuple[str, ...] = ("friction", "grasp", "adhesion")


def _vec3(value: Any, what: str) -> tuple[float, float, float]:
    if isinstance(value, tuple | list) and len(value) == 3 or isinstance(value, np.ndarray) and value.shape == (3,):
        try:  # fast path (one call per contact and per solve): three finite numbers
            x, y, z = float(value[0]), float(value[1]), float(value[2])
        except (TypeError, ValueError):
            pass
        else:
            if x - x == 0.0 and y - y == 0.0 and z - z == 0.0:
                return (x, y, z)
    try:
        arr = np.asarray(value, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise EquilibriumError(f"{what}: expected 3 numbers, got {value!r}") from None
    if arr.shape != (3,):
        raise EquilibriumError(f"{what}: expected 3 numbers, got {value!r}")
    if not np.all(np.isfinite(arr)):
        raise EquilibriumError(f"{what}: non-finite value in {arr.tolist()!r}")
    return (float(arr[0]), float(arr[1]), float(arr[2]))


@dataclass(frozen=True)
class Contact:
    """A point contact between a hand (or foot) and a hold.

    Attributes:
        position: contact point in the world frame, metres.
        normal: unit surface normal pointing from the hold towards the robot (normalised on creation).
        friction: Coulomb coefficient ``mu >= 0`` (the cone's half-angle is ``atan(mu)``).
        kind: ``"friction"`` (Coulomb cone, Bretl (2006) eq. (B3)), ``"grasp"`` (any force with
            ``|f| <= max_force``: a peg held in a gripper, Bretl (2006)'s double-link robot) or
            ``"adhesion"`` (the Coulomb cone shifted by a pull of at most ``max_force`` along
            ``-normal``: a suction foot, Kim, Kang & Choi (MRWALLSPECT III); the force set is
            ``|f_t| <= mu (n.f + max_force)``).
        max_force: force bound in newtons for ``grasp`` and ``adhesion`` (ignored for ``friction``).
        row: (derived, not a field) ``(*position, *normal, friction, pull)``, the pull ``max_force`` for adhesion
            and 0 otherwise: the input row of the compiled support region (:mod:`._project`).

    Raises:
        EquilibriumError: naming the bad value (non-finite position, zero or non-finite normal,
            negative friction, unknown kind, missing or non-positive ``max_force``).
    """

    position: tuple[float, float, float]
    normal: tuple[float, float, float]
    friction: float = 1.0
    kind: ContactKind = "friction"
    max_force: float | None = None

    def __post_init__(self) -> None:
        object.__setattr__(self, "position", _vec3(self.position, "Contact.position"))
        n = np.array(_vec3(self.normal, "Contact.normal"))
        norm = float(np.linalg.norm(n))
        if norm < 1e-12:
            raise EquilibriumError(f"Contact.normal: zero normal {tuple(n.tolist())!r} (needs a non-zero length)")
        object.__setattr__(self, "normal", tuple(float(x) for x in n / norm))
        try:
            mu = float(self.friction)
        except (TypeError, ValueError):
            raise EquilibriumError(f"Contact.friction: expected a number, got {self.friction!r}") from None
        if not math.isfinite(mu) or mu < 0:
            raise EquilibriumError(f"Contact.friction: must be finite and >= 0, got {self.friction!r}")
        object.__setattr__(self, "friction", mu)
        if self.kind not in CONTACT_KINDS:
            raise EquilibriumError(f"Contact.kind: must be one of {', '.join(CONTACT_KINDS)}, got {self.kind!r}")
        if self.kind == "friction":
            object.__setattr__(self, "max_force", None)
        else:
            fmax = self.max_force
            if fmax is None or isinstance(fmax, bool):
                raise EquilibriumError(f"Contact.max_force: required for a {self.kind} contact")
            fmax = float(fmax)
            if not math.isfinite(fmax) or fmax <= 0:
                raise EquilibriumError(f"Contact.max_force: must be finite and > 0, got {self.max_force!r}")
            object.__setattr__(self, "max_force", fmax)
        # position, normal, friction and adhesion pull as one row: the compiled support region's input
        object.__setattr__(self, "row", (*self.position, *self.normal, mu,
                                         self.max_force if self.kind == "adhesion" else 0.0))

    @classmethod
    def from_hold(cls, hold: Any) -> "Contact":
        """The contact at a :class:`climb_ompl.model.terrain.Hold` (its ``type`` becomes :attr:`kind`)."""
        return cls(hold.position, hold.normal, hold.friction, hold.type, hold.max_force)

    @property
    def p(self) -> np.ndarray:
        """Position as a numpy array, metres."""
        return np.asarray(self.position, dtype=float)

    @property
    def n(self) -> np.ndarray:
        """Unit normal as a numpy array."""
        return np.asarray(self.normal, dtype=float)

    def key(self) -> tuple[Any, ...]:
        """Hashable identity of the contact geometry (used by :class:`RegionCache`)."""
        return (self.position, self.normal, self.friction, self.kind, self.max_force)


def as_contacts(contacts: Sequence[Any]) -> list[Contact]:
    """Convert a sequence of :class:`Contact` or :class:`~climb_ompl.model.terrain.Hold` to contacts.

    Raises:
        EquilibriumError: an element is neither, or the list is empty.
    """
    if isinstance(contacts, (Contact, str, bytes)) or not hasattr(contacts, "__iter__"):
        raise EquilibriumError(f"contacts: expected a list of Contact, got {type(contacts).__name__}")
    out: list[Contact] = []
    for i, c in enumerate(contacts):
        if isinstance(c, Contact):
            out.append(c)
        elif all(hasattr(c, a) for a in ("position", "normal", "friction", "type")):
            try:
                out.append(Contact.from_hold(c))
            except EquilibriumError as exc:
                raise EquilibriumError(f"contacts[{i}]: {exc}") from None
        else:
            raise EquilibriumError(f"contacts[{i}]: expected a Contact or Hold, got {type(c).__name__}")
    if not out:
        raise EquilibriumError("contacts: empty list (equilibrium needs at least one contact)")
    return out


def check_mass_gravity(mass: Any, gravity: Any, planar: bool) -> tuple[float, np.ndarray]:
    """Validate ``mass`` (kg, > 0) and ``gravity`` (m/s^2, non-zero 3-vector).

    Raises:
        EquilibriumError: naming the bad value.
    """
    try:
        m = float(mass)
    except (TypeError, ValueError):
        raise EquilibriumError(f"mass: expected a number, got {mass!r}") from None
    if not math.isfinite(m) or m <= 0:
        raise EquilibriumError(f"mass: must be finite and > 0 kg, got {mass!r}")
    gx, gy, gz = _vec3(gravity, "gravity")
    g = np.array((gx, gy, gz))
    if math.sqrt(gx * gx + gy * gy + gz * gz) < 1e-9:
        raise EquilibriumError(f"gravity: zero gravity vector {g.tolist()!r}")
    if planar and abs(g[1]) > 1e-9 * np.linalg.norm(g):
        raise EquilibriumError(f"gravity: planar problems need gravity in the x-z plane (y = 0), got {g.tolist()!r}")
    return m, g


def check_planar_contacts(contacts: Sequence[Contact]) -> None:
    """Planar problems need contact normals in the x-z plane.

    Raises:
        EquilibriumError: naming the contact with an out-of-plane normal.
    """
    for i, c in enumerate(contacts):
        if abs(c.normal[1]) > 1e-9:
            raise EquilibriumError(f"contacts[{i}].normal: planar contacts need normals in the x-z plane "
                                   f"(y = 0), got {c.normal!r}")


def check_point(com: Any, what: str = "com") -> np.ndarray:
    """``com`` as a finite (3,) array.

    Raises:
        EquilibriumError: wrong shape or non-finite value.
    """
    return np.array(_vec3(com, what))


def gravity_basis(g: np.ndarray, planar: bool) -> np.ndarray:
    """Orthonormal basis of the plane perpendicular to gravity: rows ``u, v`` (3-D) or ``u`` (planar).

    ``u`` is the world ``x`` axis made perpendicular to gravity (the world ``y`` axis if gravity is
    along ``x``); ``v = up x u`` so that ``(u, v, up)`` is right-handed.  For ``g = -z``: ``u = x``,
    ``v = y``.  Planar: ``u`` lies in the x-z plane.
    """
    gx, gy, gz = (float(x) for x in g)
    ng = math.sqrt(gx * gx + gy * gy + gz * gz)
    up = (-gx / ng, -gy / ng, -gz / ng)
    ref = (1.0, 0.0, 0.0)
    if abs(up[0]) > 0.99:
        ref = (0.0, 1.0, 0.0) if not planar else (0.0, 0.0, 1.0)
    dot = ref[0] * up[0] + ref[1] * up[1] + ref[2] * up[2]
    u = [ref[i] - dot * up[i] for i in range(3)]
    nu = math.sqrt(u[0] * u[0] + u[1] * u[1] + u[2] * u[2])
    u = [x / nu for x in u]
    if planar:
        return np.array([u])
    v = [up[1] * u[2] - up[2] * u[1], up[2] * u[0] - up[0] * u[2], up[0] * u[1] - up[1] * u[0]]
    return np.array([u, v])


def cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a x b`` along the last axis (both ``(..., 3)``), without ``np.cross``'s per-call overhead."""
    a0, a1, a2 = a[..., 0], a[..., 1], a[..., 2]
    b0, b1, b2 = b[..., 0], b[..., 1], b[..., 2]
    out = np.empty(np.broadcast_shapes(np.shape(a), np.shape(b)))
    out[..., 0] = a1 * b2 - a2 * b1
    out[..., 1] = a2 * b0 - a0 * b2
    out[..., 2] = a0 * b1 - a1 * b0
    return out


def tangent_bases(N: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Unit tangents ``t1, t2`` (each ``(k, 3)``) with ``(t1, t2, n)`` right-handed for unit normals ``N (k, 3)``."""
    t1s, t2s = [], []
    for n0, n1, n2 in N.tolist():  # Python floats: a few contacts, so no per-call numpy overhead
        # t1 = n x e_x, or n x e_y when n is near the x axis, normalised; t2 = n x t1.
        a0, a1, a2 = (0.0, n2, -n1) if abs(n0) < 0.9 else (-n2, 0.0, n0)
        L = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        a0, a1, a2 = a0 / L, a1 / L, a2 / L
        t1s.append((a0, a1, a2))
        t2s.append((n1 * a2 - n2 * a1, n2 * a0 - n0 * a2, n0 * a1 - n1 * a0))
    return np.array(t1s).reshape(-1, 3), np.array(t2s).reshape(-1, 3)


def tangent_basis(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit tangents ``t1, t2`` with ``(t1, t2, n)`` right-handed."""
    t1, t2 = tangent_bases(np.asarray(n, dtype=float)[None, :])
    return t1[0], t2[0]


def skew(r: np.ndarray) -> np.ndarray:
    """Matrix of ``x -> r x x``."""
    return np.array([[0.0, -r[2], r[1]], [r[2], 0.0, -r[0]], [-r[1], r[0], 0.0]])


@dataclass(frozen=True)
class Linearised:
    """Inner polyhedral approximation of every contact's force set, in weight units.

    Contact ``i``'s force is ``f_i = gens[:, cols_i] @ lam_i + offsets[i]`` with ``lam_i >= 0`` and, for
    grasps, ``sum(lam_i) <= bound_i``.  Friction cones become inscribed ``k``-edge pyramids (Bretl,
    Latombe & Rock (2003) section 4, eq. (6)), grasp balls inscribed polytopes, so the linearised support
    region lies inside the exact one (``linearise(..., outer=True)`` gives circumscribed ones).
    """

    gens: np.ndarray  # (3, n_lam)
    owner: np.ndarray  # (n_lam,) contact index of each generator
    offsets: np.ndarray  # (k, 3)
    bounds: tuple[tuple[int, float], ...]  # (contact index, sum bound) of grasp contacts


def sphere_directions(k: int) -> np.ndarray:
    """Unit directions (3, m) whose hull is inscribed in the unit ball: poles plus 3 rings of ``k``."""
    th = 2 * np.pi * np.arange(k) / k
    rings = []
    for lat, off in ((0.0, 0.0), (np.pi / 4, np.pi / k), (-np.pi / 4, np.pi / k)):
        rings.append(np.vstack([np.cos(lat) * np.cos(th + off), np.cos(lat) * np.sin(th + off),
                                np.full(k, np.sin(lat))]))
    poles = np.array([[0.0, 0.0], [0.0, 0.0], [1.0, -1.0]])
    return np.hstack([*rings, poles])


_INRADIUS: dict[int, float] = {}


def sphere_inradius(k: int) -> float:
    """Radius of the largest ball centred at 0 inside the hull of :func:`sphere_directions` ``(k)``."""
    if k not in _INRADIUS:
        from scipy.spatial import ConvexHull

        _INRADIUS[k] = float(-ConvexHull(sphere_directions(k).T).equations[:, -1].max())
    return _INRADIUS[k]


_RINGS: dict[int, tuple[np.ndarray, np.ndarray]] = {}


def _ring(k: int) -> tuple[np.ndarray, np.ndarray]:
    """``cos``, ``sin`` of the ``k`` cone-edge angles ``2 pi i / k``, shaped ``(1, k, 1)`` (cached)."""
    if k not in _RINGS:
        th = 2 * np.pi * np.arange(k) / k
        _RINGS[k] = (np.cos(th)[None, :, None], np.sin(th)[None, :, None])
    return _RINGS[k]


def linearise(contacts: Sequence[Contact], weight: float, k: int, planar: bool, outer: bool = False) -> Linearised:
    """Generators of the linearised force sets (weight units).

    Args:
        contacts: the contacts.
        weight: ``m |g|`` in newtons (forces are divided by it).
        k: edges per friction cone (3-D, >= 3) or polygon vertices per grasp disc (planar).
        planar: 2-D problem in the x-z plane (friction cones then have exactly two edges).
        outer: circumscribed instead of inscribed sets (3-D): pyramids with friction ``mu / cos(pi/k)``
            and grasp polytopes scaled by their inradius, so that they contain the exact sets.
    """
    nc = len(contacts)
    N = np.array([c.normal for c in contacts])
    mu = np.array([c.friction for c in contacts])
    if outer and not planar:
        mu = mu / math.cos(math.pi / k)
    kinds = [c.kind for c in contacts]
    grasp = np.array([kd == "grasp" for kd in kinds])
    # Cone edges of every contact at once (grasp contacts' rows are replaced below).
    if planar:
        T = cross(np.array([0.0, 1.0, 0.0]), N)[:, None, :]  # (nc, 1, 3)
        s = np.array([1.0, -1.0])
        E = N[:, None, :] + (mu[:, None] * s)[:, :, None] * T  # (nc, 2, 3)
    else:
        t1, t2 = tangent_bases(N)
        cos_th, sin_th = _ring(k)
        E = N[:, None, :] + mu[:, None, None] * (cos_th * t1[:, None, :] + sin_th * t2[:, None, :])
    E /= np.sqrt((E * E).sum(axis=2))[:, :, None]
    offsets = np.zeros((nc, 3))
    bounds = []
    if not grasp.any():
        gens = E.reshape(-1, 3).T
        owner = np.repeat(np.arange(nc), E.shape[1])
        for i, c in enumerate(contacts):
            if c.kind == "adhesion":
                offsets[i] = -float(c.max_force) / weight * N[i]  # type: ignore[arg-type]
        return Linearised(np.ascontiguousarray(gens), owner, offsets, ())
    blocks, owners = [], []
    for i, c in enumerate(contacts):
        if c.kind == "grasp":
            if planar:
                th = 2 * np.pi * np.arange(k) / k
                e = np.vstack([np.cos(th), np.zeros(k), np.sin(th)])
            else:
                e = sphere_directions(k) / (sphere_inradius(k) if outer else 1.0)
            bounds.append((i, float(c.max_force) / weight))  # type: ignore[arg-type]
        else:
            e = E[i].T
            if c.kind == "adhesion":
                offsets[i] = -float(c.max_force) / weight * N[i]  # type: ignore[arg-type]
        blocks.append(e)
        owners.extend([i] * e.shape[1])
    return Linearised(np.hstack(blocks), np.array(owners), offsets, tuple(bounds))


def balance_rows(planar: bool) -> np.ndarray:
    """Rows of the 6-D wrench ``(f, tau)`` kept: all six, or ``f_x, f_z, tau_y`` for planar problems."""
    return np.array([0, 2, 4]) if planar else np.arange(6)


def wrench_matrix(positions: np.ndarray, gens: np.ndarray, owner: np.ndarray) -> np.ndarray:
    """6 x n matrix: generator weights to the wrench ``(sum f, sum r x f)`` (Bretl, Latombe & Rock (2003) eq. (6))."""
    return np.vstack([gens, cross(positions[owner], gens.T).T])


def com_columns(basis: np.ndarray, ghat: np.ndarray) -> np.ndarray:
    """6 x d matrix: the gravity wrench's moment ``c x ghat`` as a linear function of the CoM coordinates.

    With ``c = sum_j x_j basis_j + t ghat`` the moment of the unit weight is ``sum_j x_j (basis_j x ghat)``
    (independent of ``t``: Bretl (2006) appendix B after eq. (B3)).
    """
    cols = np.zeros((6, basis.shape[0]))
    for j, b in enumerate(basis):
        cols[3:, j] = cross(b, ghat)
    return cols
