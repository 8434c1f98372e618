"""Torque-limited feasible regions (Orsolino et al. (2020)) against a per-point LP oracle.

The oracle is scipy's ``linprog`` on the raw equations: cone-edge weights ``lam >= 0`` whose forces
``f_i = m|g| (sum of contact i's edges * lam)`` balance the weight (force and moment about the world
origin) at the CoM, with every limited joint's ``|g(q) - sum_i J_i^T f_i| <= tau_max``.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import linprog

from climb_ompl.equilibrium import (
    CONE_EDGES,
    Contact,
    TorqueChecker,
    feasible_region,
    support_region,
)
from climb_ompl.equilibrium._contacts import linearise
from climb_ompl.errors import EquilibriumError
from climb_ompl.model.terrain import generate_wall

BAND = 1e-6  # points nearer the boundary than this are not compared
G = np.array([0.0, 0.0, -9.81])


def posture(seed: int, holds: int = 3, planar: bool = False):
    """A stance, a random 'posture' (Jacobians of a floating base plus 3 joints per limb) and limits."""
    rng = np.random.default_rng(seed)
    if planar:
        xs = np.sort(rng.uniform(-0.4, 0.4, size=holds))
        contacts = [Contact((x, 0.0, rng.uniform(-0.05, 0.05)), (rng.normal(scale=0.4), 0.0, 1.0),
                            float(rng.uniform(0.4, 1.0))) for x in xs]
        g = G
    else:
        w = generate_wall(seed, width=1.2, height=1.2)
        P = w.positions
        centre = P[rng.integers(len(P))]
        pick = rng.choice(np.argsort(np.linalg.norm(P - centre, axis=1))[: 3 * holds], size=holds, replace=False)
        contacts = [Contact.from_hold(w.holds[i]) for i in pick]
        g = np.asarray(w.g, dtype=float)
    mass = 7.0
    nq = 3 + 3 * holds
    J = np.zeros((holds, 3, nq))
    for i in range(holds):
        J[i, :, :3] = np.eye(3)  # the base's translation
        J[i, :, 3 + 3 * i:6 + 3 * i] = rng.normal(scale=0.15, size=(3, 3))  # the limb's own joints
    gt = np.r_[-mass * g, rng.normal(scale=0.5, size=nq - 3)]
    act = np.r_[np.zeros(3, bool), np.ones(nq - 3, bool)]
    lim = np.r_[np.full(3, np.inf), np.full(nq - 3, float(rng.uniform(2.0, 5.0)))]
    return contacts, mass, g, J, gt, lim, act


def lp_oracle(contacts, mass, g, J, gt, lim, act, k, planar=False):
    """``com -> bool``: per-point feasibility LP on the raw equations, newtons."""
    W = mass * np.linalg.norm(g)
    lin = linearise(contacts, W, k, planar)
    E = lin.gens * W  # (3, n) force of a unit weight on each edge, newtons
    P = np.array([contacts[i].position for i in lin.owner])
    A_eq = np.vstack([E, np.cross(P, E.T).T])
    lt = act & np.isfinite(lim)
    Tq = np.stack([J[o][:, lt].T @ E[:, col] for col, o in enumerate(lin.owner)], axis=1)  # joint torque per lam
    A_ub = np.vstack([-Tq, Tq])  # g - Tq lam <= lim  and  -(g - Tq lam) <= lim
    b_ub = np.r_[lim[lt] - gt[lt], lim[lt] + gt[lt]]
    rows = [0, 2, 4] if planar else list(range(6))

    def feasible(com: np.ndarray) -> bool:
        b_eq = -np.r_[mass * g, np.cross(com, mass * g)]
        res = linprog(np.zeros(A_eq.shape[1]), A_ub=A_ub, b_ub=b_ub, A_eq=A_eq[rows], b_eq=b_eq[rows],
                      bounds=(0, None), method="highs")
        return res.status == 0

    return feasible


def probes(region, support, rng, n_random=40):
    """World points: random points around the support region and probes 1e-5 m across each edge."""
    V = support.vertices if len(support.vertices) else region.vertices
    lo, hi = V.min(axis=0) - 0.05, V.max(axis=0) + 0.05
    X = [rng.uniform(lo, hi, size=(n_random, V.shape[1]))]
    if not region.is_empty and len(region.vertices) >= 3:
        Rv = region.vertices
        mids = 0.5 * (Rv + np.roll(Rv, -1, axis=0))
        for a, b, c in region.halfplanes:
            on = mids[np.abs(mids @ np.array([a, b]) - c) < 1e-9]
            X += [on + 1e-5 * np.array([a, b]), on - 1e-5 * np.array([a, b])]
    return np.vstack(X) @ region.basis


@pytest.mark.parametrize("seed", range(10))
def test_feasible_region_agrees_with_per_point_lp(seed):
    contacts, mass, g, J, gt, lim, act = posture(seed)
    region = feasible_region(contacts, mass, g, J, gt, lim, act)
    support = support_region(contacts, mass, g)
    oracle = lp_oracle(contacts, mass, g, J, gt, lim, act, CONE_EDGES)
    rng = np.random.default_rng(seed)
    pts = probes(region, support, rng)
    inside, margin = region.contains(pts), region.margin(pts)
    checked = 0
    for p, ins, m in zip(pts, inside, margin, strict=True):
        if abs(m) < BAND:
            continue
        assert oracle(p) == ins, f"seed {seed}: point {p} margin {m:.3g} m, region says {ins}"
        checked += 1
    assert checked >= 40
    # Inside the support region of the same cones.
    if not region.is_empty:
        assert np.all(support.margin(region.vertices @ region.basis) > -1e-7)


def test_feasible_region_is_not_vacuous_and_matches_the_torque_checker():
    """Over the seeds, torque limits cut regions strictly inside non-empty support regions; the per-state
    TorqueChecker (same cones) accepts exactly the CoM positions inside the feasible region."""
    cut = 0
    for seed in range(10):
        contacts, mass, g, J, gt, lim, act = posture(seed)
        region = feasible_region(contacts, mass, g, J, gt, lim, act)
        support = support_region(contacts, mass, g)
        if support.is_empty:
            continue
        if region.is_empty or region.area < support.area - 1e-6:
            cut += 1
        checker = TorqueChecker(contacts, mass, g, lim, act, region=support)
        rng = np.random.default_rng(100 + seed)
        for p in probes(region, support, rng, n_random=15):
            m = region.margin(p)
            if abs(m) >= BAND:
                assert checker.check(p, J, gt).feasible == (m > 0), f"seed {seed}: {p}"
    assert cut >= 3


def test_feasible_region_planar_and_unlimited():
    contacts, mass, g, J, gt, lim, act = posture(3, planar=True)
    J[:, 1, :] = 0.0  # forces in the x-z plane
    region = feasible_region(contacts, mass, g, J, gt, lim, act, planar=True)
    oracle = lp_oracle(contacts, mass, g, J, gt, lim, act, CONE_EDGES, planar=True)
    for x in np.linspace(-0.6, 0.6, 41):
        p = np.array([x, 0.0, 0.3])
        if abs(region.margin(p)) >= BAND:
            assert oracle(p) == region.contains(p), f"x = {x}"
    # Without limits the feasible region is the support region.
    free = feasible_region(contacts, mass, g, J, gt, np.full_like(lim, np.inf), act, planar=True)
    assert free.interval == pytest.approx(support_region(contacts, mass, g, planar=True).interval, abs=1e-9)


def test_feasible_region_bad_input_and_unloaded_joint():
    contacts, mass, g, J, gt, lim, act = posture(0)
    with pytest.raises(EquilibriumError, match="jacobians"):
        feasible_region(contacts, mass, g, J[:2], gt, lim, act)
    with pytest.raises(EquilibriumError, match="cone_edges"):
        feasible_region(contacts, mass, g, J, gt, lim, act, cone_edges=2)
    J2 = np.concatenate([J, np.zeros((3, 3, 1))], axis=2)  # a joint no contact loads, over its limit
    region = feasible_region(contacts, mass, g, J2, np.r_[gt, 9.0], np.r_[lim, 5.0], np.r_[act, True])
    assert region.is_empty


def test_playback_feasible_region_of_a_lemur_climb_matches_the_torque_checker():
    """The region drawn in the playback (``viz._plans.feasible_region_of``) at each step's first posture of
    a LEMUR climb: inside the support region, and the per-state TorqueChecker at that posture accepts a CoM
    exactly when the region contains it."""
    from test_viz import make_climb_plan

    from climb_ompl.model.robot import RobotModel
    from climb_ompl.viz._plans import feasible_region_of, parse_climb_steps, terrain_from_plan

    plan = make_climb_plan()
    robot = RobotModel.load("lemur")
    terrain = terrain_from_plan(plan)
    rng = np.random.default_rng(0)
    for st in parse_climb_steps(plan, robot.nq):
        q = st.waypoints[0]
        region = feasible_region_of(robot, terrain, st.stance, q)
        limbs = sorted(st.stance)
        contacts = [Contact.from_hold(terrain.hold(st.stance[lb])) for lb in limbs]
        support = support_region(contacts, robot.mass, terrain.g)
        assert region is not None and not region.is_empty
        assert region.area < support.area
        assert np.all(support.margin(region.vertices @ region.basis) > -1e-7)
        J = robot.hand_jacobians(q)[[[lb.name for lb in robot.limbs].index(lb) for lb in limbs]]
        gt = robot.gravity_torques(q, terrain.g)
        checker = TorqueChecker(contacts, robot.mass, terrain.g, robot.torque_limits, robot.actuated, region=support)
        for p in probes(region, support, rng, n_random=20):
            m = region.margin(p)
            if abs(m) >= BAND:
                assert checker.check(p, J, gt).feasible == (m > 0)
