"""Terrains written in another frame (a slab tilted in its geometry, a wall facing +x, a ramp with gravity straight
down) are turned into the wall frame the robot specs expect.  The oracle is the bundled terrain itself: turn it,
gravity and all, by a rigid motion (statics cannot tell), and the wall frame must give it back, up to a shift
along the wall."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest
import yaml
from test_cli_terrain import _slab_yaml

from climb_ompl.errors import TerrainError
from climb_ompl.model.terrain import Terrain
from climb_ompl.model.wall_frame import to_wall_frame, wall_motion
from climb_ompl.plan.events import TerrainChange


def _rot(axis: list[float], deg: float) -> np.ndarray:
    a = np.asarray(axis, dtype=float) / np.linalg.norm(axis)
    k = np.array([[0, -a[2], a[1]], [a[2], 0, -a[0]], [-a[1], a[0], 0]])
    t = np.radians(deg)
    return np.eye(3) + np.sin(t) * k + (1 - np.cos(t)) * k @ k


def _moved(terrain: Terrain, rot: np.ndarray, t: np.ndarray) -> Terrain:
    """``terrain`` under the rigid motion ``p -> rot p + t``, gravity included, as a user's file would give it."""
    d = terrain.to_dict()
    for h in d["holds"]:
        h["position"] = (rot @ np.array(h["position"]) + t).tolist()
        h["normal"] = (rot @ np.array(h["normal"])).tolist()
    for s in d["surfaces"]:
        s["point"] = (rot @ np.array(s["point"]) + t).tolist()
        s["normal"] = (rot @ np.array(s["normal"])).tolist()
    d["gravity"] = (rot @ np.array(d["gravity"])).tolist()
    return Terrain.from_dict(d, source="moved.yaml")


def _gravity_down(terrain: Terrain, turn_deg: float) -> np.ndarray:
    """A rotation making ``terrain``'s gravity straight down, then turning it ``turn_deg`` about the vertical."""
    g = terrain.g / np.linalg.norm(terrain.g)
    axis = np.cross(g, [0.0, 0.0, -1.0])
    tilt = np.degrees(np.arccos(np.clip(g @ [0.0, 0.0, -1.0], -1, 1)))
    return _rot([0, 0, 1], turn_deg) @ (_rot(axis, tilt) if tilt > 1e-9 else np.eye(3))


@pytest.mark.parametrize("name, turn", [("slab", 37.0), ("overhang", -120.0), ("stepping-stone-ramp-3m", 90.0),
                                        ("demo-wall", 90.0)])
def test_a_terrain_moved_rigidly_comes_back_to_the_bundled_one(name: str, turn: float) -> None:
    """The slab, the overhang and the ramp with gravity straight down (tilted in their geometry, turned about the
    vertical, shifted), and the demo wall facing another way: the wall frame gives back the bundled terrain's
    normals and gravity exactly, its positions up to one shift along the wall, and the moved file's heights."""
    ref = Terrain.load(name)
    moved = _moved(ref, _gravity_down(ref, turn), np.array([0.7, -1.3, 0.4]))
    assert moved.convention_notes()  # the moved file departs from the convention, and says so
    back, note = to_wall_frame(moved)
    assert "turned into the wall frame" in note and back.convention_notes() == []
    assert np.allclose(back.g, ref.g, atol=1e-9)
    assert np.allclose([h.normal for h in back.holds], [h.normal for h in ref.holds], atol=1e-9)
    shift = back.positions - ref.positions
    assert np.allclose(shift, shift[0], atol=1e-9) and abs(shift[0][1]) < 1e-9  # along the wall only
    assert np.allclose([back.height(h.id) for h in ref.holds], [moved.height(h.id) for h in ref.holds], atol=1e-9)
    # the recorded frame takes the file's coordinates to the turned ones
    rot, t = np.asarray(back.frame)[:, :3], np.asarray(back.frame)[:, 3]
    assert np.allclose(moved.positions @ rot.T + t, back.positions, atol=1e-9)


def test_a_terrain_in_the_convention_is_left_alone() -> None:
    for name in ("demo-wall", "slab", "overhang", "stepping-stone-ramp-3m", "planar-wall"):
        t = Terrain.load(name)
        assert wall_motion(t) is None and t.in_wall_frame() is t and to_wall_frame(t)[1] == ""
        assert "frame" not in t.to_dict()  # the bundled terrains' content hashes are unchanged


