"""Planner comparison: the versioned query sets, the comparison grid, docs/planners.md from a database."""

from __future__ import annotations

import json
import math
import sqlite3

import numpy as np
import pytest

from climb_ompl.bench._planners_report import (
    Z95,
    climb_default,
    config_of,
    mcnemar_exact,
    paired,
    per_set,
    recommendation,
    success_rank,
    table,
    wilson,
    write_page,
)
from climb_ompl.bench._query_set import (
    SETS,
    check_query,
    load_queries,
    load_set,
    one_hold_points,
    queries_dir,
    reference_range,
    spec,
)
from climb_ompl.bench._runs import Grid, _experiment, load_results, open_db, run_grid, run_key, store
from climb_ompl.bench.compare import COMPARE, build_compare_grid, sample_runs
from climb_ompl.errors import InputError
from climb_ompl.manifold._ompl import PLANNER_NAMES
from climb_ompl.manifold.stance import Stance
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain


# ---- query sets ------------------------------------------------------------------------------------------
@pytest.mark.parametrize("spec", SETS, ids=lambda s: s.name)
def test_query_set_loads_and_every_query_passes_the_stance_checks(spec):
    data = load_set(spec.name)
    qs = data["queries"]
    assert len(qs) >= 30 and data["robot"] == spec.robot
    assert [q["uid"] for q in qs] == [1000 * spec.number + i for i in range(len(qs))]
    assert {q["kind"] for q in qs} <= {"grab", "release"} and any(q["kind"] == "grab" for q in qs)
    for q in qs:
        h = q["hardness"]
        assert 0 <= h["solved"] <= h["runs"] and math.isclose(h["success"], h["solved"] / h["runs"])
        assert q["set"] == spec.name and q["terrain"]
        assert check_query(q) is None, (q["uid"], check_query(q))
        if q["kind"] == "grab":  # the moving limb is off the stance, the others hold
            assert q["moving"] not in q["stance"] and q["to_hold"] not in q["stance"].values()


def test_check_query_rejects_a_start_off_its_holds():
    q = dict(load_set("lemur-demo-wall")["queries"][0])
    q["q_start"] = list(np.asarray(q["q_start"]) + np.r_[0.05, np.zeros(len(q["q_start"]) - 1)])
    assert "from its hold" in check_query(q)


def test_uids_are_unique_across_sets_and_per_set_spreads_hardness():
    everything = load_queries()
    assert len({q["uid"] for q in everything}) == len(everything) >= 30 * len(SETS)
    picked = load_queries(["lemur-lean35-65"], per_set=4)
    assert len(picked) == 4
    rates = {q["hardness"]["success"] for q in picked}
    assert len(rates) >= 2  # from easy to hard, not four of the same grade
    # the median query of each set is among the default grid's three (a small run's runs stay in the big grid)
    assert {q["uid"] for q in load_queries(per_set=1)} <= {q["uid"] for q in load_queries(per_set=3)}


def test_load_set_names_file_and_field(tmp_path):
    bad = tmp_path / "x.json"
    bad.write_text(json.dumps({"format": "climb_ompl.queries/1", "name": "x", "robot": "lemur",
                               "terrain": "demo-wall", "queries": [{"uid": 0}]}))
    with pytest.raises(InputError, match=r"x\.json: queries\[0\]\.kind: missing"):
        load_set(bad)
    with pytest.raises(InputError, match="bundled: lemur-demo-wall"):
        load_set("no-such-set")


def test_generated_walls_are_bundled_beside_the_sets():
    for s in SETS:
        if s.wall is not None or s.terrain.endswith(".yaml"):
            assert (queries_dir() / s.terrain).is_file()
    assert "go1" in {s.robot for s in SETS}  # a quadruped set (on the stepping-stone ramp)


