"""Third-party quadrupeds (Go1, ANYmal C from example-robot-data): specs, sphere contacts, SRDF, base chart.

Each robot's URDF is read from the installed example-robot-data package (``urdf_package`` in the spec);
the tests skip if it is missing.  Oracles: an independent Pinocchio model with a free-flyer root and
the URDF read by hand (``test_robot.urdf_oracle``), Coal directly, the SRDF's XML.
"""

from __future__ import annotations

import math
import xml.etree.ElementTree as ET
from importlib import metadata

import numpy as np
import pytest
from conftest import ROOT
from test_robot import _T, _rpy, urdf_oracle, values_of

from climb_ompl.errors import RobotModelError
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain

QUADRUPEDS = ("go1", "anymal-c")

try:
    metadata.distribution("example-robot-data")
except metadata.PackageNotFoundError:  # pragma: no cover - a dev install has it (pyproject.toml)
    pytest.skip("example-robot-data not installed", allow_module_level=True)

_cache: dict[str, RobotModel] = {}


def load(name: str) -> RobotModel:
    if name not in _cache:
        _cache[name] = RobotModel.load(name)
    return _cache[name]


def ground(holds: list[tuple[float, float, float]] | None = None) -> Terrain:
    """The wall y = 0 as a solid half-space with holds on it (normal +y)."""
    holds = holds or [(0.0, 0.0, 0.0)]
    return Terrain.from_dict({"name": "g", "dim": 3, "gravity": [0.0, -9.81, 0.0],
                              "holds": [{"id": f"h{i}", "position": list(p), "normal": [0, 1, 0]}
                                        for i, p in enumerate(holds)],
                              "surfaces": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}]})


# ---------------------------------------------------------------------------------------- loading
@pytest.mark.parametrize("name,mass,radius", [("go1", 13.1005, 0.02), ("anymal-c", 52.135, 0.03)])
def test_loads_from_the_package(name, mass, radius):
    r = load(name)
    assert r.nq == 18 and len(r.limbs) == 4
    assert r.mass == pytest.approx(mass, rel=1e-4)
    assert "example-robot-data" in str(r.urdf_path) and r.srdf_path is not None  # nothing copied
    assert r.joint_names[:6] == ("base_x", "base_y", "base_z", "base_rz", "base_ry", "base_rx")
    for lb in r.limbs:
        assert lb.ik == "analytic"  # abduction-pitch-pitch legs in closed form
        assert lb.contact.type == "sphere" and lb.contact.radius == radius
    assert r.within_limits(r.nominal_q)
    # nominal: belly on the wall, nose up, the four feet spheres touching the wall y = 0
    H = r.hand_positions(r.nominal_q)
    assert np.allclose(H[:, 1], radius, atol=2e-3)
    assert np.all(np.ptp(H[:, 2]) > 0.3)  # front and hind feet apart along z (up the wall)


def test_missing_package_is_a_clear_error(tmp_path):
    spec = tmp_path / "r.yaml"
    spec.write_text("name: r\nurdf_package: not-an-installed-package\nurdf: robots/r.urdf\n"
                    "base: {type: spatial, lower: [0, 0, 0, 0, 0, 0], upper: [1, 1, 1, 1, 1, 1]}\n"
                    "limbs: [{name: a, hand_frame: f, joints: [j]}]\n")
    with pytest.raises(RobotModelError, match="pip install not-an-installed-package") as ei:
        RobotModel.load(spec)
    assert ei.value.field == "urdf_package"


# ---------------------------------------------------------------------------------------- kinematics
@pytest.mark.parametrize("name", QUADRUPEDS)
def test_fk_against_free_flyer_and_urdf(name):
    """Hands and CoM against a free-flyer Pinocchio model (orientation R_ref Rz Ry Rx) and the URDF by hand."""
    import pinocchio as pin

    r = load(name)
    ref = r.spec["base"]["reference_rpy"]
    R_ref = _rpy(*ref)
    ff = pin.buildModelFromUrdf(str(r.urdf_path), pin.JointModelFreeFlyer())
    fd = ff.createData()
    assert list(r.joint_names[6:]) == [ff.names[j] for j in range(2, ff.njoints)]
    rng = np.random.default_rng(3)
    for _ in range(4):
        q = r.random_configuration(rng)
        x, y, z, rz, ry, rx = q[:6]
        R = R_ref @ _rpy(rx, ry, rz)
        qf = np.r_[x, y, z, pin.Quaternion(R).coeffs(), q[6:]]
        pin.framesForwardKinematics(ff, fd, qf)
        assert np.allclose(r.com(q), pin.centerOfMass(ff, fd, qf), atol=1e-12)
        frames, mass, com = urdf_oracle(r.urdf_path, values_of(r, q), root_T=_T(R, [x, y, z]))
        assert mass == pytest.approx(r.mass) and np.allclose(r.com(q), com, atol=1e-12)
        for lb, h in zip(r.limbs, r.hand_positions(q), strict=True):
            foot = lb.hand_frame.removesuffix("_sphere_centre")
            centre = frames[foot] @ np.r_[lb.contact.offset, 1.0]
            assert np.allclose(h, centre[:3], atol=1e-12)


