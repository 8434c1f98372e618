"""``climb-ompl bench equilibrium``: support regions against Klampt, exact cones, torque checks, feasible regions.

Over ``stances`` random 3-hold stances from :func:`climb_ompl.model.terrain.generate_wall` (3 holds among the
nearest ones to a random hold), one run measures:

* linearised support polygons (``cone_edges``-edge pyramids, the project default): time per polygon
  and, on the same stances interleaved, Klampt's C++ ``support_polygon`` with the same number of cone
  edges (``klampt_ratio`` = Klampt's median / ours; ``klampt_ratio_k4`` the same with 4-edge cones,
  Klampt's default);
* batched ``contains`` throughput on 1e6 points, the per-point scipy ``linprog`` baseline and agreement
  with that LP oracle outside a 1e-6 m band;
* exact-cone (second-order cone) polygons: wall and CPU time;
* the per-state :class:`~climb_ompl.equilibrium.TorqueChecker` time (random 12-joint Jacobians);
* :func:`~climb_ompl.equilibrium.feasible_region` time and agreement with a per-point LP with the
  torque rows, outside the same band;
* on the widened stance set (``wide`` stances of :func:`climb_ompl.bench._stances.wide_stances`: 2-4 holds,
  arbitrary normals and friction, many empty regions): Klampt's ratio per hold count and for empty and non-empty
  regions (``wide_klampt_ratio_h2`` ... ``_h4``, ``_empty``, ``_nonempty``, ``_all``; ``_k4`` with 4-edge cones),
  planar intervals, agreement with the per-point LP, exact-cone times and agreement with a per-point SOCP.

Wall times on a shared machine include waits for the CPU; the CPU-time figures do not.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import typer

from climb_ompl.bench._stances import lemur_stances, wide_stances
from climb_ompl.equilibrium._contacts import CONE_EDGES
from climb_ompl.settings import SEED_MAX

NAME = "equilibrium"
BAND = 1e-6  # oracle points nearer a region's boundary than this (metres) are not compared


def _posture(rng: Any, holds: int, mass: float, g: Any) -> tuple[Any, Any, Any, Any]:
    """Random posture of a floating-base robot with 3 joints per limb: (J, g(q), limits, actuated)."""
    import numpy as np

    nq = 3 + 3 * holds
    J = np.zeros((holds, 3, nq))
    for i in range(holds):
        J[i, :, :3] = np.eye(3)
        J[i, :, 3 + 3 * i:6 + 3 * i] = rng.normal(scale=0.15, size=(3, 3))
    gt = np.r_[-mass * np.asarray(g), rng.normal(scale=0.5, size=nq - 3)]
    act = np.r_[np.zeros(3, bool), np.ones(nq - 3, bool)]
    lim = np.r_[np.full(3, np.inf), np.full(nq - 3, float(rng.uniform(2.0, 5.0)))]
    return J, gt, lim, act


def _lp_oracle(contacts: list[Any], mass: float, g: Any, k: int, torque: tuple[Any, ...] | None = None):  # noqa: ANN202
    """Per-point feasibility LP (scipy): cone-edge weights balancing the weight, optionally within the
    joint-torque limits of ``torque = (J, g(q), limits, actuated)``."""
    import numpy as np
    from scipy.optimize import linprog

    from climb_ompl.equilibrium._contacts import linearise

    weight = mass * np.linalg.norm(g)
    lin = linearise(contacts, weight, k, planar=False)
    ghat = np.asarray(g) / np.linalg.norm(g)
    P = np.array([contacts[i].position for i in lin.owner])
    A = np.vstack([lin.gens, np.cross(P, lin.gens.T).T])
    bf = -ghat - lin.offsets.sum(axis=0)
    cost = np.zeros(A.shape[1])
    A_ub = b_ub = None
    if torque is not None:
        J, gt, lim, act = torque
        lt = act & np.isfinite(lim)
        Tq = np.stack([J[o][:, lt].T @ lin.gens[:, c] for c, o in enumerate(lin.owner)], axis=1) * weight
        A_ub, b_ub = np.vstack([-Tq, Tq]), np.r_[lim[lt] - gt[lt], lim[lt] + gt[lt]]

    def feasible(com: Any) -> bool:
        b = np.r_[bf, -np.cross(com, ghat)]
        return linprog(cost, A_ub=A_ub, b_ub=b_ub, A_eq=A, b_eq=b, bounds=(0, None), method="highs").status == 0

    return feasible


def _klampt_times(cases: list[Any], ours: Any, k: int, repeats: int = 1) -> tuple[list[float], list[float]] | None:
    """Interleaved times (s) of Klampt's ``support_polygon`` and ``ours(contacts, mass, g)`` per stance (with
    ``repeats``, the fastest of that many interleaved pairs: less of the shared machine's noise in either).

    Klampt prints a line for each empty polygon; file descriptors 1 and 2 are on /dev/null meanwhile."""
    import os

    import numpy as np

    try:
        from klampt import robotsim
    except ImportError:  # pragma: no cover - klampt is a dev dependency
        return None
    robotsim.set_friction_cone_approximation_edges(k)
    tk, to = [], []
    saved, null = (os.dup(1), os.dup(2)), os.open(os.devnull, os.O_WRONLY)
    os.dup2(null, 1)
    os.dup2(null, 2)
    try:
        for contacts, mass, g in cases:
            if not np.allclose(np.asarray(g) / np.linalg.norm(g), [0, 0, -1]):
                continue  # Klampt's support polygon assumes gravity along -z
            arr = np.array([[*c.position, *c.normal, c.friction] for c in contacts])
            a = b = float("inf")
            for _ in range(repeats):
                t0 = time.perf_counter()
                robotsim.support_polygon(arr)
                a = min(a, time.perf_counter() - t0)
                t0 = time.perf_counter()
                ours(contacts, mass, g)
                b = min(b, time.perf_counter() - t0)
            tk.append(a)
            to.append(b)
    finally:
        for fd, old_fd in ((1, saved[0]), (2, saved[1])):
            os.dup2(old_fd, fd)
            os.close(old_fd)
        os.close(null)
    return tk, to


def run(stances: int = 200, holds: int = 3, cone_edges: int = CONE_EDGES, points: int = 1_000_000,
        oracle_points: int = 20, exact_stances: int = 20, feasible_stances: int = 30, seed: int = 0,
        wide: int = 150) -> dict[str, Any]:
    """Measure; see the module docstring.  Returns the JSON-able figures."""
    import numpy as np

    from climb_ompl.equilibrium import support_region

    cases = lemur_stances(stances, seed, holds)
    support_region(*cases[0], cone_edges=cone_edges)  # warm-up (imports)
    times, cpu, regions, solves = _polygons(cases, cone_edges)
    times_ms = np.array(times) * 1e3
    nonempty = [r for r in regions if not r.is_empty and len(r.vertices) >= 3]
    ref = sorted(nonempty, key=lambda r: len(r.vertices))[len(nonempty) // 2] if nonempty else regions[0]
    klampt = _klampt_figures(cases, cone_edges)
    rng = np.random.default_rng(seed)  # one stream, drawn from in this order: CoM tests, oracle, torque, regions
    com_tests = _com_tests(ref, rng, points)
    oracle = _oracle(cases, regions, cone_edges, oracle_points, rng, com_tests["t_contains"] / points)
    exact = _exact(cases[:exact_stances])
    torque = _torque_checks(cases[regions.index(ref)], ref, cone_edges, rng)
    feasible = _feasible_regions(cases[:feasible_stances], cone_edges, oracle_points, rng)
    wide = _wide(wide, seed, cone_edges, oracle_points, rng) if wide else {}
    return {
        "stances": stances,
        "holds": holds,
        "cone_edges": cone_edges,
        "polygon_ms_median": float(np.median(times_ms)),
        "polygon_ms_p95": float(np.percentile(times_ms, 95)),
        "polygon_cpu_ms_median": float(np.median(cpu) * 1e3),
        "polygon_cpu_ms_p95": float(np.percentile(cpu, 95) * 1e3),
        "polygon_solves_median": float(np.median(solves)),
        **klampt,
        "regions_empty": int(sum(r.is_empty for r in regions)),
        "regions_unbounded": int(sum(not r.is_bounded for r in regions)),
        "com_tests_per_s": float(points / com_tests["t_contains"]),
        "margin_per_s": float(points / com_tests["t_margin"]),
        "single_contains_us": com_tests["single_us"],
        **oracle,
        **exact,
        **torque,
        **feasible,
        **wide,
    }


def _polygons(cases: list[Any], cone_edges: int) -> tuple[list[float], list[float], list[Any], list[int]]:
    """Wall times (s), CPU times (s), the regions and their solves of the linearised support polygons."""
    from climb_ompl.equilibrium import support_region

    times, cpu, regions, solves = [], [], [], []
    for contacts, mass, g in cases:
        c0, t0 = time.process_time(), time.perf_counter()
        r = support_region(contacts, mass, g, cone_edges=cone_edges)
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
        regions.append(r)
        solves.append(r.n_solves)
    return times, cpu, regions, solves


def _klampt_figures(cases: list[Any], cone_edges: int) -> dict[str, float]:
    """Klampt's C++ support polygon on the same stances, interleaved with ours (same cone edges, then 4): median
    times (ms) and Klampt's median / ours (NaN without Klampt)."""
    import numpy as np

    from climb_ompl.equilibrium import support_region

    klampt: dict[str, float] = {}
    for k, key in ((cone_edges, ""), (4, "_k4")):
        res = _klampt_times(cases, lambda c, m, g, k=k: support_region(c, m, g, cone_edges=k), k)
        if res is None:
            klampt.update({f"klampt_ratio{key}": float("nan"), f"klampt_ms_median{key}": float("nan")})
            continue
        tk, to = res
        klampt[f"klampt_ms_median{key}"] = float(np.median(tk) * 1e3)
        klampt[f"ours_ms_median{key}"] = float(np.median(to) * 1e3)
        klampt[f"klampt_ratio{key}"] = float(np.median(tk) / np.median(to))
    return klampt


