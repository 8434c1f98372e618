"""Model reduction of the planar three-limbed robot.

Bretl, Latombe & Rock (2003), section 3.4, Eq. 2-5; Bretl (2006), appendix C.

At a two-hold stance the contact chain (pelvis + two contact limbs) is fixed by the pelvis position
``(x_p, z_p)`` and the two elbow bends; the free limb's CoM abscissa is (Eq. 3 / C1)::

    x_c/free = x_p + L/4 (3 cos t1 + cos(t1 + t2))

with ``t1`` the free limb's absolute first-link angle (from +x, counter-clockwise in the x-z plane) and
``t2`` its elbow angle.  Equilibrium ``x_c in E = [x_min, x_max]`` becomes ``x_c/free in
[3 x_min - 2 x_c/chain, 3 x_max - 2 x_c/chain]`` (Eq. 2), i.e. ``delta = x_c/free - x_p`` in
``[delta_min, delta_max]``.  A pelvis position is *feasible* iff ``delta_min < L`` and ``delta_max > -L``
(Eq. 4 / C2); then ``(t1, t2) = (+-acos(delta/L), 0)`` are feasible lifts (C3), and ``Theta_f`` is connected
iff ``delta_min`` or ``delta_max`` lies outside ``(-L/2, L/2)`` (Eq. 5 / C4).

The robot (``urdf/planar-3limb.urdf``): base ``x``, ``z`` (prismatic) and ``theta`` (the massless point
pelvis' angle, a redundancy), three identical limbs of two uniform links of length ``L`` and equal mass.
Absolute angle = ``base theta + shoulder``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from climb_ompl.manifold.stance import Stance, StanceConstraint, limb_index

if TYPE_CHECKING:  # pragma: no cover
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain


def supports(robot: RobotModel, stance: Stance) -> bool:
    """Whether the reduction applies: a planar robot with three two-joint limbs, two of them in contact."""
    return bool(robot.planar) and len(robot.limbs) == 3 and len(stance) == 2 and all(
        len(lb.joint_indices) == 2 for lb in robot.limbs)


@dataclass(frozen=True)
class Chain:
    """A contact-chain configuration: pelvis, elbow bends and the reduced quantities of Eq. 2."""

    q: np.ndarray  #: full configuration with the free limb at (0, 0) (to be set by a lift)
    x_p: float
    z_p: float
    delta_min: float
    delta_max: float

    def feasible(self, L: float) -> bool:
        """Eq. (4) / (C2)."""
        return self.delta_min < L and self.delta_max > -L

    def connected(self, L: float) -> bool:
        """Eq. (5) / (C4): ``Theta_f`` is connected."""
        return not (-L / 2 < self.delta_min < L / 2) or not (-L / 2 < self.delta_max < L / 2)


class Reduction:
    """The reduced (pelvis) parameterisation of a two-hold stance of the planar three-limbed robot.

    Args:
        robot: the planar three-limbed robot.
        terrain: the 2-D terrain.
        stance: a two-hold stance.
        constraint: its :class:`StanceConstraint` (used to check closures).
    """

    def __init__(self, robot: RobotModel, terrain: Terrain, stance: Stance, constraint: StanceConstraint | None = None):
        self.robot, self.terrain, self.stance, self.constraint = robot, terrain, stance, constraint
        bx = [j for j in robot.base_indices]
        self.ix, self.iz, self.ith = int(bx[0]), int(bx[1]), int(bx[2])
        self.contact = [robot.limbs[limb_index(robot, lb)] for lb in stance.limbs]
        self.free = [lb for lb in robot.limbs if lb.name not in stance][0]
        self.holds = [robot.hand_target(lb.name, terrain.hold(stance[lb.name])) for lb in self.contact]
        q0 = np.zeros(robot.nq)
        h = robot.hand_position(q0, self.free.name)
        self.L = float(np.hypot(h[0], h[2])) / 2.0  # straight limb at zero angles: 2L from the pelvis

    # ---- kinematics -----------------------------------------------------------------------------
    def chain(self, x_p: float, z_p: float, bends: tuple[int, int], region: Any, theta: float = 0.0) -> Chain | None:
        """The contact chain for a pelvis position and elbow bends (``+1``/``-1``); ``None`` if unreachable."""
        L = self.L
        q = np.zeros(self.robot.nq)
        q[self.ix], q[self.iz], q[self.ith] = x_p, z_p, theta
        xs = []
        for lb, hp, s in zip(self.contact, self.holds, bends, strict=False):
            dx, dz = hp[0] - x_p, hp[2] - z_p
            r2 = dx * dx + dz * dz
            c2 = (r2 - 2 * L * L) / (2 * L * L)
            if c2 < -1 or c2 > 1:
                return None
            t2 = s * math.acos(c2)
            t1 = math.atan2(dz, dx) - math.atan2(L * math.sin(t2), L + L * math.cos(t2))
            q[lb.joint_indices[0]] = _wrap(t1 - theta)
            q[lb.joint_indices[1]] = t2
            xs.append(x_p + L / 4 * (3 * math.cos(t1) + math.cos(t1 + t2)))
        x_chain = float(np.mean(xs))  # CoM abscissa of the four chain links (equal masses)
        lo, hi = interval(region)
        return Chain(q, x_p, z_p, 3 * lo - 2 * x_chain - x_p, 3 * hi - 2 * x_chain - x_p)

    def lifts(self, ch: Chain) -> list[np.ndarray]:
        """Eq. (C3) lifts ``q_-`` and ``q_+`` (and, when ``Theta_f`` is connected, one with ``t1`` in {0, pi})."""
        L = self.L
        lo, hi = max(ch.delta_min, -L), min(ch.delta_max, L)
        if lo >= hi:
            return []
        d = 0.5 * (lo + hi)
        th = float(ch.q[self.ith])
        out = []
        for t1 in (-math.acos(d / L), math.acos(d / L)):
            q = ch.q.copy()
            q[self.free.joint_indices[0]], q[self.free.joint_indices[1]] = _wrap(t1 - th), 0.0
            out.append(q)
        if ch.connected(L):
            # t1 = 0 gives delta = L/4 (3 + cos t2) in [L/2, L]; t1 = pi gives -L/4 (3 + cos t2) in [-L, -L/2]
            for t1, sgn in ((0.0, 1.0), (math.pi, -1.0)):
                a, b = (L / 2, L) if sgn > 0 else (-L, -L / 2)
                lo2, hi2 = max(lo, a), min(hi, b)
                if lo2 < hi2:
                    dd = 0.5 * (lo2 + hi2)
                    c = np.clip(4 * abs(dd) / L - 3, -1.0, 1.0)
                    q = ch.q.copy()
                    q[self.free.joint_indices[0]], q[self.free.joint_indices[1]] = _wrap(t1 - th), math.acos(c)
                    out.append(q)
                    break
        return out

    def sample(self, rng: np.random.Generator, region: Any, tries: int = 50) -> np.ndarray | None:
        """A random feasible pelvis position (within 2L of both holds, Bretl (2006), Fig. 17) lifted by (C3)."""
        L = self.L
        c = np.mean(self.holds, axis=0)
        for _ in range(tries):
            x_p, z_p = c[0] + rng.uniform(-2 * L, 2 * L), c[2] + rng.uniform(-2 * L, 2 * L)
            bends = (int(rng.choice([-1, 1])), int(rng.choice([-1, 1])))
            ch = self.chain(x_p, z_p, bends, region, theta=float(rng.uniform(-0.5, 0.5)))
            if ch is None or not ch.feasible(L):
                continue
            qs = self.lifts(ch)
            if qs:
                return qs[int(rng.integers(len(qs)))]
        return None


def interval(region: Any) -> tuple[float, float]:
    """``(x_min, x_max)`` of a planar support region (the CoM-x interval ``E``,
    Bretl, Latombe & Rock (2003), section 3.3)."""
    lo, hi = region.interval
    return float(lo), float(hi)


def _wrap(a: float) -> float:
    return (a + math.pi) % (2 * math.pi) - math.pi


__all__ = ["supports", "Reduction", "Chain", "interval"]
