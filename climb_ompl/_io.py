"""Atomic file output: write to a temporary file beside the target, then rename.

A crash or a bad input half-way never leaves a half-written output file behind.
"""

from __future__ import annotations

import contextlib
import json
import math
import os
import tempfile
from collections.abc import Iterator
from pathlib import Path
from typing import Any

from climb_ompl.errors import InputError


def _file_mode(path: Path) -> int:
    """The permissions a new file gets from ``open`` (0o666 less the umask), or those of the file replaced."""
    try:
        return path.stat().st_mode & 0o7777
    except OSError:
        mask = os.umask(0o022)  # reading the umask means setting it; put it back at once
        os.umask(mask)
        return 0o666 & ~mask


def output_target(path: str | os.PathLike[str]) -> tuple[Path, str | None]:
    """The file an output path writes (a symbolic link followed: the file it points to is replaced, the link kept)
    and why it cannot be written there, or ``None``: its folder missing, or the path a folder, a device or a pipe
    (refused rather than replaced)."""
    path = Path(path)
    if path.is_symlink():
        path = Path(os.path.realpath(path))
    folder = path.parent if str(path.parent) else Path(".")
    if not folder.is_dir():
        return path, f"folder {str(folder)!r} does not exist"
    if path.is_dir():
        return path, f"{str(path)!r} is a folder: give a file name"
    if path.exists() and not path.is_file():
        return path, f"{str(path)!r} is not a regular file (a device, a pipe or a socket): give a file name"
    return path, None


def atomic_write(path: str | os.PathLike[str], data: str | bytes) -> Path:
    """Write ``data`` to ``path`` atomically (temporary file in the same folder + ``os.replace``), with the
    permissions a plain ``open`` would give it (the temporary file is private until it is complete).

    A symbolic link is followed (the file it points to is replaced, the link kept); a path that names a folder, a
    device or a pipe is refused rather than replaced.

    Raises:
        InputError: the folder does not exist or is not writable, or the path is not a regular file.
    """
    given = Path(path)
    path, why = output_target(given)
    if why is not None:
        raise InputError(given, "output", why)
    folder = path.parent if str(path.parent) else Path(".")
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

    ``where`` is ``file`` for an unreadable file and ``line N`` for a YAML syntax error.  The loader is PyYAML's
    safe loader, except that a key written twice in one mapping is an error (the last one would silently win;
    keys merged with ``<<:`` may be overridden, as YAML means them to be).  Like PyYAML (YAML 1.1), it reads
    ``1e-1`` as text: :func:`number_hint` says so where a number was expected.
    """
    import yaml

    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise error(path, "file", f"cannot read ({getattr(exc, 'strerror', None) or exc})") from None
    try:
        return loads_yaml(text)
    except yaml.YAMLError as exc:
        mark = getattr(exc, "problem_mark", None)
        where = f"line {mark.line + 1}" if mark is not None else "file"
        raise error(path, where, f"invalid YAML ({getattr(exc, 'problem', None) or exc})") from None
    except RecursionError:
        raise error(path, "file", "invalid YAML (lists or mappings nested too deep to read)") from None


@contextlib.contextmanager
def captured_stderr(lines: list[str]) -> Iterator[None]:
    """Within the block, what C or C++ code writes to the process's standard error (file descriptor 2, which
    Python's ``sys.stderr`` does not see) goes into ``lines`` instead of the terminal: urdfdom prints its parse
    errors there, before Pinocchio raises its own less specific one."""
    import sys

    try:
        sys.stderr.flush()
        saved = os.dup(2)
    except (OSError, ValueError, AttributeError):  # no real descriptor 2 (an embedded interpreter): leave it
        yield
        return
    with tempfile.TemporaryFile(mode="w+b") as tmp:
        os.dup2(tmp.fileno(), 2)
        try:
            yield
        finally:
            os.dup2(saved, 2)
            os.close(saved)
            tmp.seek(0)
            lines.extend(tmp.read().decode("utf-8", "replace").splitlines())


def number_hint(value: Any) -> str:
    """`` (YAML reads 1e-1 as text: write 0.1 or 1.0e-1)`` when ``value`` is text that Python reads as a number
    (exponent form without a dot, which YAML 1.1 leaves a string), else ``""``: appended to "expected a number"."""
    if isinstance(value, str):
        try:
            x = float(value)
        except ValueError:
            return ""
        if not math.isfinite(x) or not any(c.isdigit() for c in value):
            return ""  # "nan", "inf": YAML's are .nan and .inf, and no field takes them
        mant, _, exp = value.lower().partition("e")
        if "." in mant and exp and exp[0] not in "+-":  # YAML 1.1 wants the exponent's sign too
            return f" (YAML reads {value} as text: give the exponent a sign, e.g. {mant}e+{exp})"
        return f" (YAML reads {value} as text: write it with a dot, e.g. 0.1 or 1.0e-1)"
    return ""


def loads_yaml(text: str) -> Any:
    """Parse YAML text with the loader of :func:`load_yaml` (``yaml.YAMLError`` on bad input).

    The text is parsed by libyaml when PyYAML has it (about seven times faster on a terrain file); the
    constructor is the same Python one.  Text libyaml refuses is parsed again by PyYAML's own parser, whose
    error (message and line) is the one raised, as without libyaml.
    """
    import yaml

    fast = _loader(fast=True)
    if fast is not None:
        try:
            return yaml.load(text, Loader=fast)  # noqa: S506 (a SafeLoader)
        except yaml.YAMLError:
            pass
    return yaml.load(text, Loader=_loader())  # noqa: S506 (a SafeLoader)


_LOADERS: dict[bool, Any] = {}


def _loader(fast: bool = False) -> Any:
    """The project's YAML loader (see :func:`load_yaml`), built once: on PyYAML's pure-Python safe loader, or with
    ``fast`` on its libyaml one (``None`` when PyYAML was built without libyaml)."""
    if fast not in _LOADERS:
        import yaml

        base = getattr(yaml, "CSafeLoader", None) if fast else yaml.SafeLoader
        if base is None:
            _LOADERS[fast] = None
            return None

        class Loader(base):  # type: ignore[misc,valid-type]
            def construct_mapping(self, node: Any, deep: bool = False) -> Any:
                seen: dict[Any, Any] = {}
                for key_node, _ in node.value:  # the keys written in this mapping (merged ones, ``<<: *x``, may
                    if key_node.tag == "tag:yaml.org,2002:merge":  # be overridden: that is what a merge is for)
                        continue
                    key = self.construct_object(key_node, deep=True)
                    try:
                        hash(key)
                    except TypeError:
                        continue  # the safe loader's own error follows
                    if key in seen:
                        text = key_node.value if isinstance(key_node, yaml.ScalarNode) else repr(key)
                        raise yaml.constructor.ConstructorError(
                            "while constructing a mapping", node.start_mark,
                            f"found the key {text!r} twice (first on line {seen[key].line + 1})", key_node.start_mark)
                    seen[key] = key_node.start_mark
                return super().construct_mapping(node, deep=deep)

        _LOADERS[fast] = Loader
    return _LOADERS[fast]


def atomic_write_json(path: str | os.PathLike[str], obj: Any, *, allow_nan: bool = True) -> Path:
    """Write ``obj`` as indented, key-sorted JSON, atomically.

    Raises:
        ValueError: ``allow_nan`` is false and ``obj`` holds a NaN or an infinity (nothing is written).
    """
    return atomic_write(path, json.dumps(obj, indent=2, sort_keys=True, allow_nan=allow_nan) + "\n")
