"""Robot models: loading, kinematics vs independent oracles, IK, collision, spec validation."""

from __future__ import annotations

import math
import subprocess
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest
import yaml
from hypothesis import given, settings
from hypothesis import strategies as st

from climb_ompl.errors import ClimbError, RobotModelError
from climb_ompl.model.robot import RobotModel, bundled_robots
from climb_ompl.model.terrain import Terrain
from climb_ompl.resources import robots_dir, urdf_dir

OURS = ("planar-3limb", "lemur", "double-link", "lemur-hooks")
BAD = Path(__file__).parent / "data" / "bad_robots"


@pytest.fixture(scope="module", params=OURS)
def robot(request) -> RobotModel:
    return RobotModel.load(request.param)


_cache: dict[str, RobotModel] = {}


def load(name: str) -> RobotModel:
    if name not in _cache:
        _cache[name] = RobotModel.load(name)
    return _cache[name]


# ---------------------------------------------------------------------------------------- oracle: URDF FK by hand
def _rpy(r: float, p: float, y: float) -> np.ndarray:
    cx, sx, cy, sy, cz, sz = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    Rx = np.array([[1, 0, 0], [0, cx, -sx], [0, sx, cx]])
    Ry = np.array([[cy, 0, sy], [0, 1, 0], [-sy, 0, cy]])
    Rz = np.array([[cz, -sz, 0], [sz, cz, 0], [0, 0, 1]])
    return Rz @ Ry @ Rx


def _axis_angle(a: np.ndarray, t: float) -> np.ndarray:
    a = a / np.linalg.norm(a)
    K = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    return np.eye(3) + math.sin(t) * K + (1 - math.cos(t)) * K @ K


def _T(R: np.ndarray, p) -> np.ndarray:
    T = np.eye(4)
    T[:3, :3], T[:3, 3] = R, p
    return T


def _origin(el) -> np.ndarray:
    o = el.find("origin") if el is not None else None
    xyz = [float(x) for x in (o.get("xyz", "0 0 0") if o is not None else "0 0 0").split()]
    rpy = [float(x) for x in (o.get("rpy", "0 0 0") if o is not None else "0 0 0").split()]
    return _T(_rpy(*rpy), xyz)


def urdf_oracle(path: Path, values: dict[str, float], root_T: np.ndarray | None = None):
    """Link world transforms, total mass and CoM from the URDF XML alone (no Pinocchio)."""
    root = ET.parse(path).getroot()
    joints = {j.find("child").get("link"): j for j in root.findall("joint")}  # not transmissions
    links = {ln.get("name"): ln for ln in root.iter("link")}
    T: dict[str, np.ndarray] = {}

    def world(name: str) -> np.ndarray:
        if name in T:
            return T[name]
        j = joints.get(name)
        if j is None:
            T[name] = root_T if root_T is not None else np.eye(4)
            return T[name]
        M = world(j.find("parent").get("link")) @ _origin(j)
        kind = j.get("type")
        if kind != "fixed":
            ax = np.array([float(x) for x in (j.find("axis").get("xyz") if j.find("axis") is not None
                                               else "1 0 0").split()])
            qv = values[j.get("name")]
            M = M @ (_T(_axis_angle(ax, qv), [0, 0, 0]) if kind in ("revolute", "continuous")
                     else _T(np.eye(3), ax / np.linalg.norm(ax) * qv))
        T[name] = M
        return M

    mass, moment = 0.0, np.zeros(3)
    for name, ln in links.items():
        inert = ln.find("inertial")
        if inert is None or inert.find("mass") is None:
            continue
        m = float(inert.find("mass").get("value"))
        c = world(name) @ _origin(inert)
        mass += m
        moment += m * c[:3, 3]
    return {n: world(n) for n in links}, mass, moment / mass


def values_of(robot: RobotModel, q: np.ndarray) -> dict[str, float]:
    return {n: float(v) for n, v in zip(robot.joint_names, q, strict=True)}


# ---------------------------------------------------------------------------------------- loading
def test_bundled_robots_listed():
    names = bundled_robots()
    for n in OURS:
        assert n in names
        assert (robots_dir() / f"{n}.yaml").is_file()
        assert (urdf_dir() / f"{n}.urdf").is_file()


@pytest.mark.parametrize("name,nq,n_limbs,mass", [("planar-3limb", 9, 3, 6.0), ("double-link", 4, 2, 2.0),
                                                  ("lemur", 15, 4, 7.0), ("lemur-hooks", 22, 4, 7.0)])
def test_shapes_and_paper_facts(name, nq, n_limbs, mass):
    r = load(name)
    assert (r.nq, len(r.limbs)) == (nq, n_limbs)
    assert r.mass == pytest.approx(mass, abs=1e-9)  # LEMUR: 7 kg (Bretl (2006), sec. 5.1)
    assert r.model.nq == r.model.nv == nq
    assert np.all(np.isfinite(r.lower)) and np.all(np.isfinite(r.upper))
    assert r.within_limits(r.nominal_q)
    assert not r.actuated[list(r.base_indices)].any()
    assert np.all(np.isinf(r.torque_limits[list(r.base_indices)]))
    for lb in r.limbs:
        if lb.elbow_index is not None:
            assert lb.elbow_index in lb.joint_indices
            assert r.lower[lb.elbow_index] <= lb.elbow_straight <= r.upper[lb.elbow_index]
    assert r.planar == (name in ("planar-3limb", "double-link"))


def test_lemur_hardware_numbers():
    """Bretl (2006), sec. 5.1: 5 N m, 45 deg/s, ~1 m wingspan; Bretl et al. (2004): chassis parallel to the wall."""
    r = load("lemur")
    joints = [i for lb in r.limbs for i in lb.joint_indices]
    assert np.allclose(r.torque_limits[joints], 5.0)
    assert np.allclose(r.velocity_limits[joints], math.radians(45), atol=1e-6)
    q = r.nominal_q
    hands = r.hand_positions(q)
    assert np.allclose(hands[:, 1], 0.0, atol=1e-9)  # nominal: all pegs on the wall
    # wingspan: hands with straight limbs (shoulders 0, elbows 0, wrist at contact)
    qs = q.copy()
    for lb in r.limbs:
        qs[lb.joint_indices[0]] = qs[lb.joint_indices[1]] = 0.0
    h = r.hand_positions(qs)
    span = max(np.linalg.norm(h[i] - h[j]) for i in range(4) for j in range(4))
    assert 0.9 <= span <= 1.1
    # the chassis stays parallel to the wall at a fixed standoff: the base frame's y never changes
    rng = np.random.default_rng(0)
    ys = {round(float(r.com(np.r_[rng.uniform(r.lower[:3], r.upper[:3]), q[3:]])[1]), 12) for _ in range(5)}
    assert len(ys) == 1 and 0.0 < ys.pop() < 0.1  # CoM close to the wall


def test_wheel_layout_loads(tmp_path):
    """A wheel carries robots/ and urdf/ as climb_ompl/_data/: every bundled robot loads from that layout."""
    import shutil

    import climb_ompl

    pkg = Path(climb_ompl.__file__).parent
    dst = tmp_path / "site" / "climb_ompl"
    shutil.copytree(pkg, dst, ignore=shutil.ignore_patterns("__pycache__", "_data"))
    shutil.copytree(robots_dir(), dst / "_data" / "robots")
    shutil.copytree(urdf_dir(), dst / "_data" / "urdf")
    code = ("import climb_ompl, climb_ompl.resources as r; "
            "from climb_ompl.model.robot import RobotModel, bundled_robots;"
            f"assert str(r.robots_dir()).startswith({str(tmp_path)!r}), r.robots_dir();"
            f"[RobotModel.load(n) for n in {list(OURS)!r}]; print(len(bundled_robots()))")
    out = subprocess.run([sys.executable, "-c", code], cwd=tmp_path, env={"PYTHONPATH": str(tmp_path / "site"),
                         "PATH": "/usr/bin:/bin"}, capture_output=True, text=True, timeout=120)
    assert out.returncode == 0, out.stderr
    assert int(out.stdout.strip()) >= len(OURS)


