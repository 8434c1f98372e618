"""Where a robot spec's files come from: the URDF, the SRDF and the folders of ``package://`` meshes.

A spec names its URDF (and optionally an SRDF) as a path beside the spec, a file of the bundled ``urdf``
folder, or, with ``urdf_package: <name>``, a path inside an installed package's ``share/<name>`` folder,
e.g. ``urdf_package: example-robot-data`` with ``urdf: robots/go1_description/urdf/go1.urdf``.  Nothing is
copied: the files are read from the package at run time, and the package's ``share`` folder is added to the
mesh search path so that ``package://example-robot-data/...`` meshes resolve.
"""

from __future__ import annotations

import itertools
import sys
from pathlib import Path
from typing import Any

from climb_ompl.errors import RobotModelError
from climb_ompl.resources import urdf_dir

__all__ = ["package_share", "resolve_robot_file"]


def package_share(name: Any, src: str) -> Path:
    """``share/<name>`` of an installed Python distribution (``cmeel.prefix/share`` or ``<prefix>/share``).

    Raises:
        RobotModelError: (field ``urdf_package``) the package is not installed or has no such folder.
    """
    from importlib import metadata

    if not isinstance(name, str) or not name:
        raise RobotModelError(src, "urdf_package", f"expected a package name, got {name!r}")
    try:
        dist = metadata.distribution(name)
    except metadata.PackageNotFoundError:
        raise RobotModelError(src, "urdf_package", f"package {name!r} is not installed; it provides this "
                              f"robot's URDF (install it with: pip install {name})") from None
    cands = [Path(str(dist.locate_file(f"cmeel.prefix/share/{name}"))), Path(str(dist.locate_file(f"share/{name}"))),
             Path(sys.prefix) / "share" / name]
    for cand in cands:
        if cand.is_dir():
            return cand.resolve()
    raise RobotModelError(src, "urdf_package", f"package {name!r} is installed but has no share/{name} folder "
                          f"(looked in {', '.join(str(c) for c in cands)})")


def resolve_robot_file(value: Any, base_dir: Path, src: str, fld: str, package: Path | None = None) -> Path:
    """The file a spec's ``urdf`` or ``srdf`` field names.

    Beside the spec (``base_dir``) first, then in the bundled ``urdf`` folder, or with a package
    (:func:`package_share`) in that package's folder.  A file beside the spec wins even with a package: a
    plan file's robot is rebuilt from the URDF embedded in the plan, written beside the rebuilt spec, not
    from whatever version of the package is installed.

    Raises:
        RobotModelError: not a non-empty string, or no such file (the message says where it looked).
    """
    if not isinstance(value, str) or not value:
        raise RobotModelError(src, fld, f"expected a file name, got {value!r}")
    cands = [base_dir / value, package / value] if package is not None else [base_dir / value, urdf_dir() / value]
    for cand in cands:
        if cand.is_file():
            return cand.resolve()
    where = (f"beside the spec in {base_dir} and in the package folder {package}" if package is not None
             else f"beside the spec in {base_dir} and in the bundled urdf folder")
    raise RobotModelError(src, fld, f"file {value!r} not found (looked {where}){_files_near(cands, value)}")


def _files_near(cands: list[Path], value: str, most: int = 8, scan: int = 200) -> str:
    """`` (files ending in .urdf under robots/x: robots/x/urdf/a.urdf, ...)``: the files with ``value``'s suffix at most
    two folders below the deepest folder of ``value``'s relative path that exists in one of the places looked in (a
    package's robot folder whose files lie elsewhere than the spec says), those named as ``value``'s file first, at most
    ``scan`` of them looked at; ``""`` when there is none, ``value`` is not a relative path with a folder and a suffix,
    or the folders cannot be read."""
    rel = Path(value)
    if rel.anchor or ".." in rel.parts or len(rel.parts) < 2 or not rel.suffix:
        return ""
    parts = rel.parts[:-1]
    try:
        for cand in cands:
            root = cand.parents[len(parts)]
            for k in range(len(parts), 0, -1):
                folder = root.joinpath(*parts[:k])
                if not folder.is_dir():
                    continue
                found = []
                for pat in ("*", "*/*", "*/*/*"):
                    found += [f for f in itertools.islice(folder.glob(pat + rel.suffix), scan - len(found))
                              if f.is_file()]
                if not found:
                    break
                names = sorted((f.name != rel.name, str(f.relative_to(root))) for f in found)
                shown = ", ".join(n for _, n in names[:most]) + \
                    (f", ... ({len(names)}{'+' if len(found) >= scan else ''} in all)" if len(names) > most else "")
                return f" (files ending in {rel.suffix} under {Path(*parts[:k])}: {shown})"
    except OSError:
        return ""
    return ""
