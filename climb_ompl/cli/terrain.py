"""``climb-ompl terrain validate|generate|list`` and ``climb-ompl planners``."""

from __future__ import annotations

from pathlib import Path

import typer

from climb_ompl._io import atomic_write
from climb_ompl._options import check_out
from climb_ompl.cli._app import app, refuse_friction
from climb_ompl.errors import ARGUMENT, InputError, TerrainError
from climb_ompl.model.terrain import Terrain, bundled_terrains, generate_wall
from climb_ompl.settings import SEED_MAX

terrain_app = typer.Typer(help="Terrain files: validate, generate, list.", no_args_is_help=True)
app.add_typer(terrain_app, name="terrain")


@terrain_app.command("validate")
def validate(files: list[str] = typer.Argument(..., help="Terrain files or bundled terrain names.")) -> None:
    """Check terrain files; exit 0 if all are valid, 2 with the file, field and reason at the first bad one."""
    for file in files:
        t = Terrain.load(file)
        refuse_friction(t)
        typer.echo(f"{t.source}: ok: terrain {t.name!r}, dim {t.dim}, {len(t.holds)} holds, "
                   f"{len(t.surfaces)} surfaces, sha256 {t.content_hash()[:12]}")
        for note in t.convention_notes():
            typer.echo(f"note: {t.source}: {note}", err=True)


#: The options of ``terrain generate`` by the :func:`generate_wall` argument they give.
GENERATE_OPTIONS = {"seed": "--seed", "width": "--width", "height": "--height", "spacing": "--spacing",
                    "jitter": "--jitter", "friction": "--friction-min/--friction-max", "tilt_deg": "--tilt",
                    "normal_up_deg": "--normal-up-min/--normal-up-max", "normal_side_deg": "--normal-side",
                    "name": "--name"}


@terrain_app.command("generate")
def generate(
    out: Path = typer.Option(..., "--out", help="Output YAML file (written atomically; its folder must exist)."),
    seed: int = typer.Option(0, "--seed", min=0, max=SEED_MAX, help="RNG seed: the same seed gives the same wall."),
    width: float = typer.Option(1.6, help="Wall width, m."),
    height: float = typer.Option(3.0, help="Wall height, m."),
    spacing: float = typer.Option(0.18, help="Mean hold spacing, m."),
    jitter: float = typer.Option(0.4, help="Grid jitter as a fraction of the spacing, 0-0.5."),
    friction_min: float = typer.Option(0.9, help="Lowest friction coefficient."),
    friction_max: float = typer.Option(1.2, help="Highest friction coefficient."),
    tilt: float = typer.Option(0.0, help="Wall tilt from vertical, degrees (+ slab, - overhang)."),
    normal_up_min: float = typer.Option(55.0, help="Least upward lean of a hold's normal from the wall normal, "
                                                   "degrees (lower: holds that lean less, harder)."),
    normal_up_max: float = typer.Option(80.0, help="Greatest upward lean of a hold's normal, degrees (<= 90)."),
    normal_side: float = typer.Option(20.0, help="Greatest sideways lean of a hold's normal, degrees."),
    name: str = typer.Option(None, help="Terrain name (default wall-<seed>)."),
) -> None:
    """Generate a random climbing wall (reproducible from --seed; see climb_ompl.model.terrain.generate_wall)."""
    try:
        t = generate_wall(seed, width=width, height=height, spacing=spacing, jitter=jitter,
                          friction=(friction_min, friction_max), tilt_deg=tilt,
                          normal_up_deg=(normal_up_min, normal_up_max), normal_side_deg=normal_side, name=name)
    except TerrainError as exc:  # the generator names its argument: name the option instead
        arg = str(exc.field).removeprefix("generator.")
        raise InputError(ARGUMENT, GENERATE_OPTIONS.get(arg, arg), exc.reason) from None
    check_out(out)
    try:
        atomic_write(out, t.to_yaml())
    except OSError as exc:  # e.g. the rename fails; atomic_write already removed its temporary file
        raise InputError(out, "--out", f"cannot write ({exc.strerror or exc})") from None
    typer.echo(f"wrote {out}: terrain {t.name!r}, {len(t.holds)} holds")


@terrain_app.command("list")
def list_terrains() -> None:
    """List the bundled terrains."""
    names = bundled_terrains()
    width = max((len(n) for n in names), default=0)
    for name in names:
        t = Terrain.load(name)
        typer.echo(f"{name:{width}s}  dim {t.dim}  {len(t.holds):4d} holds  {len(t.surfaces):3d} surfaces")


@app.command("planners")
def planners(
    all_: bool = typer.Option(False, "--all", help="Also list the OMPL planners left out, with the reason."),
) -> None:
    """List the registered OMPL geometric planners (one name per line)."""
    from climb_ompl.manifold._ompl import PLANNER_NAMES, UNAVAILABLE

    for name in PLANNER_NAMES:
        typer.echo(name)
    if all_:
        for name, reason in sorted(UNAVAILABLE.items()):
            typer.echo(f"{name}  (not available: {reason})")
