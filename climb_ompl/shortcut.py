"""Shortcuts of a candidate sequence: a limb's two successive moves folded into one before its paths are planned.

EXPLORE-STANCEGRAPH (Bretl 2006, Fig. 16) returns the first sequence of stances it finds to the goal, and a
weighted best-first search commits early: on a wall of holds leaning 35-65 degrees from the wall, LEMUR's
candidates move a limb up, sideways and back again (a hand from ``h56`` to ``h66``, to ``h37`` and back to ``h56``
while two other limbs take one step each).  Every step costs a path in stage 2 (EXPLORE-TRANSITIONGRAPH) and a
step of the plan, so such detours cost more than finding them did.

A *move* is a release of a limb followed at once by a grab of the same limb (from hold ``b`` to hold ``c``).  For
two successive moves of one limb, ``b -> c`` and later ``c -> d``, with only other limbs' steps between them,
:func:`shorten` tries the sequence that makes one move ``b -> d``: first at the place of the first move (the limb
on ``d`` meanwhile), then at the place of the second (the limb staying on ``b``); when ``d`` is ``b`` the moves
cancel.  The steps between are taken again, each one an edge the search itself would propose, with a transition
found by FIND-TRANSITION about the old one (:meth:`StanceGraphSearch.follow`).  A shortcut is kept only when it
arrives at the stance after the second move in the same component (elbow bends) as the old sequence, so the rest of
the sequence goes on unchanged from there.  Stage 2 then plans the paths as for any candidate; a shortcut whose
path is not found fails as any other edge does.

This is a departure from Fig. 16 (``shortcuts`` in :class:`~climb_ompl.settings.ClimbSettings`; off in the
``paper`` search).
"""

from __future__ import annotations

from typing import Any

Action = tuple[str, str, str]


def moves(chain: list[Any]) -> list[tuple[int, str, str, str]]:
    """The moves of ``chain`` (a list of search nodes): ``(i, limb, from hold, to hold)`` where node ``i`` is
    reached by releasing ``limb`` and node ``i + 1`` by grabbing with it."""
    out = []
    for i in range(1, len(chain) - 1):
        a, b = chain[i].action, chain[i + 1].action
        if a is not None and b is not None and a[0] == "release" and b[0] == "grab" and a[1] == b[1]:
            out.append((i, a[1], a[2], b[2]))
    return out


def _folds(chain: list[Any], m1: tuple[int, str, str, str], m2: tuple[int, str, str, str]) \
        -> list[tuple[list[Action], list[Any]]]:
    """The action sequences replacing nodes ``m1[0] .. m2[0] + 1`` of ``chain`` (and per action the configuration to
    draw its transition about), most promising first."""
    (i1, limb, b, _), (i2, _, _, d) = m1, m2
    between = [chain[k].action for k in range(i1 + 2, i2)]
    near_between = [chain[k].q for k in range(i1 + 2, i2)]
    if d == b:
        return [(between, near_between)]
    rel, grab = ("release", limb, b), ("grab", limb, d)
    return [([rel, grab, *between], [chain[i1].q, chain[i2 + 1].q, *near_between]),
            ([*between, rel, grab], [*near_between, chain[i2].q, chain[i2 + 1].q])]


def shorten(search: Any, chain: list[Any]) -> list[Any]:
    """``chain`` with a limb's successive moves folded into one wherever :meth:`StanceGraphSearch.follow` finds
    the steps between again and arrives in the same component (see the module docstring); repeated until no fold
    applies.  The nodes after a fold are re-linked to it (their transitions are kept)."""
    start = 0
    while True:
        ms = moves(chain)
        folded = False
        for a, m1 in enumerate(ms):
            if m1[0] < start:
                continue
            m2 = next((m for m in ms[a + 1:] if m[1] == m1[1]), None)
            if m2 is None or m2[2] != m1[3]:
                continue
            if any(chain[k].action[1] == m1[1] for k in range(m1[0] + 2, m2[0])):
                continue  # the limb acts between its moves (a release not followed by its grab)
            end = chain[m2[0] + 1]
            for actions, near in _folds(chain, m1, m2):
                node = search.walk(chain[m1[0] - 1], actions, near)
                if node is not None and node.key == end.key:
                    chain = chain[:m1[0]] + _segment(node, chain[m1[0] - 1]) + _relink(search, node, chain[m2[0] + 2:])
                    folded = True
                    break
            if folded:
                start = m1[0] - 1
                break
        if not folded:
            return chain


def _segment(node: Any, root: Any) -> list[Any]:
    """The nodes from ``root`` (excluded) to ``node``, following the parents."""
    out = []
    while node is not root:
        out.append(node)
        node = node.parent
    return out[::-1]


def _relink(search: Any, parent: Any, rest: list[Any]) -> list[Any]:
    """``rest`` (nodes that went on from a node of ``parent``'s key) re-linked after ``parent``."""
    out = []
    for n in rest:
        parent = search.relink(parent, n)
        out.append(parent)
    return out


__all__ = ["moves", "shorten"]