# ---------------------------------------------------------------------------------------- kinematics vs oracles
def test_fk_and_com_against_urdf_oracle(robot):
    rng = np.random.default_rng(1)
    for _ in range(5):
        q = robot.random_configuration(rng)
        frames, mass, com = urdf_oracle(robot.urdf_path, values_of(robot, q))
        assert mass == pytest.approx(robot.mass, rel=1e-12)
        assert np.allclose(robot.com(q), com, atol=1e-12)
        hands = robot.hand_positions(q)
        for lb, h in zip(robot.limbs, hands, strict=True):
            assert np.allclose(h, frames[lb.hand_frame][:3, 3], atol=1e-12)
            assert np.allclose(robot.hand_position(q, lb.name), h, atol=1e-14)
        fk = robot.limb_fk(q, robot.limbs[-1])
        assert np.allclose(fk[-1], hands[-1])


def test_planar3_com_matches_seed000_eq3():
    """Bretl, Latombe & Rock (2003), Eq. 3: a limb's CoM abscissa is x_p + L/4 (3 cos t1 + cos(t1 + t2));
    the pelvis is massless."""
    r = load("planar-3limb")
    L = 0.25
    rng = np.random.default_rng(2)
    for _ in range(10):
        q = r.random_configuration(rng)
        xp, zp, tp = q[0], q[1], q[2]
        xs, zs = [], []
        for lb in r.limbs:
            t1, t2 = tp + q[lb.joint_indices[0]], q[lb.joint_indices[1]]
            xs.append(xp + L / 4 * (3 * math.cos(t1) + math.cos(t1 + t2)))
            zs.append(zp + L / 4 * (3 * math.sin(t1) + math.sin(t1 + t2)))
        assert np.allclose(r.com(q), [np.mean(xs), 0.0, np.mean(zs)], atol=1e-12)


def test_com_batch(robot):
    rng = np.random.default_rng(3)
    Q = np.array([robot.random_configuration(rng) for _ in range(20)])
    assert np.allclose(robot.com_batch(Q), [robot.com(q) for q in Q], atol=1e-14)


def test_hand_jacobians_vs_finite_differences(robot):
    rng = np.random.default_rng(4)
    h = 1e-6
    for _ in range(4):
        q = robot.random_configuration(rng)
        J = robot.hand_jacobians(q)
        assert J.shape == (len(robot.limbs), 3, robot.nq)
        fd = np.zeros_like(J)
        for i in range(robot.nq):
            dq = np.zeros(robot.nq)
            dq[i] = h
            fd[:, :, i] = (robot.hand_positions(q + dq) - robot.hand_positions(q - dq)) / (2 * h)
        assert np.allclose(J, fd, atol=1e-7)
        assert np.allclose(robot.hand_jacobian(q, robot.limbs[0].name), J[0], atol=1e-14)


def test_gravity_torques_are_gradient_of_potential(robot):
    rng = np.random.default_rng(5)
    g = np.array([0.0, -2.0, -9.5])  # a tilted wall
    q = robot.random_configuration(rng)
    V = lambda x: -robot.mass * g @ robot.com(x)
    h = 1e-6
    fd = np.array([(V(q + h * e) - V(q - h * e)) / (2 * h) for e in np.eye(robot.nq)])
    assert np.allclose(robot.gravity_torques(q, g), fd, atol=1e-6)


# ---------------------------------------------------------------------------------------- inverse kinematics
def _with_quadrupeds() -> tuple[str, ...]:
    """OURS plus the example-robot-data quadrupeds (closed-form abduction-pitch-pitch legs) when installed."""
    from importlib import metadata

    try:
        metadata.distribution("example-robot-data")
    except metadata.PackageNotFoundError:  # pragma: no cover - a dev install has it
        return OURS
    return (*OURS, "go1", "anymal-c")


@pytest.mark.parametrize("name", _with_quadrupeds())
@settings(derandomize=True, deadline=None, max_examples=25)
@given(seed=st.integers(0, 2**32 - 1))
def test_ik_round_trip(name, seed):
    """Targets made by FK from random in-bounds limb angles are reached to 1e-9 m by every solution."""
    r = load(name)
    rng = np.random.default_rng(seed)
    q = r.random_configuration(rng)
    q_goal = r.random_configuration(rng)
    for lb in r.limbs:
        idx = list(lb.joint_indices)
        qt = q.copy()
        qt[idx] = q_goal[idx]
        target = r.hand_position(qt, lb)
        sols = r.limb_ik(lb, q, target)
        assert sols, f"{name}/{lb.name}: reachable target reported unreachable"
        for s in sols:
            assert np.linalg.norm(r.hand_position(s, lb) - target) < 1e-9
            assert r.within_limits(s)
            others = np.setdiff1d(np.arange(r.nq), idx)
            assert np.array_equal(s[others], q[others])
        if lb.ik == "analytic":  # closed form: every solution, so also the one the target was made from
            assert any(np.allclose(s[idx], qt[idx], atol=1e-7) for s in sols)


def test_analytic_ik_used_and_both_elbow_bends():
    r = load("planar-3limb")
    assert all(lb.ik == "analytic" for lb in r.limbs)
    assert all(lb.ik == "analytic" for lb in load("lemur").limbs)
    assert all(lb.ik == "numeric" for lb in load("lemur-hooks").limbs)
    q = r.nominal_q
    lb = r.limbs[0]
    shoulder = r.limb_fk(q, lb)[0]
    sols = r.limb_ik(lb, q, shoulder + np.array([0.3, 0.0, 0.2]))
    elbows = sorted(np.sign(s[lb.elbow_index]) for s in sols)
    assert elbows == [-1.0, 1.0]


def test_ik_reports_unreachable():
    r = load("planar-3limb")
    q = r.nominal_q
    for lb in r.limbs:
        shoulder = r.limb_fk(q, lb)[0]
        assert r.limb_ik(lb, q, shoulder + [0.51, 0.0, 0.0]) == []  # beyond 2 L
        assert r.limb_ik(lb, q, shoulder + [0.2, 0.05, 0.0]) == []  # out of the x-z plane
    lem = load("lemur")
    q = lem.nominal_q
    for lb in lem.limbs:
        shoulder = lem.limb_fk(q, lb)[0]
        radial = shoulder - np.array([0.0, shoulder[1], q[1]])
        radial /= np.linalg.norm(radial)
        assert lem.limb_ik(lb, q, shoulder + 0.5 * radial - [0, shoulder[1], 0]) == []  # too far
        assert lem.limb_ik(lb, q, shoulder + 0.25 * radial + [0, 0.05, 0]) == []  # peg cannot point away
        assert lem.limb_ik(lb, q, shoulder + 0.25 * radial - [0, 0.2, 0]) == []  # behind the wall
    hooks = load("lemur-hooks")
    lb = hooks.limbs[0]
    assert hooks.limb_ik(lb, hooks.nominal_q, hooks.limb_fk(hooks.nominal_q, lb)[0] + [0.6, 0, 0]) == []


