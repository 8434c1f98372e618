"""Bad input across the commands, as a user mistypes it: exit 2 with one line naming the option, file or JSON path
and the reason, no traceback, and no output file (nor anything else on disk) changed."""

from __future__ import annotations

import json
import os
from pathlib import Path

import pytest

PLANAR = ["--robot", "planar-3limb", "--terrain", "planar-wall"]


@pytest.fixture(scope="module")
def planar_plan(tmp_path_factory: pytest.TempPathFactory) -> Path:
    """A small valid plan file (the planar robot, three steps)."""
    from climb_ompl.cli import main

    path = tmp_path_factory.mktemp("bad-input") / "plan.json"
    assert main(["plan", *PLANAR, "--goal-height", "1.0", "--seed", "0", "--out", str(path)]) == 0
    return path


def _edited(plan: Path, tmp_path: Path, edit: object) -> Path:
    d = json.loads(plan.read_text())
    edit(d)  # type: ignore[operator]
    out = tmp_path / "edited.json"
    out.write_text(json.dumps(d))
    return out


@pytest.mark.parametrize("args, needle", [
    (["plan", *PLANAR, "--goal-height", "1", "--seed", "-1"], "'--seed'"),
    (["plan", *PLANAR, "--goal-height", "1", "--seed", "99999999999999999999"], "'--seed'"),
    (["onestep", "planar-3limb", "planar-wall", "--stance", "limb2=R0,limb3=L3", "--limb", "limb1", "--from", "L0",
      "--to", "L2", "--seed", "-1"], "'--seed'"),
    (["demo", "--seed", "-1"], "'--seed'"),
    (["plan", *PLANAR, "--goal-height", "nan"], "--goal-height: must be a finite number"),
    (["plan", *PLANAR, "--goal-height", "1", "--time-limit", "inf"], "--time-limit: must be a finite number > 0"),
    (["plan", *PLANAR, "--goal-height", "1", "--search", "greedy"], "--search: 'greedy'"),
    (["plan", *PLANAR, "--goal-height", "1", "--start", "limb1=L0,limb1=R0,limb3=L1"],
     "--start: limb 'limb1' given twice"),
    (["plan", *PLANAR, "--goal-height", "1", "--start", "limb1=L0,,limb2=R0"], "--start: expected LIMB=HOLD"),
    (["onestep", "planar-3limb", "planar-wall", "--stance", "", "--limb", "limb1", "--from", "L0", "--to", "L2"],
     "--stance: empty"),
    (["onestep", "planar-3limb", "planar-wall", "--stance", "limb2=R0,limb2=L1", "--limb", "limb1", "--from", "L0",
      "--to", "L2"], "--stance: limb 'limb2' given twice"),
    (["onestep", "planar-3limb", "planar-wall", "--stance", "limb2=R0,limb3=L3", "--limb", "limb1", "--from", "L0",
      "--to", "L0"], "--from and --to: the same hold"),
    (["onestep", "planar-3limb", "planar-wall", "--stance", "limb2=R0,limb3=L3", "--limb", "limb1", "--from", "L0",
      "--to", "L2", "--time-limit", "-1"], "--time-limit: must be a finite number > 0"),
    (["onestep", "planar-3limb", "planar-wall", "--stance", "limb2=R0,limb3=L3", "--limb", "limb1", "--from", "L0",
      "--to", "L2", "--max-iterations", "0"], "'--max-iterations'"),
    (["onestep", "planar-3limb", "planar-wall", "--stance", "limb2=R0,limb3=L3", "--limb", "limb1", "--from", "L0",
      "--to", "L2", "--straight-phase", "5"], "--straight-phase: straight-limb draws need --space projected"),
    (["onestep", "planar-3limb", "planar-wall", "--stance", "limb2=R0,limb3=L3", "--limb", "limb1", "--from", "L0",
      "--to", "NOPE"], "--to: no hold 'NOPE' in terrain"),
    (["onestep", "planar-3limb", "planar-wall", "--stance", "limb2=R0,limb3=L3", "--limb", "limb9", "--from", "L0",
      "--to", "L2"], "--limb: robot 'planar-3limb' has no limb 'limb9'"),
    (["onestep", "planar-3limb", "planar-wall", "--stance", "limb2=R0,limb3=L3", "--limb", "limb2", "--from", "L0",
      "--to", "L2"], "--limb: limb2 is in --stance"),
    (["onestep", "planar-3limb", "planar-wall", "--stance", "limb2=R0,limb3=L3", "--limb", "limb1", "--from", "R0",
      "--to", "L2"], "--from: hold 'R0' is taken by limb2"),
    (["demo", "--height", "-1"], "--height: must be a finite number > 0"),
    (["demo", "--height", "nan"], "--height: must be a finite number > 0"),
    (["demo", "--time-limit", "nan"], "--time-limit: must be a finite number > 0"),
    (["plan", *PLANAR, "--goal-height", "1", "--heuristic-weight", "inf"], "--heuristic-weight: must be a finite"),
    (["plan", *PLANAR, "--goal-hold", "limb1=L4,limb2=R4"], "--goal-hold: one LIMB=HOLD"),
    (["plan", "--replay", "PLAN", "--time-limit", "inf"], "--time-limit: must be a finite number > 0"),
    (["replan", "PLAN", "--at-step", "1", "--remove-hold", "L4", "--time-limit", "inf"],
     "--time-limit: must be a finite number > 0"),
    (["terrain", "generate", "--spacing", "5e-324"], "wall makes inf holds, more than 20000"),
    (["terrain", "generate", "--spacing", "0.0001"], "--spacing: 0.0001 m on a 1.6 x 3 m wall makes"),
    (["terrain", "generate", "--width", "inf"], "--width: must be a finite number > 0"),
    (["terrain", "generate", "--name", ""], "--name: must not be empty"),
    (["bench", "suite", "--budget", "-5"], "--budget: must be a finite number > 0"),
    (["bench", "suite", "--workers", "0"], "'--workers'"),
    (["bench", "onestep", "--time-limit", "-1", "--queries", "1"], "--time-limit: must be a finite number > 0"),
    (["bench", "climb", "--time-limit", "nan"], "--time-limit: must be a finite number > 0"),
    (["bench", "replan", "--time-limit", "0"], "--time-limit: must be a finite number > 0"),
    (["bench", "grid", "--time-limit", "inf"], "--time-limit: must be a finite number > 0"),
    # the planner comparison's grids (a user's trial: these ran a grid of crashed runs, or none, and exited 0;
    # or ended in a traceback, a hang, or an empty output folder)
    (["bench", "grid", "--planner", "RRTconnect"], "--planner: unknown planner 'RRTconnect' (did you mean "
                                                    "'RRTConnect'?)"),
    (["bench", "grid", "--planner", "BITstar"], "--planner: planner 'BITstar' is not available: needs an informed"),
    (["bench", "grid", "--space", "atlass"], "--space: unknown constrained space 'atlass' (did you mean 'atlas'?)"),
    (["bench", "grid", "--queries", "0"], "--queries: must be a whole number >= 1"),
    (["bench", "grid", "--max-iterations", "-5"], "--max-iterations: must be a whole number >= 1"),
    (["bench", "grid", "--preset", "smal"], "--preset: unknown preset 'smal'"),
    (["bench", "grid", "--preset", "tiny", "--sampler", "straight-elbow"],
     "--sampler: custom sampler 'straight-elbow' runs only on the projected space"),  # the preset's spaces
    (["bench", "grid", "--scheduler", "foo"], "--scheduler: 'foo' is not a Dask scheduler address"),
    (["bench", "compare", "--planner", "SBL", "--space", "atlas", "--sampler", "straight-elbow"],
     "--sampler: custom sampler 'straight-elbow' runs only on the projected space"),
    (["bench", "compare", "--sampler", "straight-elbo"], "--sampler: unknown sampler 'straight-elbo'"),
    (["bench", "compare", "--max-iterations", "0"], "--max-iterations: must be a whole number >= 1"),
    (["bench", "compare", "--per-set", "0"], "--per-set: must be a whole number >= 1"),
    (["bench", "compare", "--sample", "-5"], "--sample: must be a whole number >= 1"),
    (["bench", "compare", "--workers", "0"], "--workers: must be a whole number >= 1"),
    (["show", "--terrain", "planar-wall", "--robot", "go1"], "dim 2, but robot 'go1' is 3-D"),
    pytest.param(["verify", "PLAN", "--max-listed", "-1"], "'--max-listed'", marks=pytest.mark.climb),
])
def test_bad_options_exit_2_naming_the_option(cli, tmp_path, request, args, needle):
    """Each value is refused before any work, with the option named; nothing is written."""
    out = tmp_path / "out"
    if "PLAN" in args:  # (the plan file is a climb: made only for the option that reads one)
        args = [str(request.getfixturevalue("planar_plan")) if a == "PLAN" else a for a in args]
    if args[0] in ("plan", "onestep", "terrain", "replan"):
        args = [*args, "--out", str(tmp_path / ("o.yaml" if args[0] == "terrain" else "o.json"))]
    elif args[0] == "demo":
        args = [*args, "--out-dir", str(out)]
    elif args[0] == "bench":
        args = [*args, "--out", str(out)]
    elif args[0] == "show":
        args = [*args, "--html", str(tmp_path / "o.html")]
    r = cli(*args)
    assert r.code == 2, (r.code, r.err)
    assert needle in r.err, r.err
    assert "Traceback" not in r.err
    assert not any((tmp_path / f).exists() for f in ("out", "o.json", "o.yaml", "o.html"))


