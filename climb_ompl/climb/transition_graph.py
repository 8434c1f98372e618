"""The transition graph: paths between transitions of one stance, found once and kept (Bretl 2006, Fig. 16).

EXPLORE-TRANSITIONGRAPH (:mod:`climb_ompl.climb.search`) asks for a path in ``F_sigma`` between two transitions
(the configuration the climb reached at ``sigma`` and a transition onto the next stance).  This module
answers: first with the direct local path (:mod:`climb_ompl.climb.local_path`; not with ``direct_path`` off),
then with FIND-PATH (:func:`climb_ompl.climb.onestep.find_path`, the OMPL planner, space and sampler of the
settings) within ``step_time_limit`` of CPU time (and the climb's wall-clock budget left).  Each answer, path or
failure, is kept, so a later candidate sequence sharing a prefix costs nothing to re-check.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any

import numpy as np

from climb_ompl.climb.local_path import LocalPath
from climb_ompl.climb.onestep import PathResult, PathSettings, find_path
from climb_ompl.errors import QueryError
from climb_ompl.manifold.bends import SameBendCheck
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.manifold.stance import Stance, manifold_dim
from climb_ompl.settings import ClimbSettings


def qkey(q: np.ndarray) -> bytes:
    """A configuration as a dictionary key (its exact bytes)."""
    return np.ascontiguousarray(q, dtype=float).tobytes()


class TransitionGraph:
    """Paths between transitions, cached by ``(stance, q_a, q_b)``.

    Args:
        feas: the feasibility tests.
        settings: the climb's settings (local path, FIND-PATH planner, budgets).
        seed: seed of the FIND-PATH calls (with the call count: reproducible).
    """

    def __init__(self, feas: Feasibility, settings: ClimbSettings, *, seed: int = 0):
        s = self.s = settings
        self.feas, self.robot, self.terrain, self.seed = feas, feas.robot, feas.terrain, int(seed)
        self.local_path = LocalPath.of(feas, s, seed=seed)
        self.paths: dict[tuple[Any, bytes, bytes], list[np.ndarray] | None] = {}
        #: the FIND-PATH effort each cached connection was planned at, and the failed ones planned again
        #: (the search's ``path_retries``)
        self.efforts: dict[tuple[Any, bytes, bytes], int] = {}
        self.retries = 0
        #: FIND-PATH calls, paths it returned whose waypoints failed the re-check, and calls stopped by the
        #: time guards (CPU-time ``step_time_limit``, or the climb's budget left) rather than the check budget
        #: ``path_iterations`` (a climb without such stops is reproducible on any machine)
        self.path_calls = self.ompl_rejected = self.path_timeouts = 0
        #: FIND-PATH validity checks, summed over calls (the effort ``edge_p = "time"`` counts)
        self.checks = 0
        #: wall-clock seconds of each connection (local path and FIND-PATH), of FIND-PATH calls, of local paths
        self.step_times: list[float] = []
        self.path_times: list[float] = []
        self.direct_times: list[float] = []
        #: FIND-PATH rejections by reason, summed over calls
        self.rejections: dict[str, int] = {}

    def connect(self, stance: Stance, qa: np.ndarray, qb: np.ndarray, moving: str | None,
                check_time: Callable[[], None] = lambda: None, time_left: float = float("inf"),
                effort: int = 1) -> list[np.ndarray] | None:
        """A path in ``F_stance`` from ``qa`` to ``qb`` (``moving``: the limb about to grab, or ``None``):
        zero-length, the direct local path, or FIND-PATH; ``None`` when none was found (cached either way).

        ``check_time`` is called before any work (it raises when the climb's budget is spent) and FIND-PATH
        gets at most ``time_left`` seconds.  ``effort``: FIND-PATH's budgets (``path_iterations``,
        ``step_time_limit``) are multiplied by it; a failure cached at a smaller effort is planned again
        (FIND-PATH only, with the next seed), one at this effort or more is returned.
        """
        ck = (stance, qkey(qa), qkey(qb))
        if ck in self.paths and (self.paths[ck] is not None or self.efforts.get(ck, 1) >= effort):
            return self.paths[ck]
        if np.array_equal(qa, qb):
            self.paths[ck] = [qa]
            return self.paths[ck]
        check_time()
        t = t_step = time.perf_counter()
        path = None
        retry = ck in self.paths  # failed at a smaller effort: the direct path failed then too
        # one contact (a free body swinging about one hold, Bretl 2006, sec. 2.1): no chain to re-close, FIND-PATH
        # tries the straight line first itself, far cheaper than the inverse kinematics of the direct path
        if len(stance) > 1 and not retry and self.s.direct_path:
            path = self.local_path(stance, qa, qb, moving)
            self.direct_times.append(time.perf_counter() - t)
            if path is not None and self.s.same_bend:  # Bretl et al. (2004), sec. 3: the direct path obeys it too
                bend = SameBendCheck(self.robot, stance, qa, qb)
                path = path if all(bend(x) for x in path) else None
        if path is None and self.s.step_time_limit > 0 and manifold_dim(self.robot, stance) > 0:
            path = self._find_path(stance, qa, qb, max(0.1, time_left), effort)
            self.retries += retry
        self.paths[ck] = path
        self.efforts[ck] = effort
        self.step_times.append(time.perf_counter() - t_step)
        return path

    def _find_path(self, stance: Stance, qa: np.ndarray, qb: np.ndarray, budget: float,
                   effort: int = 1) -> list[np.ndarray] | None:
        s = self.s
        self.path_calls += 1
        t = time.perf_counter()
        try:
            opts = PathSettings.of(s, time_limit=budget, cpu_limit=s.step_time_limit * effort, direct=False,
                                   max_iterations=None if s.path_iterations is None else s.path_iterations * effort)
            res = find_path(self.robot, self.terrain, stance, qa, qb, opts, seed=self.seed + 100003 * self.path_calls)
        except QueryError as exc:  # an end point the one-step checker rejects: no path from there
            res = PathResult("rejected", stats={"reason": str(exc)})
        self.path_times.append(time.perf_counter() - t)
        self.path_timeouts += res.status == "timeout"
        self.checks += int(res.stats.get("checks", 0) or 0)
        for k, n in res.stats.get("rejections", {}).items():
            self.rejections[k] = self.rejections.get(k, 0) + int(n)
        if not res.found:
            return None
        path = [np.asarray(x, dtype=float) for x in res.path]
        # the one-step planner's densified waypoints are re-checked (same rules as the direct path and verify)
        if not all(self.feas.valid_moving(stance, x) for x in path[1:-1]):
            self.ompl_rejected += 1
            return None
        return path


__all__ = ["TransitionGraph", "qkey"]
