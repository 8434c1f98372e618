"""MRWALLSPECT III transition gaits (Kim, Kang & Choi) on the real model: Pinocchio FK, Coal collision, CLI."""

from __future__ import annotations

import json
import math
import subprocess
import sys

import numpy as np
import pytest

from climb_ompl.errors import InputError, RobotModelError
from climb_ompl.mrwallspect.geometry import rot_y
from climb_ompl.mrwallspect.robot import LEGS, SlopeRobot
from climb_ompl.mrwallspect.slope import plan_slope, scene_items

CASES = [(35.0, "concave"), (35.0, "convex"), (90.0, "concave"), (90.0, "convex")]


@pytest.fixture(scope="module")
def robot() -> SlopeRobot:
    return SlopeRobot.load("mrwallspect3")


@pytest.fixture(scope="module")
def results(robot):
    return {c: plan_slope(c[0], c[1], robot=robot) for c in CASES}


def _surface_signed_distance(p: np.ndarray, planes: list[dict]) -> float:
    """Signed distance of p to the union of the two solid slabs' top faces (analytic, no Coal).

    Positive: above both surfaces (for points over each plane's extent); the robot must stay on the
    free side of every plane whose extent it is over.
    """
    out = math.inf
    for pl in planes:
        c, n, t = (np.asarray(pl[k], dtype=float) for k in ("point", "normal", "direction"))
        u = float((p - c) @ t)
        if abs(u) <= pl["extent"][0] / 2:
            out = min(out, float((p - c) @ n))
    return out


@pytest.mark.heavy
@pytest.mark.parametrize("case", CASES, ids=[f"{k}{a:g}" for a, k in CASES])
def test_transition_found_and_checks_pass(case, results, robot):
    res = results[case]
    assert res.found, res.reason
    plan = res.plan
    assert all(c["ok"] for c in res.checks.values()), res.checks
    assert res.checks["ik_round_trip"]["value"] <= 1e-9
    assert res.checks["collision"]["value"] > 0
    assert min(sum(f["attached"]) for f in plan["frames"]) >= 3
    if case[1] == "convex":
        e = res.checks["edge_clearance"]
        assert e["h_m_eq22"] > robot.p["B_t"] and e["h_m_measured_min"] >= e["h_m_eq22"] - 1e-9
    eq = res.checks["equilibrium"]
    if not eq.get("skipped"):
        assert eq["min_margin"] > 0


@pytest.mark.parametrize("case", CASES, ids=[f"{k}{a:g}" for a, k in CASES])
def test_frames_against_independent_kinematics(case, results, robot):
    """Re-check every frame: Pinocchio FK reaches the stored ankles, attached feet never slide and
    sit h_f above their plane, the body box corners stay above the surfaces (analytic, not Coal)."""
    plan = results[case].plan
    g = robot.p
    normals = {1: np.asarray(plan["planes"][0]["normal"]), 2: np.asarray(plan["planes"][1]["normal"])}
    box = g["body_box"]
    corners = np.array([[x, y, z] for x in box["x"] for y in box["y"] for z in box["z"]])
    prev = None
    for f in plan["frames"]:
        q = np.asarray(f["q"])
        assert np.all(q >= robot.lower - 1e-12) and np.all(q <= robot.upper + 1e-12)
        ankles = robot.ankle_positions(q)
        for j, leg in enumerate(LEGS):
            assert np.linalg.norm(ankles[leg] - np.asarray(f["ankles"][j])) <= 1e-9
            if f["attached"][j]:
                n = normals[f["plane"][j]]
                assert float(ankles[leg] @ n) == pytest.approx(g["h_f"], abs=1e-9)
                if prev is not None and prev["attached"][j]:
                    assert np.linalg.norm(np.asarray(prev["ankles"][j]) - ankles[leg]) <= 1e-9
        world = np.array([q[0], 0.0, q[1]]) + corners @ rot_y(q[2]).T
        assert min(_surface_signed_distance(c, plan["planes"]) for c in world) > 0
        # only one foot moves at a time and never while the body moves
        if prev is not None and f["phase"] == "body":
            assert all(f["attached"])
        prev = f
    # the gait ends with every foot on the second plane, the body past P_E
    assert plan["frames"][-1]["plane"] == [2, 2, 2, 2]
    assert plan["frames"][0]["plane"] == [1, 1, 1, 1]


