"""One-step planning end to end: FIND-TRANSITION / FIND-PATH, every planner and space.

Every returned path is checked by :func:`verify_path`, an independent verifier that does not reuse the
planner's checker objects: hands on holds from a fresh Pinocchio ``Data``, the CoM in equilibrium by a
per-point LP (scipy, outer-linearised friction cones), joint limits from the Pinocchio model, collision
through the robot model's Coal query.
"""

from __future__ import annotations

import numpy as np
import pinocchio as pin
import pytest
from scipy.optimize import linprog

from climb_ompl.climb.onestep import PathResult, find_path, find_transition
from climb_ompl.errors import PlannerNotFound, QueryError
from climb_ompl.manifold._ompl import PLANNER_NAMES
from climb_ompl.manifold.stance import DEFAULT_TOLERANCE, SPACE_NAMES, Stance, make_checks
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain


# ---- independent verifier -------------------------------------------------------------------------------
def lp_equilibrium(terrain: Terrain, holds: list[str], mass: float, com: np.ndarray, planar: bool,
                   edges: int = 32) -> bool:
    """Per-point LP oracle: contact forces in (outer-linearised) friction cones balancing gravity at ``com``."""
    g = terrain.g * mass
    cols, pts = [], []
    for h in holds:
        hd = terrain.hold(h)
        n = hd.n
        if planar:
            t = np.array([n[2], 0.0, -n[0]])
            gens = [n + hd.friction * t, n - hd.friction * t]
        else:
            t1 = np.cross(n, [0.0, 0.0, 1.0] if abs(n[2]) < 0.9 else [1.0, 0.0, 0.0])
            t1 /= np.linalg.norm(t1)
            t2 = np.cross(n, t1)
            mu = hd.friction / np.cos(np.pi / edges)  # circumscribed pyramid: a necessary condition
            gens = [n + mu * (np.cos(a) * t1 + np.sin(a) * t2) for a in np.linspace(0, 2 * np.pi, edges, False)]
        for v in gens:
            cols.append(np.r_[v, np.cross(hd.p, v)])
            pts.append(h)
    A = np.array(cols).T
    b = -np.r_[g, np.cross(com, g)]
    rows = [0, 2, 4] if planar else list(range(6))
    res = linprog(np.zeros(A.shape[1]), A_eq=A[rows], b_eq=b[rows], bounds=(0, None), method="highs")
    return res.status == 0


def verify_path(robot: RobotModel, terrain: Terrain, stance: Stance, path: list[np.ndarray],
                max_step: float = 0.05, tol: float = DEFAULT_TOLERANCE, lift_radius: float = 0.05) -> None:
    """Assert every waypoint is feasible at ``stance`` (independent of the planner's objects).

    A free hand that starts or ends the move on a hold may touch the terrain while within ``lift_radius``
    metres of that hold (it is grabbing or releasing it).
    """
    model = robot.model
    data = model.createData()
    names = [lb.name for lb in robot.limbs]
    axes = [0, 2] if robot.planar else [0, 1, 2]
    assert len(path) >= 2
    free = [i for i, n in enumerate(names) if n not in stance]
    ends = {}
    for i in free:
        for q in (path[0], path[-1]):
            pin.framesForwardKinematics(model, data, q)
            h = data.oMf[model.getFrameId(robot.limbs[i].hand_frame)].translation
            d = np.linalg.norm(terrain.positions - h, axis=1)
            if d.min() <= 1e-3:
                ends.setdefault(i, []).append(terrain.positions[int(np.argmin(d))])
    for k, q in enumerate(path):
        pin.framesForwardKinematics(model, data, q)
        for limb, hold in stance.items():
            fid = model.getFrameId(robot.limbs[names.index(limb)].hand_frame)
            err = np.linalg.norm((data.oMf[fid].translation - terrain.hold(hold).p)[axes])
            assert err <= tol * 1.01, f"waypoint {k}: hand {limb} is {err:.2e} m from {hold}"
        assert np.all(q >= model.lowerPositionLimit - 1e-9) and np.all(q <= model.upperPositionLimit + 1e-9)
        com = pin.centerOfMass(model, data, q)
        if robot.equilibrium:
            assert lp_equilibrium(terrain, list(stance.hold_ids), robot.mass, com, robot.planar), f"waypoint {k}"
        exempt = list(stance.limbs)
        for i, P in ends.items():
            h = data.oMf[model.getFrameId(robot.limbs[i].hand_frame)].translation
            if min(np.linalg.norm(p - h) for p in P) <= lift_radius:
                exempt.append(names[i])
        assert not robot.in_collision(q, terrain, contact_limbs=exempt), f"waypoint {k}: collision"
        if k:
            assert np.max(np.abs(q - path[k - 1])) <= max_step + 1e-9


