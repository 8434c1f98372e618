"""meshcat scene builder and playback without a browser: shapes, timelines, plan parsing, HTML export, CLI.

The browser half (the page really shows and animates the robot) is in test_viz_browser.py.
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from browser import make_climb_plan
from hypothesis import given, settings
from hypothesis import strategies as st

from climb_ompl.errors import InputError, PlanFileError
from climb_ompl.model.terrain import Terrain

# ---- import hygiene ---------------------------------------------------------------------------------------


@pytest.mark.heavy
def test_import_climb_ompl_starts_no_server_and_imports_no_meshcat():
    code = (
        "import sys, os, climb_ompl, climb_ompl.cli\n"
        "bad = [m for m in ('meshcat', 'zmq', 'climb_ompl.viz', 'playwright') if m in sys.modules]\n"
        "kids = [p for p in os.listdir('/proc') if p.isdigit() and "
        "open(f'/proc/{p}/stat').read().split(')')[-1].split()[1] == str(os.getpid())]\n"
        "print(bad, kids)\n"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert out.stdout.strip() == "[] []"


# ---- geometry -------------------------------------------------------------------------------------------------
unit = st.lists(st.floats(-1, 1), min_size=3, max_size=3).filter(lambda v: np.linalg.norm(v) > 1e-3)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(unit)
def test_rotation_y_to_maps_y_onto_the_direction(v):
    from climb_ompl.viz._geometry import rotation_y_to

    R = rotation_y_to(v)
    assert np.allclose(R.T @ R, np.eye(3), atol=1e-9) and np.isclose(np.linalg.det(R), 1.0)
    assert np.allclose(R[:, 1], np.asarray(v) / np.linalg.norm(v), atol=1e-9)


@settings(max_examples=40, deadline=None, derandomize=True)
@given(unit, st.floats(0.05, 2.0))
def test_friction_cone_has_half_angle_atan_mu_along_the_normal(n, mu):
    from climb_ompl.viz._geometry import cone_parts

    (part,) = cone_parts([0.1, 0.2, 0.3], n, math.atan(mu), 0.1, 0xFFFFFF, 0.5)
    low = part.geometry.lower({})
    assert low["radiusBottom"] == 0.0  # apex at the hold ...
    assert low["radiusTop"] / low["height"] == pytest.approx(mu)  # ... and tan(half angle) = mu
    nh = np.asarray(n) / np.linalg.norm(n)
    apex = part.transform[:3, 3] - part.transform[:3, 1] * low["height"] / 2
    assert np.allclose(apex, [0.1, 0.2, 0.3]) and np.allclose(part.transform[:3, 1], nh)


def _toy_robot():
    """A real Pinocchio model with every Coal primitive and a mesh: box, cylinder, sphere, capsule, cone, BVH."""
    import coal
    import pinocchio as pin

    urdf = """<robot name="toy">
      <link name="base"><inertial><mass value="1"/><inertia ixx="1e-2" iyy="1e-2" izz="1e-2" ixy="0" ixz="0"
        iyz="0"/></inertial><visual><geometry><box size="0.2 0.1 0.05"/></geometry>
        <material name="r"><color rgba="1 0 0 1"/></material></visual></link>
      <link name="arm"><inertial><mass value="0.5"/><inertia ixx="1e-3" iyy="1e-3" izz="1e-3" ixy="0" ixz="0"
        iyz="0"/></inertial><visual><origin xyz="0.15 0 0" rpy="0 1.5708 0"/><geometry>
        <cylinder radius="0.02" length="0.3"/></geometry></visual>
        <visual><geometry><sphere radius="0.03"/></geometry></visual></link>
      <joint name="slide" type="prismatic"><parent link="world_base"/><child link="base"/><axis xyz="0 0 1"/>
        <limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
      <link name="world_base"/>
      <joint name="j" type="revolute"><parent link="base"/><child link="arm"/><axis xyz="0 0 1"/>
        <limit lower="-3" upper="3" effort="1" velocity="1"/></joint>
    </robot>"""
    model = pin.buildModelFromXML(urdf)
    visual = pin.buildGeomFromUrdfString(model, urdf, pin.VISUAL)
    jid = model.getJointId("j")
    fid = model.getFrameId("arm")
    visual.addGeometryObject(pin.GeometryObject("capsule", jid, fid, pin.SE3(np.eye(3), np.array([0.3, 0, 0])),
                                                coal.Capsule(0.015, 0.05)))
    visual.addGeometryObject(pin.GeometryObject("cone", jid, fid, pin.SE3.Identity(), coal.Cone(0.02, 0.04)))
    mesh = coal.BVHModelOBBRSS()
    mesh.beginModel(2, 4)
    mesh.addVertices(np.array([[0, 0, 0], [0.05, 0, 0], [0, 0.05, 0], [0, 0, 0.05]], dtype=float))
    mesh.addTriangles(np.array([[0, 1, 2], [0, 1, 3]]))
    mesh.endModel()
    visual.addGeometryObject(pin.GeometryObject("tetra/mesh", jid, fid, pin.SE3.Identity(), mesh))

    class Toy:
        name = "toy"
        collision_model = None

    toy = Toy()
    toy.model, toy.visual_model, toy.nominal_q = model, visual, np.array([0.2, 0.5])
    return toy


def test_every_coal_shape_becomes_meshcat_parts():
    from climb_ompl.viz._geometry import geometry_parts

    toy = _toy_robot()
    types = {}
    for g in toy.visual_model.geometryObjects:
        parts = geometry_parts(g)
        types[g.name] = sorted(p.geometry.lower({})["type"] for p in parts)
    assert types["base_0"] == ["BoxGeometry"]
    assert types["arm_0"] == ["CylinderGeometry"]
    assert types["arm_1"] == ["SphereGeometry"]
    assert types["capsule"] == ["CylinderGeometry", "SphereGeometry", "SphereGeometry"]
    assert types["cone"] == ["CylinderGeometry"]
    assert types["tetra/mesh"] == ["BufferGeometry"]
    red = geometry_parts(toy.visual_model.geometryObjects[0])[0].material.color
    assert red == 0xFF0000  # the URDF colour is kept


def _uv_sphere(radius: float, n_lat: int, n_lon: int) -> tuple[np.ndarray, np.ndarray]:
    """A closed UV sphere, triangles wound outwards."""
    verts = [[0.0, 0.0, radius], [0.0, 0.0, -radius]]
    for i in range(1, n_lat):
        th = math.pi * i / n_lat
        verts += [[radius * math.sin(th) * math.cos(2 * math.pi * k / n_lon),
                   radius * math.sin(th) * math.sin(2 * math.pi * k / n_lon), radius * math.cos(th)]
                  for k in range(n_lon)]
    ring = lambda i, k: 2 + (i - 1) * n_lon + k % n_lon  # noqa: E731
    faces = [[0, ring(1, k), ring(1, k + 1)] for k in range(n_lon)]
    faces += [[1, ring(n_lat - 1, k + 1), ring(n_lat - 1, k)] for k in range(n_lon)]
    for i in range(1, n_lat - 1):
        for k in range(n_lon):
            faces += [[ring(i, k), ring(i + 1, k), ring(i + 1, k + 1)],
                      [ring(i, k), ring(i + 1, k + 1), ring(i, k + 1)]]
    return np.array(verts), np.array(faces)


def _volume(v: np.ndarray, f: np.ndarray) -> float:
    return float(np.einsum("ij,ij->i", v[f[:, 0]], np.cross(v[f[:, 1]], v[f[:, 2]])).sum() / 6.0)


def test_simplify_mesh_keeps_a_spheres_shape_within_the_triangle_limit():
    from climb_ompl.viz._geometry import simplify_mesh

    v, f = _uv_sphere(0.1, 120, 160)
    assert len(f) > 30000 and _volume(v, f) == pytest.approx(4 / 3 * math.pi * 0.1 ** 3, rel=2e-3)
    for limit in (500, 2000, 8000):
        nv, nf = simplify_mesh(v, f, limit)
        assert 0.6 * limit <= len(nf) <= limit
        assert nf.min() == 0 and nf.max() == len(nv) - 1  # every vertex kept is used
        r = np.linalg.norm(nv, axis=1)
        assert np.all(np.abs(r - 0.1) < 0.02)  # the merged vertices stay near the surface
        # still closed and wound outwards: the volume of the ball (the oracle), a little less on the chords
        assert _volume(nv, nf) == pytest.approx(4 / 3 * math.pi * 0.1 ** 3, rel=0.06)
    same = simplify_mesh(v, f, len(f))
    assert np.array_equal(same[0], v) and np.array_equal(same[1], f)


@pytest.mark.heavy
def test_a_large_robot_mesh_is_drawn_simplified_from_the_coal_model():
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.viz._geometry import MESH_FILE_BYTES, MESH_TRIANGLES, geometry_parts

    go1 = RobotModel.load("go1")
    trunk = next(g for g in go1.visual_model.geometryObjects if g.name == "trunk_0")
    assert trunk.geometry.num_tris > 300000  # a 29 MB DAE file
    (part,) = geometry_parts(trunk)
    assert part.geometry.lower({})["type"] == "BufferGeometry"
    assert 0.6 * MESH_TRIANGLES <= len(part.geometry.faces) <= MESH_TRIANGLES
    verts = np.asarray(trunk.geometry.vertices())
    lo, hi = verts.min(axis=0), verts.max(axis=0)
    got = np.asarray(part.geometry.vertices, dtype=float)
    assert np.all(got >= lo - 1e-6) and np.all(got <= hi + 1e-6)  # the trunk's box, scale included
    assert np.all(got.max(axis=0) - got.min(axis=0) > 0.9 * (hi - lo))
    camera = next(g for g in go1.visual_model.geometryObjects if g.name == "camera_face_0")
    assert geometry_parts(camera)[0].geometry.lower({})["type"] == "_meshfile"  # small: the file itself
    # few triangles in a large file (DAE text, about 60 bytes a triangle here): the Coal model's arrays, whole
    sonar = next(g for g in go1.visual_model.geometryObjects if g.name == "ultraSound_face_0")
    assert Path(sonar.meshPath).stat().st_size > MESH_FILE_BYTES and sonar.geometry.num_tris < MESH_TRIANGLES
    (part,) = geometry_parts(sonar)
    assert part.geometry.lower({})["type"] == "BufferGeometry" and len(part.geometry.faces) == sonar.geometry.num_tris


def _poses(ps: np.ndarray, rotvecs: np.ndarray) -> np.ndarray:
    from scipy.spatial.transform import Rotation

    T = np.tile(np.eye(4), (len(ps), 1, 1))
    T[:, :3, :3] = Rotation.from_rotvec(rotvecs).as_matrix()
    T[:, :3, 3] = ps
    return T


def test_pose_keys_drop_only_what_interpolation_reproduces():
    from scipy.spatial.transform import Rotation, Slerp

    from climb_ompl.viz._geometry import KEY_ANGLE_TOLERANCE, KEY_POSITION_TOLERANCE, pose_keys

    t = np.linspace(0.0, 3.0, 400)
    # a straight line at constant speed, turning at a constant rate about one axis: two keys reproduce it
    line = _poses(np.outer(t, [0.1, 0.2, -0.05]), np.outer(t, [0.0, 0.0, 0.4]))
    assert pose_keys(t, line) == [0, len(t) - 1]
    # a circle, a wobbling rotation and a pause: every pose, keyed or not, within the tolerances of what
    # scipy's interpolation (the oracle: linear in position, Slerp in orientation) makes of the kept keys
    tt = np.concatenate([t, 3.0 + 0.01 * np.arange(1, 50), 3.5 + t])
    ang = np.concatenate([t, np.full(49, 3.0), 3.0 + np.sin(3 * t)])
    ps = np.stack([0.3 * np.cos(ang), 0.3 * np.sin(ang), 0.05 * ang], axis=1)
    rv = np.stack([0.5 * np.sin(2 * ang), 0.3 * ang, np.zeros_like(ang)], axis=1)
    T = _poses(ps, rv)
    keys = pose_keys(tt, T)
    assert keys[0] == 0 and keys[-1] == len(tt) - 1 and 10 < len(keys) < len(tt) // 2
    pos = np.stack([np.interp(tt, tt[keys], ps[keys, k]) for k in range(3)], axis=1)
    rot = Slerp(tt[keys], Rotation.from_matrix(T[keys, :3, :3]))(tt)
    assert np.max(np.linalg.norm(pos - ps, axis=1)) <= KEY_POSITION_TOLERANCE + 1e-12
    err = (rot.inv() * Rotation.from_matrix(T[:, :3, :3])).magnitude()
    assert np.max(err) <= KEY_ANGLE_TOLERANCE + 1e-9
    tighter = pose_keys(tt, T, position_tol=KEY_POSITION_TOLERANCE / 10)
    assert len(tighter) > len(keys)


def test_robot_drawing_places_geometry_at_pinocchio_world_poses():
    import pinocchio as pin

    from climb_ompl.viz import Scene, open_visualizer

    toy = _toy_robot()
    q = np.array([0.3, 1.0])
    with open_visualizer() as vis:
        drawing = Scene(vis).add_robot(toy, q)
    assert drawing.nodes[-1].endswith("/tetra_mesh")  # '/' in a name must not split the scene path
    data = toy.model.createData()
    gdata = pin.GeometryData(toy.visual_model)
    pin.forwardKinematics(toy.model, data, q)
    pin.updateGeometryPlacements(toy.model, data, toy.visual_model, gdata)
    for i, (node, T) in enumerate(drawing.geometry_placements(q)):
        assert node.startswith("robot/")
        assert np.allclose(T, gdata.oMg[i].homogeneous)
    # the bodies move, each geometry object hangs under its joint's body at its placement in the joint frame
    bodies = dict(drawing.placements(q))
    for i, g in enumerate(toy.visual_model.geometryObjects):
        body = drawing.bodies[g.parentJoint]
        assert drawing.nodes[i].rsplit("/", 1)[0] == body
        assert np.allclose(bodies[body] @ g.placement.homogeneous, gdata.oMg[i].homogeneous)
    assert len(bodies) == len({g.parentJoint for g in toy.visual_model.geometryObjects})
    assert np.allclose(drawing.com(q), pin.centerOfMass(toy.model, toy.model.createData(), q))


def test_support_region_is_drawn_on_the_plane_normal_to_gravity():
    from climb_ompl.equilibrium import Contact, support_region
    from climb_ompl.viz import region_points

    t = Terrain.load("demo-wall")
    contacts = [Contact.from_hold(h) for h in t.holds[:3]]
    g = np.array([0.0, -2.0, -9.6])  # a tilted wall: the plane is not horizontal
    region = support_region(contacts, 7.0, g, cone_edges=8)
    assert not region.is_empty
    pts = region_points(region, g)
    assert np.allclose(pts @ g, 0.0, atol=1e-9)
    assert np.allclose(region.coords(pts), region.vertices, atol=1e-9)  # same polygon, in world coordinates
    assert region.contains(pts.mean(axis=0))


# ---- timeline and plan parsing ------------------------------------------------------------------------------------
def test_timeline_follows_plan_times_pauses_at_stance_changes_and_hits_every_waypoint():
    from climb_ompl.viz._plans import ClimbStep, timeline

    W0 = np.array([[0.0, 0.0], [1.0, 0.0], [1.0, 0.5]])
    W1 = np.array([[1.0, 0.5], [0.0, 0.5]])
    steps = [ClimbStep({"a": "h0"}, W0, np.array([0.0, 2.0, 3.0])), ClimbStep({"a": "h1"}, W1)]
    frames = timeline(steps, max_dq=0.1, pause=0.5, joint_speed=0.5)
    t = np.array([f.t for f in frames])
    assert np.all(np.diff(t) >= 0)
    assert max(np.abs(np.diff([f.q for f in frames], axis=0)).max(axis=1)) <= 0.1 + 1e-12
    marks = {(f.step, f.waypoint): (f.t, f.q) for f in frames if f.waypoint is not None}
    assert marks[(0, 1)][0] == pytest.approx(2.0) and marks[(0, 2)][0] == pytest.approx(3.0)
    assert marks[(1, 0)][0] == pytest.approx(3.5)  # the pause shows the stance change
    assert marks[(1, 1)][0] == pytest.approx(3.5 + 1.0 / 0.5)  # no plan times: max|dq| / joint_speed
    for (k, j), (_, q) in marks.items():
        np.testing.assert_allclose(q, steps[k].waypoints[j], rtol=0.0, atol=1e-12)  # (interpolated to the waypoint)


def test_parse_adds_the_final_stance_and_reads_force_samples():
    from climb_ompl.viz._plans import parse_climb_steps

    plan = make_climb_plan()
    steps = parse_climb_steps(plan, 15)
    assert len(steps) == 3  # two steps + the stance after the final grab
    assert steps[-1].stance == plan["steps"][0]["stance"]
    assert set(steps[0].forces) == {0} and len(steps[0].forces[0]) == 4


@pytest.mark.parametrize("mutate, field", [
    (lambda p: p["steps"][0].update(waypoints=[[0.0, 1.0]]), "steps[0].waypoints"),
    (lambda p: p["steps"][1]["stance"].update(ne="no-such-hold"), "steps[1].stance.ne"),
    (lambda p: p["steps"][0].update(times=[0.0]), "steps[0].times"),
    (lambda p: p["steps"][0].update(forces=[{"waypoint": 9, "forces": {}}]), "steps[0].forces[0].waypoint"),
    (lambda p: p.update(terrain=[1, 2]), "terrain"),
])
def test_malformed_climb_plans_name_the_field(mutate, field):
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.viz import Scene, draw_climb, open_visualizer

    plan = make_climb_plan()
    mutate(plan)
    robot = RobotModel.load("lemur")
    with open_visualizer() as vis, pytest.raises(PlanFileError) as err:
        draw_climb(Scene(vis), plan, robot=robot, source="p.json")
    assert err.value.field == field


def test_scene_items_in_all_accepted_shapes():
    from climb_ompl.viz._plans import normalize_items

    raw = {"path": np.zeros((4, 3)), "surface_points": np.ones((100, 3)), "surface_normals": np.ones((100, 3)),
           "rings": [{"points": np.zeros((5, 3)), "closed": True}],
           "frames": [{"t": 0.0, "body": np.zeros((3, 3)), "front": np.zeros(3), "front_dir": np.array([0, 0, 1.0]),
                       "rear": np.ones(3)},
                      {"t": 0.5, "body": np.ones((4, 3)), "front": np.ones(3), "front_dir": np.array([1.0, 0, 0]),
                       "rear": np.zeros(3)}]}
    items = {it["name"]: it for it in normalize_items(raw)["items"]}
    assert set(items) == {"path", "surface_points", "rings_0", "body", "front", "rear"}
    assert items["path"]["kind"] == "polyline" and items["surface_points"]["kind"] == "points"
    assert items["front"]["kind"] == "cylinder" and len(items["front"]["poses"]) == 2
    assert np.allclose(items["front"]["poses"][1][:3, 2], [1, 0, 0])  # cylinder axis along front_dir
    assert items["rear"]["kind"] == "sphere"
    assert normalize_items(raw)["times"] == [0.0, 0.5]


# ---- HTML export and CLI -------------------------------------------------------------------------------------------
def test_static_html_is_self_contained_and_written_atomically(tmp_path):
    from climb_ompl import viz

    t = Terrain.load("demo-wall")
    out = viz.show(t, _toy_robot(), html=tmp_path / "s.html")
    text = out.read_text()
    assert "new MeshCat.Viewer" in text and "handle_command_bytearray" in text
    assert "http://" not in text.split("<script>")[0] and "src=\"http" not in text  # no external assets
    assert text.count("data:application/octet-binary;base64,") > len(t.holds)  # one command per hold at least
    assert not list(tmp_path.glob(".*.tmp"))
    with pytest.raises(InputError):
        viz.show(t, html=tmp_path / "missing" / "s.html")
    assert not (tmp_path / "missing").exists()


@pytest.mark.heavy
def test_cli_show_play_and_robot_show_write_html(cli, tmp_path):
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps(make_climb_plan()))
    r = cli("show", "--terrain", "demo-wall", "--robot", "lemur", "--html", tmp_path / "wall.html")
    assert r.code == 0, r.err
    r2 = cli("play", plan, "--html", tmp_path / "climb.html", "--speed", "2")
    assert r2.code == 0, r2.err
    r3 = cli("robot", "show", "planar-3limb", "--html", tmp_path / "robot.html", "--collision")
    assert r3.code == 0, r3.err
    for name in ("wall", "climb", "robot"):
        assert (tmp_path / f"{name}.html").stat().st_size > 500_000  # viewer JS + scene


@pytest.mark.parametrize("content, field", [
    ("{not json", "line 1"),
    ('{"schema_version": 1, "kind": "walk", "climb_ompl_version": "0", "seed": 0}', "$.kind"),
])
def test_cli_play_bad_plan_exits_2_and_writes_nothing(cli, tmp_path, content, field):
    plan = tmp_path / "plan.json"
    plan.write_text(content)
    r = cli("play", plan, "--html", tmp_path / "out.html")
    assert r.code == 2
    assert r.err.startswith("error: ") and field in r.err and len(r.err.strip().splitlines()) == 1
    assert not (tmp_path / "out.html").exists()


def test_cli_play_png_time_without_png_is_refused(cli, tmp_path):
    """``--png-time`` without ``--png`` was ignored without a word."""
    plan = tmp_path / "plan.json"
    plan.write_text("{}")
    r = cli("play", plan, "--html", tmp_path / "out.html", "--png-time", "3")
    assert r.code == 2 and "--png-time" in r.err and "--png FILE" in r.err
    assert not (tmp_path / "out.html").exists()


def test_cli_play_png_with_another_suffix_is_refused(cli, tmp_path):
    """``--png y.jpg`` wrote PNG data into a file named .jpg."""
    plan = tmp_path / "plan.json"
    plan.write_text("{}")
    r = cli("play", plan, "--html", tmp_path / "out.html", "--png", tmp_path / "y.jpg")
    assert r.code == 2 and "--png" in r.err and "ending in .png" in r.err
    assert not (tmp_path / "out.html").exists()


def test_playing_a_plan_leaves_no_temporary_folder(cli, tmp_path, monkeypatch):
    """The robot is rebuilt from the URDF the plan embeds, written to a temporary folder: each ``play`` (and
    ``replan``) left one behind (a machine had 786).  The folder goes once the model is built; the model keeps the
    URDF's text."""
    import tempfile

    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps(make_climb_plan()))
    tmp = tmp_path / "tmp"
    tmp.mkdir()
    monkeypatch.setattr(tempfile, "tempdir", str(tmp))
    assert cli("play", plan, "--html", tmp_path / "o.html").code == 0
    assert (tmp_path / "o.html").stat().st_size > 10_000 and list(tmp.iterdir()) == []


