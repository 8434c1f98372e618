"""Exact (second-order) friction cones: the support-region SOCP handed straight to Clarabel, and the
sandwich projection that needs about one SOCP per polygon vertex.

The SOCP of Bretl (2006) appendix B, eqs. (B1)-(B3) - maximise ``d . x`` over the CoM coordinates
``x`` and contact forces ``f`` - is written once per stance in Clarabel's standard form
``A z + s = b, s in K`` (zero cone: the wrench balance; non-negative cone: the clip box and the
normal forces; second-order cones: one per contact); each direction then only replaces the cost
vector (``solver.update(q=...)``), so there is no modelling-layer canonicalisation per solve.
"""

from __future__ import annotations

import math
from collections.abc import Callable

import numpy as np

from climb_ompl.equilibrium._contacts import balance_rows, com_columns, skew, tangent_bases
from climb_ompl.errors import EquilibriumError

Support = Callable[[np.ndarray], "np.ndarray | None"]


def _standard_form(eq: np.ndarray, beq: np.ndarray, nn: list[np.ndarray], bnn: list[np.ndarray],
                   soc: list[np.ndarray], bsoc: list[np.ndarray], soc_dims: list[int]) -> tuple:
    """Clarabel's ``A z + s = b, s in K`` from zero-cone, non-negative and second-order-cone row blocks:
    ``(A, b, cones, settings)``, the settings quiet and single-threaded (tiny problems: worker threads only
    add scheduling delays)."""
    import clarabel
    from scipy import sparse

    A = sparse.csc_matrix(np.vstack([eq, *nn, *soc]))
    b = np.concatenate([beq, *bnn, *bsoc])
    cones = [clarabel.ZeroConeT(len(beq)), clarabel.NonnegativeConeT(sum(len(x) for x in bnn))]
    cones += [clarabel.SecondOrderConeT(n) for n in soc_dims]
    settings = clarabel.DefaultSettings()
    settings.verbose = False
    settings.max_threads = 1
    return A, b, cones, settings


def _solution(sol) -> np.ndarray | None:  # noqa: ANN001 (a clarabel solution)
    """The primal solution, ``None`` for a (near-)infeasible problem.

    Raises:
        EquilibriumError: Clarabel ended with neither a solution nor an infeasibility certificate.
    """
    status = str(sol.status)
    if status in ("Solved", "AlmostSolved"):
        return np.array(sol.x)
    if status in ("PrimalInfeasible", "AlmostPrimalInfeasible"):
        return None
    raise EquilibriumError(f"SOCP solver failed: status {status}")


