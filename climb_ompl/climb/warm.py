"""A warm start for a search on a terrain changed since an earlier one (a re-plan, :mod:`climb_ompl.climb.replan`):
what it re-uses of the earlier search and of the earlier plan's route, and the routes it follows before it searches.

Kept: the transitions found, transition points, single-contact components and paths between transitions (or the
knowledge that none was found), of stances that rely on no touched hold; the transitions and paths of the old
plan's route.  Support regions need nothing: they are cached by contact geometry.

Not kept: the first search's failed FIND-TRANSITION calls, its lowered edge probabilities and failure counts.  A
failed call is a bounded number of random draws, not a proof that the edge has no transition; a search from
scratch draws again, and a warm search that took the first one's failures as facts was steered away from the
edges near the goal (along LEMUR's demo climb, failures near the goal took two to four times as long warm as from
scratch until the failures were dropped).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from climb_ompl.climb.nodes import Action, Node
from climb_ompl.climb.transition_graph import qkey

if TYPE_CHECKING:
    from climb_ompl.climb.search import StanceGraphSearch


@dataclass(frozen=True)
class WarmStart:
    """What a search may re-use from an earlier one on a terrain changed since (see the module docstring).

    Attributes:
        search: the earlier :class:`~climb_ompl.climb.search.StanceGraphSearch`, or ``None``.
        touched: ids of the holds the change altered: anything relying on them is dropped.
        route: steps of the earlier plan (:class:`~climb_ompl.plan.file.Step`) that rely on no touched hold: their
            transitions and paths.
        hints: routes to try, in order, before the search proper: each a sequence of ``(action, limb, hold)``
            from the start stance (:meth:`StanceGraphSearch.follow`); a re-plan gives the old route when
            the terrain change moved its holds or changed their friction.
        hint_configs: per hint (the same order; may be shorter), the configurations its transitions had, one per
            action: :meth:`StanceGraphSearch.follow` looks for each transition about it first (a re-plan: the old
            route's own transitions, re-closed onto holds that moved).
        joins: where a search whose goal is stances goes on from them, as ``(stance pairs, configuration)``: a
            goal node of a stance listed here must be in the component of one of its configurations (a re-plan
            rejoining the old route: the route goes on from its own configuration, and a detour arriving in
            another component of the stance has no path to it).
        max_stances: explore at most this many ``(stance, component)`` nodes (``None``: no limit), then stop as
            when the budget is spent: a re-plan's rejoining search, where a search to the goal does better than a
            long detour.
    """

    search: StanceGraphSearch | None = None
    touched: frozenset[str] = frozenset()
    route: tuple[Any, ...] = ()
    hints: tuple[tuple[Action, ...], ...] = ()
    hint_configs: tuple[tuple[Any, ...], ...] = ()
    joins: tuple[tuple[tuple[tuple[str, str], ...], Any], ...] = ()
    max_stances: int | None = None

    def relies_on_none(self, stance: Any) -> bool:
        """Whether ``stance`` holds no touched hold."""
        return not set(stance.hold_ids) & self.touched


def inherit(search: StanceGraphSearch, warm: WarmStart) -> None:
    """Give ``search`` what ``warm`` lets it re-use (see the module docstring): its hints, its limit of nodes, the
    components its goal stances must be reached in, the earlier search's findings on untouched stances and the
    transitions and paths of the earlier route."""
    from climb_ompl.manifold.stance import Stance

    search.warm = warm
    search.budget.max_stances = warm.max_stances
    comps = search.components
    for pairs, q in warm.joins:
        stance = Stance(dict(pairs))
        if comps.bends_name(stance):
            search.joins.setdefault(stance, set()).add(comps.signature(stance, np.asarray(q, dtype=float)))
    ok = warm.relies_on_none
    old = warm.search
    if old is not None:
        # the transitions found only: failures, lowered probabilities and failure counts are drawn anew
        mine, theirs = search.transitions, old.transitions
        for m, t in ((mine.by_edge, theirs.by_edge), (mine.point_sets, theirs.point_sets)):
            m.update({k: v for k, v in t.items() if v is not None and ok(k[0][0]) and ok(k[1])})
        comps.members.update({k: v for k, v in old.components.members.items() if ok(k[0])})
        search.graph.paths.update({k: v for k, v in old.graph.paths.items() if ok(k[0])})
    for step in warm.route:
        stance = Stance(dict(step.stance))
        if not comps.bends_name(stance) or not ok(stance):
            continue  # single contacts and points are named by their history (Components.key)
        wps = [np.asarray(w, dtype=float) for w in step.waypoints]
        nxt = stance.with_hold(step.limb, step.hold) if step.action == "grab" else stance.without(step.limb)
        search.transitions.by_edge.setdefault(((stance, comps.signature(stance, wps[0])), nxt), wps[-1])
        search.graph.paths.setdefault((stance, qkey(wps[0]), qkey(wps[-1])), wps)


def follow_hints(search: StanceGraphSearch, start: Node) -> tuple[list[Node], list[list[np.ndarray]]] | None:
    """The first of the warm start's hints (:attr:`WarmStart.hints`) that reaches the goal and whose paths stage 2
    finds, as ``(chain, paths)``; ``None`` when none does (each one followed counts as a candidate)."""
    warm = search.warm
    for i, hint in enumerate(warm.hints):  # a plan along one needs no exploration
        near: Sequence[Any] | None = warm.hint_configs[i] if i < len(warm.hint_configs) else None
        end = search.follow(start, hint, near)
        if end is None:
            continue
        search.stats.candidates += 1
        chain = end.chain()
        reached, paths = search.stage2.run(chain)
        if reached == len(chain) - 1:
            return chain, paths
    return None


__all__ = ["WarmStart", "follow_hints", "inherit"]
