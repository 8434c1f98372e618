"""The linearised 3-D support polygon of friction and adhesion contacts in one compiled call (numba, cached on disk).

On 2-4 holds the numpy path's set-up around its few pivots (cone edges, the tableau, the clean-up of the traced
polygon) is a fixed cost per call far above the pivoting itself, so an empty two-hold region costs as much as a full
polygon (docs/equilibrium.md gives the profile).  :func:`project` does the whole computation in compiled
code, with the arithmetic of the numpy path it replaces (``region._Problem``, ``_contacts.linearise``,
``region._projection_tableau``, ``_simplex.Tableau.phase1`` / ``shadow_vertices`` and ``region._ccw_clean``):

1. the cone edges (Bretl, Latombe & Rock (2003) eq. (6)) and the projection tableau of the cone-edge weights
   whose image is the region (eq. (7), Bretl (2006) appendix B);
2. phase 1 of the tableau simplex: the emptiness test, one LP, before any projection;
3. the shadow-vertex simplex around the polygon (:func:`._kernels.shadow`);
4. the clean-up of the traced boundary into vertices and half-planes.

Anything unusual - a stalled or unbounded simplex, a polygon with fewer than three vertices, zero width or a
side on the clip box - returns a status instead, and the caller finishes with the numpy path.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from climb_ompl.equilibrium._kernels import OK, climb, pivot, shadow

#: Statuses of :func:`project` beyond :mod:`._kernels`' ``OK``/``UNBOUNDED``/``STALLED``: no CoM in equilibrium;
#: the traced boundary is in ``raw`` but needs the general clean-up (degenerate or unbounded polygon).
EMPTY, RAW = 3, 4
#: The grid (metres) the traced vertices are snapped to, as ``region._ccw_clean``.
SNAP = 1e-10


@njit(cache=True)
def _edges(data: np.ndarray, o: np.ndarray, cos_th: np.ndarray, sin_th: np.ndarray, weight: float, hx: float,
           hy: float, hz: float):  # noqa: ANN202  # pragma: no cover - compiled
    """The unit cone edges ``gens`` ``(3, n)`` of every contact (``_contacts.linearise``: Bretl, Latombe & Rock (2003)
    eq. (6)), their moments ``mom`` about the centroid ``o``, and the force and moment right-hand sides ``rf``,
    ``rm`` of the balance (weight units; adhesion pulls shift them)."""
    nc = data.shape[0]
    k = cos_th.shape[0]
    n = nc * k
    gens = np.empty((3, n))
    mom = np.empty((3, n))
    rf = np.array([-hx, -hy, -hz])
    rm = np.zeros(3)
    for i in range(nc):
        r0, r1, r2 = data[i, 0] - o[0], data[i, 1] - o[1], data[i, 2] - o[2]
        n0, n1, n2 = data[i, 3], data[i, 4], data[i, 5]
        mu = data[i, 6]
        a0, a1, a2 = (0.0, n2, -n1) if abs(n0) < 0.9 else (-n2, 0.0, n0)  # _contacts.tangent_bases
        L = math.sqrt(a0 * a0 + a1 * a1 + a2 * a2)
        a0, a1, a2 = a0 / L, a1 / L, a2 / L
        c0, c1, c2 = n1 * a2 - n2 * a1, n2 * a0 - n0 * a2, n0 * a1 - n1 * a0
        for e in range(k):
            col = i * k + e
            ct, st = cos_th[e], sin_th[e]
            e0 = n0 + mu * (ct * a0 + st * c0)
            e1 = n1 + mu * (ct * a1 + st * c1)
            e2 = n2 + mu * (ct * a2 + st * c2)
            s = math.sqrt(e0 * e0 + e1 * e1 + e2 * e2)
            e0, e1, e2 = e0 / s, e1 / s, e2 / s
            gens[0, col], gens[1, col], gens[2, col] = e0, e1, e2
            mom[0, col], mom[1, col], mom[2, col] = r1 * e2 - r2 * e1, r2 * e0 - r0 * e2, r0 * e1 - r1 * e0
        if data[i, 7] > 0.0:  # adhesion: the cone shifted by the pull (weight units)
            f = -data[i, 7] / weight
            f0, f1, f2 = f * n0, f * n1, f * n2
            rf[0] -= f0
            rf[1] -= f1
            rf[2] -= f2
            rm[0] -= r1 * f2 - r2 * f1
            rm[1] -= r2 * f0 - r0 * f2
            rm[2] -= r0 * f1 - r1 * f0
    return gens, mom, rf, rm


@njit(cache=True)
def _setup(data: np.ndarray, g: np.ndarray, mass: float, basis: np.ndarray, cos_th: np.ndarray,
           sin_th: np.ndarray, clip: float):  # noqa: ANN202  # pragma: no cover - compiled
    """The projection tableau (``region._projection_tableau`` without grasp or torque rows).

    ``data`` rows: position (3), unit normal (3), friction, adhesion pull (N, 0 for friction contacts).
    Returns ``(T, basis, banned, m, N, x0, centre)``: the canonical tableau, its basic columns, the banned-column
    marks of :mod:`._kernels`, its row and column counts, the CoM offset ``x0`` and the contacts' centroid in
    region coordinates.
    """
    nc = data.shape[0]
    k = cos_th.shape[0]
    gx, gy, gz = g[0], g[1], g[2]
    ng = math.sqrt(gx ** 2 + gy ** 2 + gz ** 2)
    weight = mass * ng
    hx, hy, hz = gx / ng, gy / ng, gz / ng
    E = np.empty((3, 2))  # com_moments: basis_j x ghat
    for j in range(2):
        b0, b1, b2 = basis[j, 0], basis[j, 1], basis[j, 2]
        E[0, j], E[1, j], E[2, j] = b1 * hz - b2 * hy, b2 * hx - b0 * hz, b0 * hy - b1 * hx
    o = np.zeros(3)
    for i in range(nc):
        for a in range(3):
            o[a] += data[i, a]
    o /= nc
    n = nc * k
    m, ne, d = 8, 4, 2
    N = n + m - ne
    gens, mom, rf, rm = _edges(data, o, cos_th, sin_th, weight, hx, hy, hz)
    x0 = np.zeros(2)
    vert = 0.0
    for j in range(2):
        x0[j] = E[0, j] * rm[0] + E[1, j] * rm[1] + E[2, j] * rm[2]
    vert = hx * rm[0] + hy * rm[1] + hz * rm[2]
    b = np.array([rf[0], rf[1], rf[2], vert, clip - x0[0], clip - x0[1], clip + x0[0], clip + x0[1]])
    na = 4
    for r in range(ne, m):
        if b[r] < 0:
            na += 1
    T = np.zeros((m + d + 1, N + na + 1))
    for col in range(n):
        T[0, col], T[1, col], T[2, col] = gens[0, col], gens[1, col], gens[2, col]
        T[3, col] = hx * mom[0, col] + hy * mom[1, col] + hz * mom[2, col]
        for j in range(2):
            K = E[0, j] * mom[0, col] + E[1, j] * mom[1, col] + E[2, j] * mom[2, col]
            T[ne + j, col] = -K
            T[ne + d + j, col] = K
            T[m + j, col] = -K
    bas = np.empty(m, dtype=np.int64)
    a = 0
    for r in range(m):
        bas[r] = r + n - ne
        if r >= ne:
            T[r, r + n - ne] = 1.0  # slack
        T[r, -1] = b[r]
        if b[r] < 0:
            for col in range(N):
                T[r, col] = -T[r, col]
            T[r, -1] = -T[r, -1]
        if r < ne or b[r] < 0:
            T[r, N + a] = 1.0
            bas[r] = N + a
            a += 1
            for col in range(N):
                T[m + d, col] += T[r, col]
            T[m + d, -1] += T[r, -1]
    banned = np.zeros(N + na)
    for r in range(m):
        banned[bas[r]] = np.inf
    centre = np.empty(2)
    for j in range(2):
        centre[j] = basis[j, 0] * o[0] + basis[j, 1] * o[1] + basis[j, 2] * o[2]
    return T, bas, banned, m, N, x0, centre


@njit(cache=True)
def _phase1(T: np.ndarray, bas: np.ndarray, banned: np.ndarray, m: int, N: int,
            max_pivots: int) -> tuple[int, int]:  # pragma: no cover - compiled
    """``_simplex.Tableau.phase1`` on the tableau of :func:`_setup`: ``(status, pivots)``, ``EMPTY`` when the
    polytope of cone-edge weights (so the region) is empty."""
    scale = 1.0
    top = 0.0
    for r in range(m):
        top = max(top, T[r, -1])
    scale += top
    status, pivots = climb(T, bas, banned, m, N, T.shape[0] - 1, 0.0, 0.0, 0, 0, max_pivots)
    if status != OK:
        return status, pivots
    if T[-1, -1] > 1e-9 * scale:
        return EMPTY, pivots
    for r in range(m):
        if bas[r] < N:
            continue
        j, best = 0, -1.0
        for col in range(N):
            v = abs(T[r, col])
            if v > best:
                j, best = col, v
        if best > 1e-9:
            pivot(T, bas, banned, r, j)
            pivots += 1
            if pivots > max_pivots:
                return 2, pivots
        else:
            T[r, :] = 0.0
            bas[r] = -1
    return OK, pivots


@njit(cache=True)
def _ccw_clean(P: np.ndarray) -> np.ndarray:  # pragma: no cover - compiled
    """``region._ccw_clean``: the traced boundary ``P`` snapped to the :data:`SNAP` grid, repeated points and
    points that make no left turn dropped in passes; fewer than three rows when no polygon is left."""
    eps = SNAP
    Q = np.empty_like(P)
    q = 0
    for i in range(P.shape[0]):
        x, y = np.rint(P[i, 0] / eps) * eps, np.rint(P[i, 1] / eps) * eps
        if q == 0 or abs(x - Q[q - 1, 0]) > eps or abs(y - Q[q - 1, 1]) > eps:
            Q[q, 0], Q[q, 1] = x, y
            q += 1
    while q > 1 and abs(Q[0, 0] - Q[q - 1, 0]) <= eps and abs(Q[0, 1] - Q[q - 1, 1]) <= eps:
        q -= 1
    V = Q[:q].copy()
    while V.shape[0] >= 3:
        nv = V.shape[0]
        keep = np.empty(nv, dtype=np.bool_)
        for i in range(nv):
            ax, ay = V[i - 1, 0], V[i - 1, 1]
            bx, by = V[(i + 1) % nv, 0] - ax, V[(i + 1) % nv, 1] - ay
            keep[i] = (V[i, 0] - ax) * by - (V[i, 1] - ay) * bx > eps * math.hypot(bx, by)
        if keep.all():
            return V
        V = V[keep]
    return V


@njit(cache=True)
def _extremes(P: np.ndarray) -> np.ndarray:  # pragma: no cover - compiled
    """The snapped, deduplicated points of ``P`` if at most two, else the two extremes of its lexicographic order:
    ``region._hull`` of a boundary with no left turn (all points collinear within the grid)."""
    eps = SNAP
    n = P.shape[0]
    S = np.empty((n, 2))
    for i in range(n):
        S[i, 0], S[i, 1] = np.rint(P[i, 0] / eps) * eps, np.rint(P[i, 1] / eps) * eps
    lo, hi = 0, 0
    for i in range(1, n):
        if S[i, 0] < S[lo, 0] or S[i, 0] == S[lo, 0] and S[i, 1] < S[lo, 1]:
            lo = i
        if S[i, 0] > S[hi, 0] or S[i, 0] == S[hi, 0] and S[i, 1] > S[hi, 1]:
            hi = i
    if S[lo, 0] == S[hi, 0] and S[lo, 1] == S[hi, 1]:
        return S[lo:lo + 1].copy()
    out = np.empty((2, 2))
    out[0], out[1] = S[lo], S[hi]
    return out


@njit(cache=True)
def _halfplanes(V: np.ndarray) -> tuple[np.ndarray, float]:  # pragma: no cover - compiled
    """``region._edges`` of a counter-clockwise polygon as half-plane rows ``(a, b, c)``, and its width (the
    smallest over edges of the deepest vertex behind the edge)."""
    nv = V.shape[0]
    H = np.empty((nv, 3))
    for i in range(nv):
        ex, ey = V[(i + 1) % nv, 0] - V[i, 0], V[(i + 1) % nv, 1] - V[i, 1]
        L = math.sqrt(ex * ex + ey * ey)
        H[i, 0], H[i, 1] = ey / L, -ex / L
        H[i, 2] = H[i, 0] * V[i, 0] + H[i, 1] * V[i, 1]
    width = np.inf
    for i in range(nv):
        deepest = -np.inf
        for j in range(nv):
            deepest = max(deepest, H[i, 2] - (H[i, 0] * V[j, 0] + H[i, 1] * V[j, 1]))
        width = min(width, deepest)
    return H, width


@njit(cache=True)
def _clean(P: np.ndarray, centre: np.ndarray, clip: float):  # noqa: ANN202  # pragma: no cover - compiled
    """``region._polygon_region`` of the traced boundary ``P`` (absolute coordinates) for bounded regions:
    ``(V, H, ok)``, vertices and half-planes of a polygon, a segment or a point; ``ok`` is false when a vertex lies
    on the clip box (the general clean-up then drops the box's sides)."""
    V = _ccw_clean(P)
    if V.shape[0] < 3:
        V = _extremes(P)
    if V.shape[0] >= 3:
        H, width = _halfplanes(V)
        if width >= 1e-9:
            for i in range(V.shape[0]):
                if max(abs(V[i, 0] - centre[0]), abs(V[i, 1] - centre[1])) >= clip - 1e-6:
                    return V, H, False
            return V, H, True
        d = V - V[0]  # zero width: the segment between the extremes along the farthest vertex's direction
        far = np.argmax(d[:, 0] * d[:, 0] + d[:, 1] * d[:, 1])
        s = d[:, 0] * d[far, 0] + d[:, 1] * d[far, 1]
        V2 = np.empty((2, 2))
        V2[0], V2[1] = V[np.argmin(s)], V[np.argmax(s)]
        V = V2
    if V.shape[0] == 2 and math.sqrt((V[1, 0] - V[0, 0]) ** 2 + (V[1, 1] - V[0, 1]) ** 2) < 1e-9:
        V = V[:1].copy()
    for i in range(V.shape[0]):
        if max(abs(V[i, 0] - centre[0]), abs(V[i, 1] - centre[1])) >= clip - 1e-6:
            return V, np.zeros((0, 3)), False
    if V.shape[0] == 1:
        x, y = V[0, 0], V[0, 1]
        H = np.array([[1.0, 0.0, x], [-1.0, 0.0, -x], [0.0, 1.0, y], [0.0, -1.0, -y]])
        return V, H, True
    L = math.sqrt((V[1, 0] - V[0, 0]) ** 2 + (V[1, 1] - V[0, 1]) ** 2)
    dx, dy = (V[1, 0] - V[0, 0]) / L, (V[1, 1] - V[0, 1]) / L
    H = np.empty((4, 3))
    H[0, 0], H[0, 1], H[0, 2] = dy, -dx, dy * V[0, 0] - dx * V[0, 1]
    H[1, 0], H[1, 1], H[1, 2] = -dy, dx, -dy * V[0, 0] + dx * V[0, 1]
    H[2, 0], H[2, 1], H[2, 2] = -dx, -dy, -dx * V[0, 0] - dy * V[0, 1]
    H[3, 0], H[3, 1], H[3, 2] = dx, dy, dx * V[1, 0] + dy * V[1, 1]
    return V, H, True


def constants(g: np.ndarray, basis: np.ndarray, cos_th: np.ndarray, sin_th: np.ndarray) -> np.ndarray:
    """The per-gravity, per-cone constants :func:`project` takes, in one array: gravity (3), the region axes
    (2 x 3, row-major), the cone-edge angles' cosines and sines (``k`` each)."""
    return np.concatenate((g, basis.reshape(-1), cos_th.reshape(-1), sin_th.reshape(-1)))


@njit(cache=True)
def project(data: np.ndarray, consts: np.ndarray, mass: float, clip: float):  # noqa: ANN201  # pragma: no cover
    """The linearised support polygon of the contacts ``data`` (rows as :func:`_setup`), ``mass`` (kg), with the
    gravity (m/s^2), region axes and cone edges of ``consts`` (:func:`constants`), clipped at ``clip`` metres.

    Returns ``(status, V, BH)`` (two arrays: each array returned costs about 0.4 us of boxing): with ``OK``, the
    vertices ``V`` ``(m, 2)`` counter-clockwise (a segment or a point when ``m < 3``) and ``BH``, the clip box's four
    lines then the region's half-planes, rows ``(a, b, c)`` in region coordinates; with ``RAW``, ``V`` is the traced
    boundary (absolute region coordinates) for the general clean-up and ``BH[:2, 2]`` the contacts' centroid;
    ``EMPTY``; or the simplex's ``UNBOUNDED``/``STALLED``.
    """
    k = (consts.shape[0] - 9) // 2
    g, basis = consts[:3], consts[3:9].reshape(2, 3)
    T, bas, banned, m, N, x0, centre = _setup(data, g, mass, basis, consts[9:9 + k], consts[9 + k:], clip)
    cx, cy = centre[0], centre[1]
    max_pivots = 20 * (m + N) + 100
    status, pivots = _phase1(T, bas, banned, m, N, max_pivots)
    if status == OK:
        T2 = np.empty((T.shape[0] - 1, N + 1))
        T2[:, :N] = T[:-1, :N]
        T2[:, N] = T[:-1, -1]
        banned2 = banned[:N].copy()
        status, pivots = climb(T2, bas, banned2, m, N, -1, 1.0, 0.0, 2, pivots, max_pivots)
    if status != OK:
        return status, np.zeros((0, 2)), np.zeros((0, 3))
    out = np.empty((max_pivots - pivots + 2, 2))
    status, nv, pivots = shadow(T2, bas, banned2, m, N, 0.0, pivots, max_pivots, out)
    if status != OK:
        return status, np.zeros((0, 2)), np.zeros((0, 3))
    raw = np.empty((nv, 2))
    for i in range(nv):
        raw[i, 0], raw[i, 1] = (-out[i, 0] + x0[0]) + cx, (-out[i, 1] + x0[1]) + cy
    V, H, ok = _clean(raw, centre, clip)
    if not ok:
        BH = np.zeros((4, 3))
        BH[0, 2], BH[1, 2] = cx, cy
        return RAW, raw, BH
    BH = np.empty((4 + H.shape[0], 3))
    BH[0, 0], BH[0, 1], BH[0, 2] = 1.0, 0.0, cx + clip
    BH[1, 0], BH[1, 1], BH[1, 2] = -1.0, 0.0, clip - cx
    BH[2, 0], BH[2, 1], BH[2, 2] = 0.0, 1.0, cy + clip
    BH[3, 0], BH[3, 1], BH[3, 2] = 0.0, -1.0, clip - cy
    BH[4:] = H
    return OK, V, BH
