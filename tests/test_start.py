"""The start finder (climb_ompl.climb.start): candidates among the lowest holds, ranked by the support region at the
nominal stand-off, and a diagnosis naming the failing check when no start exists; "up" is minus gravity."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest
import yaml

from climb_ompl.climb.goal import Goal
from climb_ompl.climb.multistep import default_start
from climb_ompl.climb.start import candidate_stances, find_start, lowest_stance, wall_axes
from climb_ompl.manifold.stance import Stance
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain
from climb_ompl.verification.climb import goal_met


def grid_wall(spacing: float, n: int = 4, *, friction: float = 1.0, normal=(0.0, 0.5, 0.866),
              surfaces=(), gravity=(0.0, 0.0, -9.81)) -> dict:
    """A vertical wall (plane y = 0) with an ``n`` x ``n`` grid of holds ``h<row>_<column>``, as a terrain dict."""
    holds = [{"id": f"h{i}_{j}", "position": [spacing * (j - (n - 1) / 2), 0.0, spacing * i],
              "normal": list(normal), "friction": friction} for i in range(n) for j in range(n)]
    return {"name": "grid", "dim": 3, "gravity": list(gravity), "holds": holds,
            "surfaces": [{"type": "plane", "point": [0, 0, 0], "normal": [0, 1, 0]}, *surfaces]}


@pytest.fixture(scope="module")
def lemur() -> RobotModel:
    return RobotModel.load("lemur")


def test_bundled_start_is_the_first_candidate(lemur):
    """On the demo wall the nominal layout at the bottom middle ranks first (its support region holds the CoM at
    the nominal stand-off) and is the start found; candidates whose region holds the CoM come first."""
    wall = Terrain.load("demo-wall")
    cands = candidate_stances(lemur, wall)
    assert len(cands) > 6 and len({tuple(sorted(c.stance.items())) for c in cands}) == len(cands)
    assert cands[0].stance == lowest_stance(lemur, wall) and cands[0].score > 0
    inside = [c.score >= 0 for c in cands]
    assert inside == sorted(inside, reverse=True)
    stance, q = default_start(lemur, wall, seed=0)
    assert stance == cands[0].stance and lemur.within_limits(q)


def test_no_start_out_of_reach(lemur):
    """Holds 1.5 m apart (LEMUR's limbs reach 0.42 m): every candidate fails, diagnosed as reach, per limb."""
    t = Terrain.from_dict(grid_wall(1.5))
    res = find_start(lemur, t, seed=0)
    assert not res.found and res.q is None and res.diagnoses
    d = res.diagnoses[0]
    assert set(d.checks) == {"reach"} and len(d.reasons) >= 2
    for line in d.reasons:
        dist, reach = (float(x) for x in re.findall(r"([0-9.]+) m", line)[:2])
        assert dist > reach == pytest.approx(lemur.limb(line.split()[2]).reach, abs=1e-3)
    assert "out of reach" in res.explain("lemur", "grid")


def test_no_start_no_equilibrium(lemur):
    """Holds facing straight out of a vertical wall with friction 0.05: no forces in the friction cones balance
    gravity (the vertical force is at most 0.05 times the net normal force, which must vanish): the diagnosis
    is equilibrium, with an empty support region."""
    t = Terrain.from_dict(grid_wall(0.25, normal=(0.0, 1.0, 0.0), friction=0.05))
    res = find_start(lemur, t, seed=0)
    assert not res.found
    assert all("equilibrium" in d.checks for d in res.diagnoses)
    assert all(d.score == -math.inf for d in res.diagnoses)
    assert "empty support region" in str(res.diagnoses[0])


def test_cli_advice_when_no_stance_of_the_holds_can_balance(tmp_path, cli):
    """On that wall (friction 0.05, normals straight out: no forces in the cones balance gravity) `plan` does not
    send the user to --start, which is checked the same way, but says that the holds cannot carry the robot."""
    path = tmp_path / "slippery.yaml"
    path.write_text(yaml.safe_dump(grid_wall(0.25, normal=(0.0, 1.0, 0.0), friction=0.05)))
    r = cli("plan", "--robot", "lemur", "--terrain", path, "--goal-height", "1.0", "--out", tmp_path / "p.json")
    assert r.code == 1 and "every candidate diagnosed fails on equilibrium" in r.err
    assert "give a start stance" not in r.err
    assert not (tmp_path / "p.json").exists()


def test_no_start_collision_names_the_links(lemur):
    """A slab 9-15 cm in front of the wall leaves room for the limbs but not for LEMUR's body: the diagnosis
    names the chassis and the slab (terrain surface 1, a box)."""
    box = {"type": "box", "center": [0.0, 0.12, 0.6], "size": [3.0, 0.06, 3.0]}
    t = Terrain.from_dict(grid_wall(0.25, n=6, surfaces=[box]))
    res = find_start(lemur, t, seed=0)
    assert not res.found
    d = res.diagnoses[0]
    assert "collision" in d.checks
    assert "collision: chassis with terrain 1 box" in d.reasons
    assert d.rejections.get("collision", 0) > 0  # the finder's draws were rejected by the same check


def test_cli_plan_without_a_start_exits_1_with_the_reasons(tmp_path, cli):
    """`climb-ompl plan` with no --start on a wall without a start: exit 1, the reasons on stderr, no file."""
    path = tmp_path / "far.yaml"
    path.write_text(yaml.safe_dump(grid_wall(1.5)))
    out = tmp_path / "plan.json"
    r = cli("plan", "--robot", "lemur", "--terrain", path, "--goal-height", "1.0", "--out", out)
    assert r.code == 1
    assert "no feasible start stance" in r.err and "reach: limb" in r.err and "--start" in r.err
    assert not out.exists()


def test_the_start_finders_time_limit_stops_it_between_candidates(lemur, tmp_path, cli):
    """With no start to find (holds 1.5 m apart), the finder tries its 12 best candidates; with a time limit
    already spent it tries one (the one under way finishes), says that the budget stopped it, and diagnoses
    that one.  ``plan --time-limit`` gives the finder the same budget: exit 1, the reason, no file."""
    t = Terrain.from_dict(grid_wall(1.5))
    full = find_start(lemur, t, seed=0)
    assert len(full.tried) == 12 and full.spent is None and "budget" not in full.explain()
    cut = find_start(lemur, t, seed=0, time_limit=0.0)
    assert not cut.found and len(cut.tried) == 1 and cut.spent == 0.0
    assert cut.tried[0].stance == full.tried[0].stance and len(cut.diagnoses) == 1
    assert "1 of" in cut.explain() and "the start finder's budget of 0 s spent" in cut.explain()
    path, out = tmp_path / "far.yaml", tmp_path / "plan.json"
    path.write_text(yaml.safe_dump(grid_wall(1.5)))
    r = cli("plan", "--robot", "lemur", "--terrain", path, "--goal-height", "1.0", "--time-limit", "1e-9",
            "--out", out)
    assert r.code == 1 and "the start finder's budget of 1e-09 s spent" in r.err and not out.exists()


# ---- up is minus gravity ------------------------------------------------------------------------------------
@pytest.mark.parametrize("gravity", [(0.0, -9.476, -2.539),  # a ramp: tilted about x
                                     (-9.81 * math.sin(0.4), 0.0, -9.81 * math.cos(0.4))])  # tilted along the wall
def test_goal_height_is_measured_along_minus_gravity(gravity):
    """Goal.met and verify.goal_met compare heights along -g/|g| (oracle: the dot product with the gravity as
    written); at the height chosen between the z test and the height test the two disagree."""
    t = Terrain.from_dict(grid_wall(0.25, gravity=gravity))
    up = -np.asarray(gravity) / np.linalg.norm(gravity)
    stance = {"a": "h1_1", "b": "h2_3"}
    heights = [float(t.hold(h).p @ up) for h in stance.values()]
    zs = [float(t.hold(h).p[2]) for h in stance.values()]
    assert [t.height(h) for h in stance.values()] == pytest.approx(heights, abs=1e-12)
    reach = 0.3
    for h, want in ((min(heights) + reach - 1e-9, True), (min(heights) + reach + 1e-6, False),
                    (0.5 * (min(heights) + min(zs)) + reach, False)):
        assert Goal("height", height=h).met(stance, t, reach) is want
        assert goal_met({"type": "height", "height": h}, stance, t, reach) is want
    assert min(zs) > min(heights) + 1e-3  # (the last height is met in z: the test tells the two apart)


def test_wall_axes_follow_gravity():
    """The start finder's plane axes: across the wall and up the wall (minus gravity made parallel to the wall);
    on the demo wall exactly x and z, so bundled starts are unchanged."""
    a, v = wall_axes(Terrain.load("demo-wall"))
    assert np.array_equal(np.abs(a), [1, 0, 0]) and np.array_equal(np.abs(v), [0, 0, 1]) and a[0] > 0 and v[2] > 0
    g = np.array([-math.sin(0.4), 0.0, -math.cos(0.4)])
    a, v = wall_axes(Terrain.from_dict(grid_wall(0.25, gravity=9.81 * g)))
    assert np.allclose(v, -g) and abs(a @ v) < 1e-12 and abs(a[1]) < 1e-12


def test_lowest_stance_on_a_wall_tilted_sideways(lemur):
    """Gravity tilted 0.4 rad along the wall: the start stance sits on the holds lowest along minus gravity."""
    g = 9.81 * np.array([-math.sin(0.4), 0.0, -math.cos(0.4)])
    t = Terrain.from_dict(grid_wall(0.2, n=9, gravity=g, normal=(0.0, 1.0, 0.0)))
    st = Stance(lowest_stance(lemur, t))
    h = sorted(t.height(x) for x in t.hold_ids)
    assert min(t.height(x) for x in st.hold_ids) <= h[len(h) // 4]  # among the lowest quarter
    # the layout is turned with "up": not the stance an untilted wall gives
    assert dict(st) != lowest_stance(lemur, Terrain.from_dict(grid_wall(0.2, n=9, normal=(0.0, 1.0, 0.0))))


@pytest.mark.heavy
def test_start_with_the_com_outside_the_region_at_the_nominal_stand_off():
    """Go1 on the suite's overhang: at the nominal stand-off the CoM is 0.15 m outside every candidate's
    support region, so FIND-TRANSITION's CoM prefilter cuts most draws from there (with the base's translations
    drawn six times wider, as when the spec's base was taken for six angles, it found nothing); the start finder
    tries that candidate first and brings the CoM inside (:func:`closest_com`).  That configuration is checked
    independently:
    every foot's contact point on its hold, the CoM inside the region, joints within limits, no collision."""
    from climb_ompl.climb.start import _from_closest, diagnose_stance
    from climb_ompl.climb.transition import TransitionFinder, nominal_near
    from climb_ompl.manifold.closure import closest_com
    from climb_ompl.manifold.feasibility import Feasibility

    go1 = RobotModel.load("go1")
    wall = Terrain.load("overhang")
    feas = Feasibility.of(go1, wall)
    best = candidate_stances(go1, wall, feas)[0]
    sigma = Stance(best.stance)
    assert best.score < -0.1
    near = nominal_near(go1, wall, sigma)
    st = find_start(go1, wall, seed=0)
    assert st.found and st.tried[0].stance == best.stance  # (a later candidate if this one cannot let go)
    q = _from_closest(feas, sigma, TransitionFinder(feas, ik_tries=60), 0)
    assert q is not None
    for lb, h in best.stance.items():
        hold = wall.hold(h)
        contact = go1.hand_position(q, lb) - go1.limb(lb).contact.radius * hold.n / np.linalg.norm(hold.n)
        assert np.linalg.norm(contact - hold.p) < 1e-3
    assert feas.region(sigma).margin(go1.com(q)) >= 0
    assert np.all(q >= go1.lower - 1e-9) and np.all(q <= go1.upper + 1e-9)
    assert not go1.in_collision(q, wall, contact_limbs=sigma.limbs, clearance=feas.clearance)
    # the diagnosis no longer claims the nominal stand-off's distance as the last word
    m, n, _ = closest_com(go1, wall, sigma, sigma, feas, near)
    assert m >= 0 and n > 0
    eq = [r for r in diagnose_stance(go1, wall, sigma, feas).reasons if r.startswith("equilibrium")]
    assert eq and "has it inside" in eq[0] and "not a proof" in eq[0]
    # and says what fails at that configuration, or that nothing does (the stance's checks, run directly)
    _, _, q_in = closest_com(go1, wall, sigma, sigma, feas, near)
    assert ("every check passes" in eq[0]) == feas.valid(sigma, q_in)
    assert "every check passes" in eq[0] or ": there, " in eq[0]
    # where a climb stopped (a configuration given), a configuration passing every check points to the walk
    eq = [r for r in diagnose_stance(go1, wall, sigma, feas, near=near, where="the configuration reached").reasons
          if r.startswith("equilibrium")]
    assert eq[0].startswith("equilibrium: at the configuration reached the CoM is")
    assert ("--set transition_walk=100" in eq[0]) == feas.valid(sigma, q_in)


def test_a_hold_within_reach_but_beyond_the_joint_limits_names_the_joints():
    """Go1's front-left foot placed by forward kinematics with the hip abducted to -1.5 rad (its limit is -0.863):
    no inverse-kinematics solution within the limits, and the diagnosis names the hip joint at -1.5 rad; a foot
    target within the limits names nothing."""
    from climb_ompl.climb.start import diagnose_stance, limits_needed

    go1 = RobotModel.load("go1")
    q = np.array(go1.nominal_q, dtype=float)
    x = q.copy()
    x[go1.limb("fl").joint_indices[0]] = -1.5
    target = go1.hand_position(x, "fl")
    assert go1.limb_ik("fl", q, target) == []
    (need,) = limits_needed(go1, "fl", q, target)
    assert need[0] == "FL_hip_joint" and need[1] == pytest.approx(-1.5, abs=1e-6)
    assert need[2:] == pytest.approx((-0.863, 0.863), abs=1e-3)
    assert limits_needed(go1, "fl", q, go1.hand_position(q, "fl")) == []
    # the same through the stance diagnosis: holds under the feet (sphere feet: the hold is r below the centre)
    feet = {lb.name: go1.hand_position(x, lb.name) for lb in go1.limbs}
    n = np.array([0.0, 1.0, 0.0])
    holds = [{"id": f"f_{lb}", "position": list(p - 0.02 * n), "normal": list(n), "friction": 1.0}
             for lb, p in feet.items()]
    wall = Terrain.from_dict({"name": "feet", "dim": 3, "gravity": [0, 0, -9.81], "holds": holds, "surfaces": []})
    d = diagnose_stance(go1, wall, Stance({lb: f"f_{lb}" for lb in feet}), near=q, where="the test posture")
    reach = [r for r in d.reasons if r.startswith("reach: limb fl")]
    assert reach and "FL_hip_joint = -1.500 outside [-0.863, 0.863]" in reach[0]
    # a hold inside the leg's reach sphere but in no posture of it, even with its joints free of their limits (2 cm
    # from the hip joint): said so, rather than "within the joint limits" with no joint named
    from climb_ompl.climb.start import free_solutions
    from climb_ompl.model.reach import shoulders

    inside = shoulders(go1, q)["fl"] + np.array([0.0, 0.0, 0.02])
    assert free_solutions(go1, "fl", q, inside) == []
    holds[0] = {**holds[0], "position": list(inside - 0.02 * n)}
    wall = Terrain.from_dict({"name": "feet", "dim": 3, "gravity": [0, 0, -9.81], "holds": holds, "surfaces": []})
    d = diagnose_stance(go1, wall, Stance({lb: f"f_{lb}" for lb in feet}), near=q, where="the test posture")
    (reach,) = [r for r in d.reasons if r.startswith("reach: limb fl")]
    assert "not even beyond the joint limits" in reach and "outside its workspace" in reach


@pytest.mark.climb
def test_plan_climb_finds_the_start_posture_find_start_finds():
    """Without ``q_start``, ``plan_climb`` (what ``climb-ompl plan`` calls) starts from the posture the start
    finder would give the stance (for ANYmal-C on the demo wall the CoM at the nominal stand-off is outside the
    support region).  It used to answer "no feasible configuration found for the start stance"."""
    from climb_ompl.climb.multistep import plan_climb
    from climb_ompl.climb.start import find_start, start_configuration
    from climb_ompl.manifold.feasibility import Feasibility
    from climb_ompl.manifold.stance import Stance, StanceConstraint
    from climb_ompl.model.terrain import Terrain

    r, wall = RobotModel.load("anymal-c"), Terrain.load("demo-wall")
    stance = find_start(r, wall, seed=0).stance
    q = start_configuration(r, wall, stance, seed=0)
    assert q is not None
    assert StanceConstraint(r, wall, Stance(stance), 1e-3).error(q) <= 1e-3  # every foot on its hold
    assert Feasibility.of(r, wall).valid(Stance(stance), q)
    res = plan_climb(r, wall, stance, 0.0, seed=0, time_limit=60)  # a goal the start meets
    assert res.found, res.reason
    assert np.allclose(res.plan.query["start"]["q"], q)


def test_a_torque_diagnosis_names_the_joint_and_the_amount():
    """With LEMUR's torque limits cut to a few percent, the start stance's diagnosis names the joint that limits
    the balanced contact forces and by how much.  The smallest largest torque ratio scales inversely with the
    limits (halving every limit doubles it): an oracle independent of the solver."""
    from climb_ompl.climb.start import diagnose_stance

    lemur, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    stance = {"ne": "h36", "nw": "h33", "sw": "h3", "se": "h6"}
    full = lemur.torque_limits.copy()
    ratios = []
    for scale in (0.02, 0.01):
        lemur.torque_limits = full * scale
        line = next(r for r in diagnose_stance(lemur, wall, stance).reasons if r.startswith("torque limits"))
        m = re.search(r"at best (\S+) needs ([0-9.]+) x its limit", line)
        assert m is not None, line
        assert m.group(1) in lemur.joint_names
        ratios.append(float(m.group(2)))
    assert ratios[0] > 1.0 and ratios[1] == pytest.approx(2 * ratios[0], rel=0.01)


def test_onestep_says_why_its_start_is_infeasible(cli):
    """``onestep`` with a start no transition reaches (a hold 3 m above the others) names the failing check, as
    ``plan`` does for a start stance, instead of only "no feasible start"."""
    r = cli("onestep", "lemur", "demo-wall", "--stance", "nw=h33,sw=h3,se=h6", "--limb", "ne", "--from", "h177",
            "--to", "h36")
    assert r.code == 1
    assert "no feasible start with ne on h177; with ne touching h177, the others carrying the robot:" in r.err
    assert "reach: limb ne cannot reach hold h177" in r.err
    # a misspelt planner is bad input, refused before the transitions are searched (it was reported only after
    # them, and an infeasible start then hid it behind exit 1)
    r = cli("onestep", "lemur", "demo-wall", "--stance", "nw=h33,sw=h3,se=h6", "--limb", "ne", "--from", "h177",
            "--to", "h36", "--planner", "rrtconect")
    assert r.code == 2 and "--planner: unknown planner 'rrtconect'" in r.err and "RRTConnect" in r.err


def test_angle_joints_of_a_base_built_from_the_spec():
    """A spatial base built from the spec is one composite joint of six coordinates: its translations are not
    angles (the oracle: the joints' names, ``base_x/y/z`` and ``base_rz/ry/rx``)."""
    for name in ("go1", "lemur"):
        robot = RobotModel.load(name)
        base = list(robot.base_indices)
        names = [robot.joint_names[j] for j in base]
        expected = [not n.endswith(("_x", "_y", "_z")) for n in names]
        assert list(robot.angle_joints[base]) == expected, names


@pytest.mark.heavy
def test_the_nominal_start_moves_with_the_terrain():
    """The ramp's stones moved 3.9 m along its plane: the least squares over every base coordinate would reach
    them in part by pitching the base a radian, beyond its bounds (no start was found).  The start posture is the
    nominal one translated so that the feet's centroid lands on their targets' (the closed form: a translation of
    the base moves every foot by itself), unturned, and a start is found."""
    from climb_ompl.climb.transition import nominal_near
    from climb_ompl.manifold.stance import hand_targets

    go1 = RobotModel.load("go1")
    data = Terrain.load("stepping-stone-ramp-3m").to_dict()
    shift = np.array([0.0, 0.0, 3.9])
    for h in data["holds"]:
        h["position"] = list(np.asarray(h["position"], dtype=float) + shift)
    for s in data.get("surfaces", []):
        s["point"] = list(np.asarray(s["point"], dtype=float) + shift)
    far = Terrain.from_dict(data)
    sigma = Stance({"fl": "s3_4", "fr": "s3_2", "rl": "s0_4", "rr": "s0_2"})
    base = list(go1.base_indices)
    nominal = np.asarray(go1.nominal_q, dtype=float)
    feet = np.asarray(go1.hand_positions(nominal), dtype=float).mean(axis=0)
    target = np.mean(list(hand_targets(go1, far, sigma).values()), axis=0)
    q = nominal_near(go1, far, sigma)[base]
    assert np.allclose(q[:3], nominal[base][:3] + target - feet, atol=1e-6)
    assert np.allclose(q[3:], nominal[base][3:], atol=1e-6)
    assert find_start(go1, far, seed=0).found
