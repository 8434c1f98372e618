"""A timed climb plan as samples along the climb's clock: positions, velocities, accelerations, feed-forward torques
and contact forces, one row per sample, at the plan's own samples (its waypoints) or at a chosen rate.

Between the plan's samples, positions and velocities follow the cubic Hermite curve through the stored positions and
velocities (what a trajectory controller interpolates), and accelerations are held from one sample to the next (the
timing keeps them so, :mod:`climb_ompl.trajectory.timing`).  Torques are the plan's static feed-forward torques
(stored on every ``force_every``-th waypoint, Bretl (2006), sec. 5.1, and interpolated linearly in time between them)
plus the dynamic torques of the motion (:func:`climb_ompl.trajectory.dynamics.dynamic_torques`); contact forces are
the stored ones, interpolated the same way, zero for a limb off its hold.  A plan without timing (written before
plans were timed) is timed first (:func:`climb_ompl.trajectory.retime.time_plan`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from climb_ompl.trajectory.dynamics import dynamic_torques


@dataclass(frozen=True)
class Samples:
    """The climb as rows of samples.

    Attributes:
        t: ``(n,)`` seconds since the climb began (a step's last sample and the next one's first share a time).
        step: ``(n,)`` the step each row belongs to.
        q, v, a: ``(n, nq)`` positions, velocities and accelerations (SI, radians).
        tau: ``(n, nq)`` feed-forward torques, static plus dynamic, N m or N (``nan`` where the plan stores no
            static torques: a robot without an equilibrium condition).
        forces: ``(n, len(limbs), 3)`` the force each hold exerts on each limb, world frame, newtons.
        joint_names: the name of each configuration coordinate's joint.
        actuated: ``(nq,)`` which coordinates a motor drives.
        limbs: the limb names, in the order of :attr:`forces`.
    """

    t: np.ndarray
    step: np.ndarray
    q: np.ndarray
    v: np.ndarray
    a: np.ndarray
    tau: np.ndarray
    forces: np.ndarray
    joint_names: tuple[str, ...]
    actuated: np.ndarray
    limbs: tuple[str, ...]


def timed(plan: Any, robot: Any) -> Any:
    """The plan itself when every step is timed, else the plan timed (:func:`~climb_ompl.trajectory.retime.
    time_plan`)."""
    if all(s.timed for s in plan.steps):
        return plan
    from climb_ompl.trajectory.retime import time_plan

    return time_plan(plan, robot)[0]


def _hermite(t: np.ndarray, q: np.ndarray, v: np.ndarray, tt: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Cubic Hermite interpolation at times ``tt`` of samples ``(t, q, v)``: positions, velocities and the index of
    the sample each time follows."""
    k = np.clip(np.searchsorted(t, tt, side="right") - 1, 0, len(t) - 2)
    h = t[k + 1] - t[k]
    safe = np.where(h > 0, h, 1.0)
    s = np.where(h > 0, (tt - t[k]) / safe, 0.0)[:, None]
    hh = safe[:, None]
    p0, p1, v0, v1 = q[k], q[k + 1], v[k] * hh, v[k + 1] * hh
    h00, h10, h01, h11 = 2 * s**3 - 3 * s**2 + 1, s**3 - 2 * s**2 + s, -2 * s**3 + 3 * s**2, s**3 - s**2
    pos = h00 * p0 + h10 * v0 + h01 * p1 + h11 * v1
    d00, d10, d01, d11 = 6 * s**2 - 6 * s, 3 * s**2 - 4 * s + 1, -6 * s**2 + 6 * s, 3 * s**2 - 2 * s
    vel = (d00 * p0 + d10 * v0 + d01 * p1 + d11 * v1) / hh
    return pos, vel, k


def static_at(s: Any, robot: Any, limbs: tuple[str, ...], tt: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Step ``s``'s static torques ``(n, nq)`` and contact forces ``(n, len(limbs), 3)`` at its times ``tt``,
    interpolated between its force samples (``nan`` torques and zero forces for a step without any)."""
    n = len(tt)
    if not s.forces:
        return np.full((n, robot.nq), np.nan), np.zeros((n, len(limbs), 3))
    times = np.asarray(s.times, dtype=float)
    ft = times[[f.waypoint for f in s.forces]]
    tau = np.array([f.torques for f in s.forces], dtype=float)
    fr = np.zeros((len(s.forces), len(limbs), 3))
    for i, f in enumerate(s.forces):
        for limb, vec in f.forces:
            fr[i, limbs.index(limb)] = vec
    if len(ft) == 1:
        return np.repeat(tau, n, axis=0), np.repeat(fr, n, axis=0)
    lin = np.column_stack([np.interp(tt, ft, col) for col in np.column_stack([tau, fr.reshape(len(ft), -1)]).T])
    return lin[:, :robot.nq], lin[:, robot.nq:].reshape(n, len(limbs), 3)


def plan_samples(plan: Any, robot: Any, rate: float | None = None) -> Samples:
    """The samples of ``plan`` (timed first if it is not), at its own samples (``rate=None``) or every ``1 / rate``
    seconds of each step plus the step's last instant."""
    plan = timed(plan, robot)
    limbs = tuple(lb.name for lb in robot.limbs)
    rows: dict[str, list[np.ndarray]] = {k: [] for k in ("t", "step", "q", "v", "a", "tau", "forces")}
    t0 = 0.0
    for s in plan.steps:
        t, q = np.asarray(s.times, dtype=float), s.q
        v, a = np.array(s.velocities, dtype=float), np.array(s.accelerations, dtype=float)
        if rate is not None and len(t) > 1:
            tt = np.unique(np.r_[np.arange(0.0, t[-1], 1.0 / rate), t[-1]])
            q, v, k = _hermite(t, q, v, tt)
            a = np.where((tt >= t[-1])[:, None], a[-1], a[k])
            t = tt
        static, forces = static_at(s, robot, limbs, t)
        rows["t"].append(t0 + t)
        rows["step"].append(np.full(len(t), s.index))
        rows["q"].append(q)
        rows["v"].append(v)
        rows["a"].append(a)
        rows["tau"].append(static + dynamic_torques(robot, q, v, a))
        rows["forces"].append(forces)
        t0 += float(t[-1]) if len(t) else 0.0
    nq = robot.nq
    cat = {k: np.concatenate(v) if v else np.zeros((0,) if k in ("t", "step") else (0, nq)) for k, v in rows.items()}
    if not rows["forces"]:
        cat["forces"] = np.zeros((0, len(limbs), 3))
    return Samples(cat["t"], cat["step"].astype(int), cat["q"], cat["v"], cat["a"], cat["tau"], cat["forces"],
                   tuple(robot.joint_names), np.asarray(robot.actuated, dtype=bool), limbs)


__all__ = ["Samples", "plan_samples", "static_at", "timed"]
