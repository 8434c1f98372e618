"""The kernels below the operators of Bretl (2006): joint kinds, closing order, base translations and the CoM
Jacobian on :class:`RobotModel`, the draw-and-close kernel (:mod:`climb_ompl.manifold.closure`), the one start
configuration and the components built from :class:`ClimbSettings` (:class:`PathSettings`, :class:`LocalPath`).

Oracles: the motion subspace of each joint (its Jacobian column in its own frame) for the joint kinds, forward
kinematics and finite differences for the base translations and the CoM Jacobian, the full list of inverse-kinematics
solutions for the nearest one.
"""

from __future__ import annotations

import dataclasses
import math
from pathlib import Path

import numpy as np
import pinocchio as pin
import pytest

from climb_ompl.manifold.closure import DrawClose, com_shift
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.manifold.stance import Stance, hand_targets
from climb_ompl.model.joints import ANGLE, SCREW, TRANSLATION, coordinate_kinds, elementary
from climb_ompl.model.robot import RobotModel, bundled_robots
from climb_ompl.model.terrain import Terrain
from climb_ompl.settings import ClimbSettings


def motion_kinds(model: pin.Model) -> list[str]:
    """The oracle: each coordinate's kind from its joint's Jacobian column in the joint's own frame at the neutral
    configuration (angular part only: an angle; linear only: a translation; both: a screw)."""
    data = model.createData()
    q0 = pin.neutral(model)
    out = [""] * model.nv
    for jid in range(1, model.njoints):
        jm = model.joints[jid]
        J = np.asarray(pin.computeJointJacobian(model, data, q0, jid))
        for v in range(jm.idx_v, jm.idx_v + jm.nv):
            lin, ang = np.linalg.norm(J[:3, v]) > 1e-12, np.linalg.norm(J[3:, v]) > 1e-12
            out[v] = SCREW if lin and ang else ANGLE if ang else TRANSLATION
    return out


def _erd(path: str) -> Path:
    from climb_ompl.model.files import package_share

    try:
        share = package_share("example-robot-data", "test")
    except Exception:  # noqa: BLE001 - the package is optional
        pytest.skip("example-robot-data not installed")
    f = share / "robots" / path
    if not f.exists():
        pytest.skip(f"{path} not in this example-robot-data")
    return f


ERD = ["go1_description/urdf/go1.urdf", "anymal_c_simple_description/urdf/anymal.urdf", "a1_description/urdf/a1.urdf",
       "solo_description/robots/solo12.urdf", "panda_description/urdf/panda.urdf",
       "baxter_description/urdf/baxter.urdf"]


# ---- joint kinds -----------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", bundled_robots())
def test_joint_kinds_of_the_bundled_robots_match_the_motion_subspace(name):
    robot = RobotModel.load(name)
    assert list(robot.coordinate_kinds) == motion_kinds(robot.model)
    assert np.array_equal(robot.angle_joints, [k != TRANSLATION for k in motion_kinds(robot.model)])
    with pytest.raises(ValueError):
        robot.angle_joints[0] = not robot.angle_joints[0]  # read-only: shared by every caller


@pytest.mark.parametrize("urdf", ERD)
@pytest.mark.parametrize("root", ["fixed", "planar", "spatial"])
def test_joint_kinds_of_example_robot_data_robots(urdf, root):
    """Each URDF fixed, or on the composite base a spec builds (``planar``: x, z, an angle; ``spatial``: x, y, z and
    Z-Y-X angles about a reference orientation): the composite's coordinates each take its own joint's kind."""
    from climb_ompl.model.spec import composite_base

    f = _erd(urdf)
    if root == "fixed":
        model = pin.buildModelFromUrdf(str(f))
    else:
        n = 3 if root == "planar" else 6
        base = {"type": root, "lower": [-1.0] * n, "upper": [1.0] * n}
        if root == "spatial":
            base["reference_rpy"] = [-math.pi / 2, -math.pi / 2, 0.0]
        model = pin.buildModelFromUrdf(str(f), composite_base(base, "test"))
    assert list(coordinate_kinds(model)) == motion_kinds(model)
    if root == "spatial":
        assert coordinate_kinds(model)[:6] == (TRANSLATION,) * 3 + (ANGLE,) * 3


