"""``climb-ompl bench treebot``: TreeBot's DP scaling, DP vs. brute force, proposed vs. simple (Lam et al.).

* DP time at several ring counts ``m`` (``n`` points per ring) and the slope of log(time) vs. log(m)
  (Lam et al. (TreeBot), section IV.A: O(m n^2), linear in the tree's height, so the slope should be near 1);
* the time of a brute-force shortest path (Dijkstra over the same graph, pure Python heap) over the DP's,
  with a check that both find the same cost;
* proposed vs. simple motion planning (Fig. 13): following, swept and segment errors and motions that come
  near an obstacle (:mod:`climb_ompl.treebot.compare`), on the bundled three-branch tree (target b2, as in
  the paper), on generated trees, and on smooth synthetic paths on a plane (constant curvature, S-curve),
  which separate the method from the DP paths' kinks.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer


def _dijkstra(rings, up, a0, reach) -> float:
    import heapq
    import math

    dist: dict = {}
    heap = [(0.0, 0, j) for j in range(rings[0].n) if not rings[0].obstacles[j]]
    heapq.heapify(heap)
    last = len(rings) - 1
    while heap:
        c, i, j = heapq.heappop(heap)
        if (i, j) in dist:
            continue
        dist[(i, j)] = c
        if i == last:
            return c
        a, b = rings[i], rings[i + 1]
        for k in range(b.n):
            if b.obstacles[k] or (i + 1, k) in dist:
                continue
            d = math.dist(a.points[j], b.points[k])
            if d <= reach:
                heapq.heappush(heap, (c + d - a0 * (float(b.normals[k] @ up) - 1.0), i + 1, k))
    return math.inf


def planar_path(curvature, length: float = 2.0, ds: float = 0.05) -> tuple:
    """A smooth path on the plane ``x = 0`` (normal ``+x``) starting upwards, with curvature ``curvature(s)``
    (1/m, a function of arc length), sampled every ``ds`` metres like the DP path's rings."""
    import numpy as np

    s = np.arange(0.0, length + 1e-9, ds)
    th = np.concatenate([[0.0], np.cumsum(curvature(s[:-1] + ds / 2) * ds)])  # heading at each sample
    y = np.concatenate([[0.0], np.cumsum(np.sin(th[:-1]) * ds)])
    z = np.concatenate([[0.0], np.cumsum(np.cos(th[:-1]) * ds)])
    return np.stack([np.zeros_like(y), y, z], 1), np.tile([1.0, 0.0, 0.0], (len(s), 1))