def test_demo_out_dir_that_is_a_file_is_refused(cli, tmp_path):
    (tmp_path / "taken").write_text("mine")
    r = cli("demo", "--out-dir", tmp_path / "taken")
    assert r.code == 2 and "--out-dir" in r.err and "not a folder" in r.err, r.err
    assert (tmp_path / "taken").read_text() == "mine"


@pytest.mark.climb
def test_output_onto_a_pipe_is_refused_and_a_symlink_is_followed(cli, tmp_path, planar_plan):
    """``--out`` naming a FIFO (as a device would) is refused rather than replaced; a symbolic link keeps being a
    link, and the file it points to gets the output (the atomic write used to rename over the link itself)."""
    fifo = tmp_path / "pipe"
    os.mkfifo(fifo)
    r = cli("plan", "--replay", planar_plan, "--out", fifo)
    assert r.code == 2 and "not a regular file" in r.err, r.err
    assert fifo.is_fifo()
    from climb_ompl._io import atomic_write
    from climb_ompl.errors import InputError

    with pytest.raises(InputError, match="not a regular file"):
        atomic_write(fifo, "x")
    target, link = tmp_path / "target.json", tmp_path / "link.json"
    target.write_text("old")
    link.symlink_to(target)
    atomic_write(link, "new")
    assert link.is_symlink() and target.read_text() == "new"


