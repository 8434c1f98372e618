"""A dense-tableau simplex for the tiny LPs of the equilibrium tests, and the exact 2-D projection of a polytope.

The LPs here have 6-30 rows and a few dozen columns: a call into a general solver costs far more
than the arithmetic (about 100 us of binding and set-up per HiGHS call), so a dense tableau that
pivots in place wins; its loops are compiled (:mod:`._kernels`).  Two uses:

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
from typing import Any

import numpy as np

_K: Any = None


def _kernels() -> Any:
    """:mod:`._kernels`, imported on first use (numba's import takes a few tenths of a second)."""
    global _K
    if _K is None:
        from climb_ompl.equilibrium import _kernels as k

        _K = k
    return _K


def _check(status: int) -> None:
    """Raise :class:`SimplexError` for a status of the compiled loops other than ``OK``."""
    if status == _kernels().UNBOUNDED:
        raise SimplexError("unbounded direction")
    if status == _kernels().STALLED:
        raise SimplexError("pivot limit reached (cycling?)")


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
        self._setup(T, basis.tolist(), m, N, p)

    @classmethod
    def from_array(cls, T: np.ndarray, basis: list[int], m: int, N: int, p: int = 0) -> "Tableau":
        """A tableau from a ready array in canonical form (used in place).

        ``T`` is ``(m + p + 1, N + na + 1)``: rows ``[A | artificial columns | b]`` with ``b >= 0`` and every
        row canonical for ``basis[r]`` (a unit column, possibly an artificial), then ``p`` objective rows
        (zero on the basic columns) and last the phase-1 costs (the sum of the rows whose basic variable
        is an artificial).
        """
        self = cls.__new__(cls)
        self._setup(T, basis, m, N, p)
        return self

    @classmethod
    def feasibility(cls, T: np.ndarray, basis: list[int], m: int, N: int) -> "Tableau":
        """Phase-1 tableau of ``{z >= 0 : A z = b}`` from a ready array with no objective rows (:meth:`from_array`)."""
        return cls.from_array(T, basis, m, N, 0)

    def _setup(self, T: np.ndarray, basis: Any, m: int, N: int, p: int) -> None:
        self.T, self.m, self.N, self.p = T, m, N, p
        self.basis = np.array(basis, dtype=np.int64)
        # 0 on non-basic columns, inf on basic ones: added to entering scores to exclude the basis.
        self.banned = np.zeros(T.shape[1] - 1)
        self.banned[self.basis[self.basis >= 0]] = np.inf
        self.pivots = 0
        self.max_pivots = 20 * (m + N) + 100

    # -- pivoting ----------------------------------------------------------------------------------
    def _pivot(self, r: int, j: int) -> None:
        """Pivot on row ``r``, column ``j``."""
        _kernels().pivot(self.T, self.basis, self.banned, r, j)
        self.pivots += 1
        if self.pivots > self.max_pivots:
            raise SimplexError("pivot limit reached (cycling?)")

    # -- phase 1 -----------------------------------------------------------------------------------
    def phase1(self) -> bool:
        """Drive the artificials out (Dantzig's rule); ``False`` when ``{z >= 0 : A z = b}`` is empty.

        On success the artificial columns are dropped and the tableau holds a feasible basis.
        """
        T, N, m = self.T, self.N, self.m
        scale = 1.0 + float(T[:m, -1].max(initial=0.0))  # b >= 0 in canonical form
        status, self.pivots = _kernels().climb(T, self.basis, self.banned, m, N, T.shape[0] - 1, 0.0, 0.0, 0,
                                               self.pivots, self.max_pivots)
        _check(status)
        if T[-1, -1] > 1e-9 * scale:
            return False
        # Artificials still basic (at zero): pivot them out, or blank redundant rows.
        for r in np.flatnonzero(self.basis >= N).tolist():
            row = np.abs(T[r, :N])
            j = int(row.argmax())
            if row[j] > 1e-9:
                self._pivot(r, j)
            else:
                T[r, :] = 0.0
                self.basis[r] = -1
        self.T = np.concatenate((T[:-1, :N], T[:-1, -1:]), axis=1)
        self.banned = self.banned[:N].copy()
        return True

    # -- objectives ----------------------------------------------------------------------------------
    def value(self) -> list[float]:
        """``P z`` at the current basic solution."""
        m = self.m
        return [-float(v) for v in self.T[m:m + self.p, -1]]

    def solution(self) -> np.ndarray:
        """The current basic solution ``z`` (after :meth:`phase1`)."""
        z = np.zeros(self.N)
        rows = np.flatnonzero(self.basis >= 0)
        z[self.basis[rows]] = self.T[rows, -1]
        return z

    def maximise(self, c: np.ndarray) -> None:
        """Primal simplex (Dantzig's rule) to the maximum of ``c . (P z)``."""
        c0 = float(c[0])
        c1 = float(c[1]) if self.p > 1 else 0.0
        status, self.pivots = _kernels().climb(self.T, self.basis, self.banned, self.m, self.N, -1, c0, c1, self.p,
                                               self.pivots, self.max_pivots)
        _check(status)

    def shadow_vertices(self, theta0: float = 0.0) -> np.ndarray:
        """Vertices ``(k, 2)`` of the projection ``{P z}`` counter-clockwise (shadow-vertex simplex).

        Maximises ``d(t) . P z`` with ``d(t) = (cos t, sin t)`` at ``t = theta0``, then turns ``d``
        once around: the next column to enter is the one whose reduced cost ``r_j(t)`` turns positive
        first; its ratio test moves to the adjacent vertex of the projection.  Requires ``p = 2``.
        """
        self.maximise(np.array([math.cos(theta0), math.sin(theta0)]))
        out = np.empty((self.max_pivots - self.pivots + 2, 2))
        status, nv, self.pivots = _kernels().shadow(self.T, self.basis, self.banned, self.m, self.N, theta0,
                                                    self.pivots, self.max_pivots, out)
        _check(status)
        return -out[:nv]
