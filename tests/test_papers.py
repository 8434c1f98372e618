"""The figures of ``docs/papers.md`` that ``climb_ompl.bench.papers`` measures: small, fast versions."""

from __future__ import annotations

import math

import numpy as np
import pytest

from climb_ompl.bench import papers


def test_onestep_times_by_hand() -> None:
    """Bretl et al. (2004), Fig. 6 figures on a hand-made sample (unsolved queries are left out)."""
    r = papers.onestep_times([0.1, 0.2, 0.3, 3.0, 25.0, 9.0], [True, True, True, True, False, True])
    assert r["solved"] == 5 and r["queries"] == 6
    assert r["min_s"] == 0.1 and r["max_s"] == 9.0 and r["mean_s"] == pytest.approx(12.6 / 5)
    assert r["median_s"] == 0.3 and r["share_below_mean"] == pytest.approx(3 / 5)
    assert r["solved_within_2s"] == 3 and r["solved_within_20s"] == 5 and r["share_above_2s"] == pytest.approx(2 / 5)
    assert papers.onestep_times([1.0], [False]) == {"solved": 0, "queries": 1}


def test_wilson_interval_closed_forms() -> None:
    assert papers._wilson(0, 10) == pytest.approx((0.0, 1.96**2 / (10 + 1.96**2)))
    lo, hi = papers._wilson(5, 10)
    assert lo + hi == pytest.approx(1.0) and lo < 0.5 < hi


def test_moving_average_keeps_lines_and_k0() -> None:
    P = np.column_stack([np.zeros(7), np.zeros(7), np.arange(7.0)])
    assert np.array_equal(papers._moving_average(P, 0), P)
    S = papers._moving_average(P, 2)
    assert np.allclose(S[2:-2], P[2:-2])  # interior points of a straight, evenly sampled line stay put
    assert S[0, 2] == pytest.approx(1.0)  # the ends are truncated windows


def test_joint_by_joint_beats_uniform_sampling_within_limits() -> None:
    """Bretl (2006), sec. 4.3: sampling joint by joint gives far more in-limit samples than projecting uniform
    samples onto the stance manifold (the paper: < 5 % -> > 75 %; docs/papers.md gives our shares)."""
    r = papers.sampling_gain(n=40, seed=0)
    for s in r["stances"]:
        u, j = s["uniform"], s["joint_by_joint"]
        assert u["in_limits"] <= u["projected"] <= 40 and j["feasible"] <= j["in_limits"] <= 40
        assert j["share_in_limits"] > 2 * u["share_in_limits"], s


def test_fig13_factors_match_the_comparison_module() -> None:
    """The factor table's default row is what ``treebot.compare`` gives on the same generated tree."""
    from climb_ompl.treebot import compare, generate_tree

    row = papers.treebot_fig13_factors(trees=1, points=(16,), smooth=(0,), fits=("geometric",))[0]
    g = generate_tree(1000, n_branches=3, curvature=1.0, obstacle_patches=8)
    c = compare(g, g.branches[-1].name)
    for m in ("proposed", "simple"):
        assert row[m]["following_mm"] == pytest.approx(c[m].mean_error * 1e3)
        assert row[m]["segment_mm"] == pytest.approx(c[m].segment_mean_error * 1e3)


def test_arc_fit_choice_reaches_the_proposed_method() -> None:
    """``arc_fit`` changes the proposed motion on a kinked path (Eq. 11-17 vs. the geometric fit), never the
    simple one; an unknown fit is refused."""
    from climb_ompl.treebot.motion import plan_motion
    from climb_ompl.treebot.tree import RobotParams

    s = np.arange(0.0, 1.2, 0.05)
    y = np.where(s > 0.5, 0.3 * (s - 0.5), 0.0) + 0.004 * np.sin(37 * s)  # a kink and some noise
    P = np.column_stack([np.zeros_like(s), y, s])
    N = np.tile([1.0, 0.0, 0.0], (len(s), 1))
    robot = RobotParams()
    a = plan_motion(P, N, robot, "proposed", arc_fit="geometric")
    b = plan_motion(P, N, robot, "proposed", arc_fit="algebraic")
    va = [st["v_rg"] for st in a.steps if "v_rg" in st]
    vb = [st["v_rg"] for st in b.steps if "v_rg" in st]
    assert len(va) == len(vb) > 0 and not np.allclose(va, vb)
    sa = plan_motion(P, N, robot, "simple", arc_fit="geometric")
    sb = plan_motion(P, N, robot, "simple", arc_fit="algebraic")
    assert np.allclose(sa.frames[-1].body, sb.frames[-1].body)
    with pytest.raises(ValueError, match="arc fit"):
        plan_motion(P, N, robot, "proposed", arc_fit="least-squares")
    assert math.isfinite(a.frames[-1].body.sum())


