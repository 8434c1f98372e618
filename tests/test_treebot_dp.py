"""TreeBot's DP path (Lam et al., Eq. 4-7) against brute force, and its incremental update (section IV.B)."""

from __future__ import annotations

import heapq
import itertools
import math

import numpy as np
import pytest

from climb_ompl.treebot import DPPlanner, Ring, Tree, generate_tree, plan_path

UP = np.array([0.0, 0.0, 1.0])


def random_rings(rng: np.random.Generator, m: int, n: int, p_obs: float) -> list[Ring]:
    rings = []
    for i in range(m):
        k = int(rng.integers(max(3, n - 1), n + 2))  # ring sizes may differ
        pts = rng.normal(scale=0.05, size=(k, 3)) + [0, 0, 0.05 * i]
        nrm = rng.normal(size=(k, 3))
        nrm /= np.linalg.norm(nrm, axis=1, keepdims=True)
        rings.append(Ring(pts, nrm, rng.random(k) < p_obs))
    return rings


def step_cost(a: Ring, j: int, b: Ring, k: int, a0: float, reach: float) -> float:
    """-Q of Eq. 4, written independently of the planner (inf when not allowed)."""
    if b.obstacles[k]:
        return math.inf
    d = math.dist(a.points[j], b.points[k])
    if d > reach:
        return math.inf
    nz = float(b.normals[k] @ UP)
    return d - a0 * (nz - 1.0)


def dijkstra(rings: list[Ring], a0: float, reach: float, target: int | None) -> float:
    """Shortest path from any free point of ring 0 to the target on the last ring."""
    dist = {}
    heap = [(0.0, 0, j) for j in range(rings[0].n) if not rings[0].obstacles[j]]
    heapq.heapify(heap)
    while heap:
        c, i, j = heapq.heappop(heap)
        if (i, j) in dist:
            continue
        dist[(i, j)] = c
        if i == len(rings) - 1:
            if target is None or j == target:
                return c
            continue
        for k in range(rings[i + 1].n):
            w = step_cost(rings[i], j, rings[i + 1], k, a0, reach)
            if math.isfinite(w) and (i + 1, k) not in dist:
                heapq.heappush(heap, (c + w, i + 1, k))
    return math.inf


def path_cost(rings: list[Ring], pts: list[int], a0: float, reach: float) -> float:
    return sum(step_cost(rings[i], pts[i], rings[i + 1], pts[i + 1], a0, reach) for i in range(len(pts) - 1))


def test_dp_equals_dijkstra_on_120_random_trees():
    rng = np.random.default_rng(2024)
    found = 0
    for trial in range(120):
        m, n = int(rng.integers(2, 9)), int(rng.integers(3, 7))
        rings = random_rings(rng, m, n, p_obs=float(rng.uniform(0, 0.4)))
        a0, reach = float(rng.uniform(0.01, 0.2)), float(rng.uniform(0.06, 0.3))
        target = None if trial % 2 else int(rng.integers(0, rings[-1].n))
        res = DPPlanner(rings, UP, a0, reach, target).solve()
        best = dijkstra(rings, a0, reach, target)
        assert res.found == math.isfinite(best), trial
        if res.found:
            found += 1
            assert res.cost == pytest.approx(best, abs=1e-9)
            pts = [p.point for p in res.path]
            assert len(pts) == m and [p.row for p in res.path] == list(range(m))
            assert path_cost(rings, pts, a0, reach) == pytest.approx(best, abs=1e-9)
            if target is not None:
                assert pts[-1] == target
        else:
            assert res.reason
    assert 40 <= found <= 120  # both outcomes are exercised


def test_dp_equals_exhaustive_search():
    rng = np.random.default_rng(7)
    for _ in range(40):
        rings = random_rings(rng, int(rng.integers(2, 5)), 3, p_obs=0.2)
        best = math.inf
        for pts in itertools.product(*[range(r.n) for r in rings]):
            if rings[0].obstacles[pts[0]]:
                continue
            best = min(best, path_cost(rings, list(pts), 0.05, 0.2))
        res = DPPlanner(rings, UP, 0.05, 0.2).solve()
        assert res.found == math.isfinite(best)
        if res.found:
            assert res.cost == pytest.approx(best, abs=1e-12)