def test_double_link_limbs():
    r = load("double-link")
    q = r.nominal_q
    a, b = r.limbs
    assert a.elbow_index is None and b.elbow_index is not None
    sols = r.limb_ik("a", q, [0.4, 0.0, 0.9])  # moving hand a translates the robot
    assert sols and np.allclose(sols[0][:2], [0.4, 0.9])
    sols = r.limb_ik("b", q, [0.6, 0.0, 1.5])
    assert len(sols) == 8  # two elbow bends x two representatives of each angle within +-2 pi
    assert all(np.allclose(r.hand_position(s, "b"), [0.6, 0.0, 1.5], atol=1e-9) for s in sols)


# ---------------------------------------------------------------------------------------- collision
def _wall() -> Terrain:
    return Terrain.from_dict({"name": "w", "dim": 3, "holds": [{"id": "h", "position": [0, 0, 1], "normal": [0, 1, 0]}],
                              "surfaces": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}]})


def test_lemur_collision_with_wall_and_itself():
    r = load("lemur")
    wall = _wall()
    q = r.nominal_q
    names = [lb.name for lb in r.limbs]
    assert not r.self_collision(q)
    assert not r.in_collision(q, wall, contact_limbs=names)  # nominal stance: free
    assert r.in_collision(q, wall)  # pegs touch the wall: not free unless they are at holds
    assert r.in_collision(q, wall, contact_limbs=names[:3])  # the 4th peg is exempt only when in contact
    through = q.copy()
    through[r.limbs[0].joint_indices[2]] = math.radians(90)  # peg driven through the wall
    assert r.in_collision(through, wall, contact_limbs=names)
    lifted = q.copy()
    lifted[r.limbs[0].joint_indices[2]] = 0.2  # free limb lifted a few cm off the wall
    assert not r.in_collision(lifted, wall, contact_limbs=names[1:])
    assert r.hand_position(lifted, names[0])[1] > 0.03
    folded = q.copy()
    folded[r.joint_names.index("ne_shoulder")] = -1.5  # ne and nw upper links swing into each other
    folded[r.joint_names.index("nw_shoulder")] = 1.5
    assert r.self_collision(folded) and r.in_collision(folded, wall, contact_limbs=names)
    # a box obstacle on the wall, in front of a link
    pts = r.limb_fk(q, "ne")
    mid = (pts[1] + pts[2]) / 2
    boxed = Terrain.from_dict({**wall.to_dict(), "surfaces": [{"type": "box", "center": mid.tolist(),
                                                                "size": [0.05, 0.05, 0.05]}]})
    assert r.in_collision(q, boxed, contact_limbs=names)


def test_self_collision_configurable():
    r = load("planar-3limb")
    assert not r.self_collision_enabled and r.collision_pairs() == []
    q = r.nominal_q.copy()
    q[r.limbs[0].joint_indices[0]] = q[r.limbs[1].joint_indices[0]] = 0.3  # limbs on top of each other
    assert not r.self_collision(q)
    assert load("lemur").self_collision_enabled and load("lemur").collision_pairs()


def test_planar_circle_obstacles():
    r = load("planar-3limb")
    q = r.nominal_q
    pts = r.limb_fk(q, "limb3")
    on_link = ((pts[0] + pts[1]) / 2)[[0, 2]].tolist()
    terr = lambda c: Terrain.from_dict({"name": "c", "dim": 2, "holds": [{"id": "h", "position": [0, 0],
                                        "normal": [0, 1]}], "surfaces": [{"type": "circle", "center": c,
                                                                          "radius": 0.05}]})
    assert r.in_collision(q, terr(on_link))
    assert not r.in_collision(q, terr([on_link[0] + 1.5, on_link[1]]))
    # a hand at a hold on the obstacle's rim is exempt near its hold only
    hand = r.hand_position(q, "limb3")[[0, 2]]
    rim = terr([hand[0], hand[1] + 0.05])
    assert r.in_collision(q, rim)
    assert not r.in_collision(q, rim, contact_limbs=["limb3"])


# ---------------------------------------------------------------------------------------- spec validation
def _expect(path: Path) -> str:
    first = path.read_text().splitlines()[0]
    assert first.startswith("# expect-field: ")
    return first.split(": ", 1)[1]


@pytest.mark.parametrize("path", sorted(BAD.glob("*.yaml")), ids=lambda p: p.stem)
def test_bad_specs(path):
    with pytest.raises(RobotModelError) as ei:
        RobotModel.load(path)
    err = ei.value
    assert err.field == _expect(path)
    assert str(err.path).endswith((path.name, ".urdf"))
    assert isinstance(err, ClimbError) and err.reason


def test_a_broken_urdf_is_explained_in_the_error_not_on_the_terminal(capfd):
    """urdfdom prints why it refuses a URDF to the process's standard error (file descriptor 2) before Pinocchio
    raises "does not contain a valid URDF model": that reason is now the error's, and nothing else is printed."""
    with pytest.raises(RobotModelError) as ei:
        RobotModel.load(BAD / "broken_tree.yaml")
    assert ei.value.field == "urdf" and "parent link [nosuchlink] of joint [shoulder] not found" in ei.value.reason
    assert capfd.readouterr().err == ""


def test_bad_corpus_size():
    assert len(list(BAD.glob("*.yaml"))) >= 6


def test_unknown_robot_lists_bundled():
    with pytest.raises(RobotModelError, match="lemur"):
        RobotModel.load("no-such-robot")


def test_cli_robots_and_check(capsys):
    from climb_ompl.cli import main

    assert main(["robots"]) == 0
    out = capsys.readouterr().out
    assert "lemur" in out and "nq 15" in out
    assert main(["robot", "check", "planar-3limb"]) == 0
    assert "climb defaults" not in capsys.readouterr().out
    assert main(["robot", "check", "anymal-c"]) == 0  # the spec's own climb settings are shown
    assert "climb defaults path_retry_growth=2" in capsys.readouterr().out
    assert main(["robot", "check", str(BAD / "shared_joint.yaml")]) == 2
    assert "limbs[1].joints[0]" in capsys.readouterr().err


def test_robot_check_shows_reaches_and_a_self_colliding_nominal_posture(capsys, tmp_path):
    """``robot check`` prints each limb's reach (Go1: 0.506 m, first joint to foot) and notes a nominal posture
    whose legs collide: Go1's front hips turned 0.6 rad towards each other put the two calves into each other
    (exit 0 all the same: the planner never uses the nominal posture itself)."""
    import yaml

    from climb_ompl.cli import main
    from climb_ompl.resources import robots_dir

    assert main(["robot", "check", "go1"]) == 0
    cap = capsys.readouterr()
    assert "reach (first joint to hand, m): fl 0.506" in cap.out and "self-collides" not in cap.err
    # and the widest gap two limbs span: the largest pair reach of two different limbs
    from climb_ompl.model.reach import pair_reach

    span = max(v for (a, b), v in pair_reach(RobotModel.load("go1")).items() if a != b)
    assert f"two limbs span at most {span:.3f} m" in cap.out
    spec = yaml.safe_load((robots_dir() / "go1.yaml").read_text())
    spec["nominal"].update(FL_hip_joint=-0.6, FR_hip_joint=0.6)
    (tmp_path / "splayed.yaml").write_text(yaml.safe_dump(spec))
    assert main(["robot", "check", str(tmp_path / "splayed.yaml")]) == 0
    err = capsys.readouterr().err
    assert "note: the nominal posture self-collides: FL_calf with FR_calf" in err
    # links closer than the clearance every transition keeps (1 cm) without touching: the hips turned 0.36 rad
    # (touching from 0.37 rad, farther than 1 cm apart below 0.35 rad)
    spec["nominal"].update(FL_hip_joint=-0.36, FR_hip_joint=0.36)
    (tmp_path / "close.yaml").write_text(yaml.safe_dump(spec))
    assert main(["robot", "check", str(tmp_path / "close.yaml")]) == 0
    err = capsys.readouterr().err
    assert "self-collides" not in err and "FL_calf with FR_calf are closer than the clearance of 0.01 m" in err
    # limits that look like a URDF's placeholders (Solo-12's in example-robot-data: 1000 rad/s) are named
    spec["nominal"].update(FL_hip_joint=0.0, FR_hip_joint=0.0)
    spec["velocity_limits"] = {"FL_hip_joint": 1000.0}
    (tmp_path / "fast.yaml").write_text(yaml.safe_dump(spec))
    assert main(["robot", "check", str(tmp_path / "fast.yaml")]) == 0
    err = capsys.readouterr().err
    assert "joint speed limits of at least 100 rad/s or m/s (FL_hip_joint 1000)" in err and "velocity_limits" in err
    assert err.count("note:") == 1


