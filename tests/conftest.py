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
