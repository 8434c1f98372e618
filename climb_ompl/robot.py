"""Robot models: a URDF (kinematics, masses, collision geometry) plus a short limb spec (YAML).

A robot is loaded from ``robots/<name>.yaml`` (bundled) or a user's spec file::

    name: lemur
    urdf: lemur.urdf              # bundled: a file of the urdf folder; user robots: a path relative to the spec
    # urdf_package: example-robot-data   # optional: urdf and srdf are paths inside that installed package's
    #                                    # share folder (climb_ompl/robot_files.py; docs/robots.md)
    # srdf: robots/go1_description/srdf/go1.srdf   # optional: its disable_collisions pairs are not checked
    planar: false                 # true: the robot moves in the x-z plane (y = 0), see terrain.py
    base:                         # the joints that place the body in the world (unactuated) ...
      joints: [base_x, base_z, base_theta]
    # ... or, for a URDF without base joints, a base built here from prismatic and bounded revolute joints:
    #   base: {type: planar, lower: [-2, -0.5, -3.14], upper: [2, 3.5, 3.14]}   # x, z, angle about -y
    #   base: {type: spatial, lower: [6 numbers], upper: [6 numbers]}           # x, y, z, about z, y, x
    #   base: {type: spatial, reference_rpy: [r, p, y], ...}   # the angles turn about a reference orientation
    limbs:
      - name: ne
        hand_frame: ne_hand       # frame at the contact point of the end-effector
        joints: [ne_shoulder, ne_elbow, ne_wrist]
        elbow: ne_elbow           # optional: the joint sampled "straight" (Bretl (2006), sec. 4.2.3)
        elbow_straight: 0.0       # optional (default 0), radians
        ik: auto                  # auto | analytic | numeric
        contact: {type: sphere, radius: 0.02}   # optional (default point): climb_ompl/contact.py
    mass: 7.0                     # optional: expected total mass, kg (checked against the URDF, 1 %)
    torque_limits: {ne_shoulder: 5.0}     # optional, N m: overrides / completes the URDF efforts
    velocity_limits: {ne_shoulder: 0.78}  # optional, rad/s or m/s
    self_collision: true          # false for the planar robot of Bretl, Latombe & Rock (2003) (limbs may cross)
    equilibrium: true             # false: the robot grabs holds (Bretl (2006), sec. 2.1, double-link on pegs)
                                  # and needs no static-equilibrium or torque check, only collision and a hold
    ignore_collision_pairs: [[ne_upper, nw_upper]]   # link names
    massless_links: [pelvis]      # moving links with geometry but deliberately no mass
    package_dirs: [meshes]        # optional, for package:// meshes (relative to the spec)
    nominal: {base_z: 0.5, ne_wrist: 0.775}   # optional nominal configuration (others: 0 clipped to limits)
    joint_limits: {LF_HFE: [-1.6, 1.6]}   # optional: narrower joint ranges than the URDF's, radians or metres
    climb: {release_lookahead: true}      # optional: this robot's defaults for the climb's settings
                                          # (climb_ompl.settings.ClimbSettings; options given to a climb win)
    # also accepted: ``base_joints: [...]`` for ``base: {joints: [...]}``, ``nominal_q: [nq numbers]`` for
    # ``nominal``, and a free-form ``gait`` section read by climb_ompl.gaits (MRWALLSPECT III).

Configurations are plain vectors (``nq == nv``): no ``continuous`` joints (OMPL's constrained
spaces are built on a real-vector ambient space).
Frames: world z up; planar robots in the x-z plane; 3-D walls are the plane y = 0 with the robot on the
+y side (``climb_ompl/terrain.py``).  Lengths in metres, angles in radians, masses in kilograms.

Spatial base: three prismatic joints then three revolute joints about z, y, x (Z-Y-X angles).  Those
angles are singular where the middle one is +-90 deg; ``reference_rpy`` (roll, pitch, yaw of a reference
orientation, URDF convention ``R = Rz(yaw) Ry(pitch) Rx(roll)``) makes the base orientation
``R_ref Rz(q3) Ry(q4) Rx(q5)``, so zero angles are the reference and the singularity lies where the body's
x axis is along the reference's z axis.  For a robot standing on a wall (body z along the wall normal +y,
body x up the wall) ``reference_rpy: [-pi/2, -pi/2, 0]`` puts the singularity at the body's x axis along the
wall normal, a pose a climber never takes.  Configurations stay plain real vectors.

Collision (Coal geometry from ``pin.buildGeomFromUrdf``): the robot against the terrain's surfaces
(``plane`` as a solid half-space behind the plane, ``box``, and 2-D ``circle`` obstacles as discs in the
x-z plane) and, if enabled, against itself.  Self-collision skips, as MoveIt does, geometry pairs on the
same body or on bodies joined by a joint (adjacent links), the spec's ``ignore_collision_pairs`` and the
``disable_collisions`` pairs of the spec's SRDF (``pin.removeCollisionPairs``).  Near a contact limb's hold
the limb's contact geometry may touch the terrain (:mod:`climb_ompl.contact`): with a point contact, the
geometry on the hand frame's link (a small tip at the contact point) is exempt from terrain collision; the
links a contact lists (for a sphere foot by default the hand's link and the links moved only by the limb's
last joint) may touch the terrain within ``near`` metres of the hold; the rest of the limb may not.
"""

from __future__ import annotations

import itertools
import math
import xml.etree.ElementTree as ET
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field, replace
from functools import cached_property
from pathlib import Path
from typing import Any

import numpy as np

from ._io import load_yaml, number_hint
from .contact import POINT, Contact, parse_contact
from .errors import RobotModelError
from .resources import bundled, resolve, robots_dir
from .robot_files import package_share, resolve_robot_file

__all__ = ["Limb", "RobotModel", "bundled_robots"]

_SPEC_FIELDS = {
    "name", "description", "urdf", "planar", "base", "limbs", "mass", "torque_limits", "velocity_limits",
    "self_collision", "ignore_collision_pairs", "massless_links", "package_dirs", "nominal", "references",
    "base_joints", "nominal_q", "gait", "equilibrium", "urdf_package", "srdf",
    "joint_limits", "climb",
}
_LIMB_FIELDS = {"name", "hand_frame", "joints", "elbow", "elbow_straight", "ik", "contact"}
_IK_KINDS = ("auto", "analytic", "numeric")
_MASS_RTOL = 0.01
#: Numeric IK (damped least squares): a restart stops when its smallest error has not fallen by ``IK_STALL_GAIN``
#: of itself over the last ``IK_STALL`` iterations.  Over 300 random targets of Unitree G1's 7-joint arm and
#: lemur-hooks' limbs, every restart that converged did so within 31 iterations without such a stall, and the
#: failed ones stalled after a median of 34-55 of the 200 iterations they used to run: a failed call (every
#: restart) took 45 ms on G1's arm, which made its reach maps (:mod:`climb_ompl.reach`) take minutes.
IK_STALL = 20
IK_STALL_GAIN = 1e-6


def bundled_robots() -> list[str]:
    """Names of the robots shipped with the package (``robots/*.yaml``)."""
    return bundled(robots_dir())


@dataclass(frozen=True)
class Limb:
    """One limb: the joints that move its hand, and the hand's frame.

    Attributes:
        name: limb name, unique within the robot.
        hand_frame: Pinocchio frame at the end-effector's contact point.
        joint_indices: indices into the configuration vector of the limb's joints, root to hand.
        elbow_index: index into ``q`` of the joint sampled straight (Bretl (2006), sec. 4.2.3), or ``None``.
        elbow_straight: value of that joint at which the limb is straight, radians (``None`` without elbow).
        reach: upper bound on the distance from the limb's first joint to its hand, metres.
        frame_id: Pinocchio frame id of ``hand_frame``.
        joint_ids: Pinocchio joint ids of the limb's joints.
        ik: ``"analytic"`` (closed form, see :meth:`RobotModel.limb_ik`) or ``"numeric"`` (damped least squares).
        contact: the contact geometry (:class:`climb_ompl.contact.Contact`; a point by default).  For a
            sphere with an ``offset``, ``hand_frame`` names the frame the model adds at the sphere's centre.
    """

    name: str
    hand_frame: str
    joint_indices: tuple[int, ...]
    elbow_index: int | None
    elbow_straight: float | None
    reach: float
    frame_id: int = -1
    joint_ids: tuple[int, ...] = ()
    ik: str = "numeric"
    contact: Contact = POINT


def _f3(v: Any) -> tuple[float, float, float]:
    """A 3-vector as three floats."""
    return float(v[0]), float(v[1]), float(v[2])


@dataclass(frozen=True)
class _AnalyticChain:
    """Constants of a yaw-yaw(-pitch) limb for closed-form IK (all in the first joint's frame at angle 0).

    Hand = R(a, t1) [p_e + R(a, s t2) R_e p(t3)],  p(t3) = p_w + R_w R(b, t3) p_h  (3 joints) or p_h (2 joints).
    """

    a: np.ndarray
    s: float
    p_e: np.ndarray
    R_e: np.ndarray
    p_h: np.ndarray
    p_w: np.ndarray | None = None
    R_w: np.ndarray | None = None
    b: np.ndarray | None = None

    @cached_property
    def terms(self) -> dict[str, Any]:
        """The target-independent terms of the closed form as floats (see :meth:`RobotModel._ik_analytic`).

        With ``w`` the part of the elbow-to-hand vector ``v = R_e p(t3)`` perpendicular to ``a`` and ``u`` that of
        ``p_e``: ``v`` is affine in ``(cos t3, sin t3)`` (Rodrigues' formula), so are ``w`` and the dot products
        the solve needs.
        """
        a = self.a
        ape = float(a @ self.p_e)
        u = self.p_e - ape * a
        out: dict[str, Any] = {"a": _f3(a), "ape": ape, "u": _f3(u), "uu": float(u @ u), "ua": _f3(np.cross(u, a))}
        if self.b is None:
            out["planar"] = float(a @ (self.p_e + self.R_e @ self.p_h))
            out["v"] = [_f3(self.R_e @ self.p_h), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)]
            return out
        b, p_h = self.b, self.p_h
        cw = self.R_w.T @ self.R_e.T @ a  # a expressed in the pitch joint's frame
        bp = float(b @ p_h)
        p_par = bp * b
        out["alpha"], beta, gamma = float(cw @ p_par), float(cw @ (p_h - p_par)), float(cw @ _cross(b, p_h))
        out["aRpw"] = float(a @ (self.R_e @ self.p_w))
        out["rho"], out["base"] = math.hypot(beta, gamma), math.atan2(gamma, beta)
        m = self.R_e @ self.R_w
        vb = bp * (m @ b)
        # v(t3) = v0 + c vc + s vs
        out["v"] = [_f3(self.R_e @ self.p_w + vb), _f3(m @ p_h - vb), _f3(m @ np.cross(b, p_h))]
        return out


