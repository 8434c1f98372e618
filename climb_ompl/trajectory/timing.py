"""Time-optimal timing of one step's waypoints within joint velocity and acceleration limits.

The geometric path is the cubic spline through the step's waypoints (toppra's ``SplineInterpolator``), its
parameter ``s`` the time each waypoint takes at constant joint speed (so ``s`` is in seconds and well scaled).  The
time-optimal parameterisation ``s(t)`` under ``|q'(s) s_dot| <= v_max`` and ``|q'(s) s_ddot + q''(s) s_dot^2| <=
a_max`` is found by reachability analysis (Pham & Pham (2018), "A new approach to time-optimal path parameterization
based on reachability analysis", IEEE T-RO; toppra's ``TOPPRA`` with its Seidel LP solver), with the grid at the
waypoints, so every stored sample is a waypoint the planner checked.  The step starts and ends at rest (a grasp or a
release happens between steps); velocities are continuous in between.  Only the actuated coordinates are limited:
the base of a floating robot is not a motor, it moves as the closed chains through the holds make it, at the speed
the limbs' limits allow.
"""

from __future__ import annotations

import logging
from dataclasses import dataclass

import numpy as np

#: A base coordinate's limit in the parameterisation, as a multiple of its URDF limit (or of the actuated joints'
#: highest, if lower): the base is not driven, but a path along which no actuated joint moves would otherwise be
#: traversed infinitely fast.
BASE_LIMIT_FACTOR = 1e3
#: Grid points of the parameterisation per interval between two waypoints: the limits hold at the grid points,
#: and the spline bends between waypoints.
SUBDIVISIONS = 2


@dataclass(frozen=True)
class TimedPath:
    """A step's timed samples, one row per waypoint.

    Attributes:
        times: ``(n,)`` seconds from the start of the step, increasing.
        positions: ``(n, nq)`` configurations (the waypoints), metres / radians.
        velocities: ``(n, nq)`` m/s or rad/s; zero at the first and last sample.
        accelerations: ``(n, nq)`` m/s^2 or rad/s^2: the acceleration held from each sample towards the next (the
            last one's: arriving at it).
    """

    times: np.ndarray
    positions: np.ndarray
    velocities: np.ndarray
    accelerations: np.ndarray

    @property
    def duration(self) -> float:
        """Seconds from the first sample to the last."""
        return float(self.times[-1]) if len(self.times) else 0.0

    def slowed(self, k: float) -> TimedPath:
        """The same path ``k >= 1`` times slower: times times ``k``, velocities over ``k``, accelerations over
        ``k^2`` (a uniform time scaling keeps the path and divides ``M(q) a + C(q, v) v`` by ``k^2``)."""
        return TimedPath(self.times * k, self.positions, self.velocities / k, self.accelerations / (k * k))


def distinct(wps: np.ndarray) -> np.ndarray:
    """The waypoints without consecutive repeats (a spline needs increasing parameters)."""
    q = np.asarray(wps, dtype=float)
    if len(q) < 2:
        return q
    keep = np.r_[True, np.any(q[1:] != q[:-1], axis=1)]
    return q[keep]


def time_path(wps: np.ndarray, vmax: np.ndarray, amax: np.ndarray, actuated: np.ndarray,
              sub: int = SUBDIVISIONS) -> TimedPath:
    """The time-optimal rest-to-rest timing of the spline through ``wps``.

    Args:
        wps: ``(n, nq)`` waypoints without consecutive repeats (:func:`distinct`).
        vmax, amax: ``(nq,)`` positive speed and acceleration limits (units of the coordinates per s, per s^2).
        actuated: ``(nq,)`` booleans; the others are limited only loosely (:data:`BASE_LIMIT_FACTOR`).

    Raises:
        ValueError: toppra found no parameterisation (a limit that is not positive).
    """
    import toppra
    import toppra.algorithm
    import toppra.constraint

    q = np.asarray(wps, dtype=float)
    n, nq = q.shape
    if n < 2:
        z = np.zeros((n, nq))
        return TimedPath(np.zeros(n), q, z, z.copy())
    vmax = np.asarray(vmax, dtype=float)
    amax = np.asarray(amax, dtype=float)
    act = np.asarray(actuated, dtype=bool)
    top_v = float(np.max(vmax[act])) if act.any() else 1.0  # a URDF may give a base no limit (1.8e308)
    top_a = float(np.max(amax[act])) if act.any() else 1.0
    vl = np.where(act, vmax, np.minimum(vmax, top_v) * BASE_LIMIT_FACTOR)
    al = np.where(act, amax, np.minimum(amax, top_a) * BASE_LIMIT_FACTOR)
    ss = np.r_[0.0, np.cumsum(np.max(np.abs(np.diff(q, axis=0)) / vl[None, :], axis=1))]
    path = toppra.SplineInterpolator(ss, q, bc_type="natural")
    logging.getLogger("toppra").setLevel(logging.ERROR)
    grid = (ss[:-1, None] + np.diff(ss)[:, None] * (np.arange(sub) / sub)[None, :]).ravel()
    grid = np.r_[grid, ss[-1]]
    algo = toppra.algorithm.TOPPRA([toppra.constraint.JointVelocityConstraint(vl),
                                    toppra.constraint.JointAccelerationConstraint(al)],
                                   path, gridpoints=grid, solver_wrapper="seidel")
    sdd, sd, _ = algo.compute_parameterization(0.0, 0.0)
    if sd is None or not np.all(np.isfinite(sd)):
        raise ValueError("toppra found no timing of the path (check the joint limits)")
    sd = np.maximum(np.asarray(sd, dtype=float), 0.0)
    sd[0] = sd[-1] = 0.0
    dt = 2.0 * np.diff(grid) / np.maximum(sd[:-1] + sd[1:], 1e-300)
    times = np.r_[0.0, np.cumsum(dt)][::sub]
    sd = sd[::sub]
    sdd = np.asarray(sdd, dtype=float)[::sub]
    d1, d2 = path(ss, 1), path(ss, 2)
    u = np.r_[sdd, sdd[-1]]
    # the last sample is reached with the last interval's u: its acceleration is the one arriving there
    return TimedPath(times, q, d1 * sd[:, None], d1 * u[:, None] + d2 * (sd * sd)[:, None])


__all__ = ["TimedPath", "BASE_LIMIT_FACTOR", "distinct", "time_path"]
