"""Elbow bends of a stance's contact chain: straight-limb configurations and the same-bend rule of Bretl et al. (2004).

Bretl, Rock, Latombe, Kennedy & Aghazarian (2004), sec. 3: "configurations of the robot with theta_2 = 0 in any limb
of the contact chain (straight-limb configurations) are initially sampled explicitly, since the feasible space
F_sigma is most likely to be disconnected on these manifolds.  During subsequent exploration of F_sigma, we only
attempt to connect those pairs of configurations with identical elbow-bends (i.e., when theta_2 in each limb of the
contact chain has identical sign for both configurations)."

A contact limb's bend is the sign of its elbow angle relative to straight (the robot spec's ``elbow`` joint and
``elbow_straight``); within :data:`BEND_BAND` of straight the limb counts as straight, which connects to either
bend.  :class:`SameBendCheck` imposes the rule as a state-validity check of one FIND-PATH query: a state is valid only
when no contact limb is bent against the query's bend, so every edge the planner keeps (each of its states checked at
the space's resolution) joins configurations with the query's bends, a straight limb counting as either.  Where the
start and the goal bend a limb opposite ways, the paper's rule lets a path change that bend only through a
straight-limb configuration; a state check cannot tell one edge through straight from one that jumps across it, so
that limb is left free (:attr:`SameBendCheck.free`).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

if TYPE_CHECKING:  # pragma: no cover
    from climb_ompl.manifold.stance import Stance
    from climb_ompl.model.robot import RobotModel

#: Distance from straight of a straight-limb sample, radians (the atlas charts are singular exactly at straight).
STRAIGHT_EPS: float = 0.02

#: A contact limb whose elbow is within this of straight counts as straight (either bend), radians: twice a
#: straight-limb sample's offset, so that a sample still counts once projected back onto the stance manifold.
BEND_BAND: float = 2.0 * STRAIGHT_EPS


def elbows(robot: RobotModel, stance: Stance) -> list[tuple[str, int, float]]:
    """The contact limbs of ``stance`` that have an elbow: ``(limb, index into q, straight value in rad)``, in the
    robot's limb order."""
    return [(lb.name, int(lb.elbow_index), float(lb.elbow_straight or 0.0)) for lb in robot.limbs
            if lb.name in stance.limbs and getattr(lb, "elbow_index", None) is not None]


def bend_signature(robot: RobotModel, stance: Stance, q: np.ndarray, band: float = BEND_BAND) -> dict[str, int]:
    """Each contact limb's elbow bend at ``q``: ``+1`` or ``-1`` (the sign of the elbow angle less straight), ``0``
    within ``band`` (rad) of straight."""
    q = np.asarray(q, dtype=float)
    out = {}
    for limb, i, st in elbows(robot, stance):
        e = float(q[i]) - st
        out[limb] = 0 if abs(e) <= band else (1 if e > 0 else -1)
    return out


def is_straight_limb(robot: RobotModel, stance: Stance, q: np.ndarray, band: float = BEND_BAND) -> bool:
    """Whether some contact limb's elbow lies within ``band`` (rad) of straight (a straight-limb configuration)."""
    return 0 in bend_signature(robot, stance, q, band).values()


class SameBendCheck:
    """The same-bend rule as a validity check of one query (module docstring): rejects a configuration with a contact
    limb bent more than ``band`` (rad) against the bend that the query's start and goal share.

    Attributes:
        bends: ``(limb, index, straight, sign)`` of each constrained limb.
        free: the limbs that the start and goal bend opposite ways (not constrained).
    """

    name = "bend"

    def __init__(self, robot: RobotModel, stance: Stance, q_start: np.ndarray, q_goal: np.ndarray,
                 band: float = BEND_BAND):
        a = bend_signature(robot, stance, q_start, band)
        b = bend_signature(robot, stance, q_goal, band)
        self.band = float(band)
        self.bends: list[tuple[str, int, float, int]] = []
        self.free: list[str] = []
        for limb, i, st in elbows(robot, stance):
            if a[limb] and b[limb] and a[limb] != b[limb]:
                self.free.append(limb)
            elif a[limb] or b[limb]:
                self.bends.append((limb, i, st, a[limb] or b[limb]))

    def __call__(self, q: np.ndarray) -> bool:
        return all(s * (float(q[i]) - st) >= -self.band for _, i, st, s in self.bends)


__all__ = ["BEND_BAND", "STRAIGHT_EPS", "SameBendCheck", "bend_signature", "elbows", "is_straight_limb"]
