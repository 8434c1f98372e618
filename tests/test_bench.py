"""Benchmark grid harness: isolated runs, local pool, Dask LocalCluster, SQLite DB, resume, plots.

The grid is small (RRT and RRTConnect x 2 spaces x 3 LEMUR one-step queries, a 600-check budget): both
planners are single-threaded and stop on the count budget (half of the runs solve, half do not), so serial,
pool and Dask runs must agree exactly.  The planner alone answers (``direct=False``): the lift-move-place
local path solves all three queries.  (LazyPRM checks too few states to reach the budget and would run to
the time limit instead.)
"""

from __future__ import annotations

import shutil
import sqlite3
from pathlib import Path
from typing import Any

import pytest

from climb_ompl.bench._runs import (
    CRASH_PLANNER,
    HANG_PLANNER,
    ID_KEYS,
    Grid,
    RunWorker,
    load_results,
    make_queries,
    open_db,
    run_grid,
    run_key,
    write_tidy,
)

pytestmark = pytest.mark.timeout(300)

OMPL_TABLES = {"experiments", "plannerConfigs", "runs", "progress", "enums"}


def _outcome(results: list[dict[str, Any]]) -> list[tuple[Any, ...]]:
    """What must repeat across executors: identity, solved, status and path length (rounded)."""
    return [tuple(r[k] for k in ID_KEYS) + (r["solved"], r["status"],
                                            None if r["path_length"] is None else round(r["path_length"], 9))
            for r in results]


@pytest.fixture(scope="module")
def queries() -> list[dict[str, Any]]:
    qs = make_queries("lemur", "demo-wall", 3, seed=0)
    assert len(qs) == 3
    return qs


@pytest.fixture(scope="module")
def grid(queries: list[dict[str, Any]]) -> Grid:
    return Grid(name="test-grid", planners=["RRT", "RRTConnect"], spaces=["atlas", "tangent_bundle"],
                samplers=["uniform"], queries=queries, seeds=[0], time_limit=30.0, max_iterations=600,
                hard_timeout=120.0, extra={"direct": False})


@pytest.fixture(scope="module")
def serial(grid: Grid, tmp_path_factory: pytest.TempPathFactory) -> tuple[Path, list[dict[str, Any]]]:
    db = tmp_path_factory.mktemp("serial") / "grid.db"
    return db, run_grid(grid, db, workers=1)


def test_queries_are_one_step_moves(queries: list[dict[str, Any]]) -> None:
    for q in queries:
        assert len(q["stance"]) == 3 and q["moving"] not in q["stance"]
        assert len(q["q_start"]) == len(q["q_goal"]) == 15
        assert q["from_hold"] != q["to_hold"]
    # deterministic: the same seed gives the same queries
    assert make_queries("lemur", "demo-wall", 1, seed=0)[0] == queries[0]


@pytest.mark.heavy
def test_serial_grid_database(grid: Grid, serial: tuple[Path, list[dict[str, Any]]]) -> None:
    db, results = serial
    assert len(results) == len(grid.runs()) == 12
    assert 3 <= sum(r["solved"] for r in results) <= 9  # solved and unsolved runs both occur
    for r in results:
        assert not r["crashed"] and not r["timed_out"]
        if r["solved"]:
            assert r["path_length"] > 0 and r["states_sampled"] > 0 and r["peak_rss_mb"] > 10
    con = sqlite3.connect(db)
    tables = {row[0] for row in con.execute("SELECT name FROM sqlite_master WHERE type='table'")}
    assert OMPL_TABLES | {"grid_runs"} <= tables
    assert con.execute("SELECT COUNT(*) FROM runs").fetchone()[0] == 12
    assert con.execute("SELECT COUNT(*) FROM grid_runs").fetchone()[0] == 12
    assert con.execute("SELECT COUNT(*) FROM plannerConfigs").fetchone()[0] == 4  # planner x space
    assert con.execute("SELECT COUNT(*) FROM experiments").fetchone()[0] == 1
    # OMPL's enum: solved runs carry "exact solution"
    n_exact = con.execute("SELECT COUNT(*) FROM runs r JOIN enums e ON e.name='status' AND e.value=r.status "
                          "WHERE e.description='exact solution'").fetchone()[0]
    assert n_exact == sum(r["solved"] for r in results)
    cols = {row[1] for row in con.execute("PRAGMA table_info(runs)")}
    assert {"experimentid", "plannerid", "time", "solved", "status", "solution_length", "graph_states",
            "memory"} <= cols
    con.close()


