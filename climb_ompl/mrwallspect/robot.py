"""MRWALLSPECT III for the slope gait: spec, Pinocchio model, leg IK and Coal collision (Kim, Kang & Choi).

The robot is read from ``robots/mrwallspect3.yaml`` (its ``gait`` section carries the parameters of Kim, Kang & Choi)
and ``urdf/mrwallspect3.urdf``.  The configuration is a plain 15-vector
``[x, z, pitch, leg1 (yaw, pitch, knee), leg2, leg3, leg4]`` in the slope frame of
:mod:`climb_ompl.mrwallspect.geometry`; legs are numbered as in Kim, Kang & Choi, Eq. (2): 1 front-left,
2 front-right, 3 rear-left, 4 rear-right.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from climb_ompl._io import load_yaml
from climb_ompl.errors import RobotModelError
from climb_ompl.mrwallspect.geometry import EY, rot_y
from climb_ompl.resources import resolve, robots_dir, urdf_dir

LEGS: tuple[str, ...] = ("leg1", "leg2", "leg3", "leg4")
FRONT: tuple[str, ...] = ("leg1", "leg2")

_REQUIRED = ("X_f", "Y_f", "Y_r", "L1", "L2", "L3", "h_f", "h", "B_t", "body_box", "foot_lateral", "foot_forward",
             "stride", "d", "swing_height", "foot_radius", "clearance", "suction_force", "friction", "leg_order")


def _rot_z(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


@dataclass(frozen=True)
class Leg:
    """One leg: where its hip sits on the body and which configuration entries it owns.

    Attributes:
        name: ``leg1`` .. ``leg4``.
        hip: joint-1 position in the body frame :math:`\\Sigma_B`, metres (Kim, Kang & Choi, Eq. 2).
        hip_rot: rotation body -> hip frame (hip ``x`` points laterally outward at zero yaw).
        side: +1 left, -1 right (the leg frame's lateral axis is ``side * y``).
        front: +1 front leg, -1 rear leg (the leg frame's ``x`` is ``front * body x``, Eq. 2).
        q_index: first of its three entries in the configuration vector.
        lower, upper: joint limits, radians.
    """

    name: str
    hip: np.ndarray
    hip_rot: np.ndarray
    side: float
    front: float
    q_index: int
    lower: np.ndarray
    upper: np.ndarray


class SlopeRobot:
    """MRWALLSPECT III: the parameters of Kim, Kang & Choi, the Pinocchio model and the Coal collision model."""

    def __init__(self, spec: dict[str, Any], spec_path: Path, urdf_path: Path):
        import pinocchio as pin

        self.spec, self.spec_path, self.urdf_path = spec, spec_path, urdf_path
        self.name = str(spec.get("name", spec_path.stem))
        g = spec.get("gait")
        if not isinstance(g, dict):
            raise RobotModelError(spec_path, "gait", "missing section with the gait parameters of Kim, Kang & Choi")
        for key in _REQUIRED:
            if key not in g:
                raise RobotModelError(spec_path, f"gait.{key}", "missing")
        self.p: dict[str, Any] = dict(g)
        for key in _REQUIRED:
            if key not in ("body_box", "leg_order") and not (isinstance(g[key], (int, float)) and g[key] >= 0):
                raise RobotModelError(spec_path, f"gait.{key}", f"must be a non-negative number, got {g[key]!r}")
        if sorted(g["leg_order"]) != sorted(LEGS):
            raise RobotModelError(spec_path, "gait.leg_order", f"must list each of {LEGS} once")
        if g["h"] <= g["B_t"] - g["h_f"]:
            raise RobotModelError(spec_path, "gait.h", "body bottom would sit below the ankle plane")
        try:
            self.model = pin.buildModelFromUrdf(str(urdf_path))
            self.geom_model = pin.buildGeomFromUrdf(self.model, str(urdf_path), pin.COLLISION)
        except (ValueError, RuntimeError) as exc:
            raise RobotModelError(urdf_path, "urdf", f"cannot load ({exc})") from None
        self.data = self.model.createData()
        self.geom_data = pin.GeometryData(self.geom_model)
        self.nq = self.model.nq
        if self.nq != 15:
            raise RobotModelError(urdf_path, "joints", f"expected 15 (3 base + 4 x 3 leg) joints, got {self.nq}")
        self.lower = np.array(self.model.lowerPositionLimit)
        self.upper = np.array(self.model.upperPositionLimit)
        self.mass = float(sum(i.mass for i in self.model.inertias))
        self.ankle_frames = {}
        self.legs: dict[str, Leg] = {}
        X, Yf, Yr = g["X_f"], g["Y_f"], g["Y_r"]
        hips = {"leg1": (X, Yf / 2, 1.0, 1.0), "leg2": (X, -Yf / 2, -1.0, 1.0),
                "leg3": (0.0, Yr / 2, 1.0, -1.0), "leg4": (0.0, -Yr / 2, -1.0, -1.0)}
        for name, (x, y, side, front) in hips.items():
            fid = self.model.getFrameId(f"{name}_ankle")
            if fid >= self.model.nframes:
                raise RobotModelError(urdf_path, f"{name}_ankle", "frame not found")
            self.ankle_frames[name] = fid
            jid = self.model.getJointId(f"{name}_yaw")
            placement = self.model.jointPlacements[jid]
            hip = np.array([x, y, 0.0])
            if np.linalg.norm(placement.translation - hip) > 1e-9:
                raise RobotModelError(urdf_path, f"{name}_yaw", f"hip at {placement.translation}, spec says {hip}")
            iq = self.model.joints[jid].idx_q
            self.legs[name] = Leg(name, hip, np.array(placement.rotation), side, front, iq,
                                  self.lower[iq:iq + 3].copy(), self.upper[iq:iq + 3].copy())

    @classmethod
    def load(cls, name_or_path: str | Path = "mrwallspect3") -> SlopeRobot:
        """Load a robot spec (bundled name or YAML path) and its URDF.

        Raises:
            RobotModelError: the spec or URDF is missing or malformed (file, field, reason).
        """
        path = resolve(name_or_path, robots_dir(), "robot")
        spec = load_yaml(path, RobotModelError)
        if not isinstance(spec, dict) or "urdf" not in spec:
            raise RobotModelError(path, "urdf", "missing")
        urdf = Path(spec["urdf"])
        if not urdf.is_absolute():
            urdf = path.parent / urdf if (path.parent / urdf).is_file() else urdf_dir() / urdf
        if not urdf.is_file():
            raise RobotModelError(path, "urdf", f"file {str(urdf)!r} not found")
        return cls(spec, path, urdf)

    # -- kinematics --------------------------------------------------------------------------------
    def basic_upsilon(self) -> float:
        """:math:`\\Upsilon` of the basic form (Fig. 2-3): joint 2 -> ankle distance when standing flat."""
        g = self.p
        rho = math.hypot(g["foot_lateral"], g["foot_forward"]) - g["L1"]
        return math.hypot(rho, g["h"])

    def leg_frame(self, leg: str, origin: np.ndarray, pitch: float) -> tuple[np.ndarray, np.ndarray, np.ndarray,
                                                                              np.ndarray]:
        """Kim, Kang & Choi, Eq. (2) leg frame in the slope frame: ``(hip, x axis, lateral axis, z axis)``."""
        lg = self.legs[leg]
        rb = rot_y(pitch)
        return origin + rb @ lg.hip, lg.front * (rb[:, 0]), lg.side * EY, rb[:, 2]

    def leg_ik(self, leg: str, origin: np.ndarray, pitch: float, ankle: np.ndarray) -> list[np.ndarray]:
        """All joint triples ``(yaw, pitch, knee)`` of ``leg`` within limits that put its ankle at ``ankle``.

        Analytic IK of the yaw-pitch-pitch leg (Kim, Kang & Choi, Fig. 2): yaw from the ankle's bearing, then the
        planar two-link problem in the plane of joint 2 (distance :math:`\\Upsilon` of Eq. 1).

        Args:
            leg: ``leg1`` .. ``leg4``.
            origin: body origin :math:`O_B` in the slope frame, metres.
            pitch: body pitch, radians.
            ankle: target ankle position in the slope frame, metres.

        Returns:
            Solutions (knee up first); empty when the target is out of reach or of the joint limits.
        """
        g, lg = self.p, self.legs[leg]
        L1, L2, L3 = g["L1"], g["L2"], g["L3"]
        rb = rot_y(pitch)
        p = lg.hip_rot.T @ (rb.T @ (ankle - origin) - lg.hip)
        out = []
        for flip in (1.0, -1.0):
            q1 = math.atan2(flip * p[1], flip * p[0])
            rho = flip * math.hypot(p[0], p[1]) - L1
            z = p[2]
            D = (rho * rho + z * z - L2 * L2 - L3 * L3) / (2 * L2 * L3)
            if abs(D) > 1.0:
                continue
            for ks in (-1.0, 1.0):
                q3 = ks * math.acos(D)
                q2 = math.atan2(z, rho) - math.atan2(L3 * math.sin(q3), L2 + L3 * math.cos(q3))
                q2 = math.atan2(math.sin(q2), math.cos(q2))
                sol = np.array([q1, q2, q3])
                if np.all(sol >= lg.lower - 1e-12) and np.all(sol <= lg.upper + 1e-12):
                    out.append(sol)
        return out

    def configuration(self, origin: np.ndarray, pitch: float, legs: dict[str, np.ndarray]) -> np.ndarray:
        """Assemble the 15-vector from the body pose and the legs' joint triples."""
        q = np.zeros(self.nq)
        q[0], q[1], q[2] = origin[0], origin[2], pitch
        for name, j in legs.items():
            i = self.legs[name].q_index
            q[i:i + 3] = j
        return q

    def ankle_positions(self, q: np.ndarray) -> dict[str, np.ndarray]:
        """Ankle positions from Pinocchio forward kinematics, slope frame, metres."""
        import pinocchio as pin

        pin.framesForwardKinematics(self.model, self.data, q)
        return {n: np.array(self.data.oMf[f].translation) for n, f in self.ankle_frames.items()}

    def com(self, q: np.ndarray) -> np.ndarray:
        """Centre of mass (Pinocchio), slope frame, metres."""
        import pinocchio as pin

        return np.array(pin.centerOfMass(self.model, self.data, q))

    # -- collision ---------------------------------------------------------------------------------
    def distances(self, q: np.ndarray, obstacles: list[tuple[Any, Any]]) -> list[tuple[str, int, float]]:
        """Coal distance of every collision geometry to every obstacle: ``(geometry name, obstacle, metres)``.

        Negative or zero means contact/penetration.  ``obstacles`` are ``(coal geometry, coal.Transform3s)``.
        """
        import coal
        import pinocchio as pin

        pin.updateGeometryPlacements(self.model, self.data, self.geom_model, self.geom_data, q)
        out = []
        req = coal.DistanceRequest()
        for gi, obj in enumerate(self.geom_model.geometryObjects):
            m = self.geom_data.oMg[gi]
            tf = coal.Transform3s(m.rotation, m.translation)
            for k, (geom, otf) in enumerate(obstacles):
                res = coal.DistanceResult()
                dist = coal.distance(obj.geometry, tf, geom, otf, req, res)
                out.append((obj.name, k, float(dist)))
        return out


def leg_points(g: dict[str, Any], leg: Leg, origin: np.ndarray, pitch: float, joints: np.ndarray) -> list[np.ndarray]:
    """Points of a leg's kinematic chain (hip, joint 2, knee, ankle), slope frame, metres; numpy only.

    Forward kinematics of Kim, Kang & Choi, Fig. 2: yaw ``q1`` about the hip ``z``, link ``L1``, pitch ``q2``,
    link ``L2``, pitch ``q3``, link ``L3``.  Used for drawing and as an oracle for Pinocchio.
    """
    q1, q2, q3 = (float(v) for v in joints)
    rb = rot_y(pitch)
    r = rb @ leg.hip_rot @ _rot_z(q1)
    hip = origin + rb @ leg.hip
    j2 = hip + r @ np.array([g["L1"], 0.0, 0.0])
    knee = j2 + r @ np.array([g["L2"] * math.cos(q2), 0.0, g["L2"] * math.sin(q2)])
    ankle = knee + r @ np.array([g["L3"] * math.cos(q2 + q3), 0.0, g["L3"] * math.sin(q2 + q3)])
    return [hip, j2, knee, ankle]
