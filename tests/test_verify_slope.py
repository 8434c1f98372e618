"""``climb-ompl verify`` on slope-transition plans (Kim, Kang & Choi (MRWALLSPECT III)): plans the gait
planner writes pass, each injected fault is caught, named and located (step, frame, time); bad input is exit 2
naming the JSON path."""

from __future__ import annotations

import json
import math
from functools import lru_cache

import numpy as np
import pytest

from climb_ompl.cli import main
from climb_ompl.errors import PlanFileError
from climb_ompl.mrwallspect.slope import plan_slope
from climb_ompl.plan.file import sha256_json
from climb_ompl.verification import verify_plan_dict

FAST = {"resolution": 0.2}  # few states between frames: the faults below sit at frames


@lru_cache(maxsize=2)
def _plan(kind: str) -> str:
    res = plan_slope(90.0 if kind == "concave" else 60.0, kind)
    assert res.found, res.reason
    return json.dumps(res.plan, allow_nan=False)


def plan(kind: str = "concave") -> dict:
    return json.loads(_plan(kind))


def check(p: dict, **kw) -> dict[str, int]:
    return verify_plan_dict(p, "<test>", **{**FAST, **kw}).by_check()


def swing_frame(p: dict) -> int:
    """A frame in the middle of a leg swing (three feet attached)."""
    return next(i for i, f in enumerate(p["frames"]) if f["phase"].startswith("swing") and sum(f["attached"]) == 3
                and i + 1 < len(p["frames"]) and sum(p["frames"][i + 1]["attached"]) == 3)


@pytest.mark.heavy
@pytest.mark.parametrize("kind", ["concave", "convex"])
def test_planner_plans_verify_densely(kind):
    p = plan(kind)
    rep = verify_plan_dict(p, "<test>")
    assert rep.ok, [str(v) for v in rep.violations]
    assert rep.states_checked > 2 * len(p["frames"])  # states between the planner's frames too


@pytest.mark.heavy
def test_foot_detached_is_caught():
    p = plan()
    i = swing_frame(p)
    f = p["frames"][i]
    j = next(k for k in range(4) if f["attached"][k])
    f["attached"][j] = False
    rep = verify_plan_dict(p, "<test>", **FAST)
    hits = [v for v in rep.violations if v.check == "support"]
    assert hits and hits[0].step == f["step"] and math.floor(hits[0].waypoint) in (i - 1, i)
    assert "only 2 feet attached" in hits[0].message and "t = " in hits[0].message


@pytest.mark.heavy
def test_leg_through_the_plane_is_caught():
    """The knee of a standing leg folded so that the shank and foot go through the floor."""
    p = plan()
    f = p["frames"][0]
    f["q"][5] += 1.0  # leg1 knee
    got = check(p)
    assert got.get("clearance") and got.get("feet_on_planes"), got


@pytest.mark.heavy
def test_foot_off_its_plane_is_caught():
    p = plan()
    f = p["frames"][3]
    j = next(k for k in range(4) if f["attached"][k])
    n = np.asarray(p["planes"][f["plane"][j] - 1]["normal"])
    f["feet"][j] = (np.asarray(f["feet"][j]) + 0.01 * n).tolist()
    got = check(p)
    assert got.get("feet_on_planes"), got


@pytest.mark.heavy
def test_attached_foot_that_slides_is_caught():
    p = plan()
    fr = p["frames"]
    i = next(i for i in range(1, len(fr)) if fr[i]["phase"] == "body")
    for f in fr[i:]:  # from frame i on, the footprint of foot 4 is said to be 5 mm further along its plane
        if f["attached"][3]:
            f["feet"][3][0] += 0.005
        else:
            break
    assert "feet_on_planes" in check(p)


@pytest.mark.heavy
def test_joint_past_its_limit_is_caught():
    p = plan()
    p["frames"][7]["q"][3] = 1.6  # leg1 yaw, limit 1.4 rad
    assert "joint_limits" in check(p)


