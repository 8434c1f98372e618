"""The goal a ``plan`` pursues, said before the search: the threshold every contact hold must reach, and on a
slope the height that a climb measured along it gains (against the ramp's angle: a metre along a ramp 20 degrees
from level rises sin 20 deg = 0.342 m); ``--climb-height`` asks for height itself."""

from __future__ import annotations

import math

import pytest
from conftest import DATA


@pytest.fixture(scope="module")
def solo_on_ramp():
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.model.wall_frame import to_wall_frame

    return RobotModel.load(DATA / "solo12.yaml"), to_wall_frame(Terrain.load(DATA / "ramp20.yaml"))[0]


def test_statement_gives_the_threshold_and_the_height_along_the_slope(solo_on_ramp):
    from climb_ompl.climb.goal import Goal, climb_height, goal_statement, robot_reach, threshold_text, wall_slope

    robot, ramp = solo_on_ramp
    assert wall_slope(ramp) == pytest.approx(math.sin(math.radians(20.0)), abs=1e-4)
    start = {"fl": "s1_3", "fr": "s1_1", "hl": "s0_3", "hr": "s0_1"}
    goal = Goal("height", height=climb_height(robot, ramp, start, 0.4))
    top = max(ramp.height(h) for h in start.values())
    thr = top + 0.4 * math.sin(math.radians(20.0))
    text = goal_statement(goal, robot, ramp, start, climb=0.4)
    assert text.startswith(f"goal: every contact hold at or above {thr:.3f} m of height")
    assert f"{0.4 * math.sin(math.radians(20.0)):.3f} m of height" in text and "--climb-height" in text
    assert threshold_text(goal, robot) == f"every contact hold >= {goal.height - robot_reach(robot):.3f} m"
    assert "--climb-height" not in goal_statement(goal, robot, ramp, start)  # asked as height: no slope note


@pytest.mark.parametrize("args, needle", [
    (["--climb", "0.3", "--climb-height", "0.1"], "exactly one goal"),
    (["--climb-height", "-0.1"], "--climb-height"),
])
def test_climb_height_option_is_checked(cli, tmp_path, args, needle):
    r = cli("plan", "--robot", DATA / "solo12.yaml", "--terrain", DATA / "ramp20.yaml", *args,
            "--out", tmp_path / "p.json")
    assert r.code == 2 and needle in r.err


@pytest.mark.climb
def test_plan_says_the_goal_before_the_search_and_reaches_the_height(cli, tmp_path):
    """``--climb-height 0.1`` on the ramp: the goal line comes before the summary table, every end hold is at
    least 0.1 m of height above the start's highest, and the table's title names the same threshold."""
    import json

    import numpy as np

    out = tmp_path / "p.json"
    r = cli("plan", "--robot", DATA / "solo12.yaml", "--terrain", DATA / "ramp20.yaml", "--climb-height", "0.1",
            "--seed", "0", "--out", out)
    assert r.code == 0, r.err
    lines = [ln for ln in r.err.splitlines() if ln.startswith("goal: ")]
    assert len(lines) == 1 and r.err.index(lines[0]) < r.err.index("planning time")
    d = json.loads(out.read_text())
    up = -np.asarray(d["terrain"]["data"]["gravity"], float)
    up /= np.linalg.norm(up)
    pos = {h["id"]: np.asarray(h["position"], float) for h in d["terrain"]["data"]["holds"]}
    start = max(float(pos[h] @ up) for h in d["query"]["start"]["stance"].values())
    last = d["steps"][-1]
    end = dict(last["stance"])
    end.pop(last["limb"], None) if last["action"] == "release" else end.__setitem__(last["limb"], last["hold"])
    thr = float(lines[0].split("at or above ")[1].split(" m")[0])
    assert thr == pytest.approx(start + 0.1, abs=1e-3)
    assert min(float(pos[h] @ up) for h in end.values()) >= thr - 1e-3
    assert f"every contact hold >= {thr:.3f} m" in r.err
