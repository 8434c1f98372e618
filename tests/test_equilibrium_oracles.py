"""Support regions against independent oracles.

* linearised cones: a per-point feasibility LP (scipy ``linprog``, assembled here from the raw
  equations (B1)-(B2) of Bretl (2006), appendix B) on grids, random points and probes 1e-5 m on either
  side of every edge, for 200+ random stances; and an exact polyhedral projection (pycddlib's double
  description method, v3 API) of the lifted polyhedron;
* exact cones: a per-point SOCP (cvxpy) - inner polygon feasible, anything ``tol`` beyond an edge infeasible;
* linearised inside exact, converging as the number of cone edges grows.
"""

from __future__ import annotations

import warnings

import cdd
import cvxpy as cp
import numpy as np
import pytest
from scipy.optimize import linprog

from climb_ompl.equilibrium import Contact, support_region
from climb_ompl.equilibrium._contacts import linearise
from climb_ompl.model.terrain import generate_wall

BAND = 1e-6  # points nearer the boundary than this are not compared (solver tolerance)
FAMILIES = ("wall", "overhang", "slab", "floor", "hanging", "random_gravity", "mixed_kinds", "random_normals")


def random_stance(seed: int) -> tuple[list[Contact], float, np.ndarray, str]:
    """A reproducible random stance: (contacts, mass, gravity, family)."""
    rng = np.random.default_rng(seed)
    family = FAMILIES[seed % len(FAMILIES)]
    n = int(rng.integers(2, 5))
    mass = float(rng.uniform(1.0, 10.0))
    if family in ("wall", "overhang", "slab", "mixed_kinds", "random_gravity"):
        tilt = {"wall": 0.0, "overhang": -rng.uniform(5, 25), "slab": rng.uniform(5, 40)}.get(family, 0.0)
        w = generate_wall(seed, width=1.2, height=1.2, tilt_deg=tilt)
        P = w.positions
        centre = P[rng.integers(len(P))]
        near = np.argsort(np.linalg.norm(P - centre, axis=1))[: 4 * n]
        pick = rng.choice(near, size=n, replace=False)
        contacts = [Contact.from_hold(w.holds[i]) for i in pick]
        g = w.g
        if family == "random_gravity":
            d = rng.normal(size=3)
            d[2] = -abs(d[2]) - 0.5
            g = 9.81 * d / np.linalg.norm(d)
        if family == "mixed_kinds":
            c0, c1 = contacts[0], contacts[-1]
            contacts[0] = Contact(c0.position, c0.normal, c0.friction, "adhesion", float(rng.uniform(5, 60)))
            contacts[-1] = Contact(c1.position, c1.normal, 0.0, "grasp", float(rng.uniform(20, 150)))
        return contacts, mass, np.asarray(g, dtype=float), family
    contacts = []
    for _ in range(n):
        p = rng.uniform(-0.4, 0.4, size=3)
        if family == "floor":  # pushing only: holds below, normals near +z
            p[2] = rng.uniform(-0.1, 0.1)
            nrm = np.array([*rng.normal(scale=0.3, size=2), 1.0])
        elif family == "hanging":  # pulling only: ledges above the CoM, the robot hangs from them
            p[2] = 1.0 + rng.uniform(-0.1, 0.1)
            nrm = np.array([*rng.normal(scale=0.5, size=2), 1.0])
        else:
            nrm = rng.normal(size=3)
        contacts.append(Contact(tuple(p), tuple(nrm), float(rng.uniform(0.2, 1.2))))
    return contacts, mass, np.array([0.0, 0.0, -9.81]), family


