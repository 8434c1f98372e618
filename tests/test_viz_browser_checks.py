"""Browser checks that need their own Playwright session (the climb page's module fixture holds one).

They show that the playback checks can fail: an empty page raises, a page without animation has no
animation actions and no robot, and the screenshot helper writes a real PNG.
"""

from __future__ import annotations

import json

import pytest
from browser import JS_ANIMATION, JS_CHILDREN, distinct_colours, make_climb_plan, requires_chromium

pytestmark = [pytest.mark.browser, requires_chromium]


def test_checks_fail_on_an_empty_page_or_a_page_without_animation(tmp_path):
    from climb_ompl import viz
    from climb_ompl.model.terrain import Terrain

    empty = tmp_path / "empty.html"
    empty.write_text("")
    with pytest.raises(viz.VizError, match="no meshcat scene"):  # an empty page waits out the whole timeout
        with viz.open_page(empty, timeout_s=1):
            pass
    static = viz.show(Terrain.load("pegs"), html=tmp_path / "static.html")
    with viz.open_page(static) as (pg, log):
        assert log.console_errors == []
        assert pg.evaluate(JS_ANIMATION)["actions"] == 0  # what the climb test requires to be > 0
        assert pg.evaluate(JS_CHILDREN, ["meshcat", "robot"]) is None


@pytest.mark.slow
def test_screenshot_helper_and_play_png_write_real_pngs(tmp_path, cli):
    from climb_ompl import viz

    (tmp_path / "plan.json").write_text(json.dumps(make_climb_plan()))
    r = cli("play", tmp_path / "plan.json", "--html", tmp_path / "climb.html", "--png", tmp_path / "end.png")
    assert r.code == 0, r.err
    notes: list[str] = []
    png = viz.screenshot(tmp_path / "climb.html", tmp_path / "climb.png", time=1.0, size=(640, 400),
                         note=notes.append)
    assert notes == []  # within the animation
    late = viz.screenshot(tmp_path / "climb.html", tmp_path / "late.png", time=1e6, size=(320, 200),
                          note=notes.append)
    assert len(notes) == 1 and "past the animation's end" in notes[0]  # shown, and said so (it was silent)
    for p in (png, late, tmp_path / "end.png"):
        data = p.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and distinct_colours(data) > 300


@pytest.mark.slow
def test_first_step_items_are_hidden_at_a_late_time(tmp_path):
    """Late in the climb only the current step's stance, support polygon and forces show (not step 0's).

    The page plays on load, as in a screenshot, and is then sought to the end; a page that also set
    a static ``visible`` on the per-step nodes kept the first step's items shown over the whole climb.
    """
    from browser import pose_at

    from climb_ompl import viz
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.viz._browser import JS_SEEK, JS_TWO_FRAMES
    from climb_ompl.viz._plans import parse_climb_steps, timeline

    plan = make_climb_plan()
    steps = parse_climb_steps(plan, RobotModel.load("lemur").nq)
    frames = timeline(steps)
    last = frames[-1].step
    html = viz.play(plan, html=tmp_path / "climb.html")
    for _ in range(3):  # the autoplay's timing varies from load to load
        with viz.open_page(html) as (pg, _log):
            pg.wait_for_timeout(1200)  # let the autoplay run past step 0
            t = pg.evaluate(JS_SEEK, None)  # the end, where the screenshot of a climb is taken
            pg.evaluate(JS_TWO_FRAMES)
            groups = set(pg.evaluate(JS_CHILDREN, ["meshcat"]))
            assert {"stance", "support", "forces"} <= groups
            final = steps[last]
            expect = {"support": {f"s{last}"}, "stance": set(final.stance.values()),
                      "forces": {lb for d in final.forces.values() for lb in d} & set(final.stance)}
            for group in ("stance", "support", "forces"):
                kids = pg.evaluate(JS_CHILDREN, ["meshcat", group])
                shown = {k for k in kids if pose_at(pg, ["meshcat", group, k], t)[1]}
                assert shown == expect[group], f"{group} at t={t}: {sorted(shown)}"


