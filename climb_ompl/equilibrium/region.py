"""Support regions: the CoM positions at which a stance can be in static equilibrium.

Bretl (2006) appendix B: with contact forces ``f_i`` at holds ``r_i``, mass ``m`` and gravity ``g``,

* (B1) ``sum f_i + m g = 0``, (B2) ``sum r_i x f_i + c x m g = 0``,
* (B3) ``|(I - n_i n_i^T) f_i| <= mu_i n_i^T f_i``.

(B1)-(B2) do not depend on the CoM's component along gravity, so the set of feasible CoM positions is
a prism along gravity over a convex region of the plane perpendicular to it: a polygon in 3-D (the
*support polygon*, Bretl, Latombe & Rock (2003) eq. (7)) and an interval in 2-D (their eq. (1)).

* Linearised cones (Bretl, Latombe & Rock (2003) eq. (6)): the region is the projection of a
  polytope of cone-edge weights, traced exactly by the shadow-vertex simplex of :mod:`._simplex`
  (one pivot per vertex).  Should it stall, the *iterative projection* of Bretl & Lall (2006) (one
  HiGHS LP per edge, warm-started) takes over; planar intervals are two HiGHS LPs.
* ``exact=True``: second-order cones; the SOCPs go straight to Clarabel and the curved boundary is
  refined by the sandwich projection of :mod:`._exact` to a stated tolerance.
"""

from __future__ import annotations

import math
from collections import OrderedDict
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from climb_ompl.equilibrium._contacts import (
    CONE_EDGES,
    Contact,
    Linearised,
    _ring,
    as_contacts,
    balance_rows,
    check_mass_gravity,
    check_planar_contacts,
    com_columns,
    cross,
    gravity_basis,
    linearise,
    wrench_matrix,
)
from climb_ompl.equilibrium._exact import clarabel_support, sandwich_projection
from climb_ompl.equilibrium._highs import DenseLP
from climb_ompl.equilibrium._simplex import SimplexError, Tableau
from climb_ompl.errors import EquilibriumError

#: Half-width (metres) of the box around the contacts' centroid that bounds unbounded regions.
CLIP = 20.0
#: Default refinement tolerance of the iterative projection (metres): linearised / exact cones.
TOL_LP = 1e-9
TOL_EXACT = 1e-4


