"""How a climb query ended: :class:`ClimbStatus`, the value :class:`climb_ompl.climb.multistep.ClimbResult` carries
beside its ``reason`` (the human sentence), so that callers decide on the outcome without reading the sentence."""

from __future__ import annotations

from enum import StrEnum


class ClimbStatus(StrEnum):
    """The outcome of a climb query (:func:`climb_ompl.climb.multistep.plan_climb`).

    Members:
        FOUND: a plan was found.
        INFEASIBLE_GOAL: no stance of the terrain meets the goal (a height above every hold plus the reach;
            :func:`climb_ompl.climb.frontier.goal_beyond_terrain`), decided before any search.
        GOAL_UNREACHABLE: the goal's holds lie beyond a gap wider than the robot can span from the start's holds
            (:func:`climb_ompl.climb.frontier.goal_beyond_reach`, reason starting with
            :data:`climb_ompl.climb.frontier.CUT_OFF`), decided before any search.
        NO_START: no state to climb from: FIND-TRANSITION found no feasible configuration for the start stance
            (a re-plan: every state of the plan up to the step reached relies on a changed hold).
        EXHAUSTED: EXPLORE-STANCEGRAPH (Bretl 2006, Fig. 16) ran out of edges to try: the stance graph holds no
            route the search could find (it samples, so this is not a proof).
        BUDGET: the time budget (``time_limit``) was spent.
        STANCE_LIMIT: the limit of ``(stance, component)`` nodes explored was reached (a re-plan's rejoining
            search, :attr:`climb_ompl.climb.warm.WarmStart.max_stances`).

    The values are lower-case words (a :class:`str`: JSON writes them as they are).
    """

    FOUND = "found"
    INFEASIBLE_GOAL = "infeasible_goal"
    GOAL_UNREACHABLE = "goal_unreachable"
    NO_START = "no_start"
    EXHAUSTED = "exhausted"
    BUDGET = "budget"
    STANCE_LIMIT = "stance_limit"


__all__ = ["ClimbStatus"]