@pytest.mark.parametrize("name", QUADRUPEDS)
def test_leg_ik_out_of_reach(name):
    """Round trips are in test_robot.test_ik_round_trip; here a target 2 m from the hip has no solution."""
    r = load(name)
    lb = r.limbs[0]
    assert r.limb_ik(lb, r.nominal_q, r.limb_fk(r.nominal_q, lb)[0] + [0.0, -2.0, 0.0]) == []  # out of reach


@pytest.mark.parametrize("name", QUADRUPEDS)
def test_base_is_not_singular_facing_up_the_wall(name):
    """Reference chart: the base's angular Jacobian has full rank facing up the wall and turning on it;
    plain Z-Y-X angles (reference identity) lose a rank at exactly that orientation (pitch -90 deg)."""
    import pinocchio as pin

    r = load(name)
    lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    fid = next(i for i, f in enumerate(r.model.frames) if f.type == pin.FrameType.BODY and f.parentJoint == 1)

    def smallest_sv(model, q):
        J = pin.computeFrameJacobian(model, model.createData(), q, fid, lwa)[3:, 3:6]
        return float(np.linalg.svd(J, compute_uv=False)[-1])

    q = r.nominal_q.copy()
    pin.framesForwardKinematics(r.model, r.data, q)
    Rb = np.array(r.data.oMf[fid].rotation)
    assert np.allclose(Rb[:, 0], [0, 0, 1], atol=1e-9) and np.allclose(Rb[:, 2], [0, 1, 0], atol=1e-9)
    assert smallest_sv(r.model, q) == pytest.approx(1.0)
    rng = np.random.default_rng(5)
    for _ in range(20):  # any turn on the wall, tilts within the spec's bounds
        q[3:6] = rng.uniform(r.lower[3:6], r.upper[3:6])
        # closed form: the Gram matrix of the axes (z, y', x'') has eigenvalues 1, 1 +- sin(ry)
        assert smallest_sv(r.model, q) == pytest.approx(math.sqrt(1.0 - abs(math.sin(q[4]))), abs=1e-9)
    assert math.sqrt(1.0 - math.sin(max(abs(r.lower[4]), abs(r.upper[4])))) > 0.5  # far from the singularity
    plain = {**r.spec, "base": {**r.spec["base"], "reference_rpy": [0.0, 0.0, 0.0],
                                "lower": [-3, -3, -3, -4, -2, -4], "upper": [3, 3, 3, 4, 2, 4]}}
    p = RobotModel.from_spec(plain, base_dir=r.spec_path.parent)
    qp = r.nominal_q.copy()
    qp[3:6] = [0.0, -math.pi / 2, -math.pi / 2]  # yaw, pitch, roll of the same orientation
    pin.framesForwardKinematics(p.model, p.data, qp)
    assert np.allclose(p.data.oMf[fid].rotation, Rb, atol=1e-9)
    assert smallest_sv(p.model, qp) < 1e-9