# ---- fixtures ---------------------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def planar(planar_move):
    return planar_move


def test_transition_is_feasible_for_both_stances(planar):
    robot, terrain, s, qs, _ = planar
    verify_path(robot, terrain, s.with_hold("limb3", "c"), [qs, qs])
    verify_path(robot, terrain, s, [qs, qs])


def test_planar_move_lazyprm_verified(planar):
    """Bretl, Latombe & Rock (2003), section 3: the three-limbed robot moves its free limb from hold c to hold d."""
    robot, terrain, s, qs, qg = planar
    res = find_path(robot, terrain, s, qs, qg, seed=3, max_iterations=20000, time_limit=20, cpu_limit=None,
                    direct=False)
    assert isinstance(res, PathResult) and res.found, res.stats
    assert np.allclose(res.path[0], qs) and np.allclose(res.path[-1], qg)
    verify_path(robot, terrain, s, res.path)
    assert set(res.stats["rejections"]) >= {"joint_limits", "equilibrium", "collision"}
    assert res.stats["roadmap_vertices"] >= 2


def test_same_seed_same_path(planar):
    robot, terrain, s, qs, qg = planar
    kw = dict(seed=5, max_iterations=5000, sampler="joint-by-joint+straight-elbow", space="projected", time_limit=30,
              cpu_limit=None, direct=False)
    a = find_path(robot, terrain, s, qs, qg, **kw)
    b = find_path(robot, terrain, s, qs, qg, **kw)
    assert a.status == b.status
    assert len(a.path) == len(b.path) and all(np.array_equal(x, y) for x, y in zip(a.path, b.path, strict=False))


@pytest.mark.heavy
@pytest.mark.parametrize("planner", PLANNER_NAMES)
def test_every_planner_runs(planar, planner):
    """Every registered planner on the projected space: no crash, a verified path or an honest failure."""
    robot, terrain, s, qs, qg = planar
    res = find_path(robot, terrain, s, qs, qg, planner=planner, time_limit=0.4, seed=0, simplify=False,
                    direct=False)
    assert res.status in ("exact", "no-path", "timeout")
    if res.found:
        verify_path(robot, terrain, s, res.path)


@pytest.mark.heavy
@pytest.mark.parametrize("space", SPACE_NAMES)
@pytest.mark.parametrize("planner", ["LazyPRM", "PRM", "RRTConnect"])
def test_every_space_runs(planar, space, planner):
    robot, terrain, s, qs, qg = planar
    res = find_path(robot, terrain, s, qs, qg, planner=planner, space=space, time_limit=1.0, seed=0,
                    direct=False)
    assert res.status in ("exact", "no-path", "timeout")
    if res.found:
        verify_path(robot, terrain, s, res.path)


def test_bad_input(planar):
    robot, terrain, s, qs, qg = planar
    with pytest.raises(PlannerNotFound, match="LazyPRM"):
        find_path(robot, terrain, s, qs, qg, planner="Nope")
    with pytest.raises(PlannerNotFound, match="projected"):
        find_path(robot, terrain, s, qs, qg, space="nope")
    with pytest.raises(PlannerNotFound, match="straight-elbow"):
        find_path(robot, terrain, s, qs, qg, sampler="nope")
    with pytest.raises(QueryError, match="no hold"):
        find_path(robot, terrain, Stance(limb1="a", limb2="zz"), qs, qg)
    with pytest.raises(QueryError, match="unknown limb"):
        find_path(robot, terrain, Stance(limb9="a", limb2="b"), qs, qg)
    bad = qs.copy()
    bad[0] += 0.1
    with pytest.raises(QueryError, match="violates the stance"):
        find_path(robot, terrain, s, bad, qg)
    with pytest.raises(QueryError, match="projected"):
        find_path(robot, terrain, s, qs, qg, space="atlas", sampler="straight-elbow")
    with pytest.raises(QueryError, match="adjacent"):
        find_transition(robot, terrain, s, Stance(limb1="c", limb2="d"))