# ---- the double-link set (Bretl, Latombe & Rock (2003); Bretl (2006), sec. 2.1, Fig. 3-6 and 13) ----------------
def test_double_link_queries_go_between_pegs_of_its_stance_graph():
    """Forward kinematics, not the generator: each query holds one peg with one hand, and the other hand is on
    its from-peg at the start and on its to-peg at the goal; the stance graph is a star around peg 2 (pegs
    1, 3, 4 are more than two links apart); all eight one-peg stances contribute, and some queries wind an
    angle by more than half a turn (the whole-turn variants of the +-2 pi joints)."""
    data = load_set("double-link-pegs")
    robot, terrain = RobotModel.load("double-link"), Terrain.load("pegs")
    names = [lb.name for lb in robot.limbs]
    stances, winding = set(), 0
    for q in data["queries"]:
        ((held, peg),) = q["stance"].items()
        for cfg, hold in ((q["q_start"], q["from_hold"]), (q["q_goal"], q["to_hold"])):
            hands = robot.hand_positions(np.asarray(cfg))
            assert np.linalg.norm(hands[names.index(q["moving"])] - terrain.hold(hold).p) < 1e-6, q["uid"]
            assert np.linalg.norm(hands[names.index(held)] - terrain.hold(peg).p) < 1e-6, q["uid"]
        assert {q["from_hold"], q["to_hold"]} <= ({"1", "3", "4"} if peg == "2" else {"2"})
        stances.add((held, peg))
        winding += float(np.max(np.abs(np.subtract(q["q_goal"], q["q_start"])[2:]))) > np.pi
    assert len(stances) == 8 and winding >= 5
    assert data["generator"]["source"] == spec("double-link-pegs").source == "points"


@pytest.mark.heavy
@pytest.mark.parametrize("held,moving", [("a", "b"), ("b", "a")])
def test_double_link_components_on_peg_2_give_the_route_of_fig_13(held, moving):
    """Bretl (2006), Fig. 6 and 13: holding peg 2, the free hand can go from peg 1 to peg 3 and from peg 3
    to peg 4, never from peg 1 to peg 4 (the direct route 1 -> 2 -> 4 is blocked, the climb goes
    1 -> 2 -> 3 -> 2 -> 4): the components of the transition points onto pegs 1 and 4 are disjoint."""
    pts = one_hold_points("double-link", "pegs", Stance({held: "2"}), grid=121)  # the generator uses a finer grid
    comp = {h: {c for m, hh, _, c in pts if hh == h and m == moving and c} for h in "134"}
    assert all(comp.values()) and len(pts) == 24  # 8 points per peg: 2 elbow bends x 4 whole-turn variants
    assert not comp["1"] & comp["4"]
    assert comp["1"] & comp["3"] and comp["3"] & comp["4"]


@pytest.mark.heavy
def test_double_link_grades_replay_and_its_hardest_pick_has_a_path():
    """The comparison's picks of the double-link set: the reference planner on the stored configurations gives
    the stored grade again (the grade is taken on the file's rounded values), and the pick the reference never
    solved at its budget is solved with ten times the budget (a path exists, as the components say)."""
    from climb_ompl.bench._runs import run_query

    data = load_set("double-link-pegs")
    ref = data["reference"]
    picks = load_queries(["double-link-pegs"], per_set=COMPARE["per_set"])
    graded = next(q for q in picks if 0 < q["hardness"]["solved"] < q["hardness"]["runs"])
    scale = reference_range(ref, data["robot"], graded["terrain"])  # OMPL's range and rho, as graded
    runs = [run_query(graded, planner=ref["planner"], space=ref["space"], sampler=ref["sampler"], seed=s,
                      time_limit=float(ref["time_limit"]), max_iterations=ref["max_iterations"], direct=False,
                      **scale)
            for s in ref["seeds"]]
    assert sum(r["solved"] for r in runs) == graded["hardness"]["solved"]
    hard = next(q for q in picks if q["hardness"]["solved"] == 0)
    res = run_query(hard, planner=ref["planner"], space=ref["space"], seed=1, time_limit=60.0,
                    max_iterations=10 * ref["max_iterations"], direct=False, **scale)
    assert res["solved"], res
    # graded on seeds the comparison does not use: its picks are not chosen by the default's own runs
    assert not set(ref["seeds"]) & set(COMPARE["seeds"])


# ---- the comparison grid ---------------------------------------------------------------------------------
def test_compare_grid_covers_every_planner_space_and_sampler_with_one_budget():
    grid = build_compare_grid(per_set=1)  # the default grid takes 3 per set
    runs = grid.runs()
    n_q, n_s = len(grid.queries), len(COMPARE["seeds"])
    assert n_q == len(SETS) and n_s >= 3
    # uniform on the three spaces + the custom sampler on the projected space
    assert len(runs) == len(PLANNER_NAMES) * (len(COMPARE["spaces"]) + len(COMPARE["samplers"]) - 1) * n_q * n_s
    assert {r["planner"] for r in runs} == set(PLANNER_NAMES)
    assert {(r["max_iterations"], r["time_limit"], r["direct"]) for r in runs} == {
        (COMPARE["max_iterations"], COMPARE["time_limit"], False)}
    assert all(r["space"] == "projected" for r in runs if r["sampler"] != "uniform")
    assert len({run_key(r) for r in runs}) == len(runs)
    sub = sample_runs(runs, 7)
    assert len(sub) == 7 and sub == sample_runs(runs, 7) and all(r in runs for r in sub)


