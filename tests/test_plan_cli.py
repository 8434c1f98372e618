"""``climb-ompl plan`` and ``climb-ompl verify``: exit codes, messages, atomic output (real subprocesses; the cases
of bad options and settings in this process, the same ``main`` without a Python start-up each, the ``cli`` fixture)."""

from __future__ import annotations

import json
import math
import subprocess
import sys
from functools import lru_cache
from pathlib import Path

import pytest
from conftest import ROOT

PLANAR = ["--robot", "planar-3limb", "--terrain", "planar-wall"]


def cli(*args: str, timeout: float = 300) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-m", "climb_ompl", *args], capture_output=True, text=True,
                          timeout=timeout)


@lru_cache(maxsize=1)
def planar_plan_file() -> tuple[Path, subprocess.CompletedProcess]:
    import tempfile

    out = Path(tempfile.mkdtemp(prefix="climb-cli-")) / "plan.json"
    return out, cli("plan", *PLANAR, "--goal-height", "1.6", "--seed", "1", "--out", str(out))


@pytest.mark.climb
def test_plan_then_verify_succeeds():
    out, p = planar_plan_file()
    assert p.returncode == 0, p.stderr
    assert "steps" in p.stderr and "one-step calls" in p.stderr  # the summary table
    # the heights of the query: the goal 1.6 less the planar robot's reach 0.5, and where the climb ended
    assert "goal 1.600 = every contact hold >= 1.100" in p.stderr and "end holds" in p.stderr
    assert out.is_file() and json.loads(out.read_text())["kind"] == "climb"
    v = cli("verify", str(out))
    assert v.returncode == 0, v.stderr
    assert "valid" in v.stdout


@pytest.mark.climb
def test_verify_lists_violations_with_exit_1(tmp_path):
    out, p = planar_plan_file()
    assert p.returncode == 0
    d = json.loads(out.read_text())
    step = next(s for s in d["steps"] if len(s["waypoints"]) > 5)
    step["waypoints"][3][0] += 0.01
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(d))
    v = cli("verify", str(bad))
    assert v.returncode == 1
    assert f"step {step['index']} waypoint 3: hands_on_holds" in v.stderr


def _nan_waypoint(d: dict) -> None:
    d["steps"][1]["waypoints"][2][0] = float("nan")


@pytest.mark.climb
@pytest.mark.parametrize("mutate, where", [
    (lambda d: d["steps"][0].update(waypoints="oops"), "$.steps[0].waypoints"),
    (_nan_waypoint, "$.steps[1].waypoints[2][0]"),
    (lambda d: d.update(schema_version=99), "$.schema_version"),
    (lambda d: d["terrain"].pop("sha256"), "$.terrain"),
])
def test_verify_schema_invalid_names_the_json_path(tmp_path, mutate, where):
    out, _ = planar_plan_file()
    d = json.loads(out.read_text())
    mutate(d)
    bad = tmp_path / "bad.json"
    bad.write_text(json.dumps(d))
    v = cli("verify", str(bad))
    assert v.returncode == 2
    assert where in v.stderr and len(v.stderr.strip().splitlines()) == 1


@pytest.mark.climb
def test_replay_writes_the_same_plan(tmp_path):
    """`plan --replay` plans again from the file's query, seed and settings: the same plan, timings aside."""
    from climb_ompl.plan.file import Plan, canonical_json

    out, p = planar_plan_file()
    assert p.returncode == 0, p.stderr
    again = tmp_path / "again.json"
    r = cli("plan", "--replay", str(out), "--out", str(again))
    assert r.returncode == 0, r.stderr
    assert canonical_json(Plan.load(again)) == canonical_json(Plan.load(out))
    assert Plan.load(out).settings["transition_attempts"] > 0  # every setting is in the file
    bad = cli("plan", "--replay", str(out), *PLANAR, "--out", str(tmp_path / "x.json"))
    assert bad.returncode == 2 and "--replay" in bad.stderr and not (tmp_path / "x.json").exists()


