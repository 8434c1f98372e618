"""The compiled tableau simplex (climb_ompl/equilibrium/_simplex.py, _kernels.py) on LPs with closed-form answers.

The polygon tests compare the shadow-vertex output with the vertices of polygons written by hand (a box,
and a regular polygon given by its half-planes); the status tests check that the compiled loops' failure
codes come back as :class:`SimplexError` or an infeasible phase 1.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from climb_ompl.equilibrium._simplex import SimplexError, Tableau
from climb_ompl.equilibrium.region import _ccw_clean


def _halfplane_tableau(normals: np.ndarray, offsets: np.ndarray) -> Tableau:
    """``{x : normals @ x <= offsets}`` (a polygon containing 0) as ``x = u - v`` with ``u, v >= 0`` and slacks.

    Columns: ``u (2), v (2), slacks (m)``; objective rows ``P z = x``.
    """
    m = len(normals)
    A = np.hstack([normals, -normals, np.eye(m)])
    P = np.zeros((2, 4 + m))
    P[0, 0], P[0, 2], P[1, 1], P[1, 3] = 1.0, -1.0, 1.0, -1.0
    return Tableau(A, np.asarray(offsets, dtype=float), P, np.arange(4, 4 + m))


def _same_polygon(V: np.ndarray, W: np.ndarray) -> bool:
    """The shadow-vertex points ``V`` trace the counter-clockwise polygon ``W`` (up to rotation).

    The points may repeat and may include points inside edges (degenerate bases along a face); the
    region code drops those with :func:`_ccw_clean`, which is what is checked here.
    """
    V = _ccw_clean(V)
    if len(V) != len(W):
        return False
    k = int(np.argmin(np.linalg.norm(W - V[0], axis=1)))
    return bool(np.allclose(np.roll(W, -k, axis=0), V, atol=1e-12))


def test_shadow_vertices_of_a_box():
    """The box [-1, 2] x [-0.5, 3]: four vertices, counter-clockwise, starting at the maximum of x."""
    tab = _halfplane_tableau(np.array([[1.0, 0], [-1, 0], [0, 1], [0, -1]]), np.array([2.0, 1.0, 3.0, 0.5]))
    assert tab.phase1()
    V = tab.shadow_vertices()
    assert _same_polygon(V, np.array([[2.0, -0.5], [2.0, 3.0], [-1.0, 3.0], [-1.0, -0.5]]))


@pytest.mark.parametrize("n", [3, 7, 12])
def test_shadow_vertices_of_a_regular_polygon(n):
    """A regular n-gon given by its n half-planes: its n vertices in closed form."""
    a = 2 * np.pi * (np.arange(n) + 0.5) / n  # edge normals
    tab = _halfplane_tableau(np.c_[np.cos(a), np.sin(a)], np.ones(n))
    assert tab.phase1()
    V = tab.shadow_vertices(theta0=0.1)
    b = 2 * np.pi * np.arange(n) / n  # vertices: halfway between consecutive normals, at radius 1 / cos(pi / n)
    assert _same_polygon(V, np.c_[np.cos(b), np.sin(b)] / math.cos(math.pi / n))


def test_phase1_finds_a_feasible_point_or_proves_there_is_none():
    """x1 + x2 = 1, x1 - x2 = b: feasible (x1 = (1 + b) / 2) for |b| <= 1, empty otherwise."""
    for b, feasible in ((0.5, True), (-1.0, True), (1.5, False), (-3.0, False)):
        tab = Tableau(np.array([[1.0, 1.0], [1.0, -1.0]]), np.array([1.0, b]), np.zeros((0, 2)), np.array([-1, -1]))
        assert tab.phase1() is feasible
        if feasible:
            assert np.allclose(tab.solution(), [(1 + b) / 2, (1 - b) / 2])


def test_unbounded_direction_raises():
    """{x >= 0 : x1 - x2 <= 1} has no maximum of x2: the compiled loop's status becomes a SimplexError."""
    tab = Tableau(np.array([[1.0, -1.0, 1.0]]), np.array([1.0]), np.array([[0.0, 1.0, 0.0]]), np.array([2]))
    assert tab.phase1()
    with pytest.raises(SimplexError, match="unbounded"):
        tab.maximise(np.array([1.0]))


def test_pivot_limit_raises():
    """A pivot budget of zero stops the first pivot with a SimplexError (the guard against cycling)."""
    tab = _halfplane_tableau(np.array([[1.0, 0], [-1, 0], [0, 1], [0, -1]]), np.ones(4))
    assert tab.phase1()
    tab.max_pivots = tab.pivots
    with pytest.raises(SimplexError, match="pivot limit"):
        tab.shadow_vertices()