def test_dp_on_generated_trees_equals_dijkstra():
    for seed in range(6):
        t = generate_tree(seed, n_branches=3, trunk_rings=10, points_per_ring=8)
        target = t.branches[-1].name
        labels = t.ring_sequence(target)
        rings = [t.branch(b).rings[r] for b, r in labels]
        res = plan_path(t, target)
        best = dijkstra(rings, t.a0, t.robot.max_reach, None)
        assert res.found == math.isfinite(best)
        if res.found:
            assert res.cost == pytest.approx(best, abs=1e-9)
            assert [(p.branch, p.ring) for p in res.path] == labels


def test_work_is_m_n_squared():
    """The DP evaluates exactly sum n_i n_{i+1} actions: O(m n^2), linear in the number of rings."""
    rng = np.random.default_rng(1)
    rings = random_rings(rng, 30, 6, 0.1)
    dp = DPPlanner(rings, UP, 0.05, 1.0)
    assert dp.edges == sum(a.n * b.n for a, b in zip(rings, rings[1:], strict=False))


def test_incremental_update_recomputes_only_lower_rows():
    rng = np.random.default_rng(5)
    for _ in range(20):
        rings = random_rings(rng, 12, 5, 0.1)
        dp = DPPlanner(rings, UP, 0.05, 0.25)
        changed = {}
        for r in rng.choice(11, size=int(rng.integers(1, 4)), replace=False):
            old = rings[int(r)]
            pts = old.points + rng.normal(scale=0.01, size=old.points.shape)
            changed[int(r)] = Ring(pts, old.normals, rng.random(old.n) < 0.1)
        v_upper = [v.copy() for v in dp.V[max(changed) + 1:]]
        rows = dp.update(changed)
        assert rows == max(changed) + 1
        for a, b in zip(v_upper, dp.V[max(changed) + 1:], strict=False):
            assert np.array_equal(a, b)  # values above the change are untouched
        new = list(rings)
        for r, ring in changed.items():
            new[r] = ring
        fresh = DPPlanner(new, UP, 0.05, 0.25)
        for a, b in zip(fresh.V, dp.V, strict=False):  # the same values (inf where unreachable), to rounding
            np.testing.assert_allclose(a, b, rtol=1e-12, atol=1e-12)
        f1, f2 = fresh.solve(), dp.solve()
        assert f1.found == f2.found and (not f1.found or f1.cost == f2.cost)


def test_no_path_is_a_status_with_a_reason():
    t = Tree.load("three-branch")
    d = t.to_dict()
    ring = d["branches"][0]["rings"][5]
    ring["obstacles"] = list(range(len(ring["points"])))  # a fully blocked trunk ring
    res = plan_path(Tree.from_dict(d), "b2")
    assert not res.found and "ring 5 of branch 'trunk'" in res.reason


def test_top_side_preferred():
    """With the pull-out weight a0 the path keeps to the top side of a leaning branch (Fig. 6)."""
    m, n = 8, 12
    ang = np.arange(n) * 2 * np.pi / n
    lean = np.array([1.0, 0.0, 1.0]) / math.sqrt(2)  # branch axis at 45 degrees
    u, v = np.array([-1.0, 0.0, 1.0]) / math.sqrt(2), np.array([0.0, 1.0, 0.0])
    rings = []
    for i in range(m):
        radial = np.cos(ang)[:, None] * u + np.sin(ang)[:, None] * v
        rings.append(Ring(0.05 * i * lean + 0.1 * radial, radial, np.zeros(n, bool)))
    res = DPPlanner(rings, UP, a0=0.5, max_reach=1.0).solve()
    assert all(p.point == 0 for p in res.path)  # angle 0 = radial u, the upper side