# ---------------------------------------------------------------------------------------- contact
@pytest.mark.parametrize("name", QUADRUPEDS)
def test_sphere_foot_on_a_hold(name):
    """hand_target puts the sphere on the hold; then neither the foot nor the lower leg collides with the
    ground, Coal's distance from the foot sphere to the plane is 0, and the contact point is the hold."""
    import coal
    import pinocchio as pin

    r = load(name)
    q = r.nominal_q.copy()
    hold = np.array([r.hand_position(q, 0)[0], 0.0, r.hand_position(q, 0)[2] + 0.03])
    others = [tuple(r.contact_point(q, lb, [0, 1, 0])) for lb in r.limbs[1:]]  # the feet stay on their holds
    wall = ground([tuple(hold), *others])
    lb = r.limbs[0]
    target = r.hand_target(lb, wall.holds[0])
    assert np.allclose(target, hold + [0, lb.contact.radius, 0])
    (q,) = r.limb_ik(lb, q, target)[:1]
    assert np.allclose(r.contact_point(q, lb, [0, 1, 0]), hold, atol=1e-9)
    names = [x.name for x in r.limbs]
    assert not r.in_collision(q, wall, contact_limbs=names) and r.collisions(q, wall, names) == []
    gm, gd = r.collision_model, r.collision_model.createData()
    pin.updateGeometryPlacements(r.model, r.data, gm, gd, q)
    spheres = [i for i, o in enumerate(gm.geometryObjects)
               if isinstance(o.geometry, coal.Sphere) and o.geometry.radius == lb.contact.radius]
    half = coal.Halfspace(np.array([0.0, 1.0, 0.0]), 0.0)
    i = min(spheres, key=lambda i: np.linalg.norm(gd.oMg[i].translation - r.hand_position(q, lb)))
    assert np.allclose(gd.oMg[i].translation, r.hand_position(q, lb), atol=1e-12)  # the frame is its centre
    d = coal.distance(gm.geometryObjects[i].geometry, coal.Transform3s(gd.oMg[i].rotation, gd.oMg[i].translation),
                      half, coal.Transform3s(), coal.DistanceRequest(), coal.DistanceResult())
    assert abs(d) < 1e-9


@pytest.mark.parametrize("name", QUADRUPEDS)
def test_lower_leg_near_the_hold_is_exempt(name):
    """The failure a new user met: with the foot frame on the hold (the sphere 2-3 cm into the wall), the
    lower leg touches the ground near the hold.  Exempt when the limb is in contact, reported otherwise,
    and reported when the leg reaches into the wall far from the hold."""
    r = load(name)
    q = r.nominal_q.copy()
    q[1] -= r.limbs[0].contact.radius  # every foot centre on the wall plane, spheres half inside
    holds = [tuple(h) for h in r.hand_positions(q)]
    wall = ground(holds)
    names = [lb.name for lb in r.limbs]
    assert not r.in_collision(q, wall, contact_limbs=names)
    hit = r.collisions(q, wall)
    assert {a for a, _ in hit} and all(b == "terrain 0 plane" for _, b in hit)
    assert r.in_collision(q, wall, contact_limbs=names[1:])  # the first foot is not in contact
    first = set(r.collisions(q, wall, names[1:]))
    assert first and first <= set(hit)
    # sink the whole robot: the legs enter the wall far from the holds
    deep = q.copy()
    deep[1] -= 0.15
    links = {a for a, _ in r.collisions(deep, wall, names)}
    assert links and r.in_collision(deep, wall, contact_limbs=names)


def test_near_rule_against_coal_oracle():
    """in_collision with contact limbs equals a plain Coal loop: contact links count only where a contact
    point lies farther than ``near`` from the hold; other links always; self pairs as listed."""
    import coal
    import pinocchio as pin

    r = load("go1")
    q0 = r.nominal_q.copy()
    q0[1] -= 0.02
    holds = [tuple(h) for h in r.hand_positions(q0)]
    wall = ground(holds)
    names = [lb.name for lb in r.limbs]
    gm, gd = r.collision_model, r.collision_model.createData()
    objs = gm.geometryObjects
    half = coal.Halfspace(np.array([0.0, 1.0, 0.0]), 0.0)
    req = coal.CollisionRequest(coal.CollisionRequestFlag.CONTACT, 8)
    near = {g: k for k in range(4) for g in r.collision_checker.near_geoms[k]}
    pairs = {tuple(sorted((a, b))) for a, b in r.collision_pairs()}
    rng = np.random.default_rng(2)
    seen = {True: 0, False: 0}
    exempted = 0  # samples where a contact link touches the wall near its hold only
    for _ in range(80):
        q = q0.copy()
        q[1] += rng.uniform(-0.08, 0.02)
        for lb in r.limbs:
            idx = list(lb.joint_indices)
            q[idx] = np.clip(q[idx] + rng.uniform(-0.12, 0.12, 3), r.lower[idx], r.upper[idx])
        pin.updateGeometryPlacements(r.model, r.data, gm, gd, q)
        P = np.array(r.hand_positions(q))
        hit, touched = False, False
        for i, o in enumerate(objs):
            res = coal.CollisionResult()
            Ti = coal.Transform3s(gd.oMg[i].rotation, gd.oMg[i].translation)
            if coal.collide(o.geometry, Ti, half, coal.Transform3s(), req, res):
                if i in near:
                    touched = True
                    hold = np.array(holds)[np.argmin(np.linalg.norm(np.array(holds) - P[near[i]], axis=1))]
                    hit |= any(np.linalg.norm(c.pos - hold) > r.limbs[near[i]].contact.near for c in res.getContacts())
                else:
                    hit = True
            for j in range(i + 1, gm.ngeoms):
                if tuple(sorted((o.name, objs[j].name))) in pairs:
                    Tj = coal.Transform3s(gd.oMg[j].rotation, gd.oMg[j].translation)
                    hit |= coal.collide(o.geometry, Ti, objs[j].geometry, Tj, coal.CollisionRequest(),
                                        coal.CollisionResult()) > 0
        assert r.in_collision(q, wall, contact_limbs=names) == hit
        assert (r.collisions(q, wall, names) != []) == hit
        seen[hit] += 1
        exempted += touched and not hit
    assert seen[True] >= 10 and seen[False] >= 10 and exempted >= 10


