"""Terrain model and YAML format: validation errors naming the field, round trip, content hash, generator."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
import yaml
from conftest import DATA, ROOT, run_subprocess
from hypothesis import given, settings
from hypothesis import strategies as st

from climb_ompl.errors import ClimbError, InputError, TerrainError
from climb_ompl.model.terrain import Hold, Terrain, bundled_terrains, generate_wall, stored_unit

BAD = sorted((DATA / "bad").glob("*.yaml"))


def expected_field(path: Path) -> str:
    """The field a bad file must be rejected for, from its first line ``# expect: FIELD``."""
    first = path.read_text().splitlines()[0]
    assert first.startswith("# expect: "), f"{path} must start with '# expect: FIELD'"
    return first.removeprefix("# expect: ").strip()


SMALL_2D = {
    "name": "small",
    "dim": 2,
    "gravity": [0.0, -9.81],
    "holds": [
        {"id": "a", "position": [0.0, 1.0], "normal": [0.0, 1.0], "friction": 0.8},
        {"id": "b", "position": [0.3, 1.2], "normal": [-0.5, 0.5]},
        {"id": "c", "position": [0.6, 1.0], "normal": [0.0, 1.0], "type": "grasp", "max_force": 40},
    ],
    "surfaces": [{"type": "circle", "center": [0.3, 0.8], "radius": 0.1},
                 {"type": "plane", "point": [0.0, 0.0], "normal": [0.0, 1.0], "size": [3.0]}],
}

#: content_hash() of SMALL_2D. A change means every plan file's terrain hash changes (bump the plan schema).
PINNED_HASH = "f8eac7746449c296d547846a59f7b260c2c4e2c734c3737354fa09c1b060eccf"


def test_corpus_is_large_enough() -> None:
    assert len(BAD) >= 10


@pytest.mark.parametrize("path", BAD, ids=lambda p: p.stem)
def test_bad_file_raises_terrain_error_naming_field(path: Path) -> None:
    with pytest.raises(TerrainError) as info:
        Terrain.load(path)
    err = info.value
    assert isinstance(err, ClimbError) and isinstance(err, InputError)
    assert err.field == expected_field(path)
    assert Path(err.path) == path
    assert err.reason and str(path) in str(err) and err.field in str(err)


def test_missing_file_and_unknown_name() -> None:
    with pytest.raises(TerrainError) as info:
        Terrain.load("no-such-terrain")
    assert "bundled" in info.value.reason and "demo-wall" in info.value.reason


def test_from_dict_2d_vectors_become_xz() -> None:
    t = Terrain.from_dict(SMALL_2D)
    assert t.dim == 2 and t.g.tolist() == [0.0, 0.0, -9.81]
    b = t.hold("b")
    assert b.position == (0.3, 0.0, 1.2)
    assert b.normal == pytest.approx((-math.sqrt(0.5), 0.0, math.sqrt(0.5)))
    assert b.friction == 1.0  # the file's default
    assert t.hold("c").type == "grasp" and t.hold("c").max_force == 40.0
    assert t.positions.shape == (3, 3)
    assert t.up.tolist() == [0.0, 0.0, 1.0]
    assert t.surfaces[0].center == (0.3, 0.0, 0.8) and t.surfaces[1].normal == (0.0, 0.0, 1.0)
    with pytest.raises(TerrainError, match="no hold 'zz'"):
        t.hold("zz")


def test_round_trip_yaml_and_load(tmp_path: Path) -> None:
    for t in [Terrain.from_dict(SMALL_2D), generate_wall(5, height=1.0), *map(Terrain.load, bundled_terrains())]:
        f = tmp_path / f"{t.name}.yaml"
        f.write_text(t.to_yaml())
        back = Terrain.load(f)
        assert back == t
        assert back.content_hash() == t.content_hash()
        assert back.to_yaml() == t.to_yaml()  # a fixed point after one write


def test_content_hash_is_pinned_and_sensitive() -> None:
    t = Terrain.from_dict(SMALL_2D)
    assert t.content_hash() == PINNED_HASH
    moved = dict(SMALL_2D, holds=[dict(SMALL_2D["holds"][0], position=[0.0, 1.001]), *SMALL_2D["holds"][1:]])
    assert Terrain.from_dict(moved).content_hash() != t.content_hash()
    # Description and source are metadata, not content.
    described = Terrain.from_dict(dict(SMALL_2D, description="hello"), source="elsewhere.yaml")
    assert described.content_hash() == t.content_hash() and described == t



