"""``climb-ompl bench NAME``: every module of :mod:`climb_ompl.bench` with a ``command``."""

from __future__ import annotations

import importlib
import pkgutil

import typer

from climb_ompl import bench as benchmarks
from climb_ompl.cli._app import app

bench_app = typer.Typer(help="Benchmarks: each writes JSON (--out) and prints a one-line summary.",
                        no_args_is_help=True)
app.add_typer(bench_app, name="bench")

for _info in sorted(pkgutil.iter_modules(benchmarks.__path__), key=lambda m: m.name):
    if _info.name.startswith("_"):
        continue
    _mod = importlib.import_module(f"{benchmarks.__name__}.{_info.name}")
    if hasattr(_mod, "command"):
        bench_app.command(_info.name.replace("_", "-"))(_mod.command)
