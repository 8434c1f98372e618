"""The package's layers: each subpackage imports only the layers below it, with no cycles between modules.

The import graph is read from the source with :mod:`ast`, imports inside functions included (a lazy import is
still a dependency).  The table below is the one in docs/architecture.md; a change of layers changes both.
"""

from __future__ import annotations

import ast
import subprocess
import sys
from pathlib import Path

import pytest

PKG = Path(__file__).resolve().parents[1] / "climb_ompl"

#: Each layer and the layers it may import (besides itself).  ``root`` is infrastructure (errors, files, settings,
#: names); ``api`` is the public surface (``climb_ompl/__init__.py``, ``__main__``).
ALLOWED: dict[str, set[str]] = {
    "root": set(),
    "equilibrium": {"root"},
    "model": {"root", "equilibrium"},
    "manifold": {"root", "equilibrium", "model"},
    "plan": {"root", "equilibrium", "model"},
    "trajectory": {"root", "equilibrium", "model", "plan"},
    "climb": {"root", "equilibrium", "model", "manifold", "plan", "trajectory"},
    "treebot": {"root", "equilibrium", "model", "plan"},
    "mrwallspect": {"root", "equilibrium", "model", "plan"},
    "verification": {"root", "equilibrium", "model", "plan", "treebot", "mrwallspect"},
    "viz": {"root", "equilibrium", "model", "manifold", "plan", "trajectory", "climb", "treebot", "mrwallspect",
            "verification"},
    "export": {"root", "equilibrium", "model", "manifold", "plan", "trajectory", "climb", "treebot", "mrwallspect",
               "verification", "viz"},
    "console": {"root", "equilibrium", "model", "manifold", "plan", "trajectory", "climb", "treebot", "mrwallspect",
                "verification", "viz"},
    "bench": {"root", "equilibrium", "model", "manifold", "plan", "trajectory", "climb", "treebot", "mrwallspect",
              "verification", "viz", "export", "console"},
    "cli": {"root", "equilibrium", "model", "manifold", "plan", "trajectory", "climb", "treebot", "mrwallspect",
            "verification", "viz", "export", "console", "bench", "api"},
    "api": {"root", "equilibrium", "model", "manifold", "plan", "trajectory", "climb", "treebot", "mrwallspect",
            "verification", "viz", "export", "console", "bench", "cli"},
}

#: At most this many modules at the package root (infrastructure only).
MAX_ROOT_MODULES = 12
#: No function longer than this many lines, no class longer than that (a class past it holds several jobs).
MAX_FUNCTION_LINES, MAX_CLASS_LINES = 100, 400


def _modules() -> dict[str, Path]:
    """Dotted module name -> file, packages under their package's name."""
    out = {}
    for p in sorted(PKG.rglob("*.py")):
        parts = list(p.relative_to(PKG.parent).with_suffix("").parts)
        if parts[-1] == "__init__":
            parts = parts[:-1]
        out[".".join(parts)] = p
    return out


MODULES = _modules()


