"""ClimbSettings: one frozen value of every climb setting, its search modes, and its validation."""

from __future__ import annotations

import dataclasses

import pytest

from climb_ompl.errors import PlannerNotFound, QueryError
from climb_ompl.settings import SEARCH_MODES, ClimbSettings


def test_round_trip_and_every_field_in_the_dict():
    s = ClimbSettings(planner="RRTConnect", transition_attempts=77, stride=0.3)
    d = s.to_dict()
    assert set(d) == {f.name for f in dataclasses.fields(ClimbSettings)}
    assert ClimbSettings.from_dict(d) == s
    with pytest.raises(dataclasses.FrozenInstanceError):
        s.planner = "PRM"  # type: ignore[misc]


def test_paper_mode_is_fig16_as_published():
    """Bretl (2006) Fig. 16 with sec. 3.3.3: cost alone, nothing deleted, transitions on expansion, every
    elbow-bend combination; the guided mode differs from it in exactly those settings."""
    p, g = ClimbSettings.for_search("paper"), ClimbSettings.for_search("guided")
    assert (p.heuristic_weight, p.max_edge_failures, p.transitions, p.resume, p.elbow_bends) == \
        (0.0, 0, "eager", "queue", "enumerate")
    differ = {k for k, v in p.to_dict().items() if g.to_dict()[k] != v}
    # (the paper mode also fixes FIND-PATH's planner, SBL, the guided default: a robot's own choice does not apply)
    assert differ == set(SEARCH_MODES["paper"]) - {"planner"} | {"search"}
    assert ClimbSettings.for_search("paper", time_limit=5).time_limit == 5


@pytest.mark.parametrize("bad, needle", [
    ({"nope": 1}, "unknown setting"),
    ({"search": "fast"}, "settings.search"),
    ({"elbow_bends": "some"}, "settings.elbow_bends"),
    ({"time_limit": -1.0}, "settings.time_limit"),
    ({"max_step": float("nan")}, "settings.max_step"),
    ({"cone_edges": 2}, "settings.cone_edges"),
    ({"transition_walk": "many"}, "settings.transition_walk: 'many' must be a number"),
    ({"margin": "0.01"}, "settings.margin: '0.01' must be a number"),
    ({"keep_shape": 1}, "settings.keep_shape: 1 must be true or false"),
    ({"path_iterations": 2.5}, "settings.path_iterations: 2.5 must be a whole number"),
])
def test_bad_settings_name_the_field(bad, needle):
    with pytest.raises(QueryError, match=needle):
        ClimbSettings.from_dict(bad)


def test_unknown_planner_lists_the_valid_names():
    with pytest.raises(PlannerNotFound, match="LazyPRM"):
        ClimbSettings(planner="Dijkstra")


def test_custom_sampler_needs_the_projected_space():
    """The atlas and tangent-bundle spaces (the default) sample their own charts: a custom sampler there is refused up
    front, not turned into failed FIND-PATH calls in the middle of a climb."""
    with pytest.raises(QueryError, match="projected"):
        ClimbSettings(sampler="straight-elbow")
    assert ClimbSettings(sampler="straight-elbow", space="projected", planner="LazyPRM").space == "projected"


# ---- a robot's own defaults (the spec's ``climb`` section) ------------------------------------------------------
def _planar_with(climb):
    from pathlib import Path

    import yaml

    from climb_ompl.model.robot import RobotModel

    root = Path(__file__).resolve().parents[1]
    spec = yaml.safe_load((root / "robots" / "planar-3limb.yaml").read_text())
    return RobotModel.from_spec({**spec, "climb": climb}, base_dir=root / "urdf")


