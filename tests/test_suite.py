"""``climb-ompl bench suite`` on a small subset with a short climb: the files, the statuses, resuming."""

from __future__ import annotations

import json
import math

import pytest

from climb_ompl.bench.suite import TERRAINS, run_suite, terrain_path
from climb_ompl.climb.goal import climb_height
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain


@pytest.mark.parametrize("name", sorted(TERRAINS))
def test_suite_terrains_load(name):
    """Every terrain of the suite is a valid terrain file (or a bundled name) with "up" along minus gravity."""
    t = Terrain.load(terrain_path(name))
    assert len(t.holds) > 100 and t.dim == 3


def test_goal_height_is_a_climb_along_the_slope():
    """On the 15-degree ramp a metre along the slope is sin(15 deg) metres of height; the goal adds the reach
    (a height goal is met with every hold at or above the goal minus the largest reach)."""
    t = Terrain.load(terrain_path("stepping-stone-ramp-3m"))
    go1 = RobotModel.load("go1")
    st = {"fl": "s3_4", "fr": "s3_2", "rl": "s0_4", "rr": "s0_2"}
    top = max(t.height(h) for h in st.values())
    assert climb_height(go1, t, st, 1.0) - top - 0.506 == pytest.approx(0.2588, abs=1e-3)
    # the report says how far the threshold lies above the start's highest and lowest holds (the hind feet climb
    # the second: a tall robot's "--climb 1" moves its lowest limbs farther than 1 m along the slope)
    from climb_ompl.climb.goal import Goal, height_report

    low = min(t.height(h) for h in st.values())
    line = height_report(Goal("height", height=climb_height(go1, t, st, 1.0)), go1, t, st)
    assert f"{math.sin(math.radians(15)):.3f} above the start's highest hold, " in line
    assert f"{math.sin(math.radians(15)) + top - low:.3f} above its lowest" in line
    # asked as --climb, it says the climb is along the slope (a user read 1.0 m of height for --climb 3)
    goal = Goal("height", height=climb_height(go1, t, st, 3.0))
    assert f"the climb of 3 m is measured along the wall's slope, {3 * math.sin(math.radians(15)):.3f} m of " \
        "height" in height_report(goal, go1, t, st, climb=3.0)
    wall = Terrain.load("demo-wall")  # vertical: nothing to add
    lemur = RobotModel.load("lemur")
    st = {"ne": "h36", "nw": "h33", "se": "h6", "sw": "h3"}
    assert "slope" not in height_report(Goal("height", height=climb_height(lemur, wall, st, 1.0)), lemur, wall, st,
                                        climb=1.0)
    # a hold a tenth of a millimetre below zero reads 0.000, not -0.000
    d = {"name": "z", "holds": [{"id": "a", "position": [0, 0, -0.0001], "normal": [0, 1, 0]},
                                {"id": "b", "position": [0.2, 0, 0.3], "normal": [0, 1, 0]}]}
    line = height_report(Goal("height", height=1.0), lemur, Terrain.from_dict(d), {"ne": "a", "nw": "b"})
    assert "start holds 0.000 to 0.300" in line and "-0.000" not in line


def test_the_height_report_says_when_the_goal_holds_span_less_than_the_start():
    """A board whose holds above the goal's threshold form one row: every limb must end in it, so the report says
    the terrain may end too soon (a user's HyQ spent its budget there); with two rows as far apart as the start's
    holds, or a lower goal, it says nothing of it."""
    from climb_ompl.climb.goal import Goal, height_report

    lemur = RobotModel.load("lemur")
    rows = [0.0, 0.3, 0.6, 0.9, 1.2]
    d = {"name": "board", "holds": [{"id": f"r{i}c{j}", "position": [0.2 * j, 0, z], "normal": [0, 1, 0]}
                                    for i, z in enumerate(rows) for j in range(4)]}
    wall, st = Terrain.from_dict(d), {"ne": "r1c0", "nw": "r1c3", "se": "r0c0", "sw": "r0c3"}
    reach = max(lb.reach for lb in lemur.limbs)
    note = "the terrain may end before every limb can stand up there"
    line = height_report(Goal("height", height=1.1 + reach), lemur, wall, st)  # only the top row is >= 1.1
    assert note in line
    assert "the terrain's 4 holds at or above 1.100 m span 0.000 m of height, the start stance's 0.300 m" in line
    assert note not in height_report(Goal("height", height=0.8 + reach), lemur, wall, st)  # two rows: 0.3 m
    assert note not in height_report(Goal("height", height=0.5 + reach), lemur, wall, st)