def test_hill_up_and_down_sequences(results):
    """The paper's simulation: up a 35-degree hill (concave then convex) and down (convex then concave)."""
    up = [results[(35.0, "concave")], results[(35.0, "convex")]]
    assert all(r.found for r in up)
    # both transitions at the same slope share d-independent geometry: the body ends parallel to plane 2
    for r in up:
        last = r.plan["frames"][-1]
        sign = 1.0 if r.plan["query"]["kind"] == "convex" else -1.0
        assert last["body"]["pitch"] == pytest.approx(sign * math.radians(35.0), abs=1e-9)


@pytest.mark.heavy
def test_impossible_angles_are_reported_infeasible_with_the_reason(robot):
    res = plan_slope(120.0, "convex", robot=robot, equilibrium=False)
    assert res.status == "infeasible" and res.plan is None
    assert any(k in res.reason for k in ("collision failed", "reachable failed", "edge_clearance failed"))
    assert "t = " in res.reason or "d" in res.reason
    res = plan_slope(150.0, "concave", robot=robot, equilibrium=False)
    assert res.status == "infeasible" and "failed" in res.reason
    # a d that violates Eq. (22) at a convex edge is named as such
    res = plan_slope(90.0, "convex", d=0.5, robot=robot, equilibrium=False)
    assert res.status == "infeasible" and "Eq. (22)" in res.reason


def test_a_d_below_eq_10_at_a_concave_slope_is_bad_input(robot):
    """At a concave slope Eq. (10) gives the body's arc the radius R = d / tan(gamma/2) - h: a given d at or below
    h tan(gamma/2) has no arc.  It used to write a plan (R < 0, exit 0) that ``verify`` refused."""
    low = robot.p["h"] * math.tan(math.radians(35.0) / 2)
    with pytest.raises(InputError, match=r"d: .* Eq\. \(10\) needs d > h tan\(gamma/2\) = "):
        plan_slope(35.0, "concave", d=0.9 * low, robot=robot, equilibrium=False)
    assert plan_slope(35.0, "concave", d=low + 0.02, robot=robot, equilibrium=False).plan["trajectory"]["R"] > 0


def test_bad_input_raises_input_errors(robot, tmp_path):
    for kwargs in ({"angle_deg": 0.0, "kind": "concave"}, {"angle_deg": 180.0, "kind": "convex"},
                   {"angle_deg": 30.0, "kind": "flat"}, {"angle_deg": 30.0, "kind": "convex", "d": -1.0}):
        with pytest.raises(InputError):
            plan_slope(robot=robot, **kwargs)
    bad = tmp_path / "bad.yaml"
    bad.write_text(robot.spec_path.read_text().replace("  stride: 0.06", "  stride: fast"))
    with pytest.raises(RobotModelError, match="gait.stride"):
        SlopeRobot.load(bad)


def test_deterministic(robot, results):
    again = plan_slope(35.0, "convex", robot=robot, seed=7)
    a, b = again.plan["frames"], results[(35.0, "convex")].plan["frames"]
    assert [f["q"] for f in a] == [f["q"] for f in b]
    assert again.plan["seed"] == 7