def test_double_link_two_peg_stance_is_a_transition_only():
    """Bretl (2006), section 2.1: the double-link robot with both hands on pegs is a point (0-D stance):
    FIND-TRANSITION finds it by projection, FIND-PATH refuses it."""
    robot = RobotModel.load("double-link")
    terrain = Terrain.from_dict({"name": "pegs", "dim": 2, "holds": [
        {"id": "p0", "position": [0.0, 1.0], "normal": [0, 1], "type": "grasp", "max_force": 100},
        {"id": "p1", "position": [0.6, 1.3], "normal": [0, 1], "type": "grasp", "max_force": 100}]})
    s = Stance(a="p0", b="p1")
    q = find_transition(robot, terrain, s, None, seed=0, attempts=200)
    assert q is not None
    verify_path(robot, terrain, s, [q, q])
    with pytest.raises(QueryError, match="zero-dimensional"):
        find_path(robot, terrain, s, q, q)


# ---- double-link robot on pegs (Bretl (2006), sec. 2.1, Fig. 3-6) ---------------------------------------------
@pytest.fixture(scope="module")
def pegs():
    robot = RobotModel.load("double-link")
    return robot, Terrain.load("pegs")


def test_double_link_needs_no_equilibrium(pegs):
    """Bretl (2006), sec. 2.1: the peg-grabbing robot has no equilibrium (nor torque) check, only limits+collision."""
    robot, terrain = pegs
    assert robot.equilibrium is False and RobotModel.load("lemur").equilibrium is True
    names = [c.name for c in make_checks(robot, terrain, Stance(a="2"), torque="state")]
    assert names == ["joint_limits", "collision"]


@pytest.mark.parametrize("other", ["1", "3", "4"])
def test_double_link_transitions_on_pegs(pegs, other):
    """Bretl (2006), Fig. 3-6: hand a on peg 2, hand b grabs each neighbouring peg."""
    robot, terrain = pegs
    s = Stance(a="2")
    q = find_transition(robot, terrain, s, s.with_hold("b", other), seed=0)
    assert q is not None
    verify_path(robot, terrain, s.with_hold("b", other), [q, q])


def _torus_grid(robot, terrain, hold, n=121):
    """Brute force: collision-free cells of the one-hold stance's 2-D torus (bounded to +-2 pi) and their
    4-connected components, plus the components of the grid eroded by one cell (wide corridors only)."""
    from scipy import ndimage

    p = terrain.hold(hold).p
    th = np.linspace(-2 * np.pi, 2 * np.pi, n)
    free = np.array([[not robot.in_collision(np.array([p[0], p[2], a, b]), terrain, contact_limbs=("a",))
                      for b in th] for a in th])
    wide = ndimage.binary_erosion(free, structure=np.ones((3, 3)))
    return th, free, ndimage.label(free)[0], ndimage.label(wide)[0]


