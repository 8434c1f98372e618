"""``climb-ompl treebot plan``: plan file, exit codes, and the drawable scene for playback."""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from climb_ompl.cli import main
from climb_ompl.treebot import Tree, scene_items

BAD = Path(__file__).parent / "data" / "bad_trees"


@pytest.mark.heavy
def test_plan_file(tmp_path, capsys):
    out = tmp_path / "plan.json"
    assert main(["treebot", "plan", "--tree", "three-branch", "--target", "b2", "--seed", "3", "--out", str(out)]) == 0
    plan = json.loads(out.read_text())
    for key in ("schema_version", "kind", "climb_ompl_version", "seed", "tree", "target", "path", "motion", "cost",
                "stats"):
        assert key in plan
    assert plan["schema_version"] == 1 and plan["kind"] == "treebot" and plan["seed"] == 3
    tree = dict(plan["tree"])
    h = tree.pop("tree_hash")
    assert Tree.from_dict(tree).content_hash() == h == Tree.load("three-branch").content_hash()
    assert plan["path"][-1]["branch"] == "b2"
    sc = scene_items(plan)
    assert len(sc["rings"]) == sum(len(b["rings"]) for b in plan["tree"]["branches"])
    assert sc["path"].shape == (len(plan["path"]), 3)
    assert len(sc["frames"]) == len(plan["motion"]["frames"]) > 0
    for f in sc["frames"]:
        assert np.linalg.norm(f["body"][0] - f["rear"]) < 1e-6 and np.linalg.norm(f["body"][-1] - f["front"]) < 1e-6
    assert len(sc["obstacle_points"]) > 0 and sc["gripping_points"].shape[1] == 3


@pytest.mark.heavy
def test_exit_codes(tmp_path, capsys):
    out = tmp_path / "p.json"
    assert main(["treebot", "plan", "--tree", str(BAD / "zero_normal.yaml"), "--target", "b2", "--out", str(out)]) == 2
    assert "zero normal" in capsys.readouterr().err
    assert main(["treebot", "plan", "--tree", "three-branch", "--target", "b9", "--out", str(out)]) == 2
    d = Tree.load("three-branch").to_dict()
    d["branches"][0]["rings"][4]["obstacles"] = list(range(len(d["branches"][0]["rings"][4]["points"])))
    blocked = tmp_path / "blocked.yaml"
    blocked.write_text(Tree.from_dict(d).to_yaml())
    with pytest.raises(SystemExit) as info:
        main(["treebot", "plan", "--tree", str(blocked), "--target", "b2", "--out", str(out)])
    assert info.value.code == 1
    assert "ring 4 of branch 'trunk'" in capsys.readouterr().err
    assert not out.exists()


def test_generate_and_validate(tmp_path):
    out = tmp_path / "t.yaml"
    assert main(["treebot", "generate", "--seed", "5", "--out", str(out)]) == 0
    assert main(["treebot", "validate", str(out)]) == 0
    assert main(["treebot", "validate", str(BAD / "orphan_branch.yaml")]) == 2