@pytest.mark.climb
def test_a_robots_climb_defaults_reach_plan_and_replay_with_a_mode(tmp_path):
    """A copy of LEMUR's spec that turns the release look-ahead off: ``plan`` stores it, and ``plan --replay
    --search guided`` (the mode's settings instead of the file's) keeps the robot's own defaults under the mode, so
    the same plan comes back (it dropped them before).  A 0.8 m goal: 7 steps in limb order, 9 other ones with the
    look-ahead."""
    import yaml

    from climb_ompl.plan.file import Plan

    root = Path(__file__).resolve().parents[1]
    spec = yaml.safe_load((root / "robots" / "lemur.yaml").read_text())
    spec.update(urdf=str(root / "urdf" / spec["urdf"]), climb={"release_lookahead": False})
    path = tmp_path / "lemur-limb-order.yaml"
    path.write_text(yaml.safe_dump(spec))
    out = tmp_path / "p.json"
    p = cli("plan", "--robot", str(path), "--terrain", "demo-wall", "--goal-height", "0.8", "--seed", "0",
            "--out", str(out))
    assert p.returncode == 0, p.stderr
    assert Plan.load(out).settings["release_lookahead"] is False
    again = tmp_path / "again.json"
    r = cli("plan", "--replay", str(out), "--search", "guided", "--out", str(again))
    assert r.returncode == 0, r.stderr
    a, b = Plan.load(out), Plan.load(again)
    assert b.settings["release_lookahead"] is False
    assert [s.waypoints for s in a.steps] == [s.waypoints for s in b.steps]


@pytest.mark.heavy
def test_verify_unreadable_files(tmp_path):
    v = cli("verify", str(tmp_path / "missing.json"))
    assert v.returncode == 2 and "cannot read" in v.stderr
    (tmp_path / "c.json").write_text('{"kind": "climb", ')
    v = cli("verify", str(tmp_path / "c.json"))
    assert v.returncode == 2 and "invalid JSON" in v.stderr
    (tmp_path / "empty.json").write_text("\n")
    v = cli("verify", str(tmp_path / "empty.json"))
    assert v.returncode == 2 and "file: empty" in v.stderr, v.stderr
    # a terrain or a robot spec given where the plan goes: said so, not "invalid JSON"
    import yaml

    slab = yaml.safe_load((ROOT / "climb_ompl/terrains/slab.yaml").read_text())
    (tmp_path / "slab.json").write_text(json.dumps(slab))
    for path, kind in ((ROOT / "climb_ompl/terrains/slab.yaml", "a terrain file"), (tmp_path / "slab.json",
                       "a terrain file"), (ROOT / "robots/go1.yaml", "a robot spec")):
        v = cli("verify", str(path))
        assert v.returncode == 2 and f"{kind}" in v.stderr and "not a plan file" in v.stderr, v.stderr


@pytest.mark.parametrize("args, needle", [
    (["--robot", "nobody", "--terrain", "planar-wall", "--goal-height", "2"], "nobody"),
    ([*PLANAR, "--goal-height", "2", "--goal-hold", "limb1=L4"], "exactly one goal"),
    ([*PLANAR], "exactly one goal"),
    ([*PLANAR, "--goal-hold", "limb1=NOPE"], "--goal-hold: no hold 'NOPE' in terrain 'planar-wall'"),
    ([*PLANAR, "--goal-hold", "limb1"], "LIMB=HOLD"),
    ([*PLANAR, "--goal-height", "2", "--planner", "Dijkstra"], "valid names"),
    ([*PLANAR, "--goal-height", "2", "--start", "limb1=L0,arm=R0"], "arm"),
    ([*PLANAR, "--goal-height", "2", "--step-time-limit", "0"], "--step-time-limit"),
    ([*PLANAR, "--goal-height", "2", "--heuristic-weight", "-1"], "--heuristic-weight"),
    ([*PLANAR, "--climb", "0"], "--climb: must be a finite number > 0"),
    ([*PLANAR, "--climb", "0.5", "--goal-hold", "limb1=L4"], "exactly one goal"),
    # the start stance (L0, R0, L3: holds 0.25-0.91 m up) already has every hold above 0.3 - 0.5 m
    ([*PLANAR, "--goal-height", "0.3"], "already meets it"),
])
def test_plan_bad_input_exits_2_and_writes_nothing(tmp_path, cli, args, needle):
    out = tmp_path / "p.json"
    r = cli("plan", *args, "--out", out)
    assert r.code == 2, r.err
    assert needle in r.err
    assert not out.exists() and list(tmp_path.iterdir()) == []


