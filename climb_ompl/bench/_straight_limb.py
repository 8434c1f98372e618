"""Straight-limb sampling of Bretl et al. (2004), sec. 3, measured (``climb-ompl bench papers``, key ``straight_limb``).

The paper's two heuristics: straight-limb configurations "initially sampled explicitly" (the sampler's initial phase,
``straight_phase``) and connections "only [between] pairs of configurations with identical elbow-bends" (``same_bend``,
:class:`climb_ompl.manifold.bends.SameBendCheck`).  :func:`onestep` plans the same LEMUR one-step queries
(:func:`climb_ompl.bench._runs.make_queries`) without and with them, planner only, in one run; :func:`climb` plans
LEMUR's climb with the default settings and with them (the direct local path obeys the rule too).  Times are CPU
times of this process (``time.process_time``).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

#: The one-step planner of the measurement: ``climb-ompl bench onestep``'s (a lazy PRM, as Bretl et al. (2004) used,
#: on the projected space with the papers' samplers).
ONESTEP = {"planner": "LazyPRM", "space": "projected", "sampler": "joint-by-joint+straight-elbow+free-limb+lift"}


def _variants() -> dict[str, dict[str, Any]]:
    from climb_ompl.manifold.samplers import STRAIGHT_PHASE

    both = {"straight_phase": STRAIGHT_PHASE, "same_bend": True}
    return {"off": {}, "phase": {"straight_phase": STRAIGHT_PHASE}, "same_bend": {"same_bend": True}, "both": both,
            # every custom draw with random elbow bends (no draws about the query's segment, ``local_fraction``)
            "off_global": {"local_fraction": 0.0}, "both_global": {**both, "local_fraction": 0.0}}


def bend_changes(robot: Any, stance: Any, path: list[np.ndarray]) -> int:
    """How many times a contact limb's elbow changes bend along ``path``: per limb, the changes of sign in the
    sequence of its bends with the straight waypoints left out (:func:`climb_ompl.manifold.bends.bend_signature`),
    summed over the limbs.  0 for a path that keeps every bend (a straight limb counting as either)."""
    from climb_ompl.manifold.bends import bend_signature

    sig = [bend_signature(robot, stance, q) for q in path]
    n = 0
    for limb in (sig[0] if sig else {}):
        seq = [x[limb] for x in sig if x[limb]]
        n += sum(a != b for a, b in zip(seq[:-1], seq[1:], strict=False))
    return n


def onestep(robot: str = "lemur", terrain: str = "demo-wall", queries: int = 20, seed: int = 0,
            cpu_limit: float = 10.0) -> dict[str, Any]:
    """The same one-step queries planned with each variant (off, initial phase, same-bend rule, both; off and both again
    with every custom draw's elbow bends random, ``local_fraction = 0``): per variant the solved count, the median CPU
    time (an unsolved query counted at ``cpu_limit``, s), the bend changes along the solved paths
    (:func:`bend_changes`), the states the rule rejected; how many queries' start and goal share every bend."""
    from climb_ompl.bench._common import ONESTEP_OPTIONS
    from climb_ompl.bench._runs import make_queries
    from climb_ompl.climb.multistep import load_terrain
    from climb_ompl.climb.onestep import find_path
    from climb_ompl.manifold.bends import SameBendCheck
    from climb_ompl.manifold.stance import Stance
    from climb_ompl.model.robot import RobotModel

    rob, ter = RobotModel.load(robot), load_terrain(terrain)
    qs = [(Stance(d["stance"]), np.asarray(d["q_start"], float), np.asarray(d["q_goal"], float))
          for d in make_queries(robot, terrain, queries, seed)]
    out: dict[str, Any] = {"robot": rob.name, "terrain": ter.name, "queries": len(qs), "cpu_limit_s": cpu_limit,
                           **ONESTEP, "shared_bends": sum(not SameBendCheck(rob, s, a, b).free for s, a, b in qs)}
    for name, kw in _variants().items():
        times, ok, flips, samples, rejected = [], [], 0, 0, 0
        for i, (s, a, b) in enumerate(qs):
            t = time.process_time()
            res = find_path(rob, ter, s, a, b, seed=seed + i, **{**ONESTEP_OPTIONS, **ONESTEP, "direct": False,
                                                                  "time_limit": 10 * cpu_limit, "cpu_limit": cpu_limit,
                                                                  **kw})
            times.append(time.process_time() - t)
            ok.append(res.found)
            flips += bend_changes(rob, s, res.path) if res.found else 0
            samples += res.stats.get("samples") or 0
            rejected += res.stats["rejections"].get("bend", 0)
        capped = [t if k else cpu_limit for t, k in zip(times, ok, strict=False)]
        out[name] = {**kw, "solved": int(sum(ok)), "median_cpu_s": float(np.median(capped)),
                     "mean_solved_cpu_s": float(np.mean([t for t, k in zip(times, ok, strict=False) if k]))
                     if any(ok) else None, "bend_changes": flips, "samples": samples,
                     "bend_rejected": rejected, "cpu_s": times, "found": ok}
    return out


def climb(robot: str = "lemur", terrain: str = "demo-wall", height: float = 2.0, seed: int = 0,
          time_limit: float = 600.0) -> dict[str, Any]:
    """LEMUR's ``height`` metre climb (the guided search) with the default settings, with the same-bend rule, and with
    both heuristics (the initial phase needs the ``projected`` space: ``space = projected``, its sampler uniform
    after the phase; and that space alone, to tell the two apart), as ``climb-ompl bench climb`` plans it: found,
    verified, steps, CPU time (s), one-step calls."""
    from climb_ompl.climb.multistep import load_terrain, plan_climb
    from climb_ompl.climb.start import find_start
    from climb_ompl.manifold.samplers import STRAIGHT_PHASE
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.verification import verify

    rob, ter = RobotModel.load(robot), load_terrain(terrain)
    start = find_start(rob, ter, seed=seed)
    z0 = max(ter.height(h) for h in start.stance.values())
    variants = {"default": {}, "same_bend": {"same_bend": True}, "projected": {"space": "projected"},
                "projected_both": {"space": "projected", "straight_phase": STRAIGHT_PHASE, "same_bend": True}}
    out: dict[str, Any] = {"robot": rob.name, "terrain": ter.name, "height_m": height, "seed": seed}
    for name, kw in variants.items():
        t = time.process_time()
        res = plan_climb(rob, ter, start.stance, z0 + height, q_start=start.q, seed=seed,
                         **{**kw, "time_limit": time_limit})
        cpu, st = time.process_time() - t, res.stats
        out[name] = {**kw, "found": res.found, "verified": bool(res.found and verify(res.plan).ok),
                     "steps": st.get("steps"), "cpu_s": cpu, "onestep_calls": st.get("onestep_calls"),
                     "path_calls": st.get("path_calls"), "direct_found": st.get("direct_found"),
                     "bend_rejected": st.get("rejections", {}).get("bend", 0)}
    return out


__all__ = ["ONESTEP", "bend_changes", "climb", "onestep"]
