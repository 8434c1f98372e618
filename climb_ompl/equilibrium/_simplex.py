"""A dense-tableau simplex for the tiny LPs of the equilibrium tests, and the exact 2-D projection of a polytope.

The LPs here have 6-30 rows and a few dozen columns: a call into a compiled solver costs far more
than the arithmetic (about 100 us of binding and set-up per HiGHS call), so a numpy tableau that
pivots in place wins.  Two uses:

* :meth:`Tableau.phase1` finds a basic feasible solution of ``{z >= 0 : A z = b}`` (or proves there is
  none): the per-state torque test.
* :meth:`Tableau.shadow_vertices` traces the projection of that polytope onto two coordinates by the
  *shadow-vertex* (parametric objective) simplex: the objective ``cos(t) p1 + sin(t) p2`` is rotated
  through a full turn, and each pivot moves to the next vertex of the projected polygon, in
  counter-clockwise order.  The polygon is therefore exact (every vertex is a basic solution), found in
  one pivot per vertex, rather than refined by one LP per edge as in the iterative projection of
  Bretl & Lall (2006).

Raises :class:`SimplexError` on cycling or numerical trouble so that callers can fall back to HiGHS.
"""

from __future__ import annotations

import math

import numpy as np

#: Pivot elements and reduced costs below this are treated as zero (the LPs are scaled to O(1)).
EPS = 1e-10
TWO_PI = 2.0 * math.pi


class SimplexError(RuntimeError):
    """The tableau simplex did not finish (pivot limit or a missing pivot): use another solver."""


