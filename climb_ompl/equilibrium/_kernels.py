"""Compiled loops of the equilibrium tests (numba, cached on disk): the dense-tableau simplex of :mod:`._simplex`,
and the batch test of many CoMs against a support region (:func:`outside_by_more_than`).

The equilibrium LPs have 6-30 rows and a few dozen columns, so a pivot is a few hundred flops: in
numpy each pivot costs a dozen array calls (about 10 us), in compiled code well under a microsecond.
These functions work in place on the tableau array ``T``, the basis (``int64`` array, ``-1`` for a
blanked row) and ``banned`` (0 on non-basic columns, ``inf`` on basic ones), and return a status
instead of raising (numba's exceptions are costly): :data:`OK`, :data:`UNBOUNDED` or :data:`STALLED`.
:class:`._simplex.Tableau` turns the statuses into :class:`._simplex.SimplexError`.

The first call compiles them (a few seconds, once per machine: ``cache=True`` writes the machine code
next to this file); later processes load it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: Pivot elements and reduced costs below this are treated as zero (the LPs are scaled to O(1)).
EPS = 1e-10
#: Statuses of the loops: done, an unbounded direction, the pivot limit reached.
OK, UNBOUNDED, STALLED = 0, 1, 2

TWO_PI = 2.0 * math.pi


@njit(cache=True)
def pivot(T: np.ndarray, basis: np.ndarray, banned: np.ndarray, r: int, j: int) -> int:  # pragma: no cover - compiled
    """Pivot on row ``r``, column ``j``; returns the column that left the basis (``-1`` if none)."""
    nr, nc = T.shape
    inv = 1.0 / T[r, j]
    for k in range(nc):
        T[r, k] *= inv
    T[r, j] = 1.0
    for i in range(nr):
        if i == r:
            continue
        f = T[i, j]
        if f != 0.0:
            for k in range(nc):
                T[i, k] -= f * T[r, k]
    old = basis[r]
    if old >= 0:
        banned[old] = 0.0
    banned[j] = np.inf
    basis[r] = j
    return old


@njit(cache=True)
def ratio_row(T: np.ndarray, m: int, j: int) -> int:  # pragma: no cover - compiled
    """The leaving row of column ``j`` (minimum ratio, first on ties), ``-1`` if the column is unbounded."""
    b = T.shape[1] - 1
    r, best = -1, np.inf
    for i in range(m):
        c = T[i, j]
        if c > EPS:
            q = T[i, b] / c
            if q < best:
                r, best = i, q
    return r


@njit(cache=True)
def climb(T: np.ndarray, basis: np.ndarray, banned: np.ndarray, m: int, N: int, cost_row: int,
          c0: float, c1: float, p: int, pivots: int, max_pivots: int) -> tuple[int, int]:  # pragma: no cover
    """Primal simplex with Dantzig's rule; returns ``(status, pivots)``.

    The reduced costs are row ``cost_row`` of ``T`` (phase 1: the artificials' sum, ``p = 0``) or
    ``c0 * T[m] + c1 * T[m + 1]`` (``p`` objective rows from row ``m``: maximise ``c . (P z)``).
    """
    while True:
        j, best = -1, EPS
        for k in range(N):
            if p == 0:
                v = T[cost_row, k]
            elif p == 1:
                v = c0 * T[m, k] - banned[k]
            else:
                v = c0 * T[m, k] + c1 * T[m + 1, k] - banned[k]
            if v > best:
                j, best = k, v
        if j < 0:
            return OK, pivots
        r = ratio_row(T, m, j)
        if r < 0:
            return UNBOUNDED, pivots
        pivot(T, basis, banned, r, j)
        pivots += 1
        if pivots > max_pivots:
            return STALLED, pivots


@njit(cache=True)
def shadow(T: np.ndarray, basis: np.ndarray, banned: np.ndarray, m: int, N: int, theta0: float,
           pivots: int, max_pivots: int, out: np.ndarray) -> tuple[int, int, int]:  # pragma: no cover - compiled
    """Shadow-vertex simplex around the projection onto the two objective rows (see ``Tableau.shadow_vertices``).

    Starts at an optimum for the direction ``(cos theta0, sin theta0)``; writes the objective values
    ``(T[m, -1], T[m + 1, -1])`` of each vertex visited to ``out`` (at least ``max_pivots + 1`` rows) and
    returns ``(status, vertices written, pivots)``.
    """
    t = theta0
    b = T.shape[1] - 1
    out[0, 0], out[0, 1] = T[m, b], T[m + 1, b]
    nv = 1
    turned = 0.0
    last = -1
    while True:
        c, s = math.cos(t), math.sin(t)
        # The column whose reduced cost turns positive first as the direction turns counter-clockwise:
        # q0 = minus its reduced cost at t (>= 0 at an optimum), q1 = its derivative; the angle to the
        # zero crossing is |atan2(q0, q1)| (abs folds round-off just above zero).
        j, step = -1, np.inf
        for k in range(N):
            if banned[k] != 0.0:
                continue
            o0, o1 = T[m, k], T[m + 1, k]
            q0 = -c * o0 - s * o1
            q1 = -s * o0 + c * o1
            if abs(q0) + abs(q1) <= EPS:
                continue  # a column that moves no coordinate never enters
            d = abs(math.atan2(q0, q1))
            if k == last and d < 1e-12:
                continue  # the column that just left cannot re-enter at the same angle
            if d < step:
                j, step = k, d
        if j < 0 or turned + step >= TWO_PI - 1e-12:
            return OK, nv, pivots
        turned += step
        t += step
        r = ratio_row(T, m, j)
        if r < 0:
            return UNBOUNDED, nv, pivots
        last = pivot(T, basis, banned, r, j)
        pivots += 1
        if pivots > max_pivots:
            return STALLED, nv, pivots
        out[nv, 0], out[nv, 1] = T[m, b], T[m + 1, b]
        nv += 1


@njit(cache=True)
def outside_by_more_than(C: np.ndarray, basis: np.ndarray, H: np.ndarray, edges: np.ndarray,
                         d: float) -> np.ndarray:  # pragma: no cover - compiled
    """Per world point ``C[i]``, whether it lies more than ``d`` outside the polygon with halfplanes ``H`` (rows
    ``a, b, c``: ``a u + b v <= c``) and edges ``edges`` (rows ``ax, ay, ex, ey, |e|^2``) in the coordinates ``basis``
    (the arithmetic of :meth:`climb_ompl.equilibrium.region.SupportRegion.outside_by_more_than`)."""
    k = C.shape[0]
    out = np.zeros(k, dtype=np.bool_)
    for i in range(k):
        u = C[i, 0] * basis[0, 0] + C[i, 1] * basis[0, 1] + C[i, 2] * basis[0, 2]
        v = C[i, 0] * basis[1, 0] + C[i, 1] * basis[1, 1] + C[i, 2] * basis[1, 2]
        worst = -np.inf
        for h in range(H.shape[0]):
            worst = max(worst, u * H[h, 0] + v * H[h, 1] - H[h, 2])
        if worst > d:
            out[i] = True
        elif worst > 0.0 and edges.shape[0]:  # outside, by at most d from every halfplane: the edges decide
            best = np.inf
            for e in range(edges.shape[0]):
                ax, ay, ex, ey, l2 = edges[e, 0], edges[e, 1], edges[e, 2], edges[e, 3], edges[e, 4]
                s = min(1.0, max(0.0, ((u - ax) * ex + (v - ay) * ey) / l2))
                dx, dy = u - (ax + s * ex), v - (ay + s * ey)
                best = min(best, dx * dx + dy * dy)
            out[i] = math.sqrt(best) > d
    return out