def test_yaml_duplicate_keys_are_errors_merges_load_and_exponent_text_is_explained(tmp_path, cli):
    """A key written twice used to keep the last value silently; keys merged with ``<<:`` may still be overridden
    (a hold written from another's anchor); ``1e-1``, which YAML 1.1 reads as text, is explained where a number was
    expected (hold ids such as ``2E1`` stay text)."""
    from climb_ompl.model.terrain import Terrain

    path = tmp_path / "wall.yaml"
    path.write_text("name: w\nholds:\n  - {id: a, position: [0, 0, 1], normal: [0, 1, 0]}\n"
                    "  - id: b\n    position: [0.3, 0, 1]\n    normal: [0, 1, 0]\n    position: [0.5, 0, 1]\n")
    r = cli("terrain", "validate", path)
    assert r.code == 2 and f"{path}: line 7" in r.err and "'position' twice (first on line 5)" in r.err, r.err
    path.write_text("name: w\nholds:\n  - &h {id: a, position: [0, 0, 1], normal: [0, 1, 0]}\n"
                    "  - {<<: *h, id: 2E1, position: [0.3, 0, 1]}\n")
    wall = Terrain.load(path)
    assert [h.id for h in wall.holds] == ["a", "2E1"] and wall.hold("2E1").p[0] == pytest.approx(0.3)
    path.write_text("name: w\nfriction: 1e-1\nholds:\n  - {id: a, position: [0, 0, 1], normal: [0, 1, 0]}\n")
    r = cli("terrain", "validate", path)
    assert r.code == 2 and "friction: expected a number, got '1e-1'" in r.err and "with a dot" in r.err, r.err


