"""The operator's console: single-step and multi-step goals planned from the state the robot is in, previewed in a
browser before they run, accepted into a session file (Bretl (2006), sec. 5.1; Bretl et al. (2004), sec. 2.3, 3.1).

:mod:`~climb_ompl.console.state` holds the loop (goals planned in a worker thread, the proposal, the session),
:mod:`~climb_ompl.console.page` the viser page, :mod:`~climb_ompl.console.drawing` the 3-D drawing;
:func:`open_console` builds both from a robot and a terrain, or from a session file.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any


def open_session(robot: Any, terrain: Any, path: str | Path | None, *, seed: int = 0) -> tuple[Any, Path | None, str]:
    """The session a console starts with, the file it writes and a note for the operator.

    ``path`` an existing session (or plan) file: that session, written back there.  ``path`` missing or ``None``: a
    new session of ``robot`` on ``terrain`` at their default start, written to ``path``.  A malformed file is left
    untouched: a new session is written beside it (``NAME.new.json``) and the note names the bad field.

    Raises:
        ClimbError: no robot or terrain for a new session, or no start stance.
    """
    from climb_ompl.errors import ClimbError, QueryError
    from climb_ompl.plan.session import Session

    note = ""
    if path is not None and Path(path).exists():
        try:
            return Session.load(path), Path(path), ""
        except ClimbError as exc:
            new = Path(path).with_suffix(".new.json")
            note = f"session file not read ({exc}); it is left as it was, this session is written to {new}"
            path = new
    if robot is None or terrain is None:
        raise QueryError("a new session needs --robot and --terrain")
    from climb_ompl.climb.multistep import check_dimensions, default_start, load_robot, load_terrain
    from climb_ompl.settings import ClimbSettings

    rob, wall = load_robot(robot), load_terrain(terrain)
    check_dimensions(rob, wall)
    start = default_start(rob, wall, seed=seed)
    if start is None:
        raise QueryError(f"no start stance found for {rob.name} on {wall.name} (climb-ompl plan says why)")
    settings = ClimbSettings.for_search("guided", robot=rob)
    return Session.start(rob, wall, start[0], start[1], settings.to_dict(), seed), \
        None if path is None else Path(path), note


def open_console(robot: Any = None, terrain: Any = None, session: str | Path | None = None, *,
                 host: str = "127.0.0.1", port: int = 8080, seed: int = 0, time_limit: float | None = None) -> Any:
    """Start the console's server (:class:`~climb_ompl.console.page.ConsolePage`; its ``url`` is the address).

    Raises:
        ClimbError: as :func:`open_session`.
    """
    from climb_ompl.console.page import ConsolePage
    from climb_ompl.console.state import ConsoleState

    s, path, note = open_session(robot, terrain, session, seed=seed)
    state = ConsoleState(s, path, seed=seed, time_limit=time_limit)
    state.message = note
    return ConsolePage(state, host=host, port=port)


__all__ = ["open_console", "open_session"]
