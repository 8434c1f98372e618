"""Why a climb ended without a plan: the frontier diagnosis of ``plan_climb`` and ``climb-ompl plan``."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import yaml

from climb_ompl.climb.multistep import ClimbStatus, plan_climb
from climb_ompl.climb.start import find_start
from climb_ompl.model.reach import pair_reach
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain


def rows_wall(rows: list[float], lean_deg: float, n: int = 7, spacing: float = 0.18) -> dict:
    """A vertical wall with rows of ``n`` holds at the heights ``rows`` (``r<cm>_<column>``), their normals
    leaning up ``lean_deg`` from the wall normal, as a terrain dict."""
    nrm = [0.0, math.cos(math.radians(lean_deg)), math.sin(math.radians(lean_deg))]
    holds = [{"id": f"r{round(z * 100)}_{i}", "position": [round(spacing * (i - (n - 1) / 2), 4), 0.0, z],
              "normal": nrm} for z in rows for i in range(n)]
    return {"name": "rows", "holds": holds, "surfaces": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}]}


@pytest.fixture(scope="module")
def lemur() -> RobotModel:
    return RobotModel.load("lemur")


@pytest.mark.climb
def test_gap_too_wide_names_the_nearest_hold_out_of_reach(lemur):
    """Three rows at the bottom, then nothing for 0.94 m: the search stops in the bottom rows and the diagnosis
    says every hold above is beyond the pair reach, naming the nearest with its distance (checked against the
    terrain) and the pair reach (checked against :func:`pair_reach`)."""
    t = Terrain.from_dict(rows_wall([0.0, 0.18, 0.36, 1.3, 1.48, 1.66], 75.0))
    st = find_start(lemur, t, seed=0)
    assert st.found
    res = plan_climb(lemur, t, st.stance, 1.6, q_start=st.q, seed=0, time_limit=4.0)
    assert not res.found
    assert "the climb stopped at these stances" in res.reason
    m = re.search(r"every hold above this stance is beyond the pair reach of the free limb; the nearest: hold "
                  r"(\S+) is ([0-9.]+) m from hold (\S+) of limb (\S+), beyond the two limbs' reach \(([0-9.]+) m",
                  res.reason)
    assert m, res.reason
    far, d, near, limb, r = m.group(1), float(m.group(2)), m.group(3), m.group(4), float(m.group(5))
    assert far.startswith("r130_")  # the lowest row above the gap
    assert d == pytest.approx(float(np.linalg.norm(t.hold(far).p - t.hold(near).p)), abs=1e-3)
    assert d > r and r == pytest.approx(max(v for (a, b), v in pair_reach(lemur).items() if b == limb), abs=1e-3)
    assert res.diagnosis and all(max(t.height(h) for h in f["stance"].values()) <= 0.36 + 1e-9
                                 for f in res.diagnosis)
    for f in res.diagnosis:  # the lowest and highest holds' heights, as the terrain gives them
        hs = [t.height(h) for h in f["stance"].values()]
        assert (f["lowest"], f["height"]) == (round(min(hs), 4), round(max(hs), 4))
        held = f"holds at {max(hs):.3f} m" if f"{min(hs):.3f}" == f"{max(hs):.3f}" else \
            f"holds {min(hs):.3f} to {max(hs):.3f} m high"
        assert f"{held}, about" in res.reason
    assert any(r.startswith("reach:") for f in res.diagnosis for e in f["failures"] for r in e["reasons"])


@pytest.mark.climb
def test_no_release_keeps_equilibrium(lemur):
    """Ledges leaning 60 deg: LEMUR stands on four holds but cannot let go of any (the CoM falls outside the
    support region of the other three): the graph is exhausted at the start and the diagnosis says
    equilibrium, with the CoM's distance to the region, for the releases."""
    t = Terrain.from_dict(rows_wall([0.0, 0.18, 0.36, 1.3, 1.48, 1.66], 60.0))
    st = find_start(lemur, t, seed=0)
    res = plan_climb(lemur, t, st.stance, 1.6, q_start=st.q, seed=0, time_limit=30.0)
    assert not res.found and res.status == ClimbStatus.EXHAUSTED and "the stance graph is exhausted" in res.reason
    assert "before the search stopped" not in res.reason  # (its budget did not stop it)
    (front,) = res.diagnosis
    assert front["stance"] == dict(sorted(st.stance.items()))
    assert front["failures"] and all(e["action"] == "release" for e in front["failures"])
    for e in front["failures"]:
        eq = [r for r in e["reasons"] if r.startswith("equilibrium:")]
        assert eq and float(re.search(r"CoM is ([0-9.]+) m outside", eq[0]).group(1)) > 0


