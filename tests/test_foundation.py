"""Foundation: cheap import, one exception family, benchmark subprocess isolation, set-up files and docs."""

from __future__ import annotations

import inspect
import re
import subprocess
import textwrap
import tomllib
from pathlib import Path

import pytest
import yaml
from conftest import ROOT, run_subprocess

from climb_ompl import errors
from climb_ompl.bench import _common
from climb_ompl.model.terrain import Terrain


def test_import_is_cheap() -> None:
    """``import climb_ompl`` loads neither OMPL, nor meshcat, nor Pinocchio: the CLI and light users start fast."""
    heavy = "('ompl', 'meshcat', 'pinocchio', 'cvxpy')"
    code = f"import sys, climb_ompl; print(sorted(m for m in {heavy} if m in sys.modules))"
    proc = run_subprocess(["-c", code])
    assert proc.returncode == 0 and proc.stdout.strip() == "[]", proc.stdout + proc.stderr


def test_every_error_is_a_climb_error() -> None:
    from climb_ompl.manifold._ompl import PlannerUnavailable

    classes = [c for _, c in inspect.getmembers(errors, inspect.isclass) if issubclass(c, Exception)]
    assert len(classes) >= 5
    for cls in [*classes, PlannerUnavailable, _common.BenchmarkFailed]:
        assert issubclass(cls, errors.ClimbError), cls
    e = errors.TerrainError("f.yaml", "holds[2].normal", "zero normal")
    assert str(e) == "f.yaml: holds[2].normal: zero normal" and e.field == "holds[2].normal"


# ---- benchmark subprocess isolation ----------------------------------------------------------------
BENCH_MODULE = '''
import os, time
def run(mode="ok", n=3):
    if mode == "crash":
        os.abort()
    if mode == "hang":
        time.sleep(60)
    return {"values": list(range(n)), "pid": os.getpid()}
def summary(result):
    return f"{len(result['values'])} values"
'''


@pytest.fixture
def bench_module(tmp_path: Path, monkeypatch: pytest.MonkeyPatch) -> str:
    pkg = tmp_path / "fakebench"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("")
    (pkg / "mod.py").write_text(textwrap.dedent(BENCH_MODULE))
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("PYTHONPATH", str(tmp_path))
    return "fakebench.mod"


def test_benchmark_runs_in_a_subprocess_and_writes_json(bench_module: str, tmp_path: Path, capsys) -> None:
    import json
    import os

    out = tmp_path / "sub" / "r.json"
    res = _common.execute(bench_module, {"n": 4}, out)
    assert res["values"] == [0, 1, 2, 3] and res["pid"] != os.getpid()
    for key in ("benchmark", "climb_ompl_version", "created_utc", "machine", "params"):
        assert key in res
    assert res["params"] == {"n": 4}
    assert json.loads(out.read_text()) == res
    assert "[fakebench.mod] 4 values" in capsys.readouterr().out


@pytest.mark.heavy
@pytest.mark.parametrize("mode, timeout, match", [("crash", 60.0, "failed"), ("hang", 1.0, "timeout")])
def test_crashing_or_hanging_benchmark_is_contained(bench_module: str, tmp_path: Path, mode: str,
                                                    timeout: float, match: str) -> None:
    out = tmp_path / "r.json"
    with pytest.raises(_common.BenchmarkFailed, match=match) as info:
        _common.execute(bench_module, {"mode": mode}, out, timeout=timeout)
    assert info.value.exit_code == 1
    assert not out.exists()
    if mode == "crash":
        assert "exit code -6" in str(info.value)  # the child aborted, not an import error


def test_benchmark_failure_is_cli_exit_code_1(monkeypatch: pytest.MonkeyPatch) -> None:
    from climb_ompl.cli import app, main

    @app.command("fake-failing-bench", hidden=True)
    def _fail() -> None:
        raise _common.BenchmarkFailed("boom")

    try:
        assert main(["fake-failing-bench"]) == 1
    finally:
        app.registered_commands[:] = [c for c in app.registered_commands if c.name != "fake-failing-bench"]


def test_typer_exit_codes_from_commands_reach_the_process() -> None:
    """``raise error(msg, 1)`` inside a command gives exit code 1 (typer without standalone mode)."""
    from climb_ompl._options import error
    from climb_ompl.cli import app, main

    @app.command("fake-no-result", hidden=True)
    def _no_result() -> None:
        raise error("nothing found", 1)

    try:
        assert main(["fake-no-result"]) == 1
    finally:
        app.registered_commands[:] = [c for c in app.registered_commands if c.name != "fake-no-result"]


# ---- set-up files -----------------------------------------------------------------------------------
def test_makefile_targets_and_ci_script() -> None:
    text = (ROOT / "Makefile").read_text()
    for target in ("demo", "test", "bench", "install"):
        assert re.search(rf"^{target}:", text, re.M), target
    dry = subprocess.run(["make", "-n", "-C", str(ROOT), "test"], capture_output=True, text=True, timeout=60)
    assert dry.returncode == 0, dry.stderr
    assert "requirements.lock" in dry.stdout or (ROOT / ".venv" / ".installed").exists()
    assert "ruff check" in dry.stdout and "pytest" in dry.stdout
    ci = ROOT / ".ci" / "run"
    assert ci.stat().st_mode & 0o111, ".ci/run must be executable"
    assert re.search(r"^[^#]*\bmake test\b", ci.read_text(), re.M) and "set -euo pipefail" in ci.read_text()


def _name(req: str) -> str:
    return re.split(r"[<>=!~\[; ]", req, maxsplit=1)[0].lower().replace("_", "-")


def test_lock_pins_every_dependency_within_its_range() -> None:
    meta = tomllib.loads((ROOT / "pyproject.toml").read_text())["project"]
    lock = {}
    for line in (ROOT / "requirements.lock").read_text().splitlines():
        if line and not line.startswith("#"):
            name, _, version = line.partition("==")
            assert version, f"requirements.lock: {line!r} is not pinned with =="
            lock[name.lower().replace("_", "-")] = version
    for req in [*meta["dependencies"], *meta["optional-dependencies"]["dev"]]:
        assert _name(req) in lock, f"{req} is in pyproject.toml but not in requirements.lock"
    assert lock["ompl"] == "1.7.0"
    assert tuple(int(x) for x in lock["scipy"].split(".")[:3]) >= (1, 15, 3)
    assert "hatchling" in lock  # the editable install runs without build isolation


def test_docs_terrain_example_is_a_valid_terrain() -> None:
    text = (ROOT / "docs" / "terrain.md").read_text()
    blocks = re.findall(r"```yaml\n(.*?)```", text, re.S)
    assert blocks, "docs/terrain.md must show an example"
    t = Terrain.from_dict(yaml.safe_load(blocks[0]), source="docs/terrain.md")
    assert t.hold("peg").type == "grasp" and len(t.surfaces) == 2
    for name in ("pegs", "planar-wall", "demo-wall"):
        assert f"`{name}`" in text
