"""Geometry of MRWALLSPECT III's slope transition: planes, body trajectory, foot placement (Kim, Kang & Choi).

Pure numpy, no robot model.  Everything lives in the *slope frame*, the paper's sagittal plane:

* ``x`` is the walking direction, ``y`` lateral (left), ``z`` the normal of the first plane.
* The boundary edge between the two foot surfaces is the ``y`` axis (the origin lies on it).
* First plane (the paper's :math:`\\Pi_{1f}`): ``z = 0`` for ``x <= 0``; normal ``n1 = (0, 0, 1)``.
* Second plane (:math:`\\Pi_{2f}`): through the edge along ``t2 = R_Y(-s*angle) x`` with ``s = +1`` for a
  concave boundary (uphill, floor to wall) and ``s = -1`` for a convex one (downhill, over an edge);
  its normal ``n2 = R_Y(-s*angle) z`` points to the robot's side.

``R_Y(theta)`` is the right-handed rotation about ``y`` (``R_Y(theta) x = (cos, 0, -sin)``), so a body
pitch ``theta`` is the paper's :math:`\\theta_R` (Kim, Kang & Choi, Eq. 15: a positive pitch tips the nose down).

Heights (Kim, Kang & Choi, section 2-3.1): ``h_f`` is the foot height (ankle above sole), ``h`` the height of
the body origin :math:`O_B` above the ankle plane :math:`\\Pi_i` (Eq. 5-8), so the body lines
:math:`\\Pi_{ih}` lie ``H = h + h_f`` above the foot surfaces.  ``d`` is the marginal distance between the
ankle and the boundary line of :math:`\\Pi_1` and :math:`\\Pi_2` when the transition starts or ends.
All lengths in metres, angles in radians unless a name ends in ``_deg``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Literal

import numpy as np

Kind = Literal["concave", "convex"]
KINDS: tuple[str, ...] = ("concave", "convex")

EX = np.array([1.0, 0.0, 0.0])
EY = np.array([0.0, 1.0, 0.0])
EZ = np.array([0.0, 0.0, 1.0])


def rot_y(theta: float) -> np.ndarray:
    """Rotation matrix about ``y`` by ``theta`` radians (right-handed), the paper's :math:`R_Y`."""
    c, s = math.cos(theta), math.sin(theta)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def pitch_of(direction: np.ndarray) -> float:
    """Body pitch whose ``x`` axis points along ``direction`` (x-z plane): Kim, Kang & Choi, Eq. (15).

    Eq. (15) reads :math:`\\theta_R = \\mathrm{atan2}(v_x, v_z) - \\pi/2`, wrapped here to ``(-pi, pi]``.
    """
    th = math.atan2(direction[0], direction[2]) - math.pi / 2
    return math.atan2(math.sin(th), math.cos(th))


def _sign(kind: str) -> float:
    return 1.0 if kind == "concave" else -1.0


