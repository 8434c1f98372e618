"""The start finder's ``release`` ranking: stances from which every limb can let go at a crouched stand-off.

On the suite's overhang (10 degrees past vertical, ledges, friction 1) the support region lets the CoM stand off the
wall at most 0.24 to 0.41 times the stance's length (tests/test_equilibrium_standoff.py).  Go1's nominal layout is
0.38 m long, so every candidate of the nominal ranking is 0.45 m long; a broad search over Go1's postures on a
0.45 m x 0.15 m stance met one balancing with the left hind foot released and none with any other foot released
(best margins -0.026, -0.015, +0.007, -0.020 m), on a 0.6 m one all four within 1 mm of balancing or better.  The
release ranking stretches the layouts along the slope and puts a longer stance first.
"""

from __future__ import annotations

import numpy as np
import pytest

from climb_ompl.feasibility import Feasibility
from climb_ompl.robot import RobotModel
from climb_ompl.stance import Stance
from climb_ompl.start import candidate_stances, release_score, wall_axes
from climb_ompl.terrain import Terrain


def _length(terrain: Terrain, stance: dict[str, str]) -> float:
    _, v = wall_axes(terrain)
    z = [float(terrain.hold(h).p @ v) for h in stance.values()]
    return max(z) - min(z)


@pytest.fixture(scope="module")
def go1_overhang():
    robot = RobotModel.load("go1")
    terrain = Terrain.load("overhang")
    return robot, terrain, Feasibility.of(robot, terrain)


def test_release_ranking_puts_a_longer_stance_first(go1_overhang):
    robot, terrain, feas = go1_overhang
    nominal = candidate_stances(robot, terrain, feas)
    release = candidate_stances(robot, terrain, feas, "release")
    assert max(_length(terrain, c.stance) for c in nominal) < 0.5
    best = release[0].stance
    assert _length(terrain, best) > 0.55
    score = release_score(robot, terrain, feas, Stance(best))
    assert all(score > release_score(robot, terrain, feas, Stance(c.stance)) for c in nominal)
    # every candidate of the nominal ranking is among the release ranking's
    assert {tuple(sorted(c.stance.items())) for c in nominal} <= {tuple(sorted(c.stance.items())) for c in release}


def test_release_score_is_the_smallest_margin_without_one_limb(go1_overhang):
    """At the nominal stand-off only (a crouch fraction of 1), the score is a minimum of the region margins."""
    import climb_ompl.start as start
    from climb_ompl.transition import nominal_near

    robot, terrain, feas = go1_overhang
    sigma = Stance({"fl": "h5_6", "fr": "h5_4", "rl": "h1_6", "rr": "h1_4"})
    com = robot.com(nominal_near(robot, terrain, sigma))
    want = min(float(feas.region(sigma.without(lb)).margin(com)) for lb in sigma.limbs)
    old = start.CROUCH
    try:
        start.CROUCH = (1.0,)
        assert release_score(robot, terrain, feas, sigma) == pytest.approx(want)
    finally:
        start.CROUCH = old


def test_unknown_rank(go1_overhang):
    robot, terrain, feas = go1_overhang
    with pytest.raises(ValueError, match="rank"):
        candidate_stances(robot, terrain, feas, "tallest")
    assert np.isfinite(release_score(robot, terrain, feas, Stance({"fl": "h5_6", "fr": "h5_4", "rl": "h1_6",
                                                                     "rr": "h1_4"})))


def _climbed(res, terrain: Terrain, start: dict[str, str]) -> bool:
    """Whether the search ``res`` grabbed, at a node right after a release of the start, a hold higher than the
    one released: one step of progress (the oracle of :func:`climb_ompl.start.steps_up`, from the search)."""
    sg = res.search
    for (key, nxt), q in sg.transitions.items():
        if q is None or len(nxt) != len(start) or len(key[0]) != len(start) - 1:
            continue
        (limb, hold), = set(nxt.pairs) - set(key[0].pairs)
        if set(key[0].pairs) <= set(start.items()) and terrain.height(hold) > terrain.height(start[limb]) + 1e-9:
            return True
    return False


def test_start_finder_passes_over_a_start_that_cannot_step_up(go1_overhang):
    """Go1 crouched on a compact stance of the overhang lets go of its left hind foot, and from there no hold
    takes the foot higher (its thigh and calf in the wall, its hip abduction beyond the limits): the stance graph
    is exhausted after the start and that release, and :func:`steps_up` says so.  The start finder passes over
    it."""
    from climb_ompl.multistep import plan_climb
    from climb_ompl.start import _configure, find_start, steps_up

    robot, terrain, feas = go1_overhang
    dead = {"fl": "h4_6", "fr": "h4_5", "rl": "h1_6", "rr": "h1_5"}  # the start the finder took before
    q, _ = _configure(feas, Stance(dead), 1, True)  # (the configuration depends on the draws: seed 2's can step up)
    assert q is not None and not steps_up(feas, Stance(dead), q)
    res = plan_climb(robot, terrain, dead, 1.8, q_start=q, seed=0, time_limit=60.0, keep_search=True)
    assert not res.found and res.reason.startswith("the stance graph is exhausted")
    assert res.stats["stances_explored"] <= 3
    assert not _climbed(res, terrain, dead)
    st = find_start(robot, terrain, seed=0)
    assert st.found and st.stance != dead  # (the climb from it: the suite's Go1 x overhang cell, `bench suite`)
