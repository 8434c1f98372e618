"""One-step planning end to end (issue 6): FIND-TRANSITION / FIND-PATH, every planner and space.

Every returned path is checked by :func:`verify_path`, an independent verifier that does not reuse the
planner's checker objects: hands on holds from a fresh Pinocchio ``Data``, the CoM in equilibrium by a
per-point LP (scipy, outer-linearised friction cones), joint limits from the Pinocchio model, collision
through the robot model's Coal query.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from scipy.optimize import linprog

from climb_ompl._ompl import PLANNER_NAMES
from climb_ompl.errors import PlannerNotFound, QueryError
from climb_ompl.onestep import PlanResult, find_path, find_transition
from climb_ompl.robot import RobotModel
from climb_ompl.stance import DEFAULT_TOLERANCE, SPACE_NAMES, Stance
from climb_ompl.terrain import Terrain

PLANAR = {"name": "planar-test", "dim": 2, "friction": 0.8, "holds": [
    {"id": "a", "position": [-0.35, 0.8], "normal": [0.4, 1]},
    {"id": "b", "position": [0.35, 0.8], "normal": [-0.4, 1]},
    {"id": "c", "position": [-0.3, 1.4], "normal": [0.3, 1]},
    {"id": "d", "position": [0.3, 1.35], "normal": [-0.3, 1]}]}


# ---- independent verifier -------------------------------------------------------------------------------
def lp_equilibrium(terrain: Terrain, holds: list[str], mass: float, com: np.ndarray, planar: bool,
                   edges: int = 32) -> bool:
    """Per-point LP oracle: contact forces in (outer-linearised) friction cones balancing gravity at ``com``."""
    g = terrain.g * mass
    cols, pts = [], []
    for h in holds:
        hd = terrain.hold(h)
        n = hd.n
        if planar:
            t = np.array([n[2], 0.0, -n[0]])
            gens = [n + hd.friction * t, n - hd.friction * t]
        else:
            t1 = np.cross(n, [0.0, 0.0, 1.0] if abs(n[2]) < 0.9 else [1.0, 0.0, 0.0])
            t1 /= np.linalg.norm(t1)
            t2 = np.cross(n, t1)
            mu = hd.friction / np.cos(np.pi / edges)  # circumscribed pyramid: a necessary condition
            gens = [n + mu * (np.cos(a) * t1 + np.sin(a) * t2) for a in np.linspace(0, 2 * np.pi, edges, False)]
        for v in gens:
            cols.append(np.r_[v, np.cross(hd.p, v)])
            pts.append(h)
    A = np.array(cols).T
    b = -np.r_[g, np.cross(com, g)]
    rows = [0, 2, 4] if planar else list(range(6))
    res = linprog(np.zeros(A.shape[1]), A_eq=A[rows], b_eq=b[rows], bounds=(0, None), method="highs")
    return res.status == 0


def verify_path(robot: RobotModel, terrain: Terrain, stance: Stance, path: list[np.ndarray],
                max_step: float = 0.05, tol: float = DEFAULT_TOLERANCE) -> None:
    """Assert every waypoint is feasible at ``stance`` (independent of the planner's objects)."""
    model = robot.model
    data = model.createData()
    names = [lb.name for lb in robot.limbs]
    axes = [0, 2] if robot.planar else [0, 1, 2]
    assert len(path) >= 2
    for k, q in enumerate(path):
        pin.framesForwardKinematics(model, data, q)
        for limb, hold in stance.items():
            fid = model.getFrameId(robot.limbs[names.index(limb)].hand_frame)
            err = np.linalg.norm((data.oMf[fid].translation - terrain.hold(hold).p)[axes])
            assert err <= tol * 1.01, f"waypoint {k}: hand {limb} is {err:.2e} m from {hold}"
        assert np.all(q >= model.lowerPositionLimit - 1e-9) and np.all(q <= model.upperPositionLimit + 1e-9)
        com = pin.centerOfMass(model, data, q)
        assert lp_equilibrium(terrain, list(stance.hold_ids), robot.mass, com, robot.planar), f"waypoint {k}: CoM"
        assert not robot.in_collision(q, terrain, contact_limbs=stance.limbs) or k in (0, len(path) - 1)
        if k:
            assert np.max(np.abs(q - path[k - 1])) <= max_step + 1e-9


# ---- fixtures ---------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def planar():
    robot = RobotModel.load("planar-3limb")
    terrain = Terrain.from_dict(PLANAR)
    s = Stance(limb1="a", limb2="b")
    qs = find_transition(robot, terrain, s, s.with_hold("limb3", "c"), seed=1)
    qg = find_transition(robot, terrain, s, s.with_hold("limb3", "d"), seed=2)
    assert qs is not None and qg is not None
    return robot, terrain, s, qs, qg


def test_transition_is_feasible_for_both_stances(planar):
    robot, terrain, s, qs, _ = planar
    verify_path(robot, terrain, s.with_hold("limb3", "c"), [qs, qs])
    verify_path(robot, terrain, s, [qs, qs])


def test_planar_move_lazyprm_verified(planar):
    """Seed 000 section 3: the three-limbed robot moves its free limb from hold c to hold d."""
    robot, terrain, s, qs, qg = planar
    res = find_path(robot, terrain, s, qs, qg, seed=3, max_iterations=20000, time_limit=20)
    assert isinstance(res, PlanResult) and res.solved, res.stats
    assert np.allclose(res.path[0], qs) and np.allclose(res.path[-1], qg)
    verify_path(robot, terrain, s, res.path)
    assert set(res.stats["rejections"]) >= {"joint_limits", "equilibrium", "collision"}
    assert res.stats["roadmap_vertices"] >= 2


def test_same_seed_same_path(planar):
    robot, terrain, s, qs, qg = planar
    kw = dict(seed=5, max_iterations=5000, sampler="joint-by-joint+straight-elbow", time_limit=30)
    a = find_path(robot, terrain, s, qs, qg, **kw)
    b = find_path(robot, terrain, s, qs, qg, **kw)
    assert a.status == b.status
    assert len(a.path) == len(b.path) and all(np.array_equal(x, y) for x, y in zip(a.path, b.path, strict=False))


@pytest.mark.parametrize("planner", PLANNER_NAMES)
def test_every_planner_runs(planar, planner):
    """Every registered planner on the projected space: no crash, a verified path or an honest failure."""
    robot, terrain, s, qs, qg = planar
    res = find_path(robot, terrain, s, qs, qg, planner=planner, time_limit=0.4, seed=0, simplify=False)
    assert res.status in ("exact", "no-path", "timeout")
    if res.solved:
        verify_path(robot, terrain, s, res.path)


@pytest.mark.parametrize("space", SPACE_NAMES)
@pytest.mark.parametrize("planner", ["LazyPRM", "PRM", "RRTConnect"])
def test_every_space_runs(planar, space, planner):
    robot, terrain, s, qs, qg = planar
    res = find_path(robot, terrain, s, qs, qg, planner=planner, space=space, time_limit=1.0, seed=0)
    assert res.status in ("exact", "no-path", "timeout")
    if res.solved:
        verify_path(robot, terrain, s, res.path)


def test_bad_input(planar):
    robot, terrain, s, qs, qg = planar
    with pytest.raises(PlannerNotFound, match="LazyPRM"):
        find_path(robot, terrain, s, qs, qg, planner="Nope")
    with pytest.raises(PlannerNotFound, match="projected"):
        find_path(robot, terrain, s, qs, qg, space="nope")
    with pytest.raises(PlannerNotFound, match="straight-elbow"):
        find_path(robot, terrain, s, qs, qg, sampler="nope")
    with pytest.raises(QueryError, match="no hold"):
        find_path(robot, terrain, Stance(limb1="a", limb2="zz"), qs, qg)
    with pytest.raises(QueryError, match="unknown limb"):
        find_path(robot, terrain, Stance(limb9="a", limb2="b"), qs, qg)
    bad = qs.copy()
    bad[0] += 0.1
    with pytest.raises(QueryError, match="violates the stance"):
        find_path(robot, terrain, s, bad, qg)
    with pytest.raises(QueryError, match="projected"):
        find_path(robot, terrain, s, qs, qg, space="atlas", sampler="straight-elbow")
    with pytest.raises(QueryError, match="adjacent"):
        find_transition(robot, terrain, s, Stance(limb1="c", limb2="d"))


def test_double_link_two_peg_stance_is_a_transition_only():
    """Seed 001 section 2.1: the double-link robot with both hands on pegs is a point (0-D stance):
    FIND-TRANSITION finds it by projection, FIND-PATH refuses it."""
    robot = RobotModel.load("double-link")
    terrain = Terrain.from_dict({"name": "pegs", "dim": 2, "holds": [
        {"id": "p0", "position": [0.0, 1.0], "normal": [0, 1], "type": "grasp", "max_force": 100},
        {"id": "p1", "position": [0.6, 1.3], "normal": [0, 1], "type": "grasp", "max_force": 100}]})
    s = Stance(a="p0", b="p1")
    q = find_transition(robot, terrain, s, None, seed=0, attempts=200)
    assert q is not None
    verify_path(robot, terrain, s, [q, q])
    with pytest.raises(QueryError, match="zero-dimensional"):
        find_path(robot, terrain, s, q, q)


@pytest.mark.slow
def test_lemur_grab_release_on_demo_wall():
    """Seeds 000/002: LEMUR releases one hold and grabs a neighbouring one on the demo wall."""
    from climb_ompl.benchmarks.onestep import make_queries

    robot = RobotModel.load("lemur")
    terrain = Terrain.load("demo-wall")
    (s, qs, qg), = make_queries(robot, terrain, 1, seed=0)
    res = find_path(robot, terrain, s, qs, qg, seed=0, time_limit=60)
    assert res.solved, res.stats
    verify_path(robot, terrain, s, res.path)