@pytest.mark.heavy
def test_plan_unwritable_output_exits_2(tmp_path):
    p = cli("plan", *PLANAR, "--goal-height", "2", "--out", str(tmp_path / "no" / "p.json"))
    assert p.returncode == 2 and "does not exist" in p.stderr


@pytest.mark.climb
def test_plan_no_route_exits_1_with_reason(tmp_path):
    out = tmp_path / "p.json"
    p = cli("plan", *PLANAR, "--goal-height", "2.6", "--time-limit", "0.5", "--out", str(out))
    assert p.returncode == 1
    assert "no plan" in p.stderr and "time budget" in p.stderr
    assert "hint:" in p.stderr and "--set release_lookahead=false" in p.stderr  # the other order of the releases
    assert not out.exists()


@pytest.mark.climb
def test_a_search_without_a_plan_leaves_an_older_file_as_it_was_and_says_so(tmp_path, cli):
    """A plan file of that name from an earlier run is not this query's answer: ``plan`` says it wrote nothing."""
    out = tmp_path / "p.json"
    out.write_text("an older plan")
    r = cli("plan", *PLANAR, "--goal-height", "2.6", "--time-limit", "0.5", "--out", out)
    assert r.code == 1 and out.read_text() == "an older plan"
    assert f"note: nothing written; {out} is an older file, left as it was" in r.err


@pytest.mark.climb
def test_climb_goal_is_measured_from_the_start_stance(tmp_path):
    """``--climb M``: every contact hold at least M metres above the start stance's highest hold (0.91 m on the
    planar wall, a vertical wall: a metre along it is a metre of height), checked on the plan file's final
    stance independently of the planner's goal test."""
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.plan.file import Plan

    out = tmp_path / "p.json"
    p = cli("plan", *PLANAR, "--climb", "0.3", "--seed", "1", "--out", str(out))
    assert p.returncode == 0, p.stderr
    plan, wall = Plan.load(out), Terrain.load("planar-wall")
    start = max(wall.height(h) for h in plan.query["start"]["stance"].values())
    assert start == pytest.approx(0.91)
    assert plan.query["goal"]["height"] == pytest.approx(start + 0.3 + 0.5)
    assert min(wall.height(h) for _, h in plan.final_stance) >= start + 0.3 - 1e-9
    assert oct(out.stat().st_mode & 0o777) == oct(0o666 & ~_umask())


def _umask() -> int:
    import os

    mask = os.umask(0o022)
    os.umask(mask)
    return mask


@pytest.mark.climb
def test_plan_bad_files_exit_2_naming_the_problem(tmp_path):
    """More bad input: missing file, malformed YAML, URDF without the named frame."""
    data = Path(__file__).parent / "data"
    bad_yaml = tmp_path / "wall.yaml"
    bad_yaml.write_text("name: w\nholds: [\n")
    cases = [
        (["--robot", "planar-3limb", "--terrain", str(tmp_path / "missing.yaml")], "missing.yaml"),
        (["--robot", "planar-3limb", "--terrain", str(bad_yaml)], "invalid YAML"),
        (["--robot", str(data / "bad_robots" / "unknown_frame.yaml"), "--terrain", "planar-wall"], "frame"),
    ]
    out = tmp_path / "out"
    out.mkdir()
    for args, needle in cases:
        p = cli("plan", *args, "--goal-height", "2", "--out", str(out / "p.json"))
        assert p.returncode == 2, (args, p.stderr)
        assert needle in p.stderr and len(p.stderr.strip().splitlines()) == 1, p.stderr
        assert list(out.iterdir()) == []