def plane_frames(kind: str, angle: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Directions ``(t1, n1, t2, n2)`` of the two planes: along the walking direction and outward normal.

    Kim, Kang & Choi, Eq. (3)-(4) write plane i as :math:`x\\sin\\gamma_i + z\\cos\\gamma_i = \\eta_i`, i.e. normal
    :math:`(\\sin\\gamma_i, 0, \\cos\\gamma_i)`; here :math:`\\gamma_1 = 0` and :math:`\\gamma_2 = -s\\,\\gamma`.
    """
    g2 = -_sign(kind) * angle
    r = rot_y(g2)
    return EX.copy(), EZ.copy(), r @ EX, r @ EZ


def arc_radius(kind: str, angle: float, h: float, d: float) -> float:
    """Radius of the body trajectory's arc: Kim, Kang & Choi, Eq. (10) (concave) and Eq. (11) (convex).

    :math:`R = d / \\tan(\\gamma/2) \\mp h`: the arc is concentric with the arc of radius
    :math:`r_0 = d/\\tan(\\gamma/2)` tangent to both ankle planes at distance ``d`` from their boundary
    line, offset by ``h`` towards (concave) or away from (convex) its centre.
    """
    r0 = d / math.tan(angle / 2)
    return r0 - h if kind == "concave" else r0 + h


def edge_clearance(angle: float, h: float, h_f: float, d: float) -> float:
    """``h_m``: distance from the body's xy plane to the convex boundary edge, Kim, Kang & Choi, Eq. (22).

    :math:`h_m = R - (d/\\tan(\\gamma/2) - h_f)\\sqrt{1 + d^2/r^2}` with :math:`R` of Eq. (11) and
    :math:`r = d/\\tan(\\gamma/2)` (the symbol ``r`` is not defined in the paper's text; this reading makes
    the square root :math:`1/\\cos(\\gamma/2)`, the distance from the arc centre to the edge, and is
    checked against direct geometry in the tests).  Evaluated at the moment of Fig. 11 (the body
    symmetric about the bisector), where it is smallest.
    """
    r = d / math.tan(angle / 2)
    return arc_radius("convex", angle, h, d) - (r - h_f) * math.sqrt(1.0 + d * d / (r * r))


def max_d_for_clearance(angle: float, h: float, h_f: float, clearance: float) -> float:
    """Largest ``d`` with :math:`h_m \\ge` ``clearance`` for a fixed ``h``
    (Kim, Kang & Choi, section 3.1, after Eq. 22).

    Eq. (22) simplifies to :math:`h_m = h + h_f/c - r(1/c - 1)` with :math:`c = \\cos(\\gamma/2)`,
    decreasing in ``d``; solving for ``d`` gives the bound.  ``inf`` when any ``d`` works.
    """
    c = math.cos(angle / 2)
    slack = h + h_f / c - clearance
    if slack <= 0:
        return 0.0
    k = 1.0 / c - 1.0
    if k <= 0:
        return math.inf
    return slack / k * math.tan(angle / 2)


@dataclass(frozen=True)
class BodyPose:
    """The body at one instant of the transition (slope frame).

    Attributes:
        origin: :math:`O` (midpoint of the rear hips), metres.
        front: :math:`F` (centre of the front body), metres; ``|front - origin| = X_f``.
        pitch: rotation about ``y``, radians (Kim, Kang & Choi, Eq. 15).
        case: which part of the trajectory ``O`` and ``F`` are on: ``approach`` (both on line 1),
            ``I``-``IV`` (concave, Fig. 6-10), ``convex`` (Fig. 11), ``departure`` (both on line 2).
    """

    origin: np.ndarray
    front: np.ndarray
    pitch: float
    case: str


class BodyTrajectory:
    """Lines + arc the body follows across the boundary (Kim, Kang & Choi, section 3.1, Eq. 7-21).

    The progress parameter ``p`` (metres) is 0 when :math:`F_B` reaches the arc's start :math:`P_S`
    (the transition begins) and :attr:`p_end` when :math:`O_B` reaches its end :math:`P_E` (it is complete).
    Concave: ``p`` is the distance :math:`O` travelled along the trajectory (Eq. 12, 16-17).  Convex: ``p``
    is the distance the tangent point travelled along the arc (Eq. 19-21).  Outside ``[0, p_end]`` the
    body walks straight along line 1 (``p < 0``) or line 2 (``p > p_end``).

    Args:
        kind: ``"concave"`` or ``"convex"``.
        angle: slope angle :math:`\\gamma` between the planes (Eq. 9), radians, in ``(0, pi)``.
        h: body origin height above the ankle plane, metres.
        h_f: foot height, metres.
        d: marginal distance (see module docstring), metres.
        body_length: :math:`X_f`, metres.
    """

    def __init__(self, kind: str, angle: float, h: float, h_f: float, d: float, body_length: float):
        if kind not in KINDS:
            raise ValueError(f"kind must be one of {KINDS}, got {kind!r}")
        if not 0.0 < angle < math.pi:
            raise ValueError(f"angle must be in (0, pi) radians, got {angle!r}")
        self.kind, self.angle, self.h, self.h_f, self.d, self.X = kind, angle, h, h_f, d, body_length
        self.t1, self.n1, self.t2, self.n2 = plane_frames(kind, angle)
        self.H = h + h_f
        self.R = arc_radius(kind, angle, h, d)
        # Intersection of the body lines Pi_1h and Pi_2h (Eq. 7-8): n_i . p = H.
        a = np.array([[self.n1[0], self.n1[2]], [self.n2[0], self.n2[2]]])
        vx, vz = np.linalg.solve(a, [self.H, self.H])
        self.V = np.array([vx, 0.0, vz])
        tan_len = self.R * math.tan(angle / 2)
        self.P_S = self.V - tan_len * self.t1
        self.P_E = self.V + tan_len * self.t2
        s = _sign(kind)
        self.P_R = self.P_S + s * self.R * self.n1  # arc centre: robot side (concave), below (convex)
        self.arc_len = self.R * angle
        self.p_end = (body_length + self.arc_len) if kind == "concave" else self.arc_len

    # -- the trajectory curve, by arc length s (0 at P_S) -------------------------------------------
    def curve_point(self, s: float) -> np.ndarray:
        """Point of the trajectory at arc length ``s`` from :math:`P_S` (negative: on line 1)."""
        if s <= 0.0:
            return self.P_S + s * self.t1
        if s >= self.arc_len:
            return self.P_E + (s - self.arc_len) * self.t2
        return self.arc_point(s / self.R)

    def arc_point(self, phi: float) -> np.ndarray:
        """Point on the arc turned by ``phi`` from :math:`P_S` about :math:`P_R` (Eq. 17 / Eq. 20)."""
        return self.P_R + rot_y(-_sign(self.kind) * phi) @ (self.P_S - self.P_R)

    def segment_of(self, s: float, tol: float = 1e-12) -> str:
        """``line1``, ``arc`` or ``line2``: the part of the trajectory at arc length ``s``."""
        if s <= tol:
            return "line1"
        if s >= self.arc_len - tol:
            return "line2"
        return "arc"

    # -- the body pose by progress p ------------------------------------------------------------------
    def pose(self, p: float) -> BodyPose:
        """Body pose at progress ``p`` (metres), from the paper's equations for the current case."""
        return self._pose_concave(p) if self.kind == "concave" else self._pose_convex(p)

    def _pose_convex(self, p: float) -> BodyPose:
        if p <= 0.0:
            o = self.P_S - self.X * self.t1 + p * self.t1
            return BodyPose(o, o + self.X * self.t1, pitch_of(self.t1), "approach" if p < 0 else "convex")
        if p >= self.p_end:
            o = self.P_E + (p - self.p_end) * self.t2
            return BodyPose(o, o + self.X * self.t2, pitch_of(self.t2), "departure" if p > self.p_end else "convex")
        theta = p / self.R  # Eq. (19), accumulated over the steps
        p_t2 = self.P_R + rot_y(theta) @ (self.P_S - self.P_R)  # Eq. (20), P_T1 = P_S at the start
        u = rot_y(theta) @ EX
        o = p_t2 - abs(self.angle - theta) / self.angle * self.X * u  # Eq. (21), gamma_1 = 0
        return BodyPose(o, o + self.X * u, theta, "convex")

    def _pose_concave(self, p: float) -> BodyPose:
        s_o = p - self.X
        o = self.curve_point(s_o)
        seg_o = self.segment_of(s_o)
        if seg_o == "line1" and s_o + self.X <= 0.0:
            f = o + self.X * self.t1
            case = "approach"
        elif seg_o == "line2":
            f = o + self.X * self.t2
            case = "departure"
        elif np.linalg.norm(self.P_E - o) > self.X:
            f = self.front_on_arc(o)  # Eq. (13): case I (O on line 1) or III (O on the arc)
            case = "I" if seg_o == "line1" else "III"
        else:
            f = self.front_on_line2(o)  # Eq. (14): case II or IV
            case = "II" if seg_o == "line1" else "IV"
        return BodyPose(o, f, pitch_of(f - o), case)

    def front_on_arc(self, o: np.ndarray) -> np.ndarray:
        """Kim, Kang & Choi, Eq. (13): :math:`|F - P_R| = R`, :math:`|F - O| = X_f`; the solution on the arc."""
        c = self.P_R
        dv = o - c
        dist = float(np.linalg.norm(dv))
        # circle-circle intersection in the x-z plane
        a = (self.R**2 - self.X**2 + dist**2) / (2 * dist)
        hh = math.sqrt(max(self.R**2 - a * a, 0.0))
        e = dv / dist
        perp = np.array([-e[2], 0.0, e[0]])
        cands = [c + a * e + hh * perp, c + a * e - hh * perp]
        on_arc = [q for q in cands if -1e-9 <= self._arc_angle(q) <= self.angle + 1e-9]
        return max(on_arc or cands, key=lambda q: self._arc_angle(q))

    def front_on_line2(self, o: np.ndarray) -> np.ndarray:
        """Kim, Kang & Choi, Eq. (14): :math:`F\\cdot n_{2h} = \\eta_2 + h`, :math:`|F - O| = X_f`; the one ahead."""
        # F = P_E + u t2; |P_E + u t2 - O|^2 = X^2  ->  u^2 + 2 u (w.t2) + |w|^2 - X^2 = 0, w = P_E - O
        w = self.P_E - o
        b = float(w @ self.t2)
        disc = b * b - (float(w @ w) - self.X**2)
        u = -b + math.sqrt(max(disc, 0.0))
        return self.P_E + u * self.t2

    def _arc_angle(self, q: np.ndarray) -> float:
        """Signed angle from :math:`P_S` to ``q`` about :math:`P_R`, in the direction of travel."""
        a = self.P_S - self.P_R
        b = q - self.P_R
        cross = a[2] * b[0] - a[0] * b[2]  # (a x b) . y: positive for a turn nose-down about P_R
        ang = math.atan2(cross, float(a @ b))
        return ang if self.kind == "convex" else -ang

    def junctions(self) -> tuple[float, ...]:
        """Values of ``p`` where a body step must stop (Kim, Kang & Choi: "if ||P_S|| < t_p, P_S is O_N")."""
        return (self.X, self.p_end) if self.kind == "concave" else (0.0, self.p_end)


def step_schedule(p_start: float, p_stop: float, t_p: float, junctions: tuple[float, ...]) -> list[float]:
    """Body positions ``p_0 = p_start < p_1 < ...`` one stride ``t_p`` apart, clipped at the junctions.

    Kim, Kang & Choi, Eq. (12) and the text after Eq. (17): a step that would carry the body past the start or
    end of the arc stops there, and the next step starts from it.
    """
    if t_p <= 0:
        raise ValueError("stride t_p must be positive")
    out = [p_start]
    p = p_start
    while p < p_stop - 1e-12:
        nxt = min(p + t_p, p_stop)
        for j in junctions:
            if p < j - 1e-12 < nxt:
                nxt = j
                break
        out.append(nxt)
        p = nxt
    return out


def foot_on_plane(
    hip: np.ndarray,
    axis_x: np.ndarray,
    axis_z: np.ndarray,
    lateral: float,
    lateral_axis: np.ndarray,
    upsilon: float,
    L1: float,
    plane_normal: np.ndarray,
    plane_offset: float,
    plane_dir: np.ndarray,
) -> list[np.ndarray]:
    """Ankle points on an ankle plane at leg distance :math:`\\Upsilon` from joint 2:
    Kim, Kang & Choi, Eq. (1), (23)-(24).

    The leg frame :math:`\\Sigma_L` has origin ``hip`` (joint 1), ``x`` along ``axis_x``, lateral ``y`` along
    ``lateral_axis`` and ``z`` along ``axis_z``.  The workspace surface is Eq. (1),
    :math:`(\\sqrt{x^2+y^2} - L_1)^2 + z^2 = \\Upsilon^2`, taking the outward branch
    :math:`\\sqrt{x^2+y^2} \\ge L_1`.  The foot keeps the basic form's lateral coordinate
    (":math:`^W y` is equal to y", section 3.2), so the ankle runs along the line
    ``plane_offset * plane_normal + lateral * lateral_axis + u * plane_dir`` on the plane
    ``plane_normal . p = plane_offset``; Eq. (24) is Eq. (1) restricted to that line, a quartic in ``u``.

    Note:
        Eq. (24) as printed lost the squares under its root; the form solved here is
        :math:`{}^Wx^2 + {}^Wy^2 - 2L_1\\sqrt{({}^Wx\\cos\\gamma + \\eta_W\\sin\\gamma)^2 + {}^Wy^2}
        = \\Upsilon^2 - L_1^2 - \\eta_W^2`, which is what Eq. (1) and (23) give.

    Returns:
        The ankle points (slope frame, metres), possibly empty, sorted by ``u``.
    """
    base = plane_offset * plane_normal + (float(hip @ lateral_axis) + lateral) * lateral_axis
    # leg-frame coordinates as affine functions of u: c0 + u c1
    rel0 = base - hip
    x0, x1 = float(rel0 @ axis_x), float(plane_dir @ axis_x)
    y0 = float(rel0 @ lateral_axis)
    z0, z1 = float(rel0 @ axis_z), float(plane_dir @ axis_z)
    # a(u) = x^2 + y^2 ; f(u) = a + z^2 + L1^2 - U^2 ; f^2 = 4 L1^2 a
    a = np.array([x1 * x1, 2 * x0 * x1, x0 * x0 + y0 * y0])
    f = a + np.array([z1 * z1, 2 * z0 * z1, z0 * z0]) + np.array([0.0, 0.0, L1 * L1 - upsilon * upsilon])
    quartic = np.polymul(f, f) - np.concatenate([[0.0, 0.0], 4 * L1 * L1 * a])
    quartic = np.trim_zeros(quartic, "f")
    if quartic.size < 2:
        return []
    out: list[np.ndarray] = []
    for r in np.roots(quartic):
        if abs(r.imag) > 1e-5:  # keep near-double roots (tangency); Newton and the residual decide
            continue
        u = float(r.real)
        # polish with Newton steps on the un-squared residual
        for _ in range(3):
            x, z = x0 + u * x1, z0 + u * z1
            rho = math.hypot(x, y0)
            if rho < 1e-12:
                break
            g = (rho - L1) ** 2 + z * z - upsilon**2
            dg = 2 * (rho - L1) * x * x1 / rho + 2 * z * z1
            if abs(dg) < 1e-14:
                break
            u -= g / dg
        x, z = x0 + u * x1, z0 + u * z1
        rho = math.hypot(x, y0)
        if rho < L1 or abs((rho - L1) ** 2 + z * z - upsilon**2) > 1e-8:
            continue
        p = base + u * plane_dir
        if not any(np.linalg.norm(p - q) < 1e-9 for q in out):
            out.append(p)
    out.sort(key=lambda q: float(q @ plane_dir))
    return out