@pytest.mark.heavy
def test_double_link_find_path_matches_torus_grid(pegs):
    """FIND-PATH on the one-hold torus finds a path iff a brute-force grid says the configurations connect."""
    robot, terrain = pegs
    th, free, lab, lab_wide = _torus_grid(robot, terrain, "2")
    p = terrain.hold("2").p
    rng = np.random.default_rng(0)
    cells = np.argwhere(lab_wide > 0)
    same, diff = [], []
    while len(same) < 3 or len(diff) < 3:
        (i, j), (k, m) = cells[rng.integers(len(cells), size=2)]
        if lab_wide[i, j] == lab_wide[k, m] and len(same) < 3 and abs(i - k) + abs(j - m) > 20:
            same.append(((i, j), (k, m)))
        elif lab[i, j] != lab[k, m] and len(diff) < 3:
            diff.append(((i, j), (k, m)))
    for pairs, connected in ((same, True), (diff, False)):
        for (i, j), (k, m) in pairs:
            qa = np.array([p[0], p[2], th[i], th[j]])
            qb = np.array([p[0], p[2], th[k], th[m]])
            # a disconnected pair can never be solved, so a small budget suffices; a connected pair gets a large one
            budget = dict(max_iterations=20000, time_limit=60.0) if connected else dict(max_iterations=1500,
                                                                                        time_limit=2.0)
            res = find_path(robot, terrain, Stance(a="2"), qa, qb, seed=1, direct=False, **budget)
            assert res.found == connected, (qa, qb, res.status, res.stats)
            if res.found:
                verify_path(robot, terrain, Stance(a="2"), res.path)


def test_find_path_range_scales_with_the_extent(pegs):
    """Every planner with a range gets RANGE_FRACTION of the ambient bounds' diagonal (computed here from the
    bounds, not from OMPL's extent), for the double-link robot and LEMUR alike; an explicit ``range_`` wins; PRM
    has no range; the chart radius stays OMPL's unless ``rho`` is given; the projected space has no charts."""
    from climb_ompl.climb.onestep import RANGE_FRACTION
    from climb_ompl.manifold.stance import ambient_bounds

    robot, terrain = pegs
    lo, hi = ambient_bounds(robot, terrain)
    scale = RANGE_FRACTION * float(np.linalg.norm(hi - lo))
    p = terrain.hold("2").p
    qa, qb = np.array([p[0], p[2], 0.5, 1.0]), np.array([p[0], p[2], 0.6, 1.1])
    run = dict(seed=1, direct=False, max_iterations=200, time_limit=5.0)
    for planner in ("RRTConnect", "LazyPRM", "BiEST", "KPIECE1"):
        st = find_path(robot, terrain, Stance(a="2"), qa, qb, planner=planner, space="atlas", **run).stats
        assert st["range"] == pytest.approx(scale) and st["rho"] == pytest.approx(0.25), planner
    st = find_path(robot, terrain, Stance(a="2"), qa, qb, range_=0.4, rho=0.3, **run).stats
    assert (st["range"], st["rho"]) == (pytest.approx(0.4), pytest.approx(0.3))
    st = find_path(robot, terrain, Stance(a="2"), qa, qb, planner="PRM", space="projected", **run).stats
    assert st["range"] is None and st["rho"] is None
    lemur, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    lo, hi = ambient_bounds(lemur, wall)
    assert RANGE_FRACTION * float(np.linalg.norm(hi - lo)) == pytest.approx(0.759, abs=0.01)  # docs/onestep.md


def test_scaled_range_solves_a_winding_double_link_query_ompls_default_does_not(pegs):
    """Why the range is scaled (docs/bench.md): on a double-link query that winds an angle by a whole turn on
    the one-peg torus (hand a on peg 2), RRTConnect/atlas with OMPL's range (0.2 of the extent) spends its 2000
    checks on long extensions that end in a collision and are discarded whole, and finds nothing on seeds 1 and
    2; with the scaled range it finds a path on both, which verifies."""
    from climb_ompl.bench._query_set import load_set
    from climb_ompl.manifold.stance import ambient_bounds

    robot, terrain = pegs
    (q,) = [q for q in load_set("double-link-pegs")["queries"] if q["uid"] == 5002]
    assert abs(q["q_goal"][3] - q["q_start"][3]) > np.pi  # it winds
    lo, hi = ambient_bounds(robot, terrain)
    run = dict(planner="RRTConnect", space="atlas", direct=False, max_iterations=2000, time_limit=30.0)
    for seed in (1, 2):
        old = find_path(robot, terrain, q["stance"], q["q_start"], q["q_goal"], seed=seed, **run,
                        range_=0.2 * float(np.linalg.norm(hi - lo)))
        assert old.status == "no-path", old.stats
        new = find_path(robot, terrain, q["stance"], q["q_start"], q["q_goal"], seed=seed, **run)
        assert new.found, new.stats
        verify_path(robot, terrain, Stance(q["stance"]), new.path)


