"""The reach prefilters of :mod:`climb_ompl.model.reach` against configurations built to touch their bounds."""

from __future__ import annotations

from importlib import resources
from pathlib import Path

import numpy as np
import pytest
import yaml

from climb_ompl.model.reach import pair_reach
from climb_ompl.model.robot import RobotModel

ROOT = Path(__file__).resolve().parents[1]


def planar(radius: float | None) -> RobotModel:
    """The planar three-limbed robot, with sphere feet of ``radius`` (``None``: its point contacts)."""
    spec = yaml.safe_load((ROOT / "robots" / "planar-3limb.yaml").read_text())
    if radius is not None:
        for lb in spec["limbs"]:
            lb["contact"] = {"type": "sphere", "radius": radius}
    return RobotModel.from_spec(spec, base_dir=ROOT / "urdf")


@pytest.mark.parametrize("radius", [None, 0.02, 0.05])
def test_pair_reach_bounds_two_holds_touched_at_full_stretch(radius):
    """Limbs 1 and 2 stretched straight in opposite directions (their shoulders meet at the pelvis): the hands are
    the two reaches apart, and two holds whose normals face each other put those hand frames (sphere centres)
    there from ``r`` farther out each.  The prefilter must keep such a pair: the hold distance is at most
    ``pair_reach``, equal to it at full stretch (a prefilter ignoring the radius cuts it by ``2 r``)."""
    r = planar(radius)
    q = np.asarray(r.nominal_q, dtype=float)
    names = list(r.joint_names)
    for j in ("limb1_elbow", "limb2_elbow", "base_theta"):
        q[names.index(j)] = 0.0
    q[names.index("limb1_shoulder")], q[names.index("limb2_shoulder")] = np.pi, 0.0
    ha, hb = r.hand_position(q, "limb1"), r.hand_position(q, "limb2")
    span = float(np.linalg.norm(ha - hb))
    assert span == pytest.approx(r.limb("limb1").reach + r.limb("limb2").reach, abs=1e-9)  # fully stretched
    u = (ha - hb) / span
    rad = radius or 0.0
    pa, pb = ha + rad * u, hb - rad * u  # holds facing each other: normals -u and u
    for limb, p, n, h in (("limb1", pa, -u, ha), ("limb2", pb, u, hb)):
        assert np.allclose(r.limb(limb).contact.hand_target(p, n), h)
    assert float(np.linalg.norm(pa - pb)) == pytest.approx(pair_reach(r)[("limb1", "limb2")], abs=1e-9)


@pytest.mark.parametrize("name", ["lemur", "go1"])
def test_shoulders_reach_is_the_reach_map_test(name):
    """Over random base poses and targets, against the reach-map test written with Pinocchio's own frame algebra
    (``oMi[parent] * jointPlacement``, then ``actInv``)."""
    import math

    import pinocchio as pin

    from climb_ompl.model.reach import ShouldersReach, map_limits, reach_maps
    from climb_ompl.model.terrain import Terrain

    r, wall = RobotModel.load(name), Terrain.load("demo-wall")
    maps = reach_maps(r, wall)
    rng = np.random.default_rng(3)
    q0 = np.asarray(r.nominal_q, dtype=float)
    base = list(r.base_indices)
    seen = {True: 0, False: 0}
    for _ in range(300):
        q = q0.copy()
        q[base] += rng.normal(0.0, 0.08, len(base))
        pre = [(lb.joint_ids[0], np.asarray(r.hand_position(q0, lb.name)) + rng.normal(0.0, 0.06, 3), lb.reach)
               for lb in r.limbs]
        got = ShouldersReach(r, maps, pre)(q)
        pin.forwardKinematics(r.model, r.data, q)
        want = True
        for jid, p, reach in pre:
            e1, e2, e3, d0, dd, radii = maps[jid]
            loc = (r.data.oMi[r.model.parents[jid]] * r.model.jointPlacements[jid]).actInv(p)
            j = int(math.floor((loc @ e3 - d0) / dd))
            if not 0 <= j < len(radii) - 1:  # the unprobed side: within the reach of the joint; beyond the
                want &= j < 0 and bool(np.linalg.norm(loc) <= reach)  # deepest plane: out of reach
                continue
            k = round((math.atan2(loc @ e2, loc @ e1) % (2 * math.pi)) / (2 * math.pi) * radii.shape[1])
            k %= radii.shape[1]
            lim = map_limits(radii)
            want &= bool(math.hypot(loc @ e1, loc @ e2) <= max(lim[j, k], lim[j + 1, k]))
        assert got == want
        seen[got] += 1
    assert min(seen.values()) >= 20, seen  # both answers exercised