def test_scene_items_match_the_plan(results):
    plan = json.loads(json.dumps(results[(90.0, "concave")].plan))  # as read back from a file
    sc = scene_items(plan)
    assert len(sc["planes"]) == 2 and all(p["corners"].shape == (4, 3) for p in sc["planes"])
    for pl, quad in zip(plan["planes"], sc["planes"], strict=True):
        n = np.asarray(pl["normal"])
        assert np.allclose((quad["corners"] - np.asarray(pl["point"])) @ n, 0.0, atol=1e-12)
    assert len(sc["frames"]) == len(plan["frames"])
    for f, s in zip(plan["frames"], sc["frames"], strict=True):
        R = s["body_pose"][:3, :3]
        assert np.allclose(R.T @ R, np.eye(3), atol=1e-12)
        for j in range(4):  # numpy FK of the drawing == the stored ankle (from IK, checked by Pinocchio)
            assert np.linalg.norm(s["legs"][j][-1] - np.asarray(f["ankles"][j])) <= 1e-9
        assert s["attached"].tolist() == f["attached"]


def test_cli_plan_and_exit_codes(tmp_path, capsys):
    from climb_ompl.cli import main

    out = tmp_path / "plan.json"
    assert main(["slope", "plan", "--angle", "35", "--kind", "convex", "--seed", "3", "--out", str(out)]) == 0
    plan = json.loads(out.read_text())
    assert plan["schema_version"] == 1 and plan["kind"] == "slope" and plan["seed"] == 3
    assert plan["query"]["angle"] == 35.0 and plan["query"]["kind"] == "convex"
    assert {"planes", "robot", "frames", "checks", "stats", "climb_ompl_version"} <= set(plan)
    assert plan["robot"]["name"] == "mrwallspect3" and "gait" in plan["robot"]["spec"]
    assert len(plan["planes"]) == 2 and {"point", "normal", "extent"} <= set(plan["planes"][0])
    f0 = plan["frames"][0]
    assert {"t", "body", "q", "attached", "feet"} <= set(f0) and len(f0["q"]) == 15
    assert main(["slope", "plan", "--angle", "200", "--kind", "convex", "--out", str(tmp_path / "x.json")]) == 2
    assert not (tmp_path / "x.json").exists()
    capsys.readouterr()
    assert main(["slope", "plan", "--angle", "35", "--kind", "concave", "--d", "0.01", "--out",
                 str(tmp_path / "x.json")]) == 2  # the error names the option, not plan_slope's argument
    assert "error: --d: 0.01 m gives the body no arc" in capsys.readouterr().err


@pytest.mark.heavy
def test_cli_infeasible_exits_1_in_a_subprocess(tmp_path):
    out = tmp_path / "p.json"
    proc = subprocess.run([sys.executable, "-m", "climb_ompl", "slope", "plan", "--angle", "150", "--kind",
                           "concave", "--out", str(out)], capture_output=True, text=True, timeout=120)
    assert proc.returncode == 1, proc.stderr
    assert "infeasible" in proc.stderr and "failed" in proc.stderr
    assert not out.exists()


def test_wall_to_ceiling_uses_tilted_gravity(robot):
    """A 90-degree concave transition on a wall (tilt 90) is wall to ceiling: gravity along -x."""
    res = plan_slope(90.0, "concave", tilt_deg=90.0, robot=robot)
    assert res.found, res.reason
    assert res.plan["gravity"] == pytest.approx([-9.81, 0.0, 0.0], abs=1e-12)
    assert res.plan["query"]["tilt"] == 90.0
    eq = res.checks["equilibrium"]
    if not eq.get("skipped"):
        assert eq["min_margin"] > 0


def test_robot_spec_loads_through_the_robot_module():
    """robots/mrwallspect3.yaml follows the shared spec format (RobotModel) and agrees with SlopeRobot."""
    robot_mod = pytest.importorskip("climb_ompl.model.robot")
    rm = robot_mod.RobotModel.load("mrwallspect3")
    sr = SlopeRobot.load("mrwallspect3")
    assert rm.nq == sr.nq == 15 and [lb.name for lb in rm.limbs] == list(LEGS)
    q = np.asarray(rm.nominal_q, dtype=float)
    ank = sr.ankle_positions(q)
    assert np.allclose(np.asarray(rm.hand_positions(q)), np.array([ank[n] for n in LEGS]), atol=1e-12)
