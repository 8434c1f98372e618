"""The exception family of climb_ompl.

Every error a user can cause derives from :class:`ClimbError`; the CLI turns them into one-line
messages with exit code 2 (bad input).  "No plan within the budget" is *not* an exception: planners
return a result whose status says so.
"""

from __future__ import annotations

from pathlib import Path

#: The ``path`` of an :class:`InputError` whose bad value is a function argument or command-line option.
ARGUMENT = "<argument>"


def nearest_name(name: object, valid: object) -> str | None:
    """The name of ``valid`` a mistyped ``name`` most likely meant (the same name in other letter case first, then
    the closest spelling, :func:`difflib.get_close_matches`), or ``None``."""
    import difflib

    names = [str(v) for v in valid]  # type: ignore[attr-defined]
    folded = {v.lower(): v for v in names}
    if str(name).lower() in folded:
        return folded[str(name).lower()]
    near = difflib.get_close_matches(str(name), names, n=1, cutoff=0.6) if isinstance(name, str) else []
    return near[0] if near else None


class ClimbError(Exception):
    """Base class of every error raised on bad input or misuse of climb_ompl."""


class InputError(ClimbError):
    """Bad input in a file or value, named by location, field and reason.

    Args:
        path: file (or other source, e.g. ``"<argument>"``) the bad value came from.
        field: dotted path of the offending field inside that source, e.g. ``holds[3].normal``.
        reason: what is wrong, in words a user can act on.
    """

    def __init__(self, path: Path | str, field: str, reason: str):
        # a command-line option names itself: "--jitter: ...", not "<argument>: --jitter: ..."
        where = field if path == ARGUMENT and str(field).startswith("-") else f"{path}: {field}"
        super().__init__(f"{where}: {reason}")
        self.path, self.field, self.reason = path, field, reason


class TerrainError(InputError):
    """A malformed terrain (file or object)."""


class RobotModelError(InputError):
    """A malformed robot spec or URDF, or a frame/joint that does not exist."""


class PlanFileError(InputError):
    """An unreadable or schema-invalid plan file."""


class EquilibriumError(ClimbError):
    """Bad input to the equilibrium core (zero normal, negative friction, mass <= 0, ...)."""


class PlannerNotFound(ClimbError):
    """An unknown planner, constrained space or sampler name; the message lists the valid names."""

    def __init__(self, kind: str, name: str, valid: list[str] | tuple[str, ...]):
        near = nearest_name(name, valid)
        guess = f" (did you mean {near!r}?)" if near else ""
        super().__init__(f"unknown {kind} {name!r}{guess}; valid names: {', '.join(valid)}")
        self.kind, self.name, self.valid = kind, name, tuple(valid)


class QueryError(ClimbError):
    """A planning query that cannot be posed (unknown hold or limb, start state infeasible, ...)."""


class VizError(ClimbError):
    """Playback cannot be produced: no meshcat server, no browser, a plan kind whose drawer is missing."""
