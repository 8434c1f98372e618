"""The goal of a climb query: a height, a hold for a limb, or a whole stance."""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any

from climb_ompl.errors import QueryError
from climb_ompl.model.terrain import Terrain


@dataclass(frozen=True)
class Goal:
    """The goal of a climb query.

    Attributes:
        type: ``"height"`` (every contact hold at or above ``height - reach``: a limb in the air does not
            count, so a climb often ends with a release, the last limb below the threshold let go), ``"hold"``
            (``limb`` on ``hold``), ``"stance"`` (exactly :attr:`stance`) or ``"stances"`` (any of
            :attr:`stances`: where a re-plan rejoins the route of the plan it repairs, :mod:`climb_ompl.climb.replan`).
        height: target height, metres along minus gravity (:meth:`Terrain.height`; world ``z`` when gravity
            is along ``-z``), for ``type == "height"``.
        limb, hold: for ``type == "hold"``.
        stance: ``(limb, hold)`` pairs for ``type == "stance"``.
        stances: stances as ``(limb, hold)`` pairs, for ``type == "stances"``.
    """

    type: str
    height: float | None = None
    limb: str | None = None
    hold: str | None = None
    stance: tuple[tuple[str, str], ...] | None = None
    stances: tuple[tuple[tuple[str, str], ...], ...] = ()

    def __post_init__(self) -> None:
        if self.type == "height" and not (isinstance(self.height, (int, float)) and math.isfinite(self.height)):
            raise QueryError(f"goal height: must be a finite number of metres, got {self.height!r}")

    @classmethod
    def parse(cls, goal: Any) -> "Goal":
        """A goal from a :class:`Goal`, a number (height), ``"limb=hold"``, a stance mapping or a goal dict.

        Raises:
            QueryError: none of these.
        """
        if isinstance(goal, Goal):
            return goal
        if isinstance(goal, (int, float)) and not isinstance(goal, bool):
            return cls("height", height=float(goal))
        if isinstance(goal, str) and goal.count("=") == 1:
            limb, hold = (x.strip() for x in goal.split("="))
            if limb and hold:
                return cls("hold", limb=limb, hold=hold)
        if isinstance(goal, Mapping):
            if "type" in goal:
                t = goal["type"]
                if t == "height":
                    return cls("height", height=float(goal["height"]))
                if t == "hold":
                    return cls("hold", limb=str(goal["limb"]), hold=str(goal["hold"]))
                if t == "stance":
                    return cls("stance", stance=tuple(sorted((str(k), str(v)) for k, v in goal["stance"].items())))
            elif goal and all(isinstance(v, str) for v in goal.values()):
                return cls("stance", stance=tuple(sorted((str(k), str(v)) for k, v in goal.items())))
        raise QueryError(f"goal {goal!r}: expected a height (number), 'LIMB=HOLD', a stance mapping or a goal dict")

    def to_dict(self) -> dict[str, Any]:
        """The goal as in the plan file's ``query.goal``."""
        if self.type == "height":
            return {"type": "height", "height": self.height}
        if self.type == "hold":
            return {"type": "hold", "limb": self.limb, "hold": self.hold}
        if self.type == "stances":
            return {"type": "stances", "stances": [dict(x) for x in self.stances]}
        return {"type": "stance", "stance": dict(self.stance or ())}

    def __str__(self) -> str:
        """The goal in words: ``height 1.256 m``, ``fl on h12``, ``stance {fl:h1, ...}``."""
        if self.type == "height":
            return f"height {self.height:.3f} m"
        if self.type == "hold":
            return f"{self.limb} on {self.hold}"
        def text(pairs: Any) -> str:
            return "{" + ", ".join(f"{k}:{v}" for k, v in sorted(pairs)) + "}"

        if self.type == "stances":
            return "one of the stances " + ", ".join(text(x) for x in self.stances)
        return f"stance {text(self.stance or ())}"

    def validate(self, robot: Any, terrain: Terrain) -> None:
        """Check limbs and holds exist.

        Raises:
            QueryError: naming the unknown limb or hold.
        """
        limbs = [lb.name for lb in robot.limbs]
        pairs = [(self.limb, self.hold)] if self.type == "hold" else \
            [p for x in self.stances for p in x] if self.type == "stances" else list(self.stance or ())
        for limb, hold in pairs:
            if limb not in limbs:
                raise QueryError(f"goal: unknown limb {limb!r}; valid limbs: {', '.join(limbs)}")
            if hold not in terrain.hold_ids:
                raise QueryError(f"goal: {terrain.no_hold(hold)}")

    def met(self, stance: Mapping[str, str], terrain: Terrain, reach: float) -> bool:
        """Whether ``stance`` meets the goal (``reach``: the robot's largest limb reach, metres)."""
        if self.type == "height":
            assert self.height is not None
            return bool(stance) and all(terrain.height(h) >= self.height - reach for h in stance.values())
        if self.type == "hold":
            return stance.get(self.limb) == self.hold  # type: ignore[arg-type]
        if self.type == "stances":
            return tuple(sorted(stance.items())) in self.stances
        return dict(stance) == dict(self.stance or ())