@pytest.mark.heavy
def test_yaml_parsed_by_libyaml_reads_as_by_pyyamls_own_parser():
    """YAML is parsed by libyaml when PyYAML has it (the constructor, duplicate-key check included, is the same
    Python one): the bundled terrains and robot specs read exactly as through PyYAML's pure-Python parser, and
    text that fails gives the pure-Python parser's error, message and line."""
    import yaml
    from conftest import DATA, ROOT

    from climb_ompl._io import _loader, loads_yaml

    files = [p for d in ("climb_ompl/terrains", "robots", "examples") for p in sorted((ROOT / d).glob("*.yaml"))]
    assert len(files) >= 10
    for p in files:
        text = p.read_text(encoding="utf-8")
        assert loads_yaml(text) == yaml.load(text, Loader=_loader()), p  # noqa: S506 (a SafeLoader)
    for text in ((DATA / "bad" / "01_yaml_syntax.yaml").read_text(), "a: 1\nb: [2\n", "a: 1\na: 2\n"):
        with pytest.raises(yaml.YAMLError) as fast:
            loads_yaml(text)
        with pytest.raises(yaml.YAMLError) as pure:
            yaml.load(text, Loader=_loader())  # noqa: S506
        assert str(fast.value) == str(pure.value)


def test_huge_numbers_in_a_terrain(tmp_path):
    """A normal's direction is all that counts, however long it is written; a gravity that overflows is named as
    such (it used to be called a zero normal, with numpy's overflow warning)."""
    import warnings

    from climb_ompl.errors import TerrainError
    from climb_ompl.model.terrain import Terrain

    path = tmp_path / "big.yaml"
    path.write_text("name: big\nholds:\n  - {id: a, position: [0, 0, 1], normal: [0, 1.0e+308, 1.0e+308]}\n")
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        n = Terrain.load(path).hold("a").normal
        assert n == pytest.approx((0.0, 2 ** -0.5, 2 ** -0.5))
        path.write_text("name: big\ngravity: [1.0e+308, 0, -1.0e+308]\n"
                        "holds:\n  - {id: a, position: [0, 0, 1], normal: [0, 1, 0]}\n")
        with pytest.raises(TerrainError, match="gravity: implausible magnitude"):
            Terrain.load(path)


@pytest.mark.parametrize("hold, needle", [
    ("position: [1" + "0" * 400 + ", 0, 1]", "position: non-finite value in"),  # a YAML integer no float holds
    ("position: [0, 1.0e+308, 0.07]", "position: a value beyond 1e+09"),  # finite, but its geometry is not
    ("position: [0, 0, 1], friction: 1" + "0" * 400, "friction: non-finite value"),
    ("position: [1.0e3, 0, 1]", "give the exponent a sign, e.g. 1.0e+3"),  # YAML 1.1 reads 1.0e3 as text
    ("position: [0, 0, 1], friction: 1.0e5", "give the exponent a sign, e.g. 1.0e+5"),
])
def test_numbers_a_terrain_cannot_use_are_named(cli, tmp_path, hold, needle):
    """Each used to end in a traceback (``OverflowError``; a hold 1e308 m away passed ``validate`` and crashed the
    planner's support regions) or in a hint to write a dot the number already had."""
    path = tmp_path / "w.yaml"
    path.write_text("name: w\nholds:\n  - {id: a, " + hold + ", normal: [0, 1, 0]}\n")
    r = cli("terrain", "validate", path)
    assert r.code == 2 and needle in r.err and len(r.err.strip().splitlines()) == 1, r.err


def test_an_empty_elbow_is_no_elbow(tmp_path):
    """``elbow:`` written empty (YAML null) means no elbow, as leaving it out does."""
    import yaml
    from conftest import ROOT

    from climb_ompl.model.robot import RobotModel

    spec = yaml.safe_load((ROOT / "robots" / "lemur.yaml").read_text())
    spec["limbs"][0]["elbow"] = None
    spec.pop("urdf_package", None)
    spec["urdf"] = str(ROOT / "urdf" / "lemur.urdf")
    r = RobotModel.from_spec(spec, base_dir=tmp_path, source="lemur-no-elbow")
    assert r.limbs[0].elbow_index is None and r.limbs[1].elbow_index is not None