def test_start_finder_prefers_a_start_that_can_let_go(lemur):
    """A climb's first step is a release: on the demo wall the first candidate can let go of a limb and is
    taken at once; on ledges leaning 60 deg none can (the support region of three holds misses the CoM), so
    every candidate is tried and the first start found is returned, the one the search then diagnoses."""
    from climb_ompl.climb.start import releasable
    from climb_ompl.manifold.feasibility import Feasibility
    from climb_ompl.manifold.stance import Stance

    demo = Terrain.load("demo-wall")
    st = find_start(lemur, demo, seed=0)
    assert len(st.tried) == 1 and releasable(Feasibility.of(lemur, demo), Stance(st.stance), st.q)
    t = Terrain.from_dict(rows_wall([0.0, 0.18, 0.36, 1.3, 1.48, 1.66], 60.0))
    feas = Feasibility.of(lemur, t)
    st = find_start(lemur, t, seed=0, max_candidates=3)
    one = find_start(lemur, t, seed=0, max_candidates=1)
    assert st.found and st.stance == one.stance and np.array_equal(st.q, one.q)
    assert len(st.tried) == 3
    assert not releasable(feas, Stance(st.stance), st.q)
    assert all(not feas.valid(Stance(st.stance).without(lb), st.q) for lb in st.stance)


def test_goal_above_every_hold(lemur):
    """A goal no stance can meet is answered at once, naming the highest hold and its height."""
    t = Terrain.from_dict(rows_wall([0.0, 0.18, 0.36], 75.0))
    res = plan_climb(lemur, t, {"ne": "r36_4", "nw": "r36_2", "sw": "r0_2", "se": "r0_4"}, 3.0)
    assert not res.found and res.status == ClimbStatus.INFEASIBLE_GOAL
    assert "highest hold" in res.reason and "r36_0" in res.reason and "0.360 m" in res.reason
    assert "2.580 m" in res.reason  # 3.0 minus LEMUR's reach 0.42


def _nearest_pair(t: Terrain, a: list[str], b: list[str]) -> tuple[float, str, str]:
    """Brute force: the smallest distance between a hold of ``a`` and one of ``b``, and the two holds."""
    return min((float(np.linalg.norm(t.hold(x).p - t.hold(y).p)), x, y) for x in a for y in b)


def test_a_gap_wider_than_any_two_limbs_span_is_proved_at_once(lemur):
    """Three rows at the bottom, then nothing for 1.24 m, more than the largest pair reach of two different limbs
    (1.08 m): no search is run; the reason names the highest hold below the gap, and the nearest hold above with
    its distance, both checked by brute force over every pair of holds.  A goal hold above the gap is named."""
    t = Terrain.from_dict(rows_wall([0.0, 0.18, 0.36, 1.6, 1.78, 1.96], 75.0))
    hop = max(v for (a, b), v in pair_reach(lemur).items() if a != b)
    below = [h.id for h in t.holds if t.height(h) < 1.0]
    above = [h.id for h in t.holds if t.height(h) > 1.0]
    d, near, far = _nearest_pair(t, below, above)
    assert d > hop  # the terrain is what the test says
    start = {"ne": "r36_4", "nw": "r36_2", "sw": "r0_2", "se": "r0_4"}
    res = plan_climb(lemur, t, start, 1.9 + 0.42, time_limit=60.0)
    assert not res.found and res.status == ClimbStatus.GOAL_UNREACHABLE and res.stats.get("stances_explored", 0) == 0
    assert f"hop by hop, each grab at most {hop:.3f} m" in res.reason, res.reason
    assert f"it reaches {len(below)} of the terrain's {len(t.holds)} holds, the highest r36_0 at 0.360 m" in res.reason
    assert f"{far} at {t.height(far):.3f} m, is {d:.3f} m from " in res.reason
    res = plan_climb(lemur, t, start, "ne=r160_3", time_limit=60.0)
    assert not res.found and res.status == ClimbStatus.GOAL_UNREACHABLE
    assert "no climb from the start stance can reach hold r160_3" in res.reason, res.reason


