"""The bundled terrains: each loads, and each has the property it was designed for (checked by small
independent models, not by the planner):

* ``pegs`` (Bretl (2006), Fig. 3/13): a two-link robot (links 0.5 m, segments; obstacles discs) must go
  1 -> 2 -> 3 -> 2 -> 4, and it is the obstacles that forbid 1 -> 2 -> 4;
* ``planar-wall`` (Bretl, Latombe & Rock (2003), Fig. 2-5): pairs of holds give a non-empty support interval
  (Bretl, Latombe & Rock (2003), Eq. 1) and at least 10 one-limb steps climb it within a 0.35 m limb reach;
* ``demo-wall``: the generator call in its description reproduces it; vertical, >= 2.5 m tall.
"""

from __future__ import annotations

import ast
import itertools
from collections import deque

import numpy as np
import pytest
from scipy import ndimage
from scipy.optimize import linprog

from climb_ompl.model.terrain import Terrain, bundled_terrains, generate_wall


def test_the_three_required_terrains_are_bundled() -> None:
    assert {"pegs", "planar-wall", "demo-wall"} <= set(bundled_terrains())


@pytest.mark.parametrize("name", bundled_terrains())
def test_bundled_terrain_loads_and_has_a_description(name: str) -> None:
    t = Terrain.load(name)
    assert t.name == name and t.description and len(t.holds) >= 4


# ---- pegs: a double-link robot on a torus grid ----------------------------------------------------
LINK = 0.5
N = 180
TH = np.linspace(-np.pi, np.pi, N, endpoint=False)
T1, T2 = np.meshgrid(TH, TH, indexing="ij")


def _seg_hits_disc(a: np.ndarray, b: np.ndarray, c: np.ndarray, r: float) -> np.ndarray:
    ab, ac = b - a, c - a
    t = np.clip(np.sum(ab * ac, -1) / np.maximum(np.sum(ab * ab, -1), 1e-12), 0.0, 1.0)
    return np.linalg.norm(a + t[..., None] * ab - c, axis=-1) < r


def _free(hold: np.ndarray, discs: list[tuple[np.ndarray, float]]) -> np.ndarray:
    """Free (theta1, theta2) cells with one hand at ``hold``: theta1 of the held link, theta2 relative."""
    a = np.broadcast_to(hold, T1.shape + (2,))
    e = a + LINK * np.stack([np.cos(T1), np.sin(T1)], -1)
    w = e + LINK * np.stack([np.cos(T1 + T2), np.sin(T1 + T2)], -1)
    hit = np.zeros(T1.shape, bool)
    for c, r in discs:
        hit |= _seg_hits_disc(a, e, c, r) | _seg_hits_disc(e, w, c, r)
    return ~hit


def _components(free: np.ndarray) -> np.ndarray:
    """Connected components on the torus (labels, -1 where blocked)."""
    lab, n = ndimage.label(free)
    parent = list(range(n + 1))

    def find(x: int) -> int:
        while parent[x] != x:
            parent[x] = parent[parent[x]]
            x = parent[x]
        return x

    for u, v in [*zip(lab[0], lab[-1], strict=True), *zip(lab[:, 0], lab[:, -1], strict=True)]:
        if u and v:
            parent[find(int(u))] = find(int(v))
    roots = {r: i for i, r in enumerate(sorted({find(k) for k in range(1, n + 1)}))}
    out = np.full(lab.shape, -1)
    mask = lab > 0
    out[mask] = [roots[find(int(k))] for k in lab[mask]]
    return out


def _cell(angle: float) -> int:
    return int(np.round((np.arctan2(np.sin(angle), np.cos(angle)) + np.pi) / (2 * np.pi) * N)) % N


def _peg_graph(t: Terrain, with_obstacles: bool = True) -> tuple[dict, list]:
    holds = {h.id: h.p[[0, 2]] for h in t.holds}
    discs = [(np.array([s.center[0], s.center[2]]), float(s.radius or 0.0)) for s in t.surfaces
             if s.type == "circle"] if with_obstacles else []
    comps = {i: _components(_free(p, discs)) for i, p in holds.items()}
    transitions = []  # (hold i, component in F_i, hold j, component in F_j, bend)
    for i, j in itertools.combinations(sorted(holds), 2):
        d = np.linalg.norm(holds[j] - holds[i])
        if d >= 2 * LINK:
            continue
        phi = np.arctan2(*(holds[j] - holds[i])[::-1])
        alpha = np.arccos(d / (2 * LINK))
        for bend in (1, -1):
            t1i = phi + bend * alpha
            elbow = holds[i] + LINK * np.array([np.cos(t1i), np.sin(t1i)])
            t1j = np.arctan2(*(elbow - holds[j])[::-1])
            ci = comps[i][_cell(t1i), _cell(-2 * bend * alpha)]
            cj = comps[j][_cell(t1j), _cell(2 * bend * alpha)]
            if ci >= 0 and cj >= 0:
                transitions.append((i, int(ci), j, int(cj), bend))
    return comps, transitions