@pytest.mark.climb
def test_verify_plan_for_another_terrain_exits_2():
    out, p = planar_plan_file()
    assert p.returncode == 0
    v = cli("verify", str(out), "--terrain", "demo-wall")
    assert v.returncode == 2
    assert "$.terrain.sha256" in v.stderr and "demo-wall" in v.stderr
    assert cli("verify", str(out), "--terrain", "planar-wall").returncode == 0


@pytest.mark.climb
def test_verify_plan_for_another_robot_or_an_edited_robot_exits_2(tmp_path):
    """``verify --robot``: the spec and URDF a plan embeds must be that robot's.  The checks use the embedded
    robot, so a spec edited in the file (``equilibrium: false`` turns the equilibrium and torque checks off) with
    its digest recomputed passes ``verify`` alone; naming the robot catches it, naming the field."""
    import json

    from climb_ompl.plan.file import sha256_json

    out, p = planar_plan_file()
    assert p.returncode == 0
    assert cli("verify", str(out), "--robot", "planar-3limb").returncode == 0
    v = cli("verify", str(out), "--robot", "lemur")
    assert v.returncode == 2 and "$.robot" in v.stderr and "'lemur'" in v.stderr, v.stderr
    d = json.loads(out.read_text())
    d["robot"]["spec"]["equilibrium"] = False
    d["robot"]["spec_sha256"] = sha256_json(d["robot"]["spec"])
    edited = tmp_path / "edited.json"
    edited.write_text(json.dumps(d))
    assert cli("verify", str(edited)).returncode == 0
    v = cli("verify", str(edited), "--robot", "planar-3limb")
    assert v.returncode == 2 and "its spec (equilibrium) differs" in v.stderr, v.stderr


@pytest.mark.parametrize("args, needle", [
    (["--set", "nosuch=1"], "--set nosuch: unknown setting; valid: "),
    (["--set", "transition_wide=-3"], "--set transition_wide: -3 must be a finite number >= 0"),
    (["--set", "release_lookahead=maybe"], "--set release_lookahead: 'maybe' must be true or false"),
    (["--set", "search=paper"], "--search"),
    (["--set", "planner=SBL", "--planner", "RRT"], "--set planner: given by its own option too"),
    (["--set", "time_limit=soon"], "--set time_limit: 'soon' must be a number"),
])
def test_plan_bad_settings_exit_2_naming_the_option(tmp_path, cli, args, needle):
    out = tmp_path / "p.json"
    r = cli("plan", *PLANAR, "--goal-height", "1.6", *args, "--out", out)
    assert r.code == 2, r.err
    assert needle in r.err
    assert not out.exists()


@pytest.mark.climb
def test_set_reaches_the_plan_file_and_an_exhausted_graph_gets_a_hint(tmp_path):
    """``--set KEY=VALUE`` gives any climb setting: the search runs with it and the plan file stores it (so
    ``--replay`` needs nothing more).  On a wall with a gap the planar robot cannot span, the stance graph is
    exhausted: the answer (exit 1, no file) suggests the settings that make the search try harder."""
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.plan.file import Plan

    stored = tmp_path / "stored.json"
    r = cli("plan", *PLANAR, "--goal-height", "0.8", "--seed", "1", "--set", "stride=0.3", "--set",
            "keep_shape=false", "--out", str(stored))
    assert r.returncode == 0, r.stderr
    s = Plan.load(stored).settings
    assert s["stride"] == 0.3 and s["keep_shape"] is False and s["planner"] == "SBL"

    # below the gap three holds (L0, L1, R1), and one 0.93 m above L1: within the pair reach (1.0 m) of L1 and R1
    # (so no gap is proved before the search), but the stance graph is exhausted within a few stances
    d = Terrain.load("planar-wall").to_dict()
    d["holds"] = [h for h in d["holds"] if h["position"][1] < 0.5 and h["id"] != "R0"] + [
        {"id": "top", "position": [0.0, 1.4], "normal": [0.0, 1.0], "friction": 1.0}]
    gap = tmp_path / "gap.json"
    gap.write_text(json.dumps(d))
    g = cli("plan", "--robot", "planar-3limb", "--terrain", str(gap), "--goal-height", "1.9", "--set",
            "transition_attempts=30", "--out", str(tmp_path / "g.json"))
    assert g.returncode == 1 and "the stance graph is exhausted" in g.stderr, g.stderr
    assert "hint:" in g.stderr and "--set transition_wide=200" in g.stderr
    assert not (tmp_path / "g.json").exists()


