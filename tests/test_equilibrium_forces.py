"""Contact forces and torque feasibility: balance, cones, closed forms, fast vs exact."""

from __future__ import annotations

import numpy as np
import pytest

from climb_ompl.equilibrium import Contact, TorqueChecker, contact_forces, support_region, torque_feasible
from climb_ompl.errors import EquilibriumError
from climb_ompl.model.terrain import generate_wall

G = np.array([0.0, 0.0, -9.81])
FLOOR = (0.0, 0.0, 1.0)
TRI = [(0.0, 0.0, 0.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)]


def balance_residual(contacts, mass, g, com, F) -> float:
    """Independent check of (B1)-(B2), newtons and newton-metres."""
    P = np.array([c.position for c in contacts])
    force = F.sum(axis=0) + mass * g
    moment = np.cross(P, F).sum(axis=0) + np.cross(com, mass * g)
    return float(max(np.abs(force).max(), np.abs(moment).max()))


def in_cone(c: Contact, f: np.ndarray, tol: float = 1e-7) -> bool:
    n = c.n
    if c.kind == "grasp":
        return np.linalg.norm(f) <= c.max_force * (1 + tol)
    fn = n @ f + (c.max_force if c.kind == "adhesion" else 0.0)
    return np.linalg.norm(f - (n @ f) * n) <= c.friction * fn + tol * np.linalg.norm(f) + 1e-9


def wall_stance(seed: int):
    w = generate_wall(seed, width=1.2, height=1.2)
    rng = np.random.default_rng(seed)
    P = w.positions
    centre = P[rng.integers(len(P))]
    pick = np.argsort(np.linalg.norm(P - centre, axis=1))[[0, 2, 4]]
    return [Contact.from_hold(w.holds[i]) for i in pick], 7.0, w.g


@pytest.mark.parametrize("seed", range(8))
def test_contact_forces_balance_and_lie_in_cones(seed):
    contacts, mass, g = wall_stance(seed)
    region = support_region(contacts, mass, g, cone_edges=8)
    assert not region.is_empty  # the generator's holds lean up 55-80 degrees: every such stance holds a CoM
    x = region.vertices.mean(axis=0)
    com = x @ region.basis + 0.2 * np.array([0, 0, 1.0])
    res = contact_forces(contacts, mass, g, com)
    assert res is not None and res.forces.shape == (3, 3)
    assert balance_residual(contacts, mass, g, com, res.forces) <= 1e-8
    assert all(in_cone(c, f) for c, f in zip(contacts, res.forces, strict=True))
    assert 0 <= res.ratio <= 1 + 1e-7
    # Most robust: no worse than the forces any admissible solution gives (here: torque_feasible's).
    other = torque_feasible(contacts, mass, g, com, np.zeros((3, 3, 1)), np.zeros(1), np.ones(1), np.zeros(1, bool))
    assert other.feasible
    from climb_ompl.equilibrium.forces import usage
    assert res.ratio <= usage(contacts, other.forces).max() + 2e-4