def test_contact_jacobian_vs_finite_differences():
    """The touching material point (fixed in the foot at q) moves with contact_jacobian; a point contact's is
    the hand Jacobian."""
    import pinocchio as pin

    r = load("anymal-c")
    n = np.array([0.3, 0.9, 0.2])
    n /= np.linalg.norm(n)
    rng = np.random.default_rng(4)
    q = r.random_configuration(rng)
    for lb in r.limbs:
        pin.framesForwardKinematics(r.model, r.data, q)
        local = r.data.oMf[lb.frame_id].actInv(r.contact_point(q, lb, n))  # the material point, foot frame

        def point(x, lb=lb, local=local):
            pin.framesForwardKinematics(r.model, r.data, x)
            return np.array(r.data.oMf[lb.frame_id].act(local))

        fd = np.array([(point(q + 1e-6 * e) - point(q - 1e-6 * e)) / 2e-6 for e in np.eye(r.nq)]).T
        J = r.contact_jacobian(q, lb, n)
        assert np.allclose(J, fd, atol=1e-7)
        assert not np.allclose(J, r.hand_jacobian(q, lb), atol=1e-3)  # the offset matters
    lem = RobotModel.load("lemur")
    assert np.array_equal(lem.contact_jacobian(lem.nominal_q, 0, n), lem.hand_jacobian(lem.nominal_q, 0))


def test_point_contacts_unchanged():
    """Bundled robots keep point contacts: hand_target is the hold, contact_point the hand frame."""
    r = RobotModel.load("lemur")
    q = r.nominal_q
    h = Terrain.load("demo-wall").holds[0]
    for lb in r.limbs:
        assert lb.contact.type == "point" and r.collision_checker.near_geoms[r.limbs.index(lb)] == ()
        assert np.array_equal(r.hand_target(lb, h), np.asarray(h.position))
        assert np.array_equal(r.contact_point(q, lb, h.normal), r.hand_position(q, lb))


# ---------------------------------------------------------------------------------------- SRDF
@pytest.mark.parametrize("name", QUADRUPEDS)
def test_srdf_pairs_removed(name):
    r = load(name)
    srdf = ET.parse(r.srdf_path).getroot()
    disabled = {frozenset((d.get("link1"), d.get("link2"))) for d in srdf.iter("disable_collisions")}
    no_srdf = RobotModel.from_spec({k: v for k, v in r.spec.items() if k != "srdf"}, base_dir=r.spec_path.parent)
    objs = r.collision_model.geometryObjects
    link = {o.name: r.model.frames[o.parentFrame].name for o in objs}
    full = set(no_srdf.collision_pairs())
    kept = set(r.collision_pairs())
    assert kept == {p for p in full if frozenset((link[p[0]], link[p[1]])) not in disabled}
    assert len(kept) < len(full)
    # adjacent links (joined by a joint) are never tested, with or without an SRDF
    m = r.model
    joint = {o.name: o.parentJoint for o in objs}
    for a, b in full:
        ja, jb = joint[a], joint[b]
        assert ja != jb and m.parents[ja] != jb and m.parents[jb] != ja


