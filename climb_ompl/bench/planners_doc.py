"""``climb-ompl bench planners-doc DB``: write ``docs/planners.md`` from a comparison database.

See :mod:`climb_ompl.bench._planners_report`; ``make compare`` runs it after ``climb-ompl bench compare``.
"""

from __future__ import annotations

from pathlib import Path

import typer


def command(
    db: Path = typer.Argument(..., help="Database written by `climb-ompl bench compare` (grid.db)."),
    out: Path = typer.Option(..., "--out", help="The Markdown page to write (the repository's is docs/planners.md; "
                             "no default, so a run from the repository does not overwrite it unasked)."),
    figures: Path = typer.Option(None, "--figures", help="Folder of the page's figures (default: beside it)."),
    copy_db: Path = typer.Option(None, "--copy-db", help="Also keep a compacted copy of the database here."),
    grid_runs: int = typer.Option(None, "--grid-runs", help="Runs of the full grid (named on a partial run's page)."),
) -> None:
    """Success vs budget, time distributions, Wilson intervals, heat map, sampler effect, recommendation."""
    from climb_ompl.bench._planners_report import write_page

    # write_page reads the database before it writes anything: a missing file, or one that is no benchmark
    # database, is an InputError naming it (exit 2) and leaves no page
    typer.echo(str(write_page(db, out, fig_dir=figures, copy_db=copy_db, grid_runs=grid_runs)))