def test_a_wall_off_y_0_is_only_shifted() -> None:
    ref = Terrain.load("demo-wall")
    moved = _moved(ref, np.eye(3), np.array([0.0, 0.8, 0.0]))
    back, note = to_wall_frame(moved)
    assert "the terrain was moved 0.80 m" in note and "turned by" not in note
    assert np.allclose(back.positions, ref.positions, atol=1e-12)


def test_the_frame_round_trips_and_is_validated(tmp_path: Path) -> None:
    moved = _moved(Terrain.load("slab"), _rot([1, 2, 3], 50), np.array([0.1, 0.2, 0.3]))
    back = moved.in_wall_frame()
    again = Terrain.from_dict(json.loads(json.dumps(back.to_dict())))
    assert again == back and again.content_hash() == back.content_hash() != moved.content_hash()
    d = back.to_dict()
    d["frame"]["rotation"][0] = [2.0, 0.0, 0.0]
    with pytest.raises(TerrainError, match=r"frame\.rotation: not a rotation"):
        Terrain.from_dict(d, source="f.yaml")
    d["frame"] = {"rotation": np.eye(3).tolist()}
    with pytest.raises(TerrainError, match=r"frame\.translation: missing required field"):
        Terrain.from_dict(d, source="f.yaml")
    flat = {**Terrain.load("pegs").to_dict(), "frame": {"rotation": np.eye(3).tolist(), "translation": [0, 0, 0]}}
    with pytest.raises(TerrainError, match=r"f\.yaml: frame: only a 3-D terrain"):
        Terrain.from_dict(flat, source="f.yaml")


def test_a_box_that_would_turn_off_axis_keeps_the_terrain_and_says_why() -> None:
    d = _moved(Terrain.load("slab"), _rot([1, 0, 0], 20), np.zeros(3)).to_dict()
    d["surfaces"].append({"type": "box", "center": [0, 0.3, 0.2], "size": [0.2, 0.2, 0.2]})
    t = Terrain.from_dict(d)
    same, note = to_wall_frame(t)
    assert same is t and "box surfaces cannot be turned" in note
    # a quarter turn about the vertical keeps boxes axis-aligned: the box turns with the wall
    d = _moved(Terrain.load("demo-wall"), _rot([0, 0, 1], 90), np.zeros(3)).to_dict()
    d["surfaces"].append({"type": "box", "center": [0.5, 0.2, 1.0], "size": [0.1, 0.2, 0.3]})
    back = to_wall_frame(Terrain.from_dict(d))[0]
    box = [s for s in back.surfaces if s.type == "box"][0]
    rot, t = np.asarray(back.frame)[:, :3], np.asarray(back.frame)[:, 3]
    assert np.allclose(rot, _rot([0, 0, 1], -90), atol=1e-12)
    assert np.allclose(box.size, [0.2, 0.1, 0.3]) and np.allclose(box.center, [0.2, -0.5, 1.0] + t, atol=1e-12)


def test_a_change_to_a_turned_terrain_is_written_in_the_files_coordinates() -> None:
    """A hold moved or added in the file's coordinates lands where the turned terrain's recorded frame takes
    those coordinates; the rest of the turned terrain is unchanged."""
    moved = _moved(Terrain.load("demo-wall"), _rot([1, 1, 0], 35), np.array([0.2, 0.0, -0.5]))
    turned = moved.in_wall_frame()
    rot, t = np.asarray(turned.frame)[:, :3], np.asarray(turned.frame)[:, 3]
    p = np.asarray(moved.hold("h40").position) + [0.03, -0.02, 0.01]
    new = {"id": "extra", "position": (np.asarray(moved.hold("h41").position) + 0.05).tolist(),
           "normal": list(moved.hold("h41").normal), "friction": 0.9}
    changed = TerrainChange(move={"h40": tuple(p)}, add=(new,)).apply(turned)
    assert np.allclose(changed.hold("h40").position, rot @ p + t, atol=1e-9)
    assert np.allclose(changed.hold("extra").position, rot @ np.asarray(new["position"]) + t, atol=1e-9)
    assert np.allclose(changed.hold("extra").normal, rot @ np.asarray(new["normal"]), atol=1e-9)
    assert changed.hold("h41") == turned.hold("h41") and changed.frame == turned.frame