def _stance_route(transitions: list, start: str, goal: str) -> list[str] | None:
    """Fewest-steps sequence of holds through the component graph (one component per stance at start)."""
    adj: dict = {}
    for i, ci, j, cj, _ in transitions:
        adj.setdefault((i, ci), []).append((j, cj))
        adj.setdefault((j, cj), []).append((i, ci))
    starts = sorted({(i, c) for i, c, *_ in transitions if i == start} | {(j, c) for _, _, j, c, _ in transitions
                                                                          if j == start})
    queue = deque((s, [start]) for s in starts)
    seen = set(starts)
    while queue:
        node, route = queue.popleft()
        if node[0] == goal:
            return route
        for nxt in adj.get(node, []):
            if nxt not in seen:
                seen.add(nxt)
                queue.append((nxt, [*route, nxt[0]]))
    return None


def test_pegs_route_is_1_2_3_2_4_as_in_fig_13() -> None:
    t = Terrain.load("pegs")
    assert [h.type for h in t.holds] == ["grasp"] * 4 and sum(s.type == "circle" for s in t.surfaces) == 3
    comps, trans = _peg_graph(t)
    assert len(trans) == 6  # q1..q6: two bends for each of the pairs 1-2, 2-3, 2-4 (Fig. 5)
    assert sorted({(i, j) for i, _, j, _, _ in trans}) == [("1", "2"), ("2", "3"), ("2", "4")]
    assert _stance_route(trans, "1", "4") == ["1", "2", "3", "2", "4"]
    # q1 and q2 are in the one component of F1 but in two different components of F2 (section 2.1).
    q12 = [(ci, cj) for i, ci, j, cj, _ in trans if (i, j) == ("1", "2")]
    assert q12[0][0] == q12[1][0] and q12[0][1] != q12[1][1]
    assert len(set(comps["2"][comps["2"] >= 0].ravel())) >= 3


def _big_components(c: np.ndarray, share: float = 1e-3) -> list[int]:
    """Labels of the components covering more than ``share`` of the torus (drops grid slivers of a few cells
    where two free regions touch at a point)."""
    labels, counts = np.unique(c[c >= 0], return_counts=True)
    return [int(k) for k, n in zip(labels, counts, strict=True) if n > share * c.size]


def test_pegs_stance_manifolds_have_the_structure_of_fig_5() -> None:
    """Bretl (2006), Fig. 5: F1, F3, F4 have one component each; F2 has four, F2^1 = {q1, q3} (the route),
    F2^2 = {q2} (a dead end), F2^3 = {q4, q5, q6} and F2^4 with no transition at all.  The paper gives no
    coordinates; on the bundled pegs F2 has the same three transition-bearing components and *two*
    transition-free ones (5 in all, stable from 180 to 400 cells per angle)."""
    comps, trans = _peg_graph(Terrain.load("pegs"))
    for peg in "134":
        assert len(_big_components(comps[peg])) == 1, peg
    big2 = _big_components(comps["2"])
    ends: dict[int, list[str]] = {c: [] for c in big2}  # F2's component -> the other peg of each transition
    for i, ci, j, cj, _ in trans:
        if i == "2":
            ends[ci].append(j)
        elif j == "2":
            ends[cj].append(i)
    ends = {c: sorted(v) for c, v in ends.items()}
    with_transitions = sorted((v for v in ends.values() if v), key=len)
    assert with_transitions == [["1"], ["1", "3"], ["3", "4", "4"]]  # F2^2, F2^1, F2^3 of Fig. 5
    assert len(big2) - len(with_transitions) == 2  # Fig. 5: one transition-free component (F2^4)


def test_pegs_without_obstacles_allows_the_direct_route() -> None:
    """Negative control: the obstacles, not the peg distances, force the detour through peg 3."""
    _, trans = _peg_graph(Terrain.load("pegs"), with_obstacles=False)
    assert _stance_route(trans, "1", "4") == ["1", "2", "4"]


def test_pegs_spacing() -> None:
    p = {h.id: h.p for h in Terrain.load("pegs").holds}
    for j in "134":
        assert 0.4 <= np.linalg.norm(p[j] - p["2"]) <= 0.8