def test_a_gap_within_reach_is_left_to_the_search(lemur):
    """The same rows with the gap 2 cm narrower than the pair reach: the check proves nothing, and the search
    runs (the per-pair reach of the limbs on the holds may still stop it, as the frontier then says)."""
    from climb_ompl.climb.frontier import goal_beyond_reach
    from climb_ompl.climb.goal import Goal

    pair = pair_reach(lemur)
    hop = max(v for (a, b), v in pair.items() if a != b)
    t = Terrain.from_dict(rows_wall([0.0, 0.18, 0.36, round(0.36 + hop - 0.02, 3)], 75.0))
    start = {"ne": "r36_4", "nw": "r36_2", "sw": "r0_2", "se": "r0_4"}
    assert goal_beyond_reach(Goal("height", height=1.5), t, start, pair, 0.42) is None
    t = Terrain.from_dict(rows_wall([0.0, 0.18, 0.36, round(0.36 + hop + 0.02, 3)], 75.0))
    assert goal_beyond_reach(Goal("height", height=1.5), t, start, pair, 0.42) is not None


def test_the_gap_named_is_the_one_below_the_goal(lemur):
    """A lone hold out of reach off to the side, lower than the rows: the gap named is the one above the rows (or,
    for a goal hold, that hold's own); an empty stance goal is left to the search."""
    from climb_ompl.climb.frontier import goal_beyond_reach
    from climb_ompl.climb.goal import Goal

    d = rows_wall([0.0, 0.18, 1.6], 75.0)
    d["holds"].append({"id": "side", "position": [-1.75, 0.0, 0.1], "normal": d["holds"][0]["normal"]})
    t, pair = Terrain.from_dict(d), pair_reach(lemur)
    start = {"ne": "r18_4", "nw": "r18_2", "sw": "r0_2", "se": "r0_4"}
    for goal in (Goal("height", height=2.0), Goal("stance", stance=(("ne", "r160_3"),))):
        text = goal_beyond_reach(goal, t, start, pair, 0.42)
        assert "r160_" in text.split(";")[1] and "side" not in text, text
    assert "the nearest the goal needs, r160_3" in goal_beyond_reach(Goal("hold", limb="ne", hold="r160_3"), t,
                                                                       start, pair, 0.42)
    t = Terrain.from_dict(rows_wall([0.0, 0.18], 75.0))
    assert goal_beyond_reach(Goal("stance", stance=()), t, start, pair, 0.42) is None


def test_cli_plan_prints_the_diagnosis(tmp_path, cli):
    """`climb-ompl plan` without a plan: exit 1 with the diagnosis on stderr, no plan file."""
    path = tmp_path / "low.yaml"
    path.write_text(yaml.safe_dump(rows_wall([0.0, 0.18, 0.36], 75.0)))
    out = tmp_path / "plan.json"
    r = cli("plan", "--robot", "lemur", "--terrain", path, "--goal-height", "3.0", "--out", out)
    assert r.code == 1 and "highest hold" in r.err and not out.exists()


def test_cli_plan_across_a_gap_answers_at_once(tmp_path, cli):
    """`climb-ompl plan` up a wall with a gap wider than the robot spans: exit 1 at once with the gap's holds,
    no plan file, and no hint to spend more time."""
    path = tmp_path / "gap.yaml"
    path.write_text(yaml.safe_dump(rows_wall([0.0, 0.18, 0.36, 1.6, 1.78, 1.96], 75.0)))
    out = tmp_path / "plan.json"
    r = cli("plan", "--robot", "lemur", "--terrain", path, "--climb", "1.5", "--out", out)
    assert r.code == 1 and "a gap wider than the robot can span" in r.err and not out.exists(), r.err
    assert "--time-limit" not in r.err


