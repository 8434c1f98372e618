"""What every command shares, the benchmarks' commands included: the one-line error exit and the checks of options.

Exit codes: 0 success; 1 no result; 2 bad input (``error: <message>`` on stderr, no traceback).
"""

from __future__ import annotations

import math
import os
from pathlib import Path

import typer

from climb_ompl._io import output_target


def error(message: str, code: int = 2) -> typer.Exit:
    """Print ``error: message`` on stderr and return the Exit to raise."""
    typer.echo(f"error: {message}", err=True)
    return typer.Exit(code)


def check_positive(value: float, option: str, unit: str = "") -> None:
    """Refuse ``value`` given by ``option`` unless it is a finite number > 0 (``unit``: its unit, for the message).

    Raises:
        typer.Exit: exit 2, naming ``option``.
    """
    if not (value > 0 and math.isfinite(value)):
        raise error(f"{option}: must be a finite number > 0{' of ' + unit if unit else ''}, got {value}")


def check_out(out: Path, option: str = "--out") -> None:
    """Refuse an output path before any work: its folder missing or not writable, or the path itself a folder or
    not a regular file (a device, a pipe).

    Raises:
        typer.Exit: exit 2, naming ``option``.
    """
    target, why = output_target(out)  # the checks of the write itself (climb_ompl._io.atomic_write)
    if why is not None:
        raise error(f"{option}: {why}")
    folder = target.parent if str(target.parent) else Path(".")
    if not os.access(folder, os.W_OK):
        raise error(f"{option}: folder {str(folder)!r} is not writable")


__all__ = ["check_out", "check_positive", "error"]