@pytest.mark.heavy
@pytest.mark.parametrize("name,terrain", [("lemur", "demo-wall"), ("go1", "demo-wall"), ("go1", "slab"),
                                          ("anymal-c", "stepping-stone-ramp-3m")])
def test_the_reach_map_keeps_every_hand_position_the_limb_reaches(name, terrain):
    """A necessary condition: a hand position reached by forward kinematics (the limb's joints drawn within their
    bounds, the base anywhere near the nominal pose) always passes.  A map probed on the nominal hand's plane
    alone rejected 4 % of them for Go1 (a body pressed to the wall reaches farther along it).  The joints are
    drawn 0.1 rad inside their bounds: slivers of workspace reached only at a bound (a straight knee at its
    limit) can fall between the probes, 2 cm apart."""
    from climb_ompl.bench.suite import terrain_path
    from climb_ompl.model.reach import ShouldersReach, reach_maps
    from climb_ompl.model.terrain import Terrain

    r, wall = RobotModel.load(name), Terrain.load(terrain_path(terrain))
    maps = reach_maps(r, wall)
    rng = np.random.default_rng(5)
    lo, hi = np.maximum(np.asarray(r.lower), -7.0) + 0.1, np.minimum(np.asarray(r.upper), 7.0) - 0.1
    q0, base = np.asarray(r.nominal_q, dtype=float), list(r.base_indices)
    rejected = []
    for _ in range(1500):
        q = q0.copy()
        q[base] += rng.normal(0.0, 0.2, len(base))
        lb = r.limbs[int(rng.integers(len(r.limbs)))]
        idx = list(lb.joint_indices)
        q[idx] = rng.uniform(lo[idx], hi[idx])
        p = np.asarray(r.hand_position(q, lb.name))
        if not ShouldersReach(r, maps, [(lb.joint_ids[0], p, lb.reach)])(q):
            rejected.append((lb.name, q[idx].round(3).tolist()))
    assert not rejected, rejected[:5]


@pytest.mark.parametrize("name", ["lemur", "go1"])
def test_find_transition_gives_up_on_a_hold_out_of_every_reach(name):
    """A grab onto a hold 1.5 m above the body: no base draw near the start posture puts it within the limb's
    reach map, and FIND-TRANSITION stops after ``REACH_PATIENCE`` draws instead of its 150; a hold within reach
    (the one the hand just left) is found at once, the first draw within reach.  (Go1: its maps leave the hip
    frame unprobed on one side, where the hold must lie within the leg's reach of the hip.)"""
    from climb_ompl.climb.start import find_start
    from climb_ompl.climb.transition import REACH_PATIENCE, TransitionFinder
    from climb_ompl.manifold.feasibility import Feasibility
    from climb_ompl.manifold.stance import Stance
    from climb_ompl.model.terrain import Terrain

    r, wall = RobotModel.load(name), Terrain.load("demo-wall")
    start = find_start(r, wall, seed=0)
    limb = r.limbs[0].name
    sigma = Stance(start.stance).without(limb)
    far = max(wall.holds, key=lambda h: h.p[2])  # the top of the wall
    assert far.p[2] - r.hand_position(start.q, limb)[2] > 1.5
    finder = TransitionFinder(Feasibility.of(r, wall), attempts=150)
    assert finder.find(sigma, sigma.with_hold(limb, far.id), start.q, seed=0) is None
    assert finder.stats[-1] == (-1, 0, REACH_PATIENCE + 1)
    assert finder.find(sigma, sigma.with_hold(limb, start.stance[limb]), start.q, seed=0) is not None
    assert finder.stats[-1][2] < REACH_PATIENCE


