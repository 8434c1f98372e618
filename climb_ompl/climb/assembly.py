"""Plan assembly: the steps of a found climb as a :class:`~climb_ompl.plan.file.Plan`.

Each step's waypoints are timed time-optimally within the joint speed and acceleration limits (Bretl 2006, sec. 5.1:
LEMUR's 45 deg/s), at rest at each grasp and release, and slowed where the dynamic torques would take more than the
``dynamic_fraction`` of the torque margin (:mod:`climb_ompl.trajectory`).  Contact forces and feed-forward torques
are stored on every ``force_every``-th waypoint (sec. 5.1: LEMUR is sent "a list of joint-angle waypoints and
feedforward torques").  The plan embeds the robot spec, its URDF and the terrain with their hashes, the query, the
seed and every setting.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np

from climb_ompl.plan.file import ForceSample, Plan, Step, library_versions, robot_record
from climb_ompl.trajectory.retime import time_plan

if TYPE_CHECKING:
    from climb_ompl.climb.search import StanceGraphSearch

#: Margin recorded for a CoM in an unbounded support region (two holds facing each other, a chimney or a crack:
#: friction holds the body wherever its CoM is), metres: a plan file holds finite numbers only (JSON).
UNBOUNDED_MARGIN = 1000.0


def waypoint_times(robot: Any, wps: list[np.ndarray]) -> list[float]:
    """Times of the waypoints when every joint moves at constant speed, at most its speed limit (no acceleration
    limit: the timing of plans written before :mod:`climb_ompl.trajectory`, and the path parameter it starts
    from)."""
    vmax = np.asarray(robot.velocity_limits, dtype=float)
    t = [0.0]
    for a, b in zip(wps[:-1], wps[1:], strict=True):
        t.append(t[-1] + float(np.max(np.abs(b - a) / vmax)) * (1 + 1e-9))
    return t


def force_samples(robot: Any, terrain: Any, stance: Any, wps: list[np.ndarray], force_every: int,
                  region: Any) -> list[ForceSample]:
    """Contact forces (exact cones, most robust) and feed-forward torques on every ``force_every``-th
    waypoint and the last; none for a robot without equilibrium condition (``equilibrium: false``, the
    peg-grabbing robot of Bretl 2006, sec. 2.1)."""
    from climb_ompl.equilibrium import torque_feasible
    from climb_ompl.manifold.stance import contact_jacobians

    r = robot
    if not r.equilibrium:
        return []
    idx = sorted(set(range(0, len(wps), max(1, force_every))) | {len(wps) - 1})
    contacts = stance.contacts(terrain)
    out = []
    for k in idx:
        q = wps[k]
        com = np.asarray(r.com(q), dtype=float)
        jac = contact_jacobians(r, terrain, stance, q)  # of the points touching the holds
        res = torque_feasible(contacts, r.mass, terrain.g, com, jac, r.gravity_torques(q, terrain.g),
                              r.torque_limits, r.actuated, planar=bool(r.planar))
        if res.forces is None:
            continue
        f = np.asarray(res.forces, dtype=float).reshape(len(stance), 3)
        tau = np.asarray(r.gravity_torques(q, terrain.g), dtype=float)
        for i in range(len(stance)):
            tau = tau - jac[i].T @ f[i]
        out.append(ForceSample(k, tuple((lb, tuple(float(x) for x in f[i])) for i, lb in enumerate(stance.limbs)),
                               tuple(float(x) for x in tau), min(UNBOUNDED_MARGIN, float(region.margin(com)))))
    return out


def assemble_plan(search: StanceGraphSearch, chain: list[Any], paths: list[list[np.ndarray]],
               query: dict[str, Any]) -> Plan:
    """The :class:`Plan` of a found climb.

    Args:
        search: the :class:`~climb_ompl.climb.search.StanceGraphSearch` that found it (robot, terrain, settings,
            seed, counters).
        chain: its nodes, start first.
        paths: the path into each node after the first.
        query: the plan file's ``query`` (start stance and configuration, goal).
    """
    from climb_ompl._version import __version__

    r, terrain, s = search.robot, search.terrain, search.settings
    steps = []
    for i, (u, v, path) in enumerate(zip(chain[:-1], chain[1:], paths, strict=True)):
        action, limb, hold = v.action
        wps = [np.asarray(x, dtype=float) for x in path]
        if not np.array_equal(wps[-1], v.q):
            wps.append(v.q)
        region = search.feas.region(u.stance) if r.equilibrium else None
        forces = force_samples(r, terrain, u.stance, wps, s.force_every, region)
        margin = min((f.margin for f in forces), default=0.0)
        steps.append(Step(i, tuple(u.stance.pairs), action, limb, hold,
                          tuple(tuple(float(x) for x in w) for w in wps), tuple(waypoint_times(r, wps)),
                          tuple(forces), float(margin)))
    st = search.summary()
    totals = {"steps": len(steps), "execution_s": float(sum(x.duration for x in steps)),
              "waypoints": int(sum(len(x.waypoints) for x in steps)),
              "grabs": sum(1 for x in steps if x.action == "grab"),
              "releases": sum(1 for x in steps if x.action == "release"),
              **{k: st[k] for k in ("onestep_calls", "transition_calls", "path_calls", "path_timeouts", "path_retries",
                                    "stances_explored", "candidates", "path_failures", "rejections", "shortcut_steps")},
              "min_margin": min((x.margin for x in steps), default=0.0), "reach": search.reach}
    plan = Plan(
        robot=robot_record(r),
        terrain={"name": terrain.name, "data": terrain.to_dict(), "sha256": terrain.content_hash()},
        query=query, seed=search.seed, steps=tuple(steps), settings=s.to_dict(), totals=totals,
        versions=library_versions(), timings=search.timings(), climb_ompl_version=__version__)
    return time_plan(plan, robot=r)[0]


__all__ = ["assemble_plan", "waypoint_times", "force_samples"]