def _wide(n: int, seed: int, cone_edges: int, oracle_points: int, rng: Any) -> dict[str, Any]:
    """The widened stance set (:func:`climb_ompl.bench._stances.wide_stances`, ``n`` stances of 2-4 holds, many
    empty): Klampt's support polygon against ours interleaved on the same stances (fastest of three pairs each),
    medians and Klampt's median / ours per hold count (``h2``-``h4``), for empty and non-empty regions and over all,
    with ``cone_edges`` and with 4 edges (``_k4``); planar intervals of the same draw; the per-point LP oracle; exact
    cones (times and the per-point SOCP oracle)."""
    import numpy as np

    from climb_ompl.equilibrium import support_region

    cases = wide_stances(n, seed)
    regions = [support_region(*c, cone_edges=cone_edges) for c in cases]
    holds = np.array([len(c[0]) for c in cases])
    empty = np.array([r.is_empty for r in regions])
    out: dict[str, Any] = {"wide_stances": n, "wide_empty": int(empty.sum())}
    groups = {**{f"h{h}": holds == h for h in (2, 3, 4)}, "empty": empty, "nonempty": ~empty, "all": holds > 0}
    for h in (2, 3, 4):
        out[f"wide_stances_h{h}"], out[f"wide_empty_h{h}"] = int((holds == h).sum()), int(empty[holds == h].sum())
    for k, key in ((cone_edges, ""), (4, "_k4")):
        res = _klampt_times(cases, lambda c, m, g, k=k: support_region(c, m, g, cone_edges=k), k, repeats=3)
        if res is None:
            out[f"wide_klampt_ratio_all{key}"] = float("nan")
            continue
        tk, to = np.array(res[0]), np.array(res[1])
        for name, sel in groups.items():
            if sel.any():
                out[f"wide_klampt_ms_{name}{key}"] = float(np.median(tk[sel]) * 1e3)
                out[f"wide_ours_ms_{name}{key}"] = float(np.median(to[sel]) * 1e3)
                out[f"wide_klampt_ratio_{name}{key}"] = float(np.median(tk[sel]) / np.median(to[sel]))
    planar, p_empty = [], 0
    for contacts, mass, g in wide_stances(n, seed + 1, planar=True):
        t0 = time.perf_counter()
        p_empty += int(support_region(contacts, mass, g, planar=True, cone_edges=cone_edges).is_empty)
        planar.append(time.perf_counter() - t0)
    out.update(wide_planar_ms_median=float(np.median(planar) * 1e3), wide_planar_empty=p_empty)
    lp = _oracle(cases, regions, cone_edges, oracle_points, rng, 1.0)
    out.update({f"wide_{key}": lp[key] for key in ("oracle_points_compared", "oracle_points_inside",
                                                  "oracle_agreement")})
    exact_regions: list[Any] = []
    out.update({f"wide_{key}": v for key, v in _exact(cases, exact_regions).items()})
    out.update(_exact_oracle(cases, exact_regions, rng))
    return out


