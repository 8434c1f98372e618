"""The feasibility tests of a climb, built once per stance and shared by every operator of the search.

FIND-TRANSITION (:mod:`climb_ompl.climb.transition`), the direct local path (:mod:`climb_ompl.climb.local_path`) and
the stance-graph search (:mod:`climb_ompl.climb.search`) ask the same questions of a configuration: is it
feasible at this stance (joint limits, static equilibrium, torque limits, collision), and is it a
transition between two stances.  :class:`Feasibility` answers them with the checks of
:func:`climb_ompl.manifold.stance.make_checks`, cached per stance, with one cone model and margin for all of them,
and counts the reasons of rejection.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from climb_ompl.contract import HAND_CONTACT_RADIUS
from climb_ompl.manifold.stance import (
    CollisionCheck,
    Stance,
    limb_hold_targets,
    make_checks,
    stance_region,
)
from climb_ompl.model.terrain import Terrain


def touching_hands(robot: Any, terrain: Terrain, q: np.ndarray, contact_limbs: Any = ()) -> list[str]:
    """Free limbs whose hand is within :data:`~climb_ompl.contract.HAND_CONTACT_RADIUS` of where it would touch a
    hold (:func:`~climb_ompl.manifold.stance.limb_hold_targets`)."""
    H = np.asarray(robot.hand_positions(q), dtype=float)
    out = []
    for i, lb in enumerate(robot.limbs):
        if lb.name in contact_limbs:
            continue
        P = limb_hold_targets(robot, terrain, lb.name)
        if float(np.min(np.linalg.norm(P - H[i], axis=1))) <= HAND_CONTACT_RADIUS:
            out.append(lb.name)
    return out


class Feasibility:
    """Cached feasibility tests of one robot on one terrain.

    Args:
        robot, terrain: the robot and terrain.
        margin: equilibrium margin, metres.
        cone_edges: edges of the linearised friction cones (equilibrium and torque tests alike).
        clearance: smallest distance between two links at a transition, metres.
        torque_cone_edges: edges of the torque check's pyramids (default: ``cone_edges``).
    """

    def __init__(self, robot: Any, terrain: Terrain, *, margin: float = 0.0, cone_edges: int = 8,
                 clearance: float = 0.0, torque_cone_edges: int | None = None):
        self.robot, self.terrain = robot, terrain
        self.margin, self.cone_edges, self.clearance = float(margin), int(cone_edges), float(clearance)
        self.torque_cone_edges = self.cone_edges if torque_cone_edges is None else int(torque_cone_edges)
        self._checks: dict[Any, list[Any]] = {}
        self._regions: dict[Stance, Any] = {}
        #: rejections by reason (check name), summed over every test made through this object
        self.rejections: dict[str, int] = {}

    @classmethod
    def of(cls, robot: Any, terrain: Terrain, settings: Any = None, **changes: Any) -> Feasibility:
        """The tests a climb with ``settings`` (default: :class:`~climb_ompl.settings.ClimbSettings` ``()``)
        makes, with ``changes`` (e.g. ``margin=0.01``)."""
        if settings is None:
            from climb_ompl.settings import ClimbSettings

            settings = ClimbSettings()
        kw = dict(margin=settings.margin, cone_edges=settings.cone_edges, clearance=settings.clearance,
                  torque_cone_edges=settings.torque_cone_edges)
        return cls(robot, terrain, **{**kw, **changes})

    # ---- regions ----------------------------------------------------------------------------------
    def region(self, stance: Stance) -> Any:
        """The support region of ``stance`` (cached)."""
        r = self._regions.get(stance)
        if r is None:
            r = self._regions[stance] = stance_region(self.robot, self.terrain, stance, cone_edges=self.cone_edges)
        return r

    def region_ok(self, stance: Stance) -> bool:
        """Whether ``stance`` has contacts and a non-empty support region."""
        return len(stance) > 0 and (not self.robot.equilibrium or not self.region(stance).is_empty)

    # ---- checks -------------------------------------------------------------------------------------
    def checks(self, stance: Stance, *, collision: bool = True) -> list[Any]:
        """The stance's checks, torque limits per state included (cheap first)."""
        key = (stance, collision)
        c = self._checks.get(key)
        if c is None:
            region = self.region(stance) if self.robot.equilibrium else None
            c = self._checks[key] = make_checks(self.robot, self.terrain, stance, margin=self.margin,
                                                collision=collision, torque="state", region=region,
                                                cone_edges=self.cone_edges,
                                                torque_cone_edges=self.torque_cone_edges)
        return c

    def transition_checks(self, small: Stance, big: Stance) -> list[Any]:
        """Checks of a transition between ``small`` and ``big`` (one more contact): ``small``'s checks
        (its equilibrium binds), collision with ``big``'s hands exempt and the links ``clearance`` apart
        (a transition is where a step starts: links that touch leave no room to lift the next hand)."""
        key = ("transition", small, big)
        c = self._checks.get(key)
        if c is None:
            c = self._checks[key] = [*self.checks(small, collision=False),
                                     CollisionCheck(self.robot, self.terrain, big.limbs, clearance=self.clearance)]
        return c

    def why(self, checks: list[Any], q: np.ndarray) -> str | None:
        """The first failing check's name (counted in :attr:`rejections`), ``None`` when ``q`` passes."""
        for c in checks:
            if not c(q):
                self.rejections[c.name] = self.rejections.get(c.name, 0) + 1
                return c.name
        return None

    def valid(self, stance: Stance, q: np.ndarray) -> bool:
        """All feasibility checks of ``stance`` at ``q``."""
        return self.why(self.checks(stance), q) is None

    def why_moving(self, stance: Stance, q: np.ndarray) -> str | None:
        """The first check ``q`` fails along a motion at ``stance`` (a free hand within the hand-contact
        radius of a hold may touch the terrain: it is leaving or reaching that hold), or ``None``."""
        bad = self.why(self.checks(stance, collision=False), q)
        if bad is not None:
            return bad
        exempt = list(stance.limbs) + touching_hands(self.robot, self.terrain, q, stance.limbs)
        if self.robot.in_collision(q, self.terrain, contact_limbs=tuple(exempt)):
            self.rejections["collision"] = self.rejections.get("collision", 0) + 1
            return "collision"
        return None

    def valid_moving(self, stance: Stance, q: np.ndarray) -> bool:
        """Whether ``q`` passes :meth:`why_moving`."""
        return self.why_moving(stance, q) is None


__all__ = ["Feasibility", "touching_hands"]
