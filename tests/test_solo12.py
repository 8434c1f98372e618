"""Solo-12 from example-robot-data, a spec written from the Go1 template (tests/data/solo12.yaml), whose collision
geometry is triangle meshes: checked as their convex hulls by default (``collision_meshes: convex``), which contain
the meshes (a posture free of collision with the hulls is free of it with the meshes: checked on random postures
against the exact meshes), and a climb of 0.6 m along a hand-written 20-degree ramp (tests/data/ramp20.yaml)."""

from __future__ import annotations

from importlib import metadata

import numpy as np
import pytest
import yaml
from conftest import DATA

try:
    metadata.distribution("example-robot-data")
except metadata.PackageNotFoundError:  # pragma: no cover
    pytest.skip("example-robot-data not installed", allow_module_level=True)

SPEC, RAMP = DATA / "solo12.yaml", DATA / "ramp20.yaml"


def _spec(tmp_path, **changes):
    d = {**yaml.safe_load(SPEC.read_text()), **changes}
    path = tmp_path / "solo12.yaml"
    path.write_text(yaml.safe_dump(d))
    return path


@pytest.fixture(scope="module")
def ramp():
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.model.wall_frame import to_wall_frame

    return to_wall_frame(Terrain.load(RAMP))[0]


def test_meshes_become_hulls_that_contain_them(tmp_path, ramp):
    from climb_ompl.model.robot import RobotModel

    hull, exact = RobotModel.load(SPEC), RobotModel.load(_spec(tmp_path, collision_meshes="exact"))
    checker = hull.collision_checker
    assert len(checker.hulls) == 17 and not exact.collision_checker.hulls
    for i, h in checker.hulls.items():  # every vertex of the mesh inside its hull (qhull's faces, outward)
        P = np.asarray(hull.collision_model.geometryObjects[i].geometry.vertices())
        H = np.asarray(h.points())
        assert len(H) <= len(P) and np.all(np.isin(H.round(9), P.round(9)).all(axis=1))
    rng = np.random.default_rng(0)
    free = hits = 0
    for _ in range(150):
        q = hull.random_configuration(rng)
        h, e = hull.in_collision(q, ramp), exact.in_collision(q, ramp)
        assert e <= h, q  # the meshes collide only where their hulls do
        free += not h
        hits += e
    assert free > 10 and hits > 10  # both outcomes met: the comparison says something
    assert hull.self_collision(hull.nominal_q) == exact.self_collision(exact.nominal_q)  # self pairs: the meshes'


def test_hulls_agree_with_the_meshes_where_the_feet_stand(tmp_path, ramp):
    """On a climb's waypoints (feet resting on the ramp, lifting off, landing: the contact links against the plane
    checked where they sink, not by Coal's one contact point), the hulls give the meshes' answer at every one."""
    from climb_ompl.climb.multistep import default_start
    from climb_ompl.model.robot import RobotModel

    hull, exact = RobotModel.load(SPEC), RobotModel.load(_spec(tmp_path, collision_meshes="exact"))
    stance, q0 = default_start(hull, ramp, seed=0)
    limbs = list(stance)
    rng = np.random.default_rng(1)
    agree = hits = 0
    for _ in range(60):  # the start posture, the base nudged towards and away from the ramp
        q = q0.copy()
        q[:3] += rng.normal(scale=0.004, size=3)
        for contact in (limbs, limbs[1:]):
            h = hull.in_collision(q, ramp, contact_limbs=contact)
            agree += h == exact.in_collision(q, ramp, contact_limbs=contact)
            hits += h
    assert agree == 120 and 10 < hits < 110  # both answers met


def test_bad_collision_meshes_value(tmp_path, cli):
    r = cli("robot", "check", _spec(tmp_path, collision_meshes="hull"))
    assert r.code == 2 and "collision_meshes" in r.err and "convex" in r.err and "exact" in r.err


def test_robot_check_notes(tmp_path, cli):
    """The foot mesh (a half sphere of radius 0.016 m) gets no note when the contact sphere has its radius, one
    when it has another; links within the clearance at the nominal posture are counted over random postures."""
    r = cli("robot", "check", SPEC)
    assert r.code == 0 and "not a sphere" not in r.err, r.err
    spec = yaml.safe_load(SPEC.read_text())
    for lb in spec["limbs"]:
        lb["contact"]["radius"] = 0.025
    r = cli("robot", "check", _spec(tmp_path, limbs=spec["limbs"]))
    assert r.code == 0 and "not a sphere" in r.err and "0.025" in r.err
    r = cli("robot", "check", _spec(tmp_path, ignore_collision_pairs=[["FL_SHOULDER", "FR_SHOULDER"]],
                                    collision_meshes="exact"))
    assert r.code == 0
    assert "postures drawn within the joint limits" in r.err and "base_link with FL_UPPER_LEG in " in r.err, r.err


@pytest.mark.climb
def test_solo12_climbs_the_ramp_without_a_guarded_find_path(ramp):
    """0.6 m along the 20-degree ramp: found, verified, no FIND-PATH call stopped by a time guard (the result does
    not depend on the machine's load), within a CPU budget a tenth of what the exact meshes took."""
    import time

    from climb_ompl.climb.goal import climb_height
    from climb_ompl.climb.multistep import climb_from_start
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.verification.climb import verify

    robot = RobotModel.load(SPEC)
    c0 = time.process_time()
    res, start, _ = climb_from_start(robot, ramp, None, climb=0.6, seed=0)
    cpu = time.process_time() - c0
    assert res is not None and res.found, res.reason if res else start
    assert res.stats.get("path_timeouts", 0) == 0
    assert climb_height(robot, ramp, start.stance, 0.6) > 0
    assert verify(res.plan).ok
    assert cpu < 30.0, cpu