def _socp_oracle(contacts: list[Any], mass: float, g: Any):  # noqa: ANN202
    """Per-point feasibility SOCP (cvxpy, Clarabel) written from Bretl (2006) appendix B, eqs. (B1)-(B3), exact
    friction cones, forces in newtons: ``feasible(com)``."""
    import cvxpy as cp
    import numpy as np

    def skew(v: Any) -> Any:
        return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])

    W = mass * np.asarray(g, dtype=float)
    F = cp.Variable((len(contacts), 3))
    com = cp.Parameter(3)
    moment = sum(skew(np.asarray(c.position)) @ F[i] for i, c in enumerate(contacts))
    cons = [cp.sum(F, axis=0) + W == 0, moment - skew(W) @ com == 0]  # (B1), (B2): c x W = -W x c
    for i, c in enumerate(contacts):
        n = np.asarray(c.normal)
        shift = c.max_force if c.kind == "adhesion" else 0.0
        cons.append(cp.norm((np.eye(3) - np.outer(n, n)) @ F[i]) <= c.friction * (n @ F[i] + shift))  # (B3)
    prob = cp.Problem(cp.Minimize(0), cons)

    def feasible(x: Any) -> bool:
        com.value = np.asarray(x, dtype=float)
        prob.solve(solver=cp.CLARABEL)
        return prob.status in ("optimal", "optimal_inaccurate")

    return feasible


