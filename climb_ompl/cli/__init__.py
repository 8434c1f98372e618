"""The ``climb-ompl`` command.

Exit codes: 0 success; 1 no result (no plan within the budget, violations found); 2 bad input (one-line
message, no traceback).  Each command group lives in its own module of this package and is added below.
"""

from __future__ import annotations

import sys

import click
import typer

from ..errors import ClimbError

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


# Command groups: each module registers its commands on ``app`` when imported.
from . import bench as _bench  # noqa: E402,F401
from . import terrain as _terrain  # noqa: E402,F401


def main(argv: list[str] | None = None) -> int:
    """Entry point of the console script; returns the exit code."""
    try:
        app(args=argv, standalone_mode=False, prog_name="climb-ompl")
    except click.exceptions.Exit as exc:
        return int(exc.exit_code)
    except click.exceptions.Abort:
        typer.echo("aborted", err=True)
        return 130
    except click.ClickException as exc:
        exc.show()
        return 2
    except ClimbError as exc:
        typer.echo(f"error: {exc}", err=True)
        return 2
    return 0


if __name__ == "__main__":
    sys.exit(main())
