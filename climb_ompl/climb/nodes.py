"""Nodes of the stance-graph search and their ``(stance, component)`` keys (Bretl 2006, sec. 4.2.3, Fig. 13(b)).

A node of EXPLORE-STANCEGRAPH (:mod:`climb_ompl.climb.search`) is a stance (limb -> hold) together with the connected
component of its feasible space ``F_sigma`` the robot is in, reached at one configuration.  :class:`Components`
names the component: by the bend sign of every contact limb's elbow (sec. 4.2.3: "most of the time, connected
components of ``F_sigma`` differ by an elbow bend"), by the point for a zero-dimensional stance, and by the
transition a single contact was entered through (:meth:`Components.key`).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from climb_ompl.climb.transition_graph import qkey
from climb_ompl.manifold.stance import manifold_dim

#: ``(action, limb, hold)``: a grab or release of ``hold`` by ``limb``
Action = tuple[str, str, str]
#: ``(stance, component label)``
NodeKey = tuple[Any, tuple[Any, ...]]
#: the free limbs' last holds, ``((limb, hold), ...)`` sorted by limb
LastHolds = tuple[tuple[str, str], ...]


@dataclass
class Node:
    """A node of the search: a ``(stance, component)`` key reached at configuration ``q``.

    Attributes:
        key: ``(stance, component label)`` (:meth:`Components.key`).
        q: the configuration it was reached at (radians and metres, the robot's ``nq`` values).
        g: the cost of the route to it, ``sum (1 - ln P)`` over its edges (Bretl 2006, sec. 3.3.3).
        parent: the node it was reached from (``None`` for the start).
        action: ``(grab|release, limb, hold)`` that led here (``None`` for the start).
        last: the free limbs' last holds (:func:`after`).
        depth: steps from the start.
    """

    key: NodeKey
    q: np.ndarray
    g: float
    parent: Node | None
    action: Action | None
    last: LastHolds
    depth: int = 0

    @property
    def stance(self) -> Any:
        """The node's stance."""
        return self.key[0]

    def chain(self) -> list[Node]:
        """The nodes from the start to this one."""
        out, n = [], self
        while n is not None:
            out.append(n)
            n = n.parent
        return out[::-1]


def after(last: LastHolds, action: str, limb: str, hold: str) -> LastHolds:
    """The limbs' last released holds after ``action``: a release records the hold, a grab forgets it."""
    d = dict(last)
    if action == "release":
        d[limb] = hold
    else:
        d.pop(limb, None)
    return tuple(sorted(d.items()))


class Components:
    """The component labels of the search's nodes (Bretl 2006, sec. 4.2.3).

    Args:
        robot: the robot (its limbs' elbow joints name the components).

    Attributes:
        members: single-contact component labels by ``(stance, configuration bytes)`` (see :meth:`key`).
    """

    def __init__(self, robot: Any):
        self.robot = robot
        self.members: dict[tuple[Any, bytes], tuple[Any, ...]] = {}

    def dim(self, stance: Any) -> int:
        """The dimension of the stance's feasible manifold (:func:`climb_ompl.manifold.stance.manifold_dim`)."""
        return manifold_dim(self.robot, stance)

    def signature(self, stance: Any, q: np.ndarray) -> tuple[int, ...]:
        """Elbow-bend signs of the contact limbs: the component label (Bretl 2006, sec. 4.2.3)."""
        out = []
        for limb in stance.limbs:
            idx, straight = (self.robot.limb(limb).elbow_index, self.robot.limb(limb).elbow_straight)
            if idx is not None:
                out.append(int(np.sign(q[idx] - (straight or 0.0))))
        return tuple(out)

    def bends_name(self, stance: Any) -> bool:
        """Whether the components of ``stance`` are named by the contact limbs' elbow bends (:meth:`key`)."""
        return len(stance) > 1 and self.dim(stance) > 0

    def key(self, parent: Node | None, stance: Any, q: np.ndarray) -> NodeKey:
        """The ``(stance, component)`` key of a search node reached at ``q`` from ``parent``.

        With two or more contacts on a manifold of positive dimension, the elbow bends of the contact limbs
        (:meth:`signature`).  Two cases where they name nothing, both met by the double-link robot of Bretl
        (2006), sec. 2.1 (Fig. 5, 13(b)):

        * a zero-dimensional stance (both hands on pegs) is a finite set of points, each its own component:
          the key is the point (in bounded joint space a whole-turn variant is another point);
        * a single contact closes no chain, the elbow of the limb on the hold bends freely: the component is
          named by the transition it was entered through (``("via", parent key)``, ``("start",)`` for the
          root), or by the component of an earlier node in which a path to ``q`` was found
          (:attr:`members`), so ``F_2^1`` entered from peg 1 and ``F_2^3`` entered from peg 3 stay apart
          while re-entering a visited component is recognised.
        """
        if self.dim(stance) <= 0:
            return (stance, ("at", *(round(float(x), 6) for x in q)))
        if len(stance) == 1:
            label = ("via", parent.key) if parent is not None else ("start",)
            return (stance, self.members.setdefault((stance, qkey(q)), label))
        return (stance, self.signature(stance, q))


__all__ = ["Action", "Components", "LastHolds", "Node", "NodeKey", "after"]