# ---- the region --------------------------------------------------------------------------------------
@dataclass(frozen=True, eq=False)
class SupportRegion:
    """Convex set of CoM positions in static equilibrium (a prism along gravity over a polygon/interval).

    Coordinates: a world point ``p`` maps to ``basis @ p`` (2 numbers in 3-D, 1 for planar problems),
    the components of ``p`` perpendicular to gravity (Bretl (2006) appendix B: the region ignores the
    component along gravity).

    Attributes:
        basis: ``(2, 3)`` rows ``u, v`` (3-D; ``u x v`` points up) or ``(1, 3)`` row ``u`` (planar).
        vertices: ``(m, 2)`` polygon vertices counter-clockwise, or ``(m, 1)`` interval ends (planar);
            unbounded regions are clipped by a box of half-width :data:`CLIP` metres around the
            contacts, so some vertices then lie on that box.  ``m`` is 1 (a point) or 2 (a segment)
            for degenerate regions and 0 for empty ones.
        halfplanes: ``(E, 3)`` rows ``a, b, c`` meaning ``a*u + b*v <= c`` with ``(a, b)`` a unit
            vector, metres (planar: ``b = 0``); the clip box is not among them.
        is_empty: no CoM position is in equilibrium.
        is_bounded: the region is bounded (no side reaches the clip box).
        planar: 2-D problem (x-z plane): the region is an interval of the ``u`` coordinate.
        exact: computed with second-order (exact) friction cones.
        cone_edges: edges of the linearised cones (ignored when ``exact``).
        tol: refinement tolerance, metres: the true region lies within ``tol`` outside every edge.
        n_solves: LPs/SOCPs solved to compute it.
    """

    basis: np.ndarray
    vertices: np.ndarray
    halfplanes: np.ndarray
    is_empty: bool
    is_bounded: bool
    planar: bool = False
    exact: bool = False
    cone_edges: int = CONE_EDGES
    tol: float = TOL_LP
    n_solves: int = 0
    _box: np.ndarray = field(default_factory=lambda: np.zeros((0, 3)), repr=False)

    # -- coordinates ----------------------------------------------------------------------------
    def coords(self, points: Any) -> np.ndarray:
        """Region coordinates ``(N, d)`` of world points ``(3,)``/``(N, 3)``.

        Planar regions also take ``[x, z]`` pairs ``(2,)``/``(N, 2)``; 3-D regions take ``(N, 2)``
        points already in region coordinates.

        Raises:
            EquilibriumError: bad shape or non-finite values.
        """
        P = np.asarray(points, dtype=float)
        if P.ndim == 1:
            P = P[None, :]
        if P.ndim != 2 or P.shape[1] not in (2, 3):
            raise EquilibriumError(f"com: expected shape (3,) or (N, 3), got {np.shape(points)}")
        if not np.isfinite(P.sum()):
            raise EquilibriumError("com: non-finite value in the CoM position(s)")
        if P.shape[1] == 3:
            B = self.basis  # explicit columns: no BLAS call (its threads thrash on a loaded machine)
            return P[:, 0:1] * B[:, 0] + P[:, 1:2] * B[:, 1] + P[:, 2:3] * B[:, 2]
        if self.planar:
            return P[:, 0:1] * self.basis[:, 0] + P[:, 1:2] * self.basis[:, 2]
        return P

    @classmethod
    def assemble(cls, basis: np.ndarray, vertices: np.ndarray, halfplanes: np.ndarray, is_empty: bool,
                 is_bounded: bool, box: np.ndarray, cone_edges: int, tol: float) -> "SupportRegion":
        """A linearised 3-D region from one shadow-vertex pass (``n_solves = 1``), without the dataclass's
        per-field set-up (a few microseconds of the region's whole cost on small stances)."""
        self = cls.__new__(cls)
        self.__dict__.update(basis=basis, vertices=vertices, halfplanes=halfplanes, is_empty=is_empty,
                             is_bounded=is_bounded, planar=False, exact=False, cone_edges=cone_edges, tol=tol,
                             n_solves=1, _box=box)
        return self

    def __getattr__(self, name: str) -> Any:
        # Derived on first use, then plain attributes: the Python-float copies of the single-point fast path (one
        # call per sampled state) and the polygon's edges (start, direction, squared length) for the single-point
        # distance outside.  Most regions a search computes are never tested (empty, or never sampled in).
        if name == "_fast":
            value: Any = (tuple(map(tuple, self.basis.tolist())), tuple(map(tuple, self.halfplanes.tolist())))
        elif name == "_edges":
            V = self.vertices.tolist() if not self.planar and len(self.vertices) >= 3 else []
            edges = []
            for (ax, ay), (bx, by) in zip(V, V[1:] + V[:1], strict=True):
                ex, ey = bx - ax, by - ay
                edges.append((ax, ay, ex, ey, max(ex * ex + ey * ey, 1e-300)))
            value = tuple(edges)
        else:
            raise AttributeError(f"{type(self).__name__!r} object has no attribute {name!r}")
        object.__setattr__(self, name, value)
        return value

    def _fast_coords(self, com: Any) -> tuple[float, ...] | None:
        if isinstance(com, np.ndarray) and com.shape == (3,) or isinstance(com, (tuple, list)) and len(com) == 3:
            x, y, z = float(com[0]), float(com[1]), float(com[2])
            if x - x == 0 and y - y == 0 and z - z == 0:  # finite
                return tuple(b0 * x + b1 * y + b2 * z for b0, b1, b2 in self._fast[0])
        return None

    @property
    def interval(self) -> tuple[float, float]:
        """Planar regions: ``(lo, hi)`` of the ``u`` coordinate (``-inf``/``inf`` when unbounded).

        Raises:
            EquilibriumError: the region is not planar.
        """
        if not self.planar:
            raise EquilibriumError("interval: only planar regions are intervals")
        if self.is_empty:
            return (np.nan, np.nan)
        lo, hi = -np.inf, np.inf
        for a, _, c in self.halfplanes:
            if a > 0:
                hi = c
            else:
                lo = -c
        return (float(lo), float(hi))

    # -- membership -----------------------------------------------------------------------------
    def contains(self, com: Any, tol: float = 1e-9) -> bool | np.ndarray:
        """Whether CoM positions are in the region (vectorised).

        Args:
            com: ``(3,)`` or ``(N, 3)`` world points, metres (see :meth:`coords`).
            tol: slack in metres (degenerate regions have no interior).

        Returns:
            A bool for one point, else an ``(N,)`` bool array.
        """
        if not self.planar and not self.is_empty:
            u = self._fast_coords(com)
            if u is not None:
                return all(a * u[0] + b * u[1] <= c + tol for a, b, c in self._fast[1])
        X = self.coords(com)
        if self.is_empty:
            out = np.zeros(len(X), dtype=bool)
        elif self.planar:
            lo, hi = self.interval
            out = (X[:, 0] >= lo - tol) & (X[:, 0] <= hi + tol)
        else:
            out = np.ones(len(X), dtype=bool)
            u, v = X[:, 0], X[:, 1]
            for a, b, c in self._fast[1]:
                out &= u * a + v * b <= c + tol
        return bool(out[0]) if np.ndim(com) == 1 else out

    def margin(self, com: Any) -> float | np.ndarray:
        """Signed distance of CoM positions to the region's boundary, metres (vectorised).

        Positive inside (the distance to the nearest edge), negative outside (minus the Euclidean
        distance to the region), ``-inf`` for an empty region.  Measured perpendicular to gravity.

        Args:
            com: ``(3,)`` or ``(N, 3)`` world points, metres (see :meth:`coords`).
        """
        if not self.planar and not self.is_empty and len(self.vertices) >= 3:
            u = self._fast_coords(com)
            if u is not None:
                inner = min((c - a * u[0] - b * u[1] for a, b, c in self._fast[1]), default=np.inf)
                if inner >= 0:
                    return float(inner)
        X = self.coords(com)
        out = self._margin(X)
        return float(out[0]) if np.ndim(com) == 1 else out

    def outside_by_more_than(self, com: Any, d: float) -> bool:
        """Whether ``margin(com) < -d``: the CoM more than ``d`` metres outside the region (or, for ``d < 0``,
        inside by less than ``-d``).

        The halfplanes settle most points without the distance to the polygon: the largest violation of a
        halfplane is a lower bound of the distance outside (the polygon lies in every halfplane), and minus the
        margin inside.  The rest (outside, but by at most ``d`` from every halfplane) are settled by the distance to
        the polygon's edges on Python floats, about ten times faster than :meth:`margin` for one point
        (docs/equilibrium.md): FIND-TRANSITION asks this of every base draw (:mod:`climb_ompl.climb.transition`).
        """
        if not self.planar and not self.is_empty and len(self.vertices) >= 3:
            u = self._fast_coords(com)
            if u is not None:
                worst = max((a * u[0] + b * u[1] - c for a, b, c in self._fast[1]), default=-math.inf)
                if worst > d:
                    return True
                if worst <= 0:
                    return False
                # outside, by at most d from every halfplane: the distance to the polygon decides, on Python
                # floats (as :func:`_dist_polyline` for one point, without its array overhead)
                x, y, best = u[0], u[1], math.inf
                for ax, ay, ex, ey, l2 in self._edges:
                    t = min(1.0, max(0.0, ((x - ax) * ex + (y - ay) * ey) / l2))
                    dx, dy = x - (ax + t * ex), y - (ay + t * ey)
                    best = min(best, dx * dx + dy * dy)
                return math.sqrt(best) > d
        return bool(self.margin(com) < -d)

    def outside_many(self, coms: np.ndarray, d: float) -> np.ndarray:
        """:meth:`outside_by_more_than` of each row of ``coms`` ``(k, 3)``; ``(k,)`` bool, with the same arithmetic in
        compiled code (:func:`climb_ompl.equilibrium._kernels.outside_by_more_than`): the halfplanes, then for the
        points they
        leave undecided (outside, but by at most ``d`` from every halfplane) the distance to the polygon's edges."""
        from climb_ompl.equilibrium._kernels import outside_by_more_than

        C = np.ascontiguousarray(coms, dtype=float).reshape(-1, 3)
        if self.planar or self.is_empty or len(self.vertices) < 3 or not np.isfinite(C.sum()):
            return np.array([self.outside_by_more_than(c, d) for c in C], dtype=bool)
        arr = self.__dict__.get("_kernel_arrays")
        if arr is None:  # (the basis, halfplanes and edges as the kernel takes them, once per region)
            arr = (np.array(self._fast[0], dtype=float), np.ascontiguousarray(self.halfplanes, dtype=float),
                   np.array(self._edges, dtype=float).reshape(-1, 5))
            object.__setattr__(self, "_kernel_arrays", arr)
        return outside_by_more_than(C, *arr, float(d))

    def _margin(self, X: np.ndarray) -> np.ndarray:
        n = len(X)
        if self.is_empty:
            return np.full(n, -np.inf)
        if self.planar:
            lo, hi = self.interval
            return np.minimum(X[:, 0] - lo, hi - X[:, 0])
        inner = np.full(n, np.inf)
        for a, b, c in self._fast[1]:
            np.minimum(inner, c - a * X[:, 0] - b * X[:, 1], out=inner)
        V = self.vertices
        if len(V) < 3 and len(V) > 0:
            # No interior: minus the distance to the point/segment (0 on it).
            return -_dist_polyline(X, V, closed=False)
        inside = inner >= 0
        out = inner.copy()
        if not np.all(inside):
            out[~inside] = -_dist_polyline(X[~inside], V, closed=True)
        return out

    # -- derived regions ------------------------------------------------------------------------
    def shrink(self, d: float) -> "SupportRegion":
        """The region shrunk by ``d >= 0`` metres (every edge moved inwards: a safety margin).

        Raises:
            EquilibriumError: ``d`` negative or non-finite.
        """
        d = float(d)
        if not np.isfinite(d) or d < 0:
            raise EquilibriumError(f"shrink: the margin must be finite and >= 0 m, got {d!r}")
        if d == 0 or self.is_empty:
            return self
        H = self.halfplanes.copy()
        H[:, -1] -= d
        if self.planar:
            lo, hi = self.interval
            lo, hi = lo + d, hi - d
            if lo > hi:
                return _empty(self)
            V = np.array([[x] for x in (lo, hi) if np.isfinite(x)])
            return _replace(self, vertices=V, halfplanes=H)
        if len(self.vertices) < 3:
            return _empty(self)
        V = _halfplane_polygon(np.vstack([H, self._box]))
        if len(V) < 3:
            return _empty(self)
        return _replace(self, vertices=V, halfplanes=H)

    @property
    def area(self) -> float:
        """Area of the (clipped) polygon, m^2 (planar: the clipped interval's length, m)."""
        V = self.vertices
        if self.planar:
            return float(V[:, 0].max() - V[:, 0].min()) if len(V) else 0.0
        if len(V) < 3:
            return 0.0
        x, y = V[:, 0], V[:, 1]
        return float(0.5 * (x @ np.roll(y, -1) - y @ np.roll(x, -1)))