def test_cli_bad_speed_and_unknown_terrain_exit_2(cli, tmp_path):
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps(make_climb_plan()))
    for speed in ("0", "inf", "1e-300"):  # an infinite factor made a page whose animation lasted 0 s
        r = cli("play", plan, "--html", tmp_path / "o.html", "--speed", speed)
        assert r.code == 2 and "--speed" in r.err, (speed, r.err)
    assert cli("show", "--terrain", "no-such-wall", "--html", tmp_path / "o.html").code == 2
    assert not (tmp_path / "o.html").exists()


@pytest.mark.heavy
def test_live_play_prints_the_url_and_returns_when_stdin_is_not_a_terminal(tmp_path):
    plan = tmp_path / "plan.json"
    plan.write_text(json.dumps(make_climb_plan()))
    out = subprocess.run([sys.executable, "-m", "climb_ompl", "play", str(plan)], stdin=subprocess.DEVNULL,
                         capture_output=True, text=True, timeout=60)
    assert out.returncode == 0, out.stderr
    assert "meshcat viewer: http://127.0.0.1:" in out.stdout and "not waiting" in out.stdout


@pytest.mark.heavy
def test_treebot_plan_plays(cli, tmp_path):
    pytest.importorskip("climb_ompl.treebot")
    plan = tmp_path / "tb.json"
    r = cli("treebot", "plan", "--tree", "three-branch", "--target", "b3", "--out", plan)
    assert r.code == 0, r.err
    r = cli("play", plan, "--html", tmp_path / "tb.html")
    assert r.code == 0, r.err


