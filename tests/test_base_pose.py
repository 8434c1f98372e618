"""The batch prefilters of FIND-TRANSITION against their one-at-a-time originals.

:class:`climb_ompl.model.base_pose.BasePose` is checked against Pinocchio's forward kinematics and centre of mass,
:meth:`ShouldersReach.many` against :meth:`ShouldersReach.__call__`, :meth:`SupportRegion.outside_many` against
:meth:`SupportRegion.outside_by_more_than`, and :meth:`TransitionFinder.find` with its chunks of draws tested on arrays
against the same calls testing one draw at a time (the path of a robot whose limbs hang from no single body).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest
import yaml

from climb_ompl.climb.transition import TransitionFinder
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.manifold.stance import Stance, hand_targets
from climb_ompl.model.base_pose import BasePose, _elementary
from climb_ompl.model.reach import ShouldersReach, reach_maps
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain


def _carrier(robot):
    (jid,) = {int(robot.model.parents[lb.joint_ids[0]]) for lb in robot.limbs if lb.joint_ids}
    return jid


def _agree_off_the_line(got, want, value, band=1e-9):
    """Two yes/no answers to a test ``value < 0`` (metres) agree wherever ``|value|`` exceeds ``band``: within it
    arithmetic done in another order (arrays, compiled code) may round the other way."""
    far = np.abs(np.asarray(value, dtype=float)) > band
    assert np.array_equal(np.asarray(got, dtype=bool)[far], np.asarray(want, dtype=bool)[far])
    assert far.sum() >= 0.9 * far.size


def _draws(robot, n, sd, seed=0):
    rng = np.random.default_rng(seed)
    q0 = np.asarray(robot.nominal_q, dtype=float)
    return [np.clip(q0 + rng.normal(0.0, sd, robot.nq), robot.lower, robot.upper) for _ in range(n)]


@pytest.mark.parametrize("name", ["lemur", "go1", "planar-3limb", "lemur-hooks"])
def test_base_pose_matches_forward_kinematics_and_com(name):
    robot = RobotModel.load(name)
    pose = BasePose.of(robot, _carrier(robot))
    assert pose is not None and pose.carries_mass(robot)
    qs = _draws(robot, 20, 0.4)
    R, t = pose.poses(np.array([q[pose.coords] for q in qs]))
    c_local = pose.com_local(robot, qs[0])
    for i, q in enumerate(qs):
        pin.forwardKinematics(robot.model, robot.data, q)
        f = robot.data.oMi[pose.jid]
        assert np.allclose(R[i], f.rotation, atol=1e-12) and np.allclose(t[i], f.translation, atol=1e-12)
        q_same_limbs = qs[0].copy()
        q_same_limbs[pose.coords] = q[pose.coords]  # the base of draw i, the limbs of draw 0
        assert np.allclose(R[i] @ c_local + t[i], robot.com(q_same_limbs), atol=1e-12)


def test_base_pose_refuses_what_it_cannot_compose():
    assert _elementary(pin.JointModelFreeFlyer()) is None
    assert _elementary(pin.JointModelSpherical()) is None
    assert _elementary(pin.JointModelRevoluteUnaligned(0.0, 0.6, 0.8))[0] == "R"
    robot = RobotModel.load("double-link")  # one hand on the world, one on the base: no single carrier
    assert len({int(robot.model.parents[lb.joint_ids[0]]) for lb in robot.limbs if lb.joint_ids}) > 1
    assert TransitionFinder(Feasibility.of(robot, Terrain.load("pegs")))._pose() is None
    # a spec naming a limb joint among the base joints: the base coordinates no longer place the body alone
    spec = yaml.safe_load((Path(__file__).parents[1] / "robots" / "planar-3limb.yaml").read_text())
    spec["base"]["joints"] = [*spec["base"]["joints"], "limb3_shoulder"]
    robot = RobotModel.from_spec(spec, base_dir=Path(__file__).parents[1] / "urdf")
    finder = TransitionFinder(Feasibility.of(robot, Terrain.load("planar-wall")))
    assert BasePose.of(robot, _carrier(robot)) is not None and finder._pose() is None


@pytest.mark.parametrize("name, wall", [("lemur", "demo-wall"), ("go1", "slab")])
def test_shoulders_reach_many_matches_one_at_a_time(name, wall):
    robot, terrain = RobotModel.load(name), Terrain.load(wall)
    pose = BasePose.of(robot, _carrier(robot))
    maps = reach_maps(robot, terrain)
    rng = np.random.default_rng(1)
    qs = _draws(robot, 300, 0.1, seed=2)
    R, t = pose.poses(np.array([q[pose.coords] for q in qs]))
    hands = np.asarray(robot.hand_positions(np.asarray(robot.nominal_q, dtype=float)))
    seen = set()
    for trial in range(8):  # targets about the nominal hands, near and far; each limb alone, then all together
        spread = 0.05 * (1 + trial)
        pre = [(lb.joint_ids[0], hands[i] + rng.normal(0.0, spread, 3), float(lb.reach))
               for i, lb in enumerate(robot.limbs)]
        for rows in [[p] for p in pre] + [pre]:
            test = ShouldersReach(robot, maps, rows)
            got = test.many(R, t)
            want = np.array([test(q) for q in qs])
            assert np.array_equal(got, want)
            seen.update(want.tolist())
    assert seen == {True, False}  # (both answers met)


def test_shoulders_reach_many_with_tables_of_other_shapes():
    """Limbs whose reach maps have other numbers of planes and directions (the arrays padded to the largest)."""
    robot, terrain = RobotModel.load("lemur"), Terrain.load("demo-wall")
    pose = BasePose.of(robot, _carrier(robot))
    maps = dict(reach_maps(robot, terrain))
    jid0, jid1 = robot.limbs[0].joint_ids[0], robot.limbs[1].joint_ids[0]
    e1, e2, e3, d0, dd, radii = maps[jid0]
    maps[jid0] = (e1, e2, e3, d0, dd, radii[:5])  # fewer planes: targets deeper are beyond the reach
    e1, e2, e3, d0, dd, radii = maps[jid1]
    maps[jid1] = (e1, e2, e3, d0, dd, radii[:, ::2])  # half the directions
    qs = _draws(robot, 300, 0.1, seed=4)
    R, t = pose.poses(np.array([q[pose.coords] for q in qs]))
    hands = np.asarray(robot.hand_positions(np.asarray(robot.nominal_q, dtype=float)))
    rng = np.random.default_rng(5)
    seen = set()
    for trial in range(8):
        pre = [(lb.joint_ids[0], hands[i] + rng.normal(0.0, 0.03 * (1 + trial), 3), float(lb.reach))
               for i, lb in enumerate(robot.limbs[:2])]
        test = ShouldersReach(robot, maps, pre)
        assert {x.shape for x in test._limits} == {(5, 36), (14, 18)}
        want = np.array([test(q) for q in qs])
        assert np.array_equal(test.many(R, t), want)
        seen.update(want.tolist())
    assert seen == {True, False}


def test_outside_many_matches_one_at_a_time(lemur_start):
    robot, wall, stance, q = lemur_start
    feas = Feasibility.of(robot, wall)
    rng = np.random.default_rng(3)
    for limb in stance.limbs:
        region = feas.region(stance.without(limb))
        if region.is_empty:
            continue
        c = np.asarray(robot.com(q))
        pts = c + rng.normal(0.0, 0.15, (400, 3))
        for d in (0.0, 0.05):
            got = region.outside_many(pts, d)
            want = np.array([region.outside_by_more_than(p, d) for p in pts])
            margin = np.array([region.margin(p) for p in pts])
            _agree_off_the_line(got, want, margin + d)
            assert got.any() and not got.all()
            _agree_off_the_line(got, margin < -d, margin + d)  # the definition
        # points outside by at most 0.05 m from every halfplane: the edges' distances decide them
        worst = (np.column_stack([region.coords(pts)[:, :2], -np.ones(len(pts))])
                 @ region.halfplanes.T).max(axis=1)
        assert np.count_nonzero((worst > 0) & (worst <= 0.05)) >= 10


def test_outside_many_on_a_planar_region():
    """A planar robot's region is an interval: every point is tested one at a time, with the same answers."""
    robot, wall = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    feas = Feasibility.of(robot, wall)
    stance = Stance(dict(zip([lb.name for lb in robot.limbs], [h.id for h in wall.holds[:3]], strict=True)))
    region = feas.region(stance)
    assert region.planar
    pts = np.column_stack([np.linspace(-1.0, 1.0, 41), np.zeros(41), np.ones(41)])
    got = region.outside_many(pts, 0.05)
    want = [region.outside_by_more_than(p, 0.05) for p in pts]
    _agree_off_the_line(got, want, np.array([region.margin(p) for p in pts]) + 0.05)