@pytest.mark.heavy
def test_tampered_planes_are_caught():
    p = plan()
    p["planes"][1]["normal"] = [-0.9, 0.0, 0.1]
    assert check(p).get("integrity") == 1
    p["planes_sha256"] = sha256_json(p["planes"])  # the hash agrees again: the geometry does not
    got = check(p)
    assert "trajectory" in got and "feet_on_planes" in got, got


@pytest.mark.heavy
def test_stated_arc_that_is_not_eq_10_is_caught():
    p = plan()
    p["trajectory"]["R"] += 0.01
    assert check(p) == {"trajectory": 1}


@pytest.mark.heavy
def test_body_off_the_trajectory_is_caught():
    p = plan()
    f = p["frames"][40]
    for key in ("origin", "front"):
        f["body"][key][2] += 0.01
    f["q"][1] += 0.01
    got = check(p)
    assert got.get("trajectory"), got


@pytest.mark.heavy
def test_convex_trajectory_is_checked_during_the_transition():
    p = plan("convex")
    i = next(i for i, f in enumerate(p["frames"]) if 0.1 < f["body"]["pitch"] < 0.9)
    f = p["frames"][i]
    u = np.array([math.cos(f["body"]["pitch"]), 0.0, -math.sin(f["body"]["pitch"])])
    for key in ("origin", "front"):  # slid 2 cm along the body axis: still tangent, wrong division (Eq. 21)
        f["body"][key] = (np.asarray(f["body"][key]) + 0.02 * u).tolist()
    f["q"][0] += 0.02 * u[0]
    f["q"][1] += 0.02 * u[2]
    got = check(p)
    assert got.get("trajectory"), got


def test_no_equilibrium_is_caught():
    p = plan()
    p["frames"] = p["frames"][:12]  # (each failing state costs an exact cone program: keep it short)
    p["gravity"] = [-9.81 * 60, 0.0, 0.0]  # along the floor, 60 g: more than the suction feet can hold
    got = check(p)
    assert got.get("equilibrium") and got.get("goal") == 1, got


@pytest.mark.heavy
def test_truncated_plan_misses_the_goal():
    p = plan()
    p["frames"] = p["frames"][:-40]
    assert check(p) == {"goal": 1}


@pytest.mark.heavy
def test_tampered_robot_is_caught():
    p = plan()
    p["robot"]["spec"]["gait"]["stride"] = 0.07
    assert check(p) == {"integrity": 1}


@pytest.mark.heavy
@pytest.mark.parametrize("field", ["$.frames[5].q[4]", "$.planes[0].point[0]"])
def test_non_finite_numbers_are_bad_input(tmp_path, capsys, field):
    p = plan()
    if field.startswith("$.frames"):
        p["frames"][5]["q"][4] = math.nan
    else:
        p["planes"][0]["point"][0] = -math.inf
    with pytest.raises(PlanFileError) as exc:
        verify_plan_dict(json.loads(json.dumps(p)), "<test>")
    assert exc.value.field == field
    f = tmp_path / "nan.json"
    f.write_text(json.dumps(p))
    assert main(["verify", str(f)]) == 2
    assert field in capsys.readouterr().err


def test_older_content_is_bad_input(tmp_path, capsys):
    p = plan()
    del p["robot"]["urdf"]
    f = tmp_path / "old.json"
    f.write_text(json.dumps(p))
    assert main(["verify", str(f)]) == 2
    assert "$.robot" in capsys.readouterr().err


@pytest.mark.heavy
def test_cli_plans_verify_end_to_end(tmp_path, capsys):
    out = tmp_path / "s.json"
    assert main(["slope", "plan", "--angle", "90", "--kind", "concave", "--out", str(out)]) == 0
    assert main(["verify", str(out)]) == 0
    assert "valid" in capsys.readouterr().out


@pytest.mark.heavy
def test_a_query_the_plan_does_not_answer_is_caught():
    """The plan's planes and trajectory are checked against each other; the query it claims to answer is now
    checked against them too (an edited ``query.angle`` or ``query.kind`` passed)."""
    p = plan("convex")
    assert check(p) == {}
    for key, value in (("angle", 90.0), ("kind", "concave")):
        q = json.loads(json.dumps(p))
        q["query"][key] = value
        assert check(q) == {"integrity": 1}, key