#: Rise per metre along the wall below which a terrain is level ground, where a climb of M metres means nothing.
LEVEL = 0.02


def climb_height(robot: Any, terrain: Terrain, stance: Mapping[str, str], climb: float) -> float:
    """The height goal of a climb of ``climb`` metres up the wall's slope above ``stance``'s highest hold: met
    when every contact hold is at least that far up.

    A height goal is met when every contact hold is at or above ``height - reach`` (:class:`Goal`, ``reach`` the
    robot's largest limb reach), so the goal height is the start's highest hold, plus the rise, plus ``reach``.
    Along the slope (:func:`climb_ompl.climb.start.wall_axes`) a metre is ``up_wall . up`` metres of height (1 on a
    vertical wall, 0.26 on a ramp 15 degrees from level).
    """
    slope = wall_slope(terrain)
    if slope < LEVEL:
        raise QueryError(f"climb: terrain {terrain.name!r} rises {slope:.3g} m per metre along its wall (gravity is "
                         "all but perpendicular to it: level ground, or a ceiling): a climb gains no height there; "
                         "give a goal hold (--goal-hold LIMB=HOLD) instead")
    return max(terrain.height(h) for h in stance.values()) + float(climb) * slope + robot_reach(robot)


def wall_slope(terrain: Terrain) -> float:
    """Metres of height (along minus gravity) per metre up the wall's slope (:func:`climb_ompl.climb.start.wall_axes`):
    1 on a vertical wall, 0.26 on a ramp 15 degrees from level."""
    from climb_ompl.climb.start import wall_axes

    return float(wall_axes(terrain)[1] @ terrain.up)


def robot_reach(robot: Any) -> float:
    """The largest limb reach of ``robot`` (metres, first joint to hand): what a height goal subtracts."""
    return max(float(lb.reach) for lb in robot.limbs)


def _m(x: float) -> str:
    """Metres to the millimetre, without a ``-0.000``."""
    text = f"{float(x):.3f}"
    return "0.000" if text == "-0.000" else text


def goal_band_note(goal: Goal, robot: Any, terrain: Terrain, start: Mapping[str, str]) -> str | None:
    """For a height goal whose holds (the terrain's at or above the threshold every contact hold must reach) span less
    than half the height the start stance's holds span: that the terrain may end before every limb can stand up
    there (every limb must end on those holds, and a robot whose limbs stand that far apart may find no stance among
    them); else ``None``.  A note, not a refusal: a robot may stand more compactly than it started (an example:
    docs/climb.md, "Goals")."""
    if goal.type != "height" or goal.height is None or not start:
        return None
    heights = [terrain.height(h) for h in start.values()]
    thr = goal.height - robot_reach(robot)
    band = [z for z in (terrain.height(h) for h in terrain.holds) if z >= thr]
    if not band or max(band) - min(band) >= 0.5 * (max(heights) - min(heights)):
        return None
    return (f"the terrain's {len(band)} holds at or above {_m(thr)} m span {_m(max(band) - min(band))} m of height, "
            f"the start stance's {_m(max(heights) - min(heights))} m: the terrain may end before every limb can stand "
            "up there (a shorter climb, or a terrain with holds higher up)")