def test_an_srdf_of_another_robot_is_refused_or_noted(tmp_path, cli):
    """Go1 given ANYmal-C's SRDF (one of its 270 pairs names two Go1 links; Pinocchio would apply it silently):
    refused, naming the SRDF and both robots.  An SRDF naming some links the URDF lacks, and of another robot's name:
    ``robot check`` notes both, counting the pairs (checked against the SRDF's own elements)."""
    import yaml

    go1, anymal = load("go1"), load("anymal-c")
    spec = {**go1.spec, "srdf": str(anymal.srdf_path)}
    spec.pop("urdf_package", None)
    spec["urdf"] = str(go1.urdf_path)
    with pytest.raises(RobotModelError, match=r"srdf: \d+ of its 270 disable_collisions pairs name links not in the "
                                              r"URDF .*the SRDF is of robot 'anymal', the URDF of 'go1': an SRDF of "
                                              r"another robot\?"):
        RobotModel.from_spec(spec, base_dir=tmp_path)
    root = ET.parse(go1.srdf_path).getroot()
    root.set("name", "go1-copy")
    extra = ET.SubElement(root, "disable_collisions", link1="trunk", link2="no_such_link")
    extra.set("reason", "Never")
    path = tmp_path / "go1-copy.srdf"
    ET.ElementTree(root).write(path)
    path_spec = tmp_path / "go1.yaml"
    path_spec.write_text(yaml.safe_dump({**spec, "srdf": str(path)}))
    n = len(list(root.iter("disable_collisions")))
    r = cli("robot", "check", path_spec)
    assert r.code == 0, r.err
    assert "its robot is 'go1-copy', the URDF's 'go1': the SRDF of another robot?" in r.err
    assert f"1 of its {n} disable_collisions pairs name links not in the URDF ('no_such_link')" in r.err
    assert "srdf" not in cli("robot", "check", "go1").err
    # plan says it too (here before refusing a goal hold that does not exist)
    r = cli("plan", "--robot", path_spec, "--terrain", "stepping-stone-ramp-3m", "--goal-hold", "fl=NOPE",
            "--out", tmp_path / "p.json")
    assert r.code == 2 and "its robot is 'go1-copy', the URDF's 'go1'" in r.err, r.err
    # example-robot-data names Go2's URDF robot "go2_description", its SRDF "go2": one robot
    assert "srdf" not in cli("robot", "check", ROOT / "examples" / "go2.yaml").err


def test_go1_trunk_box_against_the_calf_rotors_is_ignored():
    """Go1's calf-rotor cylinders touch the trunk's collision box only through the box's corners: Coal's distance
    is 3.8 cm at zero abduction, inside the 1 cm clearance beyond 0.63 rad and negative at the limit (0.863 rad).
    The spec ignores the pair, so the whole abduction range is free of self-collision."""
    import coal
    import pinocchio as pin

    r = load("go1")
    objs = r.collision_model.geometryObjects
    trunk = next(i for i, o in enumerate(objs) if r.model.frames[o.parentFrame].name == "trunk")
    rotor = next(i for i, o in enumerate(objs) if r.model.frames[o.parentFrame].name == "FL_calf_rotor")
    gd = pin.GeometryData(r.collision_model)
    hip = r.limb("fl").joint_indices[0]

    def at(a):
        q = np.array(r.nominal_q, dtype=float)
        q[hip] = a
        pin.updateGeometryPlacements(r.model, r.data, r.collision_model, gd, q)
        d = coal.distance(objs[trunk].geometry, gd.oMg[trunk], objs[rotor].geometry, gd.oMg[rotor],
                          coal.DistanceRequest(), coal.DistanceResult())
        return q, d

    _, d0 = at(0.0)
    q, d = at(r.upper[hip])
    assert d0 == pytest.approx(0.0376, abs=1e-3) and d < 0
    assert not r.self_collision(q)
    assert not any({"trunk", "FL_calf_rotor"} <= {a.rsplit("_", 1)[0], b.rsplit("_", 1)[0]}
                   for a, b in r.collision_pairs())