@pytest.mark.heavy
def test_resume_skips_finished_runs(grid: Grid, serial: tuple[Path, list[dict[str, Any]]], tmp_path: Path) -> None:
    db = tmp_path / "grid.db"
    shutil.copy(serial[0], db)
    calls: list[int] = []
    again = run_grid(grid, db, workers=1, progress=lambda k, n: calls.append(n))
    assert calls == [] and _outcome(again) == _outcome(serial[1])
    # forget two runs (an interrupted grid): only those two run again
    con = open_db(db)
    keys = [run_key(r) for r in grid.runs()[:2]]
    for k in keys:
        (runid,) = con.execute("SELECT runid FROM grid_runs WHERE key = ?", (k,)).fetchone()
        con.execute("DELETE FROM grid_runs WHERE key = ?", (k,))
        con.execute("DELETE FROM runs WHERE id = ?", (runid,))
    con.commit()
    con.close()
    calls.clear()
    again = run_grid(grid, db, workers=2, progress=lambda k, n: calls.append(n))
    assert calls == [2, 2]
    assert _outcome(again) == _outcome(serial[1])
    con = sqlite3.connect(db)
    assert con.execute("SELECT COUNT(*) FROM runs").fetchone()[0] == 12
    con.close()


@pytest.mark.heavy
def test_process_pool_matches_serial(grid: Grid, serial: tuple[Path, list[dict[str, Any]]], tmp_path: Path) -> None:
    pool = run_grid(grid, tmp_path / "pool.db", workers=2)
    assert _outcome(pool) == _outcome(serial[1])


@pytest.mark.slow
def test_dask_local_cluster_matches_serial(grid: Grid, serial: tuple[Path, list[dict[str, Any]]],
                                           tmp_path: Path) -> None:
    distributed = pytest.importorskip("distributed")
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True, dashboard_address=":0",
                                  scheduler_kwargs={"dashboard": False}, silence_logs=40) as cluster, \
            distributed.Client(cluster) as client:
        dask = run_grid(grid, tmp_path / "dask.db", scheduler=client)
        # the address form too (a fresh Client per grid), on a one-run grid
        one = Grid(name="addr", planners=["RRT"], spaces=["atlas"], samplers=["uniform"],
                   queries=grid.queries[:1], time_limit=30.0, max_iterations=600, extra={"direct": False})
        by_addr = run_grid(one, tmp_path / "addr.db", scheduler=cluster.scheduler_address)
    assert _outcome(dask) == _outcome(serial[1])
    assert _outcome(by_addr) == [o for o in _outcome(serial[1]) if o[:3] == ("RRT", "atlas", "uniform")
                                 and o[3] == 0]


@pytest.mark.heavy
def test_crash_and_hang_are_recorded_and_grid_continues(queries: list[dict[str, Any]], tmp_path: Path) -> None:
    g = Grid(name="faults", planners=[CRASH_PLANNER, HANG_PLANNER, "RRT"], spaces=["atlas"],
             samplers=["uniform"], queries=queries[:1], time_limit=5.0, max_iterations=600, hard_timeout=8.0)
    # (the hard timeout leaves the normal run room on a loaded machine: its model loading is not guarded; in its
    # fresh child it takes about 1 s, solved on the check budget, so 8 s is 8 times that and past its time limit;
    # the hung run costs the whole hard timeout)
    res = {r["planner"]: r for r in run_grid(g, tmp_path / "faults.db", workers=3)}
    assert res[CRASH_PLANNER]["crashed"] and not res[CRASH_PLANNER]["solved"]
    assert res[HANG_PLANNER]["timed_out"] and not res[HANG_PLANNER]["solved"]
    assert res[HANG_PLANNER]["time"] >= 8.0
    # the normal run beside them finished on its own (solved or not): the faults did not take it down
    assert not res["RRT"]["crashed"] and not res["RRT"]["timed_out"] and res["RRT"]["status"]
    con = sqlite3.connect(tmp_path / "faults.db")
    rows = dict(con.execute("SELECT p.name, r.crashed + 2 * r.timed_out FROM runs r "
                            "JOIN plannerConfigs p ON p.id = r.plannerid"))
    con.close()
    assert rows == {f"geometric_{CRASH_PLANNER}": 1, f"geometric_{HANG_PLANNER}": 2, "geometric_RRT": 0}


@pytest.mark.heavy
def test_a_reused_worker_repeats_a_fresh_process(grid: Grid) -> None:
    """A run gives the same result in a fresh child and in one that ran other runs before (other planner,
    other seed: every run re-seeds OMPL and numpy, seed 0 included, which OMPL alone would ignore once it
    has sampled); a crash costs the child, and the next run gets a fresh one with the same result again."""
    runs = grid.runs()
    run = next(r for r in runs if r["planner"] == "RRTConnect" and r["seed"] == 0)
    other = {**next(r for r in runs if r["planner"] == "RRT" and r["query"] != run["query"]), "seed": 7}
    with RunWorker(max_runs=1) as w:
        fresh = w.run(run, 120.0)
    with RunWorker() as w:
        first = w.run(other, 120.0)
        again = w.run(run, 120.0)
        crash = w.run({**run, "planner": CRASH_PLANNER}, 60.0)
        after = w.run(run, 120.0)
        assert w.started == 2
    assert not first["crashed"] and crash["crashed"] and not crash["solved"] and crash["error"]
    assert _outcome([again]) == _outcome([after]) == _outcome([fresh])
    assert again["states_sampled"] == fresh["states_sampled"] and again["peak_rss_mb"] > 10


