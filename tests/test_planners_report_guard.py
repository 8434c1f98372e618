"""docs/planners.md counts the runs the wall-clock guard stopped before their check budget, and names what the
database records of its making (climb_ompl.bench._planners_report)."""

from __future__ import annotations

import sqlite3

import pytest

from climb_ompl import __version__
from climb_ompl.bench._planners_report import experiment_info, guard_stopped, table, write_page
from climb_ompl.bench._runs import Grid, _experiment, load_results, open_db, store

BUDGET, GUARD = 2000, 5.0


def _run(planner: str, space: str, query: int, *, solved: bool, status: str, t: float, checks: int,
         crashed: bool = False, timed_out: bool = False) -> dict:
    return {"planner": planner, "space": space, "sampler": "uniform", "query": query, "seed": 1,
            "time_limit": GUARD, "max_iterations": BUDGET, "direct_first": False, "query_set": "lemur-demo-wall",
            "solved": solved, "status": status, "time": t, "path_length": 1.0 if solved else None,
            "states_sampled": checks, "samples": None, "roadmap_size": 10, "peak_rss_mb": 100.0,
            "crashed": crashed, "timed_out": timed_out, "rejections": {}, "direct_solved": False}


#: RRT/projected: one run the guard stopped after 150 checks (unsolved, as find_path reports it: ``timeout``),
#: one that used its budget (no path), one solved quickly.  LazyPRMstar/atlas: an anytime planner returning
#: its path at the guard (solved, 700 checks).  FMT/atlas: over the guard's time but past its check budget
#: too (the budget ended it), a crash and a hard-timeout kill: none of them is the guard's.
RUNS = [
    _run("RRT", "projected", 1, solved=False, status="timeout", t=5.02, checks=150),
    _run("RRT", "projected", 2, solved=False, status="no-path", t=0.8, checks=2010),
    _run("RRT", "projected", 3, solved=True, status="exact", t=0.3, checks=400),
    _run("LazyPRMstar", "atlas", 1, solved=True, status="exact", t=5.01, checks=700),
    _run("FMT", "atlas", 1, solved=False, status="no-path", t=6.5, checks=21000),
    _run("FMT", "atlas", 2, solved=False, status="crash", t=7.0, checks=0, crashed=True),
    _run("FMT", "atlas", 3, solved=False, status="timeout", t=45.0, checks=0, timed_out=True),
]


def _db(tmp_path, runs=RUNS):
    db = tmp_path / "grid.db"
    con = open_db(db)
    exp = _experiment(con, Grid(name="compare", planners=[], spaces=[], samplers=[], queries=[]))
    for r in runs:
        store(con, exp, {**r, "direct": False}, r)
    con.close()
    return db


def test_guard_stopped_is_time_at_the_guard_with_checks_left():
    assert [guard_stopped(r) for r in RUNS] == [True, False, False, True, False, False, False]
    # a run just short of the guard did not meet it; without a check budget the guard is the only stop
    assert not guard_stopped({**RUNS[0], "time": 4.99})
    assert guard_stopped({**RUNS[1], "time": 5.0, "max_iterations": None})


@pytest.mark.heavy
def test_table_and_page_count_the_runs_the_guard_stopped(tmp_path):
    db = _db(tmp_path)
    rows = {r["config"]: r for r in table(load_results(db))}
    got = {c: (r["guard"], r["guard_unsolved"], r["guard_checks"]) for c, r in rows.items()}
    assert got == {"RRT/projected/uniform": (1, 1, 150.0), "LazyPRMstar/atlas/uniform": (1, 0, 700.0),
                   "FMT/atlas/uniform": (0, 0, None)}
    page = tmp_path / "planners.md"
    write_page(db, page, grid_runs=7)
    text = page.read_text()
    # the set-up no longer claims one budget for every run, and says how many runs the guard cut short
    assert "The same budget per run" not in text
    assert ("the guard stopped 2 of the 7 runs (29 %) before they used it, 1 of them unsolved and 1 solved "
            "(paths returned at the guard: LazyPRMstar 1)") in text
    assert "in 2 of the 3 configurations" in text and "depend on the machine's load" in text
    # the table's guard column: RRT 1 (1 unsolved), LazyPRMstar 1 (0), FMT none; crashed and killed apart
    assert "| RRT/projected/uniform | 1/3 | 33 % |" in text
    line = next(x for x in text.splitlines() if x.startswith("| ") and "| RRT/projected/uniform |" in x
                and "| 1/3 |" in x)
    assert line.endswith("| 1 (1) | 0 | 0 |"), line
    lazy = next(x for x in text.splitlines() if "| LazyPRMstar/atlas/uniform | 1/1 |" in x)
    assert lazy.endswith("| 1 (0) | 0 | 0 |"), lazy
    fmt = next(x for x in text.splitlines() if "| FMT/atlas/uniform | 0/3 |" in x)
    assert fmt.endswith("| 0 | 1 | 1 |"), fmt
    # the section lists the configurations with unsolved guard-stopped runs, with the checks they used
    assert "## Runs the guard stopped" in text
    assert "| RRT/projected/uniform | 1/3 | 1 | 1 | 150 |" in text
    assert "| LazyPRMstar/atlas/uniform | 1/1 | 1 | 0 |" not in text


@pytest.mark.heavy
def test_page_without_guard_stops_says_every_run_had_its_budget(tmp_path):
    db = _db(tmp_path, [r for r in RUNS if not guard_stopped(r)])
    page = tmp_path / "planners.md"
    write_page(db, page, grid_runs=5)
    text = page.read_text()
    assert "The guard stopped no run before its check budget" in text and "## Runs the guard stopped" not in text


@pytest.mark.heavy
def test_page_names_the_databases_version_and_date(tmp_path):
    db = _db(tmp_path)
    with sqlite3.connect(db) as con:
        con.execute("UPDATE experiments SET date = '2026-12-01 20:01:23', hostname = 'vm', cpuinfo = '2 cpus', "
                    "totaltime = 600")
    exp = experiment_info(db)
    assert exp["version"] == f"climb_ompl {__version__}" and exp["date"] == "2026-12-01 20:01:23"
    page = tmp_path / "planners.md"
    write_page(db, page, grid_runs=7)
    text = page.read_text()
    assert (f"The database records `climb_ompl {__version__}` and the start of its first run, 2026-12-01 "
            "20:01:23 UTC (`experiments` table; host `vm`, 2 cpus, `totaltime` 10 min)") in text
    assert "It records no commit" in text