def test_hold_validates_and_normalises() -> None:
    h = Hold("x", np.array([1, 2, 3]), (0, 0, 2), 0.5)
    assert h.position == (1.0, 2.0, 3.0) and h.normal == (0.0, 0.0, 1.0)
    assert isinstance(h.position[0], float)
    assert hash(h) == hash(Hold("x", (1.0, 2.0, 3.0), (0.0, 0.0, 1.0), 0.5))
    for kwargs, fld in [
        (dict(normal=(0, 0, 0)), "normal"),
        (dict(friction=-0.1), "friction"),
        (dict(friction=float("nan")), "friction"),
        (dict(type="magnet"), "type"),
        (dict(type="adhesion"), "max_force"),
        (dict(max_force=0.0), "max_force"),
        (dict(max_force=50.0), "max_force"),  # on a friction hold it would be ignored: refused
        (dict(type="grasp", max_force=0.0), "max_force"),
        (dict(position=(1, 2)), "position"),
    ]:
        args = dict(id="x", position=(0, 0, 0), normal=(0, 1, 0)) | kwargs
        with pytest.raises(TerrainError) as info:
            Hold(**args)  # type: ignore[arg-type]
        assert info.value.field == fld


def test_terrain_constructor_checks() -> None:
    h = Hold("a", (0, 0, 1), (0, 1, 0))
    with pytest.raises(TerrainError, match="duplicate"):
        Terrain("t", 3, (0, 0, -9.81), (h, h))
    with pytest.raises(TerrainError, match="x-z plane"):
        Terrain("t", 2, (0, 0, -9.81), (h,))  # normal along y in a 2-D terrain
    with pytest.raises(TerrainError) as info:
        Terrain("t", 3, (0, 0, 0), (h,))
    assert info.value.field == "gravity"


# ---- generator ------------------------------------------------------------------------------------
def test_generator_same_seed_same_wall_other_seed_other_wall() -> None:
    a, b, c = generate_wall(7), generate_wall(7), generate_wall(8)
    assert a == b and a.to_yaml() == b.to_yaml() and a.content_hash() == b.content_hash()
    assert a != c and a.content_hash() != c.content_hash()


def test_generator_parameters_are_honoured() -> None:
    t = generate_wall(1, width=1.0, height=2.6, spacing=0.2, friction=(0.5, 0.6), tilt_deg=20.0,
                      normal_up_deg=(40.0, 50.0), normal_side_deg=0.0)
    p = t.positions
    assert t.dim == 3 and np.all(p[:, 1] == 0.0)
    assert p[:, 2].max() - p[:, 2].min() > 2.4 and p[:, 0].max() - p[:, 0].min() > 0.8
    assert len(t.holds) == 6 * 14
    mus = np.array([h.friction for h in t.holds])
    assert mus.min() >= 0.5 and mus.max() <= 0.6
    ups = np.degrees(np.arcsin([h.normal[2] for h in t.holds]))
    assert ups.min() >= 40 - 1e-6 and ups.max() <= 50 + 1e-6
    assert np.allclose([h.normal[0] for h in t.holds], 0.0)
    # slab: gravity leans into the wall (-y), 20 degrees from vertical
    assert t.g[1] < 0 and math.degrees(math.atan2(-t.g[1], -t.g[2])) == pytest.approx(20.0)
    assert np.linalg.norm(t.g) == pytest.approx(9.81)


@pytest.mark.parametrize("kwargs, fld", [
    (dict(seed=-1), "generator.seed"),
    (dict(spacing=0.0), "generator.spacing"),
    (dict(friction=(0.9, 0.2)), "generator.friction"),
    (dict(tilt_deg=95.0), "generator.tilt_deg"),
    (dict(jitter=0.7), "generator.jitter"),
    (dict(normal_up_deg=(50.0, 40.0)), "generator.normal_up_deg"),
])
def test_generator_rejects_bad_parameters(kwargs: dict, fld: str) -> None:
    with pytest.raises(TerrainError) as info:
        generate_wall(**kwargs)
    assert info.value.field == fld