@pytest.mark.heavy
def test_tidy_csv_and_report(serial: tuple[Path, list[dict[str, Any]]], tmp_path: Path) -> None:
    import pandas as pd

    from climb_ompl.cli import main

    results = load_results(serial[0])
    df = pd.read_csv(write_tidy(results, tmp_path / "runs.csv"))
    assert len(df) == 12 and set(df["planner"]) == {"RRT", "RRTConnect"}
    assert df["solved"].sum() == sum(r["solved"] for r in results)
    assert main(["bench", "report", str(serial[0]), "--out", str(tmp_path / "plots")]) == 0
    for stem in ("success_vs_time", "times", "rejections", "heatmap"):
        for ext in ("png", "svg"):
            assert (tmp_path / "plots" / f"{stem}.{ext}").stat().st_size > 1000
    assert main(["bench", "report", str(tmp_path / "missing.db"), "--out", str(tmp_path)]) == 2


@pytest.mark.parametrize("text, field", [("holds: [\n  - id: a\n", "YAML"), ("name: w\nholds: 3\n", "holds")])
def test_onestep_benchmark_rejects_a_malformed_wall(cli, tmp_path: Path, text: str, field: str) -> None:
    """A malformed terrain file is a one-line error naming the file (exit 2), not a generated stand-in wall."""
    wall = tmp_path / "wall.yaml"
    wall.write_text(text)
    out = tmp_path / "onestep.json"
    r = cli("bench", "onestep", "--terrain", wall, "--queries", "1", "--out", out)
    assert r.code == 2, r.err
    (line,) = r.err.strip().splitlines()
    assert line.startswith("error: ") and str(wall) in line and field.lower() in line.lower()
    assert not out.exists()
    r = cli("bench", "onestep", "--terrain", tmp_path / "missing.yaml", "--queries", "1")
    assert r.code == 2 and "missing.yaml" in r.err


@pytest.mark.heavy
def test_planner_arena_reads_the_grid_database(cli, tmp_path: Path) -> None:
    """``bench grid --preset tiny`` writes a database that Planner Arena's own loader reads: runs, planners, attributes.

    The oracle is OMPL's Planner Arena (the ``plannerarena`` package, ``plannerarena.database.load_database``),
    compared with this project's reader of the same file.
    """
    pytest.importorskip("plannerarena")
    import polars as pl
    from plannerarena.database import load_database

    r = cli("bench", "grid", "--preset", "tiny", "--out", tmp_path, "--workers", "1")
    assert r.code == 0, r.err
    ours = {res["planner"]: res for res in load_results(tmp_path / "grid.db")}
    assert sorted(ours) == ["RRT", "RRTConnect"]
    arena = load_database(tmp_path / "grid.db")
    assert arena["problem_names"] == ["lemur@demo-wall:tiny"]
    runs = arena["runs"]
    assert runs.height == 2
    assert sorted(runs["planner"].cast(pl.String).to_list()) == ["RRT", "RRTConnect"]
    assert {"time", "solved", "status", "solution length", "graph states", "states sampled", "memory",
            "crashed", "timed out"} <= set(arena["attributes"])
    status = dict(arena["enums"].filter(pl.col("name").cast(pl.String) == "status").select("value", "description")
                  .iter_rows())
    for row in runs.iter_rows(named=True):
        mine = ours[str(row["planner"])]
        assert bool(row["solved"]) == mine["solved"] and row["time"] == pytest.approx(mine["time"])
        assert (status[row["status"]] == "exact solution") == mine["solved"]
        assert row["experiment"] == "lemur@demo-wall:tiny" and not row["crashed"]


def test_bench_climb_compare_settings_are_checked():
    """``bench climb --compare`` takes a search mode or key=value settings, each checked before any climb."""
    from climb_ompl.bench.climb import compare_settings
    from climb_ompl.errors import PlannerNotFound, QueryError

    assert compare_settings("paper") == {"search": "paper"}
    assert compare_settings("planner=LazyPRM,space=projected,path_iterations=500") == {
        "planner": "LazyPRM", "space": "projected", "path_iterations": 500}
    with pytest.raises(QueryError, match="neither a search mode"):
        compare_settings("fast")
    with pytest.raises(QueryError, match="unknown setting"):
        compare_settings("speed=3")
    with pytest.raises(PlannerNotFound):
        compare_settings("planner=Dijkstra")
    with pytest.raises(QueryError, match="projected"):  # a custom sampler on the default tangent-bundle space
        compare_settings("sampler=straight-elbow")


@pytest.mark.heavy
def test_bench_climb_rejects_a_bad_compare_before_climbing(tmp_path):
    """A bad ``--compare`` is bad input: exit 2 with the reason, no climb run, no file written."""
    import subprocess
    import sys

    out = tmp_path / "c.json"
    r = subprocess.run([sys.executable, "-m", "climb_ompl", "bench", "climb", "--compare", "planner=Dijkstra",
                        "--out", str(out)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 2, r.stderr
    assert "Dijkstra" in r.stderr and "RRTConnect" in r.stderr  # names the bad value and the valid ones
    assert not out.exists()
