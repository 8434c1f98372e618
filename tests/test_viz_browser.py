"""The static playback page in a real browser (headless Chromium, SwiftShader WebGL).

One climb page (LEMUR on the demo wall, two steps and the final stance) is built once and opened once;
each test reads meshcat's viewer object in the page.  The robot's drawn poses are checked against
Pinocchio (the oracle), so a page whose animation is missing, empty or wrong fails.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from browser import (
    JS_ANIMATION,
    JS_CHILDREN,
    changed_fraction,
    distinct_colours,
    make_climb_plan,
    pose_at,
    requires_chromium,
)

pytestmark = [pytest.mark.browser, requires_chromium]


@pytest.fixture(scope="module")
def climb(tmp_path_factory):
    """(plan dict, robot, html path, frames) of the test climb."""
    from climb_ompl import viz
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.viz._plans import parse_climb_steps, timeline

    tmp = tmp_path_factory.mktemp("viz")
    plan = make_climb_plan()
    (tmp / "plan.json").write_text(json.dumps(plan))
    html = viz.play(tmp / "plan.json", html=tmp / "climb.html")
    robot = RobotModel.load("lemur")
    frames = timeline(parse_climb_steps(plan, robot.nq))
    return plan, robot, html, frames


@pytest.fixture(scope="module")
def page(climb):
    from climb_ompl.viz import open_page

    with open_page(climb[2]) as (pg, log):
        yield pg, log


def test_page_loads_without_errors_or_network(page):
    pg, log = page
    assert log.console_errors == []
    assert log.external_requests == []  # self-contained: nothing but the file itself and data: URLs


def test_scene_contains_robot_holds_and_stances(page, climb):
    plan, robot, _, _ = climb
    pg, _ = page
    bodies = set(pg.evaluate(JS_CHILDREN, ["meshcat", "robot"]) or [])
    assert bodies == {robot.model.names[g.parentJoint] for g in robot.visual_model.geometryObjects}
    drawn = {name for b in bodies for name in pg.evaluate(JS_CHILDREN, ["meshcat", "robot", b])}
    assert drawn == {g.name for g in robot.visual_model.geometryObjects}
    holds = set(pg.evaluate(JS_CHILDREN, ["meshcat", "terrain", "holds"]) or [])
    assert holds == {h["id"] for h in plan["terrain"]["data"]["holds"]}
    assert pg.evaluate(JS_CHILDREN, ["meshcat", "stance"]), "no hold highlighted"
    assert pg.evaluate(JS_CHILDREN, ["meshcat", "com"]) is not None
    assert pg.evaluate(JS_CHILDREN, ["meshcat", "support"]), "no support polygon drawn"


def test_animation_moves_the_robot_as_pinocchio_says(page, climb):
    _, robot, _, frames = climb
    pg, _ = page
    from climb_ompl.viz import Scene, open_visualizer
    from climb_ompl.viz._geometry import KEY_ANGLE_TOLERANCE, KEY_POSITION_TOLERANCE

    with open_visualizer() as vis:  # the oracle: Pinocchio placements of the same geometry
        drawing = Scene(vis).add_robot(robot)
    anim = pg.evaluate(JS_ANIMATION)
    assert anim["actions"] > len(drawing.bodies)  # every body, the CoM, the support regions, ...
    assert anim["duration"] == pytest.approx(frames[-1].t, abs=1e-6)
    moved = []
    lower = next(n for n in drawing.nodes if n is not None and n.endswith("/ne_lower_0"))
    # the page keys a body only where interpolation would miss its pose by more than the tolerances: every
    # frame, keyed or not, is within them (a geometry object 0.4 m from its body's origin moves 0.4 m per radian)
    tol = KEY_POSITION_TOLERANCE + 0.4 * KEY_ANGLE_TOLERANCE + 1e-4
    for fr in frames[:: max(1, len(frames) // 12)] + frames[-1:]:
        for node, T in drawing.geometry_placements(fr.q):
            M, visible = pose_at(pg, ["meshcat", *node.split("/")], fr.t)
            assert visible
            assert np.allclose(M, T, atol=tol), f"{node} at t={fr.t}"
        moved.append(pose_at(pg, ["meshcat", *lower.split("/")], fr.t)[0])
    assert np.linalg.norm(moved[0][:3, 3] - moved[-1][:3, 3]) > 0.05  # the climb really moves the limb


def test_stance_highlights_switch_with_the_steps(page, climb):
    """At each step exactly its stance's holds are highlighted, and the force arrows of exactly the limbs that
    carry load in it are shown (the plan's steps are the oracle)."""
    from climb_ompl.viz._plans import parse_climb_steps

    plan, robot, _, frames = climb
    pg, _ = page
    steps = parse_climb_steps(plan, robot.nq)  # the start stance, then the stance after each step
    starts = [next(f.t for f in frames if f.step == k) for k in range(len(steps))]
    held = sorted({h for st in steps for h in st.stance.values()})
    assert set(pg.evaluate(JS_CHILDREN, ["meshcat", "stance"])) == set(held)
    arrows = pg.evaluate(JS_CHILDREN, ["meshcat", "forces"]) or []
    assert arrows
    for k, t0 in enumerate(starts):
        t = t0 + 0.01
        shown = {h for h in held if pose_at(pg, ["meshcat", "stance", h], t)[1]}
        assert shown == set(steps[k].stance.values()), f"t={t}"
        loaded = {lb for d in steps[k].forces.values() for lb in d} & set(steps[k].stance)
        assert {a for a in arrows if pose_at(pg, ["meshcat", "forces", a], t)[1]} == loaded, f"t={t}"


def test_screenshot_shows_the_scene(page):
    pg, _ = page
    pg.evaluate("() => viewer.animator.seek(0.5)")
    pg.evaluate("() => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    full = pg.screenshot(type="png")
    assert distinct_colours(full) > 500
    pg.evaluate("() => { viewer.scene_tree.find(['meshcat']).object.visible = false; viewer.set_dirty(); }")
    pg.evaluate("() => new Promise(r => requestAnimationFrame(() => requestAnimationFrame(r)))")
    empty = pg.screenshot(type="png")
    pg.evaluate("() => { viewer.scene_tree.find(['meshcat']).object.visible = true; viewer.set_dirty(); }")
    assert changed_fraction(full, empty) > 0.1  # the climb, not just the background, is on the canvas