def test_generator_stores_rounded_numbers_and_unit_normals() -> None:
    """What a generated wall stores is rounded (positions to 1e-4 m, friction to 1e-3, normals through
    :func:`stored_unit`), so its file does not depend on last-bit differences of the maths library between machines:
    a normal computed one bit off in any component is stored the same.  Each normal is unit length to 1e-15 (kept
    as written on load) and leans up by the drawn angle; the file reads back to the same terrain."""
    t = generate_wall(3, height=1.5, normal_up_deg=(35.0, 65.0))
    for h in t.holds:
        assert all(round(c, 4) == c for c in h.position), h
        assert round(h.friction, 3) == h.friction
        assert abs(math.sqrt(math.fsum(c * c for c in h.normal)) - 1.0) <= 1e-15
        assert 35.0 - 1e-6 <= math.degrees(math.asin(h.normal[2])) <= 65.0 + 1e-6
    back = Terrain.from_dict(yaml.safe_load(t.to_yaml()))
    assert back.holds == t.holds and back.content_hash() == t.content_hash()
    rng = np.random.default_rng(0)
    for v in rng.normal(size=(500, 3)):
        v = v / np.linalg.norm(v)
        want = stored_unit(v)
        for sign in (1.0, -1.0):  # every component one unit in the last place off, either way
            off = [math.nextafter(float(c), sign * math.inf) for c in v]
            assert stored_unit(off) == want, (v, off)
        assert np.allclose(want, v, rtol=0.0, atol=1e-10)


@pytest.mark.heavy
def test_generator_identical_across_processes_and_hash_seeds() -> None:
    code = "from climb_ompl.model.terrain import generate_wall; print(generate_wall(11, height=1.2).to_yaml(), end='')"
    outs = [run_subprocess(["-c", code], env={"PYTHONHASHSEED": s}) for s in ("1", "2")]
    for o in outs:
        assert o.returncode == 0, o.stderr
    assert outs[0].stdout == outs[1].stdout == generate_wall(11, height=1.2).to_yaml()


# ---- properties -----------------------------------------------------------------------------------
finite = st.floats(-5, 5, allow_nan=False, allow_infinity=False)
nonzero_vec = st.lists(finite, min_size=3, max_size=3).filter(lambda v: np.linalg.norm(v) > 1e-3)


@settings(derandomize=True, deadline=None, max_examples=60)
@given(st.lists(st.tuples(st.lists(finite, min_size=3, max_size=3), nonzero_vec, st.floats(0, 3)),
                min_size=1, max_size=8))
def test_any_valid_terrain_round_trips(holds: list) -> None:
    d = {"name": "p", "dim": 3, "holds": [
        {"id": f"h{i}", "position": p, "normal": n, "friction": mu} for i, (p, n, mu) in enumerate(holds)]}
    t = Terrain.from_dict(d)
    for h in t.holds:
        assert abs(np.linalg.norm(h.n) - 1.0) < 1e-9
    back = Terrain.from_dict(yaml.safe_load(t.to_yaml()))
    assert back == t and back.content_hash() == t.content_hash()


def test_a_bad_hold_is_named_by_its_id_too(tmp_path: Path) -> None:
    """A long hand-written file: the hold's place in the list and its id, so that a user finds it."""
    d = {"name": "t", "dim": 3, "gravity": [0, 0, -9.81],
         "holds": [{"id": "a", "position": [0, 0, 0], "normal": [0, 1, 0]},
                   {"id": "t1_0", "position": [0, 0, 1], "normal": [0, 1, 0], "friction": -0.3}]}
    with pytest.raises(TerrainError) as info:
        Terrain.from_dict(d, source="wall.yaml")
    assert info.value.field == "holds[1].friction"
    assert str(info.value) == "wall.yaml: holds[1].friction: must be >= 0, got -0.3 (hold 't1_0')"


@pytest.mark.parametrize("gravity, normal, noted", [
    ([0, 0, 9.81], [0, 0, 1], True),     # a ramp of level stones, gravity's sign typed wrong
    ([0, 0, -9.81], [0, 0, 1], False),   # the same ramp as meant
    ([0, 0, 9.81], [0, 0, -1], False),   # a ceiling written upside down: the holds face the robot below
    ([0, -9.81, 3], [0, 1, 0], False),   # a wall whose gravity leans a little up the file's z: not "up"
])
def test_gravity_pointing_up_at_holds_facing_down_is_noted(gravity, normal, noted, cli, tmp_path):
    """Gravity along +z with most holds facing down along it (the robot would hang from a ceiling): noted by
    ``terrain validate`` (exit 0: such a terrain is valid); the other cases are not."""
    import yaml

    from climb_ompl.model.terrain import Terrain

    d = {"name": "r", "dim": 3, "gravity": gravity, "friction": 0.8,
         "holds": [{"id": f"h{i}", "position": [0.2 * i, 0.0, 0.1 * i], "normal": normal} for i in range(6)]}
    assert (Terrain.from_dict(d).gravity_note() is not None) == noted
    path = tmp_path / "r.yaml"
    path.write_text(yaml.safe_dump(d))
    r = cli("terrain", "validate", path)
    said = "gravity: (0, 0, 9.81) points along +z, and 6 of 6 hold normals face down"
    assert r.code == 0 and (said in r.err) == noted