def test_contact_forces_closed_forms():
    # One hold under the CoM: a purely normal force, ratio 0.
    r = contact_forces([Contact((0.2, 0.1, 0), FLOOR, 0.5)], 3.0, G, (0.2, 0.1, 0.8))
    assert r.forces[0] == pytest.approx([0, 0, 3 * 9.81], abs=1e-8) and r.ratio == pytest.approx(0, abs=1e-6)
    # Tilted gravity on a floor triangle: the best is forces parallel to gravity, ratio tan(t)/mu.
    t = np.radians(15)
    g = 9.81 * np.array([np.sin(t), 0, -np.cos(t)])
    tri = [Contact(p, FLOOR, 0.6) for p in TRI]
    r = contact_forces(tri, 2.0, g, (0.3, 0.3, 0.0))
    assert r.ratio == pytest.approx(np.tan(t) / 0.6, abs=2e-4)
    assert balance_residual(tri, 2.0, g, np.array([0.3, 0.3, 0.0]), r.forces) <= 1e-8
    # Outside the region: None.
    assert contact_forces(tri, 2.0, G, (0.8, 0.8, 0.0)) is None
    # A ceiling's holds (normals down, friction 0.8) only push down: nothing holds a weight anywhere (None, an empty
    # region), while the same holds turned up carry it above their triangle.
    ceiling = [Contact(p, (0.0, 0.0, -1.0), 0.8) for p in TRI]
    assert support_region(ceiling, 2.0, G).is_empty
    assert contact_forces(ceiling, 2.0, G, (0.3, 0.3, -0.5)) is None
    assert contact_forces([Contact(p, FLOOR, 0.8) for p in TRI], 2.0, G, (0.3, 0.3, -0.5)) is not None
    # Planar: two holds on a floor, CoM at x = 0.1 between -0.3 and 0.3: vertical forces 1/3 and 2/3 of W.
    two = [Contact((-0.3, 0, 0), FLOOR, 0.4), Contact((0.3, 0, 0), FLOOR, 0.4)]
    r = contact_forces(two, 3.0, G, (0.1, 0.0, 1.0), planar=True)
    W = 3 * 9.81
    assert r.forces[:, 2] == pytest.approx([W / 3, 2 * W / 3], abs=1e-8) and np.all(np.abs(r.forces[:, 1]) <= 1e-12)


