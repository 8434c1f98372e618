"""Samplers: OMPL hooks reached during solve(), straight-elbow samples, model reduction vs grid."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from conftest import PLANAR_TEST_TERRAIN as PLANAR  # noqa: E402
from hypothesis import assume, event, given, settings
from hypothesis import strategies as st

from climb_ompl.climb import onestep
from climb_ompl.climb.onestep import find_path
from climb_ompl.manifold.planar3 import Chain, Reduction, interval
from climb_ompl.manifold.samplers import STRAIGHT_EPS, SamplingCore, free_limb_extremes
from climb_ompl.manifold.stance import Stance, StanceConstraint, stance_region
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain


@pytest.fixture(scope="module")
def setup(planar_move):
    return planar_move


@pytest.mark.heavy
@pytest.mark.parametrize("planner", ["PRM", "LazyPRM", "RRTConnect"])
def test_custom_sampler_called_during_solve(setup, planner, monkeypatch):
    """The custom sampler is reached while solving (not only in setup) under PRM, LazyPRM and RRTConnect."""
    robot, terrain, s, qs, qg = setup
    seen = {}
    orig = SamplingCore.draw

    def spy(self):
        seen["core"] = self
        return orig(self)

    monkeypatch.setattr(SamplingCore, "draw", spy)
    # a disc between the two holds of the free limb blocks the direct route, so the planner must sample
    blocked = Terrain.from_dict({**PLANAR, "surfaces": [{"type": "circle", "center": [0.0, 1.5], "radius": 0.1}]})
    res = find_path(robot, blocked, s, qs, qg, planner=planner, sampler="joint-by-joint", space="projected",
                    time_limit=2.0,
                    seed=0, max_iterations=400, simplify=False, uniform_fraction=0.0, direct=False)
    assert res.stats["samples"] > 0, res.stats
    assert "core" in seen


def test_straight_elbow_samples(setup):
    robot, terrain, s, _, _ = setup
    con = StanceConstraint(robot, terrain, s)
    core = SamplingCore(robot, terrain, s, con, "straight-elbow", seed=0, uniform_fraction=0.0)
    elbows = {lb.elbow_index: lb.elbow_straight for lb in robot.limbs if lb.name in s}
    n = 0
    for _ in range(30):
        q = core._straight_elbow()
        if q is None:
            continue
        n += 1
        assert con.error(q) <= con.tol
        dev = [abs(abs(q[e] - v) - STRAIGHT_EPS) for e, v in elbows.items()]
        assert min(dev) < 1e-9, dev
    assert n >= 10


def test_free_limb_extremes_are_nearest_the_boundary(setup):
    """Bretl et al. (2004): the two free-limb samples are feasible and closer to the
    boundary than any other grid point."""
    robot, terrain, s, qs, _ = setup
    region = stance_region(robot, terrain, s)
    lo, hi = np.array(robot.lower), np.array(robot.upper)
    out = free_limb_extremes(robot, region, qs, ("limb3",), lo, hi, grid=9)
    assert 1 <= len(out) <= 2
    a, b = interval(region)
    xs = [robot.com(q)[0] for q in out]
    assert all(a - 1e-9 <= x <= b + 1e-9 for x in xs)
    gaps = sorted(min(x - a, b - x) for x in xs)
    # independent brute force over the same lattice
    idx = list(robot.limbs[2].joint_indices)
    g = np.linspace(lo[idx[0]], hi[idx[0]], 9)
    best = np.inf
    for t1 in g:
        for t2 in np.linspace(lo[idx[1]], hi[idx[1]], 9):
            q = qs.copy()
            q[idx] = (t1, t2)
            x = robot.com(q)[0]
            if a <= x <= b:
                best = min(best, x - a, b - x)
    assert gaps[0] == pytest.approx(best, abs=1e-9)


@settings(derandomize=True, deadline=None, max_examples=40)
@given(x=st.floats(-0.5, 0.5), z=st.floats(0.4, 1.3), b1=st.sampled_from([-1, 1]), b2=st.sampled_from([-1, 1]),
       centre=st.floats(-0.3, 0.3), width=st.floats(0.03, 0.3))
def test_model_reduction_matches_grid(x, z, b1, b2, centre, width):
    """Bretl, Latombe & Rock (2003), Eq. 4 / Bretl (2006), (C2): pelvis feasibility equals a
    brute-force grid over (t1, t2).  The CoM interval ``E`` is the stance's support region cut to
    ``centre +- width / 2`` (a stricter equilibrium test, as torque limits give): on the whole region every
    chain is feasible, and a narrow ``E`` makes the infeasible answer as common as the feasible one."""
    robot = _ROBOT
    terrain = Terrain.from_dict(PLANAR)
    s = Stance(limb1="a", limb2="b")
    red = Reduction(robot, terrain, s)
    lo, hi = interval(stance_region(robot, terrain, s))
    a, b = max(lo, centre - width / 2), min(hi, centre + width / 2)
    assume(a < b)
    ch = red.chain(x, z, (b1, b2), SimpleNamespace(interval=(a, b)))
    assume(ch is not None)  # (the pelvis out of the hands' reach: no chain to test)
    margin = min(abs(ch.delta_min - red.L), abs(ch.delta_max + red.L))
    assume(margin >= 0.01)  # on the boundary the grid cannot decide
    fi = robot.limbs[2].joint_indices
    T = np.linspace(-np.pi, np.pi, 121)
    t1, t2 = np.meshgrid(T, T, indexing="ij")
    Q = np.repeat(ch.q[None], t1.size, axis=0)
    Q[:, fi[0]], Q[:, fi[1]] = t1.ravel(), t2.ravel()
    cx = robot.com_batch(Q)[:, 0]
    inside = (cx > a) & (cx < b)
    feasible = ch.feasible(red.L)
    event(f"feasible: {feasible}")
    assert bool(inside.any()) == feasible
    if feasible:
        for q in red.lifts(ch):
            assert a - 1e-9 <= robot.com(q)[0] <= b + 1e-9


_ROBOT = RobotModel.load("planar-3limb")


def test_reduced_sampler_plans(setup):
    robot, terrain, s, qs, qg = setup
    res = find_path(robot, terrain, s, qs, qg, sampler="reduced", space="projected", seed=0, max_iterations=20000,
                    time_limit=20,
                    direct=False)
    assert res.found
    assert onestep.PathResult is type(res)


def _torus_components(mask: np.ndarray) -> int:
    """Connected components of a boolean grid on the torus (4-neighbours, both axes wrapping): the grid's labels
    (scipy.ndimage), merged where they meet across the wrapped edges."""
    from scipy import ndimage

    lab, n = ndimage.label(mask)
    parent = list(range(n + 1))

    def root(a: int) -> int:
        while parent[a] != a:
            a = parent[a]
        return a

    for a, b in [*zip(lab[0], lab[-1], strict=True), *zip(lab[:, 0], lab[:, -1], strict=True)]:
        if a and b:
            parent[root(int(a))] = root(int(b))
    return len({root(k) for k in range(1, n + 1)})


@settings(derandomize=True, deadline=None, max_examples=30)
@given(lo=st.floats(-1.2, 1.0), width=st.floats(0.1, 1.5))
def test_theta_f_connected_or_two_components_as_eq_5_says(lo, width):
    """Bretl, Latombe & Rock (2003), Eq. 5 / Bretl (2006), (C4): ``Theta_f``, the free limb's angles ``(t1, t2)``
    whose CoM offset ``delta = L/4 (3 cos t1 + cos(t1 + t2))`` (Eq. 3) lies in ``[delta_min, delta_max]``, is
    connected iff ``delta_min`` or ``delta_max`` lies outside ``(-L/2, L/2)``, and otherwise has exactly two
    components.  Oracle: the components of a 360 x 360 grid over the torus ``[-pi, pi)^2`` (bands at least 0.1 L
    wide, so that the grid resolves them)."""
    L = 1.0
    d_min, d_max = lo, lo + width
    assume(d_min < L and d_max > -L)  # feasible (Eq. 4)
    # on a boundary of the conditions the grid cannot decide
    assume(min(abs(abs(d_min) - L / 2), abs(abs(d_max) - L / 2), abs(abs(d_min) - L), abs(abs(d_max) - L)) > 0.03)
    ch = Chain(np.zeros(1), 0.0, 0.0, d_min, d_max)
    T = np.linspace(-np.pi, np.pi, 360, endpoint=False)
    t1, t2 = np.meshgrid(T, T, indexing="ij")
    delta = L / 4 * (3 * np.cos(t1) + np.cos(t1 + t2))
    n = _torus_components((delta >= d_min) & (delta <= d_max))
    event(f"components: {n}")
    assert n == (1 if ch.connected(L) else 2)