def goal_statement(goal: Goal, robot: Any, terrain: Terrain, start: Mapping[str, str],
                   climb: float | None = None) -> str:
    """The goal a search will pursue, in one line, said before it starts: for a height goal the threshold that
    counts (every contact hold at or above ``goal.height - reach``, metres along minus gravity) and how far above the
    start stance's highest hold it lies; given ``climb`` (the ``--climb`` asked for) on a wall that is not vertical,
    that it is measured along the slope (:func:`climb_height`) and the height it gains."""
    if goal.type != "height" or goal.height is None:
        return f"goal: {goal}"
    thr = goal.height - robot_reach(robot)
    hi = max(terrain.height(h) for h in start.values()) if start else thr
    text = (f"goal: every contact hold at or above {_m(thr)} m of height (along minus gravity), {_m(thr - hi)} m "
            "above the start stance's highest hold")
    if climb is not None:
        slope = wall_slope(terrain)
        if abs(slope - 1.0) > 1e-3:
            text += (f"; the climb of {climb:g} m is measured along the wall's slope ({slope:.3f} m of height per "
                     f"metre), {_m(slope * climb)} m of height (--climb-height H asks for H metres of height)")
    return text


def threshold_text(goal: Goal, robot: Any) -> str:
    """A goal in a few words for a table's title: a height goal as the threshold that counts (``every contact hold
    >= 0.239 m``), any other as :meth:`Goal.__str__`."""
    if goal.type != "height" or goal.height is None:
        return str(goal)
    return f"every contact hold >= {_m(goal.height - robot_reach(robot))} m"


def height_report(goal: Goal, robot: Any, terrain: Terrain, start: Mapping[str, str], end: Any = None,
                  climb: float | None = None) -> str:
    """One line on the heights of a height-goal query (metres along minus gravity): the start stance's holds,
    the threshold every contact hold must reach (and how far above the start's highest and lowest holds it lies:
    a tall robot's feet climb the second), given ``end`` (a stance: a mapping or ``(limb, hold)`` pairs) the
    final stance's holds, and given ``climb`` (the ``--climb`` asked for) on a wall that is not vertical, the
    height it rises (a climb is measured along the slope, :func:`climb_height`); and :func:`goal_band_note`."""
    assert goal.type == "height" and goal.height is not None
    reach = robot_reach(robot)
    lo, hi = (f(terrain.height(h) for h in start.values()) for f in (min, max))
    thr = goal.height - reach
    text = (f"heights (m, along minus gravity): start holds {_m(lo)} to {_m(hi)}; goal {_m(goal.height)} = every "
            f"contact hold >= {_m(thr)} (goal minus the largest limb reach {_m(reach)}"
            + (f"; {_m(thr - hi)} above the start's highest hold, {_m(thr - lo)} above its lowest"
               if thr > hi else "") + ")")
    narrow = goal_band_note(goal, robot, terrain, start)
    if narrow:
        text += f"; {narrow}"
    if end:
        ends = [terrain.height(h) for h in dict(end).values()]
        text += f"; end holds {_m(min(ends))} to {_m(max(ends))}"
    if climb is not None:
        slope = wall_slope(terrain)
        if abs(slope - 1.0) > 1e-3:
            text += (f"; the climb of {climb:g} m is measured along the wall's slope, {_m(slope * climb)} m of "
                     "height")
    return text


__all__ = ["Goal", "climb_height", "goal_band_note", "goal_statement", "height_report", "robot_reach", "threshold_text",
           "wall_slope"]