def run(ring_counts: list[int] | None = None, points: int = 16, repeats: int = 5, brute_rings: int = 200,
        generated: int = 10, seed: int = 0) -> dict[str, Any]:
    """Measure; see the module docstring."""
    import time

    import numpy as np

    from climb_ompl.treebot import DPPlanner, Tree, compare, generate_tree
    from climb_ompl.treebot.compare import compare_path
    from climb_ompl.treebot.generate import BranchSpec

    ring_counts = ring_counts or [100, 200, 400, 800, 1600]
    scaling = []
    for m in ring_counts:
        t = generate_tree(seed, layout=[BranchSpec(-1, 0, 0, 0, m, 0.09)], points_per_ring=points,
                          obstacle_patches=m // 20, curvature=0.5, taper=0.2)
        best = float("inf")
        for _ in range(repeats):
            t0 = time.perf_counter()
            res = DPPlanner.for_tree(t, "trunk").solve()
            best = min(best, time.perf_counter() - t0)
        scaling.append({"rings": m, "points": points, "dp_time_s": best, "found": res.found})
    x = np.log([s["rings"] for s in scaling])
    y = np.log([s["dp_time_s"] for s in scaling])
    slope = float(np.polyfit(x, y, 1)[0])

    t = generate_tree(seed, layout=[BranchSpec(-1, 0, 0, 0, brute_rings, 0.09)], points_per_ring=points,
                      obstacle_patches=brute_rings // 20, curvature=0.5, taper=0.2)
    rings = [r for r in t.root.rings]
    t0 = time.perf_counter()
    dp = DPPlanner(rings, t.up, t.a0, t.robot.max_reach).solve()
    t_dp = time.perf_counter() - t0
    t0 = time.perf_counter()
    bf = _dijkstra(rings, t.up, t.a0, t.robot.max_reach)
    t_bf = time.perf_counter() - t0
    brute = {"rings": brute_rings, "points": points, "dp_time_s": t_dp, "dijkstra_time_s": t_bf,
             "ratio": t_bf / t_dp, "same_cost": bool(abs(dp.cost - bf) < 1e-9)}

    def figures(tree, target):
        c = compare(tree, target)
        return None if c is None else {m: v.to_dict() for m, v in c.items()}

    fig13 = figures(Tree.load("three-branch"), "b2")
    gen = []
    for s in range(generated):
        g = generate_tree(1000 + s, n_branches=3, curvature=1.0, obstacle_patches=8)
        gen.append({"seed": 1000 + s, "target": g.branches[-1].name, "result": figures(g, g.branches[-1].name)})
    ok = [r["result"] for r in gen if r["result"] is not None]

    def agg(method: str) -> dict[str, float]:
        return {"mean_error": float(np.mean([r[method]["mean_error"] for r in ok])),
                "max_error": float(np.max([r[method]["max_error"] for r in ok])),
                "swept_mean_error": float(np.mean([r[method]["swept_mean_error"] for r in ok])),
                "segment_mean_error": float(np.mean([r[method]["segment_mean_error"] for r in ok])),
                "hit_motions": int(sum(r[method]["hits"] for r in ok)),
                "motions": int(sum(r[method]["motions"] for r in ok)),
                "length_violations": int(sum(r[method]["length_violations"] for r in ok))}

    robot = Tree.load("three-branch").robot
    shapes = {"circle_k2": lambda s: 2.0 + 0.0 * s, "s_curve_k2": lambda s: 2.0 * np.sin(2 * np.pi * s),
              "straight_then_k2": lambda s: np.where(s > 1.0, 2.0, 0.0)}
    synthetic = {k: {m: v.to_dict() for m, v in compare_path(*planar_path(f), robot).items()}
                 for k, f in shapes.items()}

    return {"scaling": scaling, "loglog_slope": slope, "brute_force": brute, "three_branch_b2": fig13,
            "synthetic": synthetic,
            "generated": gen, "generated_summary": {"trees_with_path": len(ok), "proposed": agg("proposed"),
                                                    "simple": agg("simple")}}


def summary(result: dict[str, Any]) -> str:
    """One line: slope, brute-force ratio, proposed vs. simple on the three-branch tree and generated trees."""
    f, g, sc = result["three_branch_b2"], result["generated_summary"], result["synthetic"]["s_curve_k2"]
    return (f"DP log-log slope {result['loglog_slope']:.2f} over {len(result['scaling'])} ring counts; "
            f"Dijkstra/DP {result['brute_force']['ratio']:.0f}x (same cost: {result['brute_force']['same_cost']}); "
            f"three-branch b2 mean error proposed {f['proposed']['mean_error'] * 1e3:.1f} mm vs simple "
            f"{f['simple']['mean_error'] * 1e3:.1f} mm, hits {f['proposed']['hits']} vs {f['simple']['hits']}; "
            f"{g['trees_with_path']} generated trees: {g['proposed']['mean_error'] * 1e3:.1f} vs "
            f"{g['simple']['mean_error'] * 1e3:.1f} mm, hits {g['proposed']['hit_motions']} vs "
            f"{g['simple']['hit_motions']}; synthetic S-curve {sc['proposed']['mean_error'] * 1e3:.1f} vs "
            f"{sc['simple']['mean_error'] * 1e3:.1f} mm")


def command(
    out: Path = typer.Option(None, "--out", help="Write the result JSON here."),
    points: int = typer.Option(16, "--points", help="Points per ring."),
    repeats: int = typer.Option(5, "--repeats", help="Timing repeats (the minimum is kept)."),
    generated: int = typer.Option(10, "--generated", help="Generated trees for the method comparison."),
) -> None:
    """TreeBot: DP time vs. ring count (log-log slope), brute-force ratio, proposed vs. simple (Fig. 13)."""
    from climb_ompl.bench._common import execute

    execute("treebot", {"points": points, "repeats": repeats, "generated": generated}, out)
