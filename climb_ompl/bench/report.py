"""``climb-ompl bench report DB --out DIR``: plots of a grid database (see :mod:`climb_ompl.bench._plots`)."""

from __future__ import annotations

from pathlib import Path

import typer


def command(
    db: Path = typer.Argument(..., help="Grid database written by `climb-ompl bench grid`."),
    out: Path = typer.Option(..., "--out", help="Output folder for the PNG/SVG plots."),
) -> None:
    """Plot success rate vs. time limit, time distributions, rejections by reason and a planner x space heat map."""
    from climb_ompl.bench._plots import report
    from climb_ompl.bench._runs import load_results
    from climb_ompl.errors import InputError

    results = load_results(db)  # refuses a missing file or one that is no benchmark database
    if not results:
        raise InputError(db, "grid_runs", "the database holds no runs")
    for p in report(results, out):
        typer.echo(str(p))