def test_a_robot_climb_section_sits_between_the_defaults_and_the_options():
    """defaults < robot < search mode < options: the robot's value replaces the default, a setting the paper mode
    fixes stays the paper's, and an option given to the climb wins over the robot."""
    robot = _planar_with({"release_lookahead": True, "reexpand": 5, "stride": 0.2})
    s = ClimbSettings.for_search("guided", robot=robot)
    assert (s.release_lookahead, s.reexpand, s.stride) == (True, 5, 0.2)
    assert ClimbSettings.for_search("paper", robot=robot).reexpand == 0  # Fig. 16 as published
    assert ClimbSettings.for_search("paper", robot=robot).release_lookahead is False  # not in Fig. 16 either
    assert ClimbSettings.for_search("guided", robot=robot, stride=0.3).stride == 0.3
    assert ClimbSettings.for_search("guided", robot=_planar_with(None)) == ClimbSettings()
    # settings valid only together are accepted together
    both = _planar_with({"space": "projected", "sampler": "straight-elbow"})
    assert ClimbSettings.for_search("guided", robot=both).sampler == "straight-elbow"


def test_a_plan_file_older_than_a_setting_is_read_with_the_value_it_was_planned_with():
    """A plan file written before the release look-ahead existed was planned in limb order: read back for a replay
    it keeps that order though the default is now the look-ahead; a file that names the setting keeps its value,
    and a bad one is refused as from ``from_dict``."""
    from climb_ompl.settings import FORMER_DEFAULTS

    old = {k: v for k, v in ClimbSettings().to_dict().items() if k != "release_lookahead"}
    assert ClimbSettings().release_lookahead is True and FORMER_DEFAULTS["release_lookahead"] is False
    assert ClimbSettings.from_plan(old).release_lookahead is False
    # every former value differs from today's default (else it would not be needed) and is a valid setting
    assert all(getattr(ClimbSettings(), k) != v for k, v in FORMER_DEFAULTS.items())
    oldest = {k: v for k, v in ClimbSettings().to_dict().items() if k not in FORMER_DEFAULTS}
    assert {k: getattr(ClimbSettings.from_plan(oldest), k) for k in FORMER_DEFAULTS} == FORMER_DEFAULTS
    assert ClimbSettings.from_plan({**old, "release_lookahead": True}).release_lookahead is True
    assert ClimbSettings.from_dict(old).release_lookahead is True  # (a robot's climb section: today's defaults)
    with pytest.raises(QueryError, match="plan.json: unknown setting"):
        ClimbSettings.from_plan({**old, "bogus": 1}, source="plan.json")


@pytest.mark.climb
def test_a_plan_records_the_robot_defaults_it_was_planned_with():
    """``plan_climb`` without settings takes the robot's ``climb`` section, and the plan file stores the settings
    used (a replay needs no spec); an option passed to the climb wins."""
    from climb_ompl.climb.multistep import default_start, plan_climb
    from climb_ompl.model.terrain import Terrain

    robot, wall = _planar_with({"force_every": 4}), Terrain.load("planar-wall")
    stance, q0 = default_start(robot, wall, seed=0)
    res = plan_climb(robot, wall, stance, 1.6, q_start=q0, time_limit=60, seed=0)
    assert res.found and res.plan.settings["force_every"] == 4
    res = plan_climb(robot, wall, stance, 1.6, q_start=q0, time_limit=60, seed=0, force_every=7)
    assert res.found and res.plan.settings["force_every"] == 7


@pytest.mark.parametrize("climb, field, needle", [
    ({"nosuch": 1}, "climb.nosuch", "unknown setting; valid: clearance"),
    ({"stride": "far"}, "climb.stride", "must be a number"),
    ({"tolerance": 0.01}, "climb.tolerance", "not a robot default"),
    ("fast", "climb", "expected a mapping"),
    ({"planner": "NoSuch"}, "climb.planner", "unknown planner 'NoSuch'; valid names: PRM"),
    ({"sampler": "straight-elbow"}, "climb", "needs the 'projected' space"),  # with the default tangent-bundle space
])
def test_a_bad_climb_section_names_the_setting(climb, field, needle):
    from climb_ompl.errors import RobotModelError

    with pytest.raises(RobotModelError) as ei:
        _planar_with(climb)
    assert ei.value.field == field and needle in str(ei.value)