@pytest.mark.climb
def test_plan_climbs_a_slab_tilted_in_its_geometry(cli, tmp_path: Path) -> None:
    """A user's 30-degree slab written with its holds tilted and gravity straight down (it found no start before:
    the robot specs expect the wall y = 0) is planned in the wall frame, and the plan verifies against the
    user's own file."""
    conv = Terrain.from_dict(yaml.safe_load(_slab_yaml(False)))
    user = _moved(conv, _gravity_down(conv, 0.0), np.zeros(3))
    tilted = tmp_path / "tilted.yaml"
    tilted.write_text(yaml.safe_dump(user.to_dict()))
    assert np.allclose(user.g, [0.0, 0.0, -9.81], atol=1e-4) and user.convention_notes()
    out = tmp_path / "p.json"
    r = cli("plan", "--robot", "lemur", "--terrain", tilted, "--climb", "0.2", "--seed", "0", "--out", out)
    assert r.code == 0, r.err
    assert "turned into the wall frame" in r.err and "turned by 30 deg" in r.err and "deg from +y" not in r.err
    plan = json.loads(out.read_text())
    assert np.allclose(np.asarray(plan["terrain"]["data"]["frame"]["rotation"]), _rot([1, 0, 0], -30), atol=1e-4)
    r = cli("verify", out, "--terrain", tilted)
    assert r.code == 0 and "valid" in r.out


def test_a_level_floor_faces_up_not_down() -> None:
    """Stepping stones on level ground (normals +z, gravity -z): the plane through them faces +z whichever sign
    the fit gives, so the wall frame puts gravity into the wall (a floor), not out of it (a ceiling)."""
    from climb_ompl.model.wall_frame import wall_normal

    holds = [{"id": f"s{i}_{j}", "position": [0.2 * i, 0.2 * j, 0.1], "normal": [0, 0, 1]}
             for i in range(5) for j in range(6)]
    floor = Terrain.from_dict({"name": "floor", "holds": holds})
    assert np.allclose(wall_normal(floor), [0, 0, 1])
    assert np.allclose(floor.in_wall_frame().g, [0, -9.81, 0])
    # a climb of M metres means nothing on level ground: said, instead of a goal the start already meets
    from climb_ompl.climb.goal import climb_height
    from climb_ompl.errors import QueryError
    from climb_ompl.model.robot import RobotModel

    with pytest.raises(QueryError, match="rises 0 m per metre along its wall .* give a goal hold"):
        climb_height(RobotModel.load("lemur"), floor.in_wall_frame(), {"nw": "s0_0"}, 0.4)


def test_verify_applies_the_plans_own_frame_to_the_users_file() -> None:
    """``verify PLAN --terrain FILE`` moves the file by the frame the plan records, not by the one the wall frame
    would pick today: a plan made before a change of that choice still matches its file."""
    from climb_ompl.cli.plan import _in_plan_frame

    user = _moved(Terrain.load("slab"), _gravity_down(Terrain.load("slab"), 20.0), np.array([0.4, 0.1, 0.0]))
    rot, t = np.asarray(user.in_wall_frame().frame)[:, :3], np.asarray(user.in_wall_frame().frame)[:, 3]
    embedded = user.moved(rot, t + [0.37, 0.0, 0.0])  # another shift along the wall than today's
    data = json.loads(json.dumps(embedded.to_dict()))  # as the plan file holds it
    assert _in_plan_frame(user, data) == embedded.content_hash() != user.in_wall_frame().content_hash()
    assert _in_plan_frame(user, Terrain.load("slab").to_dict()) is None  # no frame recorded


def test_notes_on_a_turned_terrain_speak_in_the_files_coordinates_and_a_flipped_plane_is_refused() -> None:
    user = _moved(Terrain.load("demo-wall"), _rot([0, 0, 1], 90), np.zeros(3))  # the wall faces -x
    d = user.to_dict()
    d["holds"][3]["normal"] = [-x for x in d["holds"][3]["normal"]]  # one hold's normal into the wall
    one = Terrain.from_dict(d).in_wall_frame()
    n = np.asarray(d["holds"][3]["normal"]) / np.linalg.norm(d["holds"][3]["normal"])
    assert f"h3 ({n[0]:.3g}, {n[1]:.3g}, {n[2]:.3g})" in " ".join(one.convention_notes())  # not the turned normal
    d = user.to_dict()
    d["surfaces"][0]["normal"] = [-x for x in d["surfaces"][0]["normal"]]  # the plane flipped: every hold "into"
    with pytest.raises(TerrainError, match=r"w\.yaml: surfaces\[0\]\.normal: the wall plane's normal and the "
                                           r"normals of 180 of 180 holds point opposite ways"):
        Terrain.from_dict(d, source="w.yaml")