def test_a_composite_joint_after_the_first_coordinate_is_read_at_its_own_place():
    """A composite (prismatic x, revolute y) after a revolute joint: its coordinates are q[1] and q[2], not q[0] and
    q[1] (the index of a joint inside a composite counts from the composite's first coordinate)."""
    model = pin.Model()
    j0 = model.addJoint(0, pin.JointModelRX(), pin.SE3.Identity(), "r0")
    comp = pin.JointModelComposite()
    comp.addJoint(pin.JointModelPX())
    comp.addJoint(pin.JointModelRY())
    j1 = model.addJoint(j0, comp, pin.SE3.Identity(), "c")
    model.addJoint(j1, pin.JointModelPZ(), pin.SE3.Identity(), "p")
    for j in range(1, model.njoints):
        model.appendBodyToJoint(j, pin.Inertia.Random(), pin.SE3.Identity())
    assert coordinate_kinds(model) == (ANGLE, TRANSLATION, ANGLE, TRANSLATION)
    assert list(coordinate_kinds(model)) == motion_kinds(model)


def test_screw_universal_and_zyx_joints():
    """Types beyond the bundled robots': a helical joint turns and translates (a screw), a universal joint and Z-Y-X
    angles are angles, a translation joint three translations; the oracle agrees."""
    model = pin.Model()
    parent = 0
    universal = pin.JointModelUniversal(np.array([1.0, 0, 0]), np.array([0, 1.0, 0]))
    for k, jm in enumerate((pin.JointModelHZ(0.1), universal, pin.JointModelSphericalZYX(),
                            pin.JointModelTranslation())):
        parent = model.addJoint(parent, jm, pin.SE3.Identity(), f"j{k}")
        model.appendBodyToJoint(parent, pin.Inertia.Random(), pin.SE3.Identity())
    assert coordinate_kinds(model) == (SCREW, ANGLE, ANGLE, ANGLE, ANGLE, ANGLE, TRANSLATION, TRANSLATION, TRANSLATION)
    assert list(coordinate_kinds(model)) == motion_kinds(model)


def test_a_free_flyer_is_refused():
    model = pin.Model()
    model.addJoint(0, pin.JointModelFreeFlyer(), pin.SE3.Identity(), "ff")
    with pytest.raises(ValueError, match="7 coordinates for 6 velocities"):
        coordinate_kinds(model)


def test_elementary_axes():
    assert elementary(pin.JointModelPY())[0] == "P" and np.array_equal(elementary(pin.JointModelPY())[1], [0, 1, 0])
    kind, axis = elementary(pin.JointModelRevoluteUnaligned(0.0, 0.6, 0.8))
    assert kind == "R" and np.allclose(axis, [0.0, 0.6, 0.8])
    assert elementary(pin.JointModelHX(0.1)) is None and elementary(pin.JointModelComposite()) is None


@pytest.mark.parametrize("name, revolute", [("lemur", True), ("double-link", False), ("go1", True)])
def test_all_revolute(name, revolute):
    """A limb with a prismatic joint (double-link's hand ``a`` moves the base's x and z) is not bounded by its
    reach; the others' joints all turn."""
    robot = RobotModel.load(name)
    assert robot.all_revolute(robot.limbs[0].name) is revolute
    assert all(robot.all_revolute(lb.name) for lb in robot.limbs[1:])


# ---- closing order, base translations ----------------------------------------------------------------------
def test_closing_order_puts_the_base_moving_limbs_first():
    dl = RobotModel.load("double-link")
    assert dl.moves_base("a") and not dl.moves_base("b")
    assert dl.closing_order(["b", "a"]) == ["a", "b"]
    assert dl.closing_order(["b", "a"], last=["a"]) == ["a", "b"]  # (base-moving first even when on its hold)
    lemur = RobotModel.load("lemur")
    names = [lb.name for lb in lemur.limbs]
    assert lemur.closing_order(sorted(names)) == names  # the robot's limb order
    assert lemur.closing_order(names, last=[names[0]]) == names[1:] + names[:1]


@pytest.mark.parametrize("name, want", [("anymal-c", [0, 1, 2]), ("go1", [0, 1, 2]), ("lemur", [0, 1]),
                                        ("mrwallspect3", [0, 1]), ("double-link", [0, 1]),
                                        ("planar-3limb", [0, 1])])
