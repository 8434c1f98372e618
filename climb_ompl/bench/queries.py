"""``climb-ompl bench queries``: (re)generate the versioned one-step query sets (see
:mod:`climb_ompl.bench._query_set`).

Each set is written to ``climb_ompl/data/queries/<name>.json`` (or ``--out DIR``) with every query's
hardness (the reference planner's success at a fixed validity-check budget); generated walls go to
``walls/`` beside it.  Deterministic up to the reference planner's wall-clock guard.
"""

from __future__ import annotations

from pathlib import Path

import typer


def command(
    name: list[str] = typer.Option(None, "--set", help="Query set to generate (repeatable; default: every set)."),
    n: int = typer.Option(30, "--n", help="Queries per set."),
    out: Path = typer.Option(None, "--out", help="Output folder (default: the package's data/queries)."),
    check: bool = typer.Option(False, "--check", help="Only load the sets and run the stance checks on them."),
) -> None:
    """Generate the query sets (or, with --check, verify every query's start and goal)."""
    from climb_ompl.bench._query_set import (
        SETS,
        check_query,
        generate_set,
        hardness_table,
        load_set,
        queries_dir,
        spec,
        write_set,
    )

    specs = [spec(x) for x in name] if name else list(SETS)
    folder = out or queries_dir()
    if check:
        bad = 0
        for s in specs:
            data = load_set(folder / f"{s.name}.json")
            for q in data["queries"]:
                why = check_query(q)
                if why is not None:
                    bad += 1
                    typer.echo(f"{s.name}: query {q['uid']}: {why}", err=True)
            typer.echo(f"[queries] {s.name}: {len(data['queries'])} queries checked")
        raise typer.Exit(1 if bad else 0)
    for s in specs:
        data = generate_set(s, n, folder=folder, progress=lambda msg: typer.echo(f"  {msg}"))
        path = write_set(data, folder)
        kinds = {k: sum(q["kind"] == k for q in data["queries"]) for k in ("grab", "release")}
        typer.echo(f"[queries] {s.name}: {len(data['queries'])} queries {kinds}, reference solved "
                   f"{hardness_table(data)} -> {path}")
