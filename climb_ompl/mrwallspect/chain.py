"""Chained plane changes: MRWALLSPECT III's hill climbed up and down as one sequence (Kim, Kang & Choi).

The paper's simulation (Kim, Kang & Choi, Fig. 12-15) crosses a 35-degree hill "sequentially": floor to up
slope (concave), up slope to the flat top (convex), top to down slope (convex), down slope to the floor
(concave).  Each transition is planned by :func:`.slope.plan_slope` in its own slope frame (the edge on the
``y`` axis, the first plane ``z = 0``, ``x <= 0``); the next one starts from the posture where the previous
one left the robot (``start_q``), carried into the next frame by :func:`next_start`, and crawls along the
plane between the two edges (``lengths``) before its own transition begins.  A transition's planes end
where the hill's do (the next edge, or :data:`.slope.PLANE_LENGTH` past the first and last edges), so its feet
stay on the hill and its collision solids are the hill's two faces next to its edge.  So the last frame of each
transition and the first frame of the next are the same posture, and each transition is a plan file that
``climb-ompl verify`` checks on its own.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from climb_ompl.errors import ARGUMENT, InputError
from climb_ompl.mrwallspect.geometry import pitch_of
from climb_ompl.mrwallspect.slope import PLANE_LENGTH, SlopeResult, plan_slope


@dataclass
class ChainResult:
    """Outcome of :func:`plan_chain`: one :class:`.slope.SlopeResult` per transition planned (it stops at the
    first that fails), and the edge-to-edge lengths."""

    transitions: list[tuple[float, str, float]]
    lengths: list[float]
    results: list[SlopeResult]

    @property
    def found(self) -> bool:
        """Whether every transition was found."""
        return len(self.results) == len(self.transitions) and all(r.found for r in self.results)

    @property
    def reason(self) -> str:
        """Empty when found, else which transition failed and why."""
        bad = next((i for i, r in enumerate(self.results) if not r.found), None)
        return "" if bad is None else f"transition {bad + 1} ({self.transitions[bad][1]}): {self.results[bad].reason}"

    def world_frames(self) -> list[tuple[np.ndarray, np.ndarray]]:
        """Per transition, the rigid map of its slope frame into the first one's: ``(R, c)`` with
        ``world = c + R @ p`` (a rotation about ``y``)."""
        R, c, out = np.eye(3), np.zeros(3), []
        for r, length in zip(self.results, [*self.lengths, 0.0], strict=False):
            out.append((R, c))
            t2, n2 = (np.asarray(r.plan["planes"][1][k], float) for k in ("direction", "normal"))
            c = c + R @ (length * t2)
            R = R @ np.column_stack([t2, [0.0, 1.0, 0.0], n2])
        return out


def next_start(plan: dict[str, Any], length: float) -> np.ndarray:
    """The last posture of a transition ``plan``, in the slope frame of the next transition, whose edge lies
    ``length`` metres further along this transition's second plane (which is the next one's first plane)."""
    last = plan["frames"][-1]
    t2, n2 = (np.asarray(plan["planes"][1][k], float) for k in ("direction", "normal"))
    q = np.asarray(last["q"], float).copy()
    o = np.array([q[0], 0.0, q[1]])
    q[0], q[1] = float(o @ t2) - length, float(o @ n2)
    q[2] = q[2] - pitch_of(t2)
    return q


def plan_chain(transitions: list[tuple[float, str, float]], lengths: list[float], *, seed: int = 0,
               robot: Any = None, equilibrium: bool = True) -> ChainResult:
    """Plan ``transitions`` (``(angle_deg, kind, tilt_deg)`` each, as :func:`.slope.plan_slope`) one after the
    other, each starting where the previous left the robot; ``lengths[i]`` is the length of the plane between
    edge ``i`` and edge ``i + 1``, metres.

    Raises:
        InputError: ``lengths`` does not have one entry fewer than ``transitions``, or a length is not positive.
    """
    if len(lengths) != max(len(transitions) - 1, 0):
        raise InputError(ARGUMENT, "lengths", f"need {max(len(transitions) - 1, 0)} plane lengths between "
                         f"{len(transitions)} transitions, got {len(lengths)}")
    if not all(np.isfinite(x) and x > 0 for x in lengths):
        raise InputError(ARGUMENT, "lengths", f"must be positive lengths in metres, got {list(lengths)}")
    out = ChainResult(list(transitions), [float(x) for x in lengths], [])
    start = None
    for i, (angle, kind, tilt) in enumerate(transitions):
        ends = (lengths[i - 1] if i else PLANE_LENGTH, lengths[i] if i < len(lengths) else PLANE_LENGTH)
        res = plan_slope(angle, kind, tilt_deg=tilt, seed=seed, robot=robot, equilibrium=equilibrium, start_q=start,
                         plane_lengths=ends)
        out.results.append(res)
        if not res.found:
            break
        if i < len(lengths):
            start = next_start(res.plan, lengths[i])
    return out


def hill(angle_deg: float = 35.0, up: float = 1.0, top: float = 1.0, down: float = 1.0
         ) -> tuple[list[tuple[float, str, float]], list[float]]:
    """The hill of Kim, Kang & Choi, Fig. 12-15: transitions and plane lengths for :func:`plan_chain`
    (``up``, ``top``, ``down``: lengths of the up slope, the flat top and the down slope, metres)."""
    a = float(angle_deg)
    return [(a, "concave", 0.0), (a, "convex", a), (a, "convex", 0.0), (a, "concave", -a)], [up, top, down]
