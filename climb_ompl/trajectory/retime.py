"""A step, and a whole climb plan, timed: toppra's time-optimal timing (:mod:`climb_ompl.trajectory.timing`), then a
uniform slow-down of any step whose samples break a limit or whose dynamic torques pass their allowance
(:mod:`climb_ompl.trajectory.dynamics`)."""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from climb_ompl.settings import ClimbSettings
from climb_ompl.trajectory.dynamics import dynamic_torques, load_ratio, torque_allowance
from climb_ompl.trajectory.timing import TimedPath, time_path

#: Name of this timing as plans record it (``totals.timing``); plans without it were timed at constant joint speed.
TIMING = "toppra"
#: A step is never slowed more than this many times (a zero torque allowance cannot be met by any slow-down).
MAX_SLOWDOWN = 100.0
#: Relative slack kept under every limit after a slow-down (round-off of the samples' arithmetic).
SLACK = 1e-9


@dataclass(frozen=True)
class TimedStep:
    """One step's timing and what it cost.

    Attributes:
        path: the timed samples, one per waypoint (repeated waypoints share a time).
        slowdown: how many times slower than toppra's optimum the step was made (1: not slowed).
        dynamic_ratio: the largest dynamic torque over its allowance (<= 1 unless :data:`MAX_SLOWDOWN` was hit).
        by_dynamics: whether the dynamic torques, not the limits' round-off, set the slow-down.
    """

    path: TimedPath
    slowdown: float
    dynamic_ratio: float
    by_dynamics: bool = False


def _limit_ratio(tp: TimedPath, vmax: np.ndarray, amax: np.ndarray, act: np.ndarray) -> float:
    """The slow-down that brings every sample's speed and acceleration, and each velocity change between samples
    (``|dv| <= a_max dt``), within the actuated joints' limits: at least 1."""
    if len(tp.times) < 2:
        return 1.0
    k = max(1.0, float(np.max(np.abs(tp.velocities[:, act]) / vmax[act])),
            math.sqrt(float(np.max(np.abs(tp.accelerations[:, act]) / amax[act]))))
    dt = np.diff(tp.times)
    ok = dt > 0
    if ok.any():
        dv = np.abs(np.diff(tp.velocities[:, act], axis=0))[ok] / (amax[act][None, :] * dt[ok, None])
        k = max(k, math.sqrt(float(np.max(dv))))  # dv / dt scales as 1 / k^2
    return k


def time_step(robot: Any, wps: Any, static_torques: Any = (),
              fraction: float = ClimbSettings.dynamic_fraction) -> TimedStep:
    """The timed samples of one step's waypoints within the robot's speed and acceleration limits, slowed until
    the dynamic torques stay within ``fraction`` of the static torque margin (``static_torques``: the step's
    stored feed-forward torques, one row per force sample)."""
    q = np.asarray(wps, dtype=float)
    new = np.r_[True, np.any(q[1:] != q[:-1], axis=1)] if len(q) else np.zeros(0, dtype=bool)
    which = np.cumsum(new) - 1  # the distinct waypoint each one repeats
    vmax = np.asarray(robot.velocity_limits, dtype=float)
    amax = np.asarray(robot.acceleration_limits, dtype=float)
    act = np.asarray(robot.actuated, dtype=bool)
    tp = time_path(q[new], vmax, amax, act)
    allowance = torque_allowance(robot, static_torques, fraction)
    ratio = load_ratio(dynamic_torques(robot, tp.positions, tp.velocities, tp.accelerations), allowance)
    k_lim, k_dyn = _limit_ratio(tp, vmax, amax, act), math.sqrt(ratio)  # torques of v and a scale as 1 / k^2
    k = max(k_lim, k_dyn)
    k = min(k * (1 + SLACK), MAX_SLOWDOWN) if k > 1 else 1.0
    tp = tp.slowed(k)
    full = TimedPath(tp.times[which], q, tp.velocities[which], tp.accelerations[which])
    return TimedStep(full, k, ratio / (k * k), k_dyn > max(1.0, k_lim))


def step_fields(ts: TimedStep) -> dict[str, Any]:
    """A timed step's ``times``, ``velocities`` and ``accelerations`` as :class:`~climb_ompl.plan.file.Step` stores
    them (tuples of floats)."""
    p = ts.path
    return {"times": tuple(float(t) for t in p.times),
            "velocities": tuple(tuple(float(x) for x in row) for row in p.velocities),
            "accelerations": tuple(tuple(float(x) for x in row) for row in p.accelerations)}


def time_plan(plan: Any, robot: Any = None) -> tuple[Any, dict[str, Any]]:
    """A climb plan with every step timed (:func:`time_step`; the plan's ``dynamic_fraction`` setting, 0.1 when it
    has none), and what the timing found: ``{"timing", "execution_s", "slowed_steps", "dynamic_ratio",
    "base_speed"}`` (``base_speed``: the base's largest speed along a translation coordinate, m/s).  Its totals
    record the same (``slowed_steps``: the steps the dynamic torques slowed).  ``robot``: the plan's robot if
    already built."""
    from climb_ompl.plan.file import robot_from_plan

    r = robot if robot is not None else robot_from_plan(plan)
    fraction = float(plan.settings.get("dynamic_fraction", ClimbSettings.dynamic_fraction))
    steps, slowed, worst, base = [], 0, 0.0, 0.0
    trans = [i for i in r.base_indices if r.coordinate_kinds[i] == "translation"] if r.base_indices else []
    for s in plan.steps:
        ts = time_step(r, s.q, [f.torques for f in s.forces], fraction)
        slowed += ts.by_dynamics
        worst = max(worst, ts.dynamic_ratio)
        if trans:
            base = max(base, float(np.max(np.linalg.norm(ts.path.velocities[:, trans], axis=1))))
        steps.append(dataclasses.replace(s, **step_fields(ts)))
    info = {"timing": TIMING, "execution_s": float(sum(st.duration for st in steps)), "slowed_steps": slowed,
            "dynamic_ratio": worst, "base_speed": base}
    totals = {**plan.totals, **info}
    return dataclasses.replace(plan, steps=tuple(steps), totals=totals), info


__all__ = ["TIMING", "TimedStep", "time_step", "step_fields", "time_plan"]