def test_collada_meshes_are_embedded_without_their_texture_files():
    """ANYmal's meshes (example-robot-data) name JPEG textures beside them; the page asked for each from the
    folder of the page (about 40 failed requests, each an error in the console).  The image library is dropped;
    the geometry stays."""
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.viz._geometry import _mesh_from_file, without_images

    r = RobotModel.load("anymal-c")
    daes = [g for g in r.visual_model.geometryObjects if str(g.meshPath).endswith(".dae")]
    assert daes, "ANYmal's visual meshes are COLLADA files"
    texts = [open(str(g.meshPath)).read() for g in daes]
    assert any("<library_images>" in t for t in texts)
    for g, t in zip(daes, texts, strict=True):
        mesh = _mesh_from_file(g)
        if mesh is not None:
            assert "<library_images" not in mesh.contents and mesh.contents.count("<triangles") == \
                t.count("<triangles")
    assert without_images("<a><library_images><image id='x'/></library_images><b/></a>") == "<a><b/></a>"


@pytest.mark.heavy
def test_the_wait_for_enter_runs_a_signal_handler_the_main_thread_was_not_woken_for():
    """A signal taken by another thread (or arriving just before the wait began) sets Python's flag without waking the
    main thread: a blocking read (``input()``) then waited for Enter with the handler pending.  The viewer's wait runs
    it within its slice."""
    import signal
    import subprocess
    import sys

    code = ("import signal, threading, time\nfrom climb_ompl.viz._server import _wait_for_enter\n"
            "def stop(signum, frame):\n    raise SystemExit(7)\n"
            "signal.signal(signal.SIGTERM, stop)\n"
            "def other():\n    time.sleep(0.3)\n    signal.pthread_kill(threading.get_ident(), signal.SIGTERM)\n"
            "threading.Thread(target=other, daemon=True).start()\n_wait_for_enter()\n")
    def deliverable() -> None:  # (a runner that blocks SIGTERM passes the mask on)
        signal.pthread_sigmask(signal.SIG_UNBLOCK, [signal.SIGTERM])

    with subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, preexec_fn=deliverable) as proc:
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.communicate()
            pytest.fail("the wait for Enter did not run the pending handler")
        assert proc.returncode == 7, proc.communicate()[1]


