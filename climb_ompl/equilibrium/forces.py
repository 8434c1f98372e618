"""Contact forces for one CoM position, and joint-torque feasibility (Bretl (2006) section 3.2.3).

Forces ``f_i`` are those the holds exert on the robot, newtons, world frame.  Static equilibrium is
Bretl (2006) appendix B, eqs. (B1)-(B3); joint torques of the quasi-static robot are
``tau = g(q) - sum_i J_i(q)^T f_i`` with ``g(q)`` the generalised gravity torques and ``J_i`` the
``3 x nq`` position Jacobians of the contact points (LEMUR's planner outputs these as feed-forward
torques, Bretl (2006) section 5).
"""

from __future__ import annotations

import warnings
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from climb_ompl.equilibrium._contacts import (
    CONE_EDGES,
    Contact,
    Linearised,
    as_contacts,
    balance_rows,
    check_mass_gravity,
    check_planar_contacts,
    check_point,
    cross,
    linearise,
    skew,
    tangent_basis,
    wrench_matrix,
)
from climb_ompl.equilibrium._exact import clarabel_torque
from climb_ompl.equilibrium._highs import DenseLP
from climb_ompl.equilibrium._simplex import SimplexError, Tableau
from climb_ompl.equilibrium.region import _Problem, check_cone_edges, support_region
from climb_ompl.errors import EquilibriumError


@dataclass(frozen=True, eq=False)
class ForceResult:
    """Contact forces realising static equilibrium.

    Attributes:
        forces: ``(k, 3)`` force of each hold on the robot, newtons, world frame.
        usage: ``(k,)`` fraction of each contact's capacity in use: ``|f_t| / (mu f_n)`` for friction,
            ``|f_t| / (mu (f_n + max_force))`` for adhesion, ``|f| / max_force`` for grasps.
        ratio: ``max(usage)``, the quantity minimised (1 = some contact on the verge of slipping).
        residual: largest absolute error of the force (N) and moment (N m) balance.
        status: ``"optimal"``.
    """

    forces: np.ndarray
    usage: np.ndarray
    ratio: float
    residual: float
    status: str = "optimal"


@dataclass(frozen=True, eq=False)
class TorqueResult:
    """Outcome of a torque-feasibility test.

    Attributes:
        feasible: contact forces exist that balance the robot with ``|tau_j| <= tau_max_j``.
        forces: ``(k, 3)`` contact forces, newtons (``None`` when infeasible).
        torques: ``(nq,)`` joint torques ``g(q) - sum J_i^T f_i``, N m (``None`` when infeasible).
        utilisation: ``max_j |tau_j| / tau_max_j`` over limited joints (``inf`` when infeasible; for
            :func:`torque_feasible`'s ``"torque_limit"``, the smallest such ratio any balanced forces give).
        status: ``"feasible"``, ``"torque_limit"`` (equilibrium possible, torques too high),
            ``"no_equilibrium"`` (no balanced contact forces) or, from :class:`TorqueChecker`'s
            prefilters, ``"outside_support_region"``.
        worst: the joint (configuration index) with the largest ratio at those forces, when known.
    """

    feasible: bool
    forces: np.ndarray | None
    torques: np.ndarray | None
    utilisation: float
    status: str
    worst: int | None = None

    def __bool__(self) -> bool:
        return self.feasible


# ---- shared pieces -----------------------------------------------------------------------------------
def _setup(contacts: Sequence[Any], mass: Any, gravity: Any, planar: bool, com: Any) -> tuple[_Problem, np.ndarray]:
    cs = as_contacts(contacts)
    m, g = check_mass_gravity(mass, gravity, planar)
    if planar:
        check_planar_contacts(cs)
    return _Problem(cs, m, g, planar), check_point(com)


