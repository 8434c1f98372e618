"""What each configuration coordinate is, read from Pinocchio's joint model types: an angle, a translation or a
screw (an angle that also translates).

The kind of a coordinate decides how far a draw moves it (radians or metres, :mod:`climb_ompl.manifold.closure`),
whether a whole turn of it is the same posture (:func:`climb_ompl.climb.multistep.whole_turn_variants`) and whether
a limb's reach bounds its hand (:meth:`climb_ompl.model.robot.RobotModel.all_revolute`).  It is read from the
joint model's type (``model.joints[j].shortname()``), never from a joint's name, and a composite joint (the
``planar`` and ``spatial`` bases of :mod:`climb_ompl.model.spec`) is read joint by joint, each of its joints at its
own place in ``q`` (its ``idx_q``, which Pinocchio sets when the composite joins the model).  A type not in the
tables (a joint model added to Pinocchio later) is read from its motion subspace: the joint's own Jacobian column
in its frame at the neutral configuration, an angle when only its angular part is non-zero, a translation when
only its linear part is, a screw when both are.
"""

from __future__ import annotations

from typing import Any

import numpy as np

#: Kinds of a coordinate.
ANGLE, TRANSLATION, SCREW = "angle", "translation", "screw"

#: Pinocchio joint model types (``shortname()``) whose every coordinate is an angle (a rotation about an axis fixed
#: in the joint's frame, or Z-Y-X angles, or a universal joint's two angles).
ANGLE_TYPES = frozenset({"JointModelRX", "JointModelRY", "JointModelRZ", "JointModelRevoluteUnaligned",
                         "JointModelSphericalZYX", "JointModelUniversal"})

#: Joint model types whose every coordinate is a translation.
TRANSLATION_TYPES = frozenset({"JointModelPX", "JointModelPY", "JointModelPZ", "JointModelPrismaticUnaligned",
                               "JointModelTranslation"})

#: Joint model types whose coordinates turn and translate at once (a helical joint, an ellipsoid joint).
SCREW_TYPES = frozenset({"JointModelHX", "JointModelHY", "JointModelHZ", "JointModelHelicalUnaligned",
                         "JointModelEllipsoid"})


def coordinate_kinds(model: Any) -> tuple[str, ...]:
    """The kind of each of ``model``'s configuration coordinates (:data:`ANGLE`, :data:`TRANSLATION` or
    :data:`SCREW`), in ``q`` order (see the module docstring).

    Raises:
        ValueError: a joint whose coordinates are not its velocities (a free-flyer, a spherical joint: a robot
            model refuses them, its configurations being plain vectors) and whose type is in no table.
    """
    out: list[str | None] = [None] * int(model.nq)
    for jid in range(1, model.njoints):
        jm = model.joints[jid]
        if jm.nq == 0:
            continue
        if not _by_type(jm, int(jm.idx_q), out):
            if jm.nq != jm.nv:
                raise ValueError(f"joint {model.names[jid]!r} ({jm.shortname()}) has {jm.nq} coordinates for "
                                 f"{jm.nv} velocities")
            for k, kind in enumerate(_by_motion(model, jid)):
                out[int(jm.idx_q) + k] = kind
    missing = [i for i, k in enumerate(out) if k is None]
    if missing:  # (no joint covers them: not a Pinocchio model)
        raise ValueError(f"coordinates {missing} belong to no joint of the model")
    return tuple(k for k in out if k is not None)


def elementary(jm: Any) -> tuple[str, np.ndarray] | None:
    """``("R" | "P", unit axis in the joint's frame)`` of a one-coordinate revolute or prismatic joint model (the
    ``R`` and ``P`` types of :data:`ANGLE_TYPES` and :data:`TRANSLATION_TYPES` with an axis), or ``None`` for any
    other joint (a composite, a helical, a spherical joint)."""
    name = jm.shortname()
    for kind, stem in (("R", "JointModelR"), ("P", "JointModelP")):
        for i, ax in enumerate("XYZ"):
            if name == f"{stem}{ax}":
                return kind, np.eye(3)[i]
    if name in ("JointModelRevoluteUnaligned", "JointModelPrismaticUnaligned"):
        axis = np.asarray((jm.extract() if hasattr(jm, "extract") else jm).axis, dtype=float)
        return ("R" if "Revolute" in name else "P"), axis / np.linalg.norm(axis)
    return None


def _by_type(jm: Any, start: int, out: list[str | None]) -> bool:
    """Write the kinds of joint model ``jm``'s coordinates (the first at ``start``) into ``out`` from its type;
    ``False`` (nothing decided for it) when a type, or a type inside a composite, is in no table."""
    name = jm.shortname()
    if name == "JointModelComposite":
        parts = jm.extract().joints
        kinds: list[str | None] = list(out)
        for sub in parts:  # (in a model, a composite's joints carry their own place in q)
            if not _by_type(sub, int(sub.idx_q), kinds):
                return False
        out[:] = kinds
        return True
    for table, kind in ((ANGLE_TYPES, ANGLE), (TRANSLATION_TYPES, TRANSLATION), (SCREW_TYPES, SCREW)):
        if name in table:
            for k in range(int(jm.nq)):
                out[start + k] = kind
            return True
    return False


def _by_motion(model: Any, jid: int) -> list[str]:
    """The kinds of joint ``jid``'s coordinates from its motion subspace (its Jacobian in its own frame at the
    neutral configuration), one per velocity coordinate."""
    import pinocchio as pin

    jm = model.joints[jid]
    J = np.asarray(pin.computeJointJacobian(model, model.createData(), pin.neutral(model), jid))
    out = []
    for v in range(int(jm.idx_v), int(jm.idx_v) + int(jm.nv)):
        lin, ang = np.linalg.norm(J[:3, v]) > 1e-12, np.linalg.norm(J[3:, v]) > 1e-12
        out.append(SCREW if lin and ang else ANGLE if ang else TRANSLATION)
    return out


__all__ = ["ANGLE", "TRANSLATION", "SCREW", "ANGLE_TYPES", "TRANSLATION_TYPES", "SCREW_TYPES", "coordinate_kinds",
           "elementary"]
