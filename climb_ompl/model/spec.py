"""The robot spec's shape and sections, checked before the URDF is read (:class:`climb_ompl.model.robot.RobotModel`;
the spec's fields are documented in :mod:`climb_ompl.model.robot` and docs/robots.md): required fields and their types,
the built base (``base: {type: planar | spatial, ...}``), the ``climb`` section, and the URDF's masses."""

from __future__ import annotations

import math
import reprlib
import xml.etree.ElementTree as ET
from pathlib import Path
from typing import Any

import numpy as np

from climb_ompl._io import number_hint
from climb_ompl.errors import RobotModelError

__all__ = ["check_spec_shape", "check_urdf_masses", "composite_base", "climb_section"]

_SPEC_FIELDS = {
    "name", "description", "urdf", "planar", "base", "limbs", "mass", "torque_limits", "velocity_limits",
    "acceleration_limits",
    "self_collision", "ignore_collision_pairs", "massless_links", "package_dirs", "nominal", "references",
    "base_joints", "nominal_q", "gait", "equilibrium", "urdf_package", "srdf",
    "joint_limits", "climb", "collision_meshes",
}
_LIMB_FIELDS = {"name", "hand_frame", "joints", "elbow", "elbow_straight", "ik", "contact"}
_IK_KINDS = ("auto", "analytic", "numeric")


def check_urdf_masses(path: Path, massless: set[str], src: str) -> None:
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


def _check_radians(val: Any, src: str, fld: str) -> None:
    """Refuse an angle (or a list of angles) of more than a whole turn: degrees written where radians go.

    Raises:
        RobotModelError: naming ``fld``, the value and its value in radians.
    """
    vals = val if isinstance(val, list) else [val]
    if all(abs(float(x)) <= 2.0 * math.pi for x in vals):
        return
    rad = [f"{math.radians(float(x)):.4g}" for x in vals]
    shown, conv = (f"{val:g}", rad[0]) if not isinstance(val, list) else (repr(val), "[" + ", ".join(rad) + "]")
    raise RobotModelError(src, fld, f"angles are in radians, got {shown} (more than a whole turn: degrees? {shown} deg "
                          f"is {conv} rad)")


def composite_base(base: dict[str, Any], src: str) -> Any:
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
        _check_radians(ref, src, "base.reference_rpy")
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
        if not isinstance(val, list) or len(val) != n or not all(
                isinstance(x, (int, float)) and not isinstance(x, bool) and math.isfinite(x) for x in val):
            raise RobotModelError(src, f"base.{key}", f"expected a list of {n} finite numbers (bounds of the {kind} "
                                  f"base), got {val!r}")
    angles = range(2, 3) if kind == "planar" else range(3, 6)  # base_theta; base_rz, base_ry, base_rx
    for key in ("lower", "upper"):
        for i in angles:
            _check_radians(base[key][i], src, f"base.{key}[{i}]")
    for i, (lo, hi) in enumerate(zip(base["lower"], base["upper"], strict=True)):
        if lo >= hi:
            raise RobotModelError(src, f"base.upper[{i}]", f"{hi:g} is not above base.lower[{i}] = {lo:g} (each "
                                  f"coordinate of the {kind} base needs lower < upper)")
    return root


def climb_section(val: Any, src: str) -> dict[str, Any]:
    """The spec's ``climb`` section, checked as settings of a climb (:class:`~climb_ompl.settings.ClimbSettings`):
    a mapping of setting names to values, except :data:`~climb_ompl.settings.NOT_GIVEN`.  A bad value is reported
    under ``climb.<name>``; settings that do not go together (a custom sampler on a space that never calls it) under
    the setting :class:`ClimbSettings` names."""
    from climb_ompl.errors import PlannerNotFound, QueryError
    from climb_ompl.settings import NOT_GIVEN, ClimbSettings, setting_error, unknown_setting

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