def test_base_translations_move_every_hand_alike(name, want):
    """The oracle: each translation moved by 1 mm moves every hand by 1 mm along its vector (forward kinematics);
    the base's angles move some hand otherwise."""
    robot = RobotModel.load(name)
    idx, dirs = robot.base_translations()
    assert idx == want and dirs.shape == (3, len(want))
    assert np.allclose(np.linalg.norm(dirs, axis=0), 1.0)
    q = np.asarray(robot.nominal_q, dtype=float)
    h0 = robot.hand_positions(q)
    for j in robot.base_indices:
        dq = np.zeros(robot.nq)
        dq[j] = 1e-3
        moved = (robot.hand_positions(q + dq) - h0) / 1e-3
        if j in idx:
            assert np.allclose(moved, dirs[:, idx.index(j)], atol=1e-9)
        else:
            assert not np.allclose(moved, moved[0], atol=1e-6)
    assert robot.base_axes() == {j: int(np.argmax(np.abs(dirs[:, k]))) for k, j in enumerate(idx)}


# ---- the CoM Jacobian ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("name", ["lemur", "go1", "planar-3limb", "anymal-c"])
def test_com_jacobian_matches_central_differences(name):
    """Pinocchio's ``jacobianCenterOfMass`` against central differences of the CoM on the plain configuration
    vector (every column: base coordinates, a composite base's included, and limb joints)."""
    robot = RobotModel.load(name)
    rng = np.random.default_rng(3)
    for _ in range(5):
        q = robot.random_configuration(rng)
        J = robot.com_jacobian(q)
        assert J.shape == (3, robot.nq)
        h = 1e-6
        fd = np.stack([(robot.com(q + h * e) - robot.com(q - h * e)) / (2 * h) for e in np.eye(robot.nq)], axis=1)
        assert np.allclose(J, fd, atol=1e-7, rtol=1e-6)


def test_com_shift_is_the_least_squares_step_to_the_region_centre():
    """The oracle: least squares through central differences of the CoM in the region's plane with respect to the
    base coordinates (LEMUR, whose base cannot move the CoM across the wall: a rank-deficient system; Go1, whose
    can)."""
    from climb_ompl.climb.start import find_start

    for name, wall in (("lemur", "demo-wall"), ("go1", "stepping-stone-ramp-3m")):
        robot, terrain = RobotModel.load(name), Terrain.load(wall)
        start = find_start(robot, terrain, seed=0)
        sigma = Stance(start.stance)
        base = np.asarray(robot.base_indices)
        q = start.q
        for lb in sigma.limbs[:2]:
            region = Feasibility.of(robot, terrain).region(sigma.without(lb))
            h = 1e-6
            J = np.stack([(robot.com(q + h * e) - robot.com(q - h * e)) / (2 * h) for e in np.eye(robot.nq)[base]], 1)
            err = np.asarray(region.vertices, dtype=float).mean(axis=0) - region.coords(robot.com(q))[0]
            want = np.linalg.lstsq(region.basis @ J, err, rcond=1e-9)[0]
            assert np.allclose(com_shift(robot, region, q, base), want, atol=1e-6)


# ---- the draw-and-close kernel ------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def lemur_stance():
    from climb_ompl.climb.start import find_start

    robot, terrain = RobotModel.load("lemur"), Terrain.load("demo-wall")
    start = find_start(robot, terrain, seed=0)
    return robot, terrain, Stance(start.stance), start.q


def test_close_puts_every_hand_on_its_hold_by_the_nearest_solutions(lemur_stance):
    robot, terrain, sigma, q = lemur_stance
    kernel = DrawClose.of(robot, terrain, sigma)
    assert kernel.order == robot.closing_order(sigma.limbs)
    rng = np.random.default_rng(0)
    closed = 0
    for _ in range(20):
        x = kernel.place(q, kernel.step(rng, np.array([0.03, 0.03, 0.05])))
        qc = kernel.close(x, q)
        if qc is None:
            assert kernel.failed in sigma.limbs
            continue
        closed += 1
        targets = hand_targets(robot, terrain, sigma)
        for lb in sigma.limbs:  # forward kinematics puts each hand on its target
            assert np.linalg.norm(robot.hand_position(qc, lb) - targets[lb]) < 1e-8
            idx = list(robot.limb(lb).joint_indices)  # and each limb at the solution nearest ``q``
            sols = robot.limb_ik(lb, x, targets[lb])
            best = min(sols, key=lambda s: float(np.sum((s[idx] - q[idx]) ** 2)))
            assert np.array_equal(qc[idx], best[idx])
        assert np.array_equal(qc[kernel.base], x[kernel.base])  # the base where it was drawn
    assert closed >= 10


