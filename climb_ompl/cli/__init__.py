"""The ``climb-ompl`` command.

Exit codes: 0 success; 1 no result (no plan within the budget, violations found); 2 bad input (one-line
message, no traceback).  Each command group lives in its own module of this package and is added below.
A :class:`~climb_ompl.errors.ClimbError` raised by a command becomes ``error: <message>`` on stderr and the
exit code in the error's ``exit_code`` attribute (2 when it has none).
"""

# ruff: noqa: I001  (the command-group imports at the bottom are appended by several people, unsorted)
from __future__ import annotations

import sys

import click
import typer

from climb_ompl.cli._app import app
from climb_ompl.errors import ClimbError

# typer >= 0.20 vendors click as ``typer._click``: its exceptions are not the ``click`` package's.
try:  # pragma: no cover - depends on the typer version
    from typer._click import exceptions as _tclick
except ImportError:  # pragma: no cover
    _tclick = click.exceptions  # type: ignore[assignment]

_EXIT = tuple({typer.Exit, click.exceptions.Exit})
_ABORT = tuple({typer.Abort, click.exceptions.Abort})
_USAGE = tuple({_tclick.ClickException, click.ClickException})



# Command groups: each module registers its commands on ``app`` when imported.
from climb_ompl.cli import bench as _bench  # noqa: E402,F401
from climb_ompl.cli import terrain as _terrain  # noqa: E402,F401
from climb_ompl.cli import robot as _robot  # noqa: E402,F401
from climb_ompl.cli import treebot as _treebot  # noqa: E402,F401
from climb_ompl.cli import slope as _slope  # noqa: E402,F401
from climb_ompl.cli import viz as _viz  # noqa: E402,F401
from climb_ompl.cli import onestep as _onestep  # noqa: E402,F401
from climb_ompl.cli import plan as _plan  # noqa: E402,F401
from climb_ompl.cli import demo as _demo  # noqa: E402,F401
from climb_ompl.cli import replan as _replan  # noqa: E402,F401
from climb_ompl.cli import export as _export  # noqa: E402,F401
from climb_ompl.cli import step as _step  # noqa: E402,F401
from climb_ompl.cli import console as _console  # noqa: E402,F401
from climb_ompl.cli import steps as _steps  # noqa: E402,F401


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