@pytest.mark.parametrize("items, needle", [(["transitions"], "expected KEY=VALUE"), (["=3"], "expected KEY=VALUE"),
                                           (["stride=0.3", "stride=0.2"], "--set stride: given twice")])
def test_malformed_set_items_are_refused(items, needle, capsys):
    import typer

    from climb_ompl.cli.plan import parse_settings

    with pytest.raises(typer.Exit) as e:
        parse_settings(items)
    assert e.value.exit_code == 2 and needle in capsys.readouterr().err
    assert parse_settings(["transition_wide=200", "release_lookahead=true", "planner=RRTConnect", "stride=null"]) == {
        "transition_wide": 200, "release_lookahead": True, "planner": "RRTConnect", "stride": None}


def test_hints_leave_out_the_settings_already_in_use():
    """The hint after an exhausted stance graph or a spent budget suggests only effort settings not already at the
    suggested value (suggesting one again would send the user in a circle), and the order of the releases not in
    use (the look-ahead is the default)."""
    from climb_ompl.cli.plan import hint
    from climb_ompl.climb.status import ClimbStatus
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.settings import ClimbSettings

    lemur = ClimbSettings.for_search("guided", robot=RobotModel.load("lemur")).to_dict()
    assert lemur["release_lookahead"] is True
    anymal = {**ClimbSettings.for_search("guided", robot=RobotModel.load("anymal-c")).to_dict(),
              "release_lookahead": False}  # (a spec or --set may turn it off)
    spent, exhausted = ClimbStatus.BUDGET, ClimbStatus.EXHAUSTED
    assert "--set release_lookahead=false" in hint(spent, lemur) and "--time-limit" in hint(spent, lemur)
    assert "--set release_lookahead=true" in hint(spent, anymal)
    out = hint(exhausted, lemur)
    assert "--set transition_wide=200" in out and "--set release_lookahead=false" in out
    every = {**lemur, "transition_wide": 200, "grab_reach": 0, "reexpand": 6, "transition_walk": 100}
    out = hint(exhausted, every)
    assert out.count("--set") == 1 and "Try the other order of the releases (--set release_lookahead=false" in out
    # without a height heuristic (the paper mode) the look-ahead does nothing: not offered
    paper = ClimbSettings.for_search("paper", robot=RobotModel.load("lemur")).to_dict()
    assert "release_lookahead" not in hint(spent, paper) and "--time-limit" in hint(spent, paper)
    out = hint(exhausted, {**paper, "transition_wide": 200, "grab_reach": 0, "reexpand": 6,
                                              "transition_walk": 100})
    assert "--set" not in out and "another --seed" in out
    assert all(hint(other, lemur) is None for other in ClimbStatus if other not in (spent, exhausted))
    # a frontier whose every failed step is a grab the grab_reach prefilter left out: time would not help
    # (a user's Solo-12 on a ramp with a 0.6 m gap spent 120 s and was told to give more time)
    from climb_ompl.climb.frontier import NOT_PROPOSED

    beyond = [{"stance": {"fr": "s0"}, "failures": [{"action": "grab", "limb": "fl", "hold": "s7", "reasons": [
        f"{NOT_PROPOSED}, the hold's hand target is 0.627 m from the limb's first joint"]}]}]
    out = hint(spent, lemur, diagnosis=beyond)
    assert "more time alone may not get past them" in out and "--set grab_reach=0" in out and "--time-limit" not in out
    mixed = [*beyond, {"stance": {"fr": "s1"}, "failures": [{"reasons": ["equilibrium: the CoM is outside"]}]}]
    assert "--time-limit" in hint(spent, lemur, diagnosis=mixed)
    assert "grab_reach=0" not in hint(spent, {**lemur, "grab_reach": 0}, diagnosis=beyond)
    assert "--time-limit" in hint(spent, lemur, diagnosis=[{**beyond[0], "untried": 3}])  # more time may help


