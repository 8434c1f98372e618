"""``climb-ompl export``: the ROS 2 bag read back with rosbags matches the plan, the CSV and NPZ tables hold the
plan's samples, a video is written, and bad input exits 2 with one line and no file."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from climb_ompl.export.rosbag import TOPICS, read_bag, write_bag
from climb_ompl.export.samples import plan_samples
from climb_ompl.model.robot import RobotModel
from climb_ompl.plan.file import Plan, robot_from_plan
from climb_ompl.trajectory.retime import time_plan

OLD = Path(__file__).parent / "data" / "plans" / "double-link-pegs-0.1.0.json"


@pytest.fixture(scope="module")
def timed():
    plan = Plan.load(OLD)
    robot = robot_from_plan(plan)
    return time_plan(plan, robot)[0], robot


def _export(*args: str) -> subprocess.CompletedProcess[str]:
    return subprocess.run([sys.executable, "-m", "climb_ompl", "export", *args], capture_output=True, text=True,
                          timeout=300)


def test_the_bag_read_back_matches_the_plan(timed, tmp_path):
    plan, robot = timed
    bag = write_bag(plan, robot, tmp_path / "climb.bag")
    msgs = read_bag(bag)
    joints = [m for topic, _, m in msgs if topic == TOPICS["joints"]]
    base = [m for topic, _, m in msgs if topic == TOPICS["base"]]
    events = [json.loads(m.data) for topic, _, m in msgs if topic == TOPICS["events"]]
    assert len(joints) == len(base) == len(events) == len(plan.steps)
    act = np.nonzero(robot.actuated)[0]
    t0 = 0.0
    for s, jt, bt, ev in zip(plan.steps, joints, base, events, strict=True):
        assert list(jt.joint_names) == ["theta1", "theta2"]  # the URDF's actuated joints
        assert (jt.header.stamp.sec, jt.header.stamp.nanosec) == (0, 0)  # "start on receipt"
        q, v, a = s.q, np.array(s.velocities), np.array(s.accelerations)
        got = np.array([p.positions for p in jt.points])
        assert np.max(np.abs(got - q[:, act])) <= 1e-9
        assert np.max(np.abs(np.array([p.velocities for p in jt.points]) - v[:, act])) <= 1e-9
        assert np.max(np.abs(np.array([p.accelerations for p in jt.points]) - a[:, act])) <= 1e-9
        tfs = np.array([p.time_from_start.sec + 1e-9 * p.time_from_start.nanosec for p in jt.points])
        assert np.max(np.abs(tfs - np.asarray(s.times))) <= 1e-9
        # the base's prismatic x and z joints: the body moves as they do, at their speed
        xyz = np.array([[p.transforms[0].translation.x, p.transforms[0].translation.z] for p in bt.points])
        assert np.max(np.abs((xyz - xyz[0]) - (q[:, :2] - q[0, :2]))) <= 1e-9
        lin = np.array([[p.velocities[0].linear.x, p.velocities[0].linear.z] for p in bt.points])
        assert np.max(np.abs(lin - v[:, :2])) <= 1e-9
        t0 += s.duration
        assert ev == {"step": s.index, "t": pytest.approx(t0), "action": s.action, "limb": s.limb, "hold": s.hold}


def test_csv_and_npz_hold_the_plans_samples(tmp_path):
    for fmt in ("csv", "npz"):
        r = _export(str(OLD), "--format", fmt, "--out", str(tmp_path / f"c.{fmt}"))
        assert r.returncode == 0, r.stderr
    plan = Plan.load(OLD)
    tp = time_plan(plan)[0]
    z = np.load(tmp_path / "c.npz")
    want = np.concatenate([s.q for s in tp.steps])
    assert z["q"].shape == want.shape and np.allclose(z["q"], want, rtol=0, atol=1e-12)
    assert list(z["joint_names"]) == list(RobotModel.load("double-link").joint_names)
    rows = np.loadtxt(tmp_path / "c.csv", delimiter=",", skiprows=1)
    header = (tmp_path / "c.csv").read_text().splitlines()[0].split(",")
    assert header[:3] == ["t", "step", "q_base_x"] and rows.shape == (len(want), len(header))
    assert np.allclose(rows[:, 2:2 + want.shape[1]], want, rtol=0, atol=1e-12)
    assert np.all(np.diff(rows[:, 0]) >= 0) and rows[-1, 0] == pytest.approx(tp.execution_s)


def test_samples_at_a_rate_follow_the_plan(timed):
    plan, robot = timed
    s = plan_samples(plan, robot, rate=20.0)
    own = plan_samples(plan, robot)
    assert s.t[-1] == pytest.approx(own.t[-1])
    # the Hermite curve passes through the plan's samples: at the plan's times it gives the waypoints
    for k in (0, len(plan.steps) - 1):
        rows = own.step == k
        np.testing.assert_allclose(np.interp(own.t[rows][-1], s.t[s.step == k], s.q[s.step == k, 2]),
                                   own.q[rows][-1, 2], atol=1e-9)
    assert np.all(np.isnan(s.tau))  # the double-link robot stores no static torques (equilibrium: false)


@pytest.mark.parametrize("args, words", [
    (["--format", "mov"], "--format: 'mov' is not one of"),
    (["--format", "csv", "--rate", "0"], "--rate"),
    (["--format", "mp4", "--size", "big"], "--size"),
    (["--format", "gif"], "does not end in .gif"),
])
def test_bad_options_exit_2_in_one_line(tmp_path, args, words):
    r = _export(str(OLD), *args, "--out", str(tmp_path / "x.out"))
    assert r.returncode == 2 and words in r.stderr and len(r.stderr.strip().splitlines()) == 1
    assert not (tmp_path / "x.out").exists()


def test_other_plan_kinds_and_unwritable_outputs_are_refused(tmp_path):
    d = json.loads(OLD.read_text())
    d["kind"] = "slope"
    other = tmp_path / "slope.json"
    other.write_text(json.dumps(d))
    r = _export(str(other), "--format", "csv", "--out", str(tmp_path / "s.csv"))
    assert r.returncode == 2 and "slope plan" in r.stderr and len(r.stderr.strip().splitlines()) == 1
    r = _export(str(OLD), "--format", "csv", "--out", str(tmp_path / "no" / "s.csv"))
    assert r.returncode == 2 and "does not exist" in r.stderr
    (tmp_path / "b.bag").mkdir()
    r = _export(str(OLD), "--format", "ros2-bag", "--out", str(tmp_path / "b.bag"))
    assert r.returncode == 2 and "exists already" in r.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["b.bag", "slope.json"]


@pytest.mark.browser
def test_a_gif_and_an_mp4_of_the_playback(tmp_path):
    import imageio.v3 as iio

    for fmt in ("gif", "mp4"):
        out = tmp_path / f"v.{fmt}"
        r = _export(str(OLD), "--format", fmt, "--out", str(out), "--fps", "2", "--speedup", "4", "--size", "160x120")
        assert r.returncode == 0, r.stderr
        frames = iio.imread(out, index=None)
        assert len(frames) == int(14 / 2) + 1 and frames[0].shape[:2] == (120, 160)
        assert np.std(frames[0]) > 5  # a picture, not a blank canvas
    assert sorted(p.name for p in tmp_path.iterdir()) == ["v.gif", "v.mp4"]
