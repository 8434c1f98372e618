"""``climb-ompl bench compare``: which OMPL planner for climbing (``make compare``, ``docs/planners.md``).

The grid: every registered planner x the three constrained spaces with uniform sampling, plus the custom
samplers on the projected space (the only space that calls them) x queries of the versioned query sets
(:mod:`climb_ompl.bench._query_set`, spread from easy to hard) x seeds.  Every run has the same budget of validity
checks and the same wall-clock guard, and the planner alone answers (``find_path(direct=False)``: the
lift-move-place local path would give every planner the same answer on the queries it solves).  Runs go
through Dask (a ``LocalCluster`` of ``--workers`` processes, or ``--scheduler tcp://HOST:PORT``), each in
a child process (:mod:`climb_ompl.bench._runs`, reused from run to run), into ``grid.db``; running the command
again resumes.  Runs execute seed by seed, so an interrupted comparison holds the same runs for every
configuration.
``--sample N`` runs only N runs of the grid, drawn at random (seeded), and estimates the full grid's time.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import typer

from climb_ompl.settings import SEED_MAX

#: The comparison's defaults: the custom sampler is the combination the climb's one-step docs measured
#: best (``docs/onestep.md``).  Seeds start at 1: OMPL draws the same numbers for the seeds 0 and 1
#: (:func:`climb_ompl.manifold._ompl.seed_rng`), so 0 and 1 would be one seed twice for the planners that only
#: sample through OMPL.
COMPARE: dict[str, Any] = {
    "spaces": ["atlas", "tangent_bundle", "projected"],
    "samplers": ["uniform", "joint-by-joint+straight-elbow+free-limb+lift"],
    "seeds": [1, 2, 3],
    "per_set": 3,
    "max_iterations": 2000,
    "time_limit": 5.0,
}


def build_compare_grid(*, sets: list[str] | None = None, per_set: int | None = None,
                       planners: list[str] | None = None, spaces: list[str] | None = None,
                       samplers: list[str] | None = None, seeds: list[int] | None = None,
                       max_iterations: int | None = None, time_limit: float | None = None, name: str = "compare"):  # noqa: ANN201
    """The comparison grid (:class:`climb_ompl.bench._runs.Grid`); explicit values override :data:`COMPARE`.

    Raises:
        InputError: an unknown query set; PlannerNotFound: an unknown planner or sampler name.
    """
    from climb_ompl.bench._query_set import load_queries
    from climb_ompl.bench._runs import Grid
    from climb_ompl.manifold._ompl import PLANNER_NAMES
    from climb_ompl.settings import check_names

    pl = list(planners or PLANNER_NAMES)
    sp = list(spaces or COMPARE["spaces"])
    sa = list(samplers or COMPARE["samplers"])
    for p in pl:
        for s in sa:
            check_names(p, "projected" if s != "uniform" or not sp else sp[0], s)  # custom: projected only
    qs = load_queries(sets, per_set=COMPARE["per_set"] if per_set is None else per_set)
    return Grid(name=name, planners=pl, spaces=sp, samplers=sa, queries=qs,
                seeds=list(COMPARE["seeds"] if seeds is None else seeds),
                time_limit=float(COMPARE["time_limit"] if time_limit is None else time_limit),
                max_iterations=int(COMPARE["max_iterations"] if max_iterations is None else max_iterations),
                extra={"direct": False})


def sample_runs(runs: list[dict[str, Any]], n: int, seed: int = 0) -> list[dict[str, Any]]:
    """``n`` runs drawn without replacement (seeded), in the grid's order."""
    import numpy as np

    if n >= len(runs):
        return runs
    idx = np.sort(np.random.default_rng(seed).choice(len(runs), size=n, replace=False))
    return [runs[int(i)] for i in idx]


