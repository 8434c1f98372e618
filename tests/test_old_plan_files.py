"""A plan file written by an earlier layout of the package (0.1.0, before its modules moved into subpackages)
still loads, verifies and replays to the same plan: plan files name no module of the package."""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

import pytest

from climb_ompl import Plan, verify

OLD = Path(__file__).parent / "data" / "plans" / "double-link-pegs-0.1.0.json"


def test_an_old_plan_file_loads_and_verifies():
    plan = Plan.load(OLD)
    assert len(plan.steps) == 7
    rep = verify(plan)
    assert rep.ok, rep.summary()


def test_the_verify_command_accepts_an_old_plan_file():
    r = subprocess.run([sys.executable, "-m", "climb_ompl", "verify", str(OLD)], capture_output=True, text=True,
                       timeout=300)
    assert r.returncode == 0, r.stdout + r.stderr
    assert "valid" in r.stdout


@pytest.mark.climb
def test_an_old_plan_file_replays_to_the_same_route(tmp_path):
    # the route of Bretl (2006), Fig. 13 (pegs 1 -> 2 -> 3 -> 2 -> 4); waypoints may differ in the last bits on
    # another machine, the route does not
    out = tmp_path / "again.json"
    r = subprocess.run([sys.executable, "-m", "climb_ompl", "plan", "--replay", str(OLD), "--out", str(out)],
                       capture_output=True, text=True, timeout=600)
    assert r.returncode == 0, r.stdout + r.stderr
    old, new = json.loads(OLD.read_text()), json.loads(out.read_text())
    assert [(s["action"], s.get("limb"), s.get("hold")) for s in new["steps"]] == \
        [(s["action"], s.get("limb"), s.get("hold")) for s in old["steps"]]