def layer(mod: str) -> str:
    parts = mod.split(".")
    if len(parts) == 1 or parts[1] == "__main__":
        return "api"
    if len(parts) == 2 and (PKG / f"{parts[1]}.py").exists():
        return "root"
    return parts[1]


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or \
        (isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING")


def _dynamic_import(node: ast.AST) -> bool:
    """A call importing a module of the package by its name as a string constant."""
    if not (isinstance(node, ast.Call) and node.args and isinstance(node.args[0], ast.Constant)
            and isinstance(node.args[0].value, str) and node.args[0].value.startswith("climb_ompl")):
        return False
    f = node.func
    return (isinstance(f, ast.Name) and f.id == "__import__") or (isinstance(f, ast.Attribute) and
                                                                  f.attr == "import_module")


def _imports(mod: str) -> set[str]:
    """The package's modules that ``mod`` imports, anywhere in its source."""
    path = MODULES[mod]
    pkg = mod.split(".") if path.name == "__init__.py" else mod.split(".")[:-1]
    found = set()
    tree = ast.parse(path.read_text())
    typing_only = {id(n) for block in ast.walk(tree) if isinstance(block, ast.If) and _is_type_checking(block.test)
                   for stmt in block.body for n in ast.walk(stmt)}
    for node in ast.walk(tree):
        if id(node) in typing_only:  # `if TYPE_CHECKING:` imports never run
            continue
        if isinstance(node, ast.Import):
            names = [a.name for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            base = ".".join(pkg[: len(pkg) - node.level + 1]) if node.level else ""
            src = ".".join(p for p in (base, node.module or "") if p)
            names = [f"{src}.{a.name}" if f"{src}.{a.name}" in MODULES else src for a in node.names]
        elif _dynamic_import(node):  # __import__("climb_ompl.x") / importlib.import_module("climb_ompl.x")
            names = [node.args[0].value]
        else:
            continue
        for name in names:
            while name and name not in MODULES:  # `import a.b.c` of an attribute: its module
                name = name.rpartition(".")[0]
            if name and name != mod:
                found.add(name)
    return found


GRAPH = {m: _imports(m) for m in MODULES}


def test_the_table_names_every_subpackage():
    subpackages = {p.parent.name for p in PKG.glob("*/__init__.py")}
    assert subpackages | {"root", "api"} == set(ALLOWED)


def test_no_layer_imports_a_higher_one():
    upward = sorted(f"{m} ({layer(m)}) imports {t} ({layer(t)})" for m, ts in GRAPH.items() for t in ts
                    if layer(t) != layer(m) and layer(t) not in ALLOWED[layer(m)])
    assert upward == []


def test_no_import_cycles_between_modules():
    # Tarjan's strongly connected components; any component of two or more modules is a cycle.
    index: dict[str, int] = {}
    low: dict[str, int] = {}
    stack: list[str] = []
    on: set[str] = set()
    cycles: list[list[str]] = []

    def visit(v: str) -> None:
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(GRAPH[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            if len(comp) > 1:
                cycles.append(sorted(comp))

    sys.setrecursionlimit(10_000)
    for v in sorted(GRAPH):
        if v not in index:
            visit(v)
    assert cycles == []


def test_the_verifier_imports_nothing_of_the_planner():
    bad = sorted(f"{m} -> {t}" for m, ts in GRAPH.items() if layer(m) == "verification" for t in ts
                 if layer(t) in {"climb", "manifold"})
    assert bad == []


def test_the_root_holds_few_modules():
    root = sorted(p.name for p in PKG.glob("*.py") if p.name not in ("__init__.py", "__main__.py"))
    assert len(root) <= MAX_ROOT_MODULES, root


def test_no_function_or_class_is_a_room_of_its_own():
    long = []
    for mod, path in MODULES.items():
        for node in ast.walk(ast.parse(path.read_text())):
            size = getattr(node, "end_lineno", 0) - getattr(node, "lineno", 0) + 1
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)) and size > MAX_FUNCTION_LINES:
                long.append(f"{mod}.{node.name}: function of {size} lines")
            elif isinstance(node, ast.ClassDef) and size > MAX_CLASS_LINES:
                long.append(f"{mod}.{node.name}: class of {size} lines")
    assert sorted(long) == []


def test_the_graph_reader_sees_imports_inside_functions():
    # the checker itself must be able to fail: a function-level import is an edge
    assert "climb_ompl.manifold._ompl" in GRAPH["climb_ompl.climb.onestep"]
    assert any(layer(t) == "climb" for t in GRAPH["climb_ompl.cli.plan"])
    assert "climb_ompl.treebot" in GRAPH["climb_ompl.viz._plans"]  # an import by a string name


@pytest.mark.parametrize("module", ["climb_ompl.settings", "climb_ompl.model.robot", "climb_ompl.model.terrain",
                                    "climb_ompl.plan.file", "climb_ompl.verification"])
def test_settings_models_and_plans_load_without_ompl(module):
    code = (f"import sys, {module}; from climb_ompl.model.robot import RobotModel; from climb_ompl.settings import "
            "ClimbSettings; RobotModel.load('lemur'); ClimbSettings.for_search('guided'); "
            "bad = sorted(m for m in sys.modules if m == 'ompl' or m.startswith('ompl.') or m == 'meshcat'); "
            "print(bad); sys.exit(1 if bad else 0)")
    r = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stdout + r.stderr