@pytest.mark.parametrize("hid", ["a=b", "a,b", "a\\nb", " a"])
def test_a_hold_id_the_command_line_cannot_name_is_refused(cli, tmp_path, hid):
    """Holds are named in ``LIMB=HOLD`` pairs separated by commas (``--start``, ``--goal-hold``, ``onestep
    --stance``): an id holding ``=``, ``,`` or a line break, or padded with spaces, passed ``validate`` and could not be
    named."""
    path = tmp_path / "w.yaml"
    path.write_text('name: w\nholds:\n  - {id: "' + hid + '", position: [0, 0, 1], normal: [0, 1, 0]}\n')
    r = cli("terrain", "validate", path)
    assert r.code == 2 and "holds[0].id" in r.err and "LIMB=HOLD" in r.err, r.err


@pytest.mark.heavy
def test_yaml_nested_too_deep_is_bad_input(cli, tmp_path):
    """PyYAML's constructor recurses once per level: 5000 nested lists were a ``RecursionError`` traceback."""
    path = tmp_path / "deep.yaml"
    path.write_text("name: w\nholds: " + "[" * 5000 + "]" * 5000 + "\n")
    r = cli("terrain", "validate", path)
    assert r.code == 2 and "nested too deep" in r.err, r.err


@pytest.mark.parametrize("edit, needle", [
    (lambda sp: sp["limbs"][0].update(hand_frame=None), "limbs[0].hand_frame: expected the name of a frame"),
    (lambda sp: sp["limbs"][0].update(hand_frame=["FL_foot"]), "limbs[0].hand_frame: expected the name of a frame"),
    (lambda sp: sp["limbs"][0].update(elbow=3), "limbs[0].elbow: expected the name of a joint"),
    (lambda sp: sp["limbs"][0].update(hand_frame="FL_feet"), "unknown frame 'FL_feet' (not a link or joint of "
     "go1.urdf); did you mean 'FL_foot'? (links: base, trunk,"),
    (lambda sp: sp.update(urdf="robots/go1_description/go1.urdf"), "(files ending in .urdf under "
     "robots/go1_description: robots/go1_description/urdf/go1.urdf)"),
    (lambda sp: sp["limbs"][0]["contact"].update(offset=[0, 0, float("nan")]), "limbs[0].contact.offset"),
    (lambda sp: sp["limbs"][0]["contact"].update(offset=[0, 0, 1e300]), "beyond 10 m from the hand frame"),
    (lambda sp: sp["limbs"][0]["contact"].update(radius=1e300), "limbs[0].contact.radius"),
    (lambda sp: sp.update(base={**sp["base"], "lower": [float("nan")] + sp["base"]["lower"][1:]}), "base.lower"),
    (lambda sp: sp["limbs"][0]["contact"].update(offset=[10 ** 20, 0, 0]), "limbs[0].contact.offset[0]: 1000"),
    (lambda sp: sp.update(mass=10 ** 400), "mass: "),  # no float holds it
])
def test_a_spec_field_the_urdf_cannot_take_is_named_in_the_spec(cli, tmp_path, edit, needle):
    """A hand frame that is not a string reached Pinocchio (a Boost.Python ``ArgumentError`` traceback); a non-finite
    contact offset gave a reach of nan and a traceback; a NaN base bound was blamed on the URDF's joint limits."""
    import yaml
    from conftest import ROOT

    spec = yaml.safe_load((ROOT / "robots" / "go1.yaml").read_text())
    if spec.get("urdf_package") is None:
        pytest.skip("go1's spec reads its URDF from example-robot-data")
    spec["limbs"][0].setdefault("contact", {"type": "sphere", "radius": 0.02})
    edit(spec)
    path = tmp_path / "go1-edited.yaml"
    path.write_text(yaml.safe_dump(spec))
    r = cli("robot", "check", path)
    assert r.code == 2 and needle in r.err and str(path) in r.err and "Traceback" not in r.err, r.err