@dataclass(frozen=True)
class _AbductionChain:
    """Constants of an abduction-pitch-pitch leg (a quadruped's hip, thigh and knee) for closed-form IK.

    The first joint turns about ``a`` (its own frame); the next two have parallel axes, so the hand's
    component along their axis is a constant.  In the first joint's frame at angle 0, with ``b2`` the second
    joint's axis there, the first angle solves ``(R(a, t1) b2) . t = k`` for a target ``t``; the other two
    then solve the planar two-link problem of ``sub`` (:class:`_AnalyticChain` of the last two joints).
    """

    a: np.ndarray
    b2: np.ndarray
    k: float
    sub_limb: Limb
    sub: _AnalyticChain


@dataclass
class _CollisionSet:
    geom_model: Any
    datas: dict[Any, Any] = field(default_factory=dict)  # by contact limbs (and clearance)
    terrain_geoms: tuple[int, ...] = ()
    terrain: Any = None
    near_pairs: dict[int, tuple[int, ...]] = field(default_factory=dict)  # by limb: (contact link, terrain) pairs


def _rot(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix about unit ``axis`` by ``angle`` (Rodrigues, written out: called in every IK solve)."""
    x, y, z = (float(v) for v in axis)
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return np.array([[c + t * x * x, t * x * y - s * z, t * x * z + s * y],
                     [t * x * y + s * z, c + t * y * y, t * y * z - s * x],
                     [t * x * z - s * y, t * y * z + s * x, c + t * z * z]])


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    """``np.allclose(a, b, atol=1e-12)`` (its default ``rtol = 1e-5``) without its per-call overhead: the
    inverse kinematics de-duplicates its solutions with it a few hundred thousand times per climb."""
    return bool(np.all(np.abs(a - b) <= 1e-12 + 1e-5 * np.abs(b)))


def _unique(sols: list[np.ndarray], idx: list[int]) -> list[np.ndarray]:
    """``sols`` without the later of any two that are :func:`_same`, in order.  The solutions differ only at
    ``idx`` (a limb's joints), so each is compared only with those in its own and the neighbouring cells of a grid
    on those coordinates whose spacing exceeds :func:`_same`'s tolerance: linear in the number of solutions, where
    comparing every pair is quadratic (a URDF's placeholder range of +-10 rad gives a leg's IK about a hundred
    whole-turn copies of each solution)."""
    if len(sols) < 8:
        out: list[np.ndarray] = []
        for sol in sols:
            if not any(_same(sol, r_) for r_ in out):
                out.append(sol)
        return out
    vals = [[float(sol[i]) for i in idx] for sol in sols]
    w = 2e-3 + 2e-5 * max(abs(v) for row in vals for v in row)  # > 1e-12 + 1e-5 |b| for every value
    cells: dict[tuple[int, ...], list[np.ndarray]] = {}
    offsets = list(itertools.product((-1, 0, 1), repeat=len(idx)))
    out = []
    for sol, row in zip(sols, vals, strict=True):
        cell = tuple(math.floor(v / w) for v in row)
        near = (tuple(c + d for c, d in zip(cell, o, strict=True)) for o in offsets)
        if any(_same(sol, r_) for n in near for r_ in cells.get(n, ())):
            continue
        cells.setdefault(cell, []).append(sol)
        out.append(sol)
    return out


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.cross`` for two 3-vectors, ten times cheaper (no axis handling)."""
    a0, a1, a2 = (float(v) for v in a)
    b0, b1, b2 = (float(v) for v in b)
    return np.array((a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0))


def wrap_into(angle: float, lo: float, hi: float, eps: float = 1e-12) -> list[float]:
    """All values ``angle + 2 pi k`` inside ``[lo, hi]`` (joints bounded by more than 2 pi have several)."""
    two_pi = 2.0 * math.pi
    k0 = math.ceil((lo - eps - angle) / two_pi)
    first = angle + k0 * two_pi
    if first > hi + eps:
        return []
    if angle + (k0 + 1) * two_pi > hi + eps:  # one value (always so for a joint bounded by less than 2 pi)
        return [min(max(first, lo), hi)]
    out = []
    k = k0
    while angle + k * two_pi <= hi + eps:
        out.append(min(max(angle + k * two_pi, lo), hi))
        k += 1
    return out


class RobotModel:
    """A climbing robot: Pinocchio model + Coal collision geometry + limb description.

    Build with :meth:`load` (bundled name or spec path) or :meth:`from_spec` (a dict).  Attributes
    follow ``docs/dev/CONTRACTS.md``: ``name, nq, lower, upper, velocity_limits, torque_limits (inf where
    unactuated), actuated, base_indices, limbs, mass, planar, nominal_q, model, data, collision_model,
    visual_model, spec, spec_path, urdf_path``; also ``equilibrium``, ``self_collision_enabled``, ``srdf_path``
    and ``joint_names`` (the name of the joint of each configuration coordinate).

    Contacts (:mod:`climb_ompl.contact`): :meth:`hand_target` (where a hand frame goes to touch a hold),
    :meth:`contact_point`, :meth:`contact_jacobian`; :meth:`in_collision` exempts each contact limb's
    contact geometry near its hold and :meth:`collisions` names what collides.
    """

    def __init__(self, spec: dict[str, Any], spec_path: Path | str, base_dir: Path | None = None):
        import pinocchio as pin

        self._pin = pin
        self.spec = spec
        self.spec_path = spec_path
        src = str(spec_path)
        if isinstance(spec, dict) and "base_joints" in spec and "base" not in spec:
            spec = {**{k: v for k, v in spec.items() if k != "base_joints"}, "base": {"joints": spec["base_joints"]}}
        _check_spec_shape(spec, src)
        self.name: str = spec["name"]
        self.planar: bool = bool(spec.get("planar", False))
        #: whether feasibility includes static equilibrium and torque limits (spec ``equilibrium``, default
        #: true); false for robots that grab and release pegs (Bretl (2006), sec. 2.1)
        self.equilibrium: bool = bool(spec.get("equilibrium", True))
        base_dir = base_dir if base_dir is not None else (Path(spec_path).parent if Path(spec_path).exists()
                                                          else Path("."))
        share = package_share(spec["urdf_package"], src) if "urdf_package" in spec else None
        self.urdf_path = resolve_robot_file(spec["urdf"], base_dir, src, "urdf", share)
        #: the SRDF whose ``disable_collisions`` pairs are skipped (spec ``srdf``), or ``None``
        self.srdf_path: Path | None = (resolve_robot_file(spec["srdf"], base_dir, src, "srdf", share)
                                       if spec.get("srdf") is not None else None)
        _check_urdf_masses(self.urdf_path, set(spec.get("massless_links", []) or []), src)

        base = spec["base"]
        try:
            if "type" in base:
                root = _composite_base(base, src)
                model = pin.buildModelFromUrdf(str(self.urdf_path), root)
            else:
                model = pin.buildModelFromUrdf(str(self.urdf_path))
        except (RuntimeError, ValueError) as exc:
            raise RobotModelError(self.urdf_path, "urdf", f"Pinocchio cannot parse it ({exc})") from None
        self.model = model
        if model.nq != model.nv:
            bad = [model.names[j] for j in range(1, model.njoints) if model.joints[j].nq != model.joints[j].nv]
            raise RobotModelError(self.urdf_path, f"joints.{bad[0] if bad else '?'}",
                                  "continuous or spherical joint: configurations must be plain vectors "
                                  "(use bounded revolute joints, e.g. +-2 pi)")
        self.nq: int = int(model.nq)
        self.joint_names: tuple[str, ...] = self._coordinate_names(base.get("type"))
        if "type" in base:
            k = len(base["lower"])
            model.lowerPositionLimit[:k] = np.asarray(base["lower"], float)
            model.upperPositionLimit[:k] = np.asarray(base["upper"], float)
            self.base_indices: tuple[int, ...] = tuple(range(k))
        else:
            self.base_indices = tuple(self._joint_q(n, src, "base.joints") for n in base["joints"])
        self._narrow_limits(spec.get("joint_limits") or {}, src)
        #: the spec's ``climb`` section: this robot's defaults for :class:`~climb_ompl.settings.ClimbSettings`
        self.climb: dict[str, Any] = _climb_section(spec.get("climb"), src)
        self.lower = np.array(model.lowerPositionLimit, dtype=float)
        self.upper = np.array(model.upperPositionLimit, dtype=float)
        for i in range(self.nq):
            if not (np.isfinite(self.lower[i]) and np.isfinite(self.upper[i]) and self.lower[i] < self.upper[i]):
                raise RobotModelError(self.urdf_path, f"joints.{self.joint_names[i]}.limit",
                                      f"needs finite lower < upper bounds, got [{self.lower[i]}, {self.upper[i]}]")
        self.data = model.createData()

        self.mass: float = float(sum(model.inertias[j].mass for j in range(model.njoints)))
        if self.mass <= 0:
            raise RobotModelError(self.urdf_path, "links.inertial", "missing mass: the robot's total mass is 0")
        if "mass" in spec:
            want = spec["mass"]
            if abs(self.mass - want) > _MASS_RTOL * want:
                raise RobotModelError(src, "mass", f"spec says {want} kg but the URDF's links weigh {self.mass:.4g} kg")

        # limits: URDF effort (0 = not given) and velocity, spec overrides, base joints unactuated
        self.torque_limits = np.array(model.effortLimit, dtype=float)
        self.torque_limits[self.torque_limits <= 0] = np.inf
        self.velocity_limits = np.array(model.velocityLimit, dtype=float)
        for key, arr in (("torque_limits", self.torque_limits), ("velocity_limits", self.velocity_limits)):
            for jn, val in (spec.get(key) or {}).items():
                arr[self._joint_q(jn, src, f"{key}.{jn}")] = float(val)
        self.actuated = np.ones(self.nq, dtype=bool)
        self.actuated[list(self.base_indices)] = False
        self.torque_limits[~self.actuated] = np.inf

        self.limbs: tuple[Limb, ...] = self._build_limbs(spec["limbs"], src)
        self.data = model.createData()  # again: a sphere contact with an offset adds a frame
        self._limb_by_name = {lb.name: i for i, lb in enumerate(self.limbs)}
        self._hand_fids = [lb.frame_id for lb in self.limbs]
        self._chains = {lb.name: self._analytic_chain(lb) for lb in self.limbs}
        self._all_revolute: dict[str, bool] = {}  # per numeric limb: every joint revolute (the reach bounds it)
        kinds = []
        for i, (lb, raw) in enumerate(zip(self.limbs, spec["limbs"], strict=True)):
            want = raw.get("ik", "auto")
            chain = self._chains[lb.name]
            if want == "analytic" and chain is None:
                raise RobotModelError(src, f"limbs[{i}].ik", "no closed-form IK for this limb (analytic IK needs "
                                      "two revolute joints with parallel axes, optionally followed by one "
                                      "revolute joint whose axis is not parallel to them)")
            kind = "analytic" if (chain is not None and want != "numeric") else "numeric"
            if kind == "numeric":
                self._chains[lb.name] = None
            kinds.append(kind)
        self.limbs = tuple(replace(lb, ik=k) for lb, k in zip(self.limbs, kinds, strict=True))

        self.nominal_q = self._nominal(spec.get("nominal") or {}, src)
        if "nominal_q" in spec:
            nq_raw = spec["nominal_q"]
            if (not isinstance(nq_raw, list) or len(nq_raw) != self.nq
                    or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in nq_raw)):
                raise RobotModelError(src, "nominal_q", f"expected a list of {self.nq} numbers")
            self.nominal_q = np.asarray(nq_raw, dtype=float)
            bad = np.flatnonzero((self.nominal_q < self.lower - 1e-9) | (self.nominal_q > self.upper + 1e-9))
            if bad.size:
                raise RobotModelError(src, f"nominal_q[{bad[0]}]", f"outside the bounds of joint "
                                      f"{self.joint_names[bad[0]]!r}")
        self.limbs = tuple(self._locked_reach(lb) for lb in self.limbs)  # (same order: the name index holds)

        # collision geometry
        pkg = [str((base_dir / p).resolve()) for p in (spec.get("package_dirs") or [])]
        pkg.append(str(self.urdf_path.parent))
        if share is not None:
            pkg.append(str(share.parent))  # package://<name>/... resolves in <prefix>/share
        self._package_dirs = pkg
        self._visual_model: Any = None
        self._urdf_text = self.urdf_path.read_text()  # the visual geometry is built later, maybe from a temp file
        try:
            self.collision_model = pin.buildGeomFromUrdf(model, str(self.urdf_path), pin.COLLISION, package_dirs=pkg)
        except (RuntimeError, ValueError, OSError) as exc:
            raise RobotModelError(self.urdf_path, "geometry", f"cannot build collision geometry ({exc})") from None
        self.self_collision_enabled: bool = bool(spec.get("self_collision", True))
        self._ignore = self._ignore_pairs(spec.get("ignore_collision_pairs") or [], src)
        self._self_pairs = self._compute_self_pairs()
        self._hand_geoms = self._compute_hand_geoms()
        self._near_geoms = self._compute_near_geoms(src)
        self._self_set: _CollisionSet | None = None
        self._terrain_sets: dict[int, _CollisionSet] = {}

    @property
    def visual_model(self) -> Any:
        """Visual geometry (``pin.GeometryModel``), read from the URDF on first use (meshes load slowly)."""
        if self._visual_model is None:
            pin = self._pin
            try:
                if self.urdf_path.is_file():
                    self._visual_model = pin.buildGeomFromUrdf(self.model, str(self.urdf_path), pin.VISUAL,
                                                               package_dirs=self._package_dirs)
                else:  # the file is gone (a plan's embedded URDF written to a temporary folder): its text
                    self._visual_model = pin.buildGeomFromUrdfString(self.model, self._urdf_text, pin.VISUAL,
                                                                     package_dirs=self._package_dirs)
            except (RuntimeError, ValueError, OSError) as exc:
                raise RobotModelError(self.urdf_path, "geometry", f"cannot build visual geometry ({exc})") from None
        return self._visual_model

    # ------------------------------------------------------------------------------------- loading
    @classmethod
    def load(cls, name_or_path: str | Path) -> "RobotModel":
        """Load a bundled robot by name (``"lemur"``) or a robot spec file by path.

        Raises:
            RobotModelError: missing file, invalid YAML, or a spec/URDF problem (names file, field, reason).
        """
        p = resolve(name_or_path, robots_dir(), "robot", error=RobotModelError)
        return cls(load_yaml(p, RobotModelError), p, p.parent)

    @classmethod
    def from_spec(cls, spec: dict[str, Any], base_dir: str | Path = ".", source: str = "<dict>") -> "RobotModel":
        """Build a robot from a spec dict; relative URDF paths are taken from ``base_dir``."""
        return cls(spec, source, Path(base_dir))

    def __repr__(self) -> str:
        return f"RobotModel({self.name!r}, nq={self.nq}, limbs={[lb.name for lb in self.limbs]})"

    # ------------------------------------------------------------------------------------- kinematics
    def limb(self, limb: str | int | Limb) -> Limb:
        """The limb given by name, index or itself.

        Raises:
            RobotModelError: unknown limb name (the message lists the limbs).
        """
        return self.limbs[self._limb_index(limb)]

    def _limb_index(self, limb: str | int | Limb) -> int:
        if isinstance(limb, Limb):
            limb = limb.name
        if isinstance(limb, (int, np.integer)):
            return int(limb)
        try:
            return self._limb_by_name[limb]
        except KeyError:
            raise RobotModelError(self.name, "limb", f"unknown limb {limb!r}; limbs: "
                                  f"{', '.join(lb.name for lb in self.limbs)}") from None

    def com(self, q: np.ndarray) -> np.ndarray:
        """Centre of mass in the world frame, metres, shape ``(3,)``."""
        return np.array(self._pin.centerOfMass(self.model, self.data, np.asarray(q, dtype=float), False))

    def com_batch(self, Q: np.ndarray) -> np.ndarray:
        """Centres of mass of many configurations: ``Q`` of shape ``(N, nq)`` gives ``(N, 3)``, metres."""
        Q = np.asarray(Q, dtype=float).reshape(-1, self.nq)
        pin, m, d = self._pin, self.model, self.data
        out = np.empty((Q.shape[0], 3))
        for i in range(Q.shape[0]):
            out[i] = pin.centerOfMass(m, d, Q[i], False)
        return out

    def hand_positions(self, q: np.ndarray) -> np.ndarray:
        """World positions of every limb's hand, metres, shape ``(L, 3)`` in ``limbs`` order."""
        pin, m, d = self._pin, self.model, self.data
        pin.forwardKinematics(m, d, np.asarray(q, dtype=float))
        upd = pin.updateFramePlacement
        return np.array([upd(m, d, f).translation for f in self._hand_fids])

    def hand_position(self, q: np.ndarray, limb: str | int | Limb) -> np.ndarray:
        """World position of one limb's hand, metres, shape ``(3,)``."""
        pin, m, d = self._pin, self.model, self.data
        fid = self.limbs[self._limb_index(limb)].frame_id
        pin.forwardKinematics(m, d, np.asarray(q, dtype=float))
        return np.array(pin.updateFramePlacement(m, d, fid).translation)

    def hand_target(self, limb: str | int | Limb, hold: Any, normal: Sequence[float] | None = None) -> np.ndarray:
        """Where ``limb``'s hand frame goes to touch ``hold``: the hold itself for a point contact, ``p + r n``
        for a sphere of radius ``r`` (:mod:`climb_ompl.contact`); the target to give :meth:`limb_ik`.

        Args:
            limb: the limb.
            hold: a :class:`climb_ompl.terrain.Hold` (its ``position`` and ``normal``), or a position
                (metres) with ``normal``.
            normal: the hold's outward normal when ``hold`` is a position.
        """
        contact = self.limbs[self._limb_index(limb)].contact
        if normal is None:
            if not hasattr(hold, "normal"):
                if contact.type == "point":
                    return np.asarray(hold, dtype=float).reshape(3).copy()
                raise ValueError("hand_target: a sphere contact needs the hold's normal")
            hold, normal = hold.position, hold.normal
        return contact.hand_target(hold, normal)

    def contact_point(self, q: np.ndarray, limb: str | int | Limb, normal: Sequence[float]) -> np.ndarray:
        """World point where ``limb``'s end-effector at ``q`` touches a surface of outward ``normal``: the
        hand frame for a point contact, the hand frame minus ``r n`` for a sphere (:mod:`climb_ompl.contact`)."""
        lb = self.limbs[self._limb_index(limb)]
        return lb.contact.contact_point(self.hand_position(q, lb), normal)

    def contact_jacobian(self, q: np.ndarray, limb: str | int | Limb, normal: Sequence[float]) -> np.ndarray:
        """Position Jacobian ``(3, nq)`` of the material point of ``limb``'s end-effector that touches a surface
        of outward ``normal`` (world-aligned): the point at ``d = -r n`` from the sphere's centre moves with
        ``J_c - [d]x J_w``, so a contact force ``f`` there costs ``J^T f`` in joint torques, moment ``d x f``
        about the centre included.  For a point contact it is :meth:`hand_jacobian`."""
        pin, m, d = self._pin, self.model, self.data
        lb = self.limbs[self._limb_index(limb)]
        J = np.array(pin.computeFrameJacobian(m, d, np.asarray(q, dtype=float), lb.frame_id,
                                              pin.ReferenceFrame.LOCAL_WORLD_ALIGNED))
        if lb.contact.radius == 0.0:
            return J[:3]
        n = np.asarray(normal, dtype=float).reshape(3)
        dvec = -lb.contact.radius * n / np.linalg.norm(n)
        skew = np.array([[0.0, -dvec[2], dvec[1]], [dvec[2], 0.0, -dvec[0]], [-dvec[1], dvec[0], 0.0]])
        return J[:3] - skew @ J[3:]

    def hand_jacobians(self, q: np.ndarray) -> np.ndarray:
        """Position Jacobians of every hand, ``(L, 3, nq)``: d(hand position, world frame)/dq."""
        return self.hands_and_jacobians(q)[1]

    def hands_and_jacobians(self, q: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """``(hand_positions(q), hand_jacobians(q))`` from one kinematics pass (the constraint's hot path)."""
        pin, m, d = self._pin, self.model, self.data
        pin.computeJointJacobians(m, d, np.asarray(q, dtype=float))
        upd, get, lwa = pin.updateFramePlacement, pin.getFrameJacobian, pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        P = np.array([upd(m, d, f).translation for f in self._hand_fids])
        J = np.array([get(m, d, f, lwa)[:3] for f in self._hand_fids])
        return P, J

    def hand_jacobian(self, q: np.ndarray, limb: str | int | Limb) -> np.ndarray:
        """Position Jacobian ``(3, nq)`` of one limb's hand (world-aligned)."""
        pin, m, d = self._pin, self.model, self.data
        fid = self.limbs[self._limb_index(limb)].frame_id
        return np.array(pin.computeFrameJacobian(m, d, np.asarray(q, dtype=float), fid,
                                                 pin.ReferenceFrame.LOCAL_WORLD_ALIGNED)[:3])

    def limb_fk(self, q: np.ndarray, limb: str | int | Limb) -> np.ndarray:
        """Per-limb forward kinematics: world positions of the limb's joints and hand, ``(k + 1, 3)``, metres."""
        pin, m, d = self._pin, self.model, self.data
        lb = self.limbs[self._limb_index(limb)]
        pin.forwardKinematics(m, d, np.asarray(q, dtype=float))
        pts = [np.array(d.oMi[j].translation) for j in lb.joint_ids]
        pts.append(np.array(pin.updateFramePlacement(m, d, lb.frame_id).translation))
        return np.array(pts)

    def gravity_torques(self, q: np.ndarray, gravity: Sequence[float] = (0.0, 0.0, -9.81)) -> np.ndarray:
        """Generalised gravity torques ``g(q)`` (N m or N), shape ``(nq,)``.

        ``g(q) = dV/dq`` with ``V(q) = -mass * gravity . com(q)``, so quasi-static balance reads
        ``tau = g(q) - sum_i J_i(q)^T f_i`` (Bretl (2006), sec. 3.2.3, torque limits).

        Args:
            q: configuration.
            gravity: gravity vector in the world frame, m/s^2 (a terrain's ``g``).
        """
        pin, m = self._pin, self.model
        m.gravity.linear = np.asarray(gravity, dtype=float)
        return np.array(pin.computeGeneralizedGravity(m, self.data, np.asarray(q, dtype=float)))

    def within_limits(self, q: np.ndarray, tol: float = 1e-9) -> bool:
        """True if every coordinate of ``q`` lies within its joint bounds (``tol`` slack)."""
        q = np.asarray(q, dtype=float)
        return bool(np.all(q >= self.lower - tol) and np.all(q <= self.upper + tol))

    def random_configuration(self, rng: np.random.Generator) -> np.ndarray:
        """A configuration drawn uniformly within the joint bounds."""
        return rng.uniform(self.lower, self.upper)

    # ------------------------------------------------------------------------------------- inverse kinematics
    def limb_ik(self, limb: str | int | Limb, q: np.ndarray, target: Sequence[float],
                tol: float = 1e-10) -> list[np.ndarray]:
        """Configurations placing ``limb``'s hand at ``target`` (world, metres), changing only that limb's joints.

        Closed form for two-link planar limbs (the planar robots; Bretl, Latombe & Rock (2003), sec. 3; Bretl (2006),
        sec. 2.1-2.2) and for LEMUR's yaw-yaw-pitch limb (Bretl et al. (2004), sec. 2): the pitch angle is fixed by the
        target's distance from the plane of the yaw joints, then the two yaw angles solve a planar two-link problem
        (law of cosines, one solution per elbow bend).  Every representative within the joint bounds is
        returned (a joint bounded by +-2 pi has two).  Other limbs use damped least squares on Pinocchio's
        frame Jacobian (restarts from seeded random starts); it returns at most one solution.

        Returns:
            Full configurations (copies of ``q`` with the limb's joints replaced), nearest to ``q`` first;
            empty if the target is unreachable within the joint bounds.
        """
        lb = self.limbs[self._limb_index(limb)]
        q = np.array(q, dtype=float)
        target = np.asarray(target, dtype=float).reshape(3)
        chain = self._chains.get(lb.name)
        if chain is None:
            sols = self._ik_numeric(lb, q, target, tol)
        elif isinstance(chain, _AbductionChain):
            sols = self._ik_abduction(lb, chain, q, target)
        else:
            sols = self._ik_analytic(lb, chain, q, target)
        idx = list(lb.joint_indices)
        q_l = [float(q[i]) for i in idx]
        sols.sort(key=lambda s: math.fsum((float(s[i]) - x) ** 2 for i, x in zip(idx, q_l, strict=True)))
        return sols

    def limb_ik_nearest(self, limb: str | int | Limb, q: np.ndarray, target: Sequence[float],
                        ref: np.ndarray, *, same_bend: bool = False) -> np.ndarray | None:
        """The solution of :meth:`limb_ik` whose limb joints are nearest ``ref`` (least squares), or ``None``.

        For closed-form limbs only that solution's hand position is checked (the others are not needed),
        which makes this the cheap call for following a path by inverse kinematics.  ``same_bend``: only
        solutions whose elbow bends the way ``ref``'s does (the sign of the elbow joint less its straight value;
        a limb without an ``elbow`` has no bend to keep).
        """
        lb = self.limbs[self._limb_index(limb)]
        chain = self._chains.get(lb.name)
        ref = np.asarray(ref, dtype=float)
        bend = None
        if same_bend and lb.elbow_index is not None:
            st = lb.elbow_straight or 0.0
            bend = (lb.elbow_index, st, float(np.sign(ref[lb.elbow_index] - st)))
        if chain is not None and not isinstance(chain, _AbductionChain):
            sols = self._ik_analytic(lb, chain, np.array(q, dtype=float), np.asarray(target, dtype=float).reshape(3),
                                     ref=ref, bend=bend)
            return sols[0] if sols else None
        sols = self.limb_ik(lb, q, target)
        if bend is not None:
            sols = [x for x in sols if np.sign(x[bend[0]] - bend[1]) == bend[2]]
        if not sols:
            return None
        idx = list(lb.joint_indices)
        return min(sols, key=lambda x: float(np.sum((x[idx] - ref[idx]) ** 2)))

    def _ik_analytic(self, lb: Limb, c: _AnalyticChain, q: np.ndarray, target: np.ndarray,
                     ref: np.ndarray | None = None,
                     bend: tuple[int, float, float] | None = None) -> list[np.ndarray]:
        """Every closed-form solution (see :meth:`limb_ik`); with ``ref``, only the one nearest ``ref``, and with
        ``bend`` (``(index into q, straight value, sign)``) too, only among those whose elbow bends that way.

        In the first joint's frame (target ``t``, unit axis ``a``), the pitch angle ``t3`` is fixed by
        ``a . hand = a . t``; then ``hand - (a . hand) a = u + R(a, phi) w`` (``phi = s t2``) has the length of
        ``t``'s part across ``a``, which gives ``phi`` by the law of cosines, and ``t1`` turns that vector onto
        ``t``.  Written on floats (:attr:`_AnalyticChain.terms`): it is called a few hundred thousand times per
        climb.
        """
        pin, m, d = self._pin, self.model, self.data
        k = c.terms
        j1 = lb.joint_ids[0]
        pin.forwardKinematics(m, d, q)
        tx, ty, tz = (d.oMi[m.parents[j1]] * m.jointPlacements[j1]).actInv(target).tolist()
        ax, ay, az = k["a"]
        ta = ax * tx + ay * ty + az * tz
        scale = 1.0 + math.sqrt(tx * tx + ty * ty + tz * tz)
        if c.b is None:
            if abs(ta - k["planar"]) > 1e-9 * scale:
                return []
            t3s: list[float | None] = [None]
        else:
            rhs = ta - k["ape"] - k["aRpw"] - k["alpha"]
            rho = k["rho"]
            if rho < 1e-12 or abs(rhs) > rho * (1 + 1e-12):
                return []
            off = math.acos(max(-1.0, min(1.0, rhs / rho)))
            t3s = [k["base"] + off, k["base"] - off]
        px, py, pz = tx - ta * ax, ty - ta * ay, tz - ta * az  # t across a
        ux, uy, uz = k["u"]
        uax, uay, uaz = k["ua"]  # u x a = -(a x u)
        (v0x, v0y, v0z), (vcx, vcy, vcz), (vsx, vsy, vsz) = k["v"]
        i1, i2 = lb.joint_indices[0], lb.joint_indices[1]
        lo1, hi1, lo2, hi2 = (float(x) for x in (self.lower[i1], self.upper[i1], self.lower[i2], self.upper[i2]))
        out: list[tuple[float, float, float | None]] = []
        for t3 in t3s:
            t3_vals: list[float | None] = [None]
            cs, sn = 0.0, 0.0
            if t3 is not None:
                i3 = lb.joint_indices[2]
                t3_vals = wrap_into(t3, float(self.lower[i3]), float(self.upper[i3]))
                if not t3_vals:
                    continue
                cs, sn = math.cos(t3), math.sin(t3)
            vx, vy, vz = v0x + cs * vcx + sn * vsx, v0y + cs * vcy + sn * vsy, v0z + cs * vcz + sn * vsz
            av = ax * vx + ay * vy + az * vz
            wx, wy, wz = vx - av * ax, vy - av * ay, vz - av * az
            A = ux * wx + uy * wy + uz * wz
            B = uax * wx + uay * wy + uaz * wz  # u . (a x w)
            C = ((px * px + py * py + pz * pz) - k["uu"] - (wx * wx + wy * wy + wz * wz)) / 2.0
            r = math.hypot(A, B)
            if r < 1e-12 or abs(C) > r * (1 + 1e-12):
                continue
            g0, g1 = math.atan2(B, A), math.acos(max(-1.0, min(1.0, C / r)))
            # a x w and a x z = a x u + cos(phi) a x w - sin(phi) w (w is across a)
            awx, awy, awz = ay * wz - az * wy, az * wx - ax * wz, ax * wy - ay * wx
            for phi in {g0 + g1, g0 - g1}:
                cp, sp = math.cos(phi), math.sin(phi)
                zx, zy, zz = ux + cp * wx + sp * awx, uy + cp * wy + sp * awy, uz + cp * wz + sp * awz
                azx, azy, azz = cp * awx - sp * wx - uax, cp * awy - sp * wy - uay, cp * awz - sp * wz - uaz
                t1 = math.atan2(azx * px + azy * py + azz * pz, zx * px + zy * py + zz * pz)
                t2 = c.s * phi
                for v1 in wrap_into(t1, lo1, hi1):
                    for v2 in wrap_into(t2, lo2, hi2):
                        for v3 in t3_vals:
                            out.append((v1, v2, v3))
        idx = list(lb.joint_indices)

        def full(v: tuple[float, float, float | None]) -> np.ndarray:
            sol = q.copy()
            sol[idx[0]], sol[idx[1]] = v[0], v[1]
            if v[2] is not None:
                sol[idx[2]] = v[2]
            return sol

        # keep exact solutions only (guards degenerate cases), drop duplicates
        if ref is not None:
            r0, r1 = float(ref[idx[0]]), float(ref[idx[1]])
            r2 = float(ref[idx[2]]) if len(idx) > 2 else 0.0
            out.sort(key=lambda v: (v[0] - r0) ** 2 + (v[1] - r1) ** 2 + (0.0 if v[2] is None else (v[2] - r2) ** 2))
            k_b = -1 if bend is None else idx.index(bend[0])
            for v in out:
                if k_b >= 0 and (v[k_b] is None or np.sign(v[k_b] - bend[1]) != bend[2]):
                    continue
                sol = full(v)
                if np.linalg.norm(self.hand_position(sol, lb) - target) <= 1e-8 * scale:
                    return [sol]
            return []
        res: list[np.ndarray] = []
        for v in out:
            sol = full(v)
            if np.linalg.norm(self.hand_position(sol, lb) - target) <= 1e-8 * scale:
                res.append(sol)
        return _unique(res, idx)

    def _ik_abduction(self, lb: Limb, c: _AbductionChain, q: np.ndarray, target: np.ndarray) -> list[np.ndarray]:
        """Closed-form IK of an abduction-pitch-pitch leg (:class:`_AbductionChain`): every first-joint angle
        solving ``alpha + beta cos t1 + gamma sin t1 = k``, each followed by the two-link solve."""
        pin, m, d = self._pin, self.model, self.data
        j1 = lb.joint_ids[0]
        pin.forwardKinematics(m, d, q)
        t = np.array((d.oMi[m.parents[j1]] * m.jointPlacements[j1]).actInv(target))
        a, b2 = c.a, c.b2
        perp = b2 - (a @ b2) * a
        alpha, beta, gamma = float(a @ b2) * float(a @ t), float(perp @ t), float(_cross(a, perp) @ t)
        rho = math.hypot(beta, gamma)
        if rho < 1e-12 or abs(c.k - alpha) > rho * (1 + 1e-12):
            return []
        base_ang, off = math.atan2(gamma, beta), math.acos(max(-1.0, min(1.0, (c.k - alpha) / rho)))
        i1 = lb.joint_indices[0]
        out: list[np.ndarray] = []
        for t1 in {base_ang + off, base_ang - off}:
            for v1 in wrap_into(t1, self.lower[i1], self.upper[i1]):
                q1 = q.copy()
                q1[i1] = v1
                out.extend(self._ik_analytic(c.sub_limb, c.sub, q1, target))
        return _unique(out, list(lb.joint_indices))

    def all_revolute(self, limb: str | int | Limb) -> bool:
        """Whether every joint of ``limb`` is revolute: then no hand lies farther from the limb's first joint than
        :attr:`Limb.reach` (a prismatic joint stretches the limb past the sum of its link offsets)."""
        lb = self.limbs[self._limb_index(limb)]
        out = self._all_revolute.get(lb.name)
        if out is None:
            out = self._all_revolute[lb.name] = all(_revolute_axis(self.model, j, self._pin) is not None
                                                    for j in lb.joint_ids)
        return out

    def _ik_numeric(self, lb: Limb, q: np.ndarray, target: np.ndarray, tol: float,
                    max_iter: int = 200, restarts: int = 8) -> list[np.ndarray]:
        pin, m, d = self._pin, self.model, self.data
        idx = np.array(lb.joint_indices)
        lo, hi = self.lower[idx], self.upper[idx]
        revolute = self.all_revolute(lb.name)
        if revolute and np.linalg.norm(target - self.limb_fk(q, lb)[0]) > lb.reach + 1e-9:
            return []  # farther than the sum of the link lengths
        eye = np.eye(3)
        rng = np.random.default_rng(0)
        lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
        for attempt in range(restarts + 1):
            x = q.copy()
            if attempt:
                x[idx] = rng.uniform(lo, hi)
            lam = 1e-2
            err_prev = np.inf
            best: list[float] = []  # the smallest error so far, per iteration
            for it in range(max_iter):
                J = pin.computeFrameJacobian(m, d, x, lb.frame_id, lwa)[:3, idx]  # (it places the joints too)
                e = target - pin.updateFramePlacement(m, d, lb.frame_id).translation
                err = math.sqrt(float(e @ e))  # np.linalg.norm's own formula, without its overhead
                if err < tol:
                    return [x]
                best.append(min(err, best[-1]) if best else err)
                if it >= IK_STALL and best[-1 - IK_STALL] - best[-1] < IK_STALL_GAIN * best[-1 - IK_STALL]:
                    break  # stuck (a local minimum, or a target outside the limits): the next restart
                lam = max(lam * 0.5, 1e-4) if err < err_prev else min(lam * 4.0, 1.0)  # floor: J J^T may be singular
                err_prev = err
                dq = J.T @ np.linalg.solve(J @ J.T + lam**2 * eye, e)
                x[idx] = np.minimum(np.maximum(x[idx] + dq, lo), hi)  # np.clip, without its overhead
        return []

    # ------------------------------------------------------------------------------------- collision
    def self_collision(self, q: np.ndarray) -> bool:
        """True if two of the robot's links collide (pairs that are not adjacent and not ignored).

        Always False for robots whose spec sets ``self_collision: false``.
        """
        if not self.self_collision_enabled or not self._self_pairs:
            return False
        if self._self_set is None:
            self._self_set = self._make_collision_set(None)
        mgr = self._self_set.datas[frozenset()]
        return bool(self._pin.computeCollisions(self.model, self.data, mgr, np.asarray(q, dtype=float), True))

    def in_collision(self, q: np.ndarray, terrain: Any = None,
                     contact_limbs: Iterable[str | int | Limb] = (), clearance: float = 0.0) -> bool:
        """True if the robot at ``q`` hits the terrain's surfaces or (if enabled) itself.

        Args:
            q: configuration.
            terrain: a :class:`climb_ompl.terrain.Terrain` (its ``surfaces``), or ``None`` for self-collision only.
            contact_limbs: limbs whose hands are at holds: their contact geometry may touch the terrain
                near the hold (:mod:`climb_ompl.contact`: a point contact's tip anywhere; a contact's
                ``links`` within ``near`` metres of the terrain's hold nearest to the hand).
            clearance: two links of the robot closer than this (metres) count as colliding (Coal's
                security margin on the self-collision pairs; the terrain pairs keep none).
        """
        if (terrain is None or not getattr(terrain, "surfaces", ())) and clearance <= 0.0:
            return self.self_collision(q)
        cs, limbs, mgr = self._collision_manager(terrain, contact_limbs, clearance)
        if self._pin.computeCollisions(self.model, self.data, mgr, np.asarray(q, dtype=float), True):
            return True
        return any(self._near_hits(li, cs, mgr._keep[1], first=True) for li in limbs if cs.near_pairs.get(li))

    def collisions(self, q: np.ndarray, terrain: Any = None, contact_limbs: Iterable[str | int | Limb] = (),
                   clearance: float = 0.0) -> list[tuple[str, str]]:
        """The colliding pairs behind :meth:`in_collision` (same arguments), by name, for diagnostics.

        Returns:
            ``(link, link)`` for a self-collision, ``(link, "terrain <k> <type>")`` for the robot against the
            terrain's surface ``k``; empty exactly when :meth:`in_collision` is False.
        """
        q = np.asarray(q, dtype=float)
        cs, limbs, mgr = self._collision_manager(terrain, contact_limbs, clearance)
        gm, gd = mgr._keep
        self._pin.computeCollisions(self.model, self.data, gm, gd, q, False)
        pairs = [(cp.first, cp.second) for k, cp in enumerate(gm.collisionPairs)
                 if gd.activeCollisionPairs[k] and gd.collisionResults[k].isCollision()]
        for li in limbs:
            pairs += self._near_hits(li, cs, gd, first=False)
        return [(self._geom_label(cs, a), self._geom_label(cs, b)) for a, b in pairs]

    def _geom_label(self, cs: _CollisionSet, g: int) -> str:
        if g in cs.terrain_geoms:
            k = cs.terrain_geoms.index(g)
            return f"terrain {k} {cs.terrain.surfaces[k].type}"
        return str(self.model.frames[cs.geom_model.geometryObjects[g].parentFrame].name)

    def _collision_manager(self, terrain: Any, contact_limbs: Iterable[str | int | Limb],
                           clearance: float) -> tuple[_CollisionSet, frozenset[int], Any]:
        """The collision set of ``terrain`` (cached) and its broad phase for these contact limbs and clearance."""
        cs = self._terrain_sets.get(id(terrain))
        if cs is None or cs.terrain is not terrain:
            if len(self._terrain_sets) > 16:
                self._terrain_sets.clear()
            cs = self._make_collision_set(terrain)
            self._terrain_sets[id(terrain)] = cs
        limbs = frozenset(self._limb_index(lb) for lb in contact_limbs)
        key = limbs if clearance <= 0.0 else (limbs, float(clearance))
        mgr = cs.datas.get(key)
        if mgr is None:
            gd = cs.geom_model.createData()
            for k, pair in enumerate(cs.geom_model.collisionPairs):
                g1, g2 = pair.first, pair.second
                robot_pair = g1 not in cs.terrain_geoms and g2 not in cs.terrain_geoms
                if robot_pair and clearance > 0.0:
                    gd.collisionRequests[k].security_margin = float(clearance)
                for li in limbs:
                    hg = self._hand_geoms[li].union(self._near_geoms[li])
                    if (g1 in hg and g2 in cs.terrain_geoms) or (g2 in hg and g1 in cs.terrain_geoms):
                        gd.deactivateCollisionPair(k)
                    if (g1 in self._near_geoms[li] and g2 in cs.terrain_geoms) or (
                            g2 in self._near_geoms[li] and g1 in cs.terrain_geoms):
                        gd.collisionRequests[k].enable_contact = True  # checked by _near_hits
                        gd.collisionRequests[k].num_max_contacts = 8
            mgr = cs.datas[key] = self._manager(cs.geom_model, gd)
        return cs, limbs, mgr

    def _near_hits(self, li: int, cs: _CollisionSet, gd: Any, first: bool) -> list[tuple[int, int]]:
        """Pairs (geometry, terrain geometry) where a contact link of limb ``li`` touches the terrain farther
        than ``contact.near`` from its hold (the terrain's hold nearest to the hand).  ``gd`` (with contacts
        requested on those pairs) and ``self.data`` hold the placements of the last check.  ``first``: stop at
        the first such pair."""
        pin = self._pin
        out: list[tuple[int, int]] = []
        pairs = cs.near_pairs.get(li, ())
        if not pairs:
            return out
        lb = self.limbs[li]
        hand = np.array(pin.updateFramePlacement(self.model, self.data, lb.frame_id).translation)
        P = cs.terrain.positions
        hold = P[int(np.argmin(np.linalg.norm(P - hand, axis=1)))]
        cps = cs.geom_model.collisionPairs
        for k in pairs:
            if not pin.computeCollision(cs.geom_model, gd, k):
                continue
            contacts = gd.collisionResults[k].getContacts()
            if any(np.linalg.norm(np.asarray(c.pos) - hold) > lb.contact.near for c in contacts):
                out.append((cps[k].first, cps[k].second))
                if first:
                    return out
        return out

    def _manager(self, gm: Any, gd: Any) -> Any:
        """A broad phase over the active pairs of ``gd``: axis-aligned boxes first, Coal's narrow phase after.

        The naive (all-pairs box test) manager is the fastest here: with a few tens of geometries and an
        unbounded wall half-space, tree managers cost more than they prune (``climb-ompl bench robot``).
        """
        mgr = self._pin.BroadPhaseManager_NaiveCollisionManager(self.model, gm, gd)
        mgr._keep = (gm, gd)  # the manager refers to both; keep them alive with it
        return mgr

    def collision_pairs(self) -> list[tuple[str, str]]:
        """Names of the robot geometry pairs tested for self-collision (empty when disabled)."""
        if not self.self_collision_enabled:
            return []
        objs = self.collision_model.geometryObjects
        return [(objs[i].name, objs[j].name) for i, j in self._self_pairs]

    def _make_collision_set(self, terrain: Any) -> _CollisionSet:
        import coal

        pin = self._pin
        gm = self.collision_model.copy()
        gm.removeAllCollisionPairs()
        if self.self_collision_enabled:
            for i, j in self._self_pairs:
                gm.addCollisionPair(pin.CollisionPair(i, j))
        n_robot = gm.ngeoms
        tg: list[int] = []
        for k, s in enumerate(getattr(terrain, "surfaces", ()) if terrain is not None else ()):
            c = np.asarray(s.center, dtype=float)
            if s.type == "plane":
                n = np.asarray(s.normal, dtype=float)
                geom, placement = coal.Halfspace(n, float(n @ c)), pin.SE3.Identity()
            elif s.type == "box":
                geom, placement = coal.Box(*[float(x) for x in s.size]), pin.SE3(np.eye(3), c)
            elif s.type == "circle":  # a disc in the x-z plane: a cylinder along y
                geom = coal.Cylinder(float(s.radius), 1.0)
                placement = pin.SE3(_rot(np.array([1.0, 0.0, 0.0]), math.pi / 2), c)
            else:  # pragma: no cover - terrain.py validates surface types
                continue
            tg.append(gm.addGeometryObject(pin.GeometryObject(f"terrain_{k}_{s.type}", 0, 0, placement, geom)))
        for gi in range(n_robot):
            for gj in tg:
                gm.addCollisionPair(pin.CollisionPair(gi, gj))
        cs = _CollisionSet(gm, terrain_geoms=tuple(tg), terrain=terrain)
        for li, near in enumerate(self._near_geoms):
            ks = tuple(k for k, cp in enumerate(gm.collisionPairs) if (cp.first in near and cp.second in tg)
                       or (cp.second in near and cp.first in tg))
            if ks:
                cs.near_pairs[li] = ks
        cs.datas[frozenset()] = self._manager(gm, gm.createData())
        return cs

    def _compute_self_pairs(self) -> list[tuple[int, int]]:
        """Geometry pairs tested for self-collision: not on one body nor on adjacent bodies (MoveIt's default),
        not ignored by the spec, not disabled by the SRDF."""
        m = self.model
        objs = list(self.collision_model.geometryObjects)
        allowed = self._srdf_allowed_pairs()
        pairs = []
        for i in range(len(objs)):
            for j in range(i + 1, len(objs)):
                ji, jj = objs[i].parentJoint, objs[j].parentJoint
                if ji == jj or m.parents[ji] == jj or m.parents[jj] == ji:
                    continue  # same body or bodies joined by a joint (they touch at the joint)
                li, lj = m.frames[objs[i].parentFrame].name, m.frames[objs[j].parentFrame].name
                if frozenset((li, lj)) in self._ignore:
                    continue
                if allowed is not None and (i, j) not in allowed:
                    continue
                pairs.append((i, j))
        return pairs

    def _srdf_allowed_pairs(self) -> set[tuple[int, int]] | None:
        """Geometry pairs left after removing the SRDF's ``disable_collisions`` (``pin.removeCollisionPairs``)."""
        if self.srdf_path is None:
            return None
        pin = self._pin
        gm = self.collision_model.copy()
        gm.addAllCollisionPairs()
        try:
            pin.removeCollisionPairs(self.model, gm, str(self.srdf_path))
        except (RuntimeError, ValueError, OSError) as exc:
            raise RobotModelError(self.srdf_path, "srdf", f"Pinocchio cannot read it ({exc})") from None
        return {(min(p.first, p.second), max(p.first, p.second)) for p in gm.collisionPairs}

    def _hand_link_geoms(self, lb: Limb) -> frozenset[int]:
        """Geometry on the link of ``lb``'s hand frame (an operational frame: the link it hangs on)."""
        m = self.model
        hosts = {lb.frame_id}
        fid = lb.frame_id
        while m.frames[fid].type != self._pin.FrameType.BODY and m.frames[fid].parentFrame != fid:
            fid = m.frames[fid].parentFrame
            hosts.add(fid)
        return frozenset(i for i, o in enumerate(self.collision_model.geometryObjects) if o.parentFrame in hosts)

    def _compute_hand_geoms(self) -> list[frozenset[int]]:
        """Per limb, the geometry exempt from terrain collision anywhere while in contact (point contacts:
        the tip on the hand's link)."""
        return [self._hand_link_geoms(lb) if lb.contact.type == "point" else frozenset() for lb in self.limbs]

    def _compute_near_geoms(self, src: str) -> list[tuple[int, ...]]:
        """Per limb, the geometry that may touch the terrain within ``contact.near`` of the hold.

        Default: none for a point contact; for a sphere, the hand's link and the links moved only by the
        limb's last joint.  A spec's ``contact.links`` replaces the default.
        """
        m, objs = self.model, list(self.collision_model.geometryObjects)
        links = {f.name: i for i, f in enumerate(m.frames) if f.type == self._pin.FrameType.BODY}
        out = []
        for k, lb in enumerate(self.limbs):
            c = lb.contact
            if c.links is not None:
                for name in c.links:
                    if name not in links:
                        raise RobotModelError(src, f"limbs[{k}].contact.links", f"unknown link {name!r}")
                hosts = {links[n] for n in c.links}
                geoms = {i for i, o in enumerate(objs) if o.parentFrame in hosts}
            elif c.type == "point":
                geoms = set()
            else:
                last = lb.joint_ids[-1] if lb.joint_ids else m.frames[lb.frame_id].parentJoint
                geoms = set(self._hand_link_geoms(lb)) | {i for i, o in enumerate(objs) if o.parentJoint == last}
            out.append(tuple(sorted(geoms - self._hand_geoms[k])))
        return out

    def _ignore_pairs(self, raw: Any, src: str) -> set[frozenset[str]]:
        links = {f.name for f in self.model.frames if f.type == self._pin.FrameType.BODY}
        out = set()
        for i, pair in enumerate(raw):
            if not isinstance(pair, (list, tuple)) or len(pair) != 2:
                raise RobotModelError(src, f"ignore_collision_pairs[{i}]", "expected a pair [link, link]")
            for name in pair:
                if name not in links:
                    raise RobotModelError(src, f"ignore_collision_pairs[{i}]", f"unknown link {name!r}")
            out.add(frozenset(pair))
        return out

    # ------------------------------------------------------------------------------------- spec helpers
    def _coordinate_names(self, base_type: str | None = None) -> tuple[str, ...]:
        """Name of each coordinate: its joint's, ``joint[k]`` inside a multi-coordinate joint, and for a base
        built here (``base.type``) ``base_x, base_z, base_theta`` (planar) or ``base_x, base_y, base_z,
        base_rz, base_ry, base_rx`` (spatial; angles about the reference orientation's axes)."""
        m = self.model
        names = [""] * m.nq
        for j in range(1, m.njoints):
            for k in range(m.joints[j].nq):
                names[m.joints[j].idx_q + k] = m.names[j] if m.joints[j].nq == 1 else f"{m.names[j]}[{k}]"
        own = {"planar": ("base_x", "base_z", "base_theta"),
               "spatial": ("base_x", "base_y", "base_z", "base_rz", "base_ry", "base_rx")}.get(base_type or "")
        if own and not any(m.existJointName(n) for n in own):
            names[:len(own)] = own
        return tuple(names)

    def _coordinate(self, name: Any, src: str, fld: str) -> int:
        """Index into ``q`` of a one-coordinate joint or of a named coordinate of :attr:`joint_names`."""
        if isinstance(name, str) and not self.model.existJointName(name) and name in self.joint_names:
            return self.joint_names.index(name)
        return self._joint_q(name, src, fld)

    def _joint_id(self, name: Any, src: str, fld: str) -> int:
        m = self.model
        if not isinstance(name, str) or not m.existJointName(name):
            raise RobotModelError(src, fld, f"joint {name!r} not in the URDF {self.urdf_path.name}")
        return int(m.getJointId(name))

    def _joint_q(self, name: Any, src: str, fld: str) -> int:
        jid = self._joint_id(name, src, fld)
        if self.model.joints[jid].nq != 1:
            raise RobotModelError(src, fld, f"joint {name!r} has {self.model.joints[jid].nq} coordinates, expected 1")
        return int(self.model.joints[jid].idx_q)

    def _build_limbs(self, raw: list[dict[str, Any]], src: str) -> tuple[Limb, ...]:
        m, pin = self.model, self._pin
        limbs: list[Limb] = []
        owner: dict[str, str] = {}
        hands: dict[str, str] = {}  # hand frame -> limb
        names: set[str] = set()
        for i, rl in enumerate(raw):
            f = f"limbs[{i}]"
            name = rl["name"]
            if name in names:
                raise RobotModelError(src, f"{f}.name", f"duplicate limb name {name!r}")
            names.add(name)
            hf = rl["hand_frame"]
            if not m.existFrame(hf):
                raise RobotModelError(src, f"{f}.hand_frame", f"unknown frame {hf!r} (not a link or joint of "
                                      f"{self.urdf_path.name})")
            hand_name = hf
            fid = int(m.getFrameId(hf))
            contact = parse_contact(rl.get("contact"), src, f"{f}.contact")
            if any(contact.offset):  # a frame at the sphere's centre becomes the limb's hand frame
                fr = m.frames[fid]
                hf = f"{hf}_sphere_centre"
                place = fr.placement * pin.SE3(np.eye(3), np.asarray(contact.offset, dtype=float))
                fid = int(m.addFrame(pin.Frame(hf, fr.parentJoint, fid, place, pin.FrameType.OP_FRAME)))
            jids, qidx = [], []
            for k, jn in enumerate(rl["joints"]):
                jid = self._joint_id(jn, src, f"{f}.joints[{k}]")
                if jn in owner:
                    raise RobotModelError(src, f"{f}.joints[{k}]",
                                          f"limb {name!r} shares joint {jn!r} with limb {owner[jn]!r}")
                owner[jn] = name
                jids.append(jid)
                qidx.append(self._joint_q(jn, src, f"{f}.joints[{k}]"))
            # every limb joint must lie on the path from the root to the hand
            path = list(m.supports[m.frames[fid].parentJoint])  # root to the hand's joint
            for k, jid in enumerate(jids):
                if jid not in path:
                    raise RobotModelError(src, f"{f}.joints[{k}]",
                                          f"joint {m.names[jid]!r} does not move frame {hf!r}")
            if jids != sorted(jids, key=path.index):
                raise RobotModelError(src, f"{f}.joints", "list the joints from the root to the hand: "
                                      f"[{', '.join(m.names[j] for j in sorted(jids, key=path.index))}]")
            if hand_name in hands:
                raise RobotModelError(src, f"{f}.hand_frame", f"limb {name!r} has the hand frame {hand_name!r} of "
                                      f"limb {hands[hand_name]!r}: two limbs cannot touch with one hand")
            hands[hand_name] = name
            elbow = rl.get("elbow")
            e_idx: int | None = None
            e_str: float | None = None
            if elbow is not None:
                if elbow not in rl["joints"]:
                    raise RobotModelError(src, f"{f}.elbow", f"elbow {elbow!r} is not one of the limb's joints")
                e_idx = self._joint_q(elbow, src, f"{f}.elbow")
                # straight = 0 unless given; a default outside the bounds becomes the nearest bound
                e_str = float(rl.get("elbow_straight", np.clip(0.0, self.lower[e_idx], self.upper[e_idx])))
                if not (self.lower[e_idx] <= e_str <= self.upper[e_idx]):
                    raise RobotModelError(src, f"{f}.elbow_straight",
                                          f"{e_str} is outside the joint bounds [{float(self.lower[e_idx])!r}, "
                                          f"{float(self.upper[e_idx])!r}] (the URDF's, in radians or metres)")
            reach = self._reach(jids, fid)
            limbs.append(Limb(name, hf, tuple(qidx), e_idx, e_str, reach, fid, tuple(jids), contact=contact))
        return tuple(limbs)

    def _locked_reach(self, lb: Limb) -> Limb:
        """``lb`` with its reach bounded again when a joint between its first joint and its hand is in no limb
        (locked at its nominal value): the sum, at the nominal configuration, of the distances between
        consecutive limb joints and from the last one to the hand.  Each limb joint turns what follows it about
        an axis through its own origin, so these distances do not change; :meth:`_reach` adds the locked
        joints' offsets one by one, as if they could straighten."""
        m = self.model
        path = list(m.supports[m.frames[lb.frame_id].parentJoint])
        if not lb.joint_ids or set(path[path.index(lb.joint_ids[0]):]) <= set(lb.joint_ids):
            return lb
        pts = self.limb_fk(self.nominal_q, lb)
        return replace(lb, reach=float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()))

    def _reach(self, jids: list[int], fid: int) -> float:
        """Sum of the link offsets from the first limb joint to the hand (an upper bound on the reach)."""
        m = self.model
        if not jids:
            return 0.0
        chain = []
        j = m.frames[fid].parentJoint
        while j != jids[0] and j > 0:
            chain.append(j)
            j = m.parents[j]
        total = float(np.linalg.norm(m.frames[fid].placement.translation))
        total += sum(float(np.linalg.norm(m.jointPlacements[c].translation)) for c in chain)
        return total

    def _analytic_chain(self, lb: Limb) -> _AnalyticChain | _AbductionChain | None:
        """Closed-form IK constants if the limb is yaw-yaw or yaw-yaw-pitch (see :class:`_AnalyticChain`), or
        abduction-pitch-pitch (:class:`_AbductionChain`, a quadruped's leg)."""
        m, pin = self.model, self._pin
        jids = lb.joint_ids
        if len(jids) not in (2, 3):
            return None
        if len(jids) == 3 and m.parents[jids[1]] == jids[0] and _revolute_axis(m, jids[0], pin) is not None:
            sub_limb = replace(lb, joint_ids=jids[1:], joint_indices=lb.joint_indices[1:])
            sub = self._analytic_chain(sub_limb)
            a = _revolute_axis(m, jids[0], pin)
            R2 = np.array(m.jointPlacements[jids[1]].rotation)
            if sub is not None and sub.b is None and abs(abs(float(a @ (R2 @ sub.a))) - 1.0) > 1e-9:
                # hand component along the parallel axes (joint 2's frame): constant whatever t2, t3
                k = float(sub.a @ (sub.p_e + sub.R_e @ sub.p_h))
                b2 = R2 @ sub.a
                return _AbductionChain(a, b2, k + float(b2 @ np.array(m.jointPlacements[jids[1]].translation)),
                                       sub_limb, sub)
        axes = []
        for j in jids:
            ax = _revolute_axis(m, j, pin)
            if ax is None:
                return None
            axes.append(ax)
        for k in range(1, len(jids)):
            if m.parents[jids[k]] != jids[k - 1]:
                return None
        fr = m.frames[lb.frame_id]
        if fr.parentJoint != jids[-1]:
            return None
        a = axes[0]
        R_e = np.array(m.jointPlacements[jids[1]].rotation)
        p_e = np.array(m.jointPlacements[jids[1]].translation)
        dot = float(a @ (R_e @ axes[1]))
        if abs(abs(dot) - 1.0) > 1e-9:
            return None
        s = 1.0 if dot > 0 else -1.0
        p_h = np.array(fr.placement.translation)
        if len(jids) == 2:
            return _AnalyticChain(a, s, p_e, R_e, p_h)
        R_w = np.array(m.jointPlacements[jids[2]].rotation)
        p_w = np.array(m.jointPlacements[jids[2]].translation)
        b = axes[2]
        if abs(abs(float(a @ (R_e @ (R_w @ b)))) - 1.0) < 1e-9:
            return None  # a third parallel axis: a redundant planar 3R limb, solved numerically
        return _AnalyticChain(a, s, p_e, R_e, p_h, p_w, R_w, b)

    def _narrow_limits(self, raw: Any, src: str) -> None:
        """Spec ``joint_limits: {joint: [lower, upper]}``: a narrower range than the URDF's (e.g. one turn of a
        joint the URDF bounds by +-3 turns, so that IK and sampling stay in the posture the robot uses)."""
        m = self.model
        if not isinstance(raw, dict):
            raise RobotModelError(src, "joint_limits", "expected a mapping joint -> [lower, upper]")
        for jn, val in raw.items():
            i = self._joint_q(jn, src, f"joint_limits.{jn}")
            if (not isinstance(val, list) or len(val) != 2
                    or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in val)
                    or not val[0] < val[1]):
                raise RobotModelError(src, f"joint_limits.{jn}", f"expected [lower, upper] with lower < upper, "
                                      f"got {val!r}")
            lo, hi = float(m.lowerPositionLimit[i]), float(m.upperPositionLimit[i])
            if val[0] < lo - 1e-9 or val[1] > hi + 1e-9:
                raise RobotModelError(src, f"joint_limits.{jn}", f"{val} is not inside the URDF's bounds "
                                      f"[{lo:.4g}, {hi:.4g}] (joint_limits may only narrow them)")
            m.lowerPositionLimit[i], m.upperPositionLimit[i] = float(val[0]), float(val[1])

    def _nominal(self, raw: Any, src: str) -> np.ndarray:
        if not isinstance(raw, dict):
            raise RobotModelError(src, "nominal", "expected a mapping joint -> value")
        q = np.clip(np.zeros(self.nq), self.lower, self.upper)
        for jn, val in raw.items():
            i = self._coordinate(jn, src, f"nominal.{jn}")
            if isinstance(val, bool) or not isinstance(val, (int, float)):
                raise RobotModelError(src, f"nominal.{jn}", f"expected a number, got {val!r}{number_hint(val)}")
            if not (self.lower[i] - 1e-9 <= val <= self.upper[i] + 1e-9):
                raise RobotModelError(src, f"nominal.{jn}", f"{val} outside the joint bounds "
                                      f"[{self.lower[i]:.4g}, {self.upper[i]:.4g}]")
            q[i] = float(val)
        return q