def test_reference_rpy_in_degrees_is_refused(tmp_path):
    """Go1's ``reference_rpy`` written in degrees ([-90, -90, 0]) loaded and planned with a base turned some
    other way: refused, naming the field and the radians; the bundled value (in radians) loads."""
    import yaml

    from climb_ompl.errors import RobotModelError
    from climb_ompl.resources import robots_dir

    spec = yaml.safe_load((robots_dir() / "go1.yaml").read_text())
    assert all(abs(x) <= 2 * math.pi for x in spec["base"]["reference_rpy"])
    spec["base"]["reference_rpy"] = [-90, -90, 0]
    (tmp_path / "deg.yaml").write_text(yaml.safe_dump(spec))
    with pytest.raises(RobotModelError, match=r"deg.yaml: base.reference_rpy: angles are in radians, got "
                                              r"\[-90, -90, 0\] \(more than a whole turn: degrees\?"):
        RobotModel.load(tmp_path / "deg.yaml")


def test_base_angle_bounds_in_degrees_are_refused(tmp_path):
    """Go1's base rotation bounds written in degrees ([-180, -45, -45] to [180, 45, 45]) were accepted: refused,
    naming the first bound and its value in radians; translations of more than 2 pi metres stay allowed."""
    import yaml

    from climb_ompl.errors import RobotModelError
    from climb_ompl.resources import robots_dir

    spec = yaml.safe_load((robots_dir() / "go1.yaml").read_text())
    spec["base"]["lower"][3:] = [-180, -45, -45]
    spec["base"]["upper"][3:] = [180, 45, 45]
    (tmp_path / "deg.yaml").write_text(yaml.safe_dump(spec))
    with pytest.raises(RobotModelError, match=r"deg.yaml: base.lower\[3\]: angles are in radians, got -180 .*"
                                              r"-180 deg is -3.142 rad"):
        RobotModel.load(tmp_path / "deg.yaml")
    spec = yaml.safe_load((robots_dir() / "go1.yaml").read_text())
    spec["base"]["upper"][2] = 8.0  # metres
    (tmp_path / "tall.yaml").write_text(yaml.safe_dump(spec))
    RobotModel.load(tmp_path / "tall.yaml")


def test_robot_check_notes_a_belly_turned_from_the_wall_and_a_joint_without_effort(capsys, tmp_path):
    """Two mistakes of a hexapod trial that planned on in silence: the base's ``reference_rpy`` left out (the
    belly faces down the wall: the nominal hands are no nearer the wall than the CoM, every hold out of reach),
    and a URDF effort of 0 (read as no torque limit).  The bundled robots get neither note."""
    import re

    import yaml

    from climb_ompl.cli import main
    from climb_ompl.resources import robots_dir, urdf_dir

    for name in ("go1", "anymal-c", "lemur", "lemur-hooks", "mrwallspect3", "planar-3limb", "double-link"):
        assert main(["robot", "check", name]) == 0
        notes = [ln for ln in capsys.readouterr().err.splitlines() if ln.startswith("note:")]
        assert all("no closed-form inverse kinematics" in ln for ln in notes), notes  # (lemur-hooks' arms)
    spec = yaml.safe_load((robots_dir() / "go1.yaml").read_text())
    spec["base"].pop("reference_rpy")
    (tmp_path / "belly.yaml").write_text(yaml.safe_dump(spec))
    assert main(["robot", "check", str(tmp_path / "belly.yaml")]) == 0
    err = capsys.readouterr().err
    assert "does not have the hands between the body and the wall" in err and "base.reference_rpy" in err
    # plan, when it finds no start, says it too (it listed 20 lines of failed stances and not this)
    from climb_ompl.climb.start import StartResult

    assert "base.reference_rpy" in StartResult(None, None, [], 0).advice(RobotModel.load(tmp_path / "belly.yaml"))
    assert StartResult(None, None, [], 0).advice(RobotModel.load("go1")) == "give a start stance with --start"
    lemur = yaml.safe_load((robots_dir() / "lemur.yaml").read_text())
    text = (urdf_dir() / lemur["urdf"]).read_text()
    first = re.search(r'<joint name="([^"]+)"[^>]*type="revolute"[^<]*(?:<[^/][^>]*/>\s*)*?<limit[^>]*effort="5"',
                      text)
    (tmp_path / "lemur.urdf").write_text(text[:first.end() - 3] + text[first.end() - 3:].replace('"5"', '"0"', 1))
    (tmp_path / "lemur.yaml").write_text(yaml.safe_dump(lemur))
    assert main(["robot", "check", str(tmp_path / "lemur.yaml")]) == 0
    err = capsys.readouterr().err
    assert f"joint(s) {first.group(1)} have effort 0 (or none) in the URDF" in err and "torque_limits" in err