def test_a_gentle_ramp_is_not_sent_far_up_its_slope_to_keep_heights() -> None:
    """Stones 0.3 m above the origin of a 3-degree ramp (gravity straight down): keeping their heights once the
    ramp's plane is at y = 0 would put them 5.7 m up the slope, beyond the robots' base bounds.  The shift along
    the slope is capped (KEEP_HEIGHTS) and the note gives the change of height instead."""
    from climb_ompl.model.wall_frame import KEEP_HEIGHTS

    a = np.radians(3.0)
    holds = [{"id": f"s{i}_{j}", "position": [0.15 * i, 0.15 * j * np.cos(a), 0.3 + 0.15 * j * np.sin(a)],
              "normal": [0.0, -np.sin(a), np.cos(a)]} for i in range(5) for j in range(10)]
    ramp = Terrain.from_dict({"name": "ramp3", "holds": holds})
    turned, note = to_wall_frame(ramp)
    assert np.max(np.abs(turned.positions[:, 2])) < 1.5 + KEEP_HEIGHTS
    rise = turned.height("s0_0") - ramp.height("s0_0")
    assert abs(rise) > 0.2 and f"heights along minus gravity {rise:+.3f} m" in note


def test_bench_replan_moves_a_hold_of_a_turned_terrain_by_its_3_cm() -> None:
    """``bench replan --change move`` writes the moved hold in the file's coordinates, as ``TerrainChange.apply``
    reads them: on a wall turned a quarter turn the hold moves 3 cm (it moved 1.16 m when the turned coordinates
    were turned again)."""
    from climb_ompl.bench.replan import MOVE, failure

    turned = _moved(Terrain.load("demo-wall"), _rot([0, 0, 1], 90), np.zeros(3)).in_wall_frame()
    change = failure(turned, "h40", "move", np.random.default_rng(0))
    d = np.asarray(change.apply(turned).hold("h40").position) - np.asarray(turned.hold("h40").position)
    assert np.isclose(np.linalg.norm(d), MOVE, atol=1e-9) and abs(float(d @ turned.hold("h40").n)) < 1e-9


def test_a_wall_far_below_the_origin_names_the_base_bounds() -> None:
    """The demo wall 3.2 m lower, in the convention (so not moved): LEMUR's base moves only down to z = -0.5 (its
    URDF), which the start finder's diagnosis now names, rather than only hands 2 m from their holds."""
    from climb_ompl.climb.start import find_start
    from climb_ompl.model.robot import RobotModel

    low = _moved(Terrain.load("demo-wall"), np.eye(3), np.array([0.0, 0.0, -3.2]))
    assert low.in_wall_frame() is low
    found = find_start(RobotModel.load("lemur"), low, seed=0)
    assert not found.found
    assert "base bounds: the base cannot get to these holds: base_z = -2.8" in found.explain("lemur", "low")
    assert "outside [-0.5, 3.5]" in found.explain("lemur", "low")


def test_a_turned_plane_keeps_its_extent():
    """A plane's ``size`` is its width and height along :func:`plane_axes`; turned into the wall frame, the
    rectangle it spans is the file's rectangle turned (the hand-written 20-degree ramp: 0.6 m up the slope, 2.4 m
    across it, drawn so in playback too)."""
    from conftest import DATA

    from climb_ompl.model.terrain import Terrain, plane_axes
    from climb_ompl.model.wall_frame import frame_of, to_wall_frame

    def corners(s):
        R = plane_axes(s.normal)
        c = np.asarray(s.center, dtype=float)
        return np.array(sorted(tuple(np.round(c + a * s.size[0] / 2 * R[:, 0] + b * s.size[1] / 2 * R[:, 1], 6))
                               for a in (-1, 1) for b in (-1, 1)))

    file = Terrain.load(DATA / "ramp20.yaml")
    wall, _ = to_wall_frame(file)
    rot, t = frame_of(wall)
    assert not np.allclose(rot, np.eye(3))
    turned = np.array(sorted(tuple(np.round(rot @ p + t, 6)) for p in corners(file.surfaces[0])))
    np.testing.assert_allclose(corners(wall.surfaces[0]), turned, atol=1e-5)
