"""A plan file means what it says: ``climb-ompl verify`` checks every stored field that something other than the
verifier reads (playback, the slope side view, re-planning) against what it recomputes (docs/plan-file.md).

For each such field, a real plan (made by the planner here) with that field corrupted exits 1 with the field's JSON
path in the violations; the unmodified plans exit 0.  The oracle of each case is the corruption itself: the plan
verifies without it, and each corruption is far beyond its check's tolerance (a length moved by 5 mm or more, a
direction turned by 0.01 or more, a force scaled by 1.5, a torque moved by 1 N m), or changes a label, a count or
content under a hash."""

from __future__ import annotations

import copy
import dataclasses
import json
from collections.abc import Callable
from functools import lru_cache
from typing import Any

import pytest

from climb_ompl.cli import main
from climb_ompl.plan.file import Plan, sha256_json

Corruption = Callable[[dict[str, Any]], str]  # edits a plan dict, returns the JSON path verify must name


def verify_cli(plan: dict[str, Any], tmp_path, capsys) -> tuple[int, str]:
    """``climb-ompl verify`` on ``plan`` written to a file: exit code and everything it printed."""
    f = tmp_path / "plan.json"
    f.write_text(json.dumps(plan, allow_nan=False))
    capsys.readouterr()
    code = main(["verify", str(f)])
    out = capsys.readouterr()
    return code, out.out + out.err


# ---- slope (Kim, Kang & Choi (MRWALLSPECT III)) -------------------------------------------------------------
@lru_cache(maxsize=1)
def _slope() -> str:
    from climb_ompl.mrwallspect.slope import plan_slope

    res = plan_slope(60.0, "convex")
    assert res.found, res.reason
    return json.dumps(res.plan, allow_nan=False)


def slope() -> dict[str, Any]:
    return json.loads(_slope())


def _swing(p: dict[str, Any]) -> tuple[int, int]:
    """A frame in the middle of a swing and the foot that swings there (detached)."""
    for i, f in enumerate(p["frames"]):
        if f["phase"].startswith("swing") and not all(f["attached"]):
            return i, f["attached"].index(False)
    raise AssertionError("no swing frame")


def _body(p: dict[str, Any]) -> int:
    """A frame of a body move after the first step."""
    return next(i for i, f in enumerate(p["frames"]) if f["phase"] == "body" and f["step"] >= 1)


def _ankles(p):
    p["frames"][0]["ankles"][1][0] += 0.2  # the review's case: 0.2 m along x
    return "$.frames[0].ankles[1]"


def _swinging_foot(p):
    i, j = _swing(p)
    p["frames"][i]["feet"][j][0] += 0.005
    return f"$.frames[{i}].feet[{j}]"


def _clearance(p):
    i = _body(p)
    p["frames"][i]["clearance"] += 0.005
    return f"$.frames[{i}].clearance"


def _margin(p):
    i = _body(p)
    assert p["frames"][i]["equilibrium_margin"] is not None
    p["frames"][i]["equilibrium_margin"] += 0.01
    return f"$.frames[{i}].equilibrium_margin"


def _phase(p):
    i, _ = _swing(p)
    p["frames"][i]["phase"] = "body"
    return f"$.frames[{i}].phase"


def _step(p):
    i = _body(p)
    p["frames"][i]["step"] += 1
    return f"$.frames[{i}].step"


def _attached(p):
    i = _body(p)
    p["frames"][i]["attached"][2] = False
    return f"$.frames[{i}].attached"


def _time(p):
    i = _body(p)
    p["frames"][i]["t"] = p["frames"][i - 1]["t"] - 0.5
    return f"$.frames[{i}].t"


def _origin(p):
    i = _body(p)
    p["frames"][i]["body"]["origin"][2] += 0.01
    return f"$.frames[{i}].body"


def _front(p):
    i = _body(p)
    p["frames"][i]["body"]["front"][0] += 0.01
    return f"$.frames[{i}].body.front"


def _q(p):
    i = _body(p)
    p["frames"][i]["q"][5] += 0.1  # a knee of a standing leg
    return f"$.frames[{i}].q"


def _planes(p):
    p["planes"][0]["point"][0] -= 0.05
    return "$.planes"


def _spec(p):
    p["robot"]["spec"]["gait"]["body_box"]["x"][0] -= 0.02  # what playback and the side view draw
    return "$.robot.spec"


def _centre(p):
    p["trajectory"]["P_R"][2] += 0.01
    return "$.trajectory.P_R"


def _d(p):
    p["trajectory"]["d"] += 0.01
    return "$.trajectory.d"


