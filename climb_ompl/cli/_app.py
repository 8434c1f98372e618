"""The ``climb-ompl`` Typer application, on which each command module of :mod:`climb_ompl.cli` registers its commands,
and the pieces of input those commands share (``LIMB=HOLD`` pairs, a terrain turned into the wall frame)."""

from __future__ import annotations

from typing import Any

import typer

from climb_ompl._options import error
from climb_ompl._version import __version__

app = typer.Typer(
    name="climb-ompl",
    help="Plan free-climbing motions for multi-limbed robots (OMPL + Pinocchio + Coal + cvxpy + meshcat).",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    add_completion=False,
)


def _version(value: bool) -> None:
    if value:
        typer.echo(f"climb-ompl {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True, help="Print the version."),
) -> None:
    """Plan free-climbing motions for multi-limbed robots."""


def parse_pairs(text: str, what: str) -> dict[str, str]:
    """``LIMB=HOLD`` pairs separated by commas (``--start``, ``--stance``, ``--goal-hold``) as a mapping.

    Raises:
        typer.Exit: exit 2 for an empty text or an empty item between commas, an item that is not one
            ``LIMB=HOLD``, or a limb given twice (naming the option ``what``).
    """
    out: dict[str, str] = {}
    parts = [p.strip() for p in text.strip().removesuffix(",").split(",")]  # a trailing comma is harmless
    if not any(parts):
        raise error(f"{what}: empty (expected LIMB=HOLD pairs separated by commas)")
    for part in parts:
        if part.count("=") != 1 or not all(x.strip() for x in part.split("=")):
            raise error(f"{what}: expected LIMB=HOLD pairs separated by commas, got {part!r}")
        k, v = (x.strip() for x in part.split("="))
        if k in out:
            raise error(f"{what}: limb {k!r} given twice ({k}={out[k]} and {k}={v})")
        out[k] = v
    return out


def load_wall(terrain: str) -> "Any":
    """The terrain file or bundled name ``terrain``, turned into the wall frame when it does not follow the
    convention (:mod:`climb_ompl.model.wall_frame`), its notes printed on stderr."""
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.model.wall_frame import to_wall_frame

    wall, note = to_wall_frame(Terrain.load(terrain))
    refuse_friction(wall)
    for line in ([note] if note else []) + wall.convention_notes():
        typer.echo(f"note: {wall.source}: {line}", err=True)
    return wall


def refuse_friction(wall: Any, name: str | None = None) -> None:
    """Refuse a terrain whose holds have a friction coefficient above
    :data:`~climb_ompl.model.terrain.FRICTION_SUSPECT` (:meth:`~climb_ompl.model.terrain.Terrain.friction_note`):
    no contact a robot climbs on is that sticky, so a plan on it would be no evidence of a climb on the real wall,
    and such a value is almost always a percentage (80 for 0.8).  The library loads such a terrain (a model may
    want one); the commands do not plan, show or validate it.

    Raises:
        typer.Exit: exit 2 naming the file (or ``name``), ``holds`` and the reason.
    """
    note = wall.friction_note()
    if note:
        raise error(f"{name or wall.source}: {note}; refused: a plan on it would hold the robot by friction no surface "
                    "gives")


__all__ = ["app", "load_wall", "parse_pairs", "refuse_friction"]
