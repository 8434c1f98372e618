"""``climb-ompl terrain validate|generate|list`` and ``climb-ompl planners``."""

from __future__ import annotations

from pathlib import Path

import typer

from . import app
from .._io import atomic_write
from ..terrain import Terrain, bundled_terrains, generate_wall

terrain_app = typer.Typer(help="Terrain files: validate, generate, list.", no_args_is_help=True)
app.add_typer(terrain_app, name="terrain")


@terrain_app.command("validate")
def validate(file: str = typer.Argument(..., help="Terrain file or bundled terrain name.")) -> None:
    """Check a terrain file; exit 0 if valid, 2 with the file, field and reason if not."""
    t = Terrain.load(file)
    typer.echo(f"{t.source}: ok: terrain {t.name!r}, dim {t.dim}, {len(t.holds)} holds, {len(t.surfaces)} surfaces")


@terrain_app.command("generate")
def generate(
    out: Path = typer.Option(..., "--out", help="Output YAML file (written atomically)."),
    seed: int = typer.Option(0, "--seed", help="RNG seed: the same seed gives the same wall."),
    width: float = typer.Option(1.6, help="Wall width, m."),
    height: float = typer.Option(3.0, help="Wall height, m."),
    spacing: float = typer.Option(0.18, help="Mean hold spacing, m."),
    friction_min: float = typer.Option(0.9, help="Lowest friction coefficient."),
    friction_max: float = typer.Option(1.2, help="Highest friction coefficient."),
    tilt: float = typer.Option(0.0, help="Wall tilt from vertical, degrees (+ slab, - overhang)."),
    name: str = typer.Option(None, help="Terrain name (default wall-<seed>)."),
) -> None:
    """Generate a random climbing wall (reproducible from --seed)."""
    t = generate_wall(seed, width=width, height=height, spacing=spacing, friction=(friction_min, friction_max),
                      tilt_deg=tilt, name=name)
    atomic_write(out, t.to_yaml())
    typer.echo(f"wrote {out}: {len(t.holds)} holds")


@terrain_app.command("list")
def list_terrains() -> None:
    """List the bundled terrains."""
    for name in bundled_terrains():
        t = Terrain.load(name)
        typer.echo(f"{name:16s} dim {t.dim}  {len(t.holds):4d} holds")


@app.command("planners")
def planners() -> None:
    """List the registered OMPL planners."""
    from .._ompl import PLANNER_NAMES

    for name in PLANNER_NAMES:
        typer.echo(name)