# ---------------------------------------------------------------------------------------------- validation
def _revolute_axis(m: Any, j: int, pin: Any) -> np.ndarray | None:
    """Unit axis of revolute joint ``j`` in its own frame (from its Jacobian column), or None otherwise."""
    jm = m.joints[j]
    if jm.nq != 1:
        return None
    d = m.createData()
    J = pin.computeJointJacobian(m, d, pin.neutral(m), j)[:, jm.idx_v]
    lin, ang = np.asarray(J[:3]), np.asarray(J[3:])
    if np.linalg.norm(lin) > 1e-12 or abs(np.linalg.norm(ang) - 1.0) > 1e-9:
        return None  # prismatic (or a coupled joint)
    return ang / np.linalg.norm(ang)


def _check_urdf_masses(path: Path, massless: set[str], src: str) -> None:
    """A moving link (child of a non-fixed joint) that carries geometry must carry a mass."""
    try:
        root = ET.parse(path).getroot()
    except ET.ParseError as exc:
        raise RobotModelError(path, "urdf", f"invalid XML ({exc})") from None
    moving = {j.find("child").get("link") for j in root.iter("joint")
              if j.get("type") != "fixed" and j.find("child") is not None}
    links = {ln.get("name"): ln for ln in root.iter("link")}
    for name in massless:
        if name not in links:
            raise RobotModelError(src, "massless_links", f"unknown link {name!r}")
    for name, ln in links.items():
        if name not in moving or name in massless:
            continue
        if ln.find("visual") is None and ln.find("collision") is None:
            continue
        mass_el = ln.find("inertial/mass")
        mass = float(mass_el.get("value", "0")) if mass_el is not None else 0.0
        if mass <= 0:
            raise RobotModelError(path, f"links.{name}.inertial",
                                  "missing mass: a moving link with geometry has no <inertial> mass (list it "
                                  "in the spec's massless_links if that is intended)")