@pytest.mark.heavy
@pytest.mark.parametrize("sig", ["SIGTERM", "SIGHUP"])
def test_a_terminated_live_viewer_stops_its_meshcat_server(sig):
    """``timeout``, ``kill`` or a closed terminal ended the process at once and left the meshcat server it had
    started running (holding its port); now the signal exits through Python and the server is stopped."""
    import contextlib
    import os
    import signal
    import subprocess
    import sys
    import time

    # the live viewer waiting for Enter (the signal comes at once, often before the wait starts: a single blocking
    # read or sleep begun after it missed it, 4 times in 30 beside two busy processes); SIGUSR1 makes the child
    # print every thread's stack, what it waits on if it does not exit
    code = ("import faulthandler, signal\nfaulthandler.register(signal.SIGUSR1, all_threads=True)\n"
            "from climb_ompl.viz._server import serve\n"
            "serve(lambda vis: print(vis.window.server_proc.pid, flush=True), wait=True)\n")
    signum = getattr(signal, sig)

    def deliverable() -> None:
        """The runner of this test may block or ignore the signal (a CI harness blocked SIGHUP); both are
        inherited across ``exec``, and the child must receive it as from a terminal."""
        signal.pthread_sigmask(signal.SIG_UNBLOCK, [signum])
        signal.signal(signum, signal.SIG_DFL)

    with subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE,
                          stderr=subprocess.PIPE, text=True, preexec_fn=deliverable) as proc:
        server = int(proc.stdout.readline())
        os.kill(server, 0)  # running
        proc.send_signal(signum)
        try:
            assert proc.wait(timeout=20) == 128 + signum
        except subprocess.TimeoutExpired:
            proc.send_signal(signal.SIGUSR1)
            time.sleep(2)
            proc.kill()
            with contextlib.suppress(ProcessLookupError):
                os.kill(server, signal.SIGKILL)
            pytest.fail(f"the process ignored {sig}; its threads then:\n{proc.communicate()[1]}")
    for _ in range(50):
        try:
            os.kill(server, 0)
        except ProcessLookupError:
            break
        time.sleep(0.1)
    else:
        os.kill(server, signal.SIGKILL)
        pytest.fail("the meshcat server outlived the process that started it")


@pytest.mark.heavy
def test_a_live_viewer_under_nohup_keeps_running_on_sighup():
    """A process started with SIGHUP ignored (``nohup``) must not be ended by the viewer's handler."""
    import os
    import signal
    import subprocess
    import sys

    code = ("from climb_ompl.viz._server import serve\n"
            "serve(lambda vis: print(vis.window.server_proc.pid, flush=True), wait=True)\n")  # waits for Enter

    def nohup() -> None:
        signal.pthread_sigmask(signal.SIG_UNBLOCK, [signal.SIGHUP, signal.SIGTERM])
        signal.signal(signal.SIGHUP, signal.SIG_IGN)
        signal.signal(signal.SIGTERM, signal.SIG_DFL)

    with subprocess.Popen([sys.executable, "-c", code], stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
                          preexec_fn=nohup) as proc:
        server = int(proc.stdout.readline())
        try:
            proc.send_signal(signal.SIGHUP)
            with pytest.raises(subprocess.TimeoutExpired):
                proc.wait(timeout=1.5)
            proc.send_signal(signal.SIGTERM)
            assert proc.wait(timeout=20) == 128 + signal.SIGTERM
        finally:
            if proc.poll() is None:
                proc.kill()
                os.kill(server, signal.SIGKILL)