@pytest.mark.heavy
def test_robot_check_notes_a_limbs_chain(capsys, tmp_path):
    """Mistakes a user made writing Go2's spec from Go1's: a leg's joints listed foot first is an error naming the
    order expected; a calf left out of the leg is a note (it would stay at its nominal angle: the leg became a
    two-joint limb without closed-form IK, whose start search ran for 14 minutes); an ``elbow_straight`` far from
    where the leg is straightest is a note, with that angle (Go1's calf bound -0.888 rad: the straight knee, 0,
    lies beyond it).  The distance from hip to foot is measured here with Pinocchio directly."""
    import pinocchio as pin
    import yaml

    from climb_ompl.cli import main
    from climb_ompl.resources import robots_dir

    spec = yaml.safe_load((robots_dir() / "go1.yaml").read_text())
    leg = spec["limbs"][0]
    bad = {**spec, "limbs": [{**leg, "joints": leg["joints"][::-1]}, *spec["limbs"][1:]]}
    (tmp_path / "reversed.yaml").write_text(yaml.safe_dump(bad))
    assert main(["robot", "check", str(tmp_path / "reversed.yaml")]) == 2
    assert "limbs[0].joints: list the joints from the root to the hand: [FL_hip_joint, FL_thigh_joint, " \
           "FL_calf_joint]" in capsys.readouterr().err
    short = {**spec, "limbs": [{**leg, "joints": leg["joints"][:2], "elbow": leg["joints"][1]},
                               *spec["limbs"][1:]]}
    short["limbs"][0].pop("elbow_straight", None)
    (tmp_path / "short.yaml").write_text(yaml.safe_dump(short))
    assert main(["robot", "check", str(tmp_path / "short.yaml")]) == 0
    err = capsys.readouterr().err
    assert "limb fl: joint(s) FL_calf_joint move its hand but are in no limb" in err
    assert "limb(s) fl have no closed-form inverse kinematics" in err
    # a joint that only turns the hand frame about its origin (the frame at the knee, a wrist centre) is said so
    knee = {**spec, "limbs": [{"name": "fl", "hand_frame": "FL_calf", "joints": leg["joints"][:2]},
                              *spec["limbs"][1:]]}
    (tmp_path / "knee.yaml").write_text(yaml.safe_dump(knee))
    assert main(["robot", "check", str(tmp_path / "knee.yaml")]) == 0
    err = capsys.readouterr().err
    assert "limb fl: joint(s) FL_calf_joint lie between its first joint and its hand frame but only turn the frame" \
        in err and "move its hand" not in err
    # its reach is bounded with the calf locked (a hexapod trial's knee-less leg said 0.320 m, reaching 0.239 m):
    # an upper bound on the distances sampled (the oracle), well below the straightened leg's 0.506 m
    shorty = RobotModel.load(tmp_path / "short.yaml")
    lb = shorty.limb("fl")
    idx = list(lb.joint_indices)
    rng = np.random.default_rng(0)
    far = 0.0
    for _ in range(4000):
        q = shorty.nominal_q.copy()
        q[idx] = rng.uniform(shorty.lower[idx], shorty.upper[idx])
        fk = shorty.limb_fk(q, lb)
        far = max(far, float(np.linalg.norm(fk[-1] - fk[0])))
    assert far <= lb.reach + 1e-9 and lb.reach < 1.25 * far and lb.reach < 0.45
    assert RobotModel.load("go1").limb("fl").reach == pytest.approx(0.506)
    r = RobotModel.load("go1")
    e = r.limb("fl").elbow_index
    lo = float(r.lower[e])
    # a bound written rounded, within 0.005 of it on either side, is that bound; farther out it is refused, naming
    # the field; farther in it is kept
    hi = float(r.upper[e])
    for value, read in ((lo - 0.0004, lo), (lo + 0.004, lo), (hi + 0.0049, hi), (hi - 0.002, hi), (lo + 0.1, lo + 0.1),
                        (lo - 0.02, None)):
        rounded = {**spec, "limbs": [{**leg, "elbow_straight": value}, *spec["limbs"][1:]]}
        (tmp_path / "rounded.yaml").write_text(yaml.safe_dump(rounded))
        if read is not None:
            got = RobotModel.load(tmp_path / "rounded.yaml").limb("fl").elbow_straight
            assert got == pytest.approx(read, abs=1e-12)
        else:
            with pytest.raises(RobotModelError, match=r"limbs\[0\]\.elbow_straight: .* is outside the joint bounds"):
                RobotModel.load(tmp_path / "rounded.yaml")
    bent = {**spec, "limbs": [{**leg, "elbow_straight": lo}, *spec["limbs"][1:]]}
    (tmp_path / "bent.yaml").write_text(yaml.safe_dump(bent))
    assert main(["robot", "check", str(tmp_path / "bent.yaml")]) == 0
    err = capsys.readouterr().err
    # the oracle: hip-to-foot distance over the calf's range, the other joints nominal
    jid = r.limb("fl").joint_ids[0]
    angles = np.linspace(lo, float(r.upper[e]), 721)
    dist = []
    for a in angles:
        q = np.array(r.nominal_q, dtype=float)
        q[e] = a
        pin.framesForwardKinematics(r.model, r.data, q)
        dist.append(np.linalg.norm(r.data.oMf[r.limb("fl").frame_id].translation - r.data.oMi[jid].translation))
    straightest = float(angles[int(np.argmax(dist))])
    assert straightest == pytest.approx(float(r.upper[e]), abs=0.01)
    assert f"limb fl: its elbow is straightest (the hand farthest from the first joint) at {straightest:.3f}" in err
    assert err.count("straightest") == 1  # the other legs' elbow_straight are right


# ---------------------------------------------------------------------------------------- a user's robot
def _erd_robots() -> Path | None:
    from importlib import metadata

    try:
        dist = metadata.distribution("example-robot-data")
    except metadata.PackageNotFoundError:
        return None
    p = Path(dist.locate_file("cmeel.prefix/share/example-robot-data/robots"))
    return p if p.is_dir() else None


@pytest.mark.heavy
def test_ik_over_whole_turn_ranges_gives_every_copy_once(tmp_path):
    """Solo-12's URDF (example-robot-data) bounds every joint by +-10 rad, so each leg's inverse-kinematics solution
    comes back once per whole turn that fits in each joint's range.  The oracle: the solutions of the same leg
    with every joint narrowed to one turn, shifted by every 2 pi k that stays inside +-10 rad."""
    import itertools

    robots = _erd_robots()
    if robots is None:
        pytest.skip("example-robot-data not installed")
    urdf = robots / "solo_description" / "robots" / "solo12.urdf"
    joints = ["FL_HAA", "FL_HFE", "FL_KFE"]
    spec = {"name": "solo12", "urdf": str(urdf), "package_dirs": [str(robots.parent.parent)],
            "base": {"type": "spatial", "lower": [-2, -2, -1, -3.1, -1.5, -3.1], "upper": [2, 2, 3, 3.1, 1.5, 3.1]},
            "limbs": [{"name": "fl", "hand_frame": "FL_FOOT", "joints": joints, "elbow": "FL_KFE"}]}
    wide = RobotModel.from_spec(spec, base_dir=tmp_path)
    one_turn = RobotModel.from_spec({**spec, "joint_limits": {j: [-math.pi, math.pi] for j in joints}},
                                    base_dir=tmp_path)
    idx = list(wide.limb("fl").joint_indices)
    lo, hi = wide.lower[idx], wide.upper[idx]
    rng = np.random.default_rng(3)
    counts, copies = [], []
    for _ in range(20):
        q = wide.random_configuration(rng)
        q[idx] = rng.uniform(-math.pi, math.pi, 3)
        target = wide.hand_position(q, "fl")
        got = np.array(sorted(tuple(s[idx]) for s in wide.limb_ik("fl", q, target)))
        want = []
        for s in one_turn.limb_ik("fl", q, target):
            for k in itertools.product(range(-2, 3), repeat=3):
                v = s[idx] + 2 * math.pi * np.array(k)
                if np.all(v >= lo - 1e-9) and np.all(v <= hi + 1e-9):
                    want.append(tuple(v))
        want_a = np.array(sorted(want))
        assert got.shape == want_a.shape and np.allclose(got, want_a, atol=1e-9)
        counts.append(len(got))
        copies.append(len(got) / max(1, len(one_turn.limb_ik("fl", q, target))))
    assert max(counts) >= 27  # three whole turns per joint fit in 20 rad
    from climb_ompl.cli.robot import limit_notes

    (note,) = [n for n in limit_notes(wide) if "range" in n]
    assert "up to 64 copies of each for limb fl" in note and 27 <= max(copies) <= 64  # 3-4 turns fit per joint


def test_unique_keeps_the_first_of_same_solutions_as_comparing_every_pair():
    """:func:`_unique` (a grid of cells) against the greedy pairwise de-duplication it replaces."""
    from climb_ompl.model.limb_ik import _same, _unique

    rng = np.random.default_rng(0)
    for trial in range(30):
        base = rng.uniform(-10, 10, (int(rng.integers(1, 40)), 3))
        rows = [b + rng.normal(0, 10.0 ** -rng.integers(5, 9), 3) * (rng.random() < 0.5)
                for b in base[rng.integers(0, len(base), 80)]]  # copies, some a hair apart
        sols = []
        for r_ in rows:
            q = np.zeros(6)
            q[[1, 3, 4]] = r_
            sols.append(q)
        brute: list[np.ndarray] = []
        for s_ in sols:
            if not any(_same(s_, b_) for b_ in brute):
                brute.append(s_)
        got = _unique(sols, [1, 3, 4])
        assert len(got) == len(brute) and all(a is b for a, b in zip(got, brute, strict=True)), trial


