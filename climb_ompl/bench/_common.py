"""Shared machinery of the benchmarks: isolated subprocess, JSON envelope, one-line summary.

Every benchmark result is one JSON object: the :func:`envelope` keys (``benchmark``,
``climb_ompl_version``, ``created_utc``, ``machine``, ``params``) plus what the benchmark's ``run``
returns.  :func:`execute` runs ``run`` in a child process (``python -m climb_ompl.bench._common``)
with a timeout, so a hung or crashing C++ planner cannot stall or kill the caller.  :func:`check_grid_options` and
:func:`check_scheduler` refuse the options of the grid benchmarks (``bench grid``, ``bench compare``) before any
output is written.
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

from climb_ompl._io import atomic_write_json
from climb_ompl.contract import CONE_EDGES
from climb_ompl.errors import ClimbError

#: FIND-PATH options of the one-step benchmarks (``bench onestep``, the planner comparison of ``bench grid`` and
#: ``bench compare``) besides those they vary: waypoints 0.05 rad or m apart, the torque check on the equilibrium
#: check's cones (:data:`climb_ompl.contract.CONE_EDGES` edges), the wall-clock guard alone (no CPU guard, no check
#: budget unless a benchmark sets one).  Their documented figures (docs/planners.md, docs/onestep.md) were measured
#: with these; a climb's own are :meth:`climb_ompl.climb.onestep.PathSettings.of`.
ONESTEP_OPTIONS: dict[str, Any] = {"max_step": 0.05, "torque_cone_edges": CONE_EDGES, "cpu_limit": None,
                                   "max_iterations": None}


class BenchmarkFailed(ClimbError):
    """A benchmark subprocess crashed, exited non-zero or exceeded its timeout (CLI exit code 1)."""

    exit_code = 1


def module_name(name: str) -> str:
    """The module of benchmark ``name``: ``climb_ompl.bench.<name>``, or ``name`` itself if dotted."""
    return name if "." in name else f"{__package__}.{name.replace('-', '_')}"


def envelope(name: str, params: dict[str, Any]) -> dict[str, Any]:
    """Common keys of every benchmark JSON file."""
    from climb_ompl._version import __version__

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
        name: benchmark name (module ``climb_ompl.bench.<name>``) or a dotted module path.
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


def check_grid_options(planners: list[str] | None, spaces: list[str] | None, samplers: list[str] | None,
                       counts: dict[str, int | None], out: Path | None = None) -> None:
    """Refuse a benchmark grid's options before any work (``bench grid`` and ``bench compare``): unknown planner,
    space or sampler names (an unavailable planner with its reason), a custom sampler without the ``projected``
    space (the only space that calls it: the grid would hold no run for it), a count (``counts``: option ->
    value, ``None`` when not given) below 1, an ``out`` that exists and is not a folder.

    Raises:
        typer.Exit: exit 2, naming the option.
    """
    from climb_ompl._options import error
    from climb_ompl.errors import ClimbError, PlannerNotFound
    from climb_ompl.manifold._ompl import check_planner
    from climb_ompl.manifold.samplers import parse_sampler
    from climb_ompl.manifold.stance import SPACE_NAMES

    for p in planners or ():
        try:
            check_planner(p)
        except PlannerNotFound as exc:
            raise error(f"--planner: {exc}") from None
    for sp in spaces or ():
        if sp not in SPACE_NAMES:
            raise error(f"--space: {PlannerNotFound('constrained space', sp, SPACE_NAMES)}")
    for sa in samplers or ():
        try:
            custom = parse_sampler(sa) != ("uniform",)
        except ClimbError as exc:
            raise error(f"--sampler: {exc}") from None
        if custom and spaces and "projected" not in spaces:
            raise error(f"--sampler: custom sampler {sa!r} runs only on the projected space (the atlas and "
                        "tangent-bundle spaces sample their own charts): add --space projected")
    for option, n in counts.items():
        if n is not None and n < 1:
            raise error(f"{option}: must be a whole number >= 1, got {n}")
    if out is not None and out.exists() and not out.is_dir():
        raise error(f"--out: {str(out)!r} is a file; give the output folder")


def check_scheduler(address: str | None, timeout: float = 10.0) -> int | None:
    """Refuse a ``--scheduler`` address no Dask scheduler answers at, before any output is written; the number of
    workers it has now (``None`` without an address).

    Raises:
        typer.Exit: exit 2, naming the option.
    """
    if address is None:
        return None
    from distributed import Client

    from climb_ompl._options import error

    try:
        client = Client(address, timeout=timeout)
    except ValueError as exc:  # malformed: no port, an unknown protocol
        raise error(f"--scheduler: {address!r} is not a Dask scheduler address, tcp://HOST:PORT ({exc})") from None
    except (OSError, TimeoutError) as exc:
        raise error(f"--scheduler: no Dask scheduler answers at {address!r} within {timeout:g} s "
                    f"({type(exc).__name__}: {exc})") from None
    try:
        return len(client.scheduler_info().get("workers", {}))
    finally:
        client.close()


if __name__ == "__main__":
    _child(*sys.argv[1:4])
