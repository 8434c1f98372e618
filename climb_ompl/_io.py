"""Atomic file output: write to a temporary file beside the target, then rename.

A crash or a bad input half-way never leaves a half-written output file behind.
"""

from __future__ import annotations

import json
import os
import tempfile
from pathlib import Path
from typing import Any

from .errors import InputError


def _file_mode(path: Path) -> int:
    """The permissions a new file gets from ``open`` (0o666 less the umask), or those of the file replaced."""
    try:
        return path.stat().st_mode & 0o7777
    except OSError:
        mask = os.umask(0o022)  # reading the umask means setting it; put it back at once
        os.umask(mask)
        return 0o666 & ~mask


def atomic_write(path: str | os.PathLike[str], data: str | bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temporary file in the same folder + ``os.replace``), with the
    permissions a plain ``open`` would give it (the temporary file is private until it is complete).

    Raises:
        InputError: the folder does not exist or is not writable.
    """
    path = Path(path)
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        raise InputError(path, "output", f"folder {str(folder)!r} does not exist")
    mode = "wb" if isinstance(data, bytes) else "w"
    try:
        fd, tmp = tempfile.mkstemp(prefix=f".{path.name}.", suffix=".tmp", dir=folder)
    except OSError as exc:
        raise InputError(path, "output", f"cannot write here ({exc.strerror})") from None
    try:
        with os.fdopen(fd, mode) as fh:
            fh.write(data)
            os.fchmod(fh.fileno(), _file_mode(path))
        os.replace(tmp, path)
    except OSError as exc:
        Path(tmp).unlink(missing_ok=True)
        raise InputError(path, "output", f"cannot write here ({exc.strerror})") from None
    except BaseException:
        Path(tmp).unlink(missing_ok=True)
        raise
    return path


def load_yaml(path: str | os.PathLike[str], error: type[InputError] = InputError) -> Any:
    """Read and parse a YAML file; problems raise ``error(path, where, reason)``.

    ``where`` is ``file`` for an unreadable file and ``line N`` for a YAML syntax error.
    """
    import yaml

    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise error(path, "file", f"cannot read ({getattr(exc, 'strerror', None) or exc})") from None
    try:
        return yaml.safe_load(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark is not None else "file"
        raise error(path, where, f"invalid YAML ({getattr(exc, 'problem', None) or exc})") from None


def atomic_write_json(path: str | os.PathLike[str], obj: Any, *, allow_nan: bool = True) -> Path:
    """Write ``obj`` as indented, key-sorted JSON, atomically.

    Raises:
        ValueError: ``allow_nan`` is false and ``obj`` holds a NaN or an infinity (nothing is written).
    """
    return atomic_write(path, json.dumps(obj, indent=2, sort_keys=True, allow_nan=allow_nan) + "\n")