def test_third_party_quadruped(tmp_path):
    """Solo-12 from example-robot-data (not written by this project), limb spec written here."""
    import pinocchio as pin

    robots = _erd_robots()
    if robots is None:
        pytest.skip("example-robot-data not installed")
    urdf = robots / "solo_description" / "robots" / "solo12.urdf"
    legs = ("FL", "FR", "HL", "HR")
    spec = {"name": "solo12", "urdf": str(urdf), "package_dirs": [str(robots.parent.parent)],
            "base": {"type": "spatial", "lower": [-2, -2, -1, -3.1, -1.5, -3.1], "upper": [2, 2, 3, 3.1, 1.5, 3.1]},
            "limbs": [{"name": leg.lower(), "hand_frame": f"{leg}_FOOT",
                       "joints": [f"{leg}_HAA", f"{leg}_HFE", f"{leg}_KFE"], "elbow": f"{leg}_KFE"}
                      for leg in legs]}
    path = tmp_path / "solo12.yaml"
    path.write_text(yaml.safe_dump(spec))
    r = RobotModel.load(path)
    assert r.nq == 6 + 12 and len(r.limbs) == 4
    # independent Pinocchio model with a free-flyer root
    ff = pin.buildModelFromUrdf(str(urdf), pin.JointModelFreeFlyer())
    fd = ff.createData()
    rng = np.random.default_rng(7)
    for _ in range(5):
        q = r.random_configuration(rng)
        x, y, z, rz, ry, rx = q[:6]
        R = _rpy(rx, ry, rz)
        quat = pin.Quaternion(R).coeffs()
        qf = np.r_[x, y, z, quat, q[6:]]
        # joint order after the base is the URDF's in both models
        assert list(r.joint_names[6:]) == [ff.names[j] for j in range(2, ff.njoints)]
        pin.framesForwardKinematics(ff, fd, qf)
        assert np.allclose(r.com(q), pin.centerOfMass(ff, fd, qf), atol=1e-12)
        for lb, h in zip(r.limbs, r.hand_positions(q), strict=True):
            assert np.allclose(h, fd.oMf[ff.getFrameId(lb.hand_frame)].translation, atol=1e-12)
        frames, mass, com = urdf_oracle(urdf, values_of(r, q), root_T=_T(R, [x, y, z]))
        assert np.allclose(r.com(q), com, atol=1e-12) and mass == pytest.approx(r.mass)
    # numeric IK on a third-party leg, and collision geometry from meshes
    q = r.nominal_q.copy()
    q[2] = 0.4
    lb = r.limbs[0]
    target = r.hand_position(q, lb) + [0.03, 0.02, 0.05]
    sols = r.limb_ik(lb, q, target)
    assert sols and np.linalg.norm(r.hand_position(sols[0], lb) - target) < 1e-9
    assert r.collision_model.ngeoms > 0
    ground = Terrain.from_dict({"name": "g", "dim": 3, "holds": [{"id": "h", "position": [0, 0, 0],
                                "normal": [0, 0, 1]}], "surfaces": [{"type": "plane", "point": [0, 0, 0],
                                                                     "normal": [0, 0, 1]}]})
    assert not r.in_collision(q, ground, contact_limbs=[])
    q_low = q.copy()
    q_low[2] = 0.0
    assert r.in_collision(q_low, ground)


def test_collision_broadphase_matches_pairwise_oracle():
    """in_collision (broad phase + Coal) equals a plain loop of coal.collide over the expected pairs."""
    import coal
    import pinocchio as pin

    r = load("lemur")
    wall = _wall()
    contact = ["ne", "sw"]
    gm = r.collision_model
    gd = gm.createData()
    exempt = {i for i, o in enumerate(gm.geometryObjects) if o.name in ("ne_hand_0", "sw_hand_0")}
    half = coal.Halfspace(np.array([0.0, 1.0, 0.0]), 0.0)
    pairs = {frozenset(p) for p in r.collision_pairs()}
    names = [o.name for o in gm.geometryObjects]
    rng = np.random.default_rng(11)
    span = 0.15 * (r.upper - r.lower)
    q0 = r.nominal_q.copy()
    q0[[r.joint_names.index("nw_wrist"), r.joint_names.index("se_wrist")]] = 0.3  # free limbs lifted
    seen = {True: 0, False: 0}
    for _ in range(150):
        q = np.clip(q0 + rng.uniform(-span, span), r.lower, r.upper)
        pin.updateGeometryPlacements(r.model, r.data, gm, gd, q)
        hit = False
        for i, oi in enumerate(gm.geometryObjects):
            Ti = coal.Transform3s(gd.oMg[i].rotation, gd.oMg[i].translation)
            if i not in exempt:
                res = coal.CollisionResult()
                hit |= coal.collide(oi.geometry, Ti, half, coal.Transform3s(), coal.CollisionRequest(), res) > 0
            for j in range(i + 1, gm.ngeoms):
                if frozenset((names[i], names[j])) not in pairs:
                    continue
                Tj = coal.Transform3s(gd.oMg[j].rotation, gd.oMg[j].translation)
                res = coal.CollisionResult()
                hit |= coal.collide(oi.geometry, Ti, gm.geometryObjects[j].geometry, Tj,
                                    coal.CollisionRequest(), res) > 0
        assert r.in_collision(q, wall, contact_limbs=contact) == hit
        seen[hit] += 1
    assert seen[True] > 10 and seen[False] > 10


def test_clearance_matches_coal_distance_oracle():
    """in_collision(clearance=c) is True exactly when two robot links are closer than c (coal.distance)."""
    import coal
    import pinocchio as pin

    r = load("lemur")
    wall = _wall()
    gm = r.collision_model
    gd = gm.createData()
    names = [o.name for o in gm.geometryObjects]
    idx = {n: i for i, n in enumerate(names)}
    pairs = [(idx[a], idx[b]) for a, b in r.collision_pairs()]
    rng = np.random.default_rng(5)
    span = 0.25 * (r.upper - r.lower)
    q0 = r.nominal_q.copy()
    checked = 0
    for _ in range(60):
        q = np.clip(q0 + rng.uniform(-span, span), r.lower, r.upper)
        if r.self_collision(q):
            continue
        pin.updateGeometryPlacements(r.model, r.data, gm, gd, q)
        d = np.inf
        for i, j in pairs:
            res = coal.DistanceResult()
            d = min(d, coal.distance(gm.geometryObjects[i].geometry,
                                     coal.Transform3s(gd.oMg[i].rotation, gd.oMg[i].translation),
                                     gm.geometryObjects[j].geometry,
                                     coal.Transform3s(gd.oMg[j].rotation, gd.oMg[j].translation),
                                     coal.DistanceRequest(), res))
        if not 0.002 < d < 0.2:
            continue
        assert not r.in_collision(q, None, clearance=0.9 * d)
        assert r.in_collision(q, None, clearance=1.1 * d)
        hands = [lb.name for lb in r.limbs]
        if not r.in_collision(q, wall, contact_limbs=hands):  # the wall pairs keep no margin
            assert not r.in_collision(q, wall, contact_limbs=hands, clearance=0.9 * d)
            assert r.in_collision(q, wall, contact_limbs=hands, clearance=1.1 * d)
        checked += 1
    assert checked >= 10


