"""The operator's goals from a state (climb.step), the session file (plan.session) and ``climb-ompl step``.

Oracles: the independent verifier (verification.climb) on every session written; the stances a goal must reach,
written out by hand; the demo wall's geometry for a hold out of reach (its distance from the limb's first joint).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from climb_ompl.climb.step import OperatorGoal, plan_goal, plan_goals
from climb_ompl.errors import PlanFileError, QueryError
from climb_ompl.plan.file import Plan
from climb_ompl.plan.session import Session
from climb_ompl.verification import verify

START = {"ne": "h36", "nw": "h33", "se": "h6", "sw": "h3"}  # LEMUR's default start on demo-wall (seed 0)


@pytest.fixture(scope="module")
def session0():
    """A new session of LEMUR on the demo wall at its default start, and the robot."""
    from climb_ompl.climb.multistep import default_start
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.settings import ClimbSettings

    robot, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    stance, q = default_start(robot, wall, seed=0)
    assert stance == START
    settings = ClimbSettings.for_search("guided", robot=robot)
    return robot, settings, Session.start(robot, wall, stance, q, settings.to_dict(), 0)


def test_goal_texts_and_adjacent_stances() -> None:
    assert OperatorGoal.parse("grab se=h25").target({"ne": "h1"}) == {"ne": "h1", "se": "h25"}
    assert OperatorGoal.parse("release ne").target({"ne": "h1", "se": "h2"}) == {"se": "h2"}
    assert OperatorGoal.parse("stance ne=h1").target({"ne": "h1", "se": "h2"}) == {"ne": "h1"}
    assert str(OperatorGoal.parse(" climb  1.5")) == "climb 1.5"
    for bad in ("grab se", "jump 3", "height x", "release", "stance ne"):
        with pytest.raises(QueryError, match="expected one of"):
            OperatorGoal.parse(bad)
    with pytest.raises(QueryError, match="already holds h1"):
        OperatorGoal.parse("grab ne=h5").target({"ne": "h1"})
    with pytest.raises(QueryError, match="last contact"):
        OperatorGoal.parse("release ne").target({"ne": "h1"})
    with pytest.raises(QueryError, match="not adjacent"):
        OperatorGoal.parse("stance ne=h1,se=h3").target({"ne": "h2", "se": "h4"})


def test_sequence_of_one_step_goals_stops_at_the_first_infeasible(session0) -> None:
    robot, settings, s = session0
    stance, q = s.state()
    goals = ["release se", "grab se=h25", "release ne", "grab ne=h170"]  # h170: near the top of the wall
    out = plan_goals(robot, s.terrain(), stance, q, goals, settings, seed=0)
    assert [r.found for r in out] == [True, True, True, False]
    assert [len(r.steps) for r in out[:3]] == [1, 1, 1]
    assert out[0].steps[0].stance_after == tuple(sorted({k: v for k, v in START.items() if k != "se"}.items()))
    assert dict(out[1].steps[0].stance_after)["se"] == "h25"
    assert "reach" in out[3].reason and "h170" in out[3].reason  # the check that failed, named
    # each step starts where the one before ended
    for a, b in zip(out[:2], out[1:3], strict=True):
        assert np.allclose(a.steps[-1].waypoints[-1], b.steps[0].waypoints[0])


def test_session_accept_fail_undo_verifies(session0, tmp_path) -> None:
    robot, settings, s0 = session0
    s = Session(s0.plan, json.loads(json.dumps(s0.record)))
    for g in ("release se", "grab se=h25"):
        stance, q = s.state()
        r = plan_goal(robot, s.terrain(), stance, q, g, settings, seed=1)
        assert r.found, r.reason
        s.accept(g, r.steps, r.seconds)
    with pytest.raises(QueryError, match="se holds it now"):
        s.fail_hold("h25")
    s.fail_hold("h54")
    stance, q = s.state()
    r = plan_goal(robot, s.terrain(), stance, q, "release ne", settings, seed=2)
    s.accept("release ne", r.steps)
    path = s.save(tmp_path / "session.json")
    assert verify(Plan.load(path)).ok
    back = Session.load(path)
    assert back.n_steps == 3 and back.failed == ["h54"] and "h54" not in back.terrain().hold_ids
    assert [g["outcome"] for g in back.record["goals"]] == ["accepted"] * 3
    back.undo()
    back.undo()  # back to before the grab: the hold failed after it stays failed
    assert back.n_steps == 1 and back.plan.events[0]["at_step"] == 1
    assert verify(Plan.load(back.save(tmp_path / "undone.json"))).ok
    with pytest.raises(QueryError, match="does not start where the robot is"):
        back.accept("release ne", r.steps)


def test_malformed_session_names_the_field(session0, tmp_path) -> None:
    d = session0[2].to_dict()
    d["session"]["goals"] = [{"goal": "release se", "time": "t", "outcome": "accepted"}]
    p = tmp_path / "bad.json"
    p.write_text(json.dumps(d))
    with pytest.raises(PlanFileError, match=r"\$\.session\.goals\[0\]\.at_step"):
        Session.load(p)


def test_cli_step_exit_codes(cli, tmp_path) -> None:
    out = tmp_path / "s.json"
    r = cli("step", "--robot", "lemur", "--terrain", "demo-wall", "--goal", "release se", "--goal", "grab se=h25",
            "--out", out)
    assert r.code == 0, r.err
    assert "goal 2 (grab se=h25): 1 step(s)" in r.out and "% of its limit" in r.out
    r = cli("verify", out)
    assert r.code == 0 and "valid (2 steps" in r.out
    before = out.read_text()
    r = cli("step", out, "--goal", "release ne", "--goal", "grab ne=h54", "--out", out)
    assert r.code == 0, r.err
    r = cli("step", out, "--goal", "grab nw=h5", "--out", out)
    assert r.code == 1 and "goal 1 (grab nw=h5): no step" in r.out and "already holds" in r.out
    assert Session.load(out).n_steps == 4
    assert Session.load(out).record["goals"][-1]["outcome"] == "no plan"
    for args in (("--goal", "grab se=h999"), ("--goal", "fly"), ("--goal", "grab xx=h1")):
        snap = out.read_text()
        r = cli("step", out, *args, "--out", out)
        assert r.code == 2 and r.err.startswith("error:"), (args, r.err)
        assert out.read_text() == snap  # nothing written
    assert before != out.read_text()
    r = cli("step", tmp_path / "missing.json", "--goal", "release se", "--out", tmp_path / "x.json")
    assert r.code == 2 and not (tmp_path / "x.json").exists()
    r = cli("play", out, "--html", tmp_path / "s.html")  # playback takes a session as it takes a plan
    assert r.code == 0 and (tmp_path / "s.html").stat().st_size > 10_000
    r = cli("console")  # neither a session nor a robot and a terrain
    assert r.code == 2 and "--robot and --terrain" in r.err


def test_a_release_that_leaves_no_equilibrium_says_so(session0) -> None:
    """Releasing a limb of a three-hold stance leaves LEMUR hanging from two holds of a vertical wall: the refusal
    names the equilibrium check with the stance that would remain, not only the search's frontier."""
    robot, settings, s = session0
    stance, q = s.state()
    out = plan_goals(robot, s.terrain(), stance, q, ["release se", "release ne"], settings, seed=0)
    assert [r.found for r in out] == [True, False]
    assert "with ne released from h36" in out[1].reason and "equilibrium" in out[1].reason, out[1].reason
