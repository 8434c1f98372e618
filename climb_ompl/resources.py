"""Where bundled data lives, for a source checkout, an editable install and a built wheel alike.

``robots/`` and ``urdf/`` sit at the top of the repository; a wheel carries them as
``climb_ompl/_data/robots`` and ``climb_ompl/_data/urdf`` (``pyproject.toml``, hatch ``force-include``).
Bundled terrains live inside the package (``climb_ompl/terrains``), TreeBot's trees in
``climb_ompl/treebot/trees``.
"""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from climb_ompl.errors import InputError

_PKG = Path(__file__).resolve().parent


def _data_dir(name: str) -> Path:
    wheel = _PKG / "_data" / name
    if wheel.is_dir():
        return wheel
    checkout = _PKG.parent / name
    if checkout.is_dir():
        return checkout
    raise FileNotFoundError(f"bundled data folder {name!r} not found (looked in {wheel} and {checkout})")


def robots_dir() -> Path:
    """Folder of the bundled robot specs (``robots/<name>.yaml``)."""
    return _data_dir("robots")


def urdf_dir() -> Path:
    """Folder of the bundled URDF files (``urdf/<name>.urdf``)."""
    return _data_dir("urdf")


def terrains_dir() -> Path:
    """Folder of the bundled terrain files (``<name>.yaml``)."""
    return _PKG / "terrains"


def bundled(folder: Path, suffix: str = ".yaml") -> list[str]:
    """Sorted names (file stems) of the bundled files with ``suffix`` in ``folder``."""
    return sorted(p.stem for p in folder.glob(f"*{suffix}"))


def resolve(name_or_path: str | Path, folder: Path, kind: str, suffix: str = ".yaml",
            error: type[InputError] | None = None) -> Path:
    """Resolve a bundled name (``"demo-wall"``) or a file path to an existing file.

    Raises:
        InputError: (or its subclass ``error``) neither a file nor a bundled name; the message lists the bundled
            names.
    """
    from climb_ompl.errors import InputError

    err = InputError if error is None else error
    p = Path(name_or_path)
    if p.is_file():
        return p
    cand = folder / f"{name_or_path}{suffix}"
    if cand.is_file():
        return cand
    if p.is_dir():
        ext = suffix.lstrip(".").upper()
        raise err(str(name_or_path), kind, f"is a folder: give the {kind} file inside it ({ext}), or a bundled name")
    from climb_ompl.errors import nearest_name

    known = bundled(folder, suffix)
    near = nearest_name(str(name_or_path), known)
    guess = f" (did you mean {near!r}?)" if near else ""
    raise err(str(name_or_path), kind, f"no such file (looked for {p.resolve()}) and no bundled {kind} of that name"
              f"{guess}; a bare name is looked up among the bundled ones: {', '.join(known) or '(none)'}")