def test_close_names_the_limb_out_of_reach(lemur_stance):
    robot, terrain, sigma, q = lemur_stance
    far = {lb: np.asarray(t) + np.array([0.0, 0.0, 5.0]) if lb == sigma.limbs[-1] else t
           for lb, t in hand_targets(robot, terrain, sigma).items()}
    kernel = DrawClose(robot, far)
    assert kernel.close(q, q) is None and kernel.failed == sigma.limbs[-1]


def test_place_clips_to_the_bounds(lemur_stance):
    robot, terrain, sigma, q = lemur_stance
    kernel = DrawClose.of(robot, terrain, sigma)
    x = kernel.place(q, np.full(len(kernel.base), 100.0))
    assert np.array_equal(x[kernel.base], robot.upper[kernel.base])
    others = np.setdiff1d(np.arange(robot.nq), kernel.base)
    assert np.array_equal(x[others], q[others])


def test_a_solution_drawn_without_reference_needs_a_generator(lemur_stance):
    robot, terrain, sigma, q = lemur_stance
    kernel = DrawClose.of(robot, terrain, sigma, bounds=(robot.lower, robot.upper))
    with pytest.raises(ValueError, match="give rng"):
        kernel.solve(sigma.limbs[0], q)
    assert kernel.solve(sigma.limbs[0], q, rng=np.random.default_rng(0)) is not None


# ---- one start configuration --------------------------------------------------------------------------------
def test_one_start_configuration_function():
    from climb_ompl.climb import multistep, start

    assert multistep.start_configuration is start.start_configuration
    assert not hasattr(start, "stance_configuration")
    from climb_ompl.climb import transition

    assert not hasattr(transition, "start_configuration")


# ---- components built from ClimbSettings --------------------------------------------------------------------
def test_path_settings_take_the_climbs_defaults():
    from climb_ompl.climb.onestep import PathSettings

    d = ClimbSettings()
    p = PathSettings()
    assert p == PathSettings.of(d)
    assert (p.planner, p.space, p.sampler, p.max_step, p.torque, p.cone_edges, p.torque_cone_edges, p.tolerance,
            p.margin, p.max_iterations, p.cpu_limit, p.lift, p.via_points) == \
        (d.planner, d.space, d.sampler, d.max_step, d.torque, d.cone_edges, d.torque_cone_edges, d.tolerance,
         d.margin, d.path_iterations, d.step_time_limit, d.lift, d.via_points)


def test_path_settings_of_reads_every_setting_it_shares():
    from climb_ompl.climb.onestep import PathSettings

    s = ClimbSettings(planner="RRTConnect", space="projected", sampler="joint-by-joint", step_time_limit=7.0,
                      path_iterations=123, torque="state", max_step=0.03, margin=0.01, cone_edges=6,
                      torque_cone_edges=5, lift=0.05, via_points=3)
    p = PathSettings.of(s, time_limit=30.0, direct=False)
    assert (p.planner, p.space, p.sampler, p.cpu_limit, p.max_iterations, p.torque, p.max_step, p.margin,
            p.cone_edges, p.torque_cone_edges, p.lift, p.via_points, p.time_limit, p.direct) == \
        ("RRTConnect", "projected", "joint-by-joint", 7.0, 123, "state", 0.03, 0.01, 6, 5, 0.05, 3, 30.0, False)
    with pytest.raises(dataclasses.FrozenInstanceError):
        p.max_step = 0.1  # type: ignore[misc]
    with pytest.raises(TypeError, match="unknown option.*max_stepp"):
        p.replace(max_stepp=0.1)


def test_local_path_of_settings():
    from climb_ompl.climb.local_path import LocalPath
    from climb_ompl.climb.onestep import PathSettings

    robot, terrain = RobotModel.load("lemur"), Terrain.load("demo-wall")
    feas = Feasibility.of(robot, terrain)
    lp = LocalPath.of(feas, ClimbSettings(max_step=0.03, lift=0.05, via_points=2), seed=4)
    assert (lp.max_step, lp.lift, lp.via_points, lp.seed) == (0.03, 0.05, 2, 4)
    d = LocalPath(feas)
    assert (d.max_step, d.lift, d.via_points) == (ClimbSettings.max_step, ClimbSettings.lift, ClimbSettings.via_points)
    p = LocalPath.of(feas, PathSettings(max_step=0.01))
    assert p.max_step == 0.01


def test_find_path_refuses_an_unknown_option(lemur_stance):
    from climb_ompl.climb.onestep import find_path

    robot, terrain, sigma, q = lemur_stance
    with pytest.raises(TypeError, match="unknown option"):
        find_path(robot, terrain, sigma, q, q, max_stepp=0.1)
