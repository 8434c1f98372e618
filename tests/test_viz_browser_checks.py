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
    from climb_ompl.terrain import Terrain

    empty = tmp_path / "empty.html"
    empty.write_text("")
    with pytest.raises(viz.VizError, match="no meshcat scene"):
        with viz.open_page(empty, timeout_s=3):
            pass
    static = viz.show(Terrain.load("pegs"), html=tmp_path / "static.html")
    with viz.open_page(static) as (pg, log):
        assert log.console_errors == []
        assert pg.evaluate(JS_ANIMATION)["actions"] == 0  # what the climb test requires to be > 0
        assert pg.evaluate(JS_CHILDREN, ["meshcat", "robot"]) is None


def test_screenshot_helper_and_play_png_write_real_pngs(tmp_path, cli):
    from climb_ompl import viz

    (tmp_path / "plan.json").write_text(json.dumps(make_climb_plan()))
    r = cli("play", tmp_path / "plan.json", "--html", tmp_path / "climb.html", "--png", tmp_path / "end.png")
    assert r.code == 0, r.err
    png = viz.screenshot(tmp_path / "climb.html", tmp_path / "climb.png", time=1.0, size=(640, 400))
    for p in (png, tmp_path / "end.png"):
        data = p.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and distinct_colours(data) > 300