@pytest.mark.heavy
def test_a_comparison_run_stores_its_query_set_and_resumes(tmp_path):
    """One real run (the planar robot's median query, RRTConnect on the atlas): the database keys it with
    ``direct`` and the result names its query set; running again executes nothing."""
    q = load_queries(["planar-3limb-planar-wall"], per_set=1)
    grid = Grid(name="t", planners=["RRTConnect"], spaces=["atlas"], samplers=["uniform"], queries=q, seeds=[0],
                time_limit=5.0, max_iterations=2000, extra={"direct": False})
    db = tmp_path / "grid.db"
    res = run_grid(grid, db, workers=1)
    assert len(res) == 1 and res[0]["query_set"] == "planar-3limb-planar-wall" and res[0]["direct_first"] is False
    assert res[0]["solved"] and res[0]["direct_solved"] is False and res[0]["query"] == q[0]["uid"]
    calls = []
    run_grid(grid, db, workers=1, progress=lambda k, n: calls.append(k))
    assert calls == []


# ---- the report ------------------------------------------------------------------------------------------
def test_wilson_interval_closed_forms_and_newcombe():
    z2 = Z95 ** 2
    for n in (1, 7, 30):
        assert wilson(0, n) == pytest.approx((0.0, z2 / (n + z2)))
        assert wilson(n, n) == pytest.approx((n / (n + z2), 1.0))
        for k in range(n + 1):
            lo, hi = wilson(k, n)
            lo2, hi2 = wilson(n - k, n)
            assert lo == pytest.approx(1 - hi2) and hi == pytest.approx(1 - lo2) and lo <= k / n <= hi
    # Newcombe (1998), Statistics in Medicine 17, Table II, method 3 (score interval)
    assert wilson(81, 263) == pytest.approx((0.2553, 0.3662), abs=1e-4)
    assert wilson(15, 148) == pytest.approx((0.0624, 0.1605), abs=1e-4)


def test_mcnemar_exact_is_the_two_sided_sign_test():
    assert mcnemar_exact(0, 0) == 1.0 and mcnemar_exact(3, 3) == 1.0
    assert mcnemar_exact(5, 0) == pytest.approx(2 / 32)  # all five discordant pairs one way
    assert mcnemar_exact(1, 9) == pytest.approx(2 * (1 + 10) / 1024)
    assert mcnemar_exact(2, 7) == mcnemar_exact(7, 2)


def _fake(planner, space, sampler, query, seed, solved, t, checks):
    return {"planner": planner, "space": space, "sampler": sampler, "query": query, "seed": seed,
            "time_limit": 5.0, "max_iterations": 2000, "direct_first": False, "query_set": "lemur-demo-wall",
            "solved": solved, "status": "exact" if solved else "no-path", "time": t, "path_length": 1.0 if solved
            else None, "states_sampled": checks, "samples": None, "roadmap_size": 10, "peak_rss_mb": 100.0,
            "crashed": False, "timed_out": False, "rejections": {"collision": 3}, "direct_solved": False}