def _angle(p):
    p["query"]["angle"] = 45.0
    return "$.query"


def _gravity(p):
    p["gravity"] = [0.0, 0.0, 9.81]
    return "$.gravity"


SLOPE: list[Corruption] = [_ankles, _swinging_foot, _clearance, _margin, _phase, _step, _attached, _time, _origin,
                           _front, _q, _planes, _spec, _centre, _d, _angle, _gravity]


def test_slope_plan_verifies(tmp_path, capsys):
    code, out = verify_cli(slope(), tmp_path, capsys)
    assert code == 0, out
    assert "valid" in out


def test_slope_ankle_moved_20_cm_fails(tmp_path, capsys):
    """The review's case: a slope plan whose frames[0].ankles[1] is moved 0.2 m used to verify (the verifier
    recomputed the ankles from q and ignored the stored ones) while playback read the file."""
    p = slope()
    p["frames"][0]["ankles"][1][0] += 0.2
    code, out = verify_cli(p, tmp_path, capsys)
    assert code == 1, out
    assert "feet_on_planes: $.frames[0].ankles[1] is 200.000 mm from leg2's ankle" in out


@pytest.mark.parametrize("corrupt", SLOPE, ids=[c.__name__.strip("_") for c in SLOPE])
def test_slope_field_corrupted_fails_naming_it(corrupt, tmp_path, capsys):
    p = slope()
    field = corrupt(p)
    code, out = verify_cli(p, tmp_path, capsys)
    assert code == 1, out
    assert field in out, out


# ---- TreeBot (Lam et al.) ------------------------------------------------------------------------------------
@lru_cache(maxsize=1)
def _tree() -> str:
    from climb_ompl.treebot import build_plan, generate_tree

    plan = build_plan(generate_tree(3, n_branches=3, points_per_ring=10, trunk_rings=12), "b2")
    assert plan["found"], plan["reason"]
    return json.dumps(plan, allow_nan=False)


def tree() -> dict[str, Any]:
    return json.loads(_tree())


def _frame(p: dict[str, Any], phase: str) -> int:
    """The frame of ``phase`` with the most bent body after the first step (inside its phase)."""
    fr = p["motion"]["frames"]
    inner = [i for i in range(1, len(fr) - 1) if fr[i]["phase"] == phase and fr[i]["step"] >= 1
             and fr[i + 1]["phase"] == phase and fr[i - 1]["phase"] == phase]
    return max(inner, key=lambda i: fr[i]["kappa"] * fr[i]["S"])


def _shift(v: list[float], by: float = 0.01) -> list[float]:
    return [x + by for x in v]


def _front_direction(p):
    i = _frame(p, "extend")
    g = p["motion"]["frames"][i]["front"]
    g["direction"] = _shift(g["direction"])
    return f"$.motion.frames[{i}].front.direction"


def _rear_direction_moving(p):
    i = _frame(p, "contract")
    g = p["motion"]["frames"][i]["rear"]
    g["direction"] = _shift(g["direction"])
    return f"$.motion.frames[{i}].rear.direction"


def _rear_direction_holding(p):
    i = _frame(p, "extend")
    g = p["motion"]["frames"][i]["rear"]
    g["direction"] = _shift(g["direction"])
    return f"$.motion.frames[{i}].rear.direction"


def _phi(p):
    i = _frame(p, "extend")
    p["motion"]["frames"][i]["phi"] += 0.05
    return f"$.motion.frames[{i}].phi"


def _targets(p):
    t = p["motion"]["targets"]
    t[2] += 1
    return "$.motion.targets"


def _normal(p):
    p["path"][3]["normal"] = [0.0, 0.0, 1.0]
    return "$.path[3].normal"


def _cost(p):
    p["cost"] += 0.01
    return "$.cost"


def _path_position(p):
    p["path"][3]["position"] = _shift(p["path"][3]["position"], 0.005)
    return "$.path[3].position"