@pytest.mark.slow
def test_lemur_grab_release_on_demo_wall():
    """LEMUR releases one hold and grabs a neighbouring one on the demo wall (Bretl et al. (2004))."""
    from climb_ompl.bench._runs import make_queries

    robot = RobotModel.load("lemur")
    terrain = Terrain.load("demo-wall")
    (d,) = make_queries("lemur", "demo-wall", 1, seed=0)
    s, qs, qg = Stance(d["stance"]), np.asarray(d["q_start"]), np.asarray(d["q_goal"])
    res = find_path(robot, terrain, s, qs, qg, seed=0, time_limit=60)
    assert res.found, res.stats
    verify_path(robot, terrain, s, res.path)


# ---- cheap local plan first, densified waypoints checked ---------------------------------------------------
@pytest.fixture(scope="module")
def crack():
    """Bretl, Latombe & Rock (2003), section 3 on the bundled crack: limbs 1/2 on L2/R2, limb 3
    from L4 (start) to R4 (goal)."""
    robot, terrain = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    s = Stance(limb1="L2", limb2="R2")
    qs = find_transition(robot, terrain, s, s.with_hold("limb3", "L4"), seed=0)
    qg = find_transition(robot, terrain, s, s.with_hold("limb3", "R4"), seed=0, near=qs)
    assert qs is not None and qg is not None
    return robot, terrain, s, qs, qg


def test_direct_lift_move_place_is_verified(crack):
    """A goal with the free hand lifted off its hold: the direct local path (tried before the planner)
    solves it without a roadmap, and the path passes the independent verifier."""

    robot, terrain, s, qs, _ = crack
    lb = s.free_limbs(robot)[0]
    h = terrain.hold("L4")
    qg = robot.limb_ik_nearest(lb, qs, h.p + 0.04 * h.n, qs)
    assert qg is not None and not np.array_equal(qg, qs)
    res = find_path(robot, terrain, s, qs, qg, seed=0, max_iterations=20000, time_limit=20)
    assert res.found and res.stats["direct"] is True, res.stats
    assert res.stats["roadmap_vertices"] == 0
    verify_path(robot, terrain, s, res.path)


def test_planar_crack_move_verified(crack):
    """The figure's move (docs/onestep_planar3.png): limb 3 from L4 to R4, planned and verified."""
    robot, terrain, s, qs, qg = crack
    res = find_path(robot, terrain, s, qs, qg, sampler="joint-by-joint+straight-elbow+free-limb+lift",
                    space="projected", seed=0,
                    max_iterations=20000, time_limit=30)
    assert res.found, res.stats
    verify_path(robot, terrain, s, res.path)


def test_direct_checks_every_waypoint(crack):
    """The direct local path fails as soon as one waypoint is infeasible; otherwise every waypoint passes the
    stance's checks, keeps the hands on their holds and moves no joint more than ``max_step``."""
    from climb_ompl.climb.local_path import LocalPath
    from climb_ompl.manifold.feasibility import Feasibility

    robot, terrain, s, qs, qg = crack
    feas = Feasibility(robot, terrain)
    lp = LocalPath(feas, max_step=0.05)
    path = lp(s, qs, qg, s.free_limbs(robot)[0])
    assert path is not None and lp.found == 1
    assert all(feas.valid_moving(s, q) for q in path[1:-1])
    for q in path:
        for limb, hold in s.pairs:
            assert np.linalg.norm(robot.hand_position(q, limb) - terrain.hold(hold).p) <= 1e-5
    assert max(np.max(np.abs(b - a)) for a, b in zip(path[:-1], path[1:], strict=False)) <= 0.05 + 1e-9
    feas.why_moving = lambda stance, q: "torque"  # every intermediate waypoint rejected, by the torque check
    lp = LocalPath(feas, max_step=0.05)
    assert lp(s, qs, qg, s.free_limbs(robot)[0]) is None and lp.failures.get("torque", 0) >= 1