# ---- planar-wall: support interval (Bretl, Latombe & Rock (2003), Eq. 1) and a ladder of steps --------------
def support_interval(holds: list, weight: float = 1.0) -> tuple[float, float] | None:
    """The interval of CoM x (m) for which two 2-D friction cones can balance ``weight``
    (Bretl, Latombe & Rock (2003), Eq. 1)."""
    cols, moments = [], []
    for h in holds:
        n = np.array([h.normal[0], h.normal[2]])
        half = np.arctan(h.friction)
        for s in (1, -1):
            c, si = np.cos(s * half), np.sin(s * half)
            e = np.array([c * n[0] - si * n[1], si * n[0] + c * n[1]])
            cols.append(e)
            moments.append(h.position[0] * e[1] - h.position[2] * e[0])
    k = len(cols)
    # unknowns: k edge magnitudes >= 0, then x_c; force balance and moment balance about the origin
    a_eq = np.zeros((3, k + 1))
    a_eq[0, :k] = [e[0] for e in cols]
    a_eq[1, :k] = [e[1] for e in cols]
    a_eq[2, :k] = moments
    a_eq[2, k] = -weight
    b_eq = np.array([0.0, weight, 0.0])
    bounds = [(0, None)] * k + [(-10, 10)]
    ends = []
    for sign in (1, -1):
        cost = np.zeros(k + 1)
        cost[k] = sign
        res = linprog(cost, A_eq=a_eq, b_eq=b_eq, bounds=bounds, method="highs")
        if res.status != 0:
            return None
        ends.append(res.x[k])
    return ends[0], ends[1]


def test_support_interval_oracle_on_a_known_case() -> None:
    """Two frictionless upward holds at x = 0 and x = 1: the CoM must lie between them."""
    from climb_ompl.model.terrain import Hold

    lo_hi = support_interval([Hold("a", (0, 0, 0), (0, 0, 1), 0.0), Hold("b", (1, 0, 0), (0, 0, 1), 0.0)])
    assert lo_hi == pytest.approx((0.0, 1.0), abs=1e-9)
    assert support_interval([Hold("a", (0, 0, 0), (1, 0, 0), 0.0), Hold("b", (0, 0, 1), (1, 0, 0), 0.0)]) is None


def _reach_ok(points: list[np.ndarray], reach: float) -> bool:
    """A pelvis position within ``reach`` of every point exists (grid search over the first disc)."""
    g = np.linspace(-reach, reach, 41)
    cand = points[0] + np.stack(np.meshgrid(g, g), -1).reshape(-1, 2)
    return bool(np.any(np.all([np.linalg.norm(cand - p, axis=1) <= reach for p in points], axis=0)))


def test_planar_wall_supports_a_ladder_of_at_least_10_steps() -> None:
    t = Terrain.load("planar-wall")
    assert t.dim == 2 and t.g[2] < 0
    z = t.positions[:, 2]
    assert z.max() - z.min() >= 2.0
    for h in t.holds:  # normals point out of the rock: up and into the crack
        assert h.normal[2] > 0.8 and np.sign(h.normal[0]) == (1 if h.id.startswith("L") else -1)
    order = sorted(t.holds, key=lambda h: (h.position[2], h.position[0]))
    reach = 0.35
    feet = order[:3]
    steps = 0
    for new in order[3:]:
        support = feet[1:]
        interval = support_interval(support)
        assert interval is not None, f"no support interval on {[h.id for h in support]}"
        xy = [np.array([h.position[0], h.position[2]]) for h in [*support, new]]
        assert _reach_ok(xy, reach), f"{new.id} out of reach from {[h.id for h in support]}"
        feet = [*support, new]
        steps += 1
    assert steps >= 10


# ---- demo-wall -------------------------------------------------------------------------------------
def test_demo_wall_is_reproduced_by_the_generator_call_in_its_description() -> None:
    t = Terrain.load("demo-wall")
    call = ast.parse(t.description, mode="eval").body
    assert isinstance(call, ast.Call) and getattr(call.func, "id", None) == "generate_wall"
    kwargs = {kw.arg: ast.literal_eval(kw.value) for kw in call.keywords}
    g = generate_wall(**kwargs, name="demo-wall")
    # exactly: the generator rounds what it stores, so its file is the same on every machine (docs/terrain.md)
    assert g.holds == t.holds
    rest = ("name", "dim", "gravity", "surfaces", "description")
    assert [getattr(g, k) for k in rest] == [getattr(t, k) for k in rest]


def test_demo_wall_is_a_tall_vertical_wall() -> None:
    t = Terrain.load("demo-wall")
    assert t.dim == 3 and t.g.tolist() == [0.0, 0.0, -9.81]
    z = t.positions[:, 2]
    assert z.max() - z.min() >= 2.5 and len(t.holds) >= 100
    assert np.all(t.positions[:, 1] == 0.0) and all(h.normal[1] > 0 for h in t.holds)