def test_find_in_chunks_equals_one_draw_at_a_time(lemur_start):
    """The same transitions, draw statistics and failure counts whether the draws' prefilters are computed on arrays or
    one at a time (and the limbs closed in their first order: the failed limb first is for a single carrying body),
    over the grabs and releases out of LEMUR's start and the stances they reach."""
    robot, wall, stance, q = lemur_start
    feas = Feasibility.of(robot, wall)
    batch, single = TransitionFinder(feas), TransitionFinder(feas)
    assert batch._pose() is not None
    single._base_pose = (None,)  # (the path of a robot whose limbs hang from no single body)
    targets = hand_targets(robot, wall, stance)
    queries = []
    for limb in stance.limbs:
        small = stance.without(limb)
        queries.append((stance, small, q))
        for h in wall.holds:
            if h.id not in stance.hold_ids and np.linalg.norm(h.p - targets[limb]) < 0.35:
                queries.append((small, small.with_hold(limb, h.id), q))
    found = 0
    for i, (a, b, near) in enumerate(queries[:40]):
        for skip in (False, True):
            qa = batch.find(a, b, near, seed=i, skip_first=skip)
            qb = single.find(a, b, near, seed=i, skip_first=skip)
            assert (qa is None) == (qb is None)
            if qa is not None:  # the same draw closed by the same code (1e-12: the batch arithmetic's last bits)
                np.testing.assert_allclose(qa, qb, rtol=0.0, atol=1e-12)
                found += 1
    assert batch.stats == single.stats and batch.failures == single.failures
    assert found and any(s[0] == -1 for s in batch.stats) and any(s[2] > 25 for s in batch.stats)


