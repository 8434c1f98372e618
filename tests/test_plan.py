"""Plan data model and plan file: exact round trip, shipped schema, errors naming the JSON path."""

from __future__ import annotations

import json
import math
from importlib import resources

import jsonschema
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from climb_ompl.errors import PlanFileError
from climb_ompl.model.terrain import generate_wall
from climb_ompl.plan.file import (
    SCHEMA_VERSION,
    ForceSample,
    Plan,
    Step,
    canonical_json,
    plan_schema,
    read_plan_dict,
    sha256_json,
    sha256_text,
)


def make_plan(waypoints: list[list[float]] | None = None, seed: int = 3) -> Plan:
    """A small, well-formed (not physically meaningful) climb plan with two steps."""
    terrain = generate_wall(0, width=0.6, height=0.6, spacing=0.3)
    spec = {"name": "toy", "urdf": "toy.urdf", "limbs": [{"name": "a"}, {"name": "b"}]}
    urdf = "<robot name='toy'/>"
    w = waypoints or [[0.1, 0.2, -0.3], [0.1 + 1e-17, 2 / 3, -1e-300], [math.pi, -0.0, 5e-324]]
    s0 = Step(0, (("a", "h0"), ("b", "h1")), "release", "b", "h1", tuple(tuple(x) for x in w),
              (0.0, 0.5, 1.25),
              (ForceSample(0, (("a", (1.0, 2.0, 3.0)), ("b", (0.1, 0.2, 0.3))), (0.0, 0.5, -0.25), 0.01),
               ForceSample(2, (("a", (1.0, 2.0, 3.5)),), (0.0, 0.1, 0.2), 0.02)), 0.01)
    s1 = Step(1, (("a", "h0"),), "grab", "b", "h2", (tuple(w[-1]), tuple(w[-1])), (0.0, 0.0),
              (ForceSample(0, (("a", (0.0, 0.0, 68.67)),), (0.0, 0.0, 0.0), 0.0),), 0.0)
    return Plan(
        robot={"name": "toy", "spec": spec, "spec_sha256": sha256_json(spec), "urdf": urdf,
               "urdf_sha256": sha256_text(urdf)},
        terrain={"name": terrain.name, "data": terrain.to_dict(), "sha256": terrain.content_hash()},
        query={"start": {"stance": {"a": "h0", "b": "h1"}, "q": list(w[0])},
               "goal": {"type": "height", "height": 0.5}},
        seed=seed, steps=(s0, s1), settings={"planner": "LazyPRM", "space": "projected"},
        totals={"steps": 2, "execution_s": 1.25}, versions={"numpy": np.__version__},
        timings={"planning_s": 0.123}, climb_ompl_version="0.1.0")


def test_schema_ships_with_the_package_and_is_a_valid_schema():
    path = resources.files("climb_ompl").joinpath("schemas", "plan.schema.json")
    assert path.is_file()
    jsonschema.Draft202012Validator.check_schema(plan_schema())
    assert plan_schema()["properties"]["schema_version"]["const"] == SCHEMA_VERSION


def test_save_load_round_trips_exactly(tmp_path):
    plan = make_plan()
    out = plan.save(tmp_path / "p.json")
    back = Plan.load(out)
    assert back == plan
    assert back.to_json() == out.read_text()
    # awkward floats survive bit for bit
    assert back.steps[0].waypoints[1][1] == 2 / 3
    assert back.steps[0].waypoints[2][2] == 5e-324
    assert math.copysign(1.0, back.steps[0].waypoints[2][1]) == -1.0
    assert [s.stance_after for s in back.steps] == [(("a", "h0"),), (("a", "h0"), ("b", "h2"))]
    assert back.execution_s == pytest.approx(1.25)
    assert back.final_stance == (("a", "h0"), ("b", "h2"))


@settings(max_examples=40, derandomize=True, deadline=None)
@given(st.lists(st.lists(st.floats(allow_nan=False, allow_infinity=False, width=64), min_size=3, max_size=3),
                min_size=3, max_size=3))
def test_round_trip_any_finite_floats(w):
    plan = make_plan(w)
    back = Plan.from_dict(json.loads(plan.to_json()))
    assert back == plan and back.unchanged  # the steps' digest survives the round trip too