def balance_rows_of(pb, nv: int, rhs: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # noqa: ANN001
    """Zero-cone rows of the wrench balance (B1)-(B2), ``sum f_i = rhs[:3]`` and ``sum r_i x f_i = rhs[3:]``
    (forces in columns ``3i..3i+2`` of ``nv``, weight units), the rows of :func:`balance_rows`, and
    ``f_y = 0`` for planar problems."""
    k = len(pb.contacts)
    rows = balance_rows(pb.planar)
    eq = np.zeros((6, nv))
    for i in range(k):
        eq[:3, 3 * i:3 * i + 3] = np.eye(3)
        eq[3:, 3 * i:3 * i + 3] = skew(pb.r[i])
    eq, beq = eq[rows], np.asarray(rhs, dtype=float)[rows]
    if pb.planar:
        fy = np.zeros((k, nv))
        fy[np.arange(k), 3 * np.arange(k) + 1] = 1.0
        eq, beq = np.vstack([eq, fy]), np.r_[beq, np.zeros(k)]
    return eq, beq


def cone_rows(pb, nv: int, implied: bool = True) -> tuple[list[np.ndarray], list[np.ndarray],  # noqa: ANN001
                                                         list[np.ndarray], list[np.ndarray], list[int]]:
    """Clarabel rows ``A z + s = b`` of the contact cones (B3), forces ``f_i`` in columns ``3i..3i+2`` of
    ``nv``: non-negative rows ``n.f + shift >= 0`` of friction and adhesion contacts, and one second-order
    cone per contact (``|T f| <= mu (n.f + shift)``, or ``|f| <= max_force`` for a grasp).  With ``implied=False``
    the non-negative row of a contact with ``mu > 0`` is left out: its cone implies it (one row fewer per contact,
    about 13 % less time per SOCP of the support region).

    Returns:
        ``(nn_rows, nn_b, soc_rows, soc_b, soc_dims)``, forces in weight units.
    """
    contacts, planar = pb.contacts, pb.planar
    nn, bnn, soc, bsoc, cones_soc = [], [], [], [], []
    N = np.array([c.normal for c in contacts])
    t1, t2 = tangent_bases(N)
    for i, c in enumerate(contacts):
        blk = slice(3 * i, 3 * i + 3)
        if c.kind == "grasp":  # |f| <= max_force
            a = np.zeros((4, nv))
            a[1:, blk] = -np.eye(3)
            soc.append(a)
            bsoc.append(np.r_[c.max_force / pb.weight, 0.0, 0.0, 0.0])
            cones_soc.append(4)
            continue
        shift = c.max_force / pb.weight if c.kind == "adhesion" else 0.0
        if implied or c.friction <= 0:
            a = np.zeros((1, nv))
            a[0, blk] = -N[i]
            nn.append(a)
            bnn.append(np.array([shift]))
        tang = np.vstack([np.cross([0.0, 1.0, 0.0], N[i])]) if planar else np.vstack([t1[i], t2[i]])
        a = np.zeros((1 + len(tang), nv))
        a[0, blk] = -c.friction * N[i]  # (B3): |T f| <= mu (n.f + shift)
        a[1:, blk] = -tang
        soc.append(a)
        bsoc.append(np.r_[c.friction * shift, np.zeros(len(tang))])
        cones_soc.append(1 + len(tang))
    return nn, bnn, soc, bsoc, cones_soc


def clarabel_support(pb, clip: float) -> Support:  # noqa: ANN001 (region._Problem: circular import)
    """``solve(d)``: a CoM point ``x`` (region coordinates relative to the contacts' centroid)
    maximising ``d . x`` with exact cones, or ``None`` when no equilibrium exists.

    Raises (from ``solve``):
        EquilibriumError: Clarabel ended with neither a solution nor an infeasibility certificate.
    """
    import clarabel
    from scipy import sparse

    contacts, planar = pb.contacts, pb.planar
    k, d = len(contacts), pb.basis.shape[0]
    nv = 3 * k + d
    # Zero cone: the wrench balance (B1)-(B2) in weight units, the CoM's moment in the x columns
    eq, beq = balance_rows_of(pb, nv, np.r_[-pb.ghat, 0.0, 0.0, 0.0])
    eq[:len(balance_rows(planar)), 3 * k:] = com_columns(pb.basis, pb.ghat)[balance_rows(planar)]
    # Non-negative cone: |x_j| <= clip, and n.f + shift >= 0 for friction and adhesion contacts.
    box = np.zeros((2 * d, nv))
    for j in range(d):
        box[2 * j, 3 * k + j], box[2 * j + 1, 3 * k + j] = 1.0, -1.0
    nn_c, bnn_c, soc, bsoc, cones_soc = cone_rows(pb, nv, implied=False)
    nn, bnn = [box, *nn_c], [np.full(2 * d, clip), *bnn_c]
    A, b, cones, settings = _standard_form(eq, beq, nn, bnn, soc, bsoc, cones_soc)
    settings.presolve_enable = False  # keeps the data updatable between directions
    # support points to about 1e-8 m, far inside the projection's tolerance (1e-4 m by default)
    settings.tol_gap_abs = settings.tol_gap_rel = 1e-7
    # no iterative refinement of the KKT solves: a quarter less time per SOCP; on 280 stances every SOCP still ended
    # Solved (or PrimalInfeasible) and the regions moved by under 1e-6 m, far inside the 1e-4 m tolerance
    settings.iterative_refinement_enable = False
    q = np.zeros(nv)
    P = sparse.csc_matrix((nv, nv))
    solver = None

    def solve(direction: np.ndarray) -> np.ndarray | None:
        nonlocal solver
        q[3 * k:] = -np.asarray(direction, dtype=float)
        if solver is None:
            solver = clarabel.DefaultSolver(P, q, A, b, cones, settings)
        else:
            solver.update(q=q)
        x = _solution(solver.solve())
        return None if x is None else x[3 * k:]

    return solve


def clarabel_torque(pb, com: np.ndarray, J: np.ndarray, gt: np.ndarray,  # noqa: ANN001
                    lim: np.ndarray, limited: np.ndarray) -> tuple[np.ndarray, float] | None:
    """The torque SOCP of :func:`climb_ompl.equilibrium.torque_feasible` in Clarabel's standard form:
    minimise ``t`` over forces ``f`` (weight units) and ``t >= 0`` subject to the wrench balance at the CoM
    ``com``, the exact cones and ``|g_j / w - sum_i J_i[:, j]^T f_i| <= t tau_max_j / w`` on the ``limited``
    joints (Bretl (2006), sec. 3.2.3 and appendix B).

    Returns:
        ``(f (k, 3) in weight units, t)``, or ``None`` when no balanced forces exist.

    Raises:
        EquilibriumError: Clarabel ended with neither a solution nor an infeasibility certificate.
    """
    import clarabel
    from scipy import sparse

    k = len(pb.contacts)
    nv = 3 * k + 1
    eq, beq = balance_rows_of(pb, nv, -np.r_[pb.ghat, np.cross(com - pb.origin, pb.ghat)])
    nn, bnn, soc, bsoc, cones_soc = cone_rows(pb, nv)
    tpos = np.zeros((1, nv))
    tpos[0, -1] = -1.0  # t >= 0
    nn, bnn = [tpos, *nn], [np.zeros(1), *bnn]
    if limited.any():
        # tau = g/w - Jt f with Jt (nl, 3k); |tau| <= t L  <=>  -Jt f - t L <= -g/w  and  Jt f - t L <= g/w
        Jt = np.hstack([J[i][:, limited].T for i in range(k)])
        L = (lim[limited] / pb.weight)[:, None]
        g = gt[limited] / pb.weight
        nn += [np.hstack([-Jt, -L]), np.hstack([Jt, -L])]
        bnn += [-g, g]
    A, b, cones, settings = _standard_form(eq, beq, nn, bnn, soc, bsoc, cones_soc)
    q = np.zeros(nv)
    q[-1] = 1.0
    x = _solution(clarabel.DefaultSolver(sparse.csc_matrix((nv, nv)), q, A, b, cones, settings).solve())
    return None if x is None else (x[:3 * k].reshape(k, 3), float(x[-1]))


def sandwich_projection(solve: Support, tol: float, max_solves: int = 400) -> tuple[np.ndarray | None, int]:
    """Inner polygon of a convex set's 2-D projection within ``tol`` of the set (sandwich algorithm).

    Every solve gives a support point ``p`` *and* a supporting line ``d . x <= d . p``.  Between two
    consecutive support points the set lies in the triangle formed by their chord and the crossing of
    their supporting lines, so a chord whose crossing is within ``tol`` of it is final without a further
    solve; otherwise the chord's outward normal is solved next.  About one solve per vertex, where
    checking each edge by another solve (the iterative projection of Bretl & Lall (2006)) needs two.

    Returns:
        (support points ``(m, 2)`` counter-clockwise, or ``None`` if the set is empty; number of solves).
    """
    items: list[tuple[float, float, float]] = []  # (angle, support point x, y), angles increasing
    for a in (0.0, 2 * math.pi / 3, 4 * math.pi / 3):
        p = solve(np.array([math.cos(a), math.sin(a)]))
        if p is None:
            return None, len(items) + 1
        items.append((a, float(p[0]), float(p[1])))
    n_solves = 3
    i = 0
    two_pi = 2 * math.pi
    while i < len(items) and n_solves < max_solves:
        a0, x0, y0 = items[i]
        a1, x1, y1 = items[(i + 1) % len(items)]
        span = (a1 - a0) % two_pi
        ex, ey = x1 - x0, y1 - y0
        L = math.hypot(ex, ey)
        if L < 1e-12 and span < math.pi:
            i += 1  # one support point for the whole angular interval: a corner
            continue
        gap = math.inf
        if span < math.pi - 1e-9 and L >= 1e-12:
            c0, s0, c1, s1 = math.cos(a0), math.sin(a0), math.cos(a1), math.sin(a1)
            det = c0 * s1 - s0 * c1
            if abs(det) > 1e-14:
                h0, h1 = c0 * x0 + s0 * y0, c1 * x1 + s1 * y1
                vx, vy = (h0 * s1 - h1 * s0) / det, (c0 * h1 - c1 * h0) / det  # the supporting lines cross
                gap = (ey * (vx - x0) - ex * (vy - y0)) / L
            else:
                gap = 0.0
        if gap <= tol:
            i += 1
            continue
        # Next direction: the chord's outward normal, kept strictly inside the angular interval.
        a = math.atan2(-ex, ey) if L >= 1e-12 else a0 + 0.5 * span
        off = (a - a0) % two_pi
        if not (1e-9 < off < span - 1e-9):
            off = 0.5 * span
        a = a0 + off
        p = solve(np.array([math.cos(a), math.sin(a)]))
        n_solves += 1
        if p is None:  # pragma: no cover - the set was non-empty for the first directions
            raise EquilibriumError("SOCP became infeasible during the projection")
        items.insert(i + 1, (a, float(p[0]), float(p[1])))
    return np.array([(x, y) for _, x, y in items]), n_solves