def lp_oracle(contacts: list[Contact], mass: float, g: np.ndarray, k: int):
    """Per-point oracle: ``com -> bool``, do non-negative cone-edge weights balance the robot at ``com``?"""
    weight = mass * np.linalg.norm(g)
    lin = linearise(contacts, weight, k, planar=False)  # the cone model (edges checked in test_equilibrium)
    ghat = g / np.linalg.norm(g)
    P = np.array([contacts[i].position for i in lin.owner])
    A = np.vstack([lin.gens, np.cross(P, lin.gens.T).T])
    b_force = -ghat - lin.offsets.sum(axis=0)
    b_moment = -sum(np.cross(c.position, o) for c, o in zip(contacts, lin.offsets, strict=True))
    A_ub = np.array([[1.0 if o == i else 0.0 for o in lin.owner] for i, _ in lin.bounds]) if lin.bounds else None
    b_ub = np.array([bd for _, bd in lin.bounds]) if lin.bounds else None
    cost = np.zeros(A.shape[1])

    def feasible(com: np.ndarray) -> bool:
        b = np.r_[b_force, b_moment - np.cross(com, ghat)]
        res = linprog(cost, A_ub=A_ub, b_ub=b_ub, A_eq=A, b_eq=b, bounds=(0, None), method="highs")
        return res.status == 0

    return feasible