@pytest.mark.parametrize("delta", [0.05, 0.3])
def test_densified_waypoints_checked_at_any_delta(planar, delta):
    """With a coarse geodesic step every stored waypoint still passes the independent verifier."""
    robot, terrain, s, qs, qg = planar
    res = find_path(robot, terrain, s, qs, qg, seed=4, max_iterations=20000, time_limit=20, direct=False,
                    delta=delta)
    assert res.found, res.stats
    assert res.stats["dense_rejected_states"] >= 0
    verify_path(robot, terrain, s, res.path)


def test_local_draws_follow_the_query_segment(planar):
    """Local draws put the base near the start-goal segment and keep the IK branches of its end points."""
    from climb_ompl.manifold.samplers import SamplingCore
    from climb_ompl.manifold.stance import StanceConstraint

    robot, terrain, s, qs, qg = planar
    con = StanceConstraint(robot, terrain, s)
    kw = dict(seed=0, uniform_fraction=0.0)
    local = SamplingCore(robot, terrain, s, con, "joint-by-joint", segment=(qs, qg), local_fraction=1.0, **kw)
    glob = SamplingCore(robot, terrain, s, con, "joint-by-joint", **kw)
    b = list(robot.base_indices)

    def dist(core):
        d = []
        for _ in range(40):
            q = core.draw()
            assert con.satisfied(q)
            t = np.clip(np.dot(q[b] - qs[b], qg[b] - qs[b]) / max(1e-12, np.dot(qg[b] - qs[b], qg[b] - qs[b])), 0, 1)
            d.append(np.linalg.norm(q[b] - (qs[b] + t * (qg[b] - qs[b]))))
        return float(np.median(d))

    assert dist(local) < 0.5 * dist(glob)
    assert local.ref is None  # the reference is restored after each local draw


@pytest.mark.heavy
def test_the_budget_counts_this_process_cpu_time_apart_from_the_wall_clock():
    """FIND-PATH's CPU-time guard (the climb's ``step_time_limit``): a sleeping process spends wall time but no CPU
    time, so the CPU limit does not end the call while it sleeps; busy work ends it once the process has used that
    much CPU, the wall-clock limit being far away.  Neither counts validity checks."""
    import time

    from climb_ompl.climb.onestep import _Budget

    class Checker:
        calls = 0

    c0 = time.process_time()  # before the budget starts its clock: the CPU time it counts is at most this span
    b = _Budget(Checker(), 100.0, None, cpu_limit=0.2)
    time.sleep(0.3)  # wall time passes, little CPU time
    assert not b() and not b.timed_out
    while not b():
        sum(range(1000))
    assert b.timed_out and time.process_time() - c0 >= 0.2
    assert _Budget(Checker(), 100.0, 5, cpu_limit=None)() is False  # no check made yet, no time limit hit


@pytest.mark.heavy
def test_step_ends_of_a_step_a_climb_took():
    """The ends of a one-step move that a climb made (``climb-ompl plan --robot go1 --terrain
    stepping-stone-ramp-3m --climb 0.3 --seed 1``, its second step: the front left foot from s3_4 to s6_2, the
    others on s3_2, s0_4, s0_2): the climb's plan is the oracle that they exist.  Drawn about the nominal posture
    alone, the start left s6_2 out of reach and ``climb-ompl onestep`` said "no feasible goal"; the ends touch
    their holds (the foot spheres' centres 2 cm from the hold points) and a path joins them."""
    from climb_ompl.climb.onestep import step_ends

    robot, ramp = RobotModel.load("go1"), Terrain.load("stepping-stone-ramp-3m")
    s = Stance(fr="s3_2", rl="s0_4", rr="s0_2")
    qs, qg = step_ends(robot, ramp, s, "fl", "s3_4", "s6_2", seed=0)
    assert qs is not None and qg is not None
    for q, hold in ((qs, "s3_4"), (qg, "s6_2")):
        for limb, h in {**s.to_dict(), "fl": hold}.items():
            gap = np.linalg.norm(robot.hand_position(q, limb) - ramp.hold(h).p)
            assert abs(gap - 0.02) < 1e-4, (limb, h, gap)
    assert find_path(robot, ramp, s, qs, qg, seed=0, max_iterations=2000).found
