"""TreeBot tree model: bundled trees, YAML round trip, generator, bad files (Lam et al., section III)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from climb_ompl.errors import InputError
from climb_ompl.treebot import Tree, TreeError, bundled_trees, generate_tree, three_branch_layout

BAD = Path(__file__).parent / "data" / "bad_trees"

# file -> (field named in the error, words of the reason)
BAD_CASES = {
    "missing_rings": ("branches[1].rings", "no rings"),
    "no_rings_field": ("branches[1].rings", "no rings"),
    "zero_normal": ("branches[0].rings[1].normals[2]", "zero normal"),
    "orphan_branch": ("branches[1].parent", "'limb7', which is not a branch"),
    "normals_count": ("branches[0].rings[0].normals", "expected 4 normals"),
    "attach_out_of_range": ("branches[1].attach_ring", "0..2"),
    "two_trunks": ("branches", "exactly one branch"),
    "cycle": ("branches[2].parent", "cycle"),
    "obstacle_index": ("branches[0].rings[0].obstacles[1]", "0..3"),
    "too_few_points": ("branches[0].rings[2].points", "at least 3"),
    "unknown_field": ("branches[0].ringz", "unknown field"),
    "bad_point": ("branches[0].rings[0].points[0]", "[x, y, z]"),
    "not_a_mapping": ("(top level)", "mapping"),
    "invalid_yaml": ("line 3", "invalid YAML"),
    "one_ring": ("branches[1].rings", "at least 2"),  # passed validate, then crashed the planner's bark mesh
    "coincident_rings": ("branches[1].rings[1]", "at least 1 mm apart"),  # planned, then refused by verify
    "parent_not_a_name": ("branches[1].parent", "expected the name of a branch"),  # a TypeError traceback
}


def test_every_bad_file_has_a_case():
    assert sorted(p.stem for p in BAD.glob("*.yaml")) == sorted(BAD_CASES)


@pytest.mark.parametrize("name", sorted(BAD_CASES))
def test_bad_tree_files_give_clear_errors(name):
    field, words = BAD_CASES[name]
    with pytest.raises(TreeError) as info:
        Tree.load(BAD / f"{name}.yaml")
    err = info.value
    assert isinstance(err, InputError)
    assert err.field == field
    assert words in err.reason
    assert str(BAD / f"{name}.yaml") in str(err)


def test_unknown_tree_name_lists_bundled():
    with pytest.raises(TreeError, match="three-branch"):
        Tree.load("no-such-tree")


def test_bundled_trees_load_and_round_trip():
    names = bundled_trees()
    assert {"three-branch", "young-oak"} <= set(names)
    for name in names:
        t = Tree.load(name)
        again = Tree.from_dict(t.to_dict())
        assert again.content_hash() == t.content_hash()
        for b in t.branches:
            for r in b.rings:
                assert np.allclose(np.linalg.norm(r.normals, axis=1), 1.0)
    fig11 = Tree.load("three-branch")
    assert [(b.name, b.parent) for b in fig11.branches] == [("trunk", None), ("b2", "trunk"), ("b3", "trunk")]


def test_ring_sequence_follows_the_branch_chain():
    t = Tree.load("young-oak")
    seq = t.ring_sequence("b4")  # trunk -> b3 -> b4
    b3, b4 = t.branch("b3"), t.branch("b4")
    expected = ([("trunk", i) for i in range(b3.attach_ring + 1)] + [("b3", i) for i in range(b4.attach_ring + 1)]
                + [("b4", i) for i in range(len(b4.rings))])
    assert seq == expected


def test_generator_is_seeded_and_geometric():
    a = generate_tree(3, layout=three_branch_layout())
    b = generate_tree(3, layout=three_branch_layout())
    c = generate_tree(4, layout=three_branch_layout())
    assert a.content_hash() == b.content_hash() != c.content_hash()
    trunk = a.root
    for r in trunk.rings:
        centre = r.points.mean(axis=0)
        # normals point outwards: along the radial direction, not against it
        radial = r.points - centre
        assert np.all(np.sum(radial * r.normals, axis=1) > 0)
    # radius tapers along the trunk
    rad = [np.linalg.norm(r.points - r.points.mean(0), axis=1).mean() for r in trunk.rings]
    assert rad[-1] < rad[0]
