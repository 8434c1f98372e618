"""The ``climb-ompl`` skeleton: --version, terrain validate/generate/list, planners, bench group, exit codes."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
import pytest
from conftest import DATA

from climb_ompl import __version__
from climb_ompl.manifold._ompl import PLANNER_NAMES, UNAVAILABLE
from climb_ompl.model.terrain import Terrain, bundled_terrains, generate_wall

BAD = sorted((DATA / "bad").glob("*.yaml"))


def test_version(cli) -> None:
    r = cli("--version")
    assert r.code == 0 and r.out.strip() == f"climb-ompl {__version__}"


@pytest.mark.heavy
def test_python_dash_m_and_console_script_agree(cli_subprocess) -> None:
    proc = cli_subprocess("--version")
    assert proc.returncode == 0 and proc.stdout.strip() == f"climb-ompl {__version__}"


def test_no_arguments_shows_help_and_usage_errors_exit_2(cli) -> None:
    r = cli()
    assert r.code == 2 and "terrain" in r.out + r.err
    r = cli("terrain", "generate", "--seed", "-1", "--out", "x.yaml")
    assert r.code == 2 and "--seed" in r.out + r.err
    assert cli("no-such-command").code == 2


@pytest.mark.parametrize("name", bundled_terrains())
def test_validate_bundled_terrains_exit_0(cli, name: str) -> None:
    r = cli("terrain", "validate", name)
    assert r.code == 0 and "ok" in r.out and r.err == ""


@pytest.mark.parametrize("path", BAD, ids=lambda p: p.stem)
def test_validate_bad_file_exits_2_naming_the_field(cli, path: Path) -> None:
    field = path.read_text().splitlines()[0].removeprefix("# expect: ").strip()
    r = cli("terrain", "validate", str(path))
    assert r.code == 2
    lines = r.err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("error: ")  # one line, no traceback
    assert f"{path}: {field}: " in lines[0]


def test_validate_several_files_stops_at_the_bad_one(cli) -> None:
    r = cli("terrain", "validate", "pegs", str(BAD[0]), "demo-wall")
    assert r.code == 2 and "pegs" in r.out and "demo-wall" not in r.out


@pytest.mark.heavy
def test_real_process_exit_codes(cli_subprocess) -> None:
    ok = cli_subprocess("terrain", "validate", "planar-wall")
    bad = cli_subprocess("terrain", "validate", str(BAD[0]))
    assert ok.returncode == 0 and "ok" in ok.stdout
    assert bad.returncode == 2 and "Traceback" not in bad.stderr and bad.stderr.startswith("error: ")


def test_generate_is_reproducible_and_valid(cli, tmp_path: Path) -> None:
    a, b = tmp_path / "a.yaml", tmp_path / "b.yaml"
    assert cli("terrain", "generate", "--seed", "4", "--height", "1.5", "--out", a).code == 0
    assert cli("terrain", "generate", "--seed", "4", "--height", "1.5", "--out", b).code == 0
    assert a.read_bytes() == b.read_bytes()
    assert Terrain.load(a) == generate_wall(4, height=1.5)
    assert cli("terrain", "validate", a).code == 0
    assert sorted(os.listdir(tmp_path)) == ["a.yaml", "b.yaml"]  # no temporary files left


def test_generate_makes_the_suites_leaning_wall_from_its_recorded_arguments(cli, tmp_path: Path) -> None:
    """The hold lean options: the bundled wall of the climb suite whose holds lean 35-65 degrees (written by
    ``generate_wall`` through the API, its arguments in its description) comes out of the command line again."""
    from climb_ompl.bench.suite import terrain_path

    out = tmp_path / "lean.yaml"
    r = cli("terrain", "generate", "--seed", "1", "--normal-up-min", "35", "--normal-up-max", "65",
            "--normal-side", "20", "--name", "wall-lean35-65", "--out", out)
    assert r.code == 0, r.err
    want = Terrain.load(terrain_path("wall-lean35-65"))
    got = Terrain.load(out)
    assert got.holds == want.holds and got.description == want.description
    bad = cli("terrain", "generate", "--normal-up-min", "70", "--normal-up-max", "60", "--out", tmp_path / "x.yaml")
    assert bad.code == 2 and "--normal-up-min/--normal-up-max" in bad.err and not (tmp_path / "x.yaml").exists()


def test_generate_to_unwritable_place_exits_2_and_writes_nothing(cli, tmp_path: Path) -> None:
    blocker = tmp_path / "a-file"
    blocker.write_text("x")
    for out in (tmp_path / "missing" / "w.yaml", blocker / "w.yaml", tmp_path):
        r = cli("terrain", "generate", "--seed", "1", "--out", out)
        assert r.code == 2 and r.err.startswith("error: ") and "Traceback" not in r.err, r.err
    assert sorted(os.listdir(tmp_path)) == ["a-file"]


def test_generate_replaces_an_existing_file_atomically(cli, tmp_path: Path) -> None:
    out = tmp_path / "w.yaml"
    out.write_text("old")
    assert cli("terrain", "generate", "--seed", "2", "--out", out).code == 0
    assert Terrain.load(out).name == "wall-2"


def test_output_files_get_the_umask_permissions_not_the_temporary_files(cli, tmp_path: Path) -> None:
    """The atomic write's temporary file is private (mkstemp: 0600); the file written is not: a new file gets
    0666 less the umask, as ``open`` gives it, and a replaced file keeps its permissions."""
    old = os.umask(0o022)
    try:
        assert cli("terrain", "generate", "--seed", "2", "--out", tmp_path / "w.yaml").code == 0
        assert (tmp_path / "w.yaml").stat().st_mode & 0o777 == 0o644
        os.umask(0o077)
        assert cli("terrain", "generate", "--seed", "3", "--out", tmp_path / "p.yaml").code == 0
        assert (tmp_path / "p.yaml").stat().st_mode & 0o777 == 0o600
        (tmp_path / "w.yaml").chmod(0o664)
        assert cli("terrain", "generate", "--seed", "4", "--out", tmp_path / "w.yaml").code == 0
        assert (tmp_path / "w.yaml").stat().st_mode & 0o777 == 0o664
    finally:
        os.umask(old)


def test_generator_errors_exit_2(cli, tmp_path: Path) -> None:
    r = cli("terrain", "generate", "--spacing", "0", "--out", tmp_path / "w.yaml")
    assert r.code == 2 and "--spacing" in r.err and "<argument>" not in r.err  # the option names itself
    assert not (tmp_path / "w.yaml").exists()


def test_terrain_list(cli) -> None:
    r = cli("terrain", "list")
    assert r.code == 0
    assert [line.split()[0] for line in r.out.splitlines()] == bundled_terrains()


def test_planners_lists_the_registry(cli) -> None:
    r = cli("planners")
    assert r.code == 0 and r.out.split() == list(PLANNER_NAMES)
    r = cli("planners", "--all")
    assert all(name in r.out for name in UNAVAILABLE) and "not available" in r.out


def _slab_yaml(geometry: bool, plane: bool = True) -> str:
    """A user's 30-degree slab, 5 x 8 holds 0.17 m apart with shelf-like normals: tilted in its geometry (the wall
    plane turned, gravity straight down), or as the convention says (the wall y = 0, gravity tilted)."""
    import math

    a = math.radians(30)
    up, n = ((0.0, -math.sin(a), math.cos(a)), (0.0, math.cos(a), math.sin(a))) if geometry else \
        ((0.0, 0.0, 1.0), (0.0, 1.0, 0.0))
    g = [0.0, 0.0, -9.81] if geometry else [0.0, round(-9.81 * math.sin(a), 4), round(-9.81 * math.cos(a), 4)]
    lines = ["name: user-slab", "dim: 3", f"gravity: {g}", "friction: 0.8", "holds:"]
    for r in range(8):
        for c in range(5):
            s = 0.17 * r
            p = [round(-0.34 + 0.17 * c, 4), round(s * up[1], 4), round(s * up[2], 4)]
            lines.append(f"  - {{id: r{r}c{c}, position: {p}, normal: [0.0, 0.5, 0.866]}}")
    if plane:
        lines.append(f"surfaces:\n  - {{type: plane, point: [0, 0, 0], normal: {[round(x, 4) for x in n]}, "
                     "size: [2, 3]}")
    return "\n".join(lines) + "\n"


def test_validate_and_plan_note_a_wall_that_departs_from_the_frame_convention(cli, tmp_path: Path) -> None:
    """A slab tilted in its geometry loads (exit 0) but is noted: its wall plane is 30 degrees from +y and its upper
    holds lie off y = 0, while the robot specs expect the wall y = 0 and a tilted gravity.  The same slab written
    by the convention gets no note (``plan`` turns such a wall into the convention: tests/test_wall_frame.py)."""
    tilted, conv = tmp_path / "tilted.yaml", tmp_path / "conv.yaml"
    tilted.write_text(_slab_yaml(True))
    conv.write_text(_slab_yaml(False))
    r = cli("terrain", "validate", str(tilted))
    assert r.code == 0 and "ok" in r.out
    assert "surfaces[0]: the wall plane's normal (0, 0.866, 0.5) is 30 deg from +y" in r.err
    # rows 4-7 lie off y = 0 by 0.17 r sin 30 > 0.3 m
    assert "holds: 20 of 40 lie more than 0.3 m off the plane y = 0" in r.err and "tilting gravity" in r.err
    r = cli("terrain", "validate", str(conv))
    assert r.code == 0 and r.err == ""
    assert Terrain.load(conv).convention_notes() == []


def test_without_a_plane_surface_the_wall_is_the_plane_the_holds_lie_on(cli, tmp_path: Path) -> None:
    """The same two slabs without their plane surface: the wall normal is that of the plane through the holds,
    whichever way gravity points.  The slab written by the convention (holds on y = 0, gravity tilted 30 degrees)
    gets none (the holds' mean normal made horizontal across the tilted gravity leaned 30 degrees, and was
    noted); the one tilted in its geometry is noted with its wall's normal, (0, 0.866, 0.5)."""
    from climb_ompl.model.wall_frame import wall_normal

    tilted, conv = tmp_path / "tilted.yaml", tmp_path / "conv.yaml"
    tilted.write_text(_slab_yaml(True, plane=False))
    conv.write_text(_slab_yaml(False, plane=False))
    assert np.allclose(wall_normal(Terrain.load(conv)), [0.0, 1.0, 0.0], atol=1e-9)
    assert np.allclose(wall_normal(Terrain.load(tilted)), [0.0, 0.866, 0.5], atol=1e-3)
    r = cli("terrain", "validate", str(conv))
    assert r.code == 0 and r.err == ""
    r = cli("terrain", "validate", str(tilted))
    assert r.code == 0 and "holds: the normal of the wall they lie on (0, 0.866, 0.5) is 30 deg from +y" in r.err