def test_fig13_three_branch_matches_the_comparison_module() -> None:
    """The bundled tree's row (target b2) is what ``treebot.compare`` gives, as ``bench treebot`` reports it."""
    from climb_ompl.treebot import Tree, compare

    row = papers.treebot_fig13_three_branch(smooth=(0,), fits=("geometric",))[0]
    c = compare(Tree.load("three-branch"), "b2")
    assert row["points"] == 16 and row["trees"] == 1
    for m in ("proposed", "simple"):
        assert row[m]["following_mm"] == pytest.approx(c[m].mean_error * 1e3)


def test_joint_by_joint_failure_causes_agree_with_the_sampler() -> None:
    """A base pose is classified ``closed`` exactly when the sampler's own closure succeeds within limits, and
    every other class names a real obstacle (the closure fails)."""
    from climb_ompl.climb.multistep import default_start, load_robot, load_terrain
    from climb_ompl.manifold.samplers import make_core
    from climb_ompl.manifold.stance import JointLimitsCheck, Stance, StanceConstraint

    rob, ter = load_robot("lemur"), load_terrain("demo-wall")
    start, _ = default_start(rob, ter, seed=0)
    stance = Stance(start)
    con = StanceConstraint(rob, ter, stance)
    core = make_core(rob, ter, stance, con, "joint-by-joint", seed=3, uniform_fraction=0.0)
    limits, seen = JointLimitsCheck(rob), set()
    lo, hi = rob.lower.copy(), rob.upper.copy()
    for _ in range(60):
        q = core._place_base(core.rng.uniform(core.jlo, core.jhi), core._radius)
        cause = papers._jbj_failure(core, rob, q)
        closed = core.close_chain(q.copy())
        assert (cause == "closed") == (closed is not None and bool(limits(closed))), cause
        seen.add(cause)
    assert np.array_equal(rob.lower, lo) and np.array_equal(rob.upper, hi)  # limits restored
    assert "closed" in seen and len(seen) >= 3


def test_sampling_gain_climb_accounts_for_every_draw() -> None:
    r = papers.sampling_gain_climb(n=8, stances=2, base_rows=40, seed=0)
    for v in r["by_size"].values():
        assert v["jbj_share"] + sum(v["jbj_failures"].values()) == pytest.approx(1.0)
        assert 0 <= v["uniform_in_limits"] <= v["uniform_projected"] <= 8 * v["stances"]
        assert 0.0 <= v["exact_base_share"] <= 1.0


def test_steps_to_reach_limit_by_hand() -> None:
    """Bretl (2006), sec. 5.3: the three readings of "the limit of its reach" on a hand-made plan."""
    from types import SimpleNamespace

    from climb_ompl.climb.multistep import load_robot, load_terrain

    rob, ter = load_robot("lemur"), load_terrain("demo-wall")
    reach = max(float(lb.reach) for lb in rob.limbs)
    holds = sorted(ter.holds, key=lambda h: h.p[2])
    z = lambda hid: float(ter.hold(hid).p[2])  # noqa: E731
    start = [("ne", holds[0].id), ("nw", holds[1].id), ("se", holds[2].id), ("sw", holds[3].id)]
    z_top = max(z(h) for _, h in start)
    high = next(h.id for h in holds if h.p[2] >= z_top + reach)  # one reach above the start's top hold
    q0 = np.asarray(rob.nominal_q, float)
    q0[list(rob.base_indices)[:2]] = [float(holds[0].p[0]), float(holds[0].p[2])]
    steps = [SimpleNamespace(action="release", hold=holds[0].id, stance_after=start[1:], waypoints=[q0]),
             SimpleNamespace(action="grab", hold=high, stance_after=[("ne", high), *start[1:]], waypoints=[q0])]
    r = papers.steps_to_reach_limit(SimpleNamespace(start_stance=start, steps=steps), rob, ter)
    assert r["steps"] == 2 and r["plan_steps"] == 2 and r["threshold_m"] == pytest.approx(z_top + reach)
    assert r["steps_beyond_start_reach"] == 2  # no shoulder of the start configuration reaches that hold
    mean0 = np.mean([z(h) for _, h in start])
    rose = np.mean([z(h) for _, h in steps[1].stance_after]) - mean0 >= reach
    assert r["steps_rise_one_reach"] == (2 if rose else None)