class Tableau:
    """``{z >= 0 : A z = b}`` with ``p`` linear objectives ``P z`` carried as reduced-cost rows.

    Args:
        A: ``(m, N)`` constraint matrix.
        b: ``(m,)`` right-hand side.
        P: ``(p, N)`` objective rows (the coordinates to project onto), ``p`` in 1..2.
        slack: ``(m,)`` column index of a unit column ``e_r`` usable as row ``r``'s initial basic
            variable (a slack), or ``-1``; rows without one (or with ``b_r < 0``) get an artificial.
    """

    def __init__(self, A: np.ndarray, b: np.ndarray, P: np.ndarray, slack: np.ndarray):
        m, N = A.shape
        p = P.shape[0]
        neg = b < 0
        need = (slack < 0) | neg
        arts = np.flatnonzero(need)
        na = len(arts)
        T = np.zeros((m + p + 1, N + na + 1))
        T[:m, :N] = A
        T[:m, -1] = b
        flip = np.flatnonzero(neg)
        T[flip, :N] *= -1.0
        T[flip, -1] *= -1.0
        T[arts, N + np.arange(na)] = 1.0
        T[m:m + p, :N] = P
        T[-1, :N] = T[arts, :N].sum(axis=0)
        T[-1, -1] = T[arts, -1].sum()
        basis = np.where(need, -1, slack)
        basis[arts] = N + np.arange(na)
        self.T, self.m, self.N, self.p = T, m, N, p
        self.basis = basis.tolist()
        # 0 on non-basic columns, inf on basic ones: added to entering scores to exclude the basis.
        self.banned = np.zeros(N + na)
        self.banned[basis] = np.inf
        self._ratio = np.empty(m)
        self._pos = np.empty(m, dtype=bool)
        self.pivots = 0
        self.max_pivots = 20 * (m + N) + 100

    @classmethod
    def feasibility(cls, T: np.ndarray, basis: list[int], m: int, N: int) -> "Tableau":
        """Phase-1 tableau of ``{z >= 0 : A z = b}`` from a ready array (no objective rows).

        ``T`` is ``(m + 1, N + na + 1)``: rows ``[A | artificial columns | b]`` with ``b >= 0`` and every
        row canonical for ``basis[r]`` (a unit column, possibly an artificial), and the last row the
        phase-1 costs (the sum of the rows whose basic variable is an artificial).  Used in place.
        """
        self = cls.__new__(cls)
        self.T, self.m, self.N, self.p = T, m, N, 0
        self.basis = basis
        self.banned = np.zeros(T.shape[1] - 1)
        self.banned[basis] = np.inf
        self._ratio = np.empty(m)
        self._pos = np.empty(m, dtype=bool)
        self.pivots = 0
        self.max_pivots = 20 * (m + N) + 100
        return self

    # -- pivoting ----------------------------------------------------------------------------------
    def _pivot(self, r: int, j: int) -> None:
        """Pivot on row ``r``, column ``j``."""
        T = self.T
        row = T[r] * (1.0 / T[r, j])
        row[j] = 1.0
        T -= T[:, j:j + 1] * row
        T[r] = row
        old = self.basis[r]
        if old >= 0:
            self.banned[old] = 0.0
        self.banned[j] = np.inf
        self.basis[r] = j
        self.pivots += 1
        if self.pivots > self.max_pivots:
            raise SimplexError("pivot limit reached (cycling?)")

    def _enter(self, j: int) -> int:
        """Bring column ``j`` into the basis (ratio test, then pivot); returns the column that left."""
        m, T = self.m, self.T
        col = T[:m, j]
        pos = self._pos
        np.greater(col, EPS, out=pos)
        ratio = self._ratio
        ratio.fill(np.inf)
        np.divide(T[:m, -1], col, out=ratio, where=pos)
        r = int(ratio.argmin())
        if ratio[r] == np.inf:
            raise SimplexError("unbounded direction")
        left = self.basis[r]
        self._pivot(r, j)
        return left

    # -- phase 1 -----------------------------------------------------------------------------------
    def phase1(self) -> bool:
        """Drive the artificials out (Dantzig's rule); ``False`` when ``{z >= 0 : A z = b}`` is empty.

        On success the artificial columns are dropped and the tableau holds a feasible basis.
        """
        T, N, m = self.T, self.N, self.m
        scale = 1.0 + float(np.abs(T[:m, -1]).max(initial=0.0))
        w = T[-1, :N]
        while True:
            j = int(w.argmax())
            if w[j] <= EPS:
                break
            self._enter(j)
        if T[-1, -1] > 1e-9 * scale:
            return False
        # Artificials still basic (at zero): pivot them out, or blank redundant rows.
        for r in range(m):
            if self.basis[r] < N:
                continue
            row = np.abs(T[r, :N])
            j = int(row.argmax())
            if row[j] > 1e-9:
                self._pivot(r, j)
            else:
                T[r, :] = 0.0
                self.basis[r] = -1
        self.T = np.ascontiguousarray(np.hstack([T[:-1, :N], T[:-1, -1:]]))
        self.banned = self.banned[:N]
        return True

    # -- objectives ----------------------------------------------------------------------------------
    def value(self) -> list[float]:
        """``P z`` at the current basic solution."""
        m = self.m
        return [-float(v) for v in self.T[m:m + self.p, -1]]

    def solution(self) -> np.ndarray:
        """The current basic solution ``z`` (after :meth:`phase1`)."""
        z = np.zeros(self.N)
        for r, j in enumerate(self.basis):
            if j >= 0:
                z[j] = self.T[r, -1]
        return z

    def maximise(self, c: np.ndarray) -> None:
        """Primal simplex (Dantzig's rule) to the maximum of ``c . (P z)``."""
        m, N = self.m, self.N
        while True:
            rc = c @ self.T[m:m + self.p, :N]
            rc -= self.banned
            j = int(rc.argmax())
            if rc[j] <= EPS:
                return
            self._enter(j)

    def shadow_vertices(self, theta0: float = 0.0) -> np.ndarray:
        """Vertices ``(k, 2)`` of the projection ``{P z}`` counter-clockwise (shadow-vertex simplex).

        Maximises ``d(t) . P z`` with ``d(t) = (cos t, sin t)`` at ``t = theta0``, then turns ``d``
        once around: the next column to enter is the one whose reduced cost ``r_j(t)`` turns positive
        first; its ratio test moves to the adjacent vertex of the projection.  Requires ``p = 2``.
        """
        m, N = self.m, self.N
        t = theta0
        self.maximise(np.array([math.cos(t), math.sin(t)]))
        T, banned = self.T, self.banned
        obj = T[m:m + 2, :N]
        verts = [(-float(T[m, -1]), -float(T[m + 1, -1]))]
        turned = 0.0
        last = -1
        R = np.empty((2, 2))
        Q = np.empty((2, N))
        delta = np.empty(N)
        inf = np.inf
        while True:
            c, s = math.cos(t), math.sin(t)
            R[0, 0], R[0, 1], R[1, 0], R[1, 1] = -c, -s, -s, c
            # Row 0: minus the reduced costs at t (>= 0 at an optimum); row 1: their derivatives.
            np.matmul(R, obj, out=Q)
            # Angle to each reduced cost's zero crossing towards positive, in [0, pi] (abs folds the
            # round-off cases of a reduced cost a hair above zero).
            np.arctan2(Q[0], Q[1], out=delta)
            np.abs(delta, out=delta)
            delta += banned
            if last >= 0 and delta[last] < 1e-12:
                delta[last] = inf  # the column that just left cannot re-enter at the same angle
            while True:
                j = int(delta.argmin())
                step = float(delta[j])
                if step == inf or abs(Q[0, j]) + abs(Q[1, j]) > EPS:
                    break
                delta[j] = inf  # a column that moves no coordinate: never entering
            if step == inf or turned + step >= TWO_PI - 1e-12:
                break
            turned += step
            t += step
            last = self._enter(j)
            verts.append((-float(T[m, -1]), -float(T[m + 1, -1])))
        return np.array(verts)
