"""Results kept on disk between runs: the reach maps of robots (a second for a closed-form limb, tens of seconds
for a limb probed by numeric inverse kinematics, :func:`climb_ompl.model.reach.reach_maps`).

The folder is ``$CLIMB_OMPL_CACHE`` if that is set (``off``, ``0`` or an empty value: nothing is kept), else
``$XDG_CACHE_HOME/climb_ompl``, else ``~/.cache/climb_ompl``; delete it to clear the cache.  An entry is a NumPy
``.npz`` file named by a SHA-256 digest of everything its result depends on (the caller's inputs and the source
of the modules that compute it), so a changed robot, wall orientation or code finds no stale entry.  Entries are
written atomically (two processes that compute the same entry at once write the same bytes), an entry that
cannot be read counts as missing, and a folder that cannot be written only means nothing is kept.
"""

from __future__ import annotations

import hashlib
import os
import tempfile
import zipfile
from pathlib import Path

import numpy as np

#: The environment variable naming the cache folder (``off`` turns the cache off).
ENV = "CLIMB_OMPL_CACHE"


def folder() -> Path | None:
    """The cache folder (see the module docstring), or ``None`` when the cache is turned off."""
    given = os.environ.get(ENV)
    if given is not None:
        return None if given.strip().lower() in ("", "0", "off", "false", "no") else Path(given).expanduser()
    xdg = os.environ.get("XDG_CACHE_HOME")
    return (Path(xdg) if xdg else Path.home() / ".cache") / "climb_ompl"


def note() -> str:
    """Where results are kept, for a message: ``kept in PATH``, or that they are not."""
    path = folder()
    return f"kept in {path}" if path is not None else f"not kept: ${ENV} turns the cache off"


def digest(*parts: str | bytes) -> str:
    """SHA-256 hex digest of ``parts`` (each length-prefixed, so that ``("ab", "c")`` and ``("a", "bc")`` differ)."""
    h = hashlib.sha256()
    for p in parts:
        b = p.encode() if isinstance(p, str) else bytes(p)
        h.update(len(b).to_bytes(8, "little"))
        h.update(b)
    return h.hexdigest()


def _path(kind: str, key: str) -> Path | None:
    base = folder()
    return None if base is None else base / kind / f"{key}.npz"


def has(kind: str, key: str) -> bool:
    """Whether entry ``key`` of ``kind`` is on disk (the cache on)."""
    path = _path(kind, key)
    return path is not None and path.is_file()


def load(kind: str, key: str) -> dict[str, np.ndarray] | None:
    """The arrays of entry ``key`` of ``kind`` (a subfolder), or ``None`` if it is missing, unreadable or the
    cache is off."""
    path = _path(kind, key)
    if path is None or not path.is_file():
        return None
    try:
        with np.load(path, allow_pickle=False) as z:
            return {k: np.array(z[k]) for k in z.files}
    except (OSError, ValueError, EOFError, KeyError, zipfile.BadZipFile):
        return None  # truncated or foreign: computed again, then overwritten


def save(kind: str, key: str, arrays: dict[str, np.ndarray]) -> Path | None:
    """Keep ``arrays`` as entry ``key`` of ``kind``; the file written, or ``None`` (cache off, or the folder not
    writable: the result is simply not kept)."""
    path = _path(kind, key)
    if path is None:
        return None
    tmp = None
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        fd, tmp = tempfile.mkstemp(prefix=f".{path.stem}.", suffix=".tmp", dir=path.parent)
        with os.fdopen(fd, "wb") as f:
            np.savez(f, **arrays)
        os.replace(tmp, path)
        return path
    except OSError:
        if tmp is not None:
            Path(tmp).unlink(missing_ok=True)
        return None
