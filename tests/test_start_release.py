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

from climb_ompl.climb.start import candidate_stances, find_start, release_score, wall_axes
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.manifold.stance import Stance
from climb_ompl.model.robot import RobotModel
from climb_ompl.model.terrain import Terrain


def _length(terrain: Terrain, stance: dict[str, str]) -> float:
    _, v = wall_axes(terrain)
    z = [float(terrain.hold(h).p @ v) for h in stance.values()]
    return max(z) - min(z)


@pytest.fixture(scope="module")
def go1_overhang():
    robot = RobotModel.load("go1")
    terrain = Terrain.load("overhang")
    return robot, terrain, Feasibility.of(robot, terrain)


@pytest.mark.heavy
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
    import climb_ompl.climb.start as start
    from climb_ompl.climb.transition import nominal_near

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


@pytest.mark.climb
def test_a_climb_exhausted_from_its_start_climbs_from_the_next_start(go1_overhang):
    """Go1 on the overhang: the start finder's first start leads nowhere (the stance graph is exhausted within a
    few stances: a hind foot let go of cannot be placed higher), so :func:`climb_from_start` climbs from the next
    one, which ``find_start(skip=...)`` gives independently, and the reason of a failed climb lists the starts.

    The climb from the second start is not asked to succeed (it spends whatever budget is left), so the budget is
    only what the first start needs (about 2 s) plus the 5 s a further start requires
    (``multistep.START_RETRY_MIN_S``), with room for a loaded machine."""
    from climb_ompl.climb.multistep import climb_from_start
    from climb_ompl.climb.status import ClimbStatus
    from climb_ompl.settings import ClimbSettings

    robot, terrain, feas = go1_overhang
    first = find_start(robot, terrain, seed=0)
    res, start, tried = climb_from_start(robot, terrain, None, ClimbSettings.for_search(
        "guided", robot=robot, time_limit=12.0), climb=0.6, seed=0, tries=2)
    assert tried[0]["stance"] == dict(sorted(first.stance.items()))
    assert not tried[0]["found"] and tried[0]["status"] == ClimbStatus.EXHAUSTED and tried[0]["stances_explored"] < 50
    assert len(tried) == 2 and tried[1]["stance"] != tried[0]["stance"]
    assert find_start(robot, terrain, seed=0, skip=[first.stance]).stance == start.stance == tried[1]["stance"]
    assert res is not None and res.stats["starts_tried"] == tried
    last = "{" + ", ".join(f"{k}:{v}" for k, v in tried[1]["stance"].items()) + "}"
    assert res.found or f"this climb was from start 2 of the start finder's, {last};" in res.reason