@pytest.mark.climb
def test_errors_inside_a_plan_file_name_the_file_and_json_path(cli, tmp_path, planar_plan):
    """The robot, terrain and settings a plan embeds: a bad value names the plan file and where in it (these said
    ``<plan robot ...>``, ``<plan terrain>`` or blamed ``--planner``, an option the user never gave)."""
    def spec(d):
        d["robot"]["spec"]["mass"] = "heavy"

    def normal(d):
        d["terrain"]["data"]["holds"][0]["normal"] = [0.0, 0.0]

    def planner(d):
        d["settings"]["planner"] = "FOO"

    for edit, cmd, needle in ((spec, "verify", "($.robot.spec): mass"),
                              (normal, "verify", "($.terrain.data): holds[0].normal: zero normal"),
                              (normal, "replan", "($.terrain.data): holds[0].normal: zero normal"),
                              (normal, "play", "($.terrain.data): holds[0].normal: zero normal"),
                              (planner, "replan", "$.settings.planner: unknown planner 'FOO'"),
                              (planner, "replay", "$.settings.planner: unknown planner 'FOO'")):
        bad = _edited(planar_plan, tmp_path, edit)
        out = tmp_path / "new.json"
        args = {"verify": ["verify", bad], "replay": ["plan", "--replay", bad, "--out", out],
                "play": ["play", bad, "--html", out],
                "replan": ["replan", bad, "--at-step", "1", "--remove-hold", "L4", "--out", out]}[cmd]
        r = cli(*args)
        assert r.code == 2 and f"{bad}" in r.err and needle in r.err, (cmd, r.err)
        assert not out.exists()


@pytest.mark.climb
def test_verify_reports_a_step_without_contacts_instead_of_crashing(cli, tmp_path, planar_plan):
    """A hand-edited step whose stance lost its other limbs: the release leaves no contact; verify lists the
    violations (it raised numpy's "need at least one array to concatenate")."""
    def lose(d):
        d["steps"][0]["stance"] = {d["steps"][0]["limb"]: d["steps"][0]["hold"]}

    r = cli("verify", _edited(planar_plan, tmp_path, lose))
    assert r.code == 1, r.err
    assert "no contact carries the robot" in r.err and "stance_change" in r.err, r.err



def test_a_folder_given_for_a_file_is_named_as_such(cli, tmp_path):
    """It used to say "no such file and no bundled ... of that name" about a folder that exists."""
    for args, needle in ((["terrain", "validate", tmp_path], "terrain: is a folder"),
                         (["robot", "check", tmp_path], "robot: is a folder")):
        r = cli(*args)
        assert r.code == 2 and needle in r.err, r.err


def test_two_limbs_with_one_hand_frame_are_refused(cli, tmp_path):
    """A slip in a spec, a limb without joints given another limb's foot, used to pass ``robot check`` (with a
    reach of 0); with joints, the frame check already names the slip."""
    import yaml
    from conftest import ROOT

    spec = yaml.safe_load((ROOT / "robots" / "go1.yaml").read_text())
    spec["limbs"][1] = {"name": "fr", "hand_frame": "FL_foot", "joints": []}
    (tmp_path / "go1-slip.yaml").write_text(yaml.safe_dump(spec))
    r = cli("robot", "check", tmp_path / "go1-slip.yaml")
    assert r.code == 2 and "limbs[1].hand_frame" in r.err and "of limb 'fl'" in r.err, r.err


def test_output_checks_come_before_the_work(cli, tmp_path):
    """A folder below a file for ``demo``, and a ``--out`` link into a missing folder, are refused at once (they
    failed after planning: a traceback, and the atomic write's refusal)."""
    (tmp_path / "taken").write_text("mine")
    r = cli("demo", "--out-dir", tmp_path / "taken" / "sub")
    assert r.code == 2 and "is a file, not a folder" in r.err, r.err
    (tmp_path / "link.json").symlink_to(tmp_path / "missing" / "x.json")
    r = cli("plan", *PLANAR, "--goal-height", "1", "--out", tmp_path / "link.json")
    assert r.code == 2 and "--out: folder" in r.err and "missing" in r.err, r.err


