"""Plane fit, arc fit and the rear gripper's direction (Lam et al. (TreeBot), sec. V.A.2-4, Eq. 8-20, Fig. 8-10).

A path segment (the path between two front-gripper targets) is moved so its start is at the origin and
rotated by ``Rot_y(theta_y) Rot_z(theta_z)`` to put its end on the ``z`` axis (Fig. 8b); a rotation
``theta_p`` about ``z`` turns the best-fitting plane through both ends into the ``y``-``z`` plane (Eq. 8-10,
Fig. 8c); the projected 2-D path is fitted by a circle through both ends (Fig. 8d); the rear gripper's best
direction is the circle's tangent a body length ``S_min`` before the segment's start (Eq. 18, Fig. 9).

The circle fit used by default (:func:`fit_segment`, ``geometric=True``) is *not* the paper's: it minimises
the geometric error ``sum (|p_i - c| - r)^2`` over the circles through both ends
(:func:`circle_through_ends_geometric`).  The paper's algebraic least squares (Eq. 11-17) is
:func:`circle_through_ends` (``geometric=False``); its printed Eq. 15-17 are garbled in extraction and
re-derived there (the printed ``y_c = -sum(g_i) / sum(h_i)`` zeroes the *sum* of the errors; the
least-squares minimiser of ``sum(e_i^2)`` is ``y_c = -sum(g_i h_i) / sum(h_i^2)``).  The algebraic error
weighs residuals by the radius and returns tight arcs on kinked segments: on generated trees it makes the
proposed method's following error worse (``docs/papers.md``).  The angle ``theta_r`` of Eq. 18 is computed
from the circle geometry for either bending side instead of the printed single-case formula.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def rot_z(a: float) -> np.ndarray:
    """Rotation matrix about ``z`` by ``a`` radians."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def rot_y(a: float) -> np.ndarray:
    """Rotation matrix about ``y`` by ``a`` radians."""
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


@dataclass(frozen=True)
class SegmentFit:
    """Result of the plane and arc fits of one path segment.

    Attributes:
        theta_z, theta_y, theta_p: the rotations of Fig. 8 (radians); local = Rz(tp) Ry(ty) Rz(tz) (p - p_1).
        origin: the segment's start point (world, metres).
        local: ``(eta, 3)`` segment points in the fitted frame (start at 0, end on +z, plane ~ y-z).
        center: fitted circle centre ``(y_c, z_c)`` in the y-z plane, metres (``nan`` if straight).
        radius: fitted radius, metres (``inf`` for a straight segment).
    """

    theta_z: float
    theta_y: float
    theta_p: float
    origin: np.ndarray
    local: np.ndarray
    center: np.ndarray
    radius: float

    @property
    def to_world(self) -> np.ndarray:
        """Rotation from the fitted frame to the world: ``Rot_z(-tz) Rot_y(-ty) Rot_z(-tp)`` (Eq. 18)."""
        return rot_z(-self.theta_z) @ rot_y(-self.theta_y) @ rot_z(-self.theta_p)

    def arc_world(self, k: int = 24) -> np.ndarray:
        """``k`` points of the fitted arc between the segment's ends, world frame."""
        p1, pe = self.local[0, 1:], self.local[-1, 1:]
        if not math.isfinite(self.radius):
            yz = p1 + np.linspace(0, 1, k)[:, None] * (pe - p1)
        else:
            c = self.center
            a1 = math.atan2(p1[1] - c[1], p1[0] - c[0])
            a2 = math.atan2(pe[1] - c[1], pe[0] - c[0])
            sweep = (a2 - a1 + math.pi) % (2 * math.pi) - math.pi  # the minor arc, as in Fig. 8(d)
            ang = a1 + np.linspace(0, 1, k) * sweep
            yz = c + self.radius * np.stack([np.cos(ang), np.sin(ang)], axis=1)
        loc = np.column_stack([np.zeros(k), yz])
        return self.origin + loc @ self.to_world.T


def plane_angle(x: np.ndarray, y: np.ndarray) -> float:
    """``theta_p`` minimising ``sum (x_i cos(tp) - y_i sin(tp))^2`` (Lam et al. (TreeBot), Eq. 8-10).

    Eq. 10: ``tan(tp) = (-q +- sqrt(q^2 + 4)) / 2`` with ``q = (sum y^2 - sum x^2) / sum x y``; of the two
    roots the one with the smaller residual is the minimum.
    """
    sxx, syy, sxy = float(x @ x), float(y @ y), float(x @ y)

    def resid(tp: float) -> float:
        return float(np.sum((x * math.cos(tp) - y * math.sin(tp)) ** 2))

    if abs(sxy) <= 1e-15 * max(sxx + syy, 1e-300):
        return 0.0 if sxx <= syy else math.pi / 2
    q = (syy - sxx) / sxy
    roots = [math.atan((-q + math.sqrt(q * q + 4)) / 2), math.atan((-q - math.sqrt(q * q + 4)) / 2)]
    return min(roots, key=resid)