def _replace(r: SupportRegion, **kw: Any) -> SupportRegion:
    d = {k: getattr(r, k) for k in r.__dataclass_fields__}
    d.update(kw)
    return SupportRegion(**d)


def _empty(r: SupportRegion) -> SupportRegion:
    dim = r.basis.shape[0]
    return _replace(r, vertices=np.zeros((0, dim)), halfplanes=np.zeros((0, 3)), is_empty=True, is_bounded=True)


# ---- planar geometry helpers ---------------------------------------------------------------------------
def _dist_polyline(X: np.ndarray, V: np.ndarray, closed: bool) -> np.ndarray:
    """Euclidean distance of points ``X (N, 2)`` to the polyline/polygon boundary through ``V``."""
    if len(V) == 1:
        return np.linalg.norm(X - V[0], axis=1)
    A = V if closed else V[:-1]
    B = np.roll(V, -1, axis=0) if closed else V[1:]
    E = B - A  # (e, 2)
    L2 = np.maximum(np.einsum("ij,ij->i", E, E), 1e-300)
    # t (N, e): projection parameter of each point on each edge, clamped.
    t = ((X[:, None, 0] - A[None, :, 0]) * E[None, :, 0] + (X[:, None, 1] - A[None, :, 1]) * E[None, :, 1]) / L2
    np.clip(t, 0.0, 1.0, out=t)
    dx = X[:, None, 0] - (A[None, :, 0] + t * E[None, :, 0])
    dy = X[:, None, 1] - (A[None, :, 1] + t * E[None, :, 1])
    return np.sqrt(np.min(dx * dx + dy * dy, axis=1))