def _balance_system(pb: _Problem, com: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """``A f = b`` for stacked forces ``f`` (3k,) in newtons, world positions (B1)-(B2)."""
    k = len(pb.contacts)
    P = np.array([c.position for c in pb.contacts])
    A = np.vstack([np.hstack([np.eye(3)] * k), np.hstack([skew(P[i]) for i in range(k)])])
    W = pb.mass * pb.g
    b = -np.r_[W, np.cross(com, W)]
    rows = balance_rows(pb.planar)
    A, b = A[rows], b[rows]
    if pb.planar:  # forces stay in the x-z plane
        Y = np.zeros((k, 3 * k))
        Y[np.arange(k), 3 * np.arange(k) + 1] = 1.0
        A, b = np.vstack([A, Y]), np.r_[b, np.zeros(k)]
    return A, b


def _polish(pb: _Problem, com: np.ndarray, F: np.ndarray) -> tuple[np.ndarray, float]:
    """Least-norm correction of forces ``F`` (k, 3) onto the balance equations; (forces, residual)."""
    A, b = _balance_system(pb, com)
    f = F.reshape(-1)
    f = f - np.linalg.lstsq(A, A @ f - b, rcond=None)[0]
    return f.reshape(-1, 3), float(np.max(np.abs(A @ f - b)))


def usage(contacts: Sequence[Contact], forces: np.ndarray) -> np.ndarray:
    """Fraction of each contact's capacity used by ``forces`` (k, 3) newtons (see :class:`ForceResult`)."""
    out = np.zeros(len(contacts))
    for i, (c, f) in enumerate(zip(contacts, forces, strict=True)):
        n = c.n
        if c.kind == "grasp":
            out[i] = np.linalg.norm(f) / c.max_force
            continue
        fn = n @ f + (c.max_force if c.kind == "adhesion" else 0.0)
        ft = np.linalg.norm(f - (n @ f) * n)
        if fn <= 0:
            out[i] = 0.0 if (ft <= 1e-9 and fn >= -1e-9) else np.inf
        elif c.friction == 0:
            out[i] = 0.0 if ft <= 1e-9 * max(1.0, fn) else np.inf
        else:
            out[i] = ft / (c.friction * fn)
    return out


# ---- contact forces -------------------------------------------------------------------------------------
def contact_forces(
    contacts: Sequence[Contact | Any],
    mass: float,
    gravity: Any,
    com: Any,
    *,
    planar: bool = False,
    tol: float = 1e-4,
) -> ForceResult | None:
    """The most robust contact forces holding the robot in equilibrium at ``com`` (exact cones).

    Minimises the largest fraction of any contact's capacity in use, ``rho`` (for friction the
    ratio of tangential to ``mu`` times normal force), subject to (B1)-(B2) with the cones (B3)
    scaled by ``rho``; the problem is quasi-convex, so ``rho`` is found by bisection over SOCPs
    (cvxpy/Clarabel) to ``tol``.  The forces are then polished onto (B1)-(B2) by a least-norm
    correction, so the balance holds to about 1e-12 relative (1e-8 N absolute for robot weights).

    Args:
        contacts: :class:`Contact` s (or terrain holds).
        mass: kg.
        gravity: m/s^2, world frame.
        com: centre of mass, world frame, metres.
        planar: forces in the x-z plane only.
        tol: bisection tolerance on ``rho``.

    Returns:
        The forces, or ``None`` when no contact forces balance the robot at ``com``.

    Raises:
        EquilibriumError: bad input (naming the value).
    """
    import cvxpy as cp

    pb, c = _setup(contacts, mass, gravity, planar, com)
    k = len(pb.contacts)
    f = cp.Variable((k, 3))
    rho = cp.Parameter(nonneg=True)
    y = np.array([0.0, 1.0, 0.0])
    cons = []
    for i, ct in enumerate(pb.contacts):
        n = ct.n
        T = np.cross(y, n)[None, :] if planar else np.vstack(tangent_basis(n))
        if ct.kind == "grasp":
            cons.append(cp.norm(f[i]) <= rho * (ct.max_force / pb.weight))
        else:
            shift = ct.max_force / pb.weight if ct.kind == "adhesion" else 0.0
            cons.append(cp.norm(T @ f[i]) <= rho * (ct.friction * (n @ f[i] + shift)))
            cons.append(n @ f[i] >= -rho * shift)
    if planar:
        cons.append(f[:, 1] == 0)
    rows = balance_rows(planar)
    cprime = c - pb.origin
    wrench = cp.hstack([cp.sum(f, axis=0), sum(skew(pb.r[i]) @ f[i] for i in range(k))])
    cons.append(wrench[rows] == -np.r_[pb.ghat, np.cross(cprime, pb.ghat)][rows])
    prob = cp.Problem(cp.Minimize(cp.sum_squares(f)), cons)

    def attempt(value: float) -> np.ndarray | None:
        rho.value = value
        try:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # "may be inaccurate" near the bisection's boundary
                prob.solve(solver="CLARABEL")
        except cp.error.SolverError:
            return None
        if prob.status in ("optimal", "optimal_inaccurate") and f.value is not None:
            return np.array(f.value)
        return None

    best = attempt(1.0)
    if best is None:
        return None
    lo, hi = 0.0, 1.0
    zero = attempt(0.0)
    if zero is not None:
        best, hi = zero, 0.0
    while hi - lo > tol:
        mid = 0.5 * (lo + hi)
        sol = attempt(mid)
        if sol is None:
            lo = mid
        else:
            best, hi = sol, mid
    forces, residual = _polish(pb, c, best * pb.weight)
    u = usage(pb.contacts, forces)
    return ForceResult(forces, u, float(u.max()), residual)


# ---- torque limits ----------------------------------------------------------------------------------------
def torque_rows(lin: Linearised, weight: float, J: np.ndarray, gt: np.ndarray, lim: np.ndarray, limited: np.ndarray,
                blocks: np.ndarray | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """The joint-torque limits as rows on the cone-edge weights: ``|tau0 - M lam| <= L`` (weight units).

    Joint torques are ``tau = g(q) - sum_i J_i^T f_i`` (Bretl (2006) sec. 3.2.3) with
    ``f_i = weight * (sum of contact i's edges * lam + offset_i)``.  Only limited joints that some
    contact Jacobian reaches become rows; the others must hold their gravity torque alone.

    Args:
        blocks: :func:`generator_blocks` ``(lin)``, if already computed.

    Returns:
        ``(M, tau0, L)``, or ``None`` when a limited joint no contact reaches exceeds its limit.
    """
    touched = (J != 0.0).any(axis=(0, 1))
    alone = limited & ~touched
    if (np.abs(gt[alone]) > lim[alone]).any():
        return None
    sel = limited & touched
    Js = J[:, :, sel].reshape(3 * len(J), int(sel.sum()))  # (3k, ns): contact i's rows are 3i..3i+2
    # M[j, l] = (J_owner(l)^T gens[:, l])_j: torque of generator l at joint j (per unit weight), as one
    # product with the block-diagonal (3k, n) matrix of the generators.
    M = Js.T @ (generator_blocks(lin) if blocks is None else blocks)
    tau0 = gt[sel] / weight
    if lin.offsets.any():
        tau0 -= Js.T @ lin.offsets.reshape(-1)
    return M, tau0, lim[sel] / weight


def generator_blocks(lin: Linearised) -> np.ndarray:
    """``(3k, n)`` matrix with contact ``i``'s cone generators in rows ``3i..3i+2`` (zeros elsewhere)."""
    k = len(lin.offsets)
    B = np.zeros((3 * k, lin.gens.shape[1]))
    cols = np.arange(lin.gens.shape[1])
    for a in range(3):
        B[3 * lin.owner + a, cols] = lin.gens[a]
    return B


def _check_torque_args(k: int, jacobians: Any, gravity_torques: Any, torque_limits: Any,
                       actuated: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    J = np.asarray(jacobians, dtype=float)
    if J.ndim != 3 or J.shape[0] != k or J.shape[1] != 3:
        raise EquilibriumError(f"jacobians: expected shape ({k}, 3, nq), got {J.shape}")
    nq = J.shape[2]
    gt = np.asarray(gravity_torques, dtype=float).reshape(-1)
    lim = np.asarray(torque_limits, dtype=float).reshape(-1)
    act = np.asarray(actuated, dtype=bool).reshape(-1)
    for name, arr in (("gravity_torques", gt), ("torque_limits", lim), ("actuated", act)):
        if arr.shape != (nq,):
            raise EquilibriumError(f"{name}: expected shape ({nq},), got {arr.shape}")
    if not (np.all(np.isfinite(J)) and np.all(np.isfinite(gt))):
        raise EquilibriumError("jacobians/gravity_torques: non-finite value")
    if np.any(np.isnan(lim)) or np.any(lim[act] <= 0):
        raise EquilibriumError(f"torque_limits: must be > 0 on actuated joints, got {lim[act].tolist()!r}")
    return J, gt, lim, act


def torque_feasible(
    contacts: Sequence[Contact | Any],
    mass: float,
    gravity: Any,
    com: Any,
    jacobians: Any,
    gravity_torques: Any,
    torque_limits: Any,
    actuated: Any,
    *,
    planar: bool = False,
) -> TorqueResult:
    """Whether contact forces in the exact cones hold the robot with every ``|tau_j| <= tau_max_j``.

    Solves one SOCP (Clarabel, :func:`._exact.clarabel_torque`): minimise ``t`` subject to the wrench
    balance (B1)-(B2) (planar:
    ``f_x, f_z, tau_y``), the cones (B3) and ``|tau_j| <= t tau_max_j`` on actuated joints with finite
    limits, where ``tau = g(q) - sum_i J_i^T f_i``.  Feasible iff ``t <= 1``; the returned forces are
    the ones that minimise the largest torque ratio.  Unactuated joints are not constrained (the
    wrench balance stands in for the free base's equations).

    Args:
        contacts: the ``k`` contacts.
        mass: kg.  gravity: m/s^2.  com: CoM, metres, world frame.
        jacobians: ``(k, 3, nq)`` position Jacobians of the contact points.
        gravity_torques: ``(nq,)`` generalised gravity torques ``g(q)``, N m (or N).
        torque_limits: ``(nq,)`` limits, N m (``inf`` where unlimited).
        actuated: ``(nq,)`` bool mask of actuated joints.
        planar: 2-D problem (x-z plane).

    Raises:
        EquilibriumError: bad input (naming the value).
    """
    pb, c = _setup(contacts, mass, gravity, planar, com)
    k = len(pb.contacts)
    J, gt, lim, act = _check_torque_args(k, jacobians, gravity_torques, torque_limits, actuated)
    limited = act & np.isfinite(lim)
    sol = clarabel_torque(pb, c, J, gt, lim, limited)
    if sol is None:
        return TorqueResult(False, None, None, np.inf, "no_equilibrium")
    forces, _ = _polish(pb, c, sol[0] * pb.weight)
    torques = gt - np.einsum("kiq,ki->q", J, forces)
    ratio = np.where(limited, np.abs(torques) / np.where(limited, lim, 1.0), 0.0)
    util = float(ratio.max()) if limited.any() else 0.0
    ok = util <= 1.0 + 1e-6
    return TorqueResult(ok, forces if ok else None, torques if ok else None, util,
                        "feasible" if ok else "torque_limit", int(np.argmax(ratio)) if limited.any() else None)


class TorqueChecker:
    """Fast per-state torque-limit test for one stance (linearised cones, one small LP).

    Cheap tests run first: the CoM must lie in the stance's (linearised) support region, and a limited
    joint that no contact Jacobian reaches (e.g. of the free limb) must hold its own gravity torque.
    Then the cone-edge weights of the last feasible state, re-fitted to this state's wrench balance, are
    tried (an explicit feasible point accepts the state at once).  Otherwise one feasibility LP over
    the cone-edge weights ``lam >= 0``: the wrench balance (Bretl, Latombe & Rock (2003) eq. (7)) and
    ``|g - sum_i J_i^T G_i lam_i| <= tau_max`` (Bretl (2006) sec. 3.2.3), solved by the dense tableau
    simplex of :mod:`._simplex` (phase 1 only).  Inscribed cones make it conservative with respect to
    :func:`torque_feasible`.

    Args:
        contacts: the stance's contacts.
        mass: kg.  gravity: m/s^2.
        torque_limits: ``(nq,)`` N m (``inf`` where unlimited).
        actuated: ``(nq,)`` bool mask.
        planar: 2-D problem.
        cone_edges: edges of the linearised cones; the default is :func:`support_region`'s, so that a
            state inside the support region is never rejected for a different cone model.
        region: the stance's support region for the prefilter (computed with the same cones if omitted).

    Raises:
        EquilibriumError: bad input, or a linearised ``region`` computed with another ``cone_edges``.
    """

    def __init__(self, contacts: Sequence[Contact | Any], mass: float, gravity: Any, torque_limits: Any,
                 actuated: Any, *, planar: bool = False, cone_edges: int = CONE_EDGES, region: Any = None):
        self.contacts = as_contacts(contacts)
        m, g = check_mass_gravity(mass, gravity, planar)
        if planar:
            check_planar_contacts(self.contacts)
        cone_edges = check_cone_edges(cone_edges)
        if region is not None and not getattr(region, "exact", False) and not planar \
                and getattr(region, "cone_edges", cone_edges) != cone_edges:
            raise EquilibriumError(f"region: computed with cone_edges={region.cone_edges}, the torque check "
                                   f"uses cone_edges={cone_edges} (pass the same value to both)")
        self.cone_edges = cone_edges
        self.pb = _Problem(self.contacts, m, g, planar)
        self.lim = np.asarray(torque_limits, dtype=float).reshape(-1)
        self.act = np.asarray(actuated, dtype=bool).reshape(-1)
        if self.lim.shape != self.act.shape:
            raise EquilibriumError(f"torque_limits/actuated: shapes differ, {self.lim.shape} vs {self.act.shape}")
        if np.any(np.isnan(self.lim)) or np.any(self.lim[self.act] <= 0):
            raise EquilibriumError(f"torque_limits: must be > 0 on actuated joints, "
                                   f"got {self.lim[self.act].tolist()!r}")
        self.limited = self.act & np.isfinite(self.lim)
        self.region = region if region is not None else support_region(
            self.contacts, m, g, planar=planar, cone_edges=cone_edges)
        self.lin = linearise(self.contacts, self.pb.weight, cone_edges, planar)
        self.rows = balance_rows(planar)
        self.W = wrench_matrix(self.pb.r, self.lin.gens, self.lin.owner)[self.rows]
        off = self.lin.offsets
        self._rhs_const = -np.r_[self.pb.ghat + off.sum(axis=0), cross(self.pb.r, off).sum(axis=0)][self.rows]
        # the balance's right-hand side moves with the CoM c by -(c x ghat) in the moment rows
        self._moment_of_com = np.vstack([np.zeros((3, 3)), -skew(self.pb.ghat)])[self.rows]
        nl = self.W.shape[1]
        self.G = np.zeros((len(self.lin.bounds), nl))
        self.Gb = np.array([b for _, b in self.lin.bounds])
        for r, (i, _) in enumerate(self.lin.bounds):
            self.G[r, self.lin.owner == i] = 1.0
        # forces (k, 3) = onehot @ (gens * lam).T
        self._onehot = (self.lin.owner[None, :] == np.arange(len(self.contacts))[:, None]).astype(float)
        self._blocks = generator_blocks(self.lin)
        self._support: np.ndarray | None = None  # cone edges in use at the last feasible state
        self._pinv: np.ndarray | None = None
        self._eqb: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None  # feasible basis of the balance rows
        self._template: tuple[Any, Any, np.ndarray] | None = None  # warm tableau without the torque rows
        self._beq: np.ndarray | None = None  # B^-1 rhs of the cached balance basis at the current state
        self.calls = 0
        self.lp_calls = 0

    def __call__(self, com: Any, jacobians: Any, gravity_torques: Any) -> bool:
        """Whether the state is torque-feasible (see :meth:`check`)."""
        return self.check(com, jacobians, gravity_torques).feasible

    def _refit(self, rhs: np.ndarray) -> np.ndarray | None:
        """The last feasible state's cone edges re-fitted to ``rhs`` (``None`` if that fails)."""
        if self._support is None:
            return None
        lam_s = self._pinv @ rhs
        if lam_s.min() < 0 or np.abs(self.W[:, self._support] @ lam_s - rhs).max() > 1e-10:
            return None
        lam = np.zeros(self.W.shape[1])
        lam[self._support] = lam_s
        return lam

    def check(self, com: Any, jacobians: Any, gravity_torques: Any) -> TorqueResult:
        """Test one state.

        Args:
            com: CoM, metres, world frame.
            jacobians: ``(k, 3, nq)`` contact-point Jacobians.
            gravity_torques: ``(nq,)`` generalised gravity torques ``g(q)``.
        """
        self.calls += 1
        pb = self.pb
        c = check_point(com)
        if not self.region.contains(c):
            return TorqueResult(False, None, None, np.inf, "outside_support_region")
        J = np.asarray(jacobians, dtype=float)
        gt = np.asarray(gravity_torques, dtype=float).reshape(-1)
        nq = len(self.lim)
        if J.shape != (len(self.contacts), 3, nq) or gt.shape != (nq,):
            _check_torque_args(len(self.contacts), J, gt, self.lim, self.act)  # raises, naming the array
        if not np.isfinite(J.sum() + gt.sum()):
            raise EquilibriumError("jacobians/gravity_torques: non-finite value")
        lim = self.lim
        rows = torque_rows(self.lin, pb.weight, J, gt, lim, self.limited, self._blocks)
        if rows is None:
            return TorqueResult(False, None, None, np.inf, "torque_limit")
        M, tau0, L = rows
        w = pb.weight
        gens, off = self.lin.gens, self.lin.offsets
        rhs = self._rhs_const - self._moment_of_com @ (c - pb.origin)
        lam = self._refit(rhs)
        if lam is not None and (np.any(np.abs(tau0 - M @ lam) > L) or np.any(self.G @ lam > self.Gb)):
            lam = None
        if lam is None:
            lam = self._solve(M, tau0, L, rhs)
        if lam is None:
            return TorqueResult(False, None, None, np.inf, "torque_limit")
        forces = (self._onehot @ (gens * lam).T + off) * w
        torques = gt - np.einsum("kiq,ki->q", J, forces)
        util = float(np.max(np.abs(torques[self.limited]) / lim[self.limited])) if self.limited.any() else 0.0
        return TorqueResult(True, forces, torques, util, "feasible")

    def _cold_tableau(self, M: np.ndarray, tau0: np.ndarray, L: np.ndarray, rhs: np.ndarray) -> Tableau:
        """Tableau with artificials on the balance rows (no feasible balance basis known)."""
        W, G = self.W, self.G
        E, nl = W.shape
        ns, ng = len(tau0), len(self.Gb)
        m = E + 2 * ns + ng
        A = np.zeros((m, nl + 2 * ns + ng))
        A[:E, :nl], A[E:E + ns, :nl], A[E + ns:E + 2 * ns, :nl], A[E + 2 * ns:, :nl] = W, M, -M, G
        slack = np.full(m, -1)
        slack[E:] = nl + np.arange(m - E)
        A[np.arange(E, m), slack[E:]] = 1.0
        b = np.concatenate([rhs, tau0 + L, L - tau0, self.Gb])
        return Tableau(A, b, np.zeros((0, A.shape[1])), slack)

    def _warm_tableau(self, start: tuple[np.ndarray, np.ndarray, np.ndarray], M: np.ndarray, tau0: np.ndarray,
                      L: np.ndarray, rhs: np.ndarray) -> Tableau:
        """Tableau in canonical form for the balance basis ``start`` and the torque and grasp rows' slacks.

        Torque or grasp rows violated at the balance basis's solution get artificials (each of these rows
        has a reserved artificial column; unused ones stay zero).
        """
        cols, inv, Weq = start
        E, nl = self.W.shape
        ns, ng = len(tau0), len(self.Gb)
        m = E + 2 * ns + ng
        N = nl + 2 * ns + ng
        key = (ns, ng)
        if self._template is None or self._template[0] != key or self._template[1] is not cols:
            T0 = np.zeros((m + 1, N + m - E + 1))
            T0[:E, :nl] = Weq
            T0[np.arange(E, m), nl + np.arange(m - E)] = 1.0
            if ng:
                Gb = self.G[:, cols]
                T0[E + 2 * ns:m, :nl] = self.G - Gb @ Weq
            self._template = (key, cols, T0)
        T = self._template[2].copy()
        beq = np.maximum(self._beq if self._beq is not None else inv @ rhs, 0.0, out=T[:E, -1])
        Mb = M[:, cols]
        Mc = np.subtract(M, Mb @ Weq, out=T[E:E + ns, :nl])
        np.negative(Mc, out=T[E + ns:E + 2 * ns, :nl])
        t0 = tau0 - Mb @ beq
        np.add(t0, L, out=T[E:E + ns, -1])
        np.subtract(L, t0, out=T[E + ns:E + 2 * ns, -1])
        if ng:
            T[E + 2 * ns:m, -1] = self.Gb - self.G[:, cols] @ beq
        basis = [*cols.tolist(), *range(nl, N)]
        bad = np.flatnonzero(T[:m, -1] < 0)
        if len(bad):
            T[bad, :N] *= -1.0
            T[bad, -1] *= -1.0
            art = N + bad - E  # row E + i owns artificial column N + i
            T[bad, art] = 1.0
            T[-1, :N] = T[bad, :N].sum(axis=0)
            T[-1, -1] = T[bad, -1].sum()
            for r, a in zip(bad.tolist(), art.tolist(), strict=True):
                basis[r] = a
        return Tableau.feasibility(T, basis, m, N)

    def _eq_basis(self, rhs: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
        """A feasible basis of the wrench balance alone: ``(columns, B^-1, B^-1 W)``, cached while feasible."""
        self._beq = None
        if self._eqb is not None:
            cols, inv, _ = self._eqb
            beq = inv @ rhs
            if beq.min() >= -1e-12:
                self._beq = beq  # B^-1 rhs, for the warm tableau
                return self._eqb
        tab = Tableau(self.W, rhs, np.zeros((0, self.W.shape[1])), np.full(len(rhs), -1))
        try:
            if not tab.phase1():
                return None
        except SimplexError:  # pragma: no cover - the full LP below decides
            return None
        cols = np.array(tab.basis)
        if cols.min() < 0:  # redundant balance rows: no square basis to start from
            return None
        inv = np.linalg.inv(self.W[:, cols])
        Weq = inv @ self.W
        Weq[:, cols] = np.eye(len(cols))
        self._eqb = (cols, inv, Weq)
        return self._eqb

    def _solve(self, M: np.ndarray, tau0: np.ndarray, L: np.ndarray, rhs: np.ndarray) -> np.ndarray | None:
        """Phase 1 of the tableau simplex on the balance, torque and grasp rows; ``lam`` or ``None``.

        The tableau starts from a feasible basis of the balance rows (with the torque and grasp rows'
        slacks), so only the violated torque rows need artificials.
        """
        self.lp_calls += 1
        W, G = self.W, self.G
        E, nl = W.shape
        ns, ng = len(tau0), len(self.Gb)
        m = E + 2 * ns + ng
        N = nl + 2 * ns + ng
        start = self._eq_basis(rhs)
        try:
            if start is None:
                tab = self._cold_tableau(M, tau0, L, rhs)
            else:
                tab = self._warm_tableau(start, M, tau0, L, rhs)
            if not tab.phase1():
                return None
            z = tab.solution()
        except SimplexError:  # pragma: no cover - stalls were not seen; HiGHS is the safety net
            A0 = np.zeros((m, N))
            A0[:E, :nl], A0[E:E + ns, :nl], A0[E + ns:E + 2 * ns, :nl], A0[E + 2 * ns:, :nl] = W, M, -M, G
            A0[np.arange(E, m), nl + np.arange(m - E)] = 1.0
            b0 = np.concatenate([rhs, tau0 + L, L - tau0, self.Gb])
            z = DenseLP(A0, b0, b0, np.zeros(N), np.full(N, np.inf)).solve()
            if z is None:
                return None
        lam = z[:nl]
        support = np.flatnonzero(lam > 1e-12)
        if len(support) <= E:
            self._support = support
            self._pinv = np.linalg.pinv(W[:, support])
        return lam