def cartesian_legs(k: int) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Jacobians of k massless Cartesian legs: joint 3i+a moves hand i along axis a (tau = -f)."""
    J = np.zeros((k, 3, 3 * k))
    for i in range(k):
        J[i, :, 3 * i: 3 * i + 3] = np.eye(3)
    return J, np.zeros(3 * k), np.ones(3 * k, dtype=bool)


@pytest.mark.parametrize("bary", [(1 / 3, 1 / 3, 1 / 3), (0.6, 0.3, 0.1), (0.2, 0.2, 0.6), (0.05, 0.9, 0.05)])
def test_torque_limits_closed_form_floor_triangle(bary):
    # On a flat floor the vertical forces are fixed by the CoM (barycentric weights times W) and the
    # z joints carry exactly them: feasible iff the largest share is within the limit.
    tri = [Contact(p, FLOOR, 0.5) for p in TRI]
    mass = 2.0
    W = mass * 9.81
    com = np.array(bary) @ np.array(TRI) + np.array([0, 0, 0.5])
    J, gt, act = cartesian_legs(3)
    need = max(bary) * W
    checker = TorqueChecker(tri, mass, G, np.full(9, need * 1.01), act, cone_edges=8)
    for scale, expected in ((1.01, True), (0.99, False)):
        lim = np.full(9, need * scale)
        res = torque_feasible(tri, mass, G, com, J, gt, lim, act)
        assert res.feasible == expected, (bary, scale)
        # the smallest largest torque ratio: the leg under the heaviest share carries it (closed form)
        assert res.utilisation == pytest.approx(1.0 / scale, rel=1e-4)
        if sorted(bary)[-1] > sorted(bary)[-2] + 0.05:  # the z joint of that leg is the one named
            assert res.worst == 3 * int(np.argmax(bary)) + 2
        fast = TorqueChecker(tri, mass, G, lim, act, cone_edges=8).check(com, J, gt)
        assert fast.feasible == expected
        if expected:
            assert np.abs(res.torques).max() <= need * scale * (1 + 1e-6)
            assert np.allclose(res.torques, gt - np.einsum("kiq,ki->q", J, res.forces))
            assert balance_residual(tri, mass, G, com, res.forces) <= 1e-8
            assert balance_residual(tri, mass, G, com, fast.forces) <= 1e-7
            assert np.abs(fast.torques).max() <= need * scale * (1 + 1e-6)
    assert checker(com, J, gt) is True
    out = checker.check(com + np.array([2.0, 0, 0]), J, gt)
    assert not out.feasible and out.status == "outside_support_region"


def test_torque_checker_is_conservative_against_exact_on_random_states():
    rng = np.random.default_rng(7)
    agree = total = 0
    for seed in range(12):
        contacts, mass, g = wall_stance(seed)
        region = support_region(contacts, mass, g, cone_edges=4)
        if region.is_empty:
            continue
        nq = 8
        act = np.r_[np.zeros(3, bool), np.ones(5, bool)]
        lim = np.r_[np.full(3, np.inf), np.full(5, 6.0)]
        checker = TorqueChecker(contacts, mass, g, lim, act, cone_edges=4)
        for _ in range(6):
            J = rng.normal(scale=0.3, size=(3, 3, nq))
            J[:, :, :3] = np.eye(3)  # a floating base's translation
            gt = np.r_[-mass * g, rng.normal(scale=2.0, size=5)]
            w = rng.dirichlet(np.ones(len(region.vertices))) if len(region.vertices) > 2 else None
            x = w @ region.vertices if w is not None else region.vertices.mean(0)
            com = x @ region.basis
            fast = checker.check(com, J, gt)
            exact = torque_feasible(contacts, mass, g, com, J, gt, lim, act)
            if fast.feasible:  # inscribed cones: fast feasible => exact feasible
                assert exact.feasible, f"seed {seed}: LP feasible but SOCP not"
                assert np.all(np.abs(fast.torques[act]) <= lim[act] * (1 + 1e-6))
                assert balance_residual(contacts, mass, g, com, fast.forces) <= 1e-6
            total += 1
            agree += int(fast.feasible == exact.feasible)
    assert total > 30 and agree / total > 0.8


def test_unloaded_joint_prefilter_and_bad_arrays():
    tri = [Contact(p, FLOOR, 0.5) for p in TRI]
    J, gt, act = cartesian_legs(3)
    J = np.concatenate([J, np.zeros((3, 3, 1))], axis=2)  # a free-limb joint no contact reaches
    gt, act = np.r_[gt, 9.0], np.r_[act, True]
    lim = np.full(10, 100.0)
    lim[-1] = 5.0
    res = TorqueChecker(tri, 1.0, G, lim, act).check((0.3, 0.3, 0.0), J, gt)
    assert not res.feasible and res.status == "torque_limit"
    assert not torque_feasible(tri, 1.0, G, (0.3, 0.3, 0.0), J, gt, lim, act).feasible
    with pytest.raises(EquilibriumError, match="jacobians"):
        torque_feasible(tri, 1.0, G, (0.3, 0.3, 0.0), J[:2], gt, lim, act)
    with pytest.raises(EquilibriumError, match="torque_limits"):
        torque_feasible(tri, 1.0, G, (0.3, 0.3, 0.0), J, gt, -lim, act)
    with pytest.raises(EquilibriumError, match="com"):
        contact_forces(tri, 1.0, G, (np.nan, 0, 0))


def test_torque_checker_uses_the_support_regions_cone_model():
    from climb_ompl.equilibrium import CONE_EDGES

    tri = [Contact(p, FLOOR, 0.5) for p in TRI]
    J, gt, act = cartesian_legs(3)
    lim = np.full(len(act), 100.0)
    checker = TorqueChecker(tri, 1.0, G, lim, act)
    assert checker.cone_edges == CONE_EDGES == support_region(tri, 1.0, G).cone_edges
    assert checker.region.cone_edges == CONE_EDGES
    with pytest.raises(EquilibriumError, match="cone_edges"):
        TorqueChecker(tri, 1.0, G, lim, act, cone_edges=4, region=support_region(tri, 1.0, G, cone_edges=8))
    # an exact region carries no cone model: any cone_edges may go with it
    TorqueChecker(tri, 1.0, G, lim, act, cone_edges=4, region=support_region(tri, 1.0, G, exact=True))