def test_steps_sha256_tells_an_edited_file_from_one_as_written(tmp_path):
    """``steps_sha256`` is the SHA-256 of the canonical JSON of the query, steps and events (computed here with
    hashlib directly); a file read back is ``unchanged`` until a waypoint, the start or the steps are edited, and
    a file without the digest (written before it existed) is not."""
    import hashlib

    plan = make_plan()
    d = json.loads(plan.save(tmp_path / "p.json").read_text())
    body = {"query": d["query"], "steps": d["steps"], "events": d.get("events", [])}
    assert d["steps_sha256"] == hashlib.sha256(json.dumps(body, sort_keys=True, separators=(",", ":")).encode()
                                               ).hexdigest()
    assert Plan.from_dict(d).unchanged and not plan.unchanged  # (a plan made in this process was never written)
    for edit in (lambda e: e["steps"][0]["waypoints"][1].__setitem__(0, 0.5),
                 lambda e: e["query"]["start"]["q"].__setitem__(0, 1.0),
                 lambda e: e.update(steps=e["steps"][:1]),
                 lambda e: e.pop("steps_sha256")):
        e = json.loads(json.dumps(d))
        edit(e)
        assert not Plan.from_dict(e).unchanged


def test_canonical_json_ignores_only_timings():
    a, b = make_plan(), make_plan()
    b2 = Plan(**{**b.__dict__, "timings": {"planning_s": 99.0}})
    assert canonical_json(a) == canonical_json(b2)
    assert a.to_json() != b2.to_json()
    assert canonical_json(a) != canonical_json(make_plan(seed=4))


@pytest.mark.parametrize(
    "mutate, path",
    [
        (lambda d: d.pop("schema_version"), "$"),
        (lambda d: d.update(schema_version=2), "$.schema_version"),
        (lambda d: d.update(kind="walk"), "$.kind"),
        (lambda d: d.pop("steps"), "$"),
        (lambda d: d["steps"][1].update(action="jump"), "$.steps[1].action"),
        (lambda d: d["steps"][0]["waypoints"][2].__setitem__(1, "x"), "$.steps[0].waypoints[2][1]"),
        (lambda d: d["steps"][0]["forces"][1]["forces"].update(a=[1, 2]), "$.steps[0].forces[1].forces.a"),
        (lambda d: d["robot"].update(spec_sha256="abc"), "$.robot.spec_sha256"),
        (lambda d: d["query"]["goal"].pop("height"), "$.query.goal"),
        (lambda d: d["query"]["goal"].update(type="hold", limb="a"), "$.query.goal"),
        (lambda d: d["steps"][0]["times"].__setitem__(1, -1.0), "$.steps[0].times[1]"),
    ],
)
def test_schema_errors_name_the_json_path(tmp_path, mutate, path):
    d = make_plan().to_dict()
    mutate(d)
    f = tmp_path / "bad.json"
    f.write_text(json.dumps(d))
    with pytest.raises(PlanFileError) as exc:
        Plan.load(f)
    assert exc.value.field == path, str(exc.value)
    assert str(f) in str(exc.value)


def test_unreadable_and_non_json_files(tmp_path):
    with pytest.raises(PlanFileError, match="cannot read"):
        Plan.load(tmp_path / "missing.json")
    bad = tmp_path / "bad.json"
    bad.write_text('{"schema_version": 1,\n  "kind": ')
    with pytest.raises(PlanFileError) as exc:
        Plan.load(bad)
    assert exc.value.field == "line 2"
    bad.write_text('{"schema_version": 1,\n  "kind": "clim')  # json's message ends in "starting at"
    with pytest.raises(PlanFileError, match="Unterminated string starting at column 11"):
        Plan.load(bad)


def test_other_kinds_pass_the_common_schema_but_are_not_climb_plans(tmp_path):
    d = {"schema_version": 1, "kind": "treebot", "climb_ompl_version": "0.1.0", "seed": 0,
         "anything": {"the": ["treebot planner", "writes"]}}
    f = tmp_path / "t.json"
    f.write_text(json.dumps(d))
    assert read_plan_dict(f) == d
    with pytest.raises(PlanFileError, match="not a climb plan"):
        Plan.load(f)
    d["seed"] = "zero"
    f.write_text(json.dumps(d))
    with pytest.raises(PlanFileError) as exc:
        read_plan_dict(f)
    assert exc.value.field == "$.seed"


def test_save_is_atomic_on_a_bad_folder(tmp_path):
    from climb_ompl.errors import InputError

    with pytest.raises(InputError):
        make_plan().save(tmp_path / "nope" / "p.json")
    assert not (tmp_path / "nope").exists()
