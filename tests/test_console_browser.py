"""The operator's console in a real browser (headless Chromium through Playwright, SwiftShader WebGL), the server in
this process on a free port, the real planner behind it.

One page drives the loop a person would: click a hold (its pixels turn orange), release a limb, grab the hold, scrub
the preview, accept, plan a multi-step goal, mark one of its holds failed and see the re-plan, undo, a click while a
plan runs, a hold out of reach; the session it writes passes the independent verifier.
"""

from __future__ import annotations

import json
import socket

import numpy as np
import pytest
from browser import requires_chromium

from climb_ompl.plan.file import Plan
from climb_ompl.plan.session import Session
from climb_ompl.verification import verify

pytestmark = [pytest.mark.browser, requires_chromium]


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def orange(rgb: np.ndarray) -> bool:
    """Whether a pixel is the console's orange (255, 140, 0) under the scene's lighting: red well above blue, green
    between them."""
    r, g, b = (int(x) for x in rgb[:3])
    return r > 150 and r - b > 110 and b < g < r


def pixel(op, x: float, y: float) -> np.ndarray:
    from io import BytesIO

    from PIL import Image

    img = np.asarray(Image.open(BytesIO(op.page.screenshot())).convert("RGB"))
    return img[int(round(y)), int(round(x))]


@pytest.fixture
def console(tmp_path):
    from climb_ompl.console import open_console

    page = open_console("lemur", "demo-wall", tmp_path / "session.json", port=free_port(), time_limit=30)
    yield page
    page.close()


def test_click_plan_preview_accept_fail_undo(console, tmp_path) -> None:
    from climb_ompl.console.operator import JS_SLIDER, browse

    st = console.state
    with browse(console) as op:
        assert console.url.startswith("http://127.0.0.1:")
        # a click on a hold selects it, and its pixels turn orange
        x, y = op.screen_point(console.hold_pos["h25"] + np.array([0.0, 0.0, 0.0]))
        assert not orange(pixel(op, x, y))
        op.click_hold("h25")
        op.wait_text("Selected hold: h25;")
        assert console.selected == "h25" and orange(pixel(op, x, y))
        # release se, accept; grab h25 with se, watch the preview start, scrub it, accept
        op.press("se")
        op.page.get_by_label("Margin threshold (m)").fill("0.5")  # every step is "almost infeasible" under 0.5 m
        op.press("Release limb")
        op.wait_text("proposal for release se")
        op.wait_text("ALMOST INFEASIBLE")
        assert st.threshold == pytest.approx(0.5)
        op.page.get_by_label("Margin threshold (m)").fill("0.02")
        op.press("Accept")
        op.wait_text("Session: 1 steps accepted")
        op.watch("proposal for grab se=h25")
        op.page.evaluate(JS_SLIDER)
        op.press("Grab selected hold")
        arrived = op.seen("proposal for grab se=h25")
        op.page.wait_for_timeout(1500)
        moves = op.page.evaluate("() => window.__slider")
        started = [t for t, v in moves if v not in ("0", None) and t >= arrived]
        assert started and started[0] - arrived < 1000  # the preview plays on its own (0.3 s target: the benchmark)
        track = op.page.locator(".mantine-Slider-root").first.bounding_box()
        op.page.mouse.click(track["x"] + 0.25 * track["width"], track["y"] + track["height"] / 2)  # scrub to 1/4
        op.page.wait_for_timeout(500)
        end = float(console.timeline[0][-1])
        assert 0.1 * end < console.t < 0.4 * end and not console.playing
        op.press("Accept")
        op.wait_text("Session: 2 steps accepted")
        # a multi-step goal; a click while it is planned is refused with a message
        op.page.get_by_label("Climb (m)").fill("0.1")
        op.page.wait_for_timeout(300)
        op.watch("still planning")
        op.press("Climb (multi-step)")
        op.press("Release limb")
        op.wait_idle()
        assert any("still planning" in m for m in st.log), st.log
        op.wait_idle()
        op.wait_text("Proposal for climb")
        p = st.proposal
        assert p is not None and p.holds(), st.message
        failed = p.holds()[0]
        if op.click_latency(failed) is None:  # the hold is behind the robot from this camera: select it as the
            console.select(failed)             # panel would (the click itself is tested above)
        op.wait_text(f"Selected hold: {failed};")
        op.press("Hold failed (selected)")
        op.wait_text(f"hold {failed} failed")
        op.wait_idle()
        assert failed in st.session.failed
        if st.proposal is not None:  # the re-plan holds on to no failed hold
            assert failed not in {h for s in st.proposal.steps for h in (s.hold, *dict(s.stance).values())}
        if st.proposal is not None:
            op.press("Accept")
            op.wait_text("accepted climb")
        n = st.session.n_steps
        op.press("Undo")
        op.wait_text("undone: step")
        assert st.session.n_steps == n - 1
        # a hold out of reach (about 1 m above the robot, LEMUR's limbs reach 0.42 m): the diagnosis in the page
        com = console.robot.com(st.session.state()[1])
        far = min(console.hold_pos, key=lambda h: np.linalg.norm(console.hold_pos[h] - com - [0, 0, 1.0]))
        op.click_hold(far)
        op.wait_text(f"Selected hold: {far};")
        op.press("ne")
        op.press("Release limb")
        op.wait_text("proposal for release ne")
        op.press("Accept")
        op.press("Grab selected hold")
        op.wait_text(f"no plan for grab ne={far}")
        assert "reach" in st.message
        assert op.blocked == []  # no request left the machine
    session = Session.load(tmp_path / "session.json")
    assert session.n_steps == st.session.n_steps and session.failed == [failed]
    assert verify(Plan.load(tmp_path / "session.json")).ok


def test_malformed_session_is_left_untouched(tmp_path) -> None:
    from climb_ompl.console import open_console
    from climb_ompl.console.operator import browse

    bad = tmp_path / "bad.json"
    d = json.loads(json.dumps(Plan.load(_tiny_session(tmp_path)).to_dict()))
    d["session"] = {"version": 1, "goals": [{"goal": "release se"}]}
    bad.write_text(json.dumps(d))
    before = bad.read_text()
    page = open_console("lemur", "demo-wall", bad, port=free_port())
    try:
        with browse(page) as op:
            op.wait_text("session file not read")
            assert "$.session.goals[0].time" in page.state.message and "bad.new.json" in page.state.message
            op.press("se")
            op.press("Release limb")
            op.wait_text("proposal for release se")
            op.press("Accept")
            op.wait_text("Session: 1 steps accepted")
    finally:
        page.close()
    assert bad.read_text() == before
    assert Session.load(tmp_path / "bad.new.json").n_steps == 1


def _tiny_session(tmp_path):
    from climb_ompl.cli import main

    out = tmp_path / "tiny.json"
    assert main(["step", "--robot", "lemur", "--terrain", "demo-wall", "--goal", "release se", "--out", str(out)]) == 0
    return out