def test_numeric_ik_survives_a_rank_deficient_jacobian():
    """``lemur-hooks`` (numerical IK): a target on which the damped least squares once met a rank-deficient
    Jacobian after its damping had decayed to zero, and raised ``LinAlgError`` (probing the reach maps)."""
    rob = RobotModel.load("lemur-hooks")
    target = np.array([-0.2121320340983502, -4.134312336923074e-11, 0.8818376620983501])
    q0 = np.asarray(rob.nominal_q, dtype=float)
    for sol in rob.limb_ik("ne", q0, target):
        assert np.linalg.norm(np.asarray(rob.hand_position(sol, "ne")) - target) < 1e-8


def test_numeric_ik_stopping_stalled_restarts_finds_the_same_solutions(monkeypatch):
    """``lemur-hooks``' limbs (numeric IK) on 60 targets, half of them reached by forward kinematics, half drawn
    near the hand (many out of reach): a restart stopped when its error stalls (``IK_STALL``) gives exactly the
    solutions (and the failures) of restarts run to their 200 iterations, and a failed call runs fewer
    iterations (counted through Pinocchio's frame Jacobian, called once per iteration)."""
    import pinocchio as pin

    import climb_ompl.model.limb_ik as ik_mod

    rob = RobotModel.load("lemur-hooks")
    rng = np.random.default_rng(3)
    q0 = np.asarray(rob.nominal_q, dtype=float)
    cases = []
    for k in range(60):
        lb = rob.limbs[k % len(rob.limbs)]
        if k % 2:
            q = q0.copy()
            q[list(lb.joint_indices)] = rob.random_configuration(rng)[list(lb.joint_indices)]
            target = np.asarray(rob.hand_position(q, lb.name))
        else:
            target = np.asarray(rob.hand_position(q0, lb.name)) + rng.normal(0.0, 0.15, 3)
        cases.append((lb.name, target))
    calls = [0]
    jac = pin.computeFrameJacobian

    def counted(*a):
        calls[0] += 1
        return jac(*a)

    monkeypatch.setattr(pin, "computeFrameJacobian", counted)

    def solve() -> tuple[list[list[np.ndarray]], int]:
        calls[0] = 0
        return [rob.limb_ik(name, q0, t) for name, t in cases], calls[0]

    stopped, n_stopped = solve()
    monkeypatch.setattr(ik_mod, "IK_STALL", 10**9)
    full, n_full = solve()
    assert sum(bool(s) for s in full) >= 30 and sum(not s for s in full) >= 5  # both outcomes exercised
    assert all(len(a) == len(b) and all(np.array_equal(x, y) for x, y in zip(a, b, strict=True))
               for a, b in zip(stopped, full, strict=True))
    assert n_stopped < 0.5 * n_full


@pytest.mark.parametrize("name", ["lemur", "planar-3limb", "go1", "anymal-c"])
def test_ik_nearest_is_the_nearest_of_every_solution(name):
    """``limb_ik_nearest`` (which checks only the solution it returns) against the brute-force minimum over
    ``limb_ik``'s full list, to the bit, for references on both sides of the elbow (the reference's elbow also
    mirrored about straight: a quadruped's knee bends one way only); with ``same_bend``, the minimum over the
    solutions whose elbow bends as the reference's does (``None`` when there is none); with ``prefer_bend``, that
    minimum, or the minimum over all when there is none."""
    r = load(name)
    rng = np.random.default_rng(5)
    n_bent = n_none = 0
    for _ in range(40):
        q, ref0 = r.random_configuration(rng), r.random_configuration(rng)
        for lb in r.limbs:
            idx = list(lb.joint_indices)
            qt = q.copy()
            qt[idx] = r.random_configuration(rng)[idx]
            target = r.hand_position(qt, lb)
            sols = r.limb_ik(lb, q, target)
            e, st = lb.elbow_index, lb.elbow_straight or 0.0
            mirrored = ref0.copy()
            mirrored[e] = 2.0 * st - ref0[e]
            for ref in (ref0, mirrored):
                best = nearest = min(sols, key=lambda s: float(np.sum((s[idx] - ref[idx]) ** 2)))
                got = r.limb_ik_nearest(lb, q, target, ref)
                assert got is not None and np.array_equal(got, best)
                same = [s for s in sols if np.sign(s[e] - st) == np.sign(ref[e] - st)]
                got = r.limb_ik_nearest(lb, q, target, ref, same_bend=True)
                pref = r.limb_ik_nearest(lb, q, target, ref, prefer_bend=True)
                if not same:
                    assert got is None
                    assert pref is not None and np.array_equal(pref, nearest)
                    n_none += 1
                    continue
                best = min(same, key=lambda s: float(np.sum((s[idx] - ref[idx]) ** 2)))
                assert got is not None and np.array_equal(got, best)
                assert pref is not None and np.array_equal(pref, best)
                n_bent += not np.array_equal(best, nearest)
    both_ways = any(r.lower[lb.elbow_index] < (lb.elbow_straight or 0.0) < r.upper[lb.elbow_index] for lb in r.limbs)
    assert n_bent >= 5 or not both_ways  # the bend changed the answer often enough to be tested
    # ``prefer_bend`` fell back to the other bend: for the mirrored references of a knee bending one way only, and
    # where LEMUR's shoulder limits leave a target one bend only
    assert n_none >= 20 or both_ways
    assert n_none >= 1 or name != "lemur"


@pytest.mark.parametrize("name", ["lemur", "go1"])
def test_the_closed_forms_take_sequences_as_arrays(name):
    """The public closed forms (``ik_analytic``, ``ik_abduction``) take lists for the configuration, the target and
    the reference, with the same answers as for arrays, and leave ``q`` as it was; a chain built without its first
    joint's parent and placement reads them from the model, with the same answers."""
    from dataclasses import replace

    from climb_ompl.model.limb_ik import AbductionChain, ik_abduction, ik_analytic

    r = load(name)
    rng = np.random.default_rng(1)
    for lb in r.limbs:
        chain = r._chains[lb.name]
        solve = ik_abduction if isinstance(chain, AbductionChain) else ik_analytic
        q, ref = r.random_configuration(rng), r.random_configuration(rng)
        qt = q.copy()
        qt[list(lb.joint_indices)] = r.random_configuration(rng)[list(lb.joint_indices)]
        target = r.hand_position(qt, lb)
        q0 = q.copy()
        for kw in ({}, {"ref": ref}):
            want = solve(r, lb, chain, q, target, **kw)
            got = solve(r, lb, chain, q.tolist(), target.tolist(), **{k: v.tolist() for k, v in kw.items()})
            assert want and len(got) == len(want) and all(np.array_equal(a, b) for a, b in zip(got, want, strict=True))
            assert chain.placement is not None
            bare = solve(r, lb, replace(chain, parent=-1, placement=None), q, target, **kw)
            assert len(bare) == len(want) and all(np.array_equal(a, b) for a, b in zip(bare, want, strict=True))
        assert np.array_equal(q, q0)


def test_an_abduction_legs_nearest_at_a_double_root_is_that_of_the_full_list():
    """Targets where an abduction leg's first angle is nearly a double root (the two roots about 1e-8 rad apart):
    the candidates are then near-duplicates, of which the full list keeps only the first, and ``limb_ik_nearest``
    gives the nearest of the full list to the bit (with either reference side and either bend option)."""
    import pinocchio as pin

    r = load("go1")
    lb = r.limbs[0]
    c, idx = r._chains[lb.name], list(lb.joint_indices)
    q = np.array(r.nominal_q, dtype=float)
    pin.forwardKinematics(r.model, r.data, q)
    frame = r.data.oMi[r.model.parents[lb.joint_ids[0]]] * r.model.jointPlacements[lb.joint_ids[0]]
    n_checked = 0
    for h0 in np.linspace(r.lower[idx[0]] + 0.05, r.upper[idx[0]] - 0.05, 7):
        n = pin.exp3(c.a * h0) @ c.b2
        for lam in np.linspace(-0.5, 0.5, 41):
            for eps in (1e-9, 1e-8, 1e-7, 3e-7):
                target = frame.act(c.k * n + lam * c.a + eps * c.k * np.cross(c.a, n))
                sols = r.limb_ik(lb, q, target)
                if not sols:
                    continue
                for side in (1, -1):
                    ref = q.copy()
                    ref[idx[0]] = h0 + side * 0.3
                    want = min(sols, key=lambda s: float(np.sum((s[idx] - ref[idx]) ** 2)))
                    assert np.array_equal(r.limb_ik_nearest(lb, q, target, ref), want)
                    n_checked += 1
    assert n_checked >= 500


