"""``climb-ompl bench equilibrium``: support-polygon speed, batched CoM tests and oracle agreement.

Over ``stances`` random 3-hold stances from :func:`climb_ompl.terrain.generate_wall` (3 holds among the
nearest ones to a random hold, 4-edge cones), one run measures: polygon time (median, p95), batched
``contains`` throughput on 1e6 points, the per-point scipy ``linprog`` baseline and the ratio, agreement
with that LP oracle outside a 1e-6 m band, the exact-cone (SOCP) polygon time, single-point test
latency and the per-state :class:`~climb_ompl.equilibrium.TorqueChecker` time.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import typer

NAME = "equilibrium"


def _stances(n: int, seed: int, holds: int) -> list[tuple[list[Any], float, Any]]:
    import numpy as np

    from ..equilibrium import Contact
    from ..terrain import generate_wall

    out = []
    rng = np.random.default_rng(seed)
    for i in range(n):
        w = generate_wall(seed + i)
        P = w.positions
        centre = P[rng.integers(len(P))]
        near = np.argsort(np.linalg.norm(P - centre, axis=1))[: 3 * holds]
        pick = rng.choice(near, size=holds, replace=False)
        out.append(([Contact.from_hold(w.holds[j]) for j in pick], 7.0, w.g))
    return out


def _lp_oracle(contacts: list[Any], mass: float, g: Any, k: int):  # noqa: ANN202
    import numpy as np
    from scipy.optimize import linprog

    from ..equilibrium._contacts import linearise

    weight = mass * np.linalg.norm(g)
    lin = linearise(contacts, weight, k, planar=False)
    ghat = np.asarray(g) / np.linalg.norm(g)
    P = np.array([contacts[i].position for i in lin.owner])
    A = np.vstack([lin.gens, np.cross(P, lin.gens.T).T])
    bf = -ghat - lin.offsets.sum(axis=0)
    cost = np.zeros(A.shape[1])

    def feasible(com: Any) -> bool:
        b = np.r_[bf, -np.cross(com, ghat)]
        return linprog(cost, A_eq=A, b_eq=b, bounds=(0, None), method="highs").status == 0

    return feasible


def run(stances: int = 200, holds: int = 3, cone_edges: int = 4, points: int = 1_000_000, oracle_points: int = 20,
        exact_stances: int = 10, seed: int = 0) -> dict[str, Any]:
    """Measure; see the module docstring.  Returns the JSON-able figures."""
    import numpy as np

    from ..equilibrium import TorqueChecker, support_region

    cases = _stances(stances, seed, holds)
    support_region(*cases[0], cone_edges=cone_edges)  # warm-up (imports, first HiGHS instance)
    times, cpu, regions, solves = [], [], [], []
    for contacts, mass, g in cases:
        c0, t0 = time.process_time(), time.perf_counter()
        r = support_region(contacts, mass, g, cone_edges=cone_edges)
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
        regions.append(r)
        solves.append(r.n_solves)
    times_ms = np.array(times) * 1e3
    nonempty = [r for r in regions if not r.is_empty and len(r.vertices) >= 3]
    ref = sorted(nonempty, key=lambda r: len(r.vertices))[len(nonempty) // 2] if nonempty else regions[0]

    rng = np.random.default_rng(seed)
    # Batched CoM tests on 1e6 points spread around the reference region.
    c2 = ref.vertices.mean(axis=0) if len(ref.vertices) else np.zeros(2)
    X2 = c2 + rng.uniform(-0.3, 0.3, size=(points, 2))
    P = X2 @ ref.basis + rng.uniform(-1, 1, size=(points, 1)) * np.array([0, 0, 1.0])
    t0 = time.perf_counter()
    ref.contains(P)
    t_contains = time.perf_counter() - t0
    t0 = time.perf_counter()
    ref.margin(P)
    t_margin = time.perf_counter() - t0
    t0 = time.perf_counter()
    for p in P[:20000]:
        ref.contains(p)
    single_us = (time.perf_counter() - t0) / 20000 * 1e6

    # Per-point LP baseline and oracle agreement (outside a 1e-6 m band).
    lp_times, agree, compared, inside = [], 0, 0, 0
    for (contacts, mass, g), r in zip(cases, regions, strict=True):
        feasible = _lp_oracle(contacts, mass, g, cone_edges)
        Q2 = np.array([c.position for c in contacts]) @ r.basis.T
        lo, hi = Q2.min(axis=0) - 0.2, Q2.max(axis=0) + 0.2
        pts = rng.uniform(lo, hi, size=(oracle_points, 2))
        if not r.is_empty and len(r.vertices):  # half the points near the region
            pts[: oracle_points // 2] = r.vertices.mean(0) + rng.normal(scale=0.03, size=(oracle_points // 2, 2))
        W = pts @ r.basis
        ins, marg = r.contains(W), r.margin(W)
        for w, i_, m in zip(W, ins, marg, strict=True):
            t0 = time.perf_counter()
            ok = feasible(w)
            lp_times.append(time.perf_counter() - t0)
            if abs(m) >= 1e-6:
                compared += 1
                agree += int(ok == i_)
                inside += int(ok)
    lp_ms = float(np.median(lp_times) * 1e3)
    per_point_s = t_contains / points

    # Exact (second-order cone) polygons.
    ex_times = []
    for contacts, mass, g in cases[:exact_stances]:
        t0 = time.perf_counter()
        support_region(contacts, mass, g, exact=True)
        ex_times.append(time.perf_counter() - t0)

    # TorqueChecker per state (a 3-limb, 12-joint robot with random Jacobians), feasible states only.
    contacts, mass, g = cases[regions.index(ref)]
    nq = 12
    act = np.r_[np.zeros(3, bool), np.ones(9, bool)]
    lim = np.r_[np.full(3, np.inf), np.full(9, 5.0)]
    checker = TorqueChecker(contacts, mass, g, lim, act, cone_edges=cone_edges, region=ref)
    com = ref.vertices.mean(0) @ ref.basis
    tq = []
    for _ in range(300):
        J = rng.normal(scale=0.2, size=(len(contacts), 3, nq))
        J[:, :, :3] = np.eye(3)
        gt = np.r_[-mass * np.asarray(g), rng.normal(scale=1.0, size=9)]
        t0 = time.perf_counter()
        checker.check(com, J, gt)
        tq.append(time.perf_counter() - t0)

    return {
        "stances": stances,
        "holds": holds,
        "cone_edges": cone_edges,
        "polygon_ms_median": float(np.median(times_ms)),
        "polygon_ms_p95": float(np.percentile(times_ms, 95)),
        "polygon_cpu_ms_median": float(np.median(cpu) * 1e3),
        "polygon_lps_median": float(np.median(solves)),
        "regions_empty": int(sum(r.is_empty for r in regions)),
        "regions_unbounded": int(sum(not r.is_bounded for r in regions)),
        "com_tests_per_s": float(points / t_contains),
        "margin_per_s": float(points / t_margin),
        "single_contains_us": float(single_us),
        "lp_test_ms_median": lp_ms,
        "speedup_vs_lp": float(lp_ms / 1e3 / per_point_s),
        "oracle_points_compared": compared,
        "oracle_points_inside": inside,
        "oracle_agreement": float(agree / compared) if compared else float("nan"),
        "exact_polygon_ms_median": float(np.median(ex_times) * 1e3) if ex_times else float("nan"),
        "torque_check_us_median": float(np.median(tq) * 1e6),
    }


def summary(result: dict[str, Any]) -> str:
    """One line: the headline figures."""
    return (f"polygon {result['polygon_ms_median']:.2f} ms median / {result['polygon_ms_p95']:.2f} ms p95 "
            f"(CPU {result['polygon_cpu_ms_median']:.2f} ms, {result['stances']} stances), "
            f"{result['com_tests_per_s'] / 1e6:.1f} M CoM tests/s, "
            f"LP {result['lp_test_ms_median']:.2f} ms/point (x{result['speedup_vs_lp']:.0f}), "
            f"oracle agreement {100 * result['oracle_agreement']:.2f} %, "
            f"exact {result['exact_polygon_ms_median']:.0f} ms, torque check {result['torque_check_us_median']:.0f} us")


def command(
    out: Path = typer.Option(None, "--out", help="write the JSON result here"),
    stances: int = typer.Option(200, help="random 3-hold stances"),
    cone_edges: int = typer.Option(4, help="edges of the linearised friction cones"),
    seed: int = typer.Option(0, help="RNG seed"),
) -> None:
    """Support-polygon time, batched CoM tests/s, per-point LP baseline and oracle agreement."""
    from ._common import execute

    execute(NAME, {"stances": stances, "cone_edges": cone_edges, "seed": seed}, out)