def _hull(P: np.ndarray, eps: float = 1e-10) -> np.ndarray:
    """Convex hull (counter-clockwise, no collinear points within ``eps`` metres) of points ``(n, 2)``.

    Andrew's monotone chain on Python floats (the point sets are small: a few dozen vertices).
    """
    if not len(P):
        return P
    pts = sorted({(round(x / eps) * eps, round(y / eps) * eps) for x, y in P.tolist()})
    if len(pts) <= 2:
        return np.array(pts, dtype=float)

    def half(points: list[tuple[float, float]]) -> list[tuple[float, float]]:
        h: list[tuple[float, float]] = []
        for px, py in points:
            while len(h) >= 2:
                (ax, ay), (bx, by) = h[-2], h[-1]
                cr = (bx - ax) * (py - ay) - (by - ay) * (px - ax)
                if cr <= eps * math.hypot(px - ax, py - ay):
                    h.pop()
                else:
                    break
            h.append((px, py))
        return h

    lower, upper = half(pts), half(pts[::-1])
    H = lower[:-1] + upper[:-1]
    if len(H) < 2:
        # All points collinear: keep the two extremes.
        P2 = np.array(pts)
        d = P2[-1] - P2[0]
        s = (P2 - P2[0]) @ d
        return P2[[int(np.argmin(s)), int(np.argmax(s))]]
    return np.array(H, dtype=float)


def _ccw_clean(P: np.ndarray, eps: float = 1e-10) -> np.ndarray:
    """Polygon vertices from boundary points already in counter-clockwise order (the shadow-vertex output).

    Snaps the points to an ``eps`` grid, then drops repeated points and points that do not make a left
    turn (collinear within ``eps`` metres), in passes until none is left; ``(0, 2)`` if fewer than three
    vertices remain.
    """
    out: list[list[float]] = []
    for p in (np.round(P / eps) * eps).tolist():  # the same grid as :func:`_hull`
        if not out or abs(p[0] - out[-1][0]) > eps or abs(p[1] - out[-1][1]) > eps:
            out.append(p)
    while len(out) > 1 and abs(out[0][0] - out[-1][0]) <= eps and abs(out[0][1] - out[-1][1]) <= eps:
        out.pop()
    V = np.array(out).reshape(-1, 2)
    while len(V) >= 3:
        # Keep B when A -> B -> C (its neighbours) turns left by more than eps metres.
        A = np.concatenate((V[-1:], V[:-1]))
        ab, ac = V - A, np.concatenate((V[1:], V[:1])) - A
        keep = ab[:, 0] * ac[:, 1] - ab[:, 1] * ac[:, 0] > eps * np.hypot(ac[:, 0], ac[:, 1])
        if keep.all():
            return V
        V = V[keep]
    return np.zeros((0, 2))


def _halfplane_polygon(H: np.ndarray, eps: float = 1e-9) -> np.ndarray:
    """Vertices (counter-clockwise) of the bounded polygon ``{x : H[:, :2] x <= H[:, 2]}``."""
    n = len(H)
    i, j = np.triu_indices(n, 1)
    A = np.stack([H[i, :2], H[j, :2]], axis=1)  # (p, 2, 2)
    det = A[:, 0, 0] * A[:, 1, 1] - A[:, 0, 1] * A[:, 1, 0]
    ok = np.abs(det) > 1e-12
    A, b, det = A[ok], np.stack([H[i, 2], H[j, 2]], axis=1)[ok], det[ok]
    x = (b[:, 0] * A[:, 1, 1] - b[:, 1] * A[:, 0, 1]) / det
    y = (A[:, 0, 0] * b[:, 1] - A[:, 1, 0] * b[:, 0]) / det
    P = np.stack([x, y], axis=1)
    feas = np.all(P @ H[:, :2].T <= H[:, 2] + eps, axis=1)
    return _hull(P[feas]) if feas.any() else np.zeros((0, 2))