def test_a_turned_terrain_gets_the_gravity_note_of_its_file():
    """A ramp of level stones with gravity's sign flipped, turned into the wall frame (as plan and replan load it):
    its note is judged in the file's coordinates through the recorded frame, the same as the file's own."""
    from climb_ompl.model.terrain import Terrain

    d = {"name": "r", "dim": 3, "gravity": [0, 0, 9.81], "friction": 0.8,
         "holds": [{"id": f"h{i}_{j}", "position": [0.2 * i, 0.2 * j, 0.05 * i], "normal": [0, 0, 1]}
                   for i in range(4) for j in range(4)]}
    t = Terrain.from_dict(d)
    turned = t.in_wall_frame()
    assert turned.frame is not None and t.gravity_note() is not None
    assert turned.gravity_note() == t.gravity_note()
    assert turned.gravity_note() in turned.convention_notes()


def test_gravity_pointing_up_in_a_2d_file_is_noted_in_its_own_axes():
    """A 2-D file writes [x, z]: the note shows the file's two numbers and the file's axis."""
    from climb_ompl.model.terrain import Terrain

    d = {"name": "p", "dim": 2, "gravity": [0, 9.81],
         "holds": [{"id": f"h{i}", "position": [0.2 * i, 0.1 * i], "normal": [0, 1]} for i in range(4)]}
    note = Terrain.from_dict(d).gravity_note()
    assert note.startswith("gravity: (0, 9.81) points along +z, and 4 of 4") and "(0, -9.81)" in note


def test_plan_without_a_start_on_a_gravity_pointing_up_says_so_first(tmp_path, cli):
    """The demo wall's holds with gravity's sign flipped: ``plan`` finds no start, and its answer starts with the
    gravity (it advised leaning the holds further up)."""
    import yaml

    d = yaml.safe_load((ROOT / "climb_ompl/terrains/demo-wall.yaml").read_text())
    d["gravity"] = [0.0, 0.0, 9.81]
    path = tmp_path / "up.yaml"
    path.write_text(yaml.safe_dump(d))
    r = cli("plan", "--robot", "lemur", "--terrain", path, "--climb", "1", "--out", tmp_path / "p.json")
    assert r.code == 1 and not (tmp_path / "p.json").exists()
    assert r.err.split("error: ", 1)[1].startswith(f"{path}: gravity: (0, 0, 9.81) points along +z"), r.err


def test_friction_written_as_a_percentage_is_noted():
    """Friction 80 (a percentage) loads (a valid, very sticky terrain), but its notes say so; the bundled
    terrains' frictions (at most 1.2) get no such note."""
    from climb_ompl.model.terrain import Terrain, bundled_terrains

    d = {"name": "w", "dim": 3, "gravity": [0, 0, -9.81], "friction": 80,
         "holds": [{"id": f"h{i}", "position": [0.2 * i, 0.0, 0.0], "normal": [0, 1, 0]} for i in range(4)]}
    d["holds"][0]["friction"] = 0.8
    notes = Terrain.from_dict(d).convention_notes()
    assert "holds: a friction coefficient above 5 on 3 of 4 (up to 80)" in notes[0] and "percentage" in notes[0]
    assert not any("friction" in n for name in bundled_terrains() for n in Terrain.load(name).convention_notes())


def test_holds_written_in_millimetres_are_noted():
    """A terrain in millimetres loads (it is a valid terrain of huge holds), but its notes say what is likely
    wrong; holds a usual distance apart get no such note."""
    from climb_ompl.model.terrain import Terrain

    def wall(scale: float) -> Terrain:
        holds = [{"id": f"h{i}_{j}", "position": [scale * 0.2 * i, 0.0, scale * 0.2 * j], "normal": [0, 0.5, 0.87],
                  "friction": 0.8} for i in range(3) for j in range(3)]
        return Terrain.from_dict({"name": "w", "dim": 3, "gravity": [0, 0, -9.81], "holds": holds})

    assert wall(1.0).scale_note() is None and wall(1.0).hold_spacing() == pytest.approx(0.2)
    notes = wall(1000.0).convention_notes()
    assert any("200 m apart" in n and "millimetres" in n for n in notes)
