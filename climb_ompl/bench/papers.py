"""The papers' numbers that no other benchmark measures (``docs/papers.md``, notebook ``04_papers``).

* :func:`sampling_gain`: Bretl (2006), sec. 4.3: "less than 5 % of sampled configurations satisfying the
  kinematic constraint also satisfy joint limits"; joint-by-joint sampling "often increases the ratio of
  feasible samples to over 75 %".  Uniform samples projected onto the stance manifold vs. the
  ``joint-by-joint`` sampler of :mod:`climb_ompl.manifold.samplers` (one closure try per draw), on LEMUR stances.
* :func:`stance_count`: Bretl et al. (2004): "over 20000 feasible stances for LEMUR IIB" on their 2 m wall.
  An importance-sampling estimate on a 2 m band of a wall, each sampled stance tested by FIND-TRANSITION on
  the stance alone (:func:`climb_ompl.climb.start.start_configuration`).
* :func:`onestep_times`: Bretl et al. (2004), Fig. 6 and the ``T_max`` discussion: min / max / mean /
  median one-step time, the share of moves quicker than the mean, how many are solved within 2 s and 20 s.
* :func:`steps_to_reach_limit`: Bretl (2006), sec. 5.3: "4-12 steps for the robot even to climb to the limit
  of its reach", counted on a plan.
* :func:`treebot_fig13_factors`: Lam et al. (TreeBot), Fig. 13: proposed vs. simple motion on generated trees
  as the rings get denser, with the paper's algebraic arc fit (Eq. 11-17) or the geometric one, and on the DP
  path smoothed by a moving average; :func:`treebot_fig13_three_branch` the same on the bundled tree.
* ``straight_limb``: Bretl et al. (2004), sec. 3, straight-limb samples first and connections between equal elbow
  bends, on one-step queries and in a climb (:mod:`climb_ompl.bench._straight_limb`).
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np
import typer

from climb_ompl.climb.goal import robot_reach
from climb_ompl.settings import SEED_MAX


def sampling_gain(robot: Any = "lemur", terrain: Any = "demo-wall", n: int = 300, seed: int = 0) -> dict[str, Any]:
    """Feasible share of uniform+projection samples vs. joint-by-joint samples on the default start stance
    (4 holds) and on it without its first limb (3 holds)."""
    import time

    from climb_ompl.climb.multistep import default_start, load_robot, load_terrain
    from climb_ompl.manifold.samplers import make_core
    from climb_ompl.manifold.stance import (
        EquilibriumCheck,
        JointLimitsCheck,
        Stance,
        StanceConstraint,
        stance_region,
    )

    rob, ter = load_robot(robot), load_terrain(terrain)
    start, _ = default_start(rob, ter, seed=seed)
    out: dict[str, Any] = {"robot": rob.name, "terrain": ter.name, "draws": n, "stances": []}
    limits = JointLimitsCheck(rob)
    for stance in (Stance(start), Stance(start).without(sorted(start)[0])):
        con = StanceConstraint(rob, ter, stance)
        eq = EquilibriumCheck(rob, stance_region(rob, ter, stance))
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


def climb_stances(queries: str = "lemur-demo-wall", limit: int | None = None) -> list[dict[str, str]]:
    """The distinct stances of a bundled query set (a climb's one-step queries): each query's stance and, for a
    grab, the stance after it; first ``limit`` of them."""
    from climb_ompl.bench._query_set import load_set

    out: list[dict[str, str]] = []
    for q in load_set(queries)["queries"]:
        for st in (q["stance"], {**q["stance"], q["moving"]: q["to_hold"]} if q["kind"] == "grab" else None):
            if st is not None and st not in out:
                out.append(dict(st))
    return out[:limit]


def _jbj_failure(core: Any, rob: Any, q: np.ndarray) -> str:
    """Why the joint-by-joint closure of a base pose ``q`` fails (``"closed"`` when it does not): the reach
    prefilter, a hold out of the limb's reach at that base pose even without joint limits, or the joint limit
    (shoulder, elbow, wrist, several) without which the first failing limb would close."""
    if not core._reachable(q):
        return "reach prefilter"
    limb = next((lb for lb in core.kernel.order if core._ik(lb, q, core.holds[lb]) is None), None)
    if limb is None:
        return "closed"
    idx = list(next(lb for lb in rob.limbs if lb.name == limb).joint_indices)
    lo0, hi0 = rob.lower.copy(), rob.upper.copy()
    try:
        for name, widen in (("shoulder", idx[:1]), ("elbow", idx[1:2]), ("wrist", idx[2:3]), ("several", idx)):
            rob.lower[widen], rob.upper[widen] = -math.pi, math.pi
            found = bool(rob.limb_ik(limb, q, core.holds[limb]))
            rob.lower[:], rob.upper[:] = lo0, hi0
            if found:
                return f"{name} limit"
    finally:
        rob.lower[:], rob.upper[:] = lo0, hi0
    return "out of reach"


def sampling_gain_climb(robot: Any = "lemur", terrain: Any = "demo-wall", queries: str = "lemur-demo-wall",
                        n: int = 60, stances: int | None = None, base_rows: int = 600, seed: int = 0
                        ) -> dict[str, Any]:
    """Bretl (2006), sec. 4.3 on the stances of a climb (the query set's): per stance size, the share of
    uniform samples projected onto the stance manifold that are within joint limits, the share of
    joint-by-joint draws (one closure try) closed within limits, why the others fail, and the same draws with
    the base restricted to poses where every contact limb closes within limits (the paper enforces limits
    joint by joint, the base included: our sampler draws its base from a reach test that ignores them).

    Limbs close independently given the base, so the restricted base set is the sampler's own base poses
    (``base_rows`` of them) kept when one analytic-IK closure within limits succeeds."""
    from collections import Counter

    from climb_ompl.climb.multistep import load_robot, load_terrain
    from climb_ompl.manifold.samplers import make_core
    from climb_ompl.manifold.stance import JointLimitsCheck, Stance, StanceConstraint

    rob, ter = load_robot(robot), load_terrain(terrain)
    limits = JointLimitsCheck(rob)
    acc: dict[int, dict[str, Any]] = {}
    for i, st in enumerate(climb_stances(queries, stances)):
        stance = Stance(st)
        con = StanceConstraint(rob, ter, stance)
        a = acc.setdefault(len(st), {"stances": 0, "projected": 0, "uniform_in_limits": 0, "draws": 0,
                                     "jbj_closed": 0, "causes": Counter(), "base_rows_kept": [],
                                     "exact_base_closed": 0})
        a["stances"] += 1
        core = make_core(rob, ter, stance, con, "uniform", seed=seed + i)
        for _ in range(n):
            q = con.project_q(core.uniform())
            if q is not None:
                a["projected"] += 1
                a["uniform_in_limits"] += bool(limits(q))
        core = make_core(rob, ter, stance, con, "joint-by-joint", seed=seed + i, uniform_fraction=0.0)
        a["draws"] += n
        for _ in range(n):  # the sampler's own draw, taken apart to see where it fails
            cause = _jbj_failure(core, rob, core._place_base(core.rng.uniform(core.jlo, core.jhi), core._radius))
            a["causes"][cause] += 1
            a["jbj_closed"] += cause == "closed"
        rows = core._base_guess
        if rows is None:
            continue
        rows = rows[core.rng.choice(len(rows), min(base_rows, len(rows)), replace=False)]
        keep = []
        for row in rows:
            q = core.rng.uniform(core.jlo, core.jhi)
            q[core.base_idx] = row
            c = core.close_chain(q)
            if c is not None and limits(c):
                keep.append(row)
        a["base_rows_kept"].append(len(keep) / len(rows))
        if keep:
            core._base_guess = np.array(keep)
            for _ in range(n):
                q = core.draw_closed()
                a["exact_base_closed"] += bool(q is not None and limits(q) and con.satisfied(q))
    out: dict[str, Any] = {"robot": rob.name, "terrain": ter.name, "queries": queries, "draws_per_stance": n,
                           "by_size": {}}
    for k, a in sorted(acc.items(), reverse=True):
        out["by_size"][k] = {"stances": a["stances"], "uniform_projected": a["projected"],
                             "uniform_in_limits": a["uniform_in_limits"],
                             "uniform_share": a["uniform_in_limits"] / max(a["projected"], 1),
                             "jbj_draws": a["draws"], "jbj_closed": a["jbj_closed"],
                             "jbj_share": a["jbj_closed"] / max(a["draws"], 1),
                             "jbj_failures": {c: v / a["draws"] for c, v in a["causes"].items() if c != "closed"},
                             "base_rows_kept": float(np.mean(a["base_rows_kept"])) if a["base_rows_kept"] else None,
                             "exact_base_share": a["exact_base_closed"] / max(a["draws"], 1)}
    return out


def stance_count(robot: Any = "lemur", terrain: Any = "demo-wall", band: float = 2.0, samples: int = 60,
                 attempts: int = 60, seed: int = 0, sizes: tuple[int, ...] = (4, 3), grid: float = 0.05,
                 angles: int = 24) -> dict[str, Any]:
    """Estimated number of feasible stances with holds in the lowest ``band`` metres of ``terrain``.

    Importance sampling over the stances that pass a reach test: a base pose ``g`` (x, z, chassis angle on a
    grid) is drawn uniformly, then for each limb of a uniformly drawn set of ``k`` limbs a hold uniformly
    among those within the limb's reach of its first joint at ``g``.  A drawn stance ``s`` has probability
    ``p(s) = mean_g prod_l [h_l reachable at g] / |reachable_l(g)|`` (over the poses where every limb of the
    set reaches some hold, divided by the number of limb sets), computed exactly; the count of feasible
    stances is estimated by ``mean(f(s) / p(s))``, ``f`` being FIND-TRANSITION on the stance alone
    (:func:`climb_ompl.climb.start.start_configuration` from the drawn base pose: closed chains, joint
    limits, equilibrium, collision).  A stance FIND-TRANSITION misses within ``attempts`` counts as
    infeasible, so the estimate is a lower bound up to sampling error (``stderr``).  ``reach_stances``
    estimates, the same way, how many stances pass the reach test alone.
    """
    import itertools

    import pinocchio as pin

    from climb_ompl.climb.multistep import load_robot, load_terrain
    from climb_ompl.climb.start import start_configuration

    rob, ter = load_robot(robot), load_terrain(terrain)
    P = ter.positions
    idx = np.flatnonzero(P[:, 2] <= P[:, 2].min() + band)
    H = P[idx]
    bx, bz, bt = rob.base_indices[:3]
    offsets = []  # first-joint positions relative to the base, per chassis angle: (angles, limbs, 3)
    thetas = np.linspace(-math.pi, math.pi, angles, endpoint=False)
    for th in thetas:
        q = np.asarray(rob.nominal_q, float).copy()
        q[bx], q[bz], q[bt] = 0.0, 0.0, th
        pin.forwardKinematics(rob.model, rob.data, q)
        offsets.append([np.asarray(rob.data.oMi[lb.joint_ids[0]].translation, float) for lb in rob.limbs])
    off = np.array(offsets)
    xs = np.arange(H[:, 0].min() - 0.4, H[:, 0].max() + 0.4 + 1e-9, grid)
    zs = np.arange(H[:, 2].min() - 0.4, H[:, 2].max() + 0.4 + 1e-9, grid)
    base = np.array([[x, 0.0, z] for x in xs for z in zs])
    reach = np.array([float(lb.reach) for lb in rob.limbs])
    # M[l][g, h]: hold h within reach of limb l's first joint at pose g = (angle, x, z)
    M = [np.concatenate([np.linalg.norm((base[:, None, :] + off[a, li])[:, None, :] - H[None, None, :, :], axis=-1)
                         [:, 0, :] <= reach[li] for a in range(angles)]) for li in range(len(rob.limbs))]
    cnt = [m.sum(axis=1) for m in M]
    rng = np.random.default_rng(seed)
    limbs = [lb.name for lb in rob.limbs]
    out: dict[str, Any] = {"robot": rob.name, "terrain": ter.name, "band_m": band, "holds": int(len(idx)),
                           "poses": int(len(M[0])), "by_size": {}}
    total = 0.0
    for k in sizes:
        sets = list(itertools.combinations(range(len(limbs)), k))
        valid = {st: np.flatnonzero(np.all([cnt[li] > 0 for li in st], axis=0)) for st in sets}
        sets = [st for st in sets if len(valid[st])]
        w, f = [], []
        for _ in range(samples):
            st = sets[int(rng.integers(len(sets)))]
            g = int(rng.choice(valid[st]))
            hs = [int(rng.choice(np.flatnonzero(M[li][g]))) for li in st]
            if len(set(hs)) < k:
                w.append(0.0)
                f.append(False)
                continue
            G = valid[st]
            prob = np.ones(len(G))
            for li, h in zip(st, hs, strict=True):
                prob *= M[li][G, h] / cnt[li][G]
            w.append(1.0 / (len(sets) * float(prob.mean())))
            stance = {limbs[li]: ter.holds[int(idx[h])].id for li, h in zip(st, hs, strict=True)}
            a, xz = divmod(g, len(base))
            near = np.asarray(rob.nominal_q, float).copy()
            near[bx], near[bz], near[bt] = base[xz, 0], base[xz, 2], thetas[a]
            f.append(start_configuration(rob, ter, stance, seed=seed, attempts=attempts, near=near,
                                         closest=False) is not None)
        wa, fa = np.array(w), np.array(f, float)
        est = float(np.mean(wa * fa))
        out["by_size"][k] = {"samples": samples, "feasible": int(fa.sum()), "estimate": est,
                             "stderr": float(np.std(wa * fa, ddof=1) / math.sqrt(samples)),
                             "reach_stances": float(np.mean(wa))}
        total += est
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
    """Steps of a climb ``plan`` to "the limit of its reach" (Bretl 2006, sec. 5.3), three readings:

    * ``steps``: until a hand first grabs a hold at or above the start's highest hold plus the robot's largest
      limb reach (the highest a hand could touch from the start stance);
    * ``steps_beyond_start_reach``: until a hand first grabs a hold no limb could reach from its shoulder
      (first joint) in the start configuration;
    * ``steps_rise_one_reach``: until the mean height of the holds held has risen by one limb reach.
    """
    import pinocchio as pin

    z_top = max(float(terrain.hold(h).p[2]) for _, h in plan.start_stance)
    reach = robot_reach(robot)
    grabs = [(i, s) for i, s in enumerate(plan.steps, 1) if s.action == "grab"]
    steps = next((i for i, s in grabs if terrain.hold(s.hold).p[2] >= z_top + reach), None)
    pin.forwardKinematics(robot.model, robot.data, np.asarray(plan.steps[0].waypoints[0], float))
    shoulders = [(np.asarray(robot.data.oMi[lb.joint_ids[0]].translation, float), float(lb.reach))
                 for lb in robot.limbs]
    beyond = next((i for i, s in grabs if all(np.linalg.norm(np.asarray(terrain.hold(s.hold).p, float) - c) > r
                                              for c, r in shoulders)), None)

    def mean_z(stance: Any) -> float:
        return float(np.mean([terrain.hold(h).p[2] for _, h in stance]))

    z0 = mean_z(plan.start_stance)
    rise = next((i for i, s in enumerate(plan.steps, 1) if mean_z(s.stance_after) - z0 >= reach), None)
    return {"steps": steps, "threshold_m": z_top + reach, "reach_m": reach, "plan_steps": len(plan.steps),
            "steps_beyond_start_reach": beyond, "steps_rise_one_reach": rise}


def _moving_average(P: np.ndarray, k: int) -> np.ndarray:
    """Each point replaced by the mean of its ``2k + 1`` neighbours along the path (ends truncated)."""
    if k <= 0:
        return P
    return np.array([P[max(0, i - k):i + k + 1].mean(axis=0) for i in range(len(P))])


def _fig13_path(tree: Any, target: str) -> tuple[Any, np.ndarray, np.ndarray, np.ndarray, Any] | None:
    """The DP path to ``target`` with its normals, the obstacle points and the bark of the branches it climbs."""
    from climb_ompl.treebot.bark import Bark
    from climb_ompl.treebot.compare import obstacle_points
    from climb_ompl.treebot.dp import plan_path

    res = plan_path(tree, target)
    if not res.found:
        return None
    bark = Bark(tree.branch(b) for b in dict.fromkeys(p.branch for p in res.path))  # as plans do
    return (tree, np.array([p.position for p in res.path]), np.array([p.normal for p in res.path]),
            obstacle_points(tree, target), bark)


def _fig13_rows(paths: dict[int, list[Any]], smooth: tuple[int, ...], fits: tuple[str, ...]) -> list[dict[str, Any]]:
    """Mean following and segment errors (mm) of both methods over ``paths`` (per points per ring)."""
    from climb_ompl.treebot.compare import compare_path

    rows = []
    for n, group in paths.items():
        for fit in fits:
            for k in smooth:
                acc: dict[str, list[tuple[float, float]]] = {"proposed": [], "simple": []}
                for g, P, N, obs, bark in group:
                    for m, v in compare_path(_moving_average(P, k), N, g.robot, obs, arc_fit=fit,
                                             bark=bark.nearest).items():
                        acc[m].append((v.mean_error, v.segment_mean_error))
                row: dict[str, Any] = {"points": n, "fit": fit, "smooth": k, "trees": len(group)}
                for m, v in acc.items():
                    a = np.array(v) * 1e3
                    row[m] = {"following_mm": float(a[:, 0].mean()), "segment_mm": float(a[:, 1].mean())}
                rows.append(row)
    return rows


def treebot_fig13_factors(trees: int = 10, points: tuple[int, ...] = (16, 32, 64), smooth: tuple[int, ...] = (0, 2),
                          fits: tuple[str, ...] = ("geometric", "algebraic")) -> list[dict[str, Any]]:
    """Mean following and segment errors (mm) of both methods on ``trees`` generated trees (the benchmark's:
    seeds 1000.., 3 branches, curvature 1.0, 8 obstacle patches), per ring density, arc fit and smoothing."""
    from climb_ompl.treebot import generate_tree

    paths: dict[int, list[Any]] = {}
    for n in points:
        found = (_fig13_path(g, g.branches[-1].name) for g in
                 (generate_tree(1000 + s, n_branches=3, curvature=1.0, obstacle_patches=8, points_per_ring=n)
                  for s in range(trees)))
        paths[n] = [f for f in found if f is not None]
    return _fig13_rows(paths, smooth, fits)


def treebot_fig13_three_branch(smooth: tuple[int, ...] = (0, 2),
                               fits: tuple[str, ...] = ("geometric", "algebraic")) -> list[dict[str, Any]]:
    """:func:`treebot_fig13_factors` on the bundled three-branch tree (target b2, 16 points per ring)."""
    from climb_ompl.treebot import Tree

    tree = Tree.load("three-branch")
    return _fig13_rows({tree.root.rings[0].n: [_fig13_path(tree, "b2")]}, smooth, fits)


def reach_and_holds(robot: Any = "lemur", terrain: Any = "demo-wall", band: float = 2.0) -> dict[str, Any]:
    """What sets a climb's step count besides the planner (Bretl 2006, sec. 5.3; Bretl et al. 2004, sec. 4): the
    robot's limb reach and wingspan (the largest distance between two hands, shoulders at the nominal posture, both
    limbs stretched), and the holds of the wall's lowest ``band`` metres: how many, how dense (per square metre of the
    band, across the holds' width), the median distance from a hold to its nearest neighbour and the mean number of
    other holds within one limb reach of a hold."""
    from climb_ompl.climb.multistep import load_robot, load_terrain
    from climb_ompl.model.reach import shoulders

    rob, ter = load_robot(robot), load_terrain(terrain)
    sh = shoulders(rob, np.asarray(rob.nominal_q, dtype=float))
    reach = {lb.name: float(lb.reach) for lb in rob.limbs}
    span = max(float(np.linalg.norm(sh[a] - sh[b])) + reach[a] + reach[b] for a in sh for b in sh if a < b)
    P = np.array([ter.hold(h).p for h in ter.hold_ids], dtype=float)
    P = P[P[:, 2] <= P[:, 2].min() + band]
    D = np.linalg.norm(P[:, None] - P[None], axis=2)
    np.fill_diagonal(D, np.inf)
    width = float(np.ptp(P[:, 0]))
    return {"robot": rob.name, "terrain": str(terrain), "limb_reach_m": max(reach.values()), "wingspan_m": span,
            "band_m": band, "holds": int(len(P)), "width_m": width, "holds_per_m2": len(P) / (width * band),
            "nearest_hold_m_median": float(np.median(D.min(axis=1))),
            "holds_within_reach_mean": float(np.mean((D <= max(reach.values())).sum(axis=1)))}


def steps_vs_spacing(spacings: tuple[float, ...] = (0.18, 0.26, 0.34), height: float = 2.0, seed: int = 0,
                     time_limit: float = 300.0) -> list[dict[str, Any]]:
    """LEMUR's ``height`` metre climb (the guided search, as :func:`climb_figures`) on walls of
    :func:`~climb_ompl.model.terrain.generate_wall` whose holds lie ``spacing`` metres apart (its default 0.18 m):
    how the step count grows as the holds thin out, towards the 80-88 steps of Bretl (2006), sec. 5.3 and Bretl et al.
    (2004), whose wall's holds are not given.  Per spacing: the holds per square metre, found, steps, grabs."""
    from climb_ompl.model.terrain import generate_wall

    out = []
    for sp in spacings:
        wall = generate_wall(seed, spacing=sp, height=height + 1.2, name=f"spacing-{sp:g}")
        P = np.array([wall.hold(h).p for h in wall.hold_ids], dtype=float)
        r = climb_figures(terrain=wall, height=height, seed=seed, time_limit=time_limit)
        out.append({"spacing_m": sp, "holds_per_m2": len(P) / float(np.ptp(P[:, 0]) * np.ptp(P[:, 2])),
                    "found": r["found"], "steps": r.get("steps"), "grabs": r.get("grabs"),
                    "rise_per_grab_m": r.get("rise_per_grab_m"), "total_s": r.get("total_s")})
    return out


def climb_figures(robot: Any = "lemur", terrain: Any = "demo-wall", height: float = 2.0, seed: int = 0,
                  time_limit: float = 600.0) -> dict[str, Any]:
    """A climb of ``height`` metres above the start (as ``climb-ompl bench climb``): its steps, the steps to the
    reach limit (Bretl 2006, sec. 5.3) and the step-motion planning times along it (Bretl et al. 2004, Fig. 6)."""
    from climb_ompl.climb.multistep import default_start, load_robot, load_terrain, plan_climb

    rob, ter = load_robot(robot), load_terrain(terrain)
    stance, q0 = default_start(rob, ter, seed=seed)
    z0 = float(np.mean([ter.hold(h).p[2] for h in stance.values()]))
    goal = z0 + 0.5 * robot_reach(rob) + height
    res = plan_climb(rob, ter, stance, goal, time_limit=time_limit, seed=seed, q_start=q0)
    out: dict[str, Any] = {"found": res.found, "reason": res.reason, "height_m": height}
    if res.found:
        plan = res.plan
        z1 = float(np.mean([ter.hold(h).p[2] for _, h in plan.steps[-1].stance_after]))
        step_s = plan.timings.get("step_s", [])
        grabs = sum(1 for s in plan.steps if s.action == "grab")
        out.update(steps=len(plan.steps), grabs=grabs, rise_per_grab_m=(z1 - z0) / max(1, grabs), rise_m=z1 - z0,
                   total_s=plan.timings.get("total_s"),
                   reach_limit=steps_to_reach_limit(plan, rob, ter),
                   step_motion_times=onestep_times(step_s, [True] * len(step_s)),
                   heights=[z0] + [float(np.mean([ter.hold(h).p[2] for _, h in s.stance_after])) for s in plan.steps])
    return out


def run(seed: int = 0, queries: int = 20, t_max: float = 20.0, stance_samples: int = 300, gain_draws: int = 300,
        climb_height: float = 2.0, climb_time_limit: float = 600.0, trees: int = 10) -> dict[str, Any]:
    """Every figure of this module at the given scale (defaults: the scale of ``docs/papers.md``)."""
    from climb_ompl.bench import _straight_limb
    from climb_ompl.bench.onestep import run as onestep_run

    t_runs = {}
    for direct in (False, True):
        r = onestep_run(queries=queries, seed=seed, time_limit=t_max, torque_compare=False, baseline=False,
                        direct=direct)
        main = r["runs"][r["sampler"]]
        t_runs["planner_only" if not direct else "with_local_plan"] = onestep_times(main["times_s"], main["solved"])
    return {"sampling_gain": sampling_gain(n=gain_draws, seed=seed),
            "sampling_gain_climb": sampling_gain_climb(seed=seed),
            "stance_count": stance_count(samples=stance_samples, seed=seed),
            "reach_and_holds": reach_and_holds(band=climb_height),
            "steps_vs_spacing": steps_vs_spacing(height=climb_height, seed=seed),
            "onestep_times": t_runs,
            "climb": climb_figures(height=climb_height, seed=seed, time_limit=climb_time_limit),
            "straight_limb": {"onestep": _straight_limb.onestep(queries=queries, seed=seed),
                              "climb": _straight_limb.climb(height=climb_height, seed=seed,
                                                            time_limit=climb_time_limit)},
            "treebot_fig13": treebot_fig13_factors(trees=trees),
            "treebot_fig13_three_branch": treebot_fig13_three_branch()}


def summary(result: dict[str, Any]) -> str:
    """One line: sampling shares, stance estimate, one-step mean, steps to the reach limit."""
    g = result["sampling_gain"]["stances"][0]
    o = result["onestep_times"]["planner_only"]
    c = result["climb"]
    lim = c.get("reach_limit", {}).get("steps")
    four = result.get("sampling_gain_climb", {}).get("by_size", {}).get(4)
    climb_gain = (f" (climb's 4-hold stances: {100 * four['uniform_share']:.1f}% vs {100 * four['jbj_share']:.0f}%, "
                  f"limit-exact base {100 * four['exact_base_share']:.0f}%)") if four else ""
    return (f"in limits: uniform {100 * g['uniform']['share_in_limits']:.0f}% vs joint-by-joint "
            f"{100 * g['joint_by_joint']['share_in_limits']:.0f}%{climb_gain}; feasible stances ~"
            f"{result['stance_count']['estimate']:.3g}; one-step (planner only) mean "
            f"{o.get('mean_s', float('nan')):.2f} s, "
            f"{o.get('solved_within_2s')}/{o.get('solved_within_20s')} within 2 s/20 s; climb "
            f"{c.get('steps')} steps, reach limit after {lim}")


def command(
    out: Path = typer.Option(None, "--out", help="Write the result JSON here."),
    seed: int = typer.Option(0, "--seed", min=0, max=SEED_MAX, help="Seed of every random choice."),
    queries: int = typer.Option(20, "--queries", help="One-step queries for the T_max figures."),
    stance_samples: int = typer.Option(300, "--stance-samples", help="Stances sampled per stance size."),
    climb_time_limit: float = typer.Option(600.0, "--climb-time-limit", help="Budget of the 2 m climb, s."),
) -> None:
    """The papers' numbers no other benchmark measures (docs/papers.md): sampling gain, stance count, T_max,
    steps to the reach limit, TreeBot Fig. 13 factors."""
    from climb_ompl._options import check_positive

    check_positive(climb_time_limit, "--climb-time-limit", "seconds")
    from climb_ompl.bench._common import execute

    execute("papers", {"seed": seed, "queries": queries, "stance_samples": stance_samples,
                       "climb_time_limit": climb_time_limit}, out)
