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
    acceleration_limits: {ne_shoulder: 3.1}   # optional, rad/s^2 or m/s^2 (default: the speed limit over 0.25 s)
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
touch near its hold).  The spec's shape is checked by :mod:`climb_ompl.model.spec`, the model built from it by
:mod:`climb_ompl.model.build`; each coordinate's kind (angle or translation) is read from Pinocchio's joint types
(:mod:`climb_ompl.model.joints`).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from climb_ompl._io import load_yaml
from climb_ompl.errors import RobotModelError
from climb_ompl.model.build import Limb, build
from climb_ompl.model.joints import ANGLE, TRANSLATION
from climb_ompl.model.limb_ik import AbductionChain, ik_abduction, ik_analytic, ik_numeric
from climb_ompl.resources import bundled, resolve, robots_dir

__all__ = ["Limb", "RobotModel", "bundled_robots"]


def bundled_robots() -> list[str]:
    """Names of the robots shipped with the package (``robots/*.yaml``)."""
    return bundled(robots_dir())


class RobotModel:
    """A climbing robot: Pinocchio model + Coal collision geometry + limb description.

    Build with :meth:`load` (bundled name or spec path) or :meth:`from_spec` (a dict).  Attributes
    follow ``docs/dev/CONTRACTS.md``: ``name, nq, lower, upper, velocity_limits, acceleration_limits, torque_limits
    (inf where unactuated), actuated, base_indices, limbs, mass, planar, nominal_q, model, data, collision_model,
    visual_model, spec, spec_path, urdf_path``; also ``urdf_text``, ``equilibrium``, ``self_collision_enabled``,
    ``srdf_path`` and ``joint_names`` (the name of the joint of each configuration coordinate).

    Contacts (:mod:`climb_ompl.model.contact`): :meth:`hand_target` (where a hand frame goes to touch a hold),
    :meth:`contact_point`, :meth:`contact_jacobian`; :meth:`in_collision` exempts each contact limb's
    contact geometry near its hold and :meth:`collisions` names what collides.
    """

    name: str
    planar: bool
    equilibrium: bool
    nq: int
    #: the kind of each configuration coordinate (:func:`climb_ompl.model.joints.coordinate_kinds`)
    coordinate_kinds: tuple[str, ...]
    joint_names: tuple[str, ...]
    base_indices: tuple[int, ...]
    limbs: tuple[Limb, ...]
    mass: float
    climb: dict[str, Any]
    urdf_path: Path
    srdf_path: Path | None
    srdf_links: Any
    urdf_text: str
    self_collision_enabled: bool

    def __init__(self, spec: dict[str, Any], spec_path: Path | str, base_dir: Path | None = None):
        build(self, spec, spec_path, base_dir)  # every attribute, from the spec (climb_ompl/model/build.py)
        self._angles: np.ndarray | None = None  # (:attr:`angle_joints`, once computed)
        self._translations: tuple[list[int], np.ndarray] | None = None  # (:meth:`base_translations`)

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

    def com_jacobian(self, q: np.ndarray) -> np.ndarray:
        """``d com / d q`` at ``q``, ``(3, nq)``, metres per radian or metre: Pinocchio's ``jacobianCenterOfMass``
        (world frame).  Configurations are plain vectors with one velocity per coordinate (``nq == nv``, every
        joint's coordinates its own velocities), so its columns are the coordinates' in ``q`` order."""
        return np.array(self._pin.jacobianCenterOfMass(self.model, self.data, np.asarray(q, dtype=float), False))

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

    # ------------------------------------------------------------------------------------- joint kinds, the base
    @property
    def angle_joints(self) -> np.ndarray:
        """``(nq,)`` bool, read-only: which coordinates are angles (a revolute or screw joint's; the others are
        translations), from Pinocchio's joint model types (:func:`climb_ompl.model.joints.coordinate_kinds`)."""
        if self._angles is None:
            self._angles = np.array([k != TRANSLATION for k in self.coordinate_kinds], dtype=bool)
            self._angles.flags.writeable = False
        return self._angles

    def all_revolute(self, limb: str | int | Limb) -> bool:
        """Whether every joint of ``limb`` is revolute (a pure rotation, :data:`climb_ompl.model.joints.ANGLE`): then
        no hand lies farther from the limb's first joint than :attr:`Limb.reach` (a prismatic or screw joint
        stretches the limb past the sum of its link offsets)."""
        kinds = self.coordinate_kinds
        return all(kinds[i] == ANGLE for i in self.limbs[self._limb_index(limb)].joint_indices)

    def moves_base(self, limb: str | int | Limb) -> bool:
        """Whether ``limb``'s joints include a base coordinate: its inverse kinematics places the base (the double-link
        robot's hand ``a``, Bretl (2006), sec. 2.1), so it is closed before the limbs hanging from the base."""
        lb = self.limbs[self._limb_index(limb)]
        return not set(self.base_indices).isdisjoint(lb.joint_indices)

    def closing_order(self, limbs: Iterable[str], last: Iterable[str] = ()) -> list[str]:
        """``limbs`` in the order their chains are closed: the base-moving limbs first (:meth:`moves_base`: their
        inverse kinematics places the base the others hang from), then the others, those in ``last`` (hands already on
        their holds) after the rest, each group in the robot's limb order."""
        after = set(last)
        return sorted(limbs, key=lambda lb: (not self.moves_base(lb), lb in after, self._limb_index(lb)))

    def base_translations(self) -> tuple[list[int], np.ndarray]:
        """The base coordinates that are translations (:attr:`coordinate_kinds`: a prismatic joint, or one inside the
        spec's composite base), and the world vector each moves the body by per metre at the nominal configuration,
        ``(3, k)``: a spatial base's ``x, y, z``, a planar base's ``x, z``.  The vector is the linear part of the
        coordinate's column in the Jacobian of the joint it belongs to (a translation moves every point after it
        alike); computed once."""
        if self._translations is None:
            pin, m, d = self._pin, self.model, self.data
            pin.computeJointJacobians(m, d, np.asarray(self.nominal_q, dtype=float))
            lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
            owner = {v: jid for jid in range(1, m.njoints) for v in range(m.joints[jid].idx_v,
                                                                          m.joints[jid].idx_v + m.joints[jid].nv)}
            idx = [int(j) for j in self.base_indices if self.coordinate_kinds[j] == TRANSLATION]
            cols = [np.asarray(pin.getJointJacobian(m, d, owner[j], lwa))[:3, j] for j in idx]
            self._translations = (idx, np.array(cols, dtype=float).T.reshape(3, len(idx)))
        idx, dirs = self._translations
        return list(idx), dirs.copy()

    def base_axes(self) -> dict[int, int]:
        """The base translations (:meth:`base_translations`) along a world axis: ``{coordinate: axis}`` (0, 1, 2 for
        x, y, z), each moving the body by one metre along that axis per metre."""
        idx, dirs = self.base_translations()
        out = {}
        for j, v in zip(idx, dirs.T, strict=True):
            ax = int(np.argmax(np.abs(v)))
            if abs(abs(v[ax]) - 1.0) < 1e-9 and abs(np.linalg.norm(v) - 1.0) < 1e-9:
                out[j] = ax
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
