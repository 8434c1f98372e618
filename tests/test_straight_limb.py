"""Straight-limb sampling of Bretl et al. (2004), sec. 3: the sampler's initial phase and the same-bend rule."""

from __future__ import annotations

import numpy as np
import pytest

from climb_ompl.bench._straight_limb import bend_changes
from climb_ompl.climb.onestep import PathSettings, find_path
from climb_ompl.errors import QueryError
from climb_ompl.manifold.bends import BEND_BAND, STRAIGHT_EPS, SameBendCheck, bend_signature, is_straight_limb
from climb_ompl.manifold.samplers import SamplingCore
from climb_ompl.manifold.stance import StanceConstraint
from climb_ompl.settings import ClimbSettings


def test_initial_phase_draws_straight_limb_configurations(planar_move):
    """The first ``straight_phase`` draws put a contact limb's elbow STRAIGHT_EPS from straight, on the manifold;
    after them the (uniform) mix resumes."""
    robot, terrain, s, _, _ = planar_move
    con = StanceConstraint(robot, terrain, s)
    core = SamplingCore(robot, terrain, s, con, "uniform", seed=3, straight_phase=8)
    elbows = [(lb.elbow_index, lb.elbow_straight) for lb in robot.limbs if lb.name in s]
    first = [core.draw() for _ in range(8)]
    straight = [q for q in first if is_straight_limb(robot, s, q, band=STRAIGHT_EPS + 1e-9)]
    assert len(straight) == 8 - core.failures and len(straight) >= 6, core.failures
    for q in straight:
        assert con.error(q) <= con.tol
        assert min(abs(abs(q[e] - v) - STRAIGHT_EPS) for e, v in elbows) < 1e-9
    after = [core.draw() for _ in range(40)]
    assert sum(is_straight_limb(robot, s, q, band=STRAIGHT_EPS + 1e-9) for q in after) < 10  # uniform again
    assert SamplingCore(robot, terrain, s, con, "uniform", seed=3).straight_phase == 0  # off by default


def test_same_bend_check_against_closed_form(planar_move):
    """A bend is the sign of the elbow angle less straight; within BEND_BAND a limb counts as either bend; a limb the
    start and goal bend opposite ways is left free."""
    robot, _, s, qs, _ = planar_move
    (l1, e1), (l2, e2) = [(lb.name, lb.elbow_index) for lb in robot.limbs if lb.name in s]
    a = np.array(qs, dtype=float)
    a[e1], a[e2] = 0.5, -0.5
    assert bend_signature(robot, s, a) == {l1: 1, l2: -1}
    check = SameBendCheck(robot, s, a, a)
    assert check(a) and not check.free
    for v1, ok in ((0.3, True), (0.5 * BEND_BAND, True), (-0.5 * BEND_BAND, True), (-1.5 * BEND_BAND, False),
                   (-0.4, False)):
        b = a.copy()
        b[e1] = v1
        assert check(b) is ok, v1
    b = a.copy()
    b[e1] = -0.5
    opposite = SameBendCheck(robot, s, a, b)
    assert opposite.free == [l1] and opposite(b) and opposite(a)
    c = a.copy()
    c[e2] = 0.4
    assert not opposite(c)  # limb 2 still bound: both ends bend it negatively


@pytest.mark.parametrize("seed", [0, 1])
def test_path_with_the_rule_never_changes_a_bend(planar_move, seed):
    """RRTConnect with long extensions crosses bends on this query (the oracle: without the rule its path changes
    an elbow's bend); with ``same_bend`` no waypoint is bent against the query and no bend changes."""
    robot, terrain, s, qs, qg = planar_move
    assert not SameBendCheck(robot, s, qs, qg).free  # the query shares its bends
    kw = dict(planner="RRTConnect", space="projected", direct=False, seed=seed, max_iterations=3000,
              simplify=False, range_fraction=0.3)
    free = find_path(robot, terrain, s, qs, qg, **kw)
    assert free.found and bend_changes(robot, s, free.path) > 0
    ruled = find_path(robot, terrain, s, qs, qg, same_bend=True, **kw)
    assert ruled.found, ruled.stats
    check = SameBendCheck(robot, s, qs, qg)
    assert all(check(q) for q in ruled.path)
    assert bend_changes(robot, s, ruled.path) == 0
    assert ruled.stats["bend_free"] == [] and "bend" in ruled.stats["rejections"]


def test_settings_switch_it_and_refuse_the_phase_off_the_projected_space():
    s = ClimbSettings(space="projected", straight_phase=40, same_bend=True)
    p = PathSettings.of(s)
    assert (p.straight_phase, p.same_bend) == (40, True)
    assert (PathSettings().straight_phase, PathSettings().same_bend) == (0, False)
    with pytest.raises(QueryError, match="settings.straight_phase: .*projected"):
        ClimbSettings(straight_phase=40)
    with pytest.raises(QueryError, match="settings.same_bend"):
        ClimbSettings(same_bend="yes")


def test_phase_off_the_projected_space_is_refused_by_find_path(planar_move):
    robot, terrain, s, qs, qg = planar_move
    with pytest.raises(QueryError, match="projected"):
        find_path(robot, terrain, s, qs, qg, space="atlas", straight_phase=5, direct=False)


def test_onestep_command_takes_both_switches(cli, tmp_path):
    """``climb-ompl onestep --straight-phase N --same-bend`` plans with both and records the rule's free limbs."""
    import json

    out = tmp_path / "p.json"
    r = cli("onestep", "planar-3limb", "planar-wall", "--stance", "limb2=R0,limb3=L3", "--limb", "limb1", "--from",
            "L0", "--to", "L2", "--space", "projected", "--planner", "RRTConnect", "--straight-phase", "10",
            "--same-bend", "--max-iterations", "3000", "--out", out)
    assert r.code in (0, 1), r.err
    stats = json.loads(out.read_text())["stats"]
    assert isinstance(stats["bend_free"], list)