def _composite_base(base: dict[str, Any], src: str) -> Any:
    import pinocchio as pin

    kind = base["type"]
    root = pin.JointModelComposite()
    known = {"type", "lower", "upper"} | ({"reference_rpy"} if kind == "spatial" else set())
    extra = sorted(set(base) - known)
    if extra:
        raise RobotModelError(src, f"base.{extra[0]}", f"unknown field for a {kind} base; known: "
                              f"{', '.join(sorted(known))}")
    if kind == "planar":
        n = 3
        for jm in (pin.JointModelPX(), pin.JointModelPZ(), pin.JointModelRevoluteUnaligned(0.0, -1.0, 0.0)):
            root.addJoint(jm)
    elif kind == "spatial":
        n = 6
        ref = base.get("reference_rpy", [0.0, 0.0, 0.0])
        if (not isinstance(ref, list) or len(ref) != 3
                or not all(isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in ref)):
            raise RobotModelError(src, "base.reference_rpy", f"expected 3 angles [roll, pitch, yaw] in radians, "
                                  f"got {ref!r}")
        R_ref = np.asarray(pin.rpy.rpyToMatrix(*[float(x) for x in ref]))
        for jm in (pin.JointModelPX(), pin.JointModelPY(), pin.JointModelPZ()):
            root.addJoint(jm)
        root.addJoint(pin.JointModelRZ(), pin.SE3(R_ref, np.zeros(3)))  # angles about the reference orientation
        for jm in (pin.JointModelRY(), pin.JointModelRX()):
            root.addJoint(jm)
    else:
        raise RobotModelError(src, "base.type", f"must be planar or spatial, got {kind!r}")
    for key in ("lower", "upper"):
        val = base.get(key)
        if not isinstance(val, list) or len(val) != n or not all(isinstance(x, (int, float)) for x in val):
            raise RobotModelError(src, f"base.{key}", f"expected a list of {n} numbers (bounds of the {kind} base)")
    for i, (lo, hi) in enumerate(zip(base["lower"], base["upper"], strict=True)):
        if lo >= hi:
            raise RobotModelError(src, f"base.upper[{i}]", f"{hi:g} is not above base.lower[{i}] = {lo:g} (each "
                                  f"coordinate of the {kind} base needs lower < upper)")
    return root


