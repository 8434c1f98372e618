"""Independent check of a timed climb step: its samples against the joint limits, the continuity of its motion and
the dynamic torques it implies.

A step with ``velocities`` and ``accelerations`` (:class:`~climb_ompl.plan.file.Step`) is re-checked sample by
sample without the code that timed it (:mod:`climb_ompl.trajectory` is not imported):

* at rest at its first and last sample (a grasp or a release happens between steps); times never go back, and
  two samples share a time only where they share a configuration;
* every actuated joint within its speed and acceleration limits at every sample (:data:`RTOL` relative);
* continuity: between two samples ``dt`` apart, an acceleration within ``a_max`` changes a velocity by at most
  ``a_max dt`` and moves a joint by ``(v_0 + v_1) dt / 2`` give or take ``a_max dt^2 / 2`` (both follow from
  ``|a| <= a_max`` on the interval; a velocity jump, or samples inconsistent with their velocities, fails);
* the quasi-static assumption: the dynamic torques ``M(q) a + h(q, v) - g(q)`` (Pinocchio's CRBA and non-linear
  effects, not the RNEA the timing uses) of each actuated joint stay within the plan's ``dynamic_fraction`` of
  the torque margin its static torques left on the step (limit less the largest stored static torque).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

#: Relative tolerance of the timing checks (samples are rounded to JSON's 17 digits; the timing keeps 1e-9 below).
RTOL = 1e-6
#: Absolute floor of the timing checks (velocities in rad/s or m/s, positions in rad or m).
ATOL = 1e-9


def _joint(robot: Any, j: int) -> str:
    names = getattr(robot, "joint_names", ())
    return repr(names[j]) if j < len(names) and names[j] else f"coordinate {j}"


def dynamic_torques(robot: Any, q: np.ndarray, v: np.ndarray, a: np.ndarray) -> np.ndarray:
    """``M(q) a + h(q, v) - g(q)`` at each sample, ``(n, nq)``: the torques the motion adds to the static ones."""
    import pinocchio as pin

    m, d = robot.model, robot.data
    out = np.empty_like(q)
    for i in range(len(q)):
        mass = pin.crba(m, d, q[i])
        mass = np.triu(mass) + np.triu(mass, 1).T  # CRBA fills the upper triangle
        out[i] = mass @ a[i] + pin.nonLinearEffects(m, d, q[i], v[i]) - pin.computeGeneralizedGravity(m, d, q[i])
    return out


def check_timed_step(robot: Any, s: Any, fraction: float, add: Callable[[str, int, float | None, str], None]) -> None:
    """Report every timing violation of the timed step ``s`` through ``add(check, step, waypoint, message)``."""
    q, t = s.q, np.asarray(s.times, dtype=float)
    v, a = np.array(s.velocities, dtype=float), np.array(s.accelerations, dtype=float)
    at = f"$.steps[{s.index}]"
    if v.shape != q.shape or a.shape != q.shape:
        add("timing", s.index, None, f"{at}: velocities {v.shape} and accelerations {a.shape} do not match the "
            f"waypoints {q.shape}")
        return
    for k in (0, len(q) - 1):
        if np.max(np.abs(v[k])) > ATOL:
            add("timing", s.index, k, f"{at}.velocities[{k}]: not at rest at the step's "
                f"{'start' if k == 0 else 'end'} (|v| = {np.max(np.abs(v[k])):.3g}; grasps and releases are at rest)")
    act = np.asarray(robot.actuated, dtype=bool)
    vmax = np.asarray(robot.velocity_limits, dtype=float)
    amax = np.asarray(robot.acceleration_limits, dtype=float)
    for name, x, lim in (("velocities", v, vmax), ("accelerations", a, amax)):
        with np.errstate(over="ignore"):  # a limit of 1.8e308 (none) stays none
            over = (np.abs(x) > lim * (1 + RTOL) + ATOL) & act
        for k, j in zip(*np.nonzero(over), strict=True):
            add("timing", s.index, int(k), f"{at}.{name}[{k}]: joint {_joint(robot, int(j))} at {x[k, j]:.6g}, over "
                f"its limit {lim[j]:.6g}")
    _check_continuity(robot, s.index, q, t, v, amax, act, add)
    _check_dynamics(robot, s, q, v, a, fraction, add)


def _check_continuity(robot: Any, step: int, q: np.ndarray, t: np.ndarray, v: np.ndarray, amax: np.ndarray,
                      act: np.ndarray, add: Callable[..., None]) -> None:
    dt = np.diff(t)
    at = f"$.steps[{step}]"
    for k in np.nonzero((dt < 0) | ((dt == 0) & np.any(q[1:] != q[:-1], axis=1)))[0]:
        add("timing", step, int(k) + 1, f"{at}.times[{k + 1}]: time goes back or stands still while the robot moves")
    dt = np.maximum(dt, 0.0)[:, None]
    with np.errstate(over="ignore", invalid="ignore"):  # unlimited coordinates (1.8e308) are not checked
        lim = amax[None, :] * (1 + RTOL)
        jump = (np.abs(np.diff(v, axis=0)) > lim * dt + ATOL) & act
        drift = (np.abs(np.diff(q, axis=0) - 0.5 * (v[1:] + v[:-1]) * dt) > 0.5 * lim * dt * dt + ATOL) & act
    for kind, bad in (("velocity jumps", jump), ("samples disagree with their velocities", drift)):
        for k, j in zip(*np.nonzero(bad), strict=True):
            add("timing", step, int(k) + 1, f"{at}.times[{k + 1}] and .velocities[{k + 1}]: {kind} (joint "
                f"{_joint(robot, int(j))}, {dt[k, 0]:.4g} s after the previous sample, beyond what its acceleration "
                "limit allows)")


def _check_dynamics(robot: Any, s: Any, q: np.ndarray, v: np.ndarray, a: np.ndarray, fraction: float,
                    add: Callable[..., None]) -> None:
    lim = np.asarray(robot.torque_limits, dtype=float)
    limited = np.asarray(robot.actuated, dtype=bool) & np.isfinite(lim)
    if not s.forces or not limited.any():
        return  # no static torques stored (equilibrium: false) or no torque limits: no margin to hold to
    peak = np.max(np.abs(np.array([f.torques for f in s.forces], dtype=float)), axis=0)
    allow = fraction * np.maximum(lim - peak, 0.0)
    tau = dynamic_torques(robot, q, v, a)
    over = (np.abs(tau) > allow[None, :] * (1 + RTOL) + ATOL) & limited[None, :]
    for k, j in zip(*np.nonzero(over), strict=True):
        add("dynamics", s.index, int(k), f"$.steps[{s.index}]: joint {_joint(robot, int(j))} needs a dynamic torque "
            f"of {tau[k, j]:.4g} N m, over {fraction:g} of its static margin ({allow[j]:.4g} N m)")


__all__ = ["RTOL", "ATOL", "check_timed_step", "dynamic_torques"]