def circle_through_ends(y: np.ndarray, z: np.ndarray) -> tuple[float, float, float]:
    """Least-squares circle through the first and last of the points ``(y_i, z_i)`` (Lam et al. (TreeBot), Eq. 11-17).

    Returns:
        ``(y_c, z_c, r)``; ``(nan, nan, inf)`` when every point lies on the chord (a straight segment).
    """
    y1, z1, ye, ze = y[0], z[0], y[-1], z[-1]
    a = ((y1**2 + z1**2) - (ye**2 + ze**2)) / (2 * (z1 - ze))  # Eq. 13
    b = (y1 - ye) / (z1 - ze)
    g = (y**2 + z**2) - (y1**2 + z1**2) - 2 * a * (z - z1)  # Eq. 16, re-derived from Eq. 14
    h = -2 * (y - y1) + 2 * b * (z - z1)
    hh = float(h @ h)
    if hh <= 1e-24 * max(float(z1 - ze) ** 4, 1e-300):
        return math.nan, math.nan, math.inf
    yc = -float(g @ h) / hh  # Eq. 17 (least squares)
    zc = a - b * yc
    return yc, zc, math.hypot(y1 - yc, z1 - zc)  # Eq. 11


def circle_through_ends_geometric(y: np.ndarray, z: np.ndarray) -> tuple[float, float, float]:
    """Circle through the first and last points minimising the *geometric* error ``sum (|p_i - c| - r)^2``.

    The algebraic error of Eq. 14, ``e_i = |p_i - c|^2 - r^2 ~ 2 r (|p_i - c| - r)``, weighs each residual by
    ``r`` and so favours small circles: on a nearly straight, slightly noisy segment Eq. 17 can return a
    half circle.  This variant searches the signed curvature ``k`` of the circles through both ends
    (``|k| <= 2 / chord``, the minor arcs of Fig. 8d, ``k = 0`` the chord) with a bounded scalar search.

    Returns:
        ``(y_c, z_c, r)``; ``(nan, nan, inf)`` for the straight chord.
    """
    from scipy.optimize import minimize_scalar

    p = np.column_stack([y, z]).astype(float)
    p1, pe = p[0], p[-1]
    L = float(np.linalg.norm(pe - p1))
    m, d = (p1 + pe) / 2, (pe - p1) / L
    u = np.array([-d[1], d[0]])

    def centre(k: float) -> tuple[np.ndarray, float]:
        r = 1.0 / abs(k)
        return m + math.copysign(math.sqrt(max(r * r - L * L / 4, 0.0)), k) * u, r

    def cost(k: float) -> float:
        if abs(k) < 1e-9 / L:
            return float(np.sum(((p - p1) @ u) ** 2))
        c, r = centre(k)
        return float(np.sum((np.linalg.norm(p - c, axis=1) - r) ** 2))

    kmax = 2.0 / L
    grid = np.linspace(-kmax, kmax, 41)
    k0 = float(grid[int(np.argmin([cost(k) for k in grid]))])
    step = grid[1] - grid[0]
    res = minimize_scalar(cost, bounds=(max(-kmax, k0 - step), min(kmax, k0 + step)), method="bounded",
                          options={"xatol": 1e-10 / L})
    k = float(res.x) if res.fun <= cost(k0) else k0
    if cost(0.0) <= cost(k) or abs(k) < 1e-9 / L:
        return math.nan, math.nan, math.inf
    c, r = centre(k)
    return float(c[0]), float(c[1]), r


def fit_segment(points: np.ndarray, geometric: bool = True) -> SegmentFit:
    """Plane fit and arc fit of a path segment ``(eta, 3)`` (world, metres), ``eta >= 2`` (Fig. 8).

    Args:
        points: the segment, start first.
        geometric: fit the arc by geometric error (:func:`circle_through_ends_geometric`, default) or by
            the paper's algebraic least squares (:func:`circle_through_ends`, Eq. 11-17).
    """
    p = np.asarray(points, float)
    origin = p[0].copy()
    q = p - origin
    e = q[-1]
    tz = -math.atan2(e[1], e[0])
    ty = -math.atan2(math.hypot(e[0], e[1]), e[2])
    q = q @ (rot_y(ty) @ rot_z(tz)).T
    tp = plane_angle(q[:, 0], q[:, 1])
    q = q @ rot_z(tp).T
    fit = circle_through_ends_geometric if geometric and len(q) > 2 else circle_through_ends
    yc, zc, r = fit(q[:, 1], q[:, 2])
    return SegmentFit(tz, ty, tp, origin, q, np.array([yc, zc]), r)


