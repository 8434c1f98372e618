"""The ``climb-ompl`` command.

Exit codes: 0 success; 1 no result (no plan within the budget, violations found); 2 bad input (one-line
message, no traceback).  Each command group lives in its own module of this package and is added below.
A :class:`~climb_ompl.errors.ClimbError` raised by a command becomes ``error: <message>`` on stderr and the
exit code in the error's ``exit_code`` attribute (2 when it has none).
"""

# ruff: noqa: I001  (the command-group imports at the bottom are appended by several people, unsorted)
from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

import click
import typer

from ..errors import ClimbError

# typer >= 0.20 vendors click as ``typer._click``: its exceptions are not the ``click`` package's.
try:  # pragma: no cover - depends on the typer version
    from typer._click import exceptions as _tclick
except ImportError:  # pragma: no cover
    _tclick = click.exceptions  # type: ignore[assignment]

_EXIT = tuple({typer.Exit, click.exceptions.Exit})
_ABORT = tuple({typer.Abort, click.exceptions.Abort})
_USAGE = tuple({_tclick.ClickException, click.ClickException})

app = typer.Typer(
    name="climb-ompl",
    help="Plan free-climbing motions for multi-limbed robots (OMPL + Pinocchio + Coal + cvxpy + meshcat).",
    no_args_is_help=True,
    pretty_exceptions_enable=False,
    add_completion=False,
)


def _version(value: bool) -> None:
    if value:
        from .. import __version__

        typer.echo(f"climb-ompl {__version__}")
        raise typer.Exit()


@app.callback()
def _root(
    version: bool = typer.Option(False, "--version", callback=_version, is_eager=True, help="Print the version."),
) -> None:
    """Plan free-climbing motions for multi-limbed robots."""


def error(message: str, code: int = 2) -> "typer.Exit":
    """Print ``error: message`` on stderr and return the Exit to raise."""
    typer.echo(f"error: {message}", err=True)
    return typer.Exit(code)


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


def check_positive(value: float, option: str, unit: str = "") -> None:
    """Refuse ``value`` given by ``option`` unless it is a finite number > 0 (``unit``: its unit, for the message).

    Raises:
        typer.Exit: exit 2, naming ``option``.
    """
    import math

    if not (value > 0 and math.isfinite(value)):
        raise error(f"{option}: must be a finite number > 0{' of ' + unit if unit else ''}, got {value}")


def check_out(out: Path, option: str = "--out") -> None:
    """Refuse an output path before any work: its folder missing or not writable, or the path itself a folder or
    not a regular file (a device, a pipe).

    Raises:
        typer.Exit: exit 2, naming ``option``.
    """
    import os

    from .._io import output_target

    target, why = output_target(out)  # the checks of the write itself (climb_ompl._io.atomic_write)
    if why is not None:
        raise error(f"{option}: {why}")
    folder = target.parent if str(target.parent) else Path(".")
    if not os.access(folder, os.W_OK):
        raise error(f"{option}: folder {str(folder)!r} is not writable")


def load_wall(terrain: str) -> "Any":
    """The terrain file or bundled name ``terrain``, turned into the wall frame when it does not follow the
    convention (:mod:`climb_ompl.wall_frame`), its notes printed on stderr."""
    from ..wall_frame import to_wall_frame
    from ..terrain import Terrain

    wall, note = to_wall_frame(Terrain.load(terrain))
    for line in ([note] if note else []) + wall.convention_notes():
        typer.echo(f"note: {wall.source}: {line}", err=True)
    return wall


# Command groups: each module registers its commands on ``app`` when imported.
from . import bench as _bench  # noqa: E402,F401
from . import terrain as _terrain  # noqa: E402,F401
from . import robot as _robot  # noqa: E402,F401
from . import treebot as _treebot  # noqa: E402,F401
from . import slope as _slope  # noqa: E402,F401
from . import viz as _viz  # noqa: E402,F401
from . import onestep as _onestep  # noqa: E402,F401
from . import plan as _plan  # noqa: E402,F401
from . import demo as _demo  # noqa: E402,F401
from . import replan as _replan  # noqa: E402,F401


def _reflow_help(group: typer.Typer) -> None:
    """Join the lines of each paragraph of the commands' docstrings: ``--help`` prints a paragraph's later lines
    as they are written (Typer keeps their line breaks), and a terminal narrower than the source wraps each of them
    again, mid-sentence.  Paragraphs (blank lines) stay."""
    import inspect

    for info in group.registered_commands:
        doc = info.help or (inspect.getdoc(info.callback) if info.callback else None)
        if doc:
            info.help = "\n\n".join(" ".join(line.strip() for line in par.splitlines()) for par in doc.split("\n\n"))
    for sub in group.registered_groups:
        if sub.typer_instance is not None:
            _reflow_help(sub.typer_instance)


_reflow_help(app)


def main(argv: list[str] | None = None) -> int:
    """Entry point of the console script and of ``python -m climb_ompl``; returns the exit code.

    Args:
        argv: the arguments (default ``sys.argv[1:]``).
    """
    try:
        rv = app(args=argv, standalone_mode=False, prog_name="climb-ompl")
    except _EXIT as exc:
        return int(exc.exit_code)
    except _ABORT:
        typer.echo("aborted", err=True)
        return 130
    except _USAGE as exc:
        exc.show()
        return int(getattr(exc, "exit_code", 2) or 2)
    except ClimbError as exc:
        typer.echo(f"error: {exc}", err=True)
        return int(getattr(exc, "exit_code", 2))
    # Without standalone mode, typer returns the code of a ``typer.Exit`` raised by a command.
    return rv if isinstance(rv, int) and not isinstance(rv, bool) else 0


if __name__ == "__main__":
    sys.exit(main())
