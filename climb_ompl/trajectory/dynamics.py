"""The quasi-static assumption, checked: the dynamic joint torques a timed motion needs.

Every equilibrium and torque check of the planner is static (Bretl (2006), sec. 3.2.3: ``tau = g(q) - sum_i J_i^T
f_i``).  Moving at the timed velocities ``v`` and accelerations ``a`` adds ``tau(q, v, a) - g(q) = M(q) a + C(q, v)
v``, computed here with Pinocchio's recursive Newton-Euler algorithm (Featherstone (2008), ch. 5).  Each actuated
joint's allowance is a fraction of the margin the static check left on that step: its torque limit less the largest
static torque stored on the step's force samples.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np


def dynamic_torques(robot: Any, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> np.ndarray:
    """``tau(q, v, a) - g(q)`` at each sample, ``(n, nq)``, N m or N (independent of the gravity vector)."""
    import pinocchio as pin

    m, d = robot.model, robot.data
    out = np.empty_like(np.asarray(q, dtype=float))
    for i in range(len(out)):
        qi = np.asarray(q[i], dtype=float)
        out[i] = pin.rnea(m, d, qi, np.asarray(v[i], dtype=float), np.asarray(a[i], dtype=float))
        out[i] -= pin.computeGeneralizedGravity(m, d, qi)
    return out


def torque_allowance(robot: Any, static_torques: Sequence[Sequence[float]], fraction: float) -> np.ndarray:
    """What the dynamic torque of each coordinate may reach on a step, ``(nq,)``, N m or N: ``fraction`` times the
    torque limit less the largest static torque on the step (``inf`` on a coordinate without a limit, on an
    unactuated one, and on every coordinate of a step without force samples: a robot without an equilibrium
    condition, ``equilibrium: false``).  Never negative."""
    lim = np.asarray(robot.torque_limits, dtype=float)
    out = np.full(robot.nq, np.inf)
    if not len(static_torques):
        return out
    peak = np.max(np.abs(np.asarray(static_torques, dtype=float)), axis=0)
    act = np.asarray(robot.actuated, dtype=bool) & np.isfinite(lim)
    out[act] = fraction * np.maximum(lim[act] - peak[act], 0.0)
    return out


def load_ratio(tau: np.ndarray, allowance: np.ndarray) -> float:
    """The largest ``|tau_j| / allowance_j`` over the samples and the limited coordinates (0 without any; ``inf``
    where a zero allowance meets a non-zero torque)."""
    lim = np.isfinite(allowance)
    if not lim.any() or not len(tau):
        return 0.0
    t = np.abs(np.asarray(tau, dtype=float)[:, lim])
    al = allowance[lim]
    with np.errstate(divide="ignore", invalid="ignore"):
        r = np.where(t > 0, t / al, 0.0)
    return float(np.max(r))


__all__ = ["dynamic_torques", "torque_allowance", "load_ratio"]