# ---------------------------------------------------------------------------------------- planning
RAMP = """\
# a gentle ramp of stepping stones: the stones lie on the plane y = 0, tilted 15 deg from level
# (gravity leans towards the plane), up the ramp is +z; 7 x 9 stones 0.125 m apart
name: stepping-stone-ramp
dim: 3
gravity: [0.0, -9.476, -2.539]
friction: 0.8
holds:
{holds}
surfaces:
  - {{type: plane, point: [0, 0, 0], normal: [0, 1, 0], size: [1.2, 1.4]}}
"""


@pytest.fixture(scope="module")
def ramp(tmp_path_factory) -> Terrain:
    path = tmp_path_factory.mktemp("ramp") / "ramp.yaml"
    path.write_text(ramp_text())
    return Terrain.load(path)


def ramp_text() -> str:
    """The ramp's file: 7 x 9 stepping stones 0.125 m apart (:data:`RAMP`)."""
    rows = [f"  - {{id: s{i}_{j}, position: [{-0.375 + 0.125 * j:.3f}, 0.0, {0.125 * i:.3f}], normal: [0, 1, 0]}}"
            for i in range(9) for j in range(7)]
    return RAMP.format(holds="\n".join(rows))


@pytest.mark.heavy
@pytest.mark.parametrize("name", QUADRUPEDS)
def test_quadruped_start_stance_on_a_ramp(name, ramp):
    """The planner's public API finds a feasible four-foot stance and a three-foot transition from it."""
    from climb_ompl.climb import onestep, start
    from climb_ompl.manifold.stance import make_checks

    r = load(name)
    stance = start.lowest_stance(r, ramp)
    assert len(stance) == 4
    q = start.start_configuration(r, ramp, stance, seed=0)
    assert q is not None
    names = [lb.name for lb in r.limbs]
    assert not r.in_collision(q, ramp, contact_limbs=names)
    for c in make_checks(r, ramp, onestep._stance(stance)):
        assert c(q), c.name
    q1 = onestep.find_transition(r, ramp, stance, seed=1)
    assert q1 is not None
    three = {k: v for k, v in stance.items() if k != names[0]}
    q2 = onestep.find_transition(r, ramp, stance, three, seed=1)
    assert q2 is not None and r.within_limits(q2)


def test_plan_file_robot_rebuilds_from_its_embedded_urdf(tmp_path):
    """A plan embeds the URDF text; rebuilt beside the spec, it is found although the spec names a package."""
    from climb_ompl.verification.climb import robot_from_plan

    r = load("go1")

    urdf = r.urdf_path.read_text().replace("autogenerated", "embedded, autogenerated")

    class _Plan(dict):  # a plan dict, or an object with .robot
        robot = {"name": "go1", "spec": r.spec, "urdf": urdf}

    rebuilt = robot_from_plan(_Plan(robot=_Plan.robot), tmp_path)
    assert rebuilt.urdf_path.is_relative_to(tmp_path.resolve())  # the embedded copy, not the package's file
    assert "embedded, autogenerated" in rebuilt.urdf_path.read_text()
    assert rebuilt.srdf_path == r.srdf_path and rebuilt.collision_pairs() == r.collision_pairs()
    q = r.random_configuration(np.random.default_rng(0))
    assert np.allclose(rebuilt.hand_positions(q), r.hand_positions(q), atol=1e-15)


@pytest.mark.slow
def test_go1_climbs_the_ramp_and_verifies(ramp):
    """A short multi-step climb (plan_climb) on the hand-written ramp, checked by the independent verifier."""
    from climb_ompl import plan_climb, verify
    from climb_ompl.climb.multistep import default_start

    r = load("go1")
    stance, q0 = default_start(r, ramp)
    # goal heights are along minus gravity (0.259 z on this ramp): every foot on the second row or above
    res = plan_climb(r, ramp, stance, goal=0.54, q_start=q0, seed=0, time_limit=120)
    assert res.found, res.reason
    assert verify(res.plan).ok


def _final_holds(plan) -> list[str]:
    """The holds in contact after a plan's last step."""
    last = plan.steps[-1]
    final = dict(last.stance)
    if last.action == "release":
        final.pop(last.limb)
    else:
        final[last.limb] = last.hold
    return list(final.values())


