"""Shared test helpers: the repository root, running the CLI in-process or as a real subprocess."""

from __future__ import annotations

import os
import subprocess
import sys
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "tests" / "data"


def pytest_configure(config: pytest.Config) -> None:
    """The on-disk cache (reach maps) in a folder of this run, never the user's: every run probes afresh, and
    the tests' subprocesses (the CLI, notebooks, bench cells) share it."""
    import tempfile

    config._climb_cache = tempfile.mkdtemp(prefix="climb-ompl-cache-")  # type: ignore[attr-defined]
    os.environ["CLIMB_OMPL_CACHE"] = config._climb_cache  # type: ignore[attr-defined]


def pytest_unconfigure(config: pytest.Config) -> None:
    import shutil

    folder = getattr(config, "_climb_cache", None)
    if folder:
        shutil.rmtree(folder, ignore_errors=True)


#: Seconds each of the longest test files takes on one ``make test`` worker (2 cores, beside other jobs; per-file
#: sums of a ``--junitxml`` report of the tests not marked slow, rounded).  ``--dist loadfile`` hands out files by
#: how many tests they hold, most first, which sends the few-test long files (browser, suite) last: one worker could
#: run the last of them while the other had nothing left (up to 10 % of the wall time).  The files listed here go
#: out first, longest first, the rest after them in pytest-xdist's order.  The figures need only be roughly right;
#: a file missing from the table (or a table out of date) costs balance, never a test.
FILE_SECONDS = {
    "test_plan_cli.py": 128, "test_replan.py": 83, "test_bench.py": 70, "test_multistep.py": 60,
    "test_verify_slope.py": 36, "test_suite.py": 31, "test_verify.py": 29, "test_robot_quadrupeds.py": 21,
    "test_viz.py": 18, "test_bad_input.py": 18, "test_onestep.py": 17, "test_frontier.py": 17,
    "test_viz_browser_checks.py": 15, "test_start_release.py": 15, "test_equilibrium_oracles.py": 14,
    "test_viz_browser.py": 12, "test_planners.py": 12,
}


@pytest.hookimpl(optionalhook=True, tryfirst=True)
def pytest_xdist_make_scheduler(config: pytest.Config, log: object) -> object:
    """``--dist loadfile`` with the files of :data:`FILE_SECONDS` handed out first, longest first."""
    if config.getvalue("dist") != "loadfile":
        return None
    from xdist.scheduler import LoadFileScheduling

    class LongestFilesFirst(LoadFileScheduling):
        def _assign_work_unit(self, node: object) -> None:
            queue = getattr(self, "workqueue", None)
            if queue:
                first = max(queue, key=lambda scope: FILE_SECONDS.get(Path(scope).name, 0))  # the earliest of ties
                queue.move_to_end(first, last=False)
            super()._assign_work_unit(node)  # type: ignore[arg-type]

    return LongestFilesFirst(config, log)  # type: ignore[arg-type]


@dataclass
class CliResult:
    """Exit code and captured output of one ``climb-ompl`` invocation."""

    code: int
    out: str
    err: str


@pytest.fixture
def cli(capsys: pytest.CaptureFixture[str]) -> Callable[..., CliResult]:
    """Run ``climb-ompl ARGS`` in this process (fast); returns exit code, stdout and stderr."""
    from climb_ompl.cli import main

    def run(*args: str) -> CliResult:
        capsys.readouterr()
        code = main([str(a) for a in args])
        cap = capsys.readouterr()
        return CliResult(code, cap.out, cap.err)

    return run


def run_subprocess(args: list[str], *, env: dict[str, str] | None = None, timeout: float = 120.0,
                   cwd: Path | None = None) -> subprocess.CompletedProcess[str]:
    """Run ``python ARGS`` with this interpreter in a fresh process (real exit codes, real exit path)."""
    full_env = {**os.environ, **(env or {})}
    return subprocess.run([sys.executable, *args], capture_output=True, text=True, timeout=timeout,
                          env=full_env, cwd=cwd or ROOT)


@pytest.fixture
def cli_subprocess() -> Callable[..., subprocess.CompletedProcess[str]]:
    """Run ``python -m climb_ompl ARGS`` in a subprocess."""

    def run(*args: str, **kw: object) -> subprocess.CompletedProcess[str]:
        return run_subprocess(["-m", "climb_ompl", *[str(a) for a in args]], **kw)  # type: ignore[arg-type]

    return run


#: A small 2-D test terrain for the planar three-limbed robot: two support holds (a, b) and two targets (c, d).
PLANAR_TEST_TERRAIN = {"name": "planar-test", "dim": 2, "friction": 0.8, "holds": [
    {"id": "a", "position": [-0.35, 0.8], "normal": [0.4, 1]},
    {"id": "b", "position": [0.35, 0.8], "normal": [-0.4, 1]},
    {"id": "c", "position": [-0.3, 1.4], "normal": [0.3, 1]},
    {"id": "d", "position": [0.3, 1.35], "normal": [-0.3, 1]}]}


@pytest.fixture(scope="session")
def planar_move():
    """(robot, terrain, stance, q_start, q_goal): limb3 moves from hold c to d while limb1/limb2 hold a/b."""
    from climb_ompl.climb.onestep import find_transition
    from climb_ompl.manifold.stance import Stance
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain

    robot = RobotModel.load("planar-3limb")
    terrain = Terrain.from_dict(PLANAR_TEST_TERRAIN)
    s = Stance(limb1="a", limb2="b")
    qs = find_transition(robot, terrain, s, s.with_hold("limb3", "c"), seed=1)
    qg = find_transition(robot, terrain, s, s.with_hold("limb3", "d"), seed=2)
    assert qs is not None and qg is not None
    return robot, terrain, s, qs, qg


@pytest.fixture(scope="module")
def lemur_start():
    """LEMUR on the demo wall at the start the start finder gives (seed 0): robot, wall, stance, configuration."""
    from climb_ompl.climb.start import find_start
    from climb_ompl.manifold.stance import Stance
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain

    robot, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    st = find_start(robot, wall, seed=0)
    assert st.found
    return robot, wall, Stance(st.stance), st.q
