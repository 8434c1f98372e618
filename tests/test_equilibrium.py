"""Equilibrium core: closed-form cases, API behaviour and bad input (oracles in test_equilibrium_oracles.py)."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from climb_ompl.equilibrium import Contact, RegionCache, SupportRegion, support_region
from climb_ompl.equilibrium._contacts import linearise
from climb_ompl.errors import ClimbError, EquilibriumError, TerrainError
from climb_ompl.model.terrain import Hold, generate_wall

G = (0.0, 0.0, -9.81)
FLOOR = (0.0, 0.0, 1.0)


def floor_triangle(mu: float = 0.5) -> list[Contact]:
    return [Contact((0, 0, 0), FLOOR, mu), Contact((1, 0, 0), FLOOR, mu), Contact((0, 1, 0), FLOOR, mu)]


def same_polygon(A: np.ndarray, B: np.ndarray, tol: float) -> bool:
    """Hausdorff distance between two vertex sets below ``tol``."""
    d = np.linalg.norm(A[:, None, :] - B[None, :, :], axis=2)
    return bool(d.min(axis=1).max() < tol and d.min(axis=0).max() < tol)


# ---- closed forms -------------------------------------------------------------------------------------
def test_single_hold_on_flat_floor_is_a_point():
    r = support_region([Contact((0.3, 0.2, 0.0), FLOOR, 0.5)], 2.0, G)
    assert not r.is_empty and r.is_bounded
    assert r.vertices.shape == (1, 2) and np.allclose(r.vertices[0], [0.3, 0.2], atol=1e-9)
    assert r.contains([0.3, 0.2, 0.7])  # any height above the hold
    assert not r.contains([0.31, 0.2, 0.7])
    assert r.margin([0.31, 0.2, 0.0]) == pytest.approx(-0.01, abs=1e-9)


def test_floor_triangle_is_the_triangle_of_the_holds():
    r = support_region(floor_triangle(), 5.0, G)
    assert same_polygon(r.vertices, np.array([[0, 0], [1, 0], [0, 1]]), 1e-8)
    assert r.area == pytest.approx(0.5, abs=1e-8)
    pts = np.array([[0.2, 0.2, 3.0], [0.6, 0.6, 0.0], [-0.1, 0.5, 0.0]])
    assert r.contains(pts).tolist() == [True, False, False]
    # Margin: inside = distance to the nearest edge, outside = minus the Euclidean distance.
    assert r.margin(pts) == pytest.approx([0.2, -np.sqrt(2) * 0.1, -0.1], abs=1e-9)


@pytest.mark.heavy
def test_outside_by_more_than_agrees_with_the_margin():
    """The halfplane shortcut against the margin itself (the exact distance to the polygon), on the floor triangle
    (whose corners make the distance outside exceed every halfplane's violation) and a wall region, for points
    inside, near and far, and thresholds of both signs."""
    regions = [support_region(floor_triangle(), 5.0, G),
               support_region([Contact(h.position, h.normal, h.friction) for h in generate_wall(seed=3).holds[:3]],
                              20.0, G)]
    rng = np.random.default_rng(0)
    for r in regions:
        assert not r.is_empty
        centre = r.basis.T @ r.vertices.mean(axis=0)
        for _ in range(3000):
            com = centre + rng.normal(0.0, 0.3, 3)
            for d in (-0.02, 0.0, 0.05, 0.2):
                assert r.outside_by_more_than(com, d) == bool(r.margin(com) < -d)


@pytest.mark.parametrize("tilt_deg, feasible", [(10.0, True), (20.0, True), (30.0, False)])
def test_tilted_gravity_on_a_floor_projects_the_triangle_along_gravity(tilt_deg, feasible):
    # mu = 0.5 is a friction angle of 26.57 deg: past it the holds slide.
    t = np.radians(tilt_deg)
    g = 9.81 * np.array([np.sin(t), 0.0, -np.cos(t)])
    r = support_region(floor_triangle(0.5), 5.0, g, cone_edges=64)
    if not feasible:
        assert r.is_empty and not r.contains([0.2, 0.2, 0.0])
        return
    expected = np.array([c.position for c in floor_triangle()]) @ r.basis.T
    assert same_polygon(r.vertices, expected, 1e-7)
    assert abs(r.basis @ g).max() < 1e-12  # the basis is perpendicular to gravity


def cross2(a: np.ndarray, b: np.ndarray) -> float:
    return float(a[0] * b[1] - a[1] * b[0])


def planar_pair_enumeration(contacts: list[Contact], g: np.ndarray) -> tuple[float, float] | None:
    """Interval of CoM x by enumerating pairs of cone edges (basic solutions
    of Bretl, Latombe & Rock (2003), eq. (1))."""
    weight = -np.array([g[0], g[2]])  # force the holds must supply (mass 1)
    edges = []
    for c in contacts:
        n = np.array([c.normal[0], c.normal[2]])
        t = np.array([-n[1], n[0]])
        for s in (1, -1):
            edges.append((np.array([c.position[0], c.position[2]]), n + s * c.friction * t))
    xs = []
    gz = np.array([g[0], g[2]])
    u = np.array([-gz[1], gz[0]]) / np.linalg.norm(gz)
    u = u if u[0] >= 0 else -u
    for (ra, ea), (rb, eb) in itertools.combinations_with_replacement(edges, 2):
        M = np.column_stack([ea, eb])
        if abs(np.linalg.det(M)) < 1e-12:
            if abs(cross2(ea, weight)) < 1e-12 and ea @ weight > 0:  # one edge alone
                lam = np.array([np.linalg.norm(weight) / np.linalg.norm(ea), 0.0])
            else:
                continue
        else:
            lam = np.linalg.solve(M, weight)
        if np.any(lam < -1e-12):
            continue
        # Moment balance about the origin: sum r x f + c x m g = 0 with c = x u.
        mom = lam[0] * cross2(ra, ea) + lam[1] * cross2(rb, eb)
        xs.append(-mom / cross2(u, gz))
    return (min(xs), max(xs)) if xs else None


@pytest.mark.parametrize("case", range(6))
def test_planar_interval_matches_pair_enumeration_and_symmetric_holds(case):
    rng = np.random.default_rng(case)
    if case == 0:  # two symmetric holds on a floor: [-a, a]
        cs = [Contact((-0.3, 0, 0), FLOOR, 0.4), Contact((0.3, 0, 0), FLOOR, 0.4)]
    else:  # Bretl, Latombe & Rock (2003), Fig. 3 style: two holds on a vertical wall, normals leaning up
        cs = []
        for _ in range(2):
            a = rng.uniform(-1.2, 1.2)
            cs.append(Contact((rng.uniform(-0.5, 0.5), 0, rng.uniform(-0.5, 0.5)), (np.sin(a), 0, np.cos(a)),
                              rng.uniform(0.3, 1.0)))
    r = support_region(cs, 1.0, G, planar=True)
    ref = planar_pair_enumeration(cs, np.array(G))
    if ref is None:
        assert r.is_empty
        return
    lo, hi = r.interval
    if case == 0:
        assert (lo, hi) == pytest.approx((-0.3, 0.3), abs=1e-9)
    if r.is_bounded:
        assert (lo, hi) == pytest.approx(ref, abs=1e-7)
    assert r.contains([0.5 * (ref[0] + ref[1]), 0.0, 3.0])


def test_planar_one_side_unbounded_and_empty():
    # A hold facing right and one facing up-left: the CoM can move arbitrarily far to the right?  Check
    # unboundedness against the LP-free pair enumeration of a large box instead: a side-pull pair
    # pinching a vertical pole holds any CoM x (two opposed normals, friction > 0).
    cs = [Contact((0, 0, 0), (1, 0, 0), 0.8), Contact((0.05, 0, 0), (-1, 0, 0), 0.8)]
    r = support_region(cs, 1.0, G, planar=True)
    assert not r.is_bounded and r.interval == (-np.inf, np.inf)
    assert r.contains([[100.0, 0, 0], [-100.0, 0, 0]]).all()
    # A cantilever: a ceiling pressing down at x = 0 and a floor pushing up at x = 0.2 below it.  Moments
    # about the first hold: 0.2 f_up = x W with f_up - f_down = W, f_down >= 0, so x in [0.2, inf).
    cs = [Contact((0, 0, 0), (0, 0, -1), 0.1), Contact((0.2, 0, -0.05), (0, 0, 1), 0.1)]
    r = support_region(cs, 1.0, G, planar=True)
    assert not r.is_bounded and r.interval[0] == pytest.approx(0.2, abs=1e-9) and r.interval[1] == np.inf
    assert r.contains([[0.21, 0, 0], [15.0, 0, 0]]).all() and not r.contains([0.19, 0, 0])
    # Frictionless holds facing down: nothing holds the robot up.
    cs = [Contact((0, 0, 1), (0, 0, -1), 0.0), Contact((1, 0, 1), (0.2, 0, -1), 0.0)]
    r = support_region(cs, 1.0, G, planar=True)
    assert r.is_empty and not r.contains([0.5, 0, 0]) and r.margin([0.5, 0, 0]) == -np.inf


def test_pinch_grip_is_an_unbounded_line_in_3d():
    # Two point contacts on the line y = 0, z = 1 exert no moment about it: the CoM must hang below
    # the line (y = 0), anywhere along it (squeezing harder balances any moment about y).
    cs = [Contact((0, 0, 1), (1, 0, 0), 0.8), Contact((0.05, 0, 1), (-1, 0, 0), 0.8)]
    r = support_region(cs, 1.0, G)
    assert not r.is_empty and not r.is_bounded and len(r.vertices) == 2
    assert r.contains([[5.0, 0.0, 0.0], [-4.0, 0.0, 2.0]]).all()
    assert not r.contains([0.0, 0.01, 0.0])
    # A third hold off the line makes it a 2-D region, still unbounded along x.
    r3 = support_region([*cs, Contact((0, 0.3, 0), (0, 0, 1), 0.8)], 1.0, G)
    assert not r3.is_bounded and r3.area > 0 and r3.contains([6.0, 0.1, 0.0])


def test_collinear_holds_give_a_segment():
    # Three frictionless floor holds on a line: the support region is the segment between the outer two.
    cs = [Contact((x, 0.5, 0), FLOOR, 0.0) for x in (0.0, 0.4, 1.0)]
    r = support_region(cs, 3.0, G)
    assert len(r.vertices) == 2 and same_polygon(r.vertices, np.array([[0, 0.5], [1, 0.5]]), 1e-8)
    assert r.contains([0.7, 0.5, 1.0]) and not r.contains([0.7, 0.51, 1.0]) and not r.contains([1.1, 0.5, 0])
    assert r.margin([0.7, 0.5, 0.0]) == pytest.approx(0.0, abs=1e-9)
    assert r.margin([1.3, 0.9, 0.0]) == pytest.approx(-0.5, abs=1e-9)
    assert r.shrink(0.01).is_empty


def test_grasp_and_adhesion_contacts():
    # A peg in a gripper above the CoM: any force up to max_force.
    grasp = [Contact((0, 0, 1), (0, 1, 0), 0.0, "grasp", max_force=30.0)]
    r = support_region(grasp, 2.0, G)
    assert len(r.vertices) == 1 and np.allclose(r.vertices[0], [0, 0])  # it cannot take a moment
    assert r.is_empty is False
    assert support_region(grasp, 4.0, G).is_empty  # 39 N > 30 N
    # Two suction feet on a ceiling (normals down): only the pull holds the robot.
    feet = [Contact((x, 0, 2), (0, 0, -1), 0.5, "adhesion", max_force=20.0) for x in (-0.2, 0.2)]
    r = support_region(feet, 2.0, G)  # 19.6 N of weight, 40 N of pull
    assert not r.is_empty and r.contains([0.0, 0.0, 1.5])
    # Moments about y: x W = 0.2 (f2 - f1), f1 + f2 = W, pulls f_i <= 20 N: |x| <= 0.2 (40 - W) / W.
    W = 2.0 * 9.81
    xs = r.vertices[:, 0]
    assert xs.min() == pytest.approx(-0.2 * (2 * 20.0 - W) / W, abs=1e-7)  # one foot pulls 20 N
    assert support_region(feet, 5.0, G).is_empty


def test_linearised_edges_lie_on_the_cone():
    c = Contact((0, 0, 0), (0.3, 0.5, 0.8), 0.7)
    lin = linearise([c], 1.0, 6, planar=False)
    n = c.n
    cosang = lin.gens.T @ n  # gens are unit vectors
    assert np.allclose(np.linalg.norm(lin.gens, axis=0), 1.0)
    assert np.allclose(np.arctan2(np.sqrt(1 - cosang**2), cosang), np.arctan(0.7))
    assert len({tuple(np.round(e, 9)) for e in lin.gens.T}) == 6


# ---- API behaviour -------------------------------------------------------------------------------------
def test_contains_and_margin_are_vectorised_and_agree():
    r = support_region(floor_triangle(), 3.0, G)
    rng = np.random.default_rng(0)
    P = rng.uniform(-0.5, 1.5, size=(2000, 3))
    inside = r.contains(P)
    m = r.margin(P)
    assert inside.shape == (2000,) and m.shape == (2000,)
    assert np.array_equal(inside, m >= -1e-9)
    assert [r.contains(p) for p in P[:50]] == inside[:50].tolist()
    assert isinstance(r.contains(P[0]), bool) and isinstance(r.margin(P[0]), float)
    # Margin is 1-Lipschitz: a point moved by d changes its margin by at most d.
    d = rng.normal(size=(2000, 3)) * 0.01
    assert np.all(np.abs(r.margin(P + d) - m) <= np.linalg.norm(d[:, :2], axis=1) + 1e-12)


@settings(derandomize=True, deadline=None, max_examples=40)
@given(d=st.floats(0.0, 0.4), x=st.floats(-0.5, 1.5), y=st.floats(-0.5, 1.5))
def test_shrink_equals_margin_threshold(d, x, y):
    r = support_region(floor_triangle(), 3.0, G)
    s = r.shrink(d)
    p = np.array([x, y, 0.0])
    m = r.margin(p)
    if abs(m - d) > 1e-9:
        assert s.contains(p) == (m > d)


def test_region_value_object_fields():
    r = support_region(floor_triangle(), 3.0, G, shrink=0.05)
    assert isinstance(r, SupportRegion)
    assert r.basis.shape == (2, 3) and np.allclose(r.basis @ r.basis.T, np.eye(2))
    assert r.halfplanes.shape[1] == 3 and np.allclose(np.linalg.norm(r.halfplanes[:, :2], axis=1), 1.0)
    V = r.vertices
    assert np.all(V @ r.halfplanes[:, :2].T <= r.halfplanes[:, 2] + 1e-9)
    assert r.area < 0.5


def test_cache_is_keyed_by_geometry():
    cache = RegionCache()
    w = generate_wall(3)
    holds = list(w.holds[:3])
    a = cache.get(holds, 7.0, w.g, cone_edges=4)
    b = cache.get([Contact.from_hold(h) for h in holds], 7.0, w.g, cone_edges=4)
    assert a is b and cache.hits == 1 and cache.misses == 1
    # Same ids on another wall: different geometry, a different entry.
    other = generate_wall(4)
    c = cache.get(list(other.holds[:3]), 7.0, other.g, cone_edges=4)
    assert c is not a and cache.misses == 2
    assert cache.get(holds, 7.5, w.g, cone_edges=4) is not a  # mass is part of the key
    assert cache.get(holds, 7.0, w.g, cone_edges=8) is not a  # options too


# ---- bad input -----------------------------------------------------------------------------------------
@pytest.mark.parametrize("kwargs, word", [
    (dict(normal=(0, 0, 0)), "normal"),
    (dict(normal=(np.nan, 0, 1)), "normal"),
    (dict(friction=-0.1), "friction"),
    (dict(position=(0, np.nan, 0)), "position"),
    (dict(kind="glue"), "kind"),
    (dict(kind="grasp"), "max_force"),
    (dict(kind="adhesion", max_force=-1.0), "max_force"),
])
def test_bad_contacts_are_named(kwargs, word):
    args = dict(position=(0, 0, 0), normal=(0, 0, 1), friction=0.5)
    args.update(kwargs)
    with pytest.raises(EquilibriumError, match=word):
        Contact(**args)


@pytest.mark.parametrize("mass, gravity, word", [
    (0.0, G, "mass"), (-1.0, G, "mass"), (np.nan, G, "mass"),
    (1.0, (0, 0, 0), "gravity"), (1.0, (0, np.inf, -9.8), "gravity"),
])
def test_bad_mass_and_gravity_are_named(mass, gravity, word):
    with pytest.raises(EquilibriumError, match=word) as exc:
        support_region(floor_triangle(), mass, gravity)
    assert isinstance(exc.value, ClimbError)


def test_other_bad_input():
    r = support_region(floor_triangle(), 1.0, G)
    with pytest.raises(EquilibriumError, match="com"):
        r.contains([np.nan, 0, 0])
    with pytest.raises(EquilibriumError, match="cone_edges"):
        support_region(floor_triangle(), 1.0, G, cone_edges=2)
    with pytest.raises(EquilibriumError, match="planar"):
        support_region([Contact((0, 0, 0), (0, 1, 1), 0.5)], 1.0, G, planar=True)
    with pytest.raises(EquilibriumError, match="contacts"):
        support_region([], 1.0, G)
    with pytest.raises(EquilibriumError, match="shrink"):
        r.shrink(-0.1)
    # A terrain Hold converts, with its kind and force bound; a friction hold has none (one given is refused).
    h = Hold("h0", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.5, "friction")
    assert Contact.from_hold(h).max_force is None
    h = Hold("h0", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.5, "adhesion", 10.0)
    assert Contact.from_hold(h).kind == "adhesion" and Contact.from_hold(h).max_force == 10.0
    with pytest.raises(TerrainError, match="friction hold takes no max_force"):
        Hold("h0", (0.0, 0.0, 0.0), (0.0, 0.0, 1.0), 0.5, "friction", 10.0)
