"""One-step planning benchmark: LEMUR moves one limb to a neighbouring hold.

Queries: the grabs of a greedy climb (:func:`climb_ompl.bench._runs.make_queries`, the generator of every one-step
query set): on the 3-hold stance without the moving limb, from the release configuration to a transition with
that limb on a higher neighbouring hold (FIND-TRANSITION both).  Each query is planned with the chosen
planner/space/sampler and, in the same run, with plain uniform sampling (the baseline for the ratio).
Reproducible: ``--seed`` seeds the query generator and every planner; the time limit is a guard.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from climb_ompl.bench._common import execute
from climb_ompl.settings import SEED_MAX


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
    lift-move-place local plan of :func:`climb_ompl.climb.onestep.find_path`, so every query measures the planner and
    its sampler; each run reports how many queries the local plan solved (``direct_solved``).
    """
    import time

    from climb_ompl.bench._common import ONESTEP_OPTIONS
    from climb_ompl.climb.multistep import load_terrain
    from climb_ompl.climb.onestep import find_path
    from climb_ompl.model.robot import RobotModel

    rob = RobotModel.load(robot)
    ter = load_terrain(terrain)
    t0 = time.perf_counter()
    import numpy as np

    from climb_ompl.bench._runs import make_queries
    from climb_ompl.manifold.stance import Stance

    qs = [(Stance(d["stance"]), np.asarray(d["q_start"], dtype=float), np.asarray(d["q_goal"], dtype=float))
          for d in make_queries(robot, terrain, queries, seed)]
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
            res = find_path(rob, ter, s, a, b, seed=seed + i,
                            **{**ONESTEP_OPTIONS, "planner": planner, "sampler": name, "time_limit": time_limit,
                               "space": space if name == "uniform" else "projected", "torque": tmode,
                               "direct": direct})
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
    seed: int = typer.Option(0, min=0, max=SEED_MAX, help="Seed of the queries and planners."),
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
    from climb_ompl._options import check_positive

    check_positive(time_limit, "--time-limit", "seconds")
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain

    RobotModel.load(robot)
    Terrain.load(terrain)
    execute("onestep", dict(robot=robot, terrain=terrain, queries=queries, seed=seed, planner=planner, space=space,
                            sampler=sampler, time_limit=time_limit, torque=torque, direct=direct), out)