def rear_direction(fit: SegmentFit, s_min: float) -> np.ndarray:
    """The rear gripper's best direction ``v_rg`` (Lam et al. (TreeBot), Eq. 18, Fig. 9), unit, world frame.

    The rear gripper sits on the fitted circle a body length ``s_min`` behind the segment's start; its
    direction is the circle's tangent there, pointing along the motion.  A straight segment gives its chord.
    """
    p1, pe = fit.local[0, 1:], fit.local[-1, 1:]
    if not math.isfinite(fit.radius):
        t = (pe - p1) / np.linalg.norm(pe - p1)
    else:
        c, r = fit.center, fit.radius
        rad = p1 - c
        perp = np.array([-rad[1], rad[0]]) / r  # counter-clockwise tangent at the start
        sigma = 1.0 if perp @ (pe - p1) >= 0 else -1.0  # the side that moves towards the segment's end
        back = -sigma * s_min / r  # the arc angle from the start back to the rear gripper
        cb, sb = math.cos(back), math.sin(back)
        rad_r = np.array([cb * rad[0] - sb * rad[1], sb * rad[0] + cb * rad[1]])
        t = sigma * np.array([-rad_r[1], rad_r[0]]) / r  # [cos(theta_r), sin(theta_r)] of Eq. 18
    v = fit.to_world @ np.array([0.0, t[0], t[1]])
    return v / np.linalg.norm(v)


def seated_direction(direction: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """A gripper's direction once it holds the bark: ``direction`` projected on the surface's tangent plane
    (unit).  Lam et al. (TreeBot), Fig. 10 puts the direction on the gripper frame's ``z`` axis *and* the surface normal
    on its ``x`` axis, so the direction of a holding gripper lies in the tangent plane."""
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    d = np.asarray(direction, float)
    t = d - (d @ n) * n
    if np.linalg.norm(t) < 1e-9:  # body along the normal: keep any tangent direction
        t = np.cross(n, [1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.cross(n, [0.0, 1.0, 0.0])
    return t / np.linalg.norm(t)


def contraction(front: np.ndarray, front_dir: np.ndarray, normal: np.ndarray, v_rg: np.ndarray,
                s_min: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Rear gripper pose after a contraction towards ``v_rg`` (Lam et al. (TreeBot), section V.B.2, Eq. 19-20, Fig. 10).

    The front gripper frame of Fig. 10 has the surface normal on ``x`` and the gripper's direction on ``z``;
    the direction is therefore taken in the tangent plane (:func:`seated_direction`), so that the frame's
    ``y``-``z`` plane is the tangent plane and the rear gripper lands on it ("to make the target position of
    the rear gripper on the tree surface").  ``v_rg`` is projected on that plane; the body, of length
    ``s_min``, bends in it by the angle ``theta_rg`` between the projection and ``z`` (so
    ``kappa = |theta_rg| / s_min``, Eq. 20).  The printed Eq. 19-20 measure ``theta_rg`` from the ``y`` axis;
    here it is measured from ``z`` so that ``theta_rg = 0`` is the straight body of the simple method
    (Fig. 13a).

    Returns:
        ``(rear position, rear direction (unit, in the tangent plane), theta_rg)``.
    """
    n = np.asarray(normal, float) / np.linalg.norm(normal)
    z = seated_direction(front_dir, n)
    R = np.stack([n, np.cross(z, n), z], axis=1)
    yp, zp = float(v_rg @ R[:, 1]), float(v_rg @ R[:, 2])
    th = math.atan2(yp, zp)
    if abs(th) < 1e-12:
        dy, dz = 0.0, s_min
    else:  # the arc's chord: integral of the tangent whose angle falls linearly from th to 0
        dy, dz = s_min * (1 - math.cos(th)) / th, s_min * math.sin(th) / th
    rear = np.asarray(front, float) - dy * R[:, 1] - dz * R[:, 2]
    rdir = math.sin(th) * R[:, 1] + math.cos(th) * R[:, 2]
    return rear, rdir, th