def test_find_transition_gives_up_when_no_draw_brings_the_com_near_the_region():
    """LEMUR's start on the 35-65 degree wall: releasing ``se`` leaves a support region about 0.28 m from the CoM.
    FIND-TRANSITION stops once ``COM_PATIENCE`` draws within reach have had the CoM far outside it, long before its
    150 draws, and gives the same answer as drawing all 150 (patience off); the releases that succeed are found
    as before."""
    import climb_ompl.climb.transition as T
    from climb_ompl.climb.start import find_start
    from climb_ompl.manifold.feasibility import Feasibility
    from climb_ompl.manifold.stance import Stance
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.settings import ClimbSettings

    r = RobotModel.load("lemur")
    wall = Terrain.load(str(resources.files("climb_ompl").joinpath("data/queries/walls/lean35-65.yaml")))
    start = find_start(r, wall, seed=0)
    sigma = Stance(start.stance)
    feas = Feasibility.of(r, wall)
    assert float(feas.region(sigma.without("se")).margin(r.com(start.q))) < -0.2

    def release(limb: str, patience: int) -> tuple[bool, tuple[int, int, int]]:
        finder = T.TransitionFinder(feas, attempts=150, com_patience=patience)
        found = finder.find(sigma, sigma.without(limb), start.q, seed=0) is not None
        return found, finder.stats[-1]

    assert T.TransitionFinder(feas).com_patience == T.COM_PATIENCE == ClimbSettings().com_patience
    assert T.TransitionFinder(feas).reach_patience == T.REACH_PATIENCE == ClimbSettings().reach_patience
    with_patience = {lb: release(lb, T.COM_PATIENCE) for lb in sigma.limbs}
    found, (_, ik_tries, draws) = with_patience["se"]
    assert not found and ik_tries == 1 and draws < 150 - 2 * T.COM_PATIENCE
    assert any(f for f, _ in with_patience.values())
    without = {lb: release(lb, 0) for lb in sigma.limbs}  # 0: no patience, every draw
    assert without["se"][1][2] == 150
    assert {lb: f for lb, (f, _) in with_patience.items()} == {lb: f for lb, (f, _) in without.items()}


@pytest.mark.heavy
@pytest.mark.parametrize("batch", [True, False])
def test_draws_far_from_closing_are_not_closed_and_change_no_answer(batch):
    """LEMUR on the 35-65 degree wall: FIND-TRANSITION closing only the draws whose CoM lies within ``closure_slack``
    (2 cm) of the support region finds the same transitions, at the same draws and with the same tries, as closing
    every draw within ``com_slack`` (``closure_slack=None``, the oracle), over the releases and grabs out of the start
    and the stances they reach (eight levels deep), with fewer closures; with the draws' prefilters on arrays
    (``batch``) and one draw at a time (the path of a robot whose limbs hang from no single body)."""
    import climb_ompl.climb.transition as T
    from climb_ompl.climb.start import find_start
    from climb_ompl.manifold.feasibility import Feasibility
    from climb_ompl.manifold.stance import Stance
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.settings import ClimbSettings

    r = RobotModel.load("lemur")
    wall = Terrain.load(str(resources.files("climb_ompl").joinpath("data/queries/walls/lean35-65.yaml")))
    start = find_start(r, wall, seed=0)
    sigma = Stance(start.stance)
    feas = Feasibility.of(r, wall)
    fast, every = T.TransitionFinder(feas), T.TransitionFinder(feas, closure_slack=None)
    if not batch:
        fast._base_pose = every._base_pose = (None,)
    assert fast.closure_slack == T.CLOSURE_SLACK == ClimbSettings().closure_slack < fast.com_slack
    assert every.closure_slack == every.com_slack
    found, frontier = 0, [(sigma, start.q)]
    for _ in range(8):  # the edges out of the start, out of the stances they reach, and so on (breadth first)
        reached = []
        for a, near in frontier:
            if len(a) == 4:
                edges = [a.without(lb) for lb in a.limbs]
            else:
                (free,) = [lb.name for lb in r.limbs if lb.name not in a]
                hand = r.hand_position(near, free)
                edges = [a.with_hold(free, h.id) for h in wall.holds
                         if h.id not in a.hold_ids and np.linalg.norm(h.p - hand) < 0.3]
            for i, b in enumerate(edges):
                qa, qb = fast.find(a, b, near, seed=i), every.find(a, b, near, seed=i)
                assert (qa is None) == (qb is None)
                if qa is not None:
                    assert np.array_equal(qa, qb)
                    found += 1
                    reached.append((b, qa))
        frontier = reached[::2][:8]
    assert fast.stats == every.stats and found and any(s[0] == -1 for s in fast.stats)
    assert sum(fast.failures.values()) < 0.9 * sum(every.failures.values())  # (about 0.84 when written)