def _exact_oracle(cases: list[Any], regions: list[Any], rng: Any, per_stance: int = 6) -> dict[str, Any]:
    """Exact-cone regions against the per-point SOCP: points beyond an edge by more than the region's ``tol`` (plus
    1e-6 m) must be infeasible (completeness), points inside by more than 1e-6 m feasible (soundness); empty
    regions: points around the holds must be infeasible.  Agreement over the points compared."""
    import numpy as np

    compared = agree = misses = 0
    for (contacts, mass, g), r in zip(cases, regions, strict=True):
        feasible = _socp_oracle(contacts, mass, g)
        Q2 = np.array([c.position for c in contacts]) @ r.basis.T
        if r.is_empty or len(r.vertices) < 3:
            pts = rng.uniform(Q2.min(0) - 0.1, Q2.max(0) + 0.1, size=(per_stance, 2))
        else:
            c0 = r.vertices.mean(0)
            inner = [v + 1e-5 * (c0 - v) / np.linalg.norm(c0 - v) for v in r.vertices[:: max(1, len(r.vertices) // 3)]]
            H = r.halfplanes[rng.choice(len(r.halfplanes), size=min(3, len(r.halfplanes)), replace=False)]
            outer = []
            for a, b, c in H:
                nrm = np.array([a, b])
                on = r.vertices[np.argmin(np.abs(r.vertices @ nrm - c))]
                outer.append(on + (r.tol + rng.uniform(1e-6, 1e-3)) * nrm)
            pts = np.array(inner[:3] + outer)
        for p2 in pts:
            m = float(r.margin(p2 @ r.basis))
            if -(r.tol + 1e-6) <= m <= 1e-6 and not r.is_empty:
                continue
            ok = feasible(p2 @ r.basis)
            compared += 1
            agree += int(ok == (m > 0))
            misses += int(ok and m < 0)
    return {"wide_exact_oracle_points": compared, "wide_exact_oracle_misses": misses,
            "wide_exact_oracle_agreement": float(agree / compared) if compared else float("nan")}


def _com_tests(ref: Any, rng: Any, points: int) -> dict[str, float]:
    """Batched CoM tests on ``points`` points spread around the reference region: ``t_contains`` and ``t_margin``
    (s for the whole batch) and ``single_us`` (one point at a time, microseconds)."""
    import numpy as np

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
    return {"t_contains": t_contains, "t_margin": t_margin,
            "single_us": float((time.perf_counter() - t0) / 20000 * 1e6)}


def _agreement(region: Any, feasible: Any, contacts: list[Any], n: int, rng: Any) -> tuple[int, int, int, list[float]]:
    """(compared, agreeing, inside, LP times) over ``n`` points around the holds / the region."""
    import numpy as np

    Q2 = np.array([c.position for c in contacts]) @ region.basis.T
    lo, hi = Q2.min(axis=0) - 0.2, Q2.max(axis=0) + 0.2
    pts = rng.uniform(lo, hi, size=(n, 2))
    if not region.is_empty and len(region.vertices):  # half the points near the region
        pts[: n // 2] = region.vertices.mean(0) + rng.normal(scale=0.03, size=(n // 2, 2))
    W = pts @ region.basis
    ins, marg = region.contains(W), region.margin(W)
    compared = agree = inside = 0
    lp_t = []
    for w, i_, m in zip(W, ins, marg, strict=True):
        t0 = time.perf_counter()
        ok = feasible(w)
        lp_t.append(time.perf_counter() - t0)
        if abs(m) >= BAND:
            compared += 1
            agree += int(ok == i_)
            inside += int(ok)
    return compared, agree, inside, lp_t


def _oracle(cases: list[Any], regions: list[Any], cone_edges: int, oracle_points: int, rng: Any,
            per_point_s: float) -> dict[str, Any]:
    """The per-point LP baseline and the support regions' agreement with it (``per_point_s``: our batched test's
    seconds per point)."""
    import numpy as np

    lp_times, agree, compared, inside = [], 0, 0, 0
    for (contacts, mass, g), r in zip(cases, regions, strict=True):
        c_, a_, i_, t_ = _agreement(r, _lp_oracle(contacts, mass, g, cone_edges), contacts, oracle_points, rng)
        compared, agree, inside = compared + c_, agree + a_, inside + i_
        lp_times += t_
    lp_ms = float(np.median(lp_times) * 1e3)
    return {"lp_test_ms_median": lp_ms, "speedup_vs_lp": float(lp_ms / 1e3 / per_point_s),
            "oracle_points_compared": compared, "oracle_points_inside": inside,
            "oracle_agreement": float(agree / compared) if compared else float("nan")}


def _exact(cases: list[Any], regions: list[Any] | None = None) -> dict[str, Any]:
    """Exact (second-order cone) polygons of ``cases``: wall and CPU times (ms), SOCPs solved (the regions are
    appended to ``regions`` if given)."""
    import numpy as np

    from climb_ompl.equilibrium import support_region

    ex_times, ex_cpu, ex_solves = [], [], []
    if cases:
        support_region(*cases[0], exact=True)  # warm-up (Clarabel's first solve in a process)
    for contacts, mass, g in cases:
        c0, t0 = time.process_time(), time.perf_counter()
        r = support_region(contacts, mass, g, exact=True)
        ex_times.append(time.perf_counter() - t0)
        ex_cpu.append(time.process_time() - c0)
        ex_solves.append(r.n_solves)
        if regions is not None:
            regions.append(r)
    ex_ms, ex_cpu_ms = np.array(ex_times) * 1e3, np.array(ex_cpu) * 1e3
    return {
        "exact_stances": len(ex_times),
        "exact_ms_median": float(np.median(ex_ms)) if ex_times else float("nan"),
        "exact_ms_p95": float(np.percentile(ex_ms, 95)) if ex_times else float("nan"),
        "exact_cpu_ms_median": float(np.median(ex_cpu_ms)) if ex_times else float("nan"),
        "exact_cpu_ms_p95": float(np.percentile(ex_cpu_ms, 95)) if ex_times else float("nan"),
        "exact_socps_median": float(np.median(ex_solves)) if ex_times else float("nan"),
    }


def _torque_checks(case: tuple[list[Any], float, Any], ref: Any, cone_edges: int, rng: Any) -> dict[str, Any]:
    """:class:`~climb_ompl.equilibrium.TorqueChecker` per state (a 3-limb, 12-joint robot with random Jacobians) at
    the reference region's centroid: median time (us), feasible states of 300, LPs solved."""
    import numpy as np

    from climb_ompl.equilibrium import TorqueChecker

    contacts, mass, g = case
    nq = 12
    act = np.r_[np.zeros(3, bool), np.ones(9, bool)]
    lim = np.r_[np.full(3, np.inf), np.full(9, 5.0)]
    checker = TorqueChecker(contacts, mass, g, lim, act, cone_edges=cone_edges, region=ref)
    com = ref.vertices.mean(0) @ ref.basis
    tq, tq_feasible = [], 0
    for _ in range(300):
        J = rng.normal(scale=0.2, size=(len(contacts), 3, nq))
        J[:, :, :3] = np.eye(3)
        gt = np.r_[-mass * np.asarray(g), rng.normal(scale=1.0, size=9)]
        t0 = time.perf_counter()
        tq_feasible += int(checker.check(com, J, gt).feasible)
        tq.append(time.perf_counter() - t0)
    return {"torque_check_us_median": float(np.median(tq) * 1e6), "torque_check_feasible": tq_feasible,
            "torque_check_lps": checker.lp_calls}


def _feasible_regions(cases: list[Any], cone_edges: int, oracle_points: int, rng: Any) -> dict[str, Any]:
    """Torque-limited feasible regions of random postures, against the per-point LP with torque rows."""
    import numpy as np

    from climb_ompl.equilibrium import feasible_region

    fr_times, fr_cmp, fr_agree, fr_inside, fr_empty = [], 0, 0, 0, 0
    for contacts, mass, g in cases:
        posture = _posture(rng, len(contacts), mass, g)
        t0 = time.perf_counter()
        fr = feasible_region(contacts, mass, g, *posture, cone_edges=cone_edges)
        fr_times.append(time.perf_counter() - t0)
        fr_empty += int(fr.is_empty)
        c_, a_, i_, _ = _agreement(fr, _lp_oracle(contacts, mass, g, cone_edges, posture), contacts, oracle_points,
                                   rng)
        fr_cmp, fr_agree, fr_inside = fr_cmp + c_, fr_agree + a_, fr_inside + i_
    return {
        "feasible_region_ms_median": float(np.median(fr_times) * 1e3) if fr_times else float("nan"),
        "feasible_regions_empty": fr_empty,
        "feasible_region_points_compared": fr_cmp,
        "feasible_region_points_inside": fr_inside,
        "feasible_region_oracle_agreement": float(fr_agree / fr_cmp) if fr_cmp else float("nan"),
    }


def summary(result: dict[str, Any]) -> str:
    """One line: the headline figures."""
    return (f"polygon {result['polygon_ms_median']:.2f} ms median / {result['polygon_ms_p95']:.2f} ms p95 "
            f"({result['cone_edges']}-edge cones, {result['stances']} stances), "
            f"Klampt ratio {result['klampt_ratio']:.2f} (4 edges: {result['klampt_ratio_k4']:.2f}), "
            f"{result['com_tests_per_s'] / 1e6:.1f} M CoM tests/s, "
            f"oracle agreement {100 * result['oracle_agreement']:.2f} %, "
            f"exact {result['exact_ms_median']:.1f} ms median / {result['exact_ms_p95']:.1f} ms p95, "
            f"torque check {result['torque_check_us_median']:.0f} us, "
            f"feasible region {result['feasible_region_ms_median']:.2f} ms "
            f"(agreement {100 * result['feasible_region_oracle_agreement']:.2f} %); "
            f"widened set: Klampt ratio {_wide_ratios(result, '')} (4 edges: {_wide_ratios(result, '_k4')}), "
            f"exact p95 {result.get('wide_exact_ms_p95', float('nan')):.1f} ms "
            f"(CPU {result.get('wide_exact_cpu_ms_p95', float('nan')):.1f} ms), "
            f"oracle agreement LP {100 * result.get('wide_oracle_agreement', float('nan')):.2f} % / "
            f"SOCP {100 * result.get('wide_exact_oracle_agreement', float('nan')):.2f} %")


def _wide_ratios(result: dict[str, Any], key: str) -> str:
    """``2/3/4 holds a/b/c, empty d, non-empty e`` from the widened set's Klampt ratios."""
    def r(name: str) -> str:
        return f"{result.get(f'wide_klampt_ratio_{name}{key}', float('nan')):.2f}"

    return f"2/3/4 holds {r('h2')}/{r('h3')}/{r('h4')}, empty {r('empty')}, non-empty {r('nonempty')}"


def command(
    out: Path = typer.Option(None, "--out", help="write the JSON result here"),
    stances: int = typer.Option(200, help="random 3-hold stances"),
    cone_edges: int = typer.Option(CONE_EDGES, help="edges of the linearised friction cones"),
    seed: int = typer.Option(0, min=0, max=SEED_MAX, help="RNG seed"),
    wide: int = typer.Option(150, min=0, help="random stances of the widened set (2-4 holds, any normals; 0: none)"),
) -> None:
    """Support polygons vs Klampt, exact cones, torque checks, feasible regions, CoM tests and LP oracles."""
    from climb_ompl.bench._common import execute

    execute(NAME, {"stances": stances, "cone_edges": cone_edges, "seed": seed, "wide": wide}, out)