@pytest.mark.heavy
def test_report_page_from_a_tiny_database(tmp_path):
    """RRTConnect/atlas solves 20 of 20, LazyPRM/projected 2 of 10 (uniform) and 5 of 10 (custom): the page
    ranks them so, with the Wilson intervals, the sampler effect (+30 points) and a separated recommendation
    (20/20 has the lower bound 20 / (20 + z^2) = 84 %, above 5/10's upper bound, 76 %)."""
    db = tmp_path / "grid.db"
    con = open_db(db)
    exp = _experiment(con, Grid(name="tiny", planners=[], spaces=[], samplers=[], queries=[]))
    custom = COMPARE["samplers"][1]
    cells = [("RRTConnect", "atlas", "uniform", 20, 20), ("LazyPRM", "projected", "uniform", 10, 2),
             ("LazyPRM", "projected", custom, 10, 5)]
    for planner, space, sampler, n, k in cells:
        for i in range(n):
            r = _fake(planner, space, sampler, i, 0, i < k, 0.1 + 0.01 * i, 100 + 10 * i)
            store(con, exp, {**r, "direct": False}, r)
    con.close()
    rows = table(load_results(db))
    assert [r["config"] for r in rows] == ["RRTConnect/atlas/uniform", "LazyPRM/projected/custom",
                                           "LazyPRM/projected/uniform"]
    rec = recommendation(rows)
    assert rec["best"] == "RRTConnect/atlas/uniform" and rec["separated"]
    page = tmp_path / "docs" / "planners.md"
    page.parent.mkdir()
    write_page(db, page, copy_db=tmp_path / "docs" / "planners.db", grid_runs=2000)
    text = page.read_text()
    assert "| 1 | RRTConnect/atlas/uniform | 20/20 | 100 % | 84 %-100 % |" in text
    assert "**RRTConnect/atlas/uniform**: 20/20" in text and "the data supports it clearly" in text
    assert "small run: 40 runs of the 2000-run grid" in text
    # the climb's default (read from ClimbSettings) is named with its rank by success rate
    p, s, sa = climb_default()
    default = config_of({"planner": p, "space": s, "sampler": sa})
    rank = success_rank(rows, default)
    if rank is None:
        assert f"The climb's FIND-PATH default ({default}, `ClimbSettings`) is not in this run." in text
    else:
        assert f"({default}, `ClimbSettings`) solves" in text and f"it ranks {rank[0]} of 3" in text
    # paired by (query, seed): custom solves queries 0-4, uniform 0-1: 3 custom-only pairs, p = 2 / 2^3
    assert "| LazyPRM | 2/10 (20 %) | 5/10 (50 %) | +30 points | 10 | 3 | 0 | 0.25 |" in text
    # the same split through the generic pairing (queries 0-9, seed 0)
    pr = paired(load_results(db), "LazyPRM/projected/custom", "LazyPRM/projected/uniform")
    assert pr == {"pairs": 10, "only_a": 3, "only_b": 0, "p": 0.25}
    for fig in ("success_vs_budget", "times", "heatmap", "sampler_effect"):
        assert (tmp_path / "docs" / "planners" / f"{fig}.png").stat().st_size > 1000
        assert f"(planners/{fig}.png)" in text
    with sqlite3.connect(tmp_path / "docs" / "planners.db") as c:
        assert c.execute("SELECT COUNT(*) FROM runs").fetchone()[0] == 40


def test_per_set_counts_each_configuration_by_query_set():
    rs = [_fake("BiEST", "atlas", "uniform", 1, s, s != 2, 0.1, 100) for s in (1, 2, 3)]
    rs += [{**_fake("BiEST", "atlas", "uniform", 5000, 1, True, 0.1, 100), "query_set": "double-link-pegs"}]
    rs += [_fake("RRTConnect", "atlas", "uniform", 1, 1, False, 0.1, 100)]
    assert per_set(rs, ["BiEST/atlas/uniform"]) == {
        "BiEST/atlas/uniform": {"double-link-pegs": (1, 1), "lemur-demo-wall": (2, 3)}}


def test_success_rank_counts_strictly_better_rates_and_ties():
    rows = [{"config": c, "rate": r} for c, r in (("a", 1.0), ("b", 1.0), ("c", 0.9), ("d", 0.9), ("e", 0.5))]
    assert [success_rank(rows, c) for c in "abcde"] == [(1, 1), (1, 1), (3, 1), (3, 1), (5, 0)]
    assert success_rank(rows, "z") is None


def test_report_refuses_an_empty_database(tmp_path):
    db = tmp_path / "grid.db"
    open_db(db).close()
    with pytest.raises(InputError, match="holds no runs"):
        write_page(db, tmp_path / "p.md")
    assert not (tmp_path / "p.md").exists()


def test_published_comparison_ranks_the_climbs_default_in_the_top_3():
    """The climb's FIND-PATH default (``ClimbSettings``) is among the three best configurations by success rate
    at the equal budget in the published comparison (docs/planners.db, written by ``make compare``): fewer than
    three configurations solve a larger share of their runs, and every configuration ran the same 54 runs."""
    from pathlib import Path

    db = Path(__file__).resolve().parents[1] / "docs" / "planners.db"
    rows = table(load_results(db))
    assert {r["runs"] for r in rows} == {54}
    dp, ds, dsa = climb_default()
    by_rate, _ = success_rank(rows, f"{dp}/{ds}/{dsa}")
    assert by_rate <= 3, [(r["config"], r["solved"]) for r in rows[:6]]
