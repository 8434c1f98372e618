"""The papers' numbers that no other benchmark measures (``docs/papers.md``, notebook ``04_papers``).

* :func:`sampling_gain`: Bretl (2006), sec. 4.3: "less than 5 % of sampled configurations satisfying the
  kinematic constraint also satisfy joint limits"; joint-by-joint sampling "often increases the ratio of
  feasible samples to over 75 %".  Uniform samples projected onto the stance manifold vs. the
  ``joint-by-joint`` sampler of :mod:`climb_ompl.samplers` (one closure try per draw), on LEMUR stances.
* :func:`stance_count`: Bretl et al. (2004): "over 20000 feasible stances for LEMUR IIB" on their 2 m wall.
  A Monte-Carlo estimate on a 2 m band of a wall: ordered hold tuples (one hold per limb) drawn uniformly,
  kept by the planner's pair-reach prefilter, then tested by FIND-TRANSITION on the stance alone
  (:func:`climb_ompl.multistep.start_configuration`: closed chains, joint limits, equilibrium, collision).
* :func:`onestep_times`: Bretl et al. (2004), Fig. 6 and the ``T_max`` discussion: min / max / mean /
  median one-step time, the share of moves quicker than the mean, how many are solved within 2 s and 20 s.
* :func:`steps_to_reach_limit`: Bretl (2006), sec. 5.3: "4-12 steps for the robot even to climb to the limit
  of its reach", counted on a plan.
* :func:`treebot_fig13_factors`: Lam et al. (TreeBot), Fig. 13: proposed vs. simple motion on generated trees
  as the rings get denser, with the paper's algebraic arc fit (Eq. 11-17) or the geometric one, and on the DP
  path smoothed by a moving average.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np


def sampling_gain(robot: Any = "lemur", terrain: Any = "demo-wall", n: int = 300, seed: int = 0) -> dict[str, Any]:
    """Feasible share of uniform+projection samples vs. joint-by-joint samples on the default start stance
    (4 holds) and on it without its first limb (3 holds)."""
    import time

    from ..multistep import _load_robot, _load_terrain, default_start
    from ..samplers import make_core
    from ..stance import EquilibriumCheck, JointLimitsCheck, Stance, StanceConstraint, support_region

    rob, ter = _load_robot(robot), _load_terrain(terrain)
    start, _ = default_start(rob, ter, seed=seed)
    out: dict[str, Any] = {"robot": rob.name, "terrain": ter.name, "draws": n, "stances": []}
    limits = JointLimitsCheck(rob)
    for stance in (Stance(start), Stance(start).without(sorted(start)[0])):
        con = StanceConstraint(rob, ter, stance)
        eq = EquilibriumCheck(rob, support_region(rob, ter, stance))
        row: dict[str, Any] = {"stance": str(stance)}
        core = make_core(rob, ter, stance, con, "uniform", seed=seed)
        t0, projected, in_limits, feasible = time.perf_counter(), 0, 0, 0
        for _ in range(n):
            q = con.project_q(core.uniform())
            if q is None:
                continue
            projected += 1
            if limits(q):
                in_limits += 1
                feasible += bool(eq(q))
        row["uniform"] = {"projected": projected, "in_limits": in_limits, "feasible": feasible,
                          "share_in_limits": in_limits / max(projected, 1),
                          "ms_per_draw": 1e3 * (time.perf_counter() - t0) / n}
        core = make_core(rob, ter, stance, con, "joint-by-joint", seed=seed, uniform_fraction=0.0)
        t0, closed, feasible = time.perf_counter(), 0, 0
        for _ in range(n):
            q = core.draw_closed()
            if q is not None and limits(q) and con.satisfied(q):
                closed += 1
                feasible += bool(eq(q))
        row["joint_by_joint"] = {"in_limits": closed, "feasible": feasible, "share_in_limits": closed / n,
                                 "ms_per_draw": 1e3 * (time.perf_counter() - t0) / n}
        out["stances"].append(row)
    return out


def stance_count(robot: Any = "lemur", terrain: Any = "demo-wall", band: float = 2.0, samples: int = 60,
                 attempts: int = 60, seed: int = 0, sizes: tuple[int, ...] = (4, 3)) -> dict[str, Any]:
    """Estimated number of feasible stances with holds in the lowest ``band`` metres of ``terrain``.

    For each stance size k, ordered tuples of k distinct holds are drawn uniformly for k limbs chosen in
    every way (``C(limbs, k)`` limb sets); the share passing the pair-reach prefilter is estimated from
    the draws, and ``samples`` of the passing stances are tested for a feasible configuration.  The count is
    ``(tuples) x (prefilter share) x (feasible share)``, with a 95 % Wilson interval on the last factor.
    """
    import itertools

    from ..multistep import ClimbPlanner, Goal, _load_robot, _load_terrain, start_configuration

    rob, ter = _load_robot(robot), _load_terrain(terrain)
    reach = ClimbPlanner(rob, ter, Goal("height", height=0.0)).pair_reach
    P = ter.positions
    idx = np.flatnonzero(P[:, 2] <= P[:, 2].min() + band)
    rng = np.random.default_rng(seed)
    limbs = [lb.name for lb in rob.limbs]
    out: dict[str, Any] = {"robot": rob.name, "terrain": ter.name, "band_m": band, "holds": int(len(idx)),
                           "by_size": {}}
    total = 0.0
    for k in sizes:
        sets = list(itertools.combinations(limbs, k))
        tuples = len(sets) * math.perm(len(idx), k)
        drawn = passed = 0
        chosen: list[dict[str, str]] = []
        while len(chosen) < samples and drawn < 200000:
            drawn += 1
            ls = sets[int(rng.integers(len(sets)))]
            hs = rng.choice(idx, size=k, replace=False)
            if all(np.linalg.norm(P[hs[a]] - P[hs[b]]) <= reach[(ls[a], ls[b])]
                   for a in range(k) for b in range(a + 1, k)):
                passed += 1
                chosen.append({lb: ter.holds[int(h)].id for lb, h in zip(ls, hs, strict=True)})
        feasible = sum(start_configuration(rob, ter, s, seed=seed, attempts=attempts) is not None for s in chosen)
        m = max(len(chosen), 1)
        lo, hi = _wilson(feasible, m)
        est = tuples * passed / max(drawn, 1)
        out["by_size"][k] = {"tuples": tuples, "drawn": drawn, "prefilter_share": passed / max(drawn, 1),
                             "tested": len(chosen), "feasible": feasible, "estimate": est * feasible / m,
                             "estimate_95": [est * lo, est * hi]}
        total += est * feasible / m
    out["estimate"] = total
    return out


def _wilson(k: int, n: int, z: float = 1.96) -> tuple[float, float]:
    """95 % Wilson score interval of a binomial share ``k / n``."""
    p = k / n
    d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d
    h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return max(0.0, c - h), min(1.0, c + h)


def onestep_times(times: Any, solved: Any) -> dict[str, Any]:
    """Fig. 6 of Bretl et al. (2004) and its ``T_max`` discussion, from per-query times and outcomes."""
    t, ok = np.asarray(times, float), np.asarray(solved, bool)
    s = t[ok]
    if not len(s):
        return {"solved": 0, "queries": int(len(t))}
    return {"queries": int(len(t)), "solved": int(ok.sum()), "min_s": float(s.min()), "max_s": float(s.max()),
            "mean_s": float(s.mean()), "median_s": float(np.median(s)),
            "share_below_mean": float(np.mean(s < s.mean())),
            "solved_within_2s": int(np.sum(s <= 2.0)), "solved_within_20s": int(np.sum(s <= 20.0)),
            "share_above_2s": float(np.mean(s > 2.0))}


def steps_to_reach_limit(plan: Any, robot: Any, terrain: Any) -> dict[str, Any]:
    """Steps of a climb ``plan`` until a hand first grabs a hold at or above the start's highest hold plus the
    robot's largest limb reach (the highest a hand could touch from the start stance)."""
    z_top = max(float(terrain.hold(h).p[2]) for _, h in plan.start_stance)
    reach = max(float(lb.reach) for lb in robot.limbs)
    steps = next((i for i, s in enumerate(plan.steps, 1)
                  if s.action == "grab" and terrain.hold(s.hold).p[2] >= z_top + reach), None)
    return {"steps": steps, "threshold_m": z_top + reach, "reach_m": reach, "plan_steps": len(plan.steps)}


