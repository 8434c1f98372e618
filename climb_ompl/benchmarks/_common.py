"""Shared machinery of the benchmarks: isolated subprocess, JSON envelope, one-line summary."""

from __future__ import annotations

import datetime as _dt
import importlib
import json
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path
from typing import Any

from .._io import atomic_write_json
from ..errors import ClimbError


class BenchmarkFailed(ClimbError):
    """A benchmark subprocess crashed or exceeded its timeout."""


def envelope(name: str, params: dict[str, Any]) -> dict[str, Any]:
    """Common keys of every benchmark JSON file."""
    from .. import __version__

    return {
        "benchmark": name,
        "climb_ompl_version": __version__,
        "created_utc": _dt.datetime.now(_dt.timezone.utc).isoformat(timespec="seconds"),
        "machine": {"python": platform.python_version(), "platform": platform.platform(),
                    "cpus": os.cpu_count()},
        "params": params,
    }


def execute(name: str, params: dict[str, Any], out: Path | None, timeout: float = 3600.0) -> dict[str, Any]:
    """Run benchmark ``name`` with ``params`` in a subprocess; write ``out``; print the summary.

    Raises:
        BenchmarkFailed: the subprocess exited non-zero or ran past ``timeout`` seconds.
    """
    with tempfile.TemporaryDirectory() as tmp:
        res_path = Path(tmp) / "result.json"
        cmd = [sys.executable, "-m", "climb_ompl.benchmarks._common", name, json.dumps(params), str(res_path)]
        try:
            proc = subprocess.run(cmd, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise BenchmarkFailed(f"benchmark {name!r} exceeded its timeout of {timeout:.0f} s") from None
        if proc.returncode != 0 or not res_path.exists():
            raise BenchmarkFailed(f"benchmark {name!r} failed (exit code {proc.returncode})")
        result = json.loads(res_path.read_text())
    if out is not None:
        atomic_write_json(out, result)
    mod = importlib.import_module(f"climb_ompl.benchmarks.{name}")
    print(f"[{name}] {mod.summary(result)}" + (f"  -> {out}" if out else ""))
    return result


def _child(name: str, params_json: str, res_path: str) -> None:
    mod = importlib.import_module(f"climb_ompl.benchmarks.{name}")
    params = json.loads(params_json)
    result = envelope(name, params)
    result.update(mod.run(**params))
    Path(res_path).write_text(json.dumps(result, indent=2, sort_keys=True, default=float))


if __name__ == "__main__":
    _child(*sys.argv[1:4])
