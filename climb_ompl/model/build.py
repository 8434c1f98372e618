"""Building a :class:`~climb_ompl.model.robot.RobotModel` from its spec (the YAML of :mod:`climb_ompl.model.robot`'s
docstring): the URDF read by Pinocchio (with a base built from the spec's ``base.type``), joint limits narrowed,
masses checked, limits of torques and velocities, the limbs (their joints, hand frames, elbows, reaches and
contact geometry), their inverse-kinematics kind (:mod:`climb_ompl.model.limb_ik`), the nominal posture and the
collision geometry (:mod:`climb_ompl.model.collision`).  Each error names the spec or URDF file, the field and the
reason (:class:`~climb_ompl.errors.RobotModelError`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from pathlib import Path
from typing import Any

import numpy as np

from climb_ompl._io import captured_stderr, number_hint
from climb_ompl.errors import RobotModelError
from climb_ompl.model.collision import CollisionChecker
from climb_ompl.model.contact import POINT, ContactGeometry, parse_contact
from climb_ompl.model.files import package_share, resolve_robot_file
from climb_ompl.model.joints import coordinate_kinds
from climb_ompl.model.limb_ik import analytic_chain
from climb_ompl.model.spec import check_spec_shape, check_urdf_masses, climb_section, composite_base

__all__ = ["Limb", "build", "BOUND_ROUNDING", "RAMP_TIME"]

_MASS_RTOL = 0.01

#: Default acceleration limit of a joint whose spec gives none (``acceleration_limits``; a URDF has no field for
#: it): the joint reaches its speed limit from rest in this many seconds, so ``a_max = v_max / RAMP_TIME``.
RAMP_TIME = 0.25


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
        contact: the contact geometry (:class:`climb_ompl.model.contact.ContactGeometry`; a point by default).  For a
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
    contact: ContactGeometry = POINT


def _did_you_mean(name: Any, valid: Any, shown: Any = None, label: str = "valid") -> str:
    """``"; did you mean 'X'? (valid: a, b, ...)"`` for an unknown name among ``valid``; the list is ``shown`` (default
    ``valid``) cut at 40, under ``label``."""
    from climb_ompl.errors import nearest_name

    valid = [str(v) for v in valid if str(v)]
    listed = valid if shown is None else [str(v) for v in shown if str(v)]
    near = nearest_name(name, valid)
    text = ", ".join(listed[:40]) + (f", ... ({len(listed)} in all)" if len(listed) > 40 else "")
    return (f"; did you mean {near!r}?" if near else "") + f" ({label}: {text})"


def build(robot: Any, spec: dict[str, Any], spec_path: Path | str, base_dir: Path | None = None) -> None:
    """Set every attribute of ``robot`` (a :class:`~climb_ompl.model.robot.RobotModel` under construction) from
    ``spec`` (read from ``spec_path``; relative files from ``base_dir``, default the spec's folder).

    Raises:
        RobotModelError: a spec or URDF problem (names the file, the field and the reason).
    """
    import pinocchio as pin

    robot._pin = pin
    robot.spec = spec
    robot.spec_path = spec_path
    src = str(spec_path)
    if isinstance(spec, dict) and "base_joints" in spec and "base" not in spec:
        spec = {**{k: v for k, v in spec.items() if k != "base_joints"}, "base": {"joints": spec["base_joints"]}}
    check_spec_shape(spec, src)
    robot.name = spec["name"]
    robot.planar = bool(spec.get("planar", False))
    #: whether feasibility includes static equilibrium and torque limits (spec ``equilibrium``, default
    #: true); false for robots that grab and release pegs (Bretl (2006), sec. 2.1)
    robot.equilibrium = bool(spec.get("equilibrium", True))
    base_dir = base_dir if base_dir is not None else (Path(spec_path).parent if Path(spec_path).exists()
                                                      else Path("."))
    share = package_share(spec["urdf_package"], src) if "urdf_package" in spec else None
    _read_urdf(robot, spec, src, base_dir, share)
    _limits(robot, spec, src)
    _limbs(robot, spec, src)
    _geometry(robot, spec, src, base_dir, share)


def _read_urdf(robot: Any, spec: dict[str, Any], src: str, base_dir: Path, share: Path | None) -> None:
    """The URDF (and SRDF) read by Pinocchio, with the spec's built base: ``urdf_path``, ``srdf_path``, ``model``,
    ``srdf_links``, ``nq``, ``coordinate_kinds`` and ``joint_names``."""
    pin = robot._pin
    robot.urdf_path = resolve_robot_file(spec["urdf"], base_dir, src, "urdf", share)
    #: the SRDF whose ``disable_collisions`` pairs are skipped (spec ``srdf``), or ``None``
    robot.srdf_path = (resolve_robot_file(spec["srdf"], base_dir, src, "srdf", share)
                       if spec.get("srdf") is not None else None)
    check_urdf_masses(robot.urdf_path, set(spec.get("massless_links", []) or []), src)
    base = spec["base"]
    root = composite_base(base, src) if "type" in base else None
    parser_said: list[str] = []
    try:
        with captured_stderr(parser_said):  # urdfdom prints its errors straight to the terminal
            model = (pin.buildModelFromUrdf(str(robot.urdf_path), root) if root is not None
                     else pin.buildModelFromUrdf(str(robot.urdf_path)))
    except (RuntimeError, ValueError) as exc:
        said = next((ln.strip()[len("Error:"):].strip() for ln in parser_said if ln.strip().startswith("Error:")),
                    "")
        raise RobotModelError(robot.urdf_path, "urdf", f"not a valid URDF: {said}" if said else
                              f"Pinocchio cannot parse it ({exc})") from None
    robot.model = model
    #: what the SRDF's pairs name against the URDF (:class:`~climb_ompl.model.collision.SrdfLinks`), or ``None``
    robot.srdf_links = None
    if robot.srdf_path is not None:
        from climb_ompl.model.collision import check_srdf

        robot.srdf_links = check_srdf(robot.srdf_path, model, src)
    if model.nq != model.nv:
        bad = [model.names[j] for j in range(1, model.njoints) if model.joints[j].nq != model.joints[j].nv]
        raise RobotModelError(robot.urdf_path, f"joints.{bad[0] if bad else '?'}",
                              "continuous or spherical joint: configurations must be plain vectors "
                              "(use bounded revolute joints, e.g. +-2 pi)")
    robot.nq = int(model.nq)
    robot.coordinate_kinds = coordinate_kinds(model)
    robot.joint_names = _coordinate_names(robot, base.get("type"))


def _limits(robot: Any, spec: dict[str, Any], src: str) -> None:
    """The base coordinates, the joint bounds (the base's and the spec's narrower ones), the mass and the limits of
    torques and velocities: ``base_indices``, ``climb``, ``lower``, ``upper``, ``data``, ``mass``,
    ``torque_limits``, ``velocity_limits``, ``acceleration_limits`` and ``actuated``."""
    model, base = robot.model, spec["base"]
    if "type" in base:
        k = len(base["lower"])
        model.lowerPositionLimit[:k] = np.asarray(base["lower"], float)
        model.upperPositionLimit[:k] = np.asarray(base["upper"], float)
        robot.base_indices = tuple(range(k))
    else:
        robot.base_indices = tuple(_joint_q(robot, n, src, "base.joints") for n in base["joints"])
    _narrow_limits(robot, spec.get("joint_limits") or {}, src)
    #: the spec's ``climb`` section: this robot's defaults for :class:`~climb_ompl.settings.ClimbSettings`
    robot.climb = climb_section(spec.get("climb"), src)
    robot.lower = np.array(model.lowerPositionLimit, dtype=float)
    robot.upper = np.array(model.upperPositionLimit, dtype=float)
    for i in range(robot.nq):
        if not (np.isfinite(robot.lower[i]) and np.isfinite(robot.upper[i]) and robot.lower[i] < robot.upper[i]):
            raise RobotModelError(robot.urdf_path, f"joints.{robot.joint_names[i]}.limit",
                                  f"needs finite lower < upper bounds, got [{robot.lower[i]}, {robot.upper[i]}]")
    robot.data = model.createData()

    robot.mass = float(sum(model.inertias[j].mass for j in range(model.njoints)))
    if robot.mass <= 0:
        raise RobotModelError(robot.urdf_path, "links.inertial", "missing mass: the robot's total mass is 0")
    if "mass" in spec:
        want = spec["mass"]
        if abs(robot.mass - want) > _MASS_RTOL * want:
            raise RobotModelError(src, "mass", f"spec says {want} kg but the URDF's links weigh {robot.mass:.4g} kg")

    # limits: URDF effort (0 = not given) and velocity, spec overrides, base joints unactuated
    robot.torque_limits = np.array(model.effortLimit, dtype=float)
    robot.torque_limits[robot.torque_limits <= 0] = np.inf
    robot.velocity_limits = np.array(model.velocityLimit, dtype=float)
    robot.acceleration_limits = np.full(robot.nq, np.nan)
    for key, arr in (("torque_limits", robot.torque_limits), ("velocity_limits", robot.velocity_limits),
                     ("acceleration_limits", robot.acceleration_limits)):
        for jn, val in (spec.get(key) or {}).items():
            arr[_joint_q(robot, jn, src, f"{key}.{jn}")] = float(val)
    unset = np.isnan(robot.acceleration_limits)  # a URDF has none: the speed limit reached in RAMP_TIME seconds
    with np.errstate(over="ignore"):  # a URDF's "no limit" (1.8e308) stays none
        robot.acceleration_limits[unset] = robot.velocity_limits[unset] / RAMP_TIME
    robot.actuated = np.ones(robot.nq, dtype=bool)
    robot.actuated[list(robot.base_indices)] = False
    robot.torque_limits[~robot.actuated] = np.inf


def _limbs(robot: Any, spec: dict[str, Any], src: str) -> None:
    """The limbs, their inverse kinematics (closed form where :func:`~climb_ompl.model.limb_ik.analytic_chain` finds
    one and the spec allows it) and the nominal posture: ``limbs``, ``nominal_q``."""
    model = robot.model
    robot.limbs = _build_limbs(robot, spec["limbs"], src)
    robot.data = model.createData()  # again: a sphere contact with an offset adds a frame
    robot._limb_by_name = {lb.name: i for i, lb in enumerate(robot.limbs)}
    robot._hand_fids = [lb.frame_id for lb in robot.limbs]
    robot._chains = {lb.name: analytic_chain(model, robot._pin, lb) for lb in robot.limbs}
    kinds = []
    for i, (lb, raw) in enumerate(zip(robot.limbs, spec["limbs"], strict=True)):
        want = raw.get("ik", "auto")
        chain = robot._chains[lb.name]
        if want == "analytic" and chain is None:
            raise RobotModelError(src, f"limbs[{i}].ik", "no closed-form IK for this limb (analytic IK needs "
                                  "two revolute joints with parallel axes, optionally followed by one "
                                  "revolute joint whose axis is not parallel to them)")
        kind = "analytic" if (chain is not None and want != "numeric") else "numeric"
        if kind == "numeric":
            robot._chains[lb.name] = None
        kinds.append(kind)
    robot.limbs = tuple(replace(lb, ik=k) for lb, k in zip(robot.limbs, kinds, strict=True))

    robot.nominal_q = _nominal(robot, spec.get("nominal") or {}, src)
    if "nominal_q" in spec:
        nq_raw = spec["nominal_q"]
        if (not isinstance(nq_raw, list) or len(nq_raw) != robot.nq
                or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in nq_raw)):
            raise RobotModelError(src, "nominal_q", f"expected a list of {robot.nq} numbers")
        robot.nominal_q = np.asarray(nq_raw, dtype=float)
        bad = np.flatnonzero((robot.nominal_q < robot.lower - 1e-9) | (robot.nominal_q > robot.upper + 1e-9))
        if bad.size:
            raise RobotModelError(src, f"nominal_q[{bad[0]}]", f"outside the bounds of joint "
                                  f"{robot.joint_names[bad[0]]!r}")
    robot.limbs = tuple(_locked_reach(robot, lb) for lb in robot.limbs)  # (same order: the name index holds)


def _geometry(robot: Any, spec: dict[str, Any], src: str, base_dir: Path, share: Path | None) -> None:
    """The collision geometry and its checker (the visual geometry is read on first use): ``urdf_text``,
    ``collision_model``, ``self_collision_enabled``, ``collision_checker``."""
    pin = robot._pin
    pkg = [str((base_dir / p).resolve()) for p in (spec.get("package_dirs") or [])]
    pkg.append(str(robot.urdf_path.parent))
    if share is not None:
        pkg.append(str(share.parent))  # package://<name>/... resolves in <prefix>/share
    robot._package_dirs = pkg
    robot._visual_model = None
    #: the URDF's text as read (a plan embeds it; the visual geometry is built from it when the file is gone)
    robot.urdf_text = robot.urdf_path.read_text()
    try:
        robot.collision_model = pin.buildGeomFromUrdf(robot.model, str(robot.urdf_path), pin.COLLISION,
                                                      package_dirs=pkg)
    except (RuntimeError, ValueError, OSError) as exc:
        raise RobotModelError(robot.urdf_path, "geometry", f"cannot build collision geometry ({exc})") from None
    robot.self_collision_enabled = bool(spec.get("self_collision", True))
    #: the collision queries (:class:`~climb_ompl.model.collision.CollisionChecker`)
    robot.collision_checker = CollisionChecker(robot, spec.get("ignore_collision_pairs"), src,
                                               hulls=spec.get("collision_meshes", "convex") == "convex")


def _coordinate_names(robot: Any, base_type: str | None = None) -> tuple[str, ...]:
    """Name of each coordinate: its joint's, ``joint[k]`` inside a multi-coordinate joint, and for a base
    built here (``base.type``) ``base_x, base_z, base_theta`` (planar) or ``base_x, base_y, base_z,
    base_rz, base_ry, base_rx`` (spatial; angles about the reference orientation's axes)."""
    m = robot.model
    names = [""] * m.nq
    for j in range(1, m.njoints):
        for k in range(m.joints[j].nq):
            names[m.joints[j].idx_q + k] = m.names[j] if m.joints[j].nq == 1 else f"{m.names[j]}[{k}]"
    own = {"planar": ("base_x", "base_z", "base_theta"),
           "spatial": ("base_x", "base_y", "base_z", "base_rz", "base_ry", "base_rx")}.get(base_type or "")
    if own and not any(m.existJointName(n) for n in own):
        names[:len(own)] = own
    return tuple(names)

def _coordinate(robot: Any, name: Any, src: str, fld: str) -> int:
    """Index into ``q`` of a one-coordinate joint or of a named coordinate of :attr:`joint_names`."""
    if isinstance(name, str) and not robot.model.existJointName(name) and name in robot.joint_names:
        return robot.joint_names.index(name)
    if not isinstance(name, str) or not robot.model.existJointName(name):
        own = [n for n in robot.joint_names if n.startswith("base_") and not robot.model.existJointName(n)]
        what = f"the URDF {robot.urdf_path.name}'s joints" + (" and the base's coordinates" if own else "")
        raise RobotModelError(src, fld, f"{name!r} is none of {what}{_did_you_mean(name, robot.joint_names)}")
    return _joint_q(robot, name, src, fld)

def _joint_id(robot: Any, name: Any, src: str, fld: str) -> int:
    m = robot.model
    if not isinstance(name, str) or not m.existJointName(name):
        joints = [str(m.names[j]) for j in range(1, m.njoints) if m.joints[j].nq == 1]  # not a built base
        raise RobotModelError(src, fld, f"joint {name!r} not in the URDF {robot.urdf_path.name}"
                              f"{_did_you_mean(name, joints)}")
    return int(m.getJointId(name))

def _joint_q(robot: Any, name: Any, src: str, fld: str) -> int:
    jid = _joint_id(robot, name, src, fld)
    if robot.model.joints[jid].nq != 1:
        raise RobotModelError(src, fld, f"joint {name!r} has {robot.model.joints[jid].nq} coordinates, expected 1")
    return int(robot.model.joints[jid].idx_q)

def _build_limbs(robot: Any, raw: list[dict[str, Any]], src: str) -> tuple[Limb, ...]:
    m, pin = robot.model, robot._pin
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
                                  f"{robot.urdf_path.name}){hint}")
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
            jid = _joint_id(robot, jn, src, f"{f}.joints[{k}]")
            if jn in owner:
                raise RobotModelError(src, f"{f}.joints[{k}]",
                                      f"limb {name!r} shares joint {jn!r} with limb {owner[jn]!r}")
            owner[jn] = name
            jids.append(jid)
            qidx.append(_joint_q(robot, jn, src, f"{f}.joints[{k}]"))
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
            e_idx = _joint_q(robot, elbow, src, f"{f}.elbow")
            # straight = 0 unless given; a default outside the bounds becomes the nearest bound
            e_str = float(rl.get("elbow_straight", np.clip(0.0, robot.lower[e_idx], robot.upper[e_idx])))
            lo_e, hi_e = float(robot.lower[e_idx]), float(robot.upper[e_idx])
            near_bound = min((lo_e, hi_e), key=lambda b: abs(e_str - b))
            if abs(e_str - near_bound) <= BOUND_ROUNDING:
                e_str = near_bound  # a bound written rounded (-0.916 for -0.91629...), either way
            if not (robot.lower[e_idx] <= e_str <= robot.upper[e_idx]):
                raise RobotModelError(src, f"{f}.elbow_straight",
                                      f"{e_str} is outside the joint bounds [{float(robot.lower[e_idx])!r}, "
                                      f"{float(robot.upper[e_idx])!r}] (the URDF's, in radians or metres)")
        reach = _reach(robot, jids, fid)
        limbs.append(Limb(name, hf, tuple(qidx), e_idx, e_str, reach, fid, tuple(jids), contact=contact))
    return tuple(limbs)

def _locked_reach(robot: Any, lb: Limb) -> Limb:
    """``lb`` with its reach bounded again when a joint between its first joint and its hand is in no limb
    (locked at its nominal value): the sum, at the nominal configuration, of the distances between
    consecutive limb joints and from the last one to the hand.  Each limb joint turns what follows it about
    an axis through its own origin, so these distances do not change; :meth:`_reach` adds the locked
    joints' offsets one by one, as if they could straighten."""
    m = robot.model
    path = list(m.supports[m.frames[lb.frame_id].parentJoint])
    if not lb.joint_ids or set(path[path.index(lb.joint_ids[0]):]) <= set(lb.joint_ids):
        return lb
    pts = robot.limb_fk(robot.nominal_q, lb)
    return replace(lb, reach=float(np.linalg.norm(np.diff(pts, axis=0), axis=1).sum()))

def _reach(robot: Any, jids: list[int], fid: int) -> float:
    """Sum of the link offsets from the first limb joint to the hand (an upper bound on the reach)."""
    m = robot.model
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

def _narrow_limits(robot: Any, raw: Any, src: str) -> None:
    """Spec ``joint_limits: {joint: [lower, upper]}``: a narrower range than the URDF's (e.g. one turn of a
    joint the URDF bounds by +-3 turns, so that IK and sampling stay in the posture the robot uses)."""
    m = robot.model
    if not isinstance(raw, dict):
        raise RobotModelError(src, "joint_limits", "expected a mapping joint -> [lower, upper]")
    for jn, val in raw.items():
        i = _joint_q(robot, jn, src, f"joint_limits.{jn}")
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

def _nominal(robot: Any, raw: Any, src: str) -> np.ndarray:
    if not isinstance(raw, dict):
        raise RobotModelError(src, "nominal", "expected a mapping joint -> value")
    q = np.clip(np.zeros(robot.nq), robot.lower, robot.upper)
    for jn, val in raw.items():
        i = _coordinate(robot, jn, src, f"nominal.{jn}")
        if isinstance(val, bool) or not isinstance(val, (int, float)):
            raise RobotModelError(src, f"nominal.{jn}", f"expected a number, got {val!r}{number_hint(val)}")
        if not (robot.lower[i] - 1e-9 <= val <= robot.upper[i] + 1e-9):
            raise RobotModelError(src, f"nominal.{jn}", f"{val} outside the joint bounds "
                                  f"[{robot.lower[i]:.4g}, {robot.upper[i]:.4g}]")
        q[i] = float(val)
    return q