@pytest.mark.climb
def test_a_plan_that_a_cpu_guard_decided_says_so(tmp_path):
    """FIND-PATH stops after its validity-check budget, or on its CPU-time guard: when the guard stopped a call
    the route depends on the machine's speed and load, and ``plan`` says so (a user's same seed gave another plan
    beside other jobs).  With a 1 ms guard every FIND-PATH call of the planar climb stops on it; with the default
    guard none does, and there is no note."""
    out = tmp_path / "p.json"
    for seed in range(6):  # the first seed whose climb calls FIND-PATH (one whose direct paths all connect does not)
        p = cli("plan", *PLANAR, "--goal-height", "1.6", "--seed", str(seed), "--step-time-limit", "0.001", "--out",
                str(out))
        assert p.returncode == 0, p.stderr
        n = json.loads(out.read_text())["totals"]["path_timeouts"]
        if n:
            break
    assert n > 0 and f"note: {n} FIND-PATH call(s) stopped on a time guard" in p.stderr
    _, q = planar_plan_file()
    assert q.returncode == 0 and "note: " not in q.stderr and "FIND-PATH calls" in q.stderr


@pytest.mark.parametrize("args,head", [
    (["--planner", "rrtconnect"], "--planner: unknown planner 'rrtconnect' (did you mean 'RRTConnect'?)"),
    (["--set", "planner=RRTConect"], "--set planner: unknown planner 'RRTConect' (did you mean 'RRTConnect'?)"),
    (["--space", "atlass"], "--space: unknown constrained space 'atlass' (did you mean 'atlas'?)"),
    (["--sampler", "NoSuch"], "--sampler: unknown sampler 'NoSuch'; valid names: uniform"),
])
def test_an_unknown_name_names_its_option_and_the_nearest_name(tmp_path, cli, args, head):
    """A misspelt planner, space or sampler: exit 2, the option it came from, the nearest valid name (case
    folded, or close by difflib) when there is one, the valid names; nothing written."""
    out = tmp_path / "p.json"
    r = cli("plan", "--robot", "lemur", "--terrain", "demo-wall", "--climb", "0.1", *args, "--out", out)
    assert r.code == 2 and f"error: {head}" in r.err and not out.exists()


CRACK = """name: crack
dim: 2
friction: 1.0
holds:
""" + "".join(f"  - {{id: l{r}, position: [-0.15, {0.2 * r:.1f}], normal: [1.0, 0.3]}}\n"
              f"  - {{id: r{r}, position: [0.15, {0.2 * r:.1f}], normal: [-1.0, 0.3]}}\n" for r in range(10))


@pytest.mark.climb
def test_a_crack_whose_support_region_is_unbounded_saves_its_plan(cli, tmp_path) -> None:
    """Two walls of a crack facing each other hold the body by friction wherever its CoM is: the support region
    is unbounded and the margin infinite, which JSON cannot hold (a user's crack crashed ``plan`` when saving the
    plan it found).  The margin is recorded as UNBOUNDED_MARGIN; a 3-D robot on the 2-D crack is bad input."""
    from climb_ompl.climb.assembly import UNBOUNDED_MARGIN

    (tmp_path / "crack.yaml").write_text(CRACK)
    out = tmp_path / "p.json"
    r = cli("plan", "--robot", "planar-3limb", "--terrain", tmp_path / "crack.yaml", "--goal-height", "1.5",
            "--seed", "0", "--out", out)
    assert r.code == 0, r.err
    margins = [s["margin"] for s in json.loads(out.read_text())["steps"]]
    assert UNBOUNDED_MARGIN in margins and all(math.isfinite(m) for m in margins)
    assert cli("verify", out).code == 0
    r = cli("plan", "--robot", "lemur", "--terrain", tmp_path / "crack.yaml", "--climb", "0.5", "--out",
            tmp_path / "q.json")
    assert r.code == 2 and "dim 2, but robot 'lemur' is 3-D" in r.err and not (tmp_path / "q.json").exists()