def _integers(value: Any, where: str) -> Any:
    """``(field path, value)`` of every integer in a spec (``limbs[0].contact.offset[2]``), booleans excepted."""
    if isinstance(value, dict):
        for k, v in value.items():
            yield from _integers(v, f"{where}.{k}" if where else str(k))
    elif isinstance(value, list):
        for i, v in enumerate(value):
            yield from _integers(v, f"{where}[{i}]")
    elif isinstance(value, int) and not isinstance(value, bool):
        yield where, value


def check_spec_shape(spec: Any, src: str) -> None:
    """Types and required fields of a spec (names are checked against the URDF later)."""
    if not isinstance(spec, dict):
        raise RobotModelError(src, "(top level)", "expected a mapping with name, urdf, base, limbs")
    extra = sorted(set(spec) - _SPEC_FIELDS)
    if extra:
        raise RobotModelError(src, extra[0], f"unknown field; known fields: {', '.join(sorted(_SPEC_FIELDS))}")
    for where, x in _integers(spec, ""):
        if abs(x) > 2 ** 53:  # YAML reads 1e20 written without a dot as an integer; no float holds 10**400
            raise RobotModelError(src, where, f"{reprlib.repr(x)} is too large an integer for a length, an angle, "
                                  "a mass or a limit")
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
        _check_limb(lb, i, src)
    _check_optional_fields(spec, src)


def _check_limb(lb: Any, i: int, src: str) -> None:
    """Types and required fields of the spec's ``limbs[i]``."""
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
    for key in ("hand_frame", "elbow"):
        val = lb.get(key, "")
        if key == "elbow" and val is None:
            continue  # written empty: no elbow
        if not isinstance(val, str) or (key == "hand_frame" and not val):
            raise RobotModelError(src, f"{f}.{key}", f"expected the name of a "
                                  f"{'frame' if key == 'hand_frame' else 'joint'} of the URDF, got {val!r}")
    if not isinstance(lb["joints"], list) or not all(isinstance(x, str) for x in lb["joints"]):
        raise RobotModelError(src, f"{f}.joints", "expected a list of joint names")
    if lb.get("ik", "auto") not in _IK_KINDS:
        raise RobotModelError(src, f"{f}.ik", f"must be one of {', '.join(_IK_KINDS)}, got {lb['ik']!r}")
    es = lb.get("elbow_straight", 0.0)
    if isinstance(es, bool) or not isinstance(es, (int, float)):
        raise RobotModelError(src, f"{f}.elbow_straight", f"expected a number, got {es!r}{number_hint(es)}")


def _check_optional_fields(spec: dict[str, Any], src: str) -> None:
    """Types of the spec's optional top-level fields (mass, limits, flags, lists, description, references, gait)."""
    if "mass" in spec:
        m = spec["mass"]
        if isinstance(m, bool) or not isinstance(m, (int, float)) or not m > 0:
            raise RobotModelError(src, "mass", f"expected a positive number of kg, got {m!r}")
    for key in ("torque_limits", "velocity_limits", "acceleration_limits"):
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
    if spec.get("collision_meshes", "convex") not in ("convex", "exact"):
        raise RobotModelError(src, "collision_meshes", "expected convex (each collision mesh checked as its convex "
                              f"hull, the default) or exact (triangle by triangle), got {spec['collision_meshes']!r}")
    for key in ("massless_links", "package_dirs", "ignore_collision_pairs"):
        if key in spec and spec[key] is not None and not isinstance(spec[key], list):
            raise RobotModelError(src, key, "expected a list")
    if spec.get("description") is not None and not isinstance(spec["description"], str):
        raise RobotModelError(src, "description", f"expected a line of text, got {spec['description']!r}")
    refs = spec.get("references")
    if refs is not None and not isinstance(refs, str) and not (
            isinstance(refs, list) and all(isinstance(r, str) for r in refs)):
        raise RobotModelError(src, "references", f"expected a list of citations (text), got {reprlib.repr(refs)}")
    if spec.get("gait") is not None and not isinstance(spec["gait"], dict):  # read by the slope gait
        raise RobotModelError(src, "gait", f"expected a mapping of gait parameters, got {reprlib.repr(spec['gait'])}")