def _moving_average(P: np.ndarray, k: int) -> np.ndarray:
    """Each point replaced by the mean of its ``2k + 1`` neighbours along the path (ends truncated)."""
    if k <= 0:
        return P
    return np.array([P[max(0, i - k):i + k + 1].mean(axis=0) for i in range(len(P))])


def treebot_fig13_factors(trees: int = 10, points: tuple[int, ...] = (16, 32, 64), smooth: tuple[int, ...] = (0, 2),
                          fits: tuple[str, ...] = ("geometric", "algebraic")) -> list[dict[str, Any]]:
    """Mean following and segment errors (mm) of both methods on ``trees`` generated trees (the benchmark's:
    seeds 1000.., 3 branches, curvature 1.0, 8 obstacle patches), per ring density, arc fit and smoothing."""
    from ..treebot import generate_tree
    from ..treebot.compare import compare_path, obstacle_points
    from ..treebot.dp import plan_path

    paths: dict[int, list[tuple[Any, np.ndarray, np.ndarray, np.ndarray]]] = {}
    for n in points:
        paths[n] = []
        for s in range(trees):
            g = generate_tree(1000 + s, n_branches=3, curvature=1.0, obstacle_patches=8, points_per_ring=n)
            target = g.branches[-1].name
            res = plan_path(g, target)
            if res.found:
                paths[n].append((g, np.array([p.position for p in res.path]),
                                 np.array([p.normal for p in res.path]), obstacle_points(g, target)))
    rows = []
    for n in points:
        for fit in fits:
            for k in smooth:
                acc: dict[str, list[tuple[float, float]]] = {"proposed": [], "simple": []}
                for g, P, N, obs in paths[n]:
                    for m, v in compare_path(_moving_average(P, k), N, g.robot, obs, arc_fit=fit).items():
                        acc[m].append((v.mean_error, v.segment_mean_error))
                row: dict[str, Any] = {"points": n, "fit": fit, "smooth": k, "trees": len(paths[n])}
                for m, v in acc.items():
                    a = np.array(v) * 1e3
                    row[m] = {"following_mm": float(a[:, 0].mean()), "segment_mm": float(a[:, 1].mean())}
                rows.append(row)
    return rows