def test_wrap_into_lists_every_whole_turn_inside_the_bounds():
    """Against a brute-force scan of ``angle + 2 pi k`` over k, for bounds narrower and wider than a turn."""
    from climb_ompl.model.limb_ik import wrap_into

    rng = np.random.default_rng(2)
    for _ in range(2000):
        lo = float(rng.uniform(-7.0, 3.0))
        hi = lo + float(rng.choice([rng.uniform(0.0, 2 * np.pi), rng.uniform(2 * np.pi, 14.0)]))
        angle = float(rng.uniform(-20.0, 20.0))
        want = [min(max(angle + 2 * np.pi * k, lo), hi) for k in range(-10, 11)
                if lo - 1e-12 <= angle + 2 * np.pi * k <= hi + 1e-12]
        assert wrap_into(angle, lo, hi) == pytest.approx(want, abs=1e-12)


def test_the_narrow_bounds_shortcut_is_wrap_into_to_the_bit(monkeypatch):
    """``_into`` (an angle inside bounds narrower than a turn taken as it is) gives :func:`wrap_into`'s values to the
    bit, a zero's sign included; and the closed-form IK gives the same solutions, byte for byte, with the shortcut
    switched off (``_NARROW = 0``: every angle through ``wrap_into``)."""
    import struct

    from climb_ompl.model import limb_ik
    from climb_ompl.model.limb_ik import _NARROW, _into, wrap_into

    def bits(xs):
        return [struct.pack("<d", x) for x in xs]

    rng = np.random.default_rng(5)
    for _ in range(5000):
        lo = float(rng.choice([rng.uniform(-7.0, 3.0), 0.0, -0.0]))
        hi = lo + float(rng.choice([rng.uniform(0.0, _NARROW), rng.uniform(_NARROW, 14.0)]))
        eps = float(rng.uniform(0, 1e-12))
        angle = float(rng.choice([rng.uniform(lo, hi), lo - eps, hi + eps, lo, hi, 0.0, -0.0, rng.uniform(-20, 20)]))
        assert bits(_into(angle, lo, hi)) == bits(wrap_into(angle, lo, hi))
    for name in ("lemur", "go1"):
        r = load(name)
        cases = []
        for _ in range(60):
            q, ref = r.random_configuration(rng), r.random_configuration(rng)
            for lb in r.limbs:
                qt = q.copy()
                qt[list(lb.joint_indices)] = r.random_configuration(rng)[list(lb.joint_indices)]
                cases.append((lb, q, r.hand_position(qt, lb), ref))
        def solve(r=r, cases=cases):
            out = []
            for lb, q, t, ref in cases:
                near, every = r.limb_ik_nearest(lb, q, t, ref), r.limb_ik(lb, q, t)
                out.append((None if near is None else near.tobytes(), [x.tobytes() for x in every]))
            return out

        fast = solve()
        monkeypatch.setattr(limb_ik, "_NARROW", 0.0)
        slow = solve()
        monkeypatch.undo()
        assert fast == slow


def test_robot_check_compares_a_sphere_contact_with_the_urdfs_foot(tmp_path):
    """The bundled quadrupeds' contact spheres match their URDFs' foot spheres (no note).  ANYmal C's spec
    without its offset gets one giving the offset its spec states (2.25 cm along the FOOT frame's z); Go1's with
    another radius names the URDF's 2 cm; Solo-12's mesh foot (a half sphere of radius 0.016 m) gets none with that
    radius and is named a mesh with another."""
    from climb_ompl.cli.robot import contact_notes
    from climb_ompl.resources import robots_dir

    assert contact_notes(RobotModel.load("go1")) == [] and contact_notes(RobotModel.load("anymal-c")) == []
    for name, edit, needle in (
            ("anymal-c", {"offset": [0.0, 0.0, 0.0]}, "contact.offset [0, 0, 0.0225] puts it there"),
            ("go1", {"radius": 0.03}, "the contact sphere has radius 0.03 m, the URDF's collision sphere at the "
                                      "hand (FL_foot_0, FR_foot_0, RL_foot_0, RR_foot_0) 0.02 m")):
        spec = yaml.safe_load((robots_dir() / f"{name}.yaml").read_text())
        for lb in spec["limbs"]:
            lb["contact"] = {**lb["contact"], **edit}
        (tmp_path / f"{name}.yaml").write_text(yaml.safe_dump(spec))
        notes = contact_notes(RobotModel.load(tmp_path / f"{name}.yaml"))
        assert len(notes) == 1 and notes[0].startswith("limbs ") and needle in notes[0], notes
    robots = _erd_robots()
    if robots is not None:
        legs = ("FL", "FR", "HL", "HR")
        spec = {"name": "solo12", "urdf": str(robots / "solo_description" / "robots" / "solo12.urdf"),
                "package_dirs": [str(robots.parent.parent)],
                "base": {"type": "spatial", "lower": [-2, -2, -1, -3.1, -1.5, -3.1], "upper": [2, 2, 3, 3.1, 1.5, 3.1]},
                "limbs": [{"name": leg.lower(), "hand_frame": f"{leg}_FOOT",
                           "contact": {"type": "sphere", "radius": 0.016},
                           "joints": [f"{leg}_HAA", f"{leg}_HFE", f"{leg}_KFE"], "elbow": f"{leg}_KFE"}
                          for leg in legs]}
        assert contact_notes(RobotModel.from_spec(spec, base_dir=tmp_path)) == []  # its half-sphere sole, r 0.016
        for lb in spec["limbs"]:
            lb["contact"]["radius"] = 0.025
        (note,) = contact_notes(RobotModel.from_spec(spec, base_dir=tmp_path))
        assert "is a mesh up to 0.032 m long, not a sphere" in note


def test_an_unknown_joint_in_a_spec_suggests_the_nearest_name(tmp_path):
    """A typo in a joint name, or in one of the base's own coordinates, is answered with the nearest valid name
    and the valid names (it said only "not in the URDF", also for base coordinates, which are not URDF joints)."""
    from climb_ompl.errors import RobotModelError
    from climb_ompl.resources import robots_dir

    spec = yaml.safe_load((robots_dir() / "go1.yaml").read_text())
    limb = spec["limbs"][0]
    good = limb["joints"][-1]
    limb["joints"][-1] = good[:-2] + good[-1] + good[-2]  # two letters swapped
    f = tmp_path / "typo.yaml"
    f.write_text(yaml.safe_dump(spec))
    with pytest.raises(RobotModelError) as exc:
        RobotModel.load(f)
    assert f"did you mean {good!r}" in str(exc.value) and "valid: " in str(exc.value)
    limb["joints"][-1] = good
    spec["nominal"] = {**spec.get("nominal", {}), "base_yy": 0.2}
    f.write_text(yaml.safe_dump(spec))
    with pytest.raises(RobotModelError) as exc:
        RobotModel.load(f)
    assert "did you mean 'base_y'" in str(exc.value) and "base's coordinates" in str(exc.value)