def test_plan_help_shows_the_settings_defaults(cli) -> None:
    """``plan --help`` gives each option's default as the climb uses it (the settings' values, not a copy that
    can go stale: it once showed LazyPRM and projected for SBL and atlas)."""
    from climb_ompl.settings import ClimbSettings

    r = cli("plan", "--help")
    text = " ".join((r.out + r.err).split())
    d = ClimbSettings()
    for shown in (f"[{d.planner}]", f"[{d.space}]", f"[{d.sampler}]", f"[{d.time_limit:g}]",
                  f"[{d.heuristic_weight:g}]", f"[{d.step_time_limit:g}]"):
        assert shown in text, shown


def test_validate_notes_a_hold_whose_normal_points_into_the_wall(cli, tmp_path: Path) -> None:
    """A sign slip a user made writing a wall by hand (a hexapod trial): a normal pointing into the rock loads
    (the back of a flake faces the wall) but is noted with the hold's id; the slab above, and every bundled
    terrain, get no such note."""
    text = _slab_yaml(False).replace("{id: r2c3, position: [0.17, 0.0, 0.34], normal: [0.0, 0.5, 0.866]}",
                                     "{id: r2c3, position: [0.17, 0.0, 0.34], normal: [0.0, -0.5, -0.866]}")
    assert "[0.0, -0.5, -0.866]" in text
    (tmp_path / "slip.yaml").write_text(text)
    r = cli("terrain", "validate", str(tmp_path / "slip.yaml"))
    assert r.code == 0 and "holds: the normal of 1 hold(s) points into the wall: r2c3 (0, -0.5, -0.866)" in r.err
    assert "tilting gravity" not in r.err  # not a departure from the frame convention
    for name in ("demo-wall", "slab", "overhang", "stepping-stone-ramp-3m"):
        assert not any("into the wall" in n for n in Terrain.load(name).convention_notes()), name