@pytest.mark.climb
def test_a_plan_file_with_a_seed_out_of_range_is_read_and_named(cli, tmp_path, planar_plan):
    """Files written before seeds were bounded (``replan --seed -1`` wrote them) still load and verify; a re-run
    that would use the seed says which value is wrong instead of numpy's traceback."""
    def neg(d):
        d["seed"] = -1
        d.pop("steps_sha256", None)  # as a file of that version: no digest of its steps

    bad = _edited(planar_plan, tmp_path, neg)
    assert cli("verify", bad).code == 0
    r = cli("plan", "--replay", bad, "--out", tmp_path / "r.json")
    assert r.code == 2 and "$.seed: -1 is not a seed" in r.err, r.err
    assert cli("plan", "--replay", bad, "--seed", "0", "--out", tmp_path / "r.json").code == 0


@pytest.mark.heavy
def test_benchmark_databases_and_outputs_that_are_not_what_they_should_be(cli, tmp_path):
    """``--out`` naming a file, a database file that is not one, an unreachable Dask scheduler: one line each,
    exit 2, nothing written (they gave tracebacks, and the scheduler an empty grid.db after 30 s)."""
    afile = tmp_path / "afile"
    afile.write_text("")
    r = cli("bench", "grid", "--preset", "tiny", "--out", afile)
    assert r.code == 2 and "--out:" in r.err and "is a file" in r.err
    bad = tmp_path / "notadb.db"
    bad.write_text("not sqlite")
    for args in (("bench", "report", bad, "--out", tmp_path / "r"),
                 ("bench", "planners-doc", bad, "--out", tmp_path / "p.md")):
        r = cli(*args)
        assert r.code == 2 and "not a benchmark database" in r.err and "Traceback" not in r.err, r.err
    r = cli("bench", "grid", "--preset", "tiny", "--scheduler", "tcp://127.0.0.1:9", "--out", tmp_path / "g")
    assert r.code == 2 and "--scheduler: no Dask scheduler answers" in r.err
    assert sorted(p.name for p in tmp_path.iterdir()) == ["afile", "notadb.db"]


def test_a_robot_file_not_found_lists_the_files_where_its_folder_exists(tmp_path):
    """The files of the same kind under the deepest folder of the path that exists, the same name first; nothing
    for a path without a folder or a suffix, outside the places looked in, or a folder without such files."""
    from climb_ompl.errors import RobotModelError
    from climb_ompl.model.files import resolve_robot_file

    pkg = tmp_path / "pkg"
    for f in ("robots/hyq/robots/hyq.urdf", "robots/hyq/robots/other.urdf", "robots/hyq/srdf/hyq.srdf",
              "robots/go/urdf/a.urdf", *(f"robots/many/m{i:02d}.urdf" for i in range(12))):
        (pkg / f).parent.mkdir(parents=True, exist_ok=True)
        (pkg / f).write_text("")

    def message(value: str) -> str:
        with pytest.raises(RobotModelError) as e:
            resolve_robot_file(value, tmp_path, "spec.yaml", "urdf", pkg)
        return str(e.value)

    assert message("robots/hyq/urdf/hyq.urdf").endswith(
        "(files ending in .urdf under robots/hyq: robots/hyq/robots/hyq.urdf, robots/hyq/robots/other.urdf)")
    assert "robots/hyq/srdf" not in message("robots/hyq/urdf/hyq.urdf")
    assert message("robots/many/x/m05.urdf").endswith(
        "under robots/many: robots/many/m05.urdf, robots/many/m00.urdf, robots/many/m01.urdf, robots/many/m02.urdf, "
        "robots/many/m03.urdf, robots/many/m04.urdf, robots/many/m06.urdf, robots/many/m07.urdf, ... (12 in all))")
    for value in ("hyq.urdf", "robots/hyq/robots/hyq", "../pkg/robots/hyq/x.urdf", str(pkg / "robots/hyq/x.urdf"),
                  "nothing/here.urdf", "robots/hyq/meshes/x.stl"):
        assert message(value).endswith("package folder " + str(pkg) + ")"), value