def test_draws_follow_the_one_draw_at_a_time_rule(lemur_start):
    """The draws of a call are those of the rule written one draw at a time (the reference below, with NumPy's
    ``normal`` and ``uniform``): draw ``i > 0`` moves the base by ``normal(0, 1) * sd * (1 + i / 20)``, plus
    ``shift * uniform(0.3, 1.2)`` when ``i`` is odd, clipped to the bounds; every third draw puts the free limbs at
    ``uniform(lower, upper)``.  The same seed, the same draws, chunked or not."""
    robot, wall, stance, q = lemur_start
    finder = TransitionFinder(Feasibility.of(robot, wall))
    base = finder.base
    free = np.array(robot.limbs[0].joint_indices)  # (as if limb 0 were free)
    sd, shift = np.array([0.04, 0.04, 0.12]), np.array([0.01, -0.02, 0.03])
    call = finder._call(Stance(stance), Stance(stance), q)
    call.shifts.append(shift)  # (the shift towards the support region, given)
    for first in (0, 1):
        got = [(a, x.copy()) for a, x, _, _ in finder._draws(call, np.random.default_rng(9), range(first, 150), sd,
                                                             free, None)]
        rng, want = np.random.default_rng(9), []
        for a in range(first, 150):
            x = q.copy()
            if a > 0:
                step = rng.normal(0.0, 1.0, len(base)) * sd * (1.0 + a / 20.0)
                if a % 2 == 1:
                    step = step + shift * rng.uniform(0.3, 1.2)
                x[base] = np.clip(q[base] + step, finder.lo[base], finder.hi[base])
            if a % 3 == 2:
                x[free] = rng.uniform(finder.lo[free], finder.hi[free])
            want.append((a, x))
        assert [a for a, _ in got] == [a for a, _ in want]
        for (_, x), (_, y) in zip(got, want, strict=True):
            np.testing.assert_allclose(x, y, rtol=0.0, atol=1e-12)  # a different draw is centimetres away
