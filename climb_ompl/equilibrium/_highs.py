"""A small dense LP held in one HiGHS instance, re-solved with new costs or rows (warm start).

``highspy`` is called directly: scipy's ``linprog`` costs about 1 ms a call here, a warm-started
re-solve through highspy about 0.09 ms.
"""

from __future__ import annotations

import ctypes
import os
import sys

import numpy as np

from climb_ompl.errors import EquilibriumError

_BANNER_SILENCED = False


def new_highs():  # noqa: ANN201 (highspy type only known at run time)
    """A quiet ``highspy.Highs`` instance (:func:`quiet_highs`) tuned for the planner's small LPs re-solved
    with new costs or rows: tight tolerances, primal simplex without presolve."""
    h = quiet_highs()
    h.setOptionValue("primal_feasibility_tolerance", 1e-10)
    h.setOptionValue("dual_feasibility_tolerance", 1e-10)
    # Only costs or a few rows change between solves: primal simplex without presolve re-uses the
    # basis best (measured 10 % faster than the defaults on 3-hold stances).
    h.setOptionValue("presolve", "off")
    h.setOptionValue("simplex_strategy", 4)
    return h


def quiet_highs():  # noqa: ANN201
    """A ``highspy.Highs`` instance with HiGHS's default options, silent and single-threaded.

    HiGHS prints a copyright banner on stdout when the first instance of a process is created; it
    would corrupt the CLI's output, so the first creation runs with file descriptor 1 on /dev/null.
    HiGHS's task scheduler otherwise starts worker threads; for these tiny LPs they only add
    synchronisation (docs/equilibrium.md).
    """
    global _BANNER_SILENCED
    import highspy

    if not _BANNER_SILENCED:
        sys.stdout.flush()
        saved = os.dup(1)
        devnull = os.open(os.devnull, os.O_WRONLY)
        try:
            os.dup2(devnull, 1)
            h = highspy.Highs()
            try:
                ctypes.CDLL(None).fflush(None)
            except (OSError, AttributeError):
                pass
        finally:
            os.dup2(saved, 1)
            os.close(saved)
            os.close(devnull)
        _BANNER_SILENCED = True
    else:
        h = highspy.Highs()
    h.setOptionValue("output_flag", False)
    h.setOptionValue("threads", 1)
    return h


def dense_lp(A: np.ndarray, row_lo: np.ndarray, row_hi: np.ndarray, col_lo: np.ndarray, col_hi: np.ndarray,
             cost: np.ndarray | None = None):  # noqa: ANN201 (highspy type only known at run time)
    """The ``highspy.HighsLp`` of ``min cost.x`` s.t. ``row_lo <= A x <= row_hi``, ``col_lo <= x <= col_hi``
    (``A`` dense, stored column-wise; bounds may be ``+-inf``; no cost: zero)."""
    import highspy

    inf = highspy.kHighsInf
    m, n = A.shape
    lp = highspy.HighsLp()
    lp.num_col_, lp.num_row_ = n, m
    lp.col_cost_ = np.zeros(n) if cost is None else np.asarray(cost, dtype=float)
    lp.col_lower_ = np.clip(col_lo, -inf, inf)
    lp.col_upper_ = np.clip(col_hi, -inf, inf)
    lp.row_lower_ = np.clip(row_lo, -inf, inf)
    lp.row_upper_ = np.clip(row_hi, -inf, inf)
    lp.a_matrix_.format_ = highspy.MatrixFormat.kColwise
    lp.a_matrix_.num_col_, lp.a_matrix_.num_row_ = n, m
    lp.a_matrix_.start_ = np.arange(0, m * n + 1, m, dtype=np.int32)
    lp.a_matrix_.index_ = np.tile(np.arange(m, dtype=np.int32), n)
    lp.a_matrix_.value_ = np.ascontiguousarray(A.T).ravel()
    return lp


class DenseLP:
    """``min cost.x`` s.t. ``row_lo <= A x <= row_hi``, ``col_lo <= x <= col_hi`` in one HiGHS model.

    Args:
        A: (m, n) dense constraint matrix.
        row_lo, row_hi: (m,) row bounds (``+-inf`` allowed).
        col_lo, col_hi: (n,) column bounds.
    """

    def __init__(self, A: np.ndarray, row_lo: np.ndarray, row_hi: np.ndarray, col_lo: np.ndarray,
                 col_hi: np.ndarray):
        import highspy

        self._hs = highspy
        self.h = new_highs()
        self.inf = highspy.kHighsInf
        self.n = A.shape[1]
        self.set_model(A, row_lo, row_hi, col_lo, col_hi)

    def set_model(self, A: np.ndarray, row_lo: np.ndarray, row_hi: np.ndarray, col_lo: np.ndarray,
                  col_hi: np.ndarray, cost: np.ndarray | None = None) -> None:
        """Replace the whole model (keeps the HiGHS instance)."""
        self.h.passModel(dense_lp(A, row_lo, row_hi, col_lo, col_hi, cost))
        self.n = A.shape[1]

    def set_cost(self, idx: np.ndarray, values: np.ndarray) -> None:
        """Change the costs of columns ``idx``."""
        self.h.changeColsCost(len(idx), np.asarray(idx, dtype=np.int32), np.asarray(values, dtype=float))

    def solve(self) -> np.ndarray | None:
        """Solve; the optimal ``x``, or ``None`` when infeasible.

        Raises:
            EquilibriumError: HiGHS ended with another status (numerical trouble).
        """
        self.h.run()
        status = self.h.getModelStatus()
        S = self._hs.HighsModelStatus
        if status == S.kOptimal:
            return np.asarray(self.h.getSolution().col_value)
        if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
            return None
        if status == S.kUnbounded:
            raise EquilibriumError("LP unbounded (internal error: CoM coordinates are boxed)")
        # Numerical trouble: retry once from scratch before giving up.
        self.h.clearSolver()
        self.h.run()
        status = self.h.getModelStatus()
        if status == S.kOptimal:
            return np.asarray(self.h.getSolution().col_value)
        if status in (S.kInfeasible, S.kUnboundedOrInfeasible):
            return None
        raise EquilibriumError(f"HiGHS failed: {self.h.modelStatusToString(status)}")
