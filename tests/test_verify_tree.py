"""``climb-ompl verify`` on TreeBot plans (Lam et al. (TreeBot)): plans the planner writes pass, and each
injected fault is caught, named and located (step and frame); bad input is exit 2 naming the JSON path."""

from __future__ import annotations

import copy
import json
import math
from functools import lru_cache

import numpy as np
import pytest

from climb_ompl.cli import main
from climb_ompl.errors import PlanFileError
from climb_ompl.treebot import Tree, build_plan, generate_tree
from climb_ompl.verification import verify_plan_dict
from climb_ompl.verification.tree import GRIP_TOLERANCE, arc, arc_samples


@lru_cache(maxsize=1)
def _small() -> str:
    """A small generated tree (trunk and three branches, 10 points per ring): planned in well under a second."""
    plan = build_plan(generate_tree(3, n_branches=3, points_per_ring=10, trunk_rings=12), "b2")
    assert plan["found"], plan["reason"]
    return json.dumps(plan, allow_nan=False)


def small() -> dict:
    return json.loads(_small())


def check(plan: dict) -> dict[str, int]:
    return verify_plan_dict(plan, "<test>").by_check()


def rehash(plan: dict) -> None:
    tree = {k: v for k, v in plan["tree"].items() if k != "tree_hash"}
    plan["tree"]["tree_hash"] = Tree.from_dict(tree).content_hash()


def extension_frame(plan: dict, last: bool = False) -> int:
    """Index of a frame inside an extension (not its last frame, unless ``last``) after the first step."""
    fr = plan["motion"]["frames"]
    for i in range(1, len(fr) - 1):
        if fr[i]["phase"] == "extend" and fr[i]["step"] >= 1:
            end = fr[i + 1]["phase"] != "extend"
            if end == last:
                return i
    raise AssertionError("no such frame")


def lift_rear(plan: dict, i: int, by: float = 0.01) -> None:
    """Move frame ``i``'s rear gripper ``by`` metres off the bark, along the normal of the nearest path point."""
    rear = plan["motion"]["frames"][i]["rear"]
    nearest = min(plan["path"], key=lambda p: np.linalg.norm(np.subtract(p["position"], rear["position"])))
    rear["position"] = (np.asarray(rear["position"]) + by * np.asarray(nearest["normal"])).tolist()


def test_planner_plans_verify():
    rep = verify_plan_dict(small(), "<test>")
    assert rep.ok, [str(v) for v in rep.violations]
    assert rep.states_checked == len(small()["motion"]["frames"])


def test_arc_is_eq_1_to_3_in_any_frame():
    """The frame-free arc agrees with the gripper-frame formulas of Eq. 1-3 (treebot.body.posture)."""
    from climb_ompl.treebot.body import arc_points, gripper_frame, posture

    rng = np.random.default_rng(0)
    for _ in range(20):
        o, d, p = rng.normal(size=3), rng.normal(size=3), rng.normal(size=3)
        d /= np.linalg.norm(d)
        R = gripper_frame(d, rng.normal(size=3))
        post = posture(R.T @ (p - o))
        S, kappa, e = arc(o, d, p)
        assert S == pytest.approx(post.S, rel=1e-9) and kappa == pytest.approx(post.kappa, rel=1e-9, abs=1e-12)
        ours = arc_samples(o, d, S, kappa, e, 12)
        assert np.allclose(ours, o + arc_points(post, 12) @ R.T, atol=1e-9)
        assert np.allclose(ours[-1], p, atol=1e-9)


def test_grip_moved_off_the_bark_is_caught():
    plan = small()
    fr = plan["motion"]["frames"]
    i = extension_frame(plan)
    lift_rear(plan, i)
    rep = verify_plan_dict(plan, "<test>")
    hits = [v for v in rep.violations if v.check == "grip_on_bark"]
    assert hits and hits[0].step == fr[i]["step"] and hits[0].waypoint == i
    assert "off the bark" in hits[0].message


def test_path_point_moved_off_its_tree_point_is_caught():
    plan = small()
    plan["path"][5]["position"][0] += 0.02
    assert check(plan).get("path")


def test_body_stretched_past_its_limit_is_caught():
    """A consistent fault: the moving front gripper is put 5 cm past s_max ahead of the holding rear one, the body
    samples follow the arc and the front gripper points along its end, so only the length limit (and not the shape)
    is wrong."""
    plan = small()
    fr = plan["motion"]["frames"]
    i = extension_frame(plan)
    f = fr[i]
    o, d = np.asarray(f["rear"]["position"]), np.asarray(f["rear"]["direction"])
    d = d / np.linalg.norm(d)
    far = o + (plan["tree"]["robot"]["s_max"] + 0.05) * d
    S, kappa, e = arc(o, d, far)
    f["front"]["position"], f["S"], f["kappa"] = far.tolist(), S, kappa
    f["front"]["direction"] = d.tolist()  # the straight arc's end tangent
    f["body"] = arc_samples(o, d, S, kappa, e, len(f["body"])).tolist()
    got = check(plan)
    assert got == {"body_length": 1}, got