JS_WORLD = """(path) => {
  let node = viewer.scene_tree;
  for (const name of path) { node = node.children[name]; if (node === undefined) return null; }
  viewer.scene.updateMatrixWorld(true);
  return Array.from(node.object.matrixWorld.elements);
}"""


def test_a_turned_terrain_is_shown_in_its_files_coordinates(tmp_path):
    """A slab written tilted (gravity straight down) is planned in the wall frame, and shown as the file gave it:
    in the page, the vector between two holds is the file's (not the turned terrain's), and the wall leans back."""
    import numpy as np
    from test_wall_frame import _gravity_down, _moved

    from climb_ompl import viz
    from climb_ompl.model.terrain import Terrain

    slab = Terrain.load("slab")
    user = _moved(slab, _gravity_down(slab, 30.0), np.array([0.5, -0.2, 0.1]))
    turned = user.in_wall_frame()
    html = viz.show(turned, html=tmp_path / "turned.html", cones=False)
    with viz.open_page(html) as (pg, log):
        assert log.console_errors == []
        # three.js's scene is y-up: meshcat turns z-up content by a quarter turn about x, the same for every node
        world = {h: np.array(pg.evaluate(JS_WORLD, ["meshcat", "terrain", "holds", h])).reshape(4, 4).T[:3, 3]
                 for h in ("h0_0", "h10_0", "h0_10")}
    for a, b in (("h0_0", "h10_0"), ("h0_0", "h0_10")):
        shown = world[b] - world[a]
        in_file = np.asarray(user.hold(b).position) - np.asarray(user.hold(a).position)
        in_plan = np.asarray(turned.hold(b).position) - np.asarray(turned.hold(a).position)
        y_up = np.array([[1.0, 0, 0], [0, 0, 1], [0, -1, 0]])  # three.js (y up) from z up: (x, y, z) -> (x, z, -y)
        assert np.allclose(shown, y_up @ in_file, atol=1e-6), (a, b)
        assert not np.allclose(shown, y_up @ in_plan, atol=1e-3)


@pytest.mark.slow
def test_a_slope_plans_legs_of_one_frame_are_hidden_at_the_others(tmp_path, cli):
    """A slope plan draws its legs per frame (``items/leg<k>/f<j>``): at the end only the last frame's legs show.
    A static ``visible`` on the first frame's nodes kept three legs of the start pose standing on the floor over the
    whole animation and in its end screenshot."""
    from browser import pose_at

    from climb_ompl import viz
    from climb_ompl.viz._browser import JS_SEEK, JS_TWO_FRAMES

    plan = tmp_path / "s.json"
    assert cli("slope", "plan", "--angle", "90", "--kind", "concave", "--out", plan).code == 0
    html = viz.play(json.loads(plan.read_text()), html=tmp_path / "slope.html")
    with viz.open_page(html) as (pg, _log):
        pg.wait_for_timeout(1200)
        t = pg.evaluate(JS_SEEK, None)  # the end
        pg.evaluate(JS_TWO_FRAMES)
        per_frame = {}
        for item in pg.evaluate(JS_CHILDREN, ["meshcat", "items"]):
            kids = pg.evaluate(JS_CHILDREN, ["meshcat", "items", item]) or []
            frames = [k for k in kids if k[:1] == "f" and k[1:].isdigit()]
            if len(frames) > 2:
                per_frame[item] = frames
        assert len([k for k in per_frame if k.startswith("leg")]) >= 4, sorted(per_frame)
        for item, frames in per_frame.items():
            shown = [f for f in frames if pose_at(pg, ["meshcat", "items", item, f], t)[1]]
            assert shown == [max(frames, key=lambda f: int(f[1:]))], (item, shown)

