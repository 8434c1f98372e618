"""The counters of one stance-graph search (:class:`SearchStats`) and the words a search stopped by its budget uses
for them.

The plan file's ``totals`` take the reproducible counters (:func:`climb_ompl.climb.assembly.assemble_plan`), its
``timings`` the wall-clock figures (excluded from the determinism of a seeded run).
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

if TYPE_CHECKING:
    from climb_ompl.climb.transition_graph import TransitionGraph


def counts_text(counts: dict[str, int]) -> str:
    """``{"collision": 12, "ik": 3}`` as ``"collision (12), ik (3)"``, most first, zeros left out."""
    return ", ".join(f"{k} ({n})" for k, n in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])) if n)


@dataclass
class SearchStats:
    """Counters of a stance-graph search (Bretl 2006, Fig. 16).

    Attributes:
        transition_calls: FIND-TRANSITION calls (each call's seed is the search's seed plus a stride times this
            count: :meth:`climb_ompl.climb.edges.TransitionCache.find`).
        transitions_skipped: edges ``transition_failures`` skipped
            (:meth:`~climb_ompl.climb.edges.TransitionCache.get`).
        transition_times: wall-clock seconds of each FIND-TRANSITION call.
        candidates: candidate sequences stage 1 returned (each checked by stage 2).
        path_failures: edges stage 2 found no path for (:meth:`~climb_ompl.climb.edges.EdgeBook.path_failed`).
        repaired: edges stage 2 connected through another transition (its ``repairs``).
        reexpanded: nodes reached again at another configuration (``reexpand``, :mod:`climb_ompl.climb.stage1`).
        shortcut_steps: steps the shortcuts removed from the last candidate (:mod:`climb_ompl.climb.shortcut`).
        failed_steps: the steps (``"grab lh h9"``) whose path was not found, with how often.
    """

    transition_calls: int = 0
    transitions_skipped: int = 0
    transition_times: list[float] = field(default_factory=list)
    candidates: int = 0
    path_failures: int = 0
    repaired: int = 0
    reexpanded: int = 0
    shortcut_steps: int = 0
    failed_steps: dict[str, int] = field(default_factory=dict)

    def to_dict(self, graph: TransitionGraph, explored: int, elapsed: float) -> dict[str, Any]:
        """The counters with those of the transition graph ``graph``, ``explored`` (the number of nodes explored)
        and ``elapsed`` (seconds since the query began), as the search's ``stats()`` gives them."""
        g = graph
        return {"onestep_calls": self.transition_calls + g.path_calls, "transition_calls": self.transition_calls,
                "path_calls": g.path_calls, "path_timeouts": g.path_timeouts, "path_retries": g.retries,
                "stances_explored": explored, "candidates": self.candidates,
                "path_failures": self.path_failures, "rejections": dict(sorted(g.rejections.items())),
                "onestep_median_s": float(np.median(g.step_times)) if g.step_times else 0.0,
                "step_times_s": list(g.step_times), "onestep_times_s": list(g.path_times),
                "transition_times_s": list(self.transition_times), "direct_calls": g.local_path.calls,
                "direct_found": g.local_path.found, "repaired": self.repaired, "reexpanded": self.reexpanded,
                "shortcut_steps": self.shortcut_steps, "transitions_skipped": self.transitions_skipped,
                "total_s": elapsed}

    def timings(self, graph: TransitionGraph, elapsed: float) -> dict[str, Any]:
        """Wall-clock figures, seconds (not reproducible; kept apart in the plan file)."""
        return {"total_s": elapsed,
                "onestep_median_s": float(np.median(graph.step_times)) if graph.step_times else 0.0,
                "step_s": [round(t, 6) for t in graph.step_times],
                "path_s": [round(t, 6) for t in graph.path_times],
                "transition_median_s": float(np.median(self.transition_times)) if self.transition_times else 0.0,
                "transition_total_s": float(sum(self.transition_times))}

    def candidates_text(self, graph: TransitionGraph) -> str:
        """The candidate sequences of a search stopped by its budget, in words: each reached the goal in the
        stance graph (stage 1) and stopped at a step whose path was not found (stage 2)."""
        g = graph
        if not self.candidates:
            return "0 candidate sequences (no sequence of stances to the goal found yet)"
        text = (f"{self.candidates} candidate sequence(s): sequences of stances that reach the goal, each stopped "
                f"at a step whose path was not found, or by the budget ({g.path_calls} FIND-PATH calls, "
                f"{g.path_timeouts} of them stopped by a time guard)")
        if self.failed_steps:
            top = sorted(self.failed_steps.items(), key=lambda kv: (-kv[1], kv[0]))[:3]
            text += "; the steps whose path was not found, most often: " + ", ".join(
                f"{k} ({n} time{'s' if n > 1 else ''})" for k, n in top)
            why = [f"the direct local path stopped on {counts_text(g.local_path.failures)}"] \
                if g.local_path.failures else []
            if any(g.rejections.values()):
                why.append(f"FIND-PATH's samples were rejected for {counts_text(g.rejections)}")
            text += (" (over the whole search, " + "; ".join(why) + ")") if why else ""
        return text


__all__ = ["SearchStats", "counts_text"]