@pytest.mark.climb
def test_cli_hint_suggests_another_start_when_no_step_leaves_it(tmp_path, cli):
    """Ledges leaning 60 deg, where LEMUR cannot let go of any limb at its start: the hint says that no step got
    nearer the goal than the start stance, and how to give another; on a wall where the climb gets going and then
    stalls (a gap above 0.36 m) it does not."""
    stuck, gap = tmp_path / "stuck.yaml", tmp_path / "gap.yaml"
    stuck.write_text(yaml.safe_dump(rows_wall([0.0, 0.18, 0.36, 1.3, 1.48, 1.66], 60.0)))
    r = cli("plan", "--robot", "lemur", "--terrain", stuck, "--goal-height", "1.6", "--time-limit", "30",
            "--out", tmp_path / "p.json")
    assert r.code == 1 and "the stance graph is exhausted" in r.err, r.err
    assert "No step got the robot nearer the goal than its start stance: try another start (--start" in r.err
    gap.write_text(yaml.safe_dump(rows_wall([0.0, 0.18, 0.36, 1.3, 1.48, 1.66], 75.0)))
    r = cli("plan", "--robot", "lemur", "--terrain", gap, "--goal-height", "1.6", "--time-limit", "4",
            "--out", tmp_path / "q.json")
    assert r.code == 1 and "try another start" not in r.err


@pytest.mark.climb
def test_a_spent_budget_lists_the_stances_whose_steps_failed():
    """When the budget runs out, the stances nearest the goal are the ones just reached, from which nothing was
    tried: after the nearest, the diagnosis lists instead the next stances (in the search's ranking) whose steps
    towards the goal failed.  Checked against every stance of the ranking diagnosed on its own."""
    from climb_ompl.climb.frontier import FRONTIER_STANCES, SCANNED, _diagnose_stance, diagnose_frontier

    robot, wall = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    start = find_start(robot, wall, seed=0)
    res = plan_climb(robot, wall, start.stance, 2.6, q_start=start.q, seed=0, time_limit=0.5, keep_search=True)
    assert not res.found and res.status == ClimbStatus.BUDGET and "time budget" in res.reason
    search = res.search
    keys: dict = {}
    for key in search.explored:
        keys.setdefault(key[0], []).append(key)
    ranked = search.frontier()[:SCANNED]
    each = [_diagnose_stance(search, s, keys, 2) for s in ranked]
    want = [each[0]] + [d for d in each[1:] if d.failures][:FRONTIER_STANCES - 1]
    got = diagnose_frontier(search)
    assert [d.stance for d in got] == [d.stance for d in want]
    assert got[0].stance == dict(ranked[0]) and all(d.failures for d in got[1:])


def test_a_frontier_stance_names_its_lowest_and_highest_holds():
    """The heights a height goal compares (every contact hold near it): both, one when they round alike, and the
    record without ``lowest`` when it is not known (as built before it was kept)."""
    from climb_ompl.climb.frontier import FrontierStance

    two = FrontierStance({"a": "h1", "b": "h2"}, 2.7564, 5.4, lowest=0.9)
    assert str(two).startswith("{a:h1, b:h2} (holds 0.900 to 2.756 m high, about 5.4 steps from the goal")
    assert two.to_dict()["lowest"] == 0.9 and two.to_dict()["height"] == 2.7564
    assert "(holds at 0.500 m," in str(FrontierStance({"a": "h1", "b": "h2"}, 0.5, 1.0, lowest=0.5))
    assert "(hold at 0.500 m," in str(FrontierStance({"a": "h1"}, 0.5, 1.0, lowest=0.5))
    old = FrontierStance({"a": "h1"}, 0.5, 1.0)
    assert "(highest hold at 0.500 m," in str(old) and "lowest" not in old.to_dict()
