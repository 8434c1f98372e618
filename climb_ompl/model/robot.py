"""Robot models: a URDF (kinematics, masses, collision geometry) plus a short limb spec (YAML).

A robot is loaded from ``robots/<name>.yaml`` (bundled) or a user's spec file::

    name: lemur
    urdf: lemur.urdf              # bundled: a file of the urdf folder; user robots: a path relative to the spec
    # urdf_package: example-robot-data   # optional: urdf and srdf are paths inside that installed package's
    #                                    # share folder (climb_ompl/model/files.py; docs/robots.md)
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
        contact: {type: sphere, radius: 0.02}   # optional (default point): climb_ompl/model/contact.py
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
    climb: {path_retry_growth: 2}         # optional: this robot's defaults for the climb's settings
                                          # (climb_ompl.settings.ClimbSettings; options given to a climb win)
    # also accepted: ``base_joints: [...]`` for ``base: {joints: [...]}``, ``nominal_q: [nq numbers]`` for
    # ``nominal``, and a free-form ``gait`` section read by climb_ompl.mrwallspect (MRWALLSPECT III).

Configurations are plain vectors (``nq == nv``): no ``continuous`` joints (OMPL's constrained
spaces are built on a real-vector ambient space).
Frames: world z up; planar robots in the x-z plane; 3-D walls are the plane y = 0 with the robot on the
+y side (``climb_ompl/model/terrain.py``).  Lengths in metres, angles in radians, masses in kilograms.

Spatial base: three prismatic joints then three revolute joints about z, y, x (Z-Y-X angles).  Those
angles are singular where the middle one is +-90 deg; ``reference_rpy`` (roll, pitch, yaw of a reference
orientation, URDF convention ``R = Rz(yaw) Ry(pitch) Rx(roll)``) makes the base orientation
``R_ref Rz(q3) Ry(q4) Rx(q5)``, so zero angles are the reference and the singularity lies where the body's
x axis is along the reference's z axis.  For a robot standing on a wall (body z along the wall normal +y,
body x up the wall) ``reference_rpy: [-pi/2, -pi/2, 0]`` puts the singularity at the body's x axis along the
wall normal, a pose a climber never takes.  Configurations stay plain real vectors.

Inverse kinematics: :mod:`climb_ompl.model.limb_ik` (closed forms recognised from the joint axes, else damped least
squares).  Collision against the terrain and the robot itself: :mod:`climb_ompl.model.collision` (Coal geometry
from the URDF, adjacent links and the SRDF's ``disable_collisions`` pairs skipped, contact geometry allowed to
touch near its hold).  The spec's shape is checked by :mod:`climb_ompl.model.spec`.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from climb_ompl._io import captured_stderr, load_yaml, number_hint
from climb_ompl.errors import RobotModelError
from climb_ompl.model.collision import CollisionChecker
from climb_ompl.model.contact import POINT, Contact, parse_contact
from climb_ompl.model.files import package_share, resolve_robot_file
from climb_ompl.model.limb_ik import (
    AbductionChain,
    analytic_chain,
    ik_abduction,
    ik_analytic,
    ik_numeric,
    revolute_axis,
)
from climb_ompl.model.spec import check_spec_shape, check_urdf_masses, climb_section, composite_base
from climb_ompl.resources import bundled, resolve, robots_dir

__all__ = ["Limb", "RobotModel", "bundled_robots"]

_MASS_RTOL = 0.01


def bundled_robots() -> list[str]:
    """Names of the robots shipped with the package (``robots/*.yaml``)."""
    return bundled(robots_dir())


#: How far from a joint bound (outside or inside) an ``elbow_straight`` is read as that bound, radians (or metres):
#: a bound copied from a URDF to three decimals (A1's knee stops at -0.91629..., a spec gives -0.916); a straight
#: angle left a hair inside the bound would name a sliver of the joint's range the other bend.
BOUND_ROUNDING = 0.005


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
        contact: the contact geometry (:class:`climb_ompl.model.contact.Contact`; a point by default).  For a
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





def _did_you_mean(name: Any, valid: Any, shown: Any = None, label: str = "valid") -> str:
    """``"; did you mean 'X'? (valid: a, b, ...)"`` for an unknown name among ``valid``; the list is ``shown`` (default
    ``valid``) cut at 40, under ``label``."""
    from climb_ompl.errors import nearest_name

    valid = [str(v) for v in valid if str(v)]
    listed = valid if shown is None else [str(v) for v in shown if str(v)]
    near = nearest_name(name, valid)
    text = ", ".join(listed[:40]) + (f", ... ({len(listed)} in all)" if len(listed) > 40 else "")
    return (f"; did you mean {near!r}?" if near else "") + f" ({label}: {text})"


class RobotModel:
    """A climbing robot: Pinocchio model + Coal collision geometry + limb description.

    Build with :meth:`load` (bundled name or spec path) or :meth:`from_spec` (a dict).  Attributes
    follow ``docs/dev/CONTRACTS.md``: ``name, nq, lower, upper, velocity_limits, torque_limits (inf where
    unactuated), actuated, base_indices, limbs, mass, planar, nominal_q, model, data, collision_model,
    visual_model, spec, spec_path, urdf_path``; also ``urdf_text``, ``equilibrium``, ``self_collision_enabled``,
    ``srdf_path`` and ``joint_names`` (the name of the joint of each configuration coordinate).

    Contacts (:mod:`climb_ompl.model.contact`): :meth:`hand_target` (where a hand frame goes to touch a hold),
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
        check_spec_shape(spec, src)
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
        check_urdf_masses(self.urdf_path, set(spec.get("massless_links", []) or []), src)

        base = spec["base"]
        root = composite_base(base, src) if "type" in base else None
        parser_said: list[str] = []
        try:
            with captured_stderr(parser_said):  # urdfdom prints its errors straight to the terminal
                model = (pin.buildModelFromUrdf(str(self.urdf_path), root) if root is not None
                         else pin.buildModelFromUrdf(str(self.urdf_path)))
        except (RuntimeError, ValueError) as exc:
            said = next((ln.strip()[len("Error:"):].strip() for ln in parser_said if ln.strip().startswith("Error:")),
                        "")
            raise RobotModelError(self.urdf_path, "urdf", f"not a valid URDF: {said}" if said else
                                  f"Pinocchio cannot parse it ({exc})") from None
        self.model = model
        #: what the SRDF's pairs name against the URDF (:class:`~climb_ompl.model.collision.SrdfLinks`), or ``None``
        self.srdf_links: Any = None
        if self.srdf_path is not None:
            from climb_ompl.model.collision import check_srdf

            self.srdf_links = check_srdf(self.srdf_path, model, src)
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
        self.climb: dict[str, Any] = climb_section(spec.get("climb"), src)
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
        self._chains = {lb.name: analytic_chain(model, pin, lb) for lb in self.limbs}
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
        #: the URDF's text as read (a plan embeds it; the visual geometry is built from it when the file is gone)
        self.urdf_text: str = self.urdf_path.read_text()
        try:
            self.collision_model = pin.buildGeomFromUrdf(model, str(self.urdf_path), pin.COLLISION, package_dirs=pkg)
        except (RuntimeError, ValueError, OSError) as exc:
            raise RobotModelError(self.urdf_path, "geometry", f"cannot build collision geometry ({exc})") from None
        self.self_collision_enabled: bool = bool(spec.get("self_collision", True))
        #: the collision queries (:class:`~climb_ompl.model.collision.CollisionChecker`)
        self.collision_checker = CollisionChecker(self, spec.get("ignore_collision_pairs"), src)

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
                    self._visual_model = pin.buildGeomFromUrdfString(self.model, self.urdf_text, pin.VISUAL,
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
        for a sphere of radius ``r`` (:mod:`climb_ompl.model.contact`); the target to give :meth:`limb_ik`.

        Args:
            limb: the limb.
            hold: a :class:`climb_ompl.model.terrain.Hold` (its ``position`` and ``normal``), or a position
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
        hand frame for a point contact, the hand frame minus ``r n`` for a sphere (:mod:`climb_ompl.model.contact`)."""
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
            sols = ik_numeric(self, lb, q, target, tol)
        elif isinstance(chain, AbductionChain):
            sols = ik_abduction(self, lb, chain, q, target)
        else:
            sols = ik_analytic(self, lb, chain, q, target)
        idx = list(lb.joint_indices)
        q_l = [float(q[i]) for i in idx]
        sols.sort(key=lambda s: math.fsum((float(s[i]) - x) ** 2 for i, x in zip(idx, q_l, strict=True)))
        return sols

    def limb_ik_nearest(self, limb: str | int | Limb, q: np.ndarray, target: Sequence[float],
                        ref: np.ndarray, *, same_bend: bool = False, prefer_bend: bool = False) -> np.ndarray | None:
        """The solution of :meth:`limb_ik` whose limb joints are nearest ``ref`` (least squares), or ``None``.

        For closed-form limbs only that solution's hand position is checked (the others are not needed),
        which makes this the cheap call for following a path by inverse kinematics.  ``same_bend``: only
        solutions whose elbow bends the way ``ref``'s does (the sign of the elbow joint less its straight value;
        a limb without an ``elbow`` has no bend to keep).  ``prefer_bend``: those first, the nearest of the other
        bend when none bends that way (a limb solved numerically has one solution: it is that one).
        """
        lb = self.limbs[self._limb_index(limb)]
        chain = self._chains.get(lb.name)
        ref = np.asarray(ref, dtype=float)
        bend = None
        if (same_bend or prefer_bend) and lb.elbow_index is not None:
            st = lb.elbow_straight or 0.0
            e = ref.item(lb.elbow_index) - st
            bend = (lb.elbow_index, st, float((e > 0.0) - (e < 0.0)) if e == e else math.nan)  # np.sign on a float
        if chain is not None:  # the closed forms check only the nearest candidates
            solve = ik_abduction if isinstance(chain, AbductionChain) else ik_analytic
            found = solve(self, lb, chain, q, target, ref=ref, bend=bend,  # (they take sequences as arrays)
                          prefer=prefer_bend and not same_bend)
            if found is not None:  # (None: an abduction leg's duplicate candidates, the full list decides)
                return found[0] if found else None
        sols = self.limb_ik(lb, q, target)
        if bend is not None:
            same = [x for x in sols if np.sign(x[bend[0]] - bend[1]) == bend[2]]
            sols = same if same or same_bend else sols
        if not sols:
            return None
        idx = list(lb.joint_indices)
        return min(sols, key=lambda x: float(np.sum((x[idx] - ref[idx]) ** 2)))

    def all_revolute(self, limb: str | int | Limb) -> bool:
        """Whether every joint of ``limb`` is revolute: then no hand lies farther from the limb's first joint than
        :attr:`Limb.reach` (a prismatic joint stretches the limb past the sum of its link offsets)."""
        lb = self.limbs[self._limb_index(limb)]
        out = self._all_revolute.get(lb.name)
        if out is None:
            out = self._all_revolute[lb.name] = all(revolute_axis(self.model, j, self._pin) is not None
                                                    for j in lb.joint_ids)
        return out

    # ------------------------------------------------------------------------------------- collision
    def self_collision(self, q: np.ndarray) -> bool:
        """True if two of the robot's links collide (:meth:`CollisionChecker.self_collision
        <climb_ompl.model.collision.CollisionChecker.self_collision>`)."""
        return self.collision_checker.self_collision(q)

    def in_collision(self, q: np.ndarray, terrain: Any = None,
                     contact_limbs: Iterable[str | int | Limb] = (), clearance: float = 0.0) -> bool:
        """True if the robot at ``q`` hits the terrain's surfaces or (if enabled) itself; contact limbs' contact
        geometry may touch the terrain near their holds (:meth:`CollisionChecker.in_collision
        <climb_ompl.model.collision.CollisionChecker.in_collision>`, which documents the arguments)."""
        return self.collision_checker.in_collision(q, terrain, contact_limbs, clearance)

    def collisions(self, q: np.ndarray, terrain: Any = None, contact_limbs: Iterable[str | int | Limb] = (),
                   clearance: float = 0.0) -> list[tuple[str, str]]:
        """The colliding pairs behind :meth:`in_collision`, by name (:meth:`CollisionChecker.collisions
        <climb_ompl.model.collision.CollisionChecker.collisions>`)."""
        return self.collision_checker.collisions(q, terrain, contact_limbs, clearance)

    def collision_pairs(self) -> list[tuple[str, str]]:
        """Names of the robot geometry pairs tested for self-collision (empty when disabled)."""
        return self.collision_checker.collision_pairs()

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
        if not isinstance(name, str) or not self.model.existJointName(name):
            own = [n for n in self.joint_names if n.startswith("base_") and not self.model.existJointName(n)]
            what = f"the URDF {self.urdf_path.name}'s joints" + (" and the base's coordinates" if own else "")
            raise RobotModelError(src, fld, f"{name!r} is none of {what}{_did_you_mean(name, self.joint_names)}")
        return self._joint_q(name, src, fld)

    def _joint_id(self, name: Any, src: str, fld: str) -> int:
        m = self.model
        if not isinstance(name, str) or not m.existJointName(name):
            joints = [str(m.names[j]) for j in range(1, m.njoints) if m.joints[j].nq == 1]  # not a built base
            raise RobotModelError(src, fld, f"joint {name!r} not in the URDF {self.urdf_path.name}"
                                  f"{_did_you_mean(name, joints)}")
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
                hint = _did_you_mean(hf, [fr.name for fr in m.frames if fr.name != "universe"],
                                     [fr.name for fr in m.frames if fr.type == pin.FrameType.BODY], "links")
                raise RobotModelError(src, f"{f}.hand_frame", f"unknown frame {hf!r} (not a link or joint of "
                                      f"{self.urdf_path.name}){hint}")
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
                lo_e, hi_e = float(self.lower[e_idx]), float(self.upper[e_idx])
                near_bound = min((lo_e, hi_e), key=lambda b: abs(e_str - b))
                if abs(e_str - near_bound) <= BOUND_ROUNDING:
                    e_str = near_bound  # a bound written rounded (-0.916 for -0.91629...), either way
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

