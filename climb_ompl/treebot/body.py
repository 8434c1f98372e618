"""Kinematics of TreeBot's continuum body (Lam et al., section II, Eq. 1-3, Fig. 3).

The body is a circular arc of length ``S`` and curvature ``kappa`` bent in the plane at angle ``phi``
about the gripper's axis.  In a *gripper frame* (origin at the gripper, ``z`` along the body's tangent
there, ``x`` towards the surface normal) the arc is

    r(s) = ( (1 - cos(kappa s)) / kappa * cos(phi), (1 - cos(kappa s)) / kappa * sin(phi), sin(kappa s) / kappa ),

``0 <= s <= S``.  :func:`posture` inverts it (Eq. 1-3): the arc that leaves the origin along ``z`` and
ends at a given point.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Posture:
    """Shape of the continuum body (Lam et al. (TreeBot), Fig. 3).

    Attributes:
        phi: bending-plane angle about the gripper's z axis, radians.
        kappa: curvature, 1/m (>= 0; 0 is a straight body).
        S: arc length, metres (``inf`` when the point cannot be reached by an arc leaving along ``z``).
    """

    phi: float
    kappa: float
    S: float


def posture(target: np.ndarray) -> Posture:
    """The arc from the origin, leaving along ``+z``, to ``target`` (gripper frame): Lam et al. (TreeBot), Eq. 1-3.

    ``phi = atan2(y, x)`` (Eq. 1), ``theta1 = atan2(z, x')`` with ``x' = x cos(phi) + y sin(phi)``,
    ``kappa = 2 cos(theta1) / sqrt(x'^2 + z^2)`` (Eq. 2), ``S = theta / kappa`` with
    ``theta = 2 (pi/2 - theta1)`` (Eq. 3); a straight body (``kappa = 0``) has ``S`` = the distance.
    """
    x, y, z = (float(v) for v in target)
    phi = math.atan2(y, x)
    xp = x * math.cos(phi) + y * math.sin(phi)
    chord = math.hypot(xp, z)
    if chord == 0.0:
        return Posture(0.0, 0.0, 0.0)
    # pi/2 - theta1 computed directly as atan2(x', z): no cancellation for nearly straight bodies.
    half = math.atan2(xp, z)  # theta / 2, with cos(theta1) = sin(theta / 2)
    sh = math.sin(half)
    if sh <= 0.0:
        return Posture(phi, 0.0, chord if z > 0 else math.inf)
    kappa = 2.0 * sh / chord
    return Posture(phi, kappa, chord * half / sh)


def arc_points(p: Posture, k: int = 12) -> np.ndarray:
    """``k`` points along the arc (gripper frame), ``(k, 3)``, from the origin to the arc's end."""
    s = np.linspace(0.0, p.S, k)
    if p.kappa == 0.0:
        rho, z = np.zeros(k), s
    else:
        rho = 2.0 * np.sin(p.kappa * s / 2) ** 2 / p.kappa  # (1 - cos) / kappa without cancellation
        z = np.sin(p.kappa * s) / p.kappa
    return np.stack([rho * math.cos(p.phi), rho * math.sin(p.phi), z], axis=1)


def arc_end_tangent(p: Posture) -> np.ndarray:
    """Unit tangent of the arc at its end (gripper frame), pointing away from the origin."""
    a = p.kappa * p.S
    return np.array([math.sin(a) * math.cos(p.phi), math.sin(a) * math.sin(p.phi), math.cos(a)])


def gripper_frame(z_dir: np.ndarray, normal: np.ndarray) -> np.ndarray:
    """Rotation (columns x, y, z) of a gripper frame: ``z`` along ``z_dir``, ``x`` the part of ``normal``
    orthogonal to it (Lam et al. (TreeBot), Fig. 3 and 10)."""
    z = np.asarray(z_dir, float) / np.linalg.norm(z_dir)
    x = np.asarray(normal, float) - (np.asarray(normal, float) @ z) * z
    if np.linalg.norm(x) < 1e-9:  # normal along the body: any perpendicular will do
        x = np.cross(z, [1.0, 0.0, 0.0]) if abs(z[0]) < 0.9 else np.cross(z, [0.0, 1.0, 0.0])
    x /= np.linalg.norm(x)
    return np.stack([x, np.cross(z, x), z], axis=1)


def interpolate(a: Posture, b: Posture, t: float) -> Posture:
    """Posture a fraction ``t`` of the way from ``a`` to ``b`` (linear in ``kappa`` and ``S``, shortest turn
    in ``phi``; a straight end takes the other end's ``phi``)."""
    pa = b.phi if a.kappa == 0.0 else a.phi
    pb = a.phi if b.kappa == 0.0 else b.phi
    dphi = (pb - pa + math.pi) % (2 * math.pi) - math.pi
    return Posture(pa + t * dphi, a.kappa + t * (b.kappa - a.kappa), a.S + t * (b.S - a.S))