def test_the_patiences_are_settings_of_the_climb():
    """The search's FIND-TRANSITION takes its patiences and its closure slack from ``ClimbSettings`` (stored in the
    plan file)."""
    from climb_ompl.climb.goal import Goal
    from climb_ompl.climb.search import StanceGraphSearch
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.settings import ClimbSettings

    r, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    s = ClimbSettings(reach_patience=0, com_patience=5, closure_slack=0.01)
    search = StanceGraphSearch(r, wall, Goal("height", height=1.0), s)
    assert (search.finder.reach_patience, search.finder.com_patience, search.finder.closure_slack) == (0, 5, 0.01)
    assert ClimbSettings.from_dict(s.to_dict()) == s


@pytest.mark.slow
def test_a_numeric_limbs_reach_map_matches_the_closed_form_one():
    """Go1's front-left leg solved by damped least squares (``ik: numeric``) against the same leg in closed form:
    the numeric map's scans start at forward-kinematics samples (:func:`climb_ompl.model.reach._sampled_radii`) instead
    of outside the reach, and its inverse kinematics can miss a target near a joint bound; still, at most 1 % of
    its cells differ from the closed-form map's (3 of 576 when written), none by more than 0.15 m (about 10 s)."""
    from climb_ompl.model.reach import _reach_map
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.model.wall_frame import wall_normal

    r = RobotModel.load("go1")
    spec = {**r.spec, "name": "go1-numeric", "limbs": [{**lb, "ik": "numeric"} for lb in r.spec["limbs"]]}
    rn = RobotModel.from_spec(spec, base_dir=r.spec_path.parent)
    assert rn.limbs[0].ik == "numeric" and r.limbs[0].ik == "analytic"
    n = wall_normal(Terrain.load("demo-wall"))
    exact, numeric = _reach_map(r, r.limbs[0], n)[-1], _reach_map(rn, rn.limbs[0], n)[-1]
    diff = numeric - exact
    assert np.count_nonzero(diff) <= 0.01 * diff.size, np.count_nonzero(diff)
    assert np.abs(diff).max() <= 0.15


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_reachable_holds_is_the_start_holds_connected_component(seed):
    """Holds scattered at random: the holds reached hop by hop are the connected components, holding a start
    hold, of the graph joining every two holds at most ``hop`` apart (scipy's connected components over the full
    distance matrix)."""
    from scipy.sparse.csgraph import connected_components
    from scipy.spatial.distance import cdist

    from climb_ompl.model.reach import reachable_holds
    from climb_ompl.model.terrain import Terrain

    rng = np.random.default_rng(seed)
    pos = np.c_[rng.uniform(-1, 1, 120), np.zeros(120), rng.uniform(0, 4, 120)]
    t = Terrain.from_dict({"name": "scatter", "holds": [
        {"id": f"h{i}", "position": p.tolist(), "normal": [0, 1, 0]} for i, p in enumerate(pos)]})
    hop = 0.3
    _, label = connected_components(cdist(pos, pos) <= hop, directed=False)
    start = [f"h{int(i)}" for i in rng.choice(120, 2, replace=False)]
    want = np.isin(label, [label[int(s[1:])] for s in start])
    got = reachable_holds(t, start, hop)
    assert 2 < want.sum() < 120 and np.array_equal(got, want)