def _body_samples(p):
    i = _frame(p, "extend")
    b = p["motion"]["frames"][i]["body"]
    b[len(b) // 2] = _shift(b[len(b) // 2])
    return f"$.motion.frames[{i}].body"


def _length(p):
    i = _frame(p, "extend")
    p["motion"]["frames"][i]["S"] += 0.01
    return f"$.motion.frames[{i}].S"


def _curvature(p):
    i = _frame(p, "extend")
    p["motion"]["frames"][i]["kappa"] *= 1.1
    return f"$.motion.frames[{i}].kappa"


def _front_position(p):
    i = _frame(p, "extend")
    g = p["motion"]["frames"][i]["front"]
    g["position"] = _shift(g["position"])
    return f"$.motion.frames[{i}].front.position"


def _rear_position(p):
    i = _frame(p, "extend")
    g = p["motion"]["frames"][i]["rear"]
    g["position"] = _shift(g["position"])
    return f"$.motion.frames[{i}].rear.position"


def _tree_rings(p):
    p["tree"]["branches"][0]["rings"][0]["points"][0][0] += 0.01
    return "$.tree"


TREE: list[Corruption] = [_front_direction, _rear_direction_moving, _rear_direction_holding, _phi, _targets, _normal,
                          _cost, _path_position, _body_samples, _length, _curvature, _front_position, _rear_position,
                          _tree_rings]


def test_tree_plan_verifies(tmp_path, capsys):
    code, out = verify_cli(tree(), tmp_path, capsys)
    assert code == 0, out


@pytest.mark.parametrize("corrupt", TREE, ids=[c.__name__.strip("_") for c in TREE])
def test_tree_field_corrupted_fails_naming_it(corrupt, tmp_path, capsys):
    p = tree()
    field = corrupt(p)
    code, out = verify_cli(p, tmp_path, capsys)
    assert code == 1, out
    assert field in out, out


# ---- climb (Bretl (2006)) -------------------------------------------------------------------------------------
KEPT = 3  # steps of the planner's climb kept: the plan's goal becomes the stance they reach (a short plan to verify)


@lru_cache(maxsize=1)
def _climb() -> str:
    """The planar three-limbed robot's climb on the bundled crack (Bretl, Latombe & Rock (2003)), its first
    :data:`KEPT` steps, with the goal the stance they reach; and the same plan with a re-plan event that removed a hold
    none of its steps uses, after its last step (the terrain it embeds without that hold)."""
    from climb_ompl.climb.multistep import default_start, plan_climb
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.plan.events import TerrainChange

    robot, wall = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    stance, q0 = default_start(robot, wall, seed=0)
    res = plan_climb(robot, wall, stance, 1.6, q_start=q0, time_limit=60, seed=0)
    assert res.found and len(res.plan.steps) > KEPT, res.reason
    plan = res.plan
    steps = plan.steps[:KEPT]
    short = dataclasses.replace(plan, steps=steps, query={**plan.query, "goal": {
        "type": "stance", "stance": dict(steps[-1].stance_after)}}, totals={**plan.totals, "steps": KEPT})
    used = {h for s in steps for _, h in s.stance} | {s.hold for s in steps}
    data = plan.terrain["data"]
    i, gone = next((i, h["id"]) for i, h in enumerate(data["holds"]) if h["id"] not in used)
    after = {**data, "holds": [h for h in data["holds"] if h["id"] != gone]}
    event = {"type": "replan", "at_step": KEPT, "resumed_at_step": KEPT,
             "change": TerrainChange(remove=(gone,)).to_dict(), "before": {gone: {**data["holds"][i], "index": i}},
             "terrain_sha256_before": plan.terrain["sha256"]}
    replanned = dataclasses.replace(short, events=(event,), terrain={
        **plan.terrain, "data": after, "sha256": sha256_json({k: v for k, v in after.items() if k != "description"})})
    return json.dumps([short.to_dict(), replanned.to_dict()], allow_nan=False)


def climb(replanned: bool = False) -> dict[str, Any]:
    return json.loads(_climb())[int(replanned)]


def _moving(p: dict[str, Any]) -> int:
    return max(range(len(p["steps"])), key=lambda k: len(p["steps"][k]["waypoints"]))


def _waypoints(p):
    k = _moving(p)
    p["steps"][k]["waypoints"][5][0] += 0.01
    return f"step {k} waypoint 5: hands_on_holds"


def _times(p):
    k = _moving(p)
    t = p["steps"][k]["times"]
    p["steps"][k]["times"] = [x * 0.5 for x in t]
    return f"$.steps[{k}].times["


def _forces(p):
    k = _moving(p)
    f = p["steps"][k]["forces"][0]["forces"]
    limb = sorted(f)[0]
    f[limb] = [1.5 * x for x in f[limb]]
    return f"$.steps[{k}].forces[0].forces"


def _torques(p):
    k = _moving(p)
    t = p["steps"][k]["forces"][1]["torques"]
    t[-1] += 1.0
    return f"$.steps[{k}].forces[1].torques"


def _duration(p):
    k = _moving(p)
    p["steps"][k]["duration"] += 1.0  # what a controller reading the file would take as the step's length
    return f"$.steps[{k}].duration"


def _step_margin(p):
    k = _moving(p)
    p["steps"][k]["margin"] += 0.05
    return f"$.steps[{k}].margin"


def _stance(p):
    s = p["steps"][1]["stance"]
    limb = sorted(s)[0]
    s[limb] = next(h["id"] for h in p["terrain"]["data"]["holds"] if h["id"] not in s.values())
    return "$.steps[1].stance"


def _grabbed(p):
    k = next(k for k, s in enumerate(p["steps"]) if s["action"] == "grab")
    held = set(p["steps"][k]["stance"].values()) | {p["steps"][k]["hold"]}
    p["steps"][k]["hold"] = next(h["id"] for h in p["terrain"]["data"]["holds"] if h["id"] not in held)
    return f"$.steps[{k}]"


def _start_q(p):
    p["query"]["start"]["q"][0] += 0.01
    return "$.query.start.q"


def _start_stance(p):
    s = p["query"]["start"]["stance"]
    limb = sorted(s)[0]
    s[limb] = next(h["id"] for h in p["terrain"]["data"]["holds"] if h["id"] not in s.values())
    return "$.query.start.stance"


def _goal(p):
    p["query"]["goal"] = {"type": "stance", "stance": dict(p["query"]["start"]["stance"])}
    return "$.query.goal"


def _terrain(p):
    p["terrain"]["data"]["holds"][0]["friction"] = 5.0
    return "$.terrain.data"


def _robot(p):
    p["robot"]["urdf"] = p["robot"]["urdf"].replace("<robot", "<!-- edited -->\n<robot", 1)
    return "$.robot.urdf"


def _totals(p):
    p["totals"]["steps"] += 1
    return "$.totals.steps"


CLIMB: list[Corruption] = [_waypoints, _times, _duration, _forces, _torques, _step_margin, _stance, _grabbed, _start_q,
                           _start_stance, _goal, _terrain, _robot, _totals]


def _before(p):
    (hid, h), = p["events"][0]["before"].items()
    h["position"] = _shift(h["position"], 0.05)  # playback draws the failed hold here
    return "$.events[0].before"


def _at_step(p):
    p["events"][0]["at_step"] = p["events"][0]["resumed_at_step"] - 1
    return "$.events[0].at_step"


def _resumed(p):
    p["events"][0]["resumed_at_step"] = len(p["steps"]) + 1  # playback marks the departure at that step
    return "$.events[0].resumed_at_step"


def _change(p):
    p["events"][0]["change"]["remove"] = []
    p["events"][0]["change"]["friction"] = {next(iter(p["events"][0]["before"])): 0.1}
    return "$.events[0]"


EVENTS: list[Corruption] = [_before, _at_step, _resumed, _change]


@pytest.mark.parametrize("replanned", [False, True], ids=["climb", "replanned"])
def test_climb_plan_verifies(replanned, tmp_path, capsys):
    p = climb(replanned)
    assert Plan.from_dict(copy.deepcopy(p)).steps  # a real plan of the climb kind
    code, out = verify_cli(p, tmp_path, capsys)
    assert code == 0, out


@pytest.mark.parametrize("corrupt", CLIMB, ids=[c.__name__.strip("_") for c in CLIMB])
def test_climb_field_corrupted_fails_naming_it(corrupt, tmp_path, capsys):
    p = climb()
    field = corrupt(p)
    code, out = verify_cli(p, tmp_path, capsys)
    assert code == 1, out
    assert field in out, out


@pytest.mark.parametrize("corrupt", EVENTS, ids=[c.__name__.strip("_") for c in EVENTS])
def test_replan_event_corrupted_fails_naming_it(corrupt, tmp_path, capsys):
    p = climb(replanned=True)
    field = corrupt(p)
    code, out = verify_cli(p, tmp_path, capsys)
    assert code == 1, out
    assert field in out, out



@pytest.mark.parametrize("kind, edit, field", [
    ("slope", lambda p: p["frames"][2].__setitem__("ankles", p["frames"][2]["ankles"][:3]), "$.frames[2].ankles"),
    ("slope", lambda p: p["frames"][2].__setitem__("clearance", "10 mm"), "$.frames[2].clearance"),
    ("treebot", lambda p: p.__setitem__("cost", "low"), "$.cost"),
])
def test_a_stored_field_of_the_wrong_shape_is_bad_input(kind, edit, field, tmp_path, capsys):
    """A field the verifier compares must have the shape it compares (schema): else exit 2 naming it, not a crash."""
    p = slope() if kind == "slope" else tree()
    edit(p)
    code, out = verify_cli(p, tmp_path, capsys)
    assert code == 2, out
    assert field in out, out