def _slab_climb(robot: RobotModel, wall: Terrain, climb: float):
    """A climb of ``climb`` metres up ``wall``'s slope from the start finder's stance, checked against the heights
    worked out here: on a slab tilted by gravity about ``x``, a metre up the wall plane ``y = 0`` (along ``+z``) is
    ``-g_z / |g|`` metres of height, and a height goal asks every contact hold to be at or above the goal less the
    largest limb reach."""
    from climb_ompl import plan_climb, verify
    from climb_ompl.climb.goal import climb_height
    from climb_ompl.climb.start import find_start

    start = find_start(robot, wall, seed=0)
    assert start.found, start.explain(robot.name, wall.name)
    g = np.asarray(wall.g, dtype=float)
    up = -g / np.linalg.norm(g)
    height = {h.id: float(np.asarray(h.position, dtype=float) @ up) for h in wall.holds}
    rise = climb * float(up[2])  # the wall plane's up-slope direction is +z
    goal = climb_height(robot, wall, start.stance, climb)
    assert goal == pytest.approx(max(height[h] for h in start.stance.values()) + rise
                                 + max(lb.reach for lb in robot.limbs), abs=1e-9)
    res = plan_climb(robot, wall, start.stance, goal=goal, q_start=start.q, seed=0, time_limit=180)
    assert res.found, res.reason
    floor = max(height[h] for h in start.stance.values()) + rise
    assert all(height[h] >= floor - 1e-9 for h in _final_holds(res.plan)), (_final_holds(res.plan), floor)
    assert len(res.plan.steps) >= 8 and verify(res.plan).ok


@pytest.mark.slow
def test_go1_climbs_the_slab_and_verifies():
    """Go1 0.3 m up the bundled slab (leaning back 15 degrees, shelves 0.15 m apart): about 15 s."""
    _slab_climb(load("go1"), Terrain.load("slab"), 0.3)


@pytest.mark.slow
def test_anymal_c_climbs_a_generated_slab_and_verifies():
    """ANYmal C 0.3 m up a generated slab leaning back 30 degrees (a wall it was not tuned on: seed 3, the
    generator's defaults otherwise): about 15 s.  The bundled slab, 15 degrees, is beyond it: at its CoM's
    stand-off a three-foot stance holds only when more than a metre long (README, "Climb suite")."""
    from climb_ompl.model.terrain import generate_wall

    _slab_climb(load("anymal-c"), generate_wall(seed=3, tilt_deg=30.0), 0.3)


@pytest.mark.climb
def test_go1_reaches_along_the_demo_wall():
    """Go1 from its start stance on the (vertical) demo wall to its front-left foot on h44, two holds up: the
    three-foot stances' support regions hold the trunk nearer the wall than its nominal stand-off, where the
    feet reach farther along the wall.  With reach maps probed at the nominal stand-off alone the stance graph
    was exhausted after five stances; the plan must also pass the independent verifier."""
    from climb_ompl import plan_climb, verify
    from climb_ompl.climb.start import find_start
    from climb_ompl.model.terrain import Terrain

    r, wall = load("go1"), Terrain.load("demo-wall")
    start = find_start(r, wall, seed=0)
    assert start.found
    res = plan_climb(r, wall, start.stance, "fl=h44", q_start=start.q, seed=0, time_limit=120)
    assert res.found, res.reason
    assert dict(res.plan.final_stance)["fl"] == "h44"
    assert verify(res.plan).ok


@pytest.mark.climb
def test_a_users_go2_climbs_the_ramp_and_verifies(ramp):
    """Go2, a robot the project does not bundle, from the spec in ``examples/go2.yaml`` (the Go1 template with the
    name, files, mass and knee limit changed): the start finder, a multi-step climb and the independent verifier."""
    from climb_ompl import plan_climb, verify
    from climb_ompl.climb.start import find_start

    r = RobotModel.load(ROOT / "examples" / "go2.yaml")
    assert r.name == "go2" and abs(r.mass - 16.085) < 1e-3
    start = find_start(r, ramp, seed=0)
    assert start.found, start.explain(r.name, ramp.name)
    # every contact on the fifth row (z = 0.5) or above at the end: the hind feet climb from the bottom row
    res = plan_climb(r, ramp, start.stance, goal=0.625, q_start=start.q, seed=0, time_limit=120)
    assert res.found, res.reason
    last = res.plan.steps[-1]
    final = dict(last.stance)
    if last.action == "release":
        final.pop(last.limb)
    else:
        final[last.limb] = last.hold
    assert all(int(h[1:].split("_")[0]) >= 4 for h in final.values()), final
    assert len(res.plan.steps) >= 8 and verify(res.plan).ok
