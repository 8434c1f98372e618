"""Shortcuts of a candidate sequence: a limb's two successive moves folded into one before its paths are planned.

EXPLORE-STANCEGRAPH (Bretl 2006, Fig. 16) returns the first sequence of stances it finds to the goal, and a
weighted best-first search commits early: on a wall of holds leaning 35-65 degrees from the wall, LEMUR's
candidates move a limb up, sideways and back again (a hand from ``h56`` to ``h66``, to ``h37`` and back to ``h56``
while two other limbs take one step each).  Every step costs a path in stage 2 (EXPLORE-TRANSITIONGRAPH) and a
step of the plan.

A *move* is a release of a limb followed at once by a grab of the same limb (from hold ``b`` to hold ``c``).  For
two successive moves of one limb, ``b -> c`` and later ``c -> d``, with only other limbs' steps between them,
:func:`shorten` tries the sequences that make one move ``b -> d``: first at the place of the first move (the limb on
``d`` meanwhile), then at the place of the second (the limb staying on ``b``); when ``d`` is ``b`` the moves cancel.
The steps between are taken again (:meth:`climb_ompl.climb.search.StanceGraphSearch.take_steps`), each one an edge
the search itself would propose, with a transition found by FIND-TRANSITION about the old one.  A shortcut is kept
only when it arrives at the stance after the second move in the same component (elbow bends) as the old sequence, so
the rest of the sequence goes on unchanged from there, and when none of its edges ever failed in stage 2 (an edge
the search dropped, or whose probability it lowered, stays out).  The folds are repeated until none applies, and a
sequence that meets the goal early ends there.  Stage 2 then plans the paths as for any candidate; a shortcut whose
path is not found fails as any other edge does.

This is a departure from Fig. 16 (``shortcuts`` in :class:`~climb_ompl.settings.ClimbSettings`; off in the
``paper`` search).  The routes a re-plan is given to follow are taken as they are, and a re-plan's search that
rejoins the old route (its detours are short) is not shortened.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from climb_ompl.climb.nodes import Action, Node, NodeKey

if TYPE_CHECKING:
    from climb_ompl.climb.edges import EdgeBook


class StepTaker(Protocol):
    """What :func:`shorten` uses of a search (:class:`climb_ompl.climb.search.StanceGraphSearch` is one).

    Attributes:
        edges: the edges' stage-2 failures (``edges.fails``: a fold onto an edge that failed is not taken).
    """

    edges: EdgeBook

    def take_steps(self, start: Node, actions: Sequence[Action], near: Sequence[Any] | None = None, *,
                   record: bool = True) -> Node | None:
        """The node reached by taking ``actions`` from ``start`` (transitions drawn about ``near`` first)."""
        ...

    def arrived(self, key: NodeKey) -> bool:
        """Whether the node ``key`` meets the goal."""
        ...

    def make_node(self, node: Node, key: NodeKey, q: np.ndarray, edge: Action) -> Node:
        """The node ``key`` reached at ``q`` from ``node`` by ``edge``, not recorded."""
        ...

    def record(self, node: Node) -> None:
        """Count ``node`` as explored."""
        ...

#: ``(i, limb, from hold, to hold)``: node ``i`` of a chain is reached by releasing ``limb``, node ``i + 1`` by
#: grabbing with it
Move = tuple[int, str, str, str]


def moves(chain: list[Node]) -> list[Move]:
    """The moves of ``chain`` (search nodes from the start), in order."""
    out = []
    for i in range(1, len(chain) - 1):
        a, b = chain[i].action, chain[i + 1].action
        if a is not None and b is not None and a[0] == "release" and b[0] == "grab" and a[1] == b[1]:
            out.append((i, a[1], a[2], b[2]))
    return out


def _folds(chain: list[Node], m1: Move, m2: Move) -> list[tuple[list[Action], list[Any]]]:
    """The action sequences replacing nodes ``m1[0] .. m2[0] + 1`` of ``chain``, each with the configuration to draw
    each action's transition about, in the order tried."""
    (i1, limb, b, _), (i2, _, _, d) = m1, m2
    between = [chain[k].action for k in range(i1 + 2, i2)]
    near_between = [chain[k].q for k in range(i1 + 2, i2)]
    if d == b:
        return [(between, near_between)]  # type: ignore[list-item]
    rel, grab = ("release", limb, b), ("grab", limb, d)
    early = ([rel, grab, *between], [chain[i1].q, chain[i2 + 1].q, *near_between])
    late = ([*between, rel, grab], [*near_between, chain[i2].q, chain[i2 + 1].q])
    return [early, late] if between else [early]  # type: ignore[list-item]


def _segment(node: Node, root: Node) -> list[Node]:
    """The nodes from ``root`` (excluded) to ``node``, following the parents."""
    out = []
    while node is not root:
        out.append(node)
        node = node.parent  # type: ignore[assignment]
    return out[::-1]


def _clean(search: StepTaker, nodes: list[Node]) -> bool:
    """Whether no edge into ``nodes`` failed in stage 2 (dropped, or its probability lowered)."""
    return not any((n.parent.key, n.stance) in search.edges.fails for n in nodes)  # type: ignore[union-attr]


def shorten(search: StepTaker, chain: list[Node]) -> list[Node]:
    """``chain`` (a candidate from the start to a goal node) with a limb's successive moves folded into one wherever
    the steps between are found again (see the module docstring), ending at its first node that meets the goal (a
    new list; ``chain`` is left as it was).  The nodes after a fold are re-linked to it (their transitions are
    kept)."""
    tried: set[tuple[Any, ...]] = set()
    kept: list[Node] = []  # the nodes of the folds kept (recorded as explored if they stay in the candidate)
    folded = True
    while folded:
        folded = False
        ms = moves(chain)
        for a, m1 in enumerate(ms):
            m2 = next((m for m in ms[a + 1:] if m[1] == m1[1]), None)
            if m2 is None or any(chain[k].action[1] == m1[1] for k in range(m1[0] + 2, m2[0])):  # type: ignore[index]
                continue  # no second move, or the limb acts between its moves (a release not followed by its grab)
            root, end = chain[m1[0] - 1], chain[m2[0] + 1]
            for actions, near in _folds(chain, m1, m2):
                memo = (root.key, tuple(actions), end.key)
                if memo in tried:
                    continue
                tried.add(memo)
                node = search.take_steps(root, actions, near, record=False)
                if node is None or node.key != end.key:
                    continue
                seg = _segment(node, root)
                if not _clean(search, seg):
                    continue
                kept += seg
                chain = chain[:m1[0]] + seg + _follow_on(search, node, chain[m2[0] + 2:])
                folded = True
                break
            if folded:
                break
    first = next((i for i, n in enumerate(chain) if search.arrived(n.key)), len(chain) - 1)
    chain = chain[:first + 1]
    final = {id(n) for n in chain}
    for n in kept:
        if id(n) in final:
            search.record(n)
    return chain


def _follow_on(search: StepTaker, parent: Node, rest: list[Node]) -> list[Node]:
    """``rest`` (nodes that went on from a node of ``parent``'s key) re-linked after ``parent``."""
    out = []
    for n in rest:
        parent = search.make_node(parent, n.key, n.q, n.action)  # type: ignore[arg-type]
        out.append(parent)
    return out


__all__ = ["StepTaker", "moves", "shorten"]
