"""One-step planning benchmark: LEMUR moves one limb to a neighbouring hold.

Queries: a 4-hold stance near a random pelvis position, a start configuration feasible at it and at the
3-hold stance without the moving limb (FIND-TRANSITION), and a goal with that limb on a neighbouring hold
(FIND-TRANSITION).  Each query is planned with the chosen planner/space/sampler and, in the same run, with
plain uniform sampling (the baseline for the ratio).  Reproducible: ``--seed`` seeds the query generator
and every planner; the time limit is a guard.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from ._common import execute


def stance_near(robot: Any, terrain: Any, x: float, z: float) -> Any:
    """The stance putting each hand on the hold nearest its nominal position with the pelvis at ``(x, z)``."""
    import numpy as np

    from ..stance import Stance

    q = np.array(robot.nominal_q, dtype=float)
    q[robot.base_indices[0]], q[robot.base_indices[1]] = x, z
    H = robot.hand_positions(q)
    P = terrain.positions
    used: set[str] = set()
    m = {}
    for i, lb in enumerate(robot.limbs):
        for k in np.argsort(np.linalg.norm(P - H[i], axis=1)):
            if terrain.holds[k].id not in used:
                break
        used.add(terrain.holds[k].id)
        m[lb.name] = terrain.holds[k].id
    return Stance(m)


def make_queries(robot: Any, terrain: Any, n: int, seed: int, attempts: int = 600) -> list[tuple[Any, Any, Any]]:
    """``n`` one-step queries ``(stance, q_start, q_goal)`` (3-hold stance, start and goal transitions)."""
    import numpy as np

    from ..onestep import find_transition

    rng = np.random.default_rng(seed)
    P = terrain.positions
    lo, hi = P.min(axis=0), P.max(axis=0)
    out: list[tuple[Any, Any, Any]] = []
    k = 0
    while len(out) < n and k < 20 * n:
        k += 1
        x = rng.uniform(lo[0] + 0.4, hi[0] - 0.4)
        z = rng.uniform(lo[2] + 0.4, hi[2] - 0.4)
        s4 = stance_near(robot, terrain, x, z)
        limb = robot.limbs[int(rng.integers(len(robot.limbs)))].name
        s3 = s4.without(limb)
        qs = find_transition(robot, terrain, s4, s3, seed=int(rng.integers(1 << 30)), attempts=attempts)
        if qs is None:
            continue
        h = terrain.hold(s4[limb]).p
        order = np.argsort(np.linalg.norm(P - h, axis=1))
        for j in order[1:5]:
            g = terrain.holds[j].id
            if g in s4.hold_ids or np.linalg.norm(P[j] - h) > 0.3:
                continue
            qg = find_transition(robot, terrain, s3, s3.with_hold(limb, g), seed=int(rng.integers(1 << 30)),
                                 attempts=attempts, near=qs)
            if qg is not None:
                out.append((s3, qs, qg))
                break
    return out


def _stats(times: list[float], ok: list[bool], limit: float) -> dict[str, Any]:
    import numpy as np

    t = np.array([x if s else limit for x, s in zip(times, ok, strict=False)])
    solved = [x for x, s in zip(times, ok, strict=False) if s]
    return {"median_s": float(np.median(t)), "p95_s": float(np.percentile(t, 95)),
            "mean_solved_s": float(np.mean(solved)) if solved else float("nan"),
            "success_rate": float(np.mean(ok)) if ok else 0.0, "n_queries": len(ok)}


def run(robot: str = "lemur", terrain: str = "demo-wall", queries: int = 50, seed: int = 0, planner: str = "LazyPRM",
        space: str = "projected", sampler: str = "joint-by-joint+straight-elbow+free-limb+lift",
        time_limit: float = 10.0, torque: str = "final-path", baseline: bool = True,
        torque_compare: bool = True, direct: bool = True) -> dict[str, Any]:
    """Plan the queries with the chosen sampler and (``baseline``) with uniform sampling; figures per run.

    With ``torque_compare`` the chosen sampler also runs with the other torque mode (``state`` vs
    ``final-path``), reported under ``runs`` as ``"<sampler> torque=<mode>"``.  ``direct=False`` skips the
    lift-move-place local plan of :func:`climb_ompl.onestep.find_path`, so every query measures the planner and
    its sampler; each run reports how many queries the local plan solved (``direct_solved``).
    """
    import time

    from ..onestep import find_path
    from ..robot import RobotModel
    from ..terrain import Terrain

    rob = RobotModel.load(robot)
    ter = Terrain.load(terrain)
    t0 = time.perf_counter()
    qs = make_queries(rob, ter, queries, seed)
    t_queries = time.perf_counter() - t0
    configs = [(sampler, torque, sampler)]
    if torque_compare:
        other = "state" if torque == "final-path" else "final-path"
        configs.append((sampler, other, f"{sampler} torque={other}"))
    if baseline and sampler != "uniform":
        configs.append(("uniform", torque, "uniform"))
    runs = {}
    for name, tmode, key in configs:
        times, ok, rej, samples, n_direct = [], [], {}, 0, 0
        for i, (s, a, b) in enumerate(qs):
            res = find_path(rob, ter, s, a, b, planner=planner, space=space if name == "uniform" else "projected",
                            sampler=name, time_limit=time_limit, seed=seed + i, torque=tmode, direct=direct)
            n_direct += bool(res.stats.get("direct"))
            times.append(res.stats["time_s"])
            ok.append(res.found)
            for k, v in res.stats["rejections"].items():
                rej[k] = rej.get(k, 0) + v
            samples += res.stats["samples"] or 0
        runs[key] = {**_stats(times, ok, time_limit), "sampler": name, "torque": tmode, "rejections": rej,
                     "sampler_calls": samples, "direct_solved": n_direct, "times_s": times, "solved": ok}
    main = runs[sampler]
    out: dict[str, Any] = {k: main[k] for k in ("median_s", "p95_s", "mean_solved_s", "success_rate", "n_queries",
                                                "rejections")}
    out.update(planner=planner, space=space, sampler=sampler, terrain=ter.name, robot=rob.name, torque=torque,
               direct=direct,
               time_limit_s=time_limit, query_generation_s=t_queries, runs=runs)
    if "uniform" in runs and sampler != "uniform":
        u = runs["uniform"]
        out["uniform"] = {k: u[k] for k in ("median_s", "p95_s", "mean_solved_s", "success_rate")}
        out["median_ratio_uniform_over_custom"] = u["median_s"] / max(main["median_s"], 1e-9)
    return out


def summary(result: dict[str, Any]) -> str:
    """One line: median, p95, success (and the uniform baseline)."""
    s = (f"{result['robot']} on {result['terrain']}: {result['planner']}/{result['space']}/{result['sampler']} "
         f"median {result['median_s']:.3f} s, p95 {result['p95_s']:.3f} s, "
         f"mean of solved {result.get('mean_solved_s', float('nan')):.3f} s, "
         f"success {100 * result['success_rate']:.0f}% of {result['n_queries']}")
    if "uniform" in result:
        u = result["uniform"]
        s += (f"; uniform: median {u['median_s']:.3f} s, p95 {u['p95_s']:.3f} s, "
              f"mean of solved {u.get('mean_solved_s', float('nan')):.3f} s, "
              f"success {100 * u['success_rate']:.0f}%")
    return s


def command(
    robot: str = typer.Option("lemur", help="Robot name or spec file."),
    terrain: str = typer.Option("demo-wall", help="Terrain name or file."),
    queries: int = typer.Option(50, help="Number of one-step queries."),
    seed: int = typer.Option(0, help="Seed of the queries and planners."),
    planner: str = typer.Option("LazyPRM", help="OMPL planner name."),
    space: str = typer.Option("projected", help="projected | atlas | tangent_bundle."),
    sampler: str = typer.Option("joint-by-joint+straight-elbow+free-limb+lift", help="Sampler name(s), a+b."),
    time_limit: float = typer.Option(10.0, help="Time limit per query, s."),
    torque: str = typer.Option("final-path", help="Torque check: state | final-path | off."),
    direct: bool = typer.Option(True, help="Try the lift-move-place local plan before the planner."),
    out: Path = typer.Option(None, help="Write the JSON result here."),
) -> None:
    """One-step planning: median/p95 time and success rate, custom samplers vs uniform.

    The robot and terrain are loaded here first, so a missing or malformed file is a one-line error naming it
    (exit 2) before the benchmark process starts.
    """
    from ..robot import RobotModel
    from ..terrain import Terrain

    RobotModel.load(robot)
    Terrain.load(terrain)
    execute("onestep", dict(robot=robot, terrain=terrain, queries=queries, seed=seed, planner=planner, space=space,
                            sampler=sampler, time_limit=time_limit, torque=torque, direct=direct), out)