def test_plan_notes_a_narrow_goal_band_before_the_search(capsys):
    """``climb-ompl plan`` says so before its search (not only in the heights line after the budget is spent), once
    per climb when the start finder tries several starts."""
    from climb_ompl.cli.plan import _check_not_met
    from climb_ompl.climb.goal import Goal

    lemur = RobotModel.load("lemur")
    d = {"name": "board", "holds": [{"id": f"r{i}c{j}", "position": [0.2 * j, 0, z], "normal": [0, 1, 0]}
                                    for i, z in enumerate([0.0, 0.3, 0.6, 0.9, 1.2]) for j in range(4)]}
    wall, st = Terrain.from_dict(d), {"ne": "r1c0", "nw": "r1c3", "se": "r0c0", "sw": "r0c3"}
    goal = Goal("height", height=1.1 + max(lb.reach for lb in lemur.limbs))
    noted: set[str] = set()
    for _ in range(2):
        _check_not_met(goal, lemur, wall, st, noted)
    err = capsys.readouterr().err
    assert err.count("note: the terrain's 4 holds at or above") == 1 and "planning anyway" in err


@pytest.mark.climb
def test_suite_subset_infeasible_and_not_applicable(tmp_path, cli):
    """ANYmal-C on the overhang (it stands on four holds and lets go of one, but no grab follows: the stance graph
    is exhausted, with the frontier's diagnosis) and the planar robot on it (not applicable): suite.json, the
    table with the cause, the heat map; a second run resumes (nothing executed)."""
    out = tmp_path / "suite"
    r = cli("bench", "suite", "--out", out, "--robot", "anymal-c", "--robot", "planar-3limb",
            "--terrain", "overhang", "--climb", "0.3", "--budget", "60")
    assert r.code == 0, r.err
    data = json.loads((out / "suite.json").read_text())
    cells = {c["robot"]: c for c in data["cells"]}
    assert cells["planar-3limb"]["status"] == "n/a" and "3-D terrain" in cells["planar-3limb"]["reason"]
    a = cells["anymal-c"]
    assert a["status"] == "infeasible" and a["stage"] == "exhausted" and not a["found"]
    assert "the climb stopped at these stances" in a["reason"] and a["diagnosis"]
    assert data["counts"] == {"verified": 0, "unverified": 0, "infeasible": 1, "budget": 0, "n/a": 1, "crash": 0}
    md = (out / "suite.md").read_text()
    assert "| anymal-c | infeasible (" in md and "| planar-3limb | n/a |" in md and "Not applicable: planar-3limb" in md
    assert "- anymal-c on overhang: infeasible: at {" in md
    assert (out / "suite.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert "verified 0/1 applicable cells" in r.out
    again = run_suite(out, robots=["anymal-c", "planar-3limb"], terrains=["overhang"], climb=0.3, budget=60.0)
    assert again["executed"] == 0 and again["cells"] == data["cells"]
    # a second seed: a cell per seed (seed 0's resumed), the table giving how many verified over the seeds
    r = cli("bench", "suite", "--out", out, "--robot", "anymal-c", "--robot", "planar-3limb",
            "--terrain", "overhang", "--climb", "0.3", "--budget", "60", "--seed", "0", "--seed", "1")
    assert r.code == 0, r.err
    two = json.loads((out / "suite.json").read_text())
    assert two["executed"] == 2 and two["params"]["seeds"] == [0, 1] and len(two["cells"]) == 4
    assert [(c["robot"], c["seed"]) for c in two["cells"]] == [("anymal-c", 0), ("anymal-c", 1),
                                                                ("planar-3limb", 0), ("planar-3limb", 1)]
    assert (out / "cells" / "anymal-c__overhang__seed1.json").exists() and "anymal-c x overhang (seed 1): " in r.out
    md = (out / "suite.md").read_text()
    assert "| anymal-c | verified " in md and "/2" in md and "| planar-3limb | n/a |" in md
    assert "(a cell per seed)" in md


@pytest.mark.slow
def test_suite_cell_verified(tmp_path):
    """Go1 0.2 m up the 3 m ramp: found and verified (about a minute)."""
    data = run_suite(tmp_path, robots=["go1"], terrains=["stepping-stone-ramp-3m"], climb=0.2, budget=180.0)
    (c,) = data["cells"]
    assert c["status"] == "verified" and c["found"] and c["verified"] and c["steps"] > 0, c["reason"]
    assert c["goal_height"] > max(Terrain.load(terrain_path("stepping-stone-ramp-3m")).height(h)
                                  for h in c["start"].values())
    assert data["verified_share"] == 1.0


def test_suite_rejects_an_unknown_terrain(tmp_path, cli):
    r = cli("bench", "suite", "--out", tmp_path / "s", "--terrain", "nowhere")
    assert r.code == 2 and "--terrain" in r.err and "nowhere" in r.err and not (tmp_path / "s").exists()


def test_lemur_ratio_and_shares_from_the_cells():
    """The summary figures from cell records: the share verified among applicable cells, and LEMUR's median over the
    generated walls over its demo-wall time (a spent budget counts with its time, making the ratio a lower bound)."""
    from climb_ompl.bench.suite import _figures

    def cell(robot, terrain, status, seconds):
        return {"robot": robot, "terrain": terrain, "status": status, "seconds": seconds}

    rows = [cell("lemur", "demo-wall", "verified", 40.0), cell("lemur", "wall-lean35-65", "verified", 30.0),
            cell("lemur", "wall-lean55-80", "verified", 70.0), cell("planar-3limb", "demo-wall", "n/a", 0.0),
            cell("go1", "slab", "infeasible", 2.0)]
    f = _figures(rows)
    assert f["applicable"] == 4 and f["verified_share"] == 0.75 and f["unexplained"] == []
    g = f["lemur_generated_over_demo"]
    assert g["median_generated_s"] == 50.0 and g["ratio"] == 1.25 and not g["lower_bound"]
    rows[2] = cell("lemur", "wall-lean55-80", "budget", 180.0)
    assert _figures(rows)["lemur_generated_over_demo"]["lower_bound"]
    rows[0] = cell("lemur", "demo-wall", "budget", 180.0)
    assert "lemur_generated_over_demo" not in _figures(rows)


def test_lemur_ratio_over_several_seeds_is_a_ratio_of_medians():
    """Over several seeds each terrain's time is its median over the seeds (worked by hand below), each seed's own
    ratio is listed, and the ratio needs the demo wall verified at every seed."""
    from climb_ompl.bench.suite import _figures, _group_text

    times = {"demo-wall": (10.0, 20.0, 40.0), "wall-lean35-65": (30.0, 60.0, 90.0),
             "wall-lean55-80": (20.0, 20.0, 100.0)}
    rows = [{"robot": "lemur", "terrain": t, "seed": sd, "status": "verified", "seconds": s, "steps": 10 + sd,
             "cpu_s": s / 2 if t == "demo-wall" else s}
            for t, ts in times.items() for sd, s in enumerate(ts)]
    g = _figures(rows)["lemur_generated_over_demo"]
    # medians over the seeds: demo 20, lean35 60, lean55 20; over the generated walls 40; 40 / 20 = 2 (CPU: 40 / 10)
    assert g["median_generated_s"] == 40.0 and g["demo_wall_s"] == 20.0 and g["ratio"] == 2.0
    assert g["cpu_ratio"] == 4.0
    assert [(p["seed"], p["ratio"]) for p in g["per_seed"]] == [(0, 2.5), (1, 2.0), (2, 2.375)]
    assert _group_text(rows[3:6]) == "verified 3/3: median 60 s (30-90), 10-12 steps"
    rows[8] = {**rows[8], "status": "budget", "seconds": 180.0}
    g = _figures(rows)["lemur_generated_over_demo"]
    assert g["lower_bound"] and g["median_generated_s"] == 40.0 and [p["lower_bound"] for p in g["per_seed"]] == \
        [False, False, True]
    assert _group_text(rows[6:9]) == "verified 2/3: median 20 s (20-20), 10-11 steps; also budget"
    rows[1] = {**rows[1], "status": "infeasible"}
    assert "lemur_generated_over_demo" not in _figures(rows)


def test_suite_needs_a_climb_length_for_a_users_robot_spec(tmp_path, cli):
    """A spec file (``examples/go2.yaml``) in the suite needs ``--climb`` (the suite's lengths are per bundled
    robot): exit 2 naming the option, nothing written."""
    from conftest import ROOT
    from test_robot_quadrupeds import ramp_text

    ramp = tmp_path / "my-ramp.yaml"
    ramp.write_text(ramp_text())
    r = cli("bench", "suite", "--out", tmp_path / "none", "--robot", ROOT / "examples" / "go2.yaml", "--terrain", ramp)
    assert r.code == 2 and "--climb" in r.err and not (tmp_path / "none").exists()


@pytest.mark.slow
def test_suite_runs_a_users_robot_spec_on_a_users_terrain_file(tmp_path, cli):
    """A spec file (``examples/go2.yaml``) and a terrain file written by hand (the stepping stones of
    tests/test_robot_quadrupeds.py) in the suite: the cell is named by the files' stems and verified.  (Slow: the
    same spec climbs the same ramp in tests/test_robot_quadrupeds.py.)"""
    from conftest import ROOT
    from test_robot_quadrupeds import ramp_text

    ramp = tmp_path / "my-ramp.yaml"
    ramp.write_text(ramp_text())
    spec = ROOT / "examples" / "go2.yaml"
    out = tmp_path / "suite"
    # a short climb (0.1 m: 15 steps, planned in about 60 % of the time of 0.3 m): what is checked is the cell
    r = cli("bench", "suite", "--out", out, "--robot", spec, "--terrain", ramp, "--climb", "0.1", "--budget", "60")
    assert r.code == 0, r.err
    assert "go2 x my-ramp: verified" in r.out and (out / "cells" / "go2__my-ramp.json").exists()
    assert "| go2 | verified" in (out / "suite.md").read_text()
    cell = json.loads((out / "suite.json").read_text())["cells"][0]
    assert cell["status"] == "verified" and cell["steps"] >= 2 and cell["robot"] == str(spec)


def test_suite_inputs_do_not_share_a_cell(tmp_path, cli):
    """A spec file whose stem is a bundled robot's name, or two files with one stem, would write one cell record
    for two cells: exit 2 before any cell runs.  A stored record is reused only for the same robot, terrain and
    file contents."""
    from conftest import ROOT

    from climb_ompl.bench.suite import _digest, _same_cell

    spec = (ROOT / "examples" / "go2.yaml").read_text()
    (tmp_path / "go1.yaml").write_text(spec)
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "go2.yaml").write_text(spec)
    for robots in ([tmp_path / "go1.yaml"], [ROOT / "examples" / "go2.yaml", tmp_path / "a" / "go2.yaml"]):
        args = [x for p in robots for x in ("--robot", p)]
        r = cli("bench", "suite", "--out", tmp_path / "s", "--climb", "0.3", *args)
        assert r.code == 2 and "rename the file" in r.err and not (tmp_path / "s").exists()
    mine = str(tmp_path / "a" / "go2.yaml")
    cell = {"robot": mine, "terrain": "slab", "climb": 0.3, "seed": 0, "budget": 60.0, "files": _digest(mine)}
    rec = {"robot": mine, "terrain": "slab", "climb_m": 0.3, "seed": 0, "budget_s": 60.0, "files": cell["files"]}
    assert _same_cell(rec, cell)
    assert not _same_cell({**rec, "robot": "go1"}, {**cell, "robot": "go1", "files": ""})
    (tmp_path / "a" / "go2.yaml").write_text(spec.replace("mass: 16.085", "mass: 16.09"))
    assert not _same_cell(rec, {**cell, "files": _digest(mine)})