def test_bending_past_the_limit_is_caught_even_with_the_hash_recomputed():
    plan = small()
    bends = [f["kappa"] * f["S"] for f in plan["motion"]["frames"]]
    plan["tree"]["robot"]["max_bend"] = 0.9 * max(bends)
    assert check(plan).get("integrity") == 1  # tampered tree
    rehash(plan)
    got = check(plan)
    assert set(got) == {"bending"} and got["bending"] >= 1


def test_tampered_tree_is_caught():
    plan = small()
    other = next(b for b in plan["tree"]["branches"] if b["name"] not in {p["branch"] for p in plan["path"]})
    other["rings"][-1]["points"][0][2] += 0.01  # far from the climb: only the hash tells
    assert check(plan) == {"integrity": 1}
    plan = small()
    pt = plan["path"][3]
    b = next(b for b in plan["tree"]["branches"] if b["name"] == pt["branch"])
    b["rings"][pt["ring"]]["points"][pt["point"]][2] += 0.01
    rehash(plan)  # the hash agrees again: the path no longer lies on the tree
    assert set(check(plan)) >= {"path"}


def test_gripping_an_unreachable_point_is_caught():
    plan = small()
    pt = plan["path"][4]
    b = next(b for b in plan["tree"]["branches"] if b["name"] == pt["branch"])
    b["rings"][pt["ring"]].setdefault("obstacles", []).append(pt["point"])
    rehash(plan)
    assert check(plan).get("path")


def test_holding_gripper_that_moves_is_caught():
    plan = small()
    fr = plan["motion"]["frames"]
    i = extension_frame(plan)
    o = np.asarray(fr[i]["rear"]["position"])
    for f in fr:  # slide the held rear gripper of this extension by 5 mm along the bark (body re-drawn)
        if f["step"] == fr[i]["step"] and f["phase"] == "extend" and f is fr[i]:
            f["rear"]["position"] = (o + 0.005 * np.asarray(f["rear"]["direction"])).tolist()
    assert "grip_held" in check(plan)


def test_truncated_motion_misses_the_goal():
    plan = small()
    fr = plan["motion"]["frames"]
    plan["motion"]["frames"] = fr[:extension_frame(plan, last=True) - 8]
    assert "goal" in check(plan)


@lru_cache(maxsize=1)
def _three_branch() -> str:
    return json.dumps(build_plan(Tree.load("three-branch"), "b2"), allow_nan=False)


@pytest.mark.heavy
def test_body_through_a_branch_not_climbed_is_caught():
    plan = json.loads(_three_branch())
    assert verify_plan_dict(plan, "<test>").ok
    b3 = next(b for b in plan["tree"]["branches"] if b["name"] == "b3")
    centre = np.mean(np.asarray(b3["rings"][3]["points"]), axis=0)
    f = plan["motion"]["frames"][-1]
    f["body"][5] = centre.tolist()
    got = check(plan)
    assert got.get("collision") == 1 and "body_shape" in got


def test_a_violation_names_its_step_and_frame(tmp_path, capsys):
    plan = small()
    i = extension_frame(plan)
    lift_rear(plan, i)
    f = tmp_path / "bad.json"
    f.write_text(json.dumps(plan))
    assert main(["verify", str(f)]) == 1
    err = capsys.readouterr().err
    assert f"step {plan['motion']['frames'][i]['step']} waypoint {i}: grip_on_bark:" in err


@pytest.mark.parametrize("where", ["frame", "path"])
def test_non_finite_numbers_are_bad_input(tmp_path, capsys, where):
    plan = small()
    if where == "frame":
        plan["motion"]["frames"][2]["S"] = math.nan
        field = "$.motion.frames[2].S"
    else:
        plan["path"][1]["position"][0] = math.inf
        field = "$.path[1].position[0]"
    with pytest.raises(PlanFileError) as exc:
        verify_plan_dict(copy.deepcopy(plan), "<test>")
    assert exc.value.field == field
    f = tmp_path / "nan.json"
    f.write_text(json.dumps(plan))
    assert main(["verify", str(f)]) == 2
    assert field in capsys.readouterr().err


def test_older_content_without_the_hash_is_bad_input(tmp_path, capsys):
    plan = small()
    del plan["tree"]["tree_hash"]
    f = tmp_path / "old.json"
    f.write_text(json.dumps(plan))
    assert main(["verify", str(f)]) == 2
    assert "$.tree" in capsys.readouterr().err


@pytest.mark.heavy
def test_cli_plans_verify_end_to_end(tmp_path, capsys):
    out = tmp_path / "t.json"
    assert main(["treebot", "plan", "--tree", "three-branch", "--target", "b2", "--out", str(out)]) == 0
    assert main(["verify", str(out)]) == 0
    assert "valid" in capsys.readouterr().out


def test_grip_tolerance_is_tight():
    assert GRIP_TOLERANCE <= 2e-3
