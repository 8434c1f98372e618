"""``climb-ompl bench grid``: a planner x space x sampler x query x seed grid (see :mod:`climb_ompl.bench._runs`).

Unlike the other benchmarks this one manages its own processes (child processes reused from run to run, in a
local pool or on a Dask cluster), so ``command`` does not go through ``_common.execute``.  ``--compare-serial``
also measures throughput serial vs. process pool, ``--compare-fresh`` reused worker processes vs. a fresh
process per run (runs per minute, and their ratio) on this machine.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import TYPE_CHECKING, Any

import typer

from climb_ompl.settings import SEED_MAX

if TYPE_CHECKING:
    from climb_ompl.bench._runs import Grid

#: Preset grids.  ``planners: None`` means every registered planner.  ``max_iterations`` (validity checks)
#: is the reproducible budget; ``time_limit`` the wall-clock guard.
PRESETS: dict[str, dict[str, Any]] = {
    "tiny": {"planners": ["RRT", "RRTConnect"], "spaces": ["tangent_bundle"], "samplers": ["uniform"], "queries": 1,
             "seeds": [0], "time_limit": 5.0, "max_iterations": 600},
    "small": {"planners": ["LazyPRM", "RRTConnect"], "spaces": ["atlas", "tangent_bundle", "projected"],
              "samplers": ["uniform"], "queries": 3, "seeds": [0], "time_limit": 5.0, "max_iterations": 5000},
    "planners": {"planners": None, "spaces": ["atlas"], "samplers": ["uniform"], "queries": 5, "seeds": [0],
                 "time_limit": 5.0, "max_iterations": 5000},
    "samplers": {"planners": ["PRM", "LazyPRM", "RRTConnect"], "spaces": ["projected"],
                 "samplers": ["uniform", "straight-elbow", "free-limb"], "queries": 5, "seeds": [0],
                 "time_limit": 5.0, "max_iterations": 5000},
}


def build_grid(preset: str | None = None, *, robot: str = "lemur", terrain: str = "demo-wall",
               planners: list[str] | None = None, spaces: list[str] | None = None,
               samplers: list[str] | None = None, queries: int | None = None, seeds: list[int] | None = None,
               time_limit: float | None = None, max_iterations: int | None = None, query_seed: int = 0,
               name: str | None = None):  # noqa: ANN201
    """A :class:`climb_ompl.bench._runs.Grid` from a preset and/or explicit lists (explicit values win).

    The planner alone answers each query (``find_path(direct=False)``): the climb's lift-move-place local path,
    which a climb tries first, solves most one-step queries before any planner runs, and every planner would
    then show the same result.

    Raises:
        InputError: unknown preset, or no one-step query could be generated on the terrain.
    """
    from climb_ompl.bench._runs import Grid, make_queries
    from climb_ompl.errors import ARGUMENT, InputError
    from climb_ompl.manifold._ompl import PLANNER_NAMES

    base: dict[str, Any] = dict(PRESETS["small"])
    if preset is not None:
        if preset not in PRESETS:
            raise InputError(ARGUMENT, "--preset", f"unknown preset {preset!r}; valid: {', '.join(PRESETS)}")
        base = dict(PRESETS[preset])
    pl = planners or base["planners"] or list(PLANNER_NAMES)
    qs = make_queries(robot, terrain, queries or base["queries"], query_seed)
    if not qs:
        raise InputError(terrain, "holds", f"no one-step query found for robot {robot!r} on this terrain")
    return Grid(name=name or f"{robot}@{terrain}:{preset or 'custom'}", planners=pl,
                spaces=spaces or base["spaces"], samplers=samplers or base["samplers"], queries=qs,
                seeds=seeds if seeds is not None else base["seeds"],
                time_limit=time_limit if time_limit is not None else base["time_limit"],
                max_iterations=max_iterations if max_iterations is not None else base.get("max_iterations"),
                extra={"direct": False})  # the planner alone answers, as in bench compare


def command(
    out: Path = typer.Option(..., "--out", help="Output folder: grid.db (SQLite, OMPL layout), runs.csv, grid.json."),
    preset: str = typer.Option(None, "--preset", help=f"Preset grid: {', '.join(PRESETS)}."),
    robot: str = typer.Option("lemur", "--robot"),
    terrain: str = typer.Option("demo-wall", "--terrain"),
    planner: list[str] = typer.Option(None, "--planner", help="Planner name (repeatable)."),
    space: list[str] = typer.Option(None, "--space", help="Constrained space (repeatable)."),
    sampler: list[str] = typer.Option(None, "--sampler", help="Sampler (repeatable)."),
    queries: int = typer.Option(None, "--queries", help="Number of one-step queries."),
    seed: list[int] = typer.Option(None, "--seed", min=0, max=SEED_MAX, help="Seed (repeatable)."),
    time_limit: float = typer.Option(None, "--time-limit", help="Per-run time limit, s."),
    max_iterations: int = typer.Option(None, "--max-iterations",
                                       help="Per-run budget of validity checks (reproducible runs)."),
    workers: int = typer.Option(None, "--workers", help="Local process-pool size (default: CPU count)."),
    scheduler: str = typer.Option(None, "--scheduler", help="Dask scheduler address tcp://HOST:PORT."),
    compare_serial: bool = typer.Option(False, "--compare-serial",
                                        help="Also run the grid serially to measure the pool's throughput ratio."),
    compare_fresh: bool = typer.Option(False, "--compare-fresh",
                                       help="Also run the grid with a fresh process per run (same pool) to measure "
                                            "what reusing worker processes saves, and check the results agree."),
) -> None:
    """Run (or resume) a benchmark grid and write the database, the tidy CSV and a JSON summary.

    With ``--compare-serial`` both databases (``grid.db``, ``grid-serial.db``) start afresh, so the two
    throughputs are measured on the same full grid; likewise ``--compare-fresh`` (``grid-fresh.db``: every
    run in a fresh process, as :class:`climb_ompl.bench._runs.RunWorker` with ``max_runs=1``).
    """
    from climb_ompl._options import check_positive
    from climb_ompl.bench._common import check_grid_options, check_scheduler

    if time_limit is not None:
        check_positive(time_limit, "--time-limit", "seconds")
    check_grid_options(planner or None, space or None, sampler or None,
                       {"--queries": queries, "--max-iterations": max_iterations, "--workers": workers}, out)
    import json

    from climb_ompl._io import atomic_write_json
    from climb_ompl.bench._common import envelope
    from climb_ompl.bench._runs import write_tidy

    grid = build_grid(preset, robot=robot, terrain=terrain, planners=planner or None, spaces=space or None,
                      samplers=sampler or None, queries=queries, seeds=seed or None, time_limit=time_limit,
                      max_iterations=max_iterations)
    check_grid_options(None, list(grid.spaces), list(grid.samplers), {})  # a preset's spaces and samplers too
    check_scheduler(scheduler)
    out.mkdir(parents=True, exist_ok=True)  # after every check: bad input leaves no folder behind
    if compare_serial or compare_fresh:
        for stale in ("grid.db", "grid-serial.db", "grid-fresh.db"):
            (out / stale).unlink(missing_ok=True)
    results, n, pool_s = _run_pool(grid, out, workers, scheduler)
    summary: dict[str, Any] = envelope("grid", {"preset": preset, "robot": robot, "terrain": terrain,
                                                "planners": list(grid.planners), "spaces": list(grid.spaces),
                                                "samplers": list(grid.samplers), "queries": len(grid.queries),
                                                "seeds": list(grid.seeds), "time_limit": grid.time_limit,
                                                "max_iterations": grid.max_iterations, "workers": workers,
                                                "scheduler": scheduler})
    summary.update(n_runs=len(results), n_executed=n, pool_s=pool_s,
                   runs_per_min_pool=60.0 * n / pool_s if pool_s > 0 and n else None)
    if compare_serial:
        summary.update(_compare_serial(grid, out, results, n, pool_s))
    if compare_fresh:
        summary.update(_compare_fresh(grid, out, results, n, pool_s, workers, scheduler))
    from climb_ompl.bench._runs import summary_table

    summary["table"] = summary_table(results)
    write_tidy(results, out / "runs.csv")
    atomic_write_json(out / "grid.json", summary)
    typer.echo(json.dumps(summary["table"], indent=1))
    typer.echo(_throughput_line(summary, n, pool_s, compare_serial, compare_fresh, out))


def _run_pool(grid: Grid, out: Path, workers: int | None, scheduler: str | None
              ) -> tuple[list[dict[str, Any]], int, float]:
    """Run (or resume) ``grid`` into ``out/grid.db`` behind a progress bar: the results of every run, the number
    executed now (the rest were resumed) and the seconds it took."""
    from rich.progress import Progress

    from climb_ompl.bench._runs import finished_keys, open_db, run_grid, run_key

    con = open_db(out / "grid.db")
    done = finished_keys(con)
    con.close()
    n = sum(1 for r in grid.runs() if run_key(r) not in done)  # runs executed now (the rest are resumed)
    with Progress(transient=True) as prog:
        task = prog.add_task(f"grid {grid.name}", total=n)
        t0 = time.perf_counter()
        results = run_grid(grid, out / "grid.db", workers=workers, scheduler=scheduler,
                           progress=lambda k, total: prog.update(task, completed=n - total + k))
        pool_s = time.perf_counter() - t0
    return results, n, pool_s


def _compare_serial(grid: Grid, out: Path, results: list[dict[str, Any]], n: int, pool_s: float) -> dict[str, Any]:
    """``--compare-serial``: the grid again in one process (``grid-serial.db``), its throughput against the pool's
    (``n`` runs in ``pool_s`` seconds) and whether it found the same."""
    from climb_ompl.bench._runs import run_grid

    t0 = time.perf_counter()
    serial = run_grid(grid, out / "grid-serial.db", workers=1, resume=False)
    serial_s = time.perf_counter() - t0
    return dict(serial_s=serial_s, runs_per_min_serial=60.0 * n / serial_s, pool_speedup=serial_s / pool_s,
                serial_equals_pool=[(r["solved"], r["path_length"]) for r in serial]
                == [(r["solved"], r["path_length"]) for r in results])


def _compare_fresh(grid: Grid, out: Path, results: list[dict[str, Any]], n: int, pool_s: float,
                   workers: int | None, scheduler: str | None) -> dict[str, Any]:
    """``--compare-fresh``: the grid again with a fresh process per run (``grid-fresh.db``), its throughput against
    the pool's and whether the results agree."""
    from climb_ompl.bench._runs import run_grid

    t0 = time.perf_counter()
    fresh = run_grid(grid, out / "grid-fresh.db", workers=workers, scheduler=scheduler, resume=False, worker_runs=1)
    fresh_s = time.perf_counter() - t0

    def outcome(rs: list[dict[str, Any]]) -> list[tuple[Any, ...]]:
        return [(r["solved"], r["status"], r["states_sampled"], r["path_length"]) for r in rs]

    return dict(fresh_s=fresh_s, runs_per_min_fresh=60.0 * n / fresh_s, reuse_speedup=fresh_s / pool_s,
                fresh_equals_reused=outcome(fresh) == outcome(results))


def _throughput_line(summary: dict[str, Any], n: int, pool_s: float, compare_serial: bool, compare_fresh: bool,
                     out: Path) -> str:
    """The command's last line: runs, seconds, runs per minute and the comparisons asked for."""
    rate = summary["runs_per_min_pool"]
    return (f"[grid] {n} runs in {pool_s:.1f} s" + (f" ({rate:.1f} runs/min" if rate else " (")
            + (f"; serial {summary['runs_per_min_serial']:.1f} runs/min, pool speedup {summary['pool_speedup']:.2f}x"
               if compare_serial else "")
            + (f"; a fresh process per run {summary['runs_per_min_fresh']:.1f} runs/min, reuse speedup "
               f"{summary['reuse_speedup']:.2f}x, same results: {summary['fresh_equals_reused']}"
               if compare_fresh else "") + f") -> {out}")