def command(
    out: Path = typer.Option(Path("out/compare"), "--out", help="Output folder: grid.db, runs.csv, compare.json."),
    query_set: list[str] = typer.Option(None, "--set", help="Query set (repeatable; default: every bundled set)."),
    per_set: int = typer.Option(None, "--per-set", help=f"Queries per set (default {COMPARE['per_set']})."),
    planner: list[str] = typer.Option(None, "--planner", help="Planner (repeatable; default: every registered)."),
    space: list[str] = typer.Option(None, "--space", help="Constrained space (repeatable)."),
    sampler: list[str] = typer.Option(None, "--sampler", help="Sampler (repeatable)."),
    seed: list[int] = typer.Option(None, "--seed", min=0, max=SEED_MAX, help="Seed (repeatable; default 1 2 3)."),
    max_iterations: int = typer.Option(None, "--max-iterations", help="Validity-check budget per run."),
    time_limit: float = typer.Option(None, "--time-limit", help="Wall-clock guard per run, s."),
    sample: int = typer.Option(None, "--sample", help="Run only this many runs of the grid (seeded draw)."),
    workers: int = typer.Option(1, "--workers", help="Dask LocalCluster worker processes."),
    scheduler: str = typer.Option(None, "--scheduler", help="Dask scheduler tcp://HOST:PORT (no local cluster)."),
) -> None:
    """Run (or resume) the planner comparison; print the runs done and the estimated time of the full grid."""
    from climb_ompl._options import check_positive
    from climb_ompl.bench._common import check_grid_options, check_scheduler

    if time_limit is not None:
        check_positive(time_limit, "--time-limit", "seconds")
    check_grid_options(planner or None, space or list(COMPARE["spaces"]), sampler or None,
                       {"--per-set": per_set, "--max-iterations": max_iterations, "--sample": sample,
                        "--workers": workers}, out)
    import json

    from climb_ompl._io import atomic_write_json
    from climb_ompl.bench._common import envelope
    from climb_ompl.bench._runs import finished_keys, open_db, run_grid, run_key, summary_table, write_tidy

    grid = build_compare_grid(sets=query_set or None, per_set=per_set, planners=planner or None,
                              spaces=space or None, samplers=sampler or None, seeds=seed or None,
                              max_iterations=max_iterations, time_limit=time_limit)
    remote_workers = check_scheduler(scheduler)
    out.mkdir(parents=True, exist_ok=True)
    runs = grid.runs()
    # seed-major order: an interrupted comparison holds whole seeds (every configuration the same runs)
    chosen = sorted(sample_runs(runs, sample) if sample else runs, key=lambda r: (r["seed"], r["query"]))
    con = open_db(out / "grid.db")
    todo = [r for r in chosen if run_key(r) not in finished_keys(con)]
    con.close()

    where = f"scheduler {scheduler}, {remote_workers}" if scheduler else f"LocalCluster, {workers}"
    typer.echo(f"[compare] grid of {len(runs)} runs; {len(chosen)} chosen, {len(todo)} to run ({where} worker(s))")
    client = cluster = None
    if scheduler is None:
        from distributed import Client, LocalCluster

        # no dashboard; the scheduler's HTTP server (which it always starts, by default on port 8787) on a free port:
        # a second grid, or a notebook's cluster, holds 8787
        cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True, dashboard_address=":0",
                               scheduler_kwargs={"dashboard": False})
        client = Client(cluster)
    t0 = time.perf_counter()
    try:
        results = run_grid(grid, out / "grid.db", runs=chosen, scheduler=client if client is not None else scheduler,
                           progress=lambda k, total: typer.echo(f"  {k}/{total}") if k % 20 == 0 else None)
    finally:
        if client is not None:
            client.close()
            cluster.close()
    wall = time.perf_counter() - t0
    n_workers = workers if scheduler is None else remote_workers
    per_run = wall / len(todo) if todo else None
    summary: dict[str, Any] = envelope("compare", {"planners": list(grid.planners), "spaces": list(grid.spaces),
                                                   "samplers": list(grid.samplers), "queries": len(grid.queries),
                                                   "seeds": list(grid.seeds), "max_iterations": grid.max_iterations,
                                                   "time_limit": grid.time_limit, "sample": sample,
                                                   "workers": n_workers, "scheduler": scheduler})
    summary.update(grid_runs=len(runs), runs_in_db=len(results), executed=len(todo), wall_s=wall,
                   wall_s_per_run=per_run,
                   full_grid_estimate_min=(per_run * len(runs) / 60.0) if per_run else None,
                   table=summary_table(results))
    write_tidy(results, out / "runs.csv")
    atomic_write_json(out / "compare.json", summary)
    est = summary["full_grid_estimate_min"]
    typer.echo(f"[compare] {len(todo)} runs in {wall:.0f} s ({per_run or 0:.2f} s/run with "
               f"{n_workers or '?'} worker(s)); {len(results)} runs in {out / 'grid.db'}"
               + (f"; the full grid of {len(runs)} runs: ~{est:.0f} min at this rate" if est else ""))
    typer.echo(json.dumps({"runs_in_db": len(results)}))
