"""Shared machinery of the benchmarks: isolated subprocess, JSON envelope, one-line summary.

Every benchmark result is one JSON object: the :func:`envelope` keys (``benchmark``,
``climb_ompl_version``, ``created_utc``, ``machine``, ``params``) plus what the benchmark's ``run``
returns.  :func:`execute` runs ``run`` in a child process (``python -m climb_ompl.benchmarks._common``)
with a timeout, so a hung or crashing C++ planner cannot stall or kill the caller.
"""

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
    """A benchmark subprocess crashed, exited non-zero or exceeded its timeout (CLI exit code 1)."""

    exit_code = 1


def module_name(name: str) -> str:
    """The module of benchmark ``name``: ``climb_ompl.benchmarks.<name>``, or ``name`` itself if dotted."""
    return name if "." in name else f"{__package__}.{name.replace('-', '_')}"


def envelope(name: str, params: dict[str, Any]) -> dict[str, Any]:
    """Common keys of every benchmark JSON file."""
    from .. import __version__

    return {
        "benchmark": name,
        "climb_ompl_version": __version__,
        "created_utc": _dt.datetime.now(_dt.UTC).isoformat(timespec="seconds"),
        "machine": {"python": platform.python_version(), "platform": platform.platform(),
                    "cpus": os.cpu_count()},
        "params": params,
    }


def execute(name: str, params: dict[str, Any], out: Path | None, timeout: float = 3600.0,
            *, quiet: bool = False) -> dict[str, Any]:
    """Run benchmark ``name`` with ``params`` in a subprocess; write ``out``; print the summary.

    Args:
        name: benchmark name (module ``climb_ompl.benchmarks.<name>``) or a dotted module path.
        params: keyword arguments of the module's ``run`` (JSON-able).
        out: JSON output file (written atomically, parent folders created), or ``None``.
        timeout: seconds before the child is killed.
        quiet: do not print the one-line summary.

    Returns:
        The result: the envelope plus what ``run`` returned.

    Raises:
        BenchmarkFailed: the subprocess exited non-zero, or ran past ``timeout`` seconds.
    """
    mod_name = module_name(name)
    if out is not None:  # fail before a long run, not after it
        Path(out).parent.mkdir(parents=True, exist_ok=True)
    with tempfile.TemporaryDirectory() as tmp:
        res_path = Path(tmp) / "result.json"
        cmd = [sys.executable, "-m", f"{__package__}._common", mod_name, json.dumps(params), str(res_path)]
        try:
            proc = subprocess.run(cmd, timeout=timeout)
        except subprocess.TimeoutExpired:
            raise BenchmarkFailed(f"benchmark {name!r} exceeded its timeout of {timeout:g} s") from None
        if proc.returncode != 0 or not res_path.exists():
            raise BenchmarkFailed(f"benchmark {name!r} failed (exit code {proc.returncode})")
        result = json.loads(res_path.read_text())
    if out is not None:
        atomic_write_json(out, result)
    if not quiet:
        mod = importlib.import_module(mod_name)
        print(f"[{name}] {mod.summary(result)}" + (f"  -> {out}" if out else ""), flush=True)
    return result


def _child(mod_name: str, params_json: str, res_path: str) -> None:
    mod = importlib.import_module(mod_name)
    params = json.loads(params_json)
    result = envelope(mod_name.rsplit(".", 1)[-1], params)
    result.update(mod.run(**params))
    Path(res_path).write_text(json.dumps(result, indent=2, sort_keys=True, default=float))


if __name__ == "__main__":
    _child(*sys.argv[1:4])