def _edges(V: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Outward unit normals ``(m, 2)`` and offsets ``(m,)`` of the edges ``V[i] -> V[i+1]`` of a ccw polygon."""
    e = np.concatenate((V[1:], V[:1])) - V
    L = np.sqrt(e[:, 0] * e[:, 0] + e[:, 1] * e[:, 1])
    nrm = np.empty_like(e)
    nrm[:, 0] = e[:, 1] / L
    nrm[:, 1] = -e[:, 0] / L
    return nrm, nrm[:, 0] * V[:, 0] + nrm[:, 1] * V[:, 1]


def _polygon_region(verts: np.ndarray, basis: np.ndarray, center: np.ndarray, clip: float, ordered: bool = False,
                    **meta: Any) -> SupportRegion:
    """A region from the support points found by the projection (absolute region coordinates).

    ``ordered``: the points are the boundary in counter-clockwise order (cleaned instead of hulled).
    """
    V = _ccw_clean(verts) if ordered else np.zeros((0, 2))
    if len(V) < 3:
        V = _hull(verts)
    cx, cy = float(center[0]), float(center[1])
    box_lines = np.array([[1.0, 0.0, cx + clip], [-1.0, 0.0, clip - cx], [0.0, 1.0, cy + clip],
                          [0.0, -1.0, clip - cy]])
    # Degenerate regions: a point or a segment (zero width, no interior).
    if len(V) >= 3:
        nrm, c = _edges(V)
        width = float((c[:, None] - nrm @ V.T).max(axis=1).min())  # (edge, vertex) depth inside
        if width < 1e-9:
            d = V - V[0]
            s = d @ (d[np.argmax(np.linalg.norm(d, axis=1))])
            V = V[[int(np.argmin(s)), int(np.argmax(s))]]
    if len(V) == 2 and np.linalg.norm(V[1] - V[0]) < 1e-9:
        V = V[:1]
    on_box = np.abs(V - center).max(axis=1) >= clip - 1e-6
    bounded = not bool(on_box.any())
    if len(V) == 1:
        p = V[0]
        H = np.array([[1, 0, p[0]], [-1, 0, -p[0]], [0, 1, p[1]], [0, -1, -p[1]]], dtype=float)
    elif len(V) == 2:
        d = (V[1] - V[0]) / np.linalg.norm(V[1] - V[0])
        n = np.array([d[1], -d[0]])
        rows = [[*n, n @ V[0]], [*-n, -n @ V[0]]]
        if not on_box[0]:
            rows.append([*-d, -d @ V[0]])
        if not on_box[1]:
            rows.append([*d, d @ V[1]])
        H = np.array(rows, dtype=float)
    else:
        H = np.empty((len(V), 3))
        H[:, :2], H[:, 2] = nrm, c
        if not bounded:
            box_edge = on_box & np.concatenate((on_box[1:], on_box[:1])) & (np.abs(nrm).max(axis=1) > 1 - 1e-9)
            H = H[~box_edge]
    return SupportRegion(basis=basis, vertices=V, halfplanes=H, is_empty=False, is_bounded=bounded,
                         _box=box_lines, **meta)


# ---- iterative projection ----------------------------------------------------------------------------
def iterative_projection(solve: Callable[[np.ndarray], np.ndarray | None], tol: float,
                         max_solves: int = 400) -> tuple[np.ndarray | None, int]:
    """Iterative projection (Bretl and Lall 2006) of a convex set onto 2-D.

    ``solve(d)`` returns a point of the projection maximising ``d . x`` (or ``None`` if the set is
    empty).  Starting from the support points of three directions, each edge of the inner polygon
    is tested with its outward normal: a new support point farther than ``tol`` beyond the edge is
    inserted, otherwise the edge is a facet (up to ``tol``).  About two solves per vertex.

    Returns:
        (support points ``(m, 2)`` counter-clockwise or ``None`` if empty, number of solves).
    """
    verts: list[np.ndarray] = []
    for a in (0.0, 2 * np.pi / 3, 4 * np.pi / 3):
        x = solve(np.array([np.cos(a), np.sin(a)]))
        if x is None:
            return None, len(verts) + 1
        verts.append(x)
    n_solves = 3
    done = [False] * 3
    i = 0
    while n_solves < max_solves:
        try:
            i = done.index(False, i)
        except ValueError:
            try:
                i = done.index(False)
            except ValueError:
                break
        a, b = verts[i], verts[(i + 1) % len(verts)]
        e = b - a
        L = float(np.hypot(e[0], e[1]))
        if L < 1e-12:
            done[i] = True
            continue
        nrm = np.array([e[1], -e[0]]) / L
        x = solve(nrm)
        n_solves += 1
        if x is None or nrm @ (x - a) <= tol:
            done[i] = True
        else:
            verts.insert(i + 1, x)
            done.insert(i + 1, False)
    return np.array(verts), n_solves


# ---- solvers for one direction -------------------------------------------------------------------------
@dataclass
class _Problem:
    contacts: list[Contact]
    mass: float
    g: np.ndarray
    planar: bool
    basis: np.ndarray = field(init=False)
    origin: np.ndarray = field(init=False)  # contacts' centroid, world frame
    r: np.ndarray = field(init=False)  # contact positions relative to origin
    ghat: np.ndarray = field(init=False)
    weight: float = field(init=False)
    com_moments: np.ndarray = field(init=False)

    def __post_init__(self) -> None:
        self.basis = gravity_basis(self.g, self.planar)
        P = np.array([c.position for c in self.contacts])
        self.origin = P.sum(axis=0) / len(P)
        self.r = P - self.origin
        gx, gy, gz = self.g.tolist()
        ng = math.sqrt(gx ** 2 + gy ** 2 + gz ** 2)
        self.weight = self.mass * ng
        self.ghat = self.g / ng
        # (3, d) orthonormal columns basis_j x ghat: the moments of the CoM coordinates (Bretl (2006) appendix B)
        hx, hy, hz = self.ghat.tolist()
        self.com_moments = np.array([(b1 * hz - b2 * hy, b2 * hx - b0 * hz, b0 * hy - b1 * hx)
                                     for b0, b1, b2 in self.basis.tolist()]).T


def _lp_solver(pb: _Problem, k: int, clip: float) -> Callable[[np.ndarray], np.ndarray | None]:
    """HiGHS LP over linearised cones: max d.x s.t. Bretl, Latombe & Rock (2003) eq. (7) with CoM coordinates x."""
    lin = linearise(pb.contacts, pb.weight, k, pb.planar)
    rows = balance_rows(pb.planar)
    d = pb.basis.shape[0]
    W = wrench_matrix(pb.r, lin.gens, lin.owner)
    C = com_columns(pb.basis, pb.ghat)
    rhs = -np.concatenate([pb.ghat + lin.offsets.sum(axis=0), np.cross(pb.r, lin.offsets).sum(axis=0)])
    A = np.hstack([W, C])[rows]
    lo, hi = rhs[rows], rhs[rows].copy()
    for i, bound in lin.bounds:
        A = np.vstack([A, np.r_[(lin.owner == i).astype(float), np.zeros(d)]])
        lo, hi = np.r_[lo, -np.inf], np.r_[hi, bound]
    nl = W.shape[1]
    lp = DenseLP(A, lo, hi, np.r_[np.zeros(nl), np.full(d, -clip)], np.r_[np.full(nl, np.inf), np.full(d, clip)])
    idx = np.arange(nl, nl + d)

    def solve(direction: np.ndarray) -> np.ndarray | None:
        lp.set_cost(idx, -direction)
        x = lp.solve()
        return None if x is None else x[nl:]

    return solve


def _projection_tableau(pb: _Problem, lin: Linearised, clip: float, extra: np.ndarray | None = None,
                        extra_lo: np.ndarray | None = None, extra_hi: np.ndarray | None = None) -> Tableau:
    """Tableau of the polytope of cone-edge weights ``lam >= 0`` whose image ``x = x0 - K lam`` is the region.

    The wrench balance of Bretl, Latombe & Rock (2003) eq. (7) with the CoM coordinates ``x`` as
    unknowns splits into rows free of ``x`` (the total force, and in 3-D the moment about the gravity
    axis) and ``d`` rows that give ``x = x0 - K lam`` (Bretl (2006) appendix B: the CoM enters the
    moment only through its components perpendicular to gravity).  Rows: those equalities, the clip
    box ``|x_j| <= clip`` (``2 d`` rows with slacks), the grasp bounds, and optional two-sided rows
    ``extra_lo <= extra @ lam <= extra_hi`` (joint torque limits).  Objective rows: ``-K``, so the
    tableau's :meth:`~Tableau.value` plus ``tab.x0`` is the CoM position of a basic solution.

    The tableau array is written directly in canonical form (:meth:`Tableau.from_array`): the equality
    rows, and rows whose right-hand side is negative, start on artificial columns.
    """
    gens, owner, offsets, bounds = lin.gens, lin.owner, lin.offsets, lin.bounds
    mom = cross(pb.r[owner], gens.T).T  # (3, n) moments of the generators
    E = pb.com_moments  # (3, d)
    K = E.T @ mom
    d = E.shape[1]
    n, ng = gens.shape[1], len(bounds)
    ne = 2 if pb.planar else 4
    nx = 0 if extra is None else extra.shape[0]
    m = ne + 2 * d + ng + 2 * nx
    N = n + m - ne  # the cone-edge weights and one slack per inequality row
    rhs_f = -pb.ghat
    if offsets.any():
        rhs_f = rhs_f - offsets.sum(axis=0)
        rhs_m = -cross(pb.r, offsets).sum(axis=0)
        x0 = E.T @ rhs_m
        vert = [float(pb.ghat @ rhs_m)]
    else:
        x0, vert = np.zeros(d), [0.0]
    b_eq = rhs_f.tolist()
    b_eq = b_eq[::2] if pb.planar else b_eq + vert
    xs = x0.tolist()
    b = [*b_eq, *(clip - x for x in xs), *(clip + x for x in xs), *(bd for _, bd in bounds)]
    if nx:
        b += [*np.asarray(extra_hi, dtype=float).tolist(), *(-np.asarray(extra_lo, dtype=float)).tolist()]
    b = np.array(b)
    neg = b < 0
    need = neg.copy()
    need[:ne] = True
    arts = np.flatnonzero(need)
    na = len(arts)
    T = np.zeros((m + d + 1, N + na + 1))
    if pb.planar:
        T[:2, :n] = gens[::2]
    else:
        T[:3, :n] = gens
        T[3, :n] = pb.ghat @ mom
    T[ne:ne + d, :n] = -K
    T[ne + d:ne + 2 * d, :n] = K
    r = ne + 2 * d
    for i, (c, _) in enumerate(bounds):
        T[r + i, :n] = owner == c
    r += ng
    if nx:
        T[r:r + nx, :n] = extra
        T[r + nx:m, :n] = -extra
    rows = np.arange(ne, m)
    T[rows, rows + (n - ne)] = 1.0  # slacks
    T[:m, -1] = b
    if neg.any():
        flip = np.flatnonzero(neg)
        T[flip, :N] *= -1.0
        T[flip, -1] *= -1.0
    T[arts, N + np.arange(na)] = 1.0
    T[m:m + d, :n] = -K
    T[-1, :N] = T[arts, :N].sum(axis=0)
    T[-1, -1] = T[arts, -1].sum()
    basis = (np.arange(m) + (n - ne)).tolist()
    for a, row in enumerate(arts.tolist()):
        basis[row] = N + a
    tab = Tableau.from_array(T, basis, m, N, d)
    tab.x0 = x0  # type: ignore[attr-defined]
    return tab


def _lp_projection(pb: _Problem, k: int, clip: float) -> np.ndarray | None:
    """The exact linearised support polygon by the shadow-vertex simplex (:mod:`._simplex`).

    Returns:
        Vertices ``(m, 2)`` counter-clockwise, relative to the contacts' centroid, or ``None`` if empty.

    Raises:
        SimplexError: the tableau simplex did not finish (the caller falls back to HiGHS).
    """
    tab = _projection_tableau(pb, linearise(pb.contacts, pb.weight, k, pb.planar), clip)
    if not tab.phase1():
        return None
    return tab.shadow_vertices() + tab.x0  # type: ignore[attr-defined]


# ---- public API ---------------------------------------------------------------------------------------
def check_cone_edges(cone_edges: Any) -> int:
    """``cone_edges`` as an int.

    Raises:
        EquilibriumError: not an integer >= 3.
    """
    if isinstance(cone_edges, bool) or not isinstance(cone_edges, (int, np.integer)) or cone_edges < 3:
        raise EquilibriumError(f"cone_edges: must be an integer >= 3, got {cone_edges!r}")
    return int(cone_edges)


def support_region(
    contacts: Sequence[Contact | Any],
    mass: float,
    gravity: Any,
    *,
    planar: bool = False,
    cone_edges: int = CONE_EDGES,
    exact: bool = False,
    shrink: float = 0.0,
    tol: float | None = None,
    clip: float = CLIP,
) -> SupportRegion:
    """The support region of a stance: CoM positions where static equilibrium is possible.

    3-D: the support polygon of the CoM projected along gravity (Bretl (2006) appendix B; Bretl,
    Latombe & Rock (2003) eq. (7)): exact for the linearised cones (shadow-vertex simplex), within
    ``tol`` for exact cones (sandwich projection of Clarabel SOCPs).  Planar (contacts and gravity in
    the x-z plane): the interval of the CoM's horizontal coordinate (Bretl, Latombe & Rock (2003)
    eq. (1); two LPs; 2-D friction cones are exactly two edges, so the interval is exact).

    Args:
        contacts: :class:`Contact` s (or terrain ``Hold`` s).
        mass: robot mass, kg (> 0).
        gravity: gravity vector, m/s^2 (any direction; planar: in the x-z plane).
        planar: 2-D problem.
        cone_edges: edges ``k`` of the inscribed pyramids replacing the friction cones (>= 3; grasp
            balls use ``3k + 2`` directions, planar grasp discs ``k``-gons).
        exact: second-order cones (Clarabel); slower, curved boundary up to ``tol``.
        shrink: safety margin, metres: the returned region is shrunk by it (:meth:`SupportRegion.shrink`).
        tol: refinement tolerance, metres (default 1e-9 linearised, 1e-4 exact).
        clip: half-width of the box bounding unbounded regions, metres.

    Returns:
        The region; ``is_empty`` when no CoM position is in equilibrium.

    Raises:
        EquilibriumError: bad contacts, mass, gravity or options (naming the value).
    """
    cs = as_contacts(contacts)
    m, g = check_mass_gravity(mass, gravity, planar)
    if planar:
        check_planar_contacts(cs)
    check_cone_edges(cone_edges)
    if not (isinstance(clip, float) and math.isfinite(clip) or np.isfinite(clip)) or not clip > 0:
        raise EquilibriumError(f"clip: must be finite and > 0 m, got {clip!r}")
    if not planar and not exact and all(c.kind != "grasp" for c in cs):
        region = _compiled_region(cs, m, g, int(cone_edges), float(clip), float(tol) if tol is not None else TOL_LP)
        if region is not None:
            return region.shrink(shrink) if shrink else region
    pb = _Problem(cs, m, g, planar)
    use_socp = exact and (not planar or any(c.kind == "grasp" for c in cs))
    tol = float(tol) if tol is not None else (TOL_EXACT if use_socp else TOL_LP)

    def solve_fn() -> Callable[[np.ndarray], np.ndarray | None]:
        return clarabel_support(pb, clip) if use_socp else _lp_solver(pb, int(cone_edges), clip)
    meta = dict(planar=planar, exact=bool(exact), cone_edges=int(cone_edges), tol=tol)
    if planar:
        solve = solve_fn()
        lo_x, hi_x = solve(np.array([-1.0])), solve(np.array([1.0]))
        region = make_region(pb, None if lo_x is None or hi_x is None else np.array([lo_x, hi_x]), clip, 2, meta)
    else:
        pts, n = None, 0
        if not use_socp:
            try:
                pts = _lp_projection(pb, int(cone_edges), clip)
                n = 1
            except SimplexError:
                pts = None
        if use_socp:
            if not _outer_empty(cs, m, g, int(cone_edges), clip):
                pts, n = sandwich_projection(solve_fn(), tol)
        elif n == 0:
            pts, n = iterative_projection(solve_fn(), tol)
        region = make_region(pb, pts, clip, n, meta, ordered=not use_socp)
    return region.shrink(shrink) if shrink else region


_NO_VERTICES, _NO_HALFPLANES = np.zeros((0, 2)), np.zeros((0, 3))
_NO_VERTICES.flags.writeable = _NO_HALFPLANES.flags.writeable = False  # shared by every empty region
_CONSTS: dict[tuple[float, float, float, int], tuple[np.ndarray, np.ndarray]] = {}


def _outer_empty(cs: list[Contact], mass: float, g: np.ndarray, k: int, clip: float) -> bool:
    """The emptiness test of exact-cone regions before any SOCP: whether the region of the circumscribed ``k``-edge
    pyramids (friction ``mu / cos(pi / k)``, :func:`._contacts.linearise` with ``outer=True``), which contains the
    exact region, is empty (one compiled phase 1).  ``False`` when it cannot tell (grasp contacts)."""
    if any(c.kind == "grasp" for c in cs):
        return False
    outer = _compiled_region(cs, mass, g, k, clip, TOL_LP, friction_scale=1.0 / math.cos(math.pi / k))
    return outer is not None and outer.is_empty


def _compiled_region(cs: list[Contact], mass: float, g: np.ndarray, k: int, clip: float,
                     tol: float, friction_scale: float = 1.0) -> SupportRegion | None:
    """The linearised 3-D region of friction and adhesion contacts in one compiled call (:func:`._project.project`:
    the emptiness test, the shadow-vertex trace and the clean-up), or ``None`` when the simplex stalled or was
    unbounded (the caller then runs the general path)."""
    from climb_ompl.equilibrium import _project

    gx, gy, gz = g.tolist()
    key = (gx, gy, gz, k)
    got = _CONSTS.get(key)
    if got is None:  # the region axes and cone edges of this gravity and cone (a few per process)
        basis = gravity_basis(g, False)
        cos_th, sin_th = _ring(k)
        got = _CONSTS[key] = (basis, _project.constants(g, basis, cos_th, sin_th))
    basis, consts = got
    data = np.array([c.row for c in cs])
    if friction_scale != 1.0:
        data[:, 6] *= friction_scale
    status, V, BH = _project.project(data, consts, mass, clip)
    if status == _project.EMPTY:
        return SupportRegion.assemble(basis, _NO_VERTICES, _NO_HALFPLANES, True, True, _NO_HALFPLANES, k, tol)
    if status == _project.OK:
        return SupportRegion.assemble(basis, V, BH[4:], False, True, BH[:4], k, tol)
    if status == _project.RAW:
        return _polygon_region(V, basis, BH[:2, 2], clip, True, planar=False, exact=False, cone_edges=k, tol=tol,
                               n_solves=1)
    return None


def make_region(pb: _Problem, pts: np.ndarray | None, clip: float, n_solves: int,
                meta: dict[str, Any], ordered: bool = False) -> SupportRegion:
    """The region from its support points relative to the contacts' centroid (``None``: empty).

    3-D: the points' convex hull (:func:`_polygon_region`; ``ordered``: the points are the boundary,
    counter-clockwise).  Planar: ``pts`` is ``[[lo], [hi]]``, the
    interval's ends; an end on the clip box is an unbounded side.
    """
    center = pb.basis @ pb.origin
    dim = pb.basis.shape[0]
    if pts is None:
        return SupportRegion(pb.basis, np.zeros((0, dim)), np.zeros((0, 3)), True, True, n_solves=n_solves, **meta)
    if not pb.planar:
        return _polygon_region(pts + center, pb.basis, center, clip, ordered, n_solves=n_solves, **meta)
    lo_x, hi_x = float(pts[0][0]), float(pts[1][0])
    lo, hi = lo_x + center[0], hi_x + center[0]
    H = []
    if hi_x < clip - 1e-6:
        H.append([1.0, 0.0, hi])
    if lo_x > -clip + 1e-6:
        H.append([-1.0, 0.0, -lo])
    V = np.array([[lo], [hi]]) if hi - lo > 1e-9 else np.array([[0.5 * (lo + hi)]])
    return SupportRegion(pb.basis, V, np.array(H, dtype=float).reshape(-1, 3), False, len(H) == 2,
                         n_solves=n_solves, **meta)


class RegionCache:
    """Support regions keyed by contact geometry, gravity, mass and options (LRU, ``maxsize`` entries).

    The key is the geometry (positions, normals, friction, kind, force bound) rather than hold ids,
    so stances on different (e.g. generated) walls never collide.

    Attributes:
        hits, misses: lookup counts.
    """

    def __init__(self, maxsize: int = 100_000):
        self.maxsize = int(maxsize)
        self._d: OrderedDict[Any, SupportRegion] = OrderedDict()
        self.hits = 0
        self.misses = 0

    def get(self, contacts: Sequence[Contact | Any], mass: float, gravity: Any, **opts: Any) -> SupportRegion:
        """The region of ``contacts`` (computed with :func:`support_region` ``(**opts)`` on a miss)."""
        cs = as_contacts(contacts)
        g = np.asarray(gravity, dtype=float).reshape(-1)
        key = (tuple(c.key() for c in cs), tuple(g.tolist()), float(mass), tuple(sorted(opts.items())))
        region = self._d.get(key)
        if region is not None:
            self.hits += 1
            self._d.move_to_end(key)
            return region
        self.misses += 1
        region = support_region(cs, mass, gravity, **opts)
        self._d[key] = region
        if len(self._d) > self.maxsize:
            self._d.popitem(last=False)
        return region

    def __len__(self) -> int:
        return len(self._d)

    def clear(self) -> None:
        """Forget every region."""
        self._d.clear()