def _climb_section(val: Any, src: str) -> dict[str, Any]:
    """The spec's ``climb`` section, checked as settings of a climb (:class:`~climb_ompl.settings.ClimbSettings`):
    a mapping of setting names to values, except :data:`~climb_ompl.settings.NOT_GIVEN`.  A bad value is reported
    under ``climb.<name>``; settings that do not go together (a custom sampler on a space that never calls it) under
    the setting :class:`ClimbSettings` names."""
    from .errors import PlannerNotFound, QueryError
    from .settings import NOT_GIVEN, ClimbSettings, setting_error, unknown_setting

    if val is None:
        return {}
    if not isinstance(val, dict):
        raise RobotModelError(src, "climb", f"expected a mapping of climb settings, got {val!r}")
    for key in val:
        if key in NOT_GIVEN:
            raise RobotModelError(src, f"climb.{key}", "not a robot default (search: a mode chosen per climb; "
                                  "tolerance: recorded, not a choice)")
        unknown = unknown_setting(key)
        if unknown:
            raise RobotModelError(src, f"climb.{key}", unknown)
    try:
        ClimbSettings.from_dict(dict(val), source="climb")
    except QueryError as e:
        key, reason = setting_error(e)
        raise RobotModelError(src, f"climb.{key}" if key in val else "climb", reason if key in val else str(e)) \
            from None
    except PlannerNotFound as e:  # an unknown planner, space or sampler name
        raise RobotModelError(src, f"climb.{e.kind}", str(e)) from None
    return dict(val)


