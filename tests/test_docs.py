"""The developer docs follow the code: docs/architecture.md's layer table is tests/test_layers.py's, it names every
module of the package, and no page names a module path the package no longer has."""

from __future__ import annotations

import re
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PKG = ROOT / "climb_ompl"
ARCH = (ROOT / "docs" / "architecture.md").read_text()


def _allowed() -> dict[str, set[str]]:
    # the table of tests/test_layers.py, read from its source (importing it would build the whole import graph)
    import ast

    tree = ast.parse((ROOT / "tests" / "test_layers.py").read_text())
    for node in tree.body:
        if isinstance(node, ast.AnnAssign) and getattr(node.target, "id", "") == "ALLOWED":
            return {k: set(v) for k, v in ast.literal_eval(node.value).items()}
    raise AssertionError("tests/test_layers.py defines no ALLOWED")


def _doc_table() -> dict[str, set[str]]:
    rows = re.findall(r"^\| `(\w+)` \| ([^|]+) \|", ARCH, flags=re.M)
    return {layer: set() if deps.strip() == "-" else {d.strip() for d in deps.split(",")} for layer, deps in rows
            if layer in _allowed()}


def test_the_layer_table_is_the_one_the_layer_test_enforces():
    assert _doc_table() == _allowed()


def _sections() -> dict[str, str]:
    """The architecture page's module listing by subpackage (``""``: the root), from its "Root" and ```pkg/```
    paragraphs."""
    listing = ARCH[ARCH.index("Root (infrastructure):"):]
    parts = re.split(r"^(?=`\w+/`)", listing, flags=re.M)
    out = {"": parts[0]}
    for part in parts[1:]:
        out[part[1:part.index("/")]] = part
    return out


def test_every_module_is_named_in_its_subpackage_on_the_architecture_page():
    sections = _sections()
    missing = []
    for p in sorted(PKG.rglob("*.py")):
        rel = p.relative_to(PKG)
        if rel.name in ("__init__.py", "__main__.py"):  # the package itself, its section heading
            continue
        pkg = rel.parts[0] if len(rel.parts) > 1 else ""
        if pkg not in sections or f"`{rel.name}`" not in sections[pkg] and f" {rel.name}" not in sections[pkg]:
            missing.append(str(rel))
    assert missing == []


#: Module paths of the layout before the subpackages (and the ``bench.py`` module that became ``bench/_runs.py``).
OLD = (r"verify_climb", r"verify_kinds", r"verify_tree\.py", r"verify_slope\.py", r"robot_spec", r"robot_files",
       r"robot_collision", r"(?<!\w)query_set\b", r"(?<!\w)planners_report\b", r"bench_plots", r"\bgaits\b",
       r"climb_ompl[./]benchmarks", r"(?<!test_)slope_(chain|geometry|robot|plot)\b",
       r"climb_ompl/(plan|search|onestep|robot|terrain|_ompl|bench|multistep|transition|stance)\.py",
       r"(?<![\w.])bench\.(RunWorker|WORKER_RUNS|make_queries)")


@pytest.mark.parametrize("page", sorted(p.relative_to(ROOT).as_posix() for p in [ROOT / "README.md",
                                                                                   *(ROOT / "docs").rglob("*.md")]))
def test_no_page_names_an_old_module_path(page):
    text = (ROOT / page).read_text()
    assert [m.group(0) for old in OLD for m in re.finditer(old, text)] == []