def probe_points(region, contacts, rng) -> np.ndarray:
    """World points: a grid and random points around the region or holds, and probes across every edge."""
    up = -np.cross(region.basis[0], region.basis[1])
    P2 = np.array([c.position for c in contacts]) @ region.basis.T
    if not region.is_empty:
        P2 = np.vstack([P2, region.vertices])
    lo, hi = P2.min(axis=0) - 0.15, P2.max(axis=0) + 0.15
    lo, hi = np.maximum(lo, P2.mean(0) - 2.0), np.minimum(hi, P2.mean(0) + 2.0)
    gx, gy = np.meshgrid(np.linspace(lo[0], hi[0], 4), np.linspace(lo[1], hi[1], 4))
    X = [np.column_stack([gx.ravel(), gy.ravel()]), rng.uniform(lo, hi, size=(6, 2))]
    if not region.is_empty and len(region.vertices) >= 2:
        V = region.vertices
        mids = 0.5 * (V + np.roll(V, -1, axis=0))
        for (a, b_, c) in region.halfplanes[:: max(1, len(region.halfplanes) // 6)]:
            n = np.array([a, b_])
            on = mids[np.abs(mids @ n - c) < 1e-9]
            X += [on + 1e-5 * n, on - 1e-5 * n]
    X = np.vstack(X)
    return X @ region.basis + rng.uniform(-1, 1, size=(len(X), 1)) * up


@pytest.mark.parametrize("chunk", [0, *(pytest.param(c, marks=pytest.mark.heavy) for c in range(1, 4))])
def test_polygon_agrees_with_per_point_lp(chunk):
    n_checked = n_inside = n_outside = 0
    for seed in range(chunk * 55, (chunk + 1) * 55):  # 220 stances in all
        contacts, mass, g, family = random_stance(seed)
        k = 4 if seed % 2 else 8
        region = support_region(contacts, mass, g, cone_edges=k)
        rng = np.random.default_rng(10_000 + seed)
        pts = probe_points(region, contacts, rng)
        inside, margin = region.contains(pts), region.margin(pts)
        feasible = lp_oracle(contacts, mass, g, k)
        for p, ins, m in zip(pts, inside, margin, strict=True):
            if abs(m) < BAND:
                continue
            oracle = feasible(p)
            assert oracle == ins, (f"seed {seed} ({family}, {len(contacts)} holds, k={k}): point {p} "
                                   f"margin {m:.3g} m, region says {ins}, LP says {oracle}")
            n_checked += 1
            n_inside += int(ins)
            n_outside += int(not ins)
    # The comparison is not vacuous: both outcomes occur often.
    assert n_checked > 1500 and n_inside > 200 and n_outside > 600


def cdd_projection(contacts: list[Contact], mass: float, g: np.ndarray, k: int, region) -> np.ndarray:
    """Exact projection by double description: vertices of the lifted polyhedron in (lam, x), projected."""
    weight = mass * np.linalg.norm(g)
    lin = linearise(contacts, weight, k, planar=False)
    ghat = g / np.linalg.norm(g)
    u, v = region.basis
    nl = lin.gens.shape[1]
    # Equalities: sum e lam = -ghat - sum o;  sum r x e lam + x (u x ghat) + y (v x ghat) = -sum r x o.
    A = np.zeros((6, nl + 2))
    for col, (e, i) in enumerate(zip(lin.gens.T, lin.owner, strict=True)):
        A[:3, col] = e
        A[3:, col] = np.cross(contacts[i].position, e)
    A[3:, nl], A[3:, nl + 1] = np.cross(u, ghat), np.cross(v, ghat)
    b_moment = -sum(np.cross(c.position, o) for c, o in zip(contacts, lin.offsets, strict=True))
    b = np.r_[-ghat - lin.offsets.sum(0), b_moment]
    rows = [np.r_[b[i], -A[i]] for i in range(6)]  # b - A z >= 0 (equalities via lin_set)
    for j in range(nl):
        rows.append(np.r_[0.0, np.eye(nl + 2)[j]])  # lam_j >= 0
    centre = np.array([c.position for c in contacts]).mean(0) @ region.basis.T
    for j, s in ((nl, 1), (nl, -1), (nl + 1, 1), (nl + 1, -1)):  # the same clip box as the region
        rows.append(np.r_[20.0 + s * centre[j - nl], -s * np.eye(nl + 2)[j]])
    for i, bd in lin.bounds:
        rows.append(np.r_[bd, -(lin.owner == i).astype(float), 0.0, 0.0])
    mat = cdd.matrix_from_array(np.array(rows), rep_type=cdd.RepType.INEQUALITY, lin_set=range(6))
    gens = np.array(cdd.copy_generators(cdd.polyhedron_from_matrix(mat)).array)
    if len(gens) == 0:
        return np.zeros((0, 2))
    pts = gens[gens[:, 0] > 0.5][:, -2:]
    return pts


@pytest.mark.parametrize("seed", range(0, 48, 3))
def test_polygon_equals_exact_polyhedral_projection(seed):
    contacts, mass, g, family = random_stance(seed)
    if len(contacts) > 3:
        contacts = contacts[:3]
    region = support_region(contacts, mass, g, cone_edges=4)
    pts = cdd_projection(contacts, mass, g, 4, region)
    if region.is_empty:
        assert len(pts) == 0, f"seed {seed}: cdd finds a non-empty projection"
        return
    # Every projected vertex lies in the region, and every region vertex is near the projection's hull.
    assert np.all(region.margin(pts) > -1e-7), f"seed {seed} ({family})"
    d = np.linalg.norm(region.vertices[:, None, :] - pts[None, :, :], axis=2).min(axis=1)
    assert d.max() < 1e-6, f"seed {seed} ({family}): region vertex {d.max():.2g} m from every cdd vertex"


def socp_feasible(contacts: list[Contact], mass: float, g: np.ndarray, com: np.ndarray) -> bool:
    """Per-point oracle with exact cones (B3) written with the projector (I - n n^T), in newtons."""
    f = cp.Variable((len(contacts), 3))
    cons = [cp.sum(f, axis=0) + mass * g == 0]
    moment = sum(cp.hstack([c.p[1] * f[i, 2] - c.p[2] * f[i, 1], c.p[2] * f[i, 0] - c.p[0] * f[i, 2],
                            c.p[0] * f[i, 1] - c.p[1] * f[i, 0]]) for i, c in enumerate(contacts))
    cons.append(moment + np.cross(com, mass * g) == 0)
    for i, c in enumerate(contacts):
        n = c.n
        proj = np.eye(3) - np.outer(n, n)
        if c.kind == "grasp":
            cons.append(cp.norm(f[i]) <= c.max_force)
        else:
            extra = c.max_force if c.kind == "adhesion" else 0.0
            cons.append(cp.norm(proj @ f[i]) <= c.friction * (n @ f[i] + extra))
    prob = cp.Problem(cp.Minimize(0), cons)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        prob.solve(solver="CLARABEL")
    return prob.status in ("optimal", "optimal_inaccurate")


EXACT_SEEDS = [0, 1, 2, 3, 5, 12]


@pytest.mark.parametrize("seed", EXACT_SEEDS)
def test_exact_region_against_per_point_socp(seed):
    contacts, mass, g, family = random_stance(seed)
    region = support_region(contacts, mass, g, exact=True)
    rng = np.random.default_rng(seed)
    up = -np.cross(region.basis[0], region.basis[1])
    if region.is_empty:
        centre = np.array([c.position for c in contacts]).mean(0)
        assert not socp_feasible(contacts, mass, g, centre)
        return
    V = region.vertices
    c0 = V.mean(axis=0)
    # Inner polygon: its vertices (pulled 1e-7 m inwards) and random interior points are feasible.
    inner = [v + 1e-7 * (c0 - v) / max(np.linalg.norm(c0 - v), 1e-12) for v in V[:: max(1, len(V) // 8)]]
    w = rng.dirichlet(np.ones(len(V)), size=4) if len(V) >= 3 else np.zeros((0, len(V)))
    inner += list(w @ V)
    for x in inner:
        assert socp_feasible(contacts, mass, g, x @ region.basis + 0.3 * up), f"seed {seed}: {x} infeasible"
    # Outer bound: beyond any edge by more than the stated tolerance -> infeasible.
    for a, b, c in region.halfplanes[:: max(1, len(region.halfplanes) // 8)]:
        n = np.array([a, b])
        on = V[np.argmin(np.abs(V @ n - c))]
        x = on + (region.tol + 1e-6) * n
        assert not socp_feasible(contacts, mass, g, x @ region.basis), f"seed {seed}: {x} feasible outside"


@pytest.mark.parametrize("seed", [0, 3, 8])
def test_linearised_regions_inside_exact_and_converging(seed):
    contacts, mass, g, family = random_stance(seed)
    exact = support_region(contacts, mass, g, exact=True)
    if exact.is_empty or not exact.is_bounded:
        pytest.skip("needs a bounded non-empty stance")  # pragma: no cover - seeds chosen to avoid it
    areas = []
    for k in (4, 8, 16, 32):
        lin = support_region(contacts, mass, g, cone_edges=k)
        if lin.is_empty:
            areas.append(0.0)
            continue
        H = exact.halfplanes
        slack = lin.vertices @ H[:, :2].T - H[:, 2]
        assert slack.max() <= exact.tol + 1e-7, f"k={k}: linearised vertex outside the exact region"
        areas.append(lin.area)
    assert areas == sorted(areas), f"areas {areas} not increasing with k (nested pyramids)"
    gaps = [exact.area - a for a in areas]
    assert gaps[-1] < 0.05 * exact.area and gaps[-1] < gaps[0] / 4, f"no convergence: {gaps}"


@pytest.mark.parametrize("seed", range(0, 40, 5))
def test_shadow_vertex_equals_iterative_projection(seed, monkeypatch):
    """The tableau shadow-vertex polygon and the HiGHS iterative projection (its fallback) are the same set."""
    from climb_ompl.equilibrium import region as region_module
    from climb_ompl.equilibrium._simplex import SimplexError

    contacts, mass, g, family = random_stance(seed)
    k = 4 if seed % 2 else 8
    shadow = support_region(contacts, mass, g, cone_edges=k)

    def stall(*args, **kwargs):
        raise SimplexError("forced")

    monkeypatch.setattr(region_module, "_lp_projection", stall)
    monkeypatch.setattr(region_module, "_compiled_region", lambda *a, **kw: None)  # as if its simplex had stalled
    highs = support_region(contacts, mass, g, cone_edges=k)
    assert shadow.is_empty == highs.is_empty, f"seed {seed} ({family})"
    if shadow.is_empty:
        return
    assert highs.n_solves > 1 and shadow.n_solves == 1
    assert np.all(np.abs(highs.margin(shadow.vertices @ shadow.basis)) < 1e-7), f"seed {seed} ({family})"
    assert np.all(np.abs(shadow.margin(highs.vertices @ highs.basis)) < 1e-7), f"seed {seed} ({family})"