def _check_spec_shape(spec: Any, src: str) -> None:
    """Types and required fields of a spec (names are checked against the URDF later)."""
    if not isinstance(spec, dict):
        raise RobotModelError(src, "(top level)", "expected a mapping with name, urdf, base, limbs")
    extra = sorted(set(spec) - _SPEC_FIELDS)
    if extra:
        raise RobotModelError(src, extra[0], f"unknown field; known fields: {', '.join(sorted(_SPEC_FIELDS))}")
    for key in ("name", "urdf", "base", "limbs"):
        if key not in spec:
            raise RobotModelError(src, key, "missing required field")
    if not isinstance(spec["name"], str) or not spec["name"]:
        raise RobotModelError(src, "name", "must be a non-empty string")
    base = spec["base"]
    if not isinstance(base, dict) or not (("joints" in base) ^ ("type" in base)):
        raise RobotModelError(src, "base", "expected {joints: [names]} or {type: planar|spatial, lower, upper}")
    if "joints" in base and (not isinstance(base["joints"], list)
                             or not all(isinstance(x, str) for x in base["joints"])):
        raise RobotModelError(src, "base.joints", "expected a list of joint names")
    limbs = spec["limbs"]
    if not isinstance(limbs, list) or not limbs:
        raise RobotModelError(src, "limbs", "expected a non-empty list of limbs")
    for i, lb in enumerate(limbs):
        f = f"limbs[{i}]"
        if not isinstance(lb, dict):
            raise RobotModelError(src, f, "expected a mapping with name, hand_frame, joints")
        unknown = sorted(set(lb) - _LIMB_FIELDS)
        if unknown:
            raise RobotModelError(src, f"{f}.{unknown[0]}", f"unknown field; known: {', '.join(sorted(_LIMB_FIELDS))}")
        for key in ("name", "hand_frame", "joints"):
            if key not in lb:
                raise RobotModelError(src, f"{f}.{key}", "missing required field")
        if not isinstance(lb["name"], str) or not lb["name"]:
            raise RobotModelError(src, f"{f}.name", "must be a non-empty string")
        if not isinstance(lb["joints"], list) or not all(isinstance(x, str) for x in lb["joints"]):
            raise RobotModelError(src, f"{f}.joints", "expected a list of joint names")
        if lb.get("ik", "auto") not in _IK_KINDS:
            raise RobotModelError(src, f"{f}.ik", f"must be one of {', '.join(_IK_KINDS)}, got {lb['ik']!r}")
        es = lb.get("elbow_straight", 0.0)
        if isinstance(es, bool) or not isinstance(es, (int, float)):
            raise RobotModelError(src, f"{f}.elbow_straight", f"expected a number, got {es!r}{number_hint(es)}")
    if "mass" in spec:
        m = spec["mass"]
        if isinstance(m, bool) or not isinstance(m, (int, float)) or not m > 0:
            raise RobotModelError(src, "mass", f"expected a positive number of kg, got {m!r}")
    for key in ("torque_limits", "velocity_limits"):
        val = spec.get(key)
        if val is None:
            continue
        if not isinstance(val, dict):
            raise RobotModelError(src, key, "expected a mapping joint -> limit")
        for jn, x in val.items():
            if isinstance(x, bool) or not isinstance(x, (int, float)) or not x > 0:
                raise RobotModelError(src, f"{key}.{jn}", f"expected a positive number, got {x!r}")
    for key in ("planar", "self_collision", "equilibrium"):
        if key in spec and not isinstance(spec[key], bool):
            raise RobotModelError(src, key, f"expected true or false, got {spec[key]!r}")
    for key in ("massless_links", "package_dirs", "ignore_collision_pairs"):
        if key in spec and spec[key] is not None and not isinstance(spec[key], list):
            raise RobotModelError(src, key, "expected a list")
