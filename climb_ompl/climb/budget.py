"""The budget of one climb query's search: wall-clock seconds, and optionally a number of nodes explored.

``time_limit`` (:class:`~climb_ompl.settings.ClimbSettings`) is the whole query's, counted from the moment the query
began (a start search may have taken part of it); a re-plan's rejoining search also stops after a number of
``(stance, component)`` nodes explored (:attr:`climb_ompl.climb.warm.WarmStart.max_stances`).
"""

from __future__ import annotations

import time
from collections.abc import Sized


class BudgetSpent(Exception):
    """Raised inside the search when its budget is spent: no message for the time budget; for the limit of nodes
    explored, the limit in words."""


class Budget:
    """The budget of a search.

    Args:
        time_limit: seconds of wall clock for the whole query.
        t0: when the query began (:func:`time.perf_counter`; default: now).
        explored: the search's explored nodes (only their number is read), for :attr:`max_stances`.

    Attributes:
        max_stances: explore at most this many ``(stance, component)`` nodes (``None``: no limit).
    """

    def __init__(self, time_limit: float, t0: float | None = None, explored: Sized = ()):
        self.time_limit = float(time_limit)
        self.t0 = time.perf_counter() if t0 is None else float(t0)
        self.explored = explored
        self.max_stances: int | None = None

    def elapsed(self) -> float:
        """Seconds since the query began."""
        return time.perf_counter() - self.t0

    def check(self) -> None:
        """Raise :class:`BudgetSpent` when the time budget is spent or more than :attr:`max_stances` nodes were
        explored."""
        if self.elapsed() > self.time_limit:
            raise BudgetSpent()
        if self.max_stances is not None and len(self.explored) > self.max_stances:
            raise BudgetSpent(f"the limit of {self.max_stances} (stance, component) nodes explored")


__all__ = ["Budget", "BudgetSpent"]
