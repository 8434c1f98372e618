"""``climb-ompl steps PLAN``: a plan's steps as a table and as JSON, checked against the plan file read as plain
JSON (heights from the embedded terrain's hold positions against its gravity)."""

from __future__ import annotations

import json

import numpy as np
from conftest import DATA

PLAN = DATA / "plans" / "double-link-pegs-0.1.0.json"


def test_steps_json_matches_the_file(cli):
    r = cli("steps", PLAN, "--json")
    assert r.code == 0, r.err
    out, raw = json.loads(r.out), json.loads(PLAN.read_text())
    holds = {h["id"]: h for h in raw["terrain"]["data"]["holds"]}
    up = -np.asarray(raw["terrain"]["data"]["gravity"], float)
    up /= np.linalg.norm(up)
    assert [s["index"] for s in out["steps"]] == list(range(len(raw["steps"])))
    for row, step in zip(out["steps"], raw["steps"], strict=True):
        assert (row["action"], row["limb"], row["hold"], row["holds"]) == \
            (step["action"], step["limb"], step["hold"], step["stance"])
        assert abs(row["height"] - float(np.dot(holds[step["hold"]]["position"], up))) < 1e-6
        assert abs(row["duration"] - (step["times"][-1] if step["times"] else 0.0)) < 1e-6
        assert abs(row["margin"] - step["margin"]) < 1e-6
    assert out["events"] == []


def test_steps_table_and_bad_file(cli, tmp_path):
    r = cli("steps", PLAN)
    assert r.code == 0, r.err
    lines = [ln for ln in r.out.splitlines() if ln.lstrip("│ ").split(" ")[0].isdigit()]
    assert len(lines) == len(json.loads(PLAN.read_text())["steps"])
    assert "hangs from" in r.out and "margin m" in r.out
    bad = tmp_path / "bad.json"
    bad.write_text("{")
    r = cli("steps", bad)
    assert r.code == 2 and str(bad) in r.err and r.err.count("\n") == 1
