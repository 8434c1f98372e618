"""The operator's console page (viser): the wall with clickable holds, the robot, its support region and CoM, the
goal buttons, the preview (play, pause, a scrub slider) and the decisions (accept, reject, undo, hold failed).

The loop is Bretl (2006), sec. 5.1 (choose a goal, the planner proposes, the operator evaluates the proposal in a GUI
before it runs) with MoveIt's motion-planning panel's conventions: plan before execute, a trajectory slider to scrub
the plan first, the state the robot is in, the goal and what is invalid told apart by colour (green, orange, red;
:data:`climb_ompl.console.drawing.COLORS`).  A step whose equilibrium margin is under the operator's threshold is
flagged "almost infeasible" before acceptance (Bretl et al. (2004), sec. 4.3).

The server binds ``127.0.0.1`` unless told otherwise, never asks for a share link, and serves viser's client from
the installed package (no network at run time).
"""

from __future__ import annotations

import threading
import time
from typing import Any

import numpy as np

from climb_ompl.console.drawing import COLORS, HOLD_RADIUS, RobotDrawing, region_loop
from climb_ompl.console.state import ConsoleState, configuration_at

#: Preview frames per second, and the preview's speed against the steps' stored times.
FPS = 25.0
SPEED = 4.0
#: How a step under the margin threshold is marked in the proposal's table.
FLAG = "<span style='color:#d21e1e'>ALMOST INFEASIBLE</span>"


class ConsolePage:
    """The console's viser server and page.

    Args:
        state: the console's :class:`~climb_ompl.console.state.ConsoleState` (its ``on_change`` is set here).
        host, port: where the server listens (``127.0.0.1`` by default: this machine only).
    """

    def __init__(self, state: ConsoleState, host: str = "127.0.0.1", port: int = 8080):
        import viser

        self.state = state
        self.server = viser.ViserServer(host=host, port=port, label="climb-ompl console", verbose=False)
        self.server.gui.configure_theme(show_share_button=False, control_width="large")
        self.robot = state.robot
        self.selected: str | None = None
        self.playing = False
        self.t = 0.0
        self.timeline: tuple[np.ndarray, np.ndarray, np.ndarray] | None = None
        self.stamps: dict[str, float] = {}
        self._draw_scene()
        self._add_gui()
        state.on_change = self.refresh
        self._stop = threading.Event()
        self.player = threading.Thread(target=self._play_loop, daemon=True, name="console-preview")
        self.player.start()
        self.server.on_client_connect(self._camera)
        self.refresh("start")

    @property
    def url(self) -> str:
        """The page's address."""
        return f"http://{self.server.get_host()}:{self.server.get_port()}"

    # ---- the scene --------------------------------------------------------------------------------------
    def _all_holds(self) -> dict[str, np.ndarray]:
        """Every hold the session's terrain has had (failed holds included): id -> position."""
        from climb_ompl.plan.events import terrain_eras

        eras = terrain_eras(self.state.session.plan)
        out: dict[str, np.ndarray] = {}
        for t in eras.terrains:
            for h in t.hold_ids:
                out.setdefault(h, np.asarray(t.hold(h).p, dtype=float))
        return out

    def _draw_scene(self) -> None:
        scene = self.server.scene
        scene.set_up_direction(tuple(-np.asarray(self.state.session.terrain().g, dtype=float)
                                     / np.linalg.norm(self.state.session.terrain().g)))
        self.holds: dict[str, Any] = {}
        self.hold_pos = self._all_holds()
        for hid, p in self.hold_pos.items():
            h = scene.add_icosphere(f"/holds/{hid}", radius=HOLD_RADIUS, color=COLORS["hold"], position=p,
                                    subdivisions=1, cast_shadow=False, receive_shadow=False)
            h.on_click(lambda ev, hid=hid: self.select(hid))
            self.holds[hid] = h
        self.drawing = RobotDrawing(scene, self.robot)
        self.com = scene.add_icosphere("/com", radius=0.025, color=COLORS["com"])
        self.region: Any = None

    def _camera(self, client: Any) -> None:
        """Point a new client's camera at the robot, from in front of the wall."""
        stance, q = self.state.session.state()
        c = np.asarray(self.robot.com(q), dtype=float)
        terrain = self.state.session.terrain()
        up = -np.asarray(terrain.g, dtype=float) / np.linalg.norm(terrain.g)
        n = np.mean([terrain.hold(h).n for h in terrain.hold_ids], axis=0)
        n = n - (n @ up) * up  # the wall's normal: the holds' mean normal, level
        n = n / (np.linalg.norm(n) or 1.0)
        client.camera.position = c + 2.2 * n + 0.3 * up
        client.camera.look_at = c + 0.3 * up
        client.camera.up_direction = up

    # ---- the panel ----------------------------------------------------------------------------------------
    def _add_gui(self) -> None:
        gui = self.server.gui
        limbs = [lb.name for lb in self.robot.limbs]
        self.md_state = gui.add_markdown("")
        self.md_selected = gui.add_markdown("")
        self.limb_value = limbs[0]
        self.limb = gui.add_button_group("Limb", limbs)
        self.b_grab = gui.add_button("Grab selected hold")
        self.b_release = gui.add_button("Release limb")
        self.b_reach = gui.add_button("Reach selected hold (multi-step)")
        self.climb_m = gui.add_number("Climb (m)", 1.0, min=0.05, max=10.0, step=0.05)
        self.b_climb = gui.add_button("Climb (multi-step)")
        self.threshold = gui.add_number("Margin threshold (m)", self.state.threshold, min=0.0, max=1.0, step=0.005)
        self.md_proposal = gui.add_markdown("")
        self.slider = gui.add_slider("Preview (s)", min=0.0, max=1.0, step=0.01, initial_value=0.0)
        self.b_play = gui.add_button("Play / pause")
        self.b_accept = gui.add_button("Accept", color="green")
        self.b_reject = gui.add_button("Reject")
        self.b_undo = gui.add_button("Undo")
        self.b_failed = gui.add_button("Hold failed (selected)", color="red")
        self.md_message = gui.add_markdown("")
        self.limb.on_click(lambda ev: self._limb(str(ev.target.value)))
        self.b_grab.on_click(lambda _: self._goal(lambda: f"grab {self.limb_value}={self.selected}"))
        self.b_release.on_click(lambda _: self.state.submit(f"release {self.limb_value}"))
        self.b_reach.on_click(lambda _: self._goal(lambda: f"hold {self.limb_value}={self.selected}"))
        self.b_climb.on_click(lambda _: self.state.submit(f"climb {float(self.climb_m.value):g}"))
        self.threshold.on_update(lambda _: self.state.set_threshold(float(self.threshold.value)))
        self.slider.on_update(lambda ev: self._scrub(ev.client is not None))
        self.b_play.on_click(lambda _: self._toggle())
        self.b_accept.on_click(lambda _: self.state.accept())
        self.b_reject.on_click(lambda _: self.state.reject())
        self.b_undo.on_click(lambda _: self.state.undo())
        self.b_failed.on_click(lambda _: self._failed())

    def _limb(self, limb: str) -> None:
        self.limb_value = limb
        self.refresh("limb")

    def _goal(self, text: Any) -> None:
        if self.selected is None:
            self.state.message = "refused: click a hold first"
            self.refresh("message")
            return
        self.state.submit(text())

    def _failed(self) -> None:
        if self.selected is None:
            self.state.message = "refused: click the hold that failed first"
            self.refresh("message")
            return
        threading.Thread(target=self.state.fail_hold, args=(self.selected,), daemon=True).start()

    def select(self, hid: str) -> None:
        """Select hold ``hid`` (a click on it): highlighted at once."""
        self.stamps["select"] = time.perf_counter()
        old, self.selected = self.selected, hid
        if old is not None and old in self.holds:
            self.holds[old].color = self._hold_color(old)
        self.holds[hid].color = COLORS["selected"]
        self._selected_text()
        self.server.flush()  # to the page now, not at the next message window

    def _selected_text(self) -> None:
        self.md_selected.content = (f"**Selected hold**: {self.selected or 'none (click a hold)'}; "
                                    f"**limb**: {self.limb_value}")

    # ---- the preview ---------------------------------------------------------------------------------------
    def _toggle(self) -> None:
        self.playing = not self.playing and self.timeline is not None

    def _scrub(self, by_hand: bool) -> None:
        if self.timeline is None:
            return
        if by_hand:  # the operator moved the slider: the preview stops there
            self.playing = False
        self.t = float(self.slider.value)
        self._pose()

    def _pose(self) -> None:
        assert self.timeline is not None
        ts, qs, ks = self.timeline
        q = configuration_at(ts, qs, self.t)
        self.drawing.place(q)
        p = self.state.proposal
        if p is not None:
            k = int(ks[min(int(np.searchsorted(ts, self.t, side="right")), len(ks)) - 1])
            self.drawing.highlight(p.steps[max(k, 0)].limb)
        self._com(q)

    def _play_loop(self) -> None:
        while not self._stop.is_set():
            time.sleep(1.0 / FPS)
            if not self.playing or self.timeline is None:
                continue
            end = float(self.timeline[0][-1])
            self.t = min(end, self.t + SPEED / FPS)
            self.slider.value = round(self.t, 2)
            self._pose()
            if self.t >= end:
                self.playing = False

    # ---- redrawing -------------------------------------------------------------------------------------------
    def _hold_color(self, hid: str) -> tuple[int, int, int]:
        stance, _ = self.state.session.state()
        p = self.state.proposal
        if hid in self.state.session.failed:
            return COLORS["failed"]
        if hid == self.selected:
            return COLORS["selected"]
        if p is not None and hid in p.holds():
            return COLORS["target"]
        return COLORS["held"] if hid in stance.values() else COLORS["hold"]

    def _com(self, q: np.ndarray) -> None:
        self.com.position = np.asarray(self.robot.com(q), dtype=float)

    def refresh(self, what: str) -> None:
        """Redraw after a change of the console's state (``what``: ``proposal``, ``accepted``, ``busy``, ...)."""
        st, p = self.state, self.state.proposal
        stance, q = st.session.state()
        for hid, h in self.holds.items():
            h.color = self._hold_color(hid)
        if what in ("start", "accepted", "undone", "failed", "refused", "rejected", "proposal"):
            self._draw_region(stance, q)
        if what in ("accepted", "undone"):  # the view follows the robot
            for client in self.server.get_clients().values():
                self._camera(client)
        self.md_state.content = (f"**Session**: {st.session.n_steps} steps accepted; stance "
                                 + ", ".join(f"{k}:{v}" for k, v in sorted(stance.items()))
                                 + (f"; failed holds: {', '.join(st.session.failed)}" if st.session.failed else ""))
        self.md_proposal.content = self._proposal_text()
        self._selected_text()
        self.md_message.content = f"**Message**: {st.message}" if st.message else ""
        if what == "proposal" and p is not None:
            self.timeline = p.timeline()
            self.slider.max = max(0.01, round(float(self.timeline[0][-1]), 2))
            self.t, self.slider.value, self.playing = 0.0, 0.0, True
            self.stamps["preview"] = time.perf_counter()
        elif p is None:
            self.timeline, self.playing = None, False
            self.drawing.place(q)
            self.drawing.highlight(None)
            self._com(q)

    def _draw_region(self, stance: dict[str, str], q: np.ndarray) -> None:
        if self.region is not None:
            self.region.remove()
            self.region = None
        try:
            segs = region_loop(self.robot, self.state.session.terrain(), stance, self.robot.com(q))
        except Exception:  # noqa: BLE001  (a region that cannot be drawn is left out; the page stays up)
            segs = None
        if segs is not None:
            self.region = self.server.scene.add_line_segments("/support", segs, COLORS["support"], thickness=0.008)

    def _proposal_text(self) -> str:
        st, p = self.state, self.state.proposal
        if st.busy is not None:
            return f"**Planning** {st.busy} ..."
        if p is None:
            return "**Proposal**: none (choose a goal)"
        flagged = set(p.flagged(st.threshold))
        rows = [f"| {i} | {s.action} {s.limb} {s.hold} | {m:.3f} | {100 * t:.0f} % | "
                f"{FLAG if i in flagged else 'ok'} |"
                for i, (s, m, t) in enumerate(zip(p.steps, p.margins, p.torques, strict=True))]
        head = (f"**Proposal** for {p.goal}: {len(p.steps)} step(s), planned in {p.seconds:.2f} s"
                + (f" ({p.note})" if p.note else "")
                + (f"; <span style='color:#d21e1e'>{len(flagged)} step(s) with a margin under "
                   f"{st.threshold:.3f} m</span>" if flagged else ""))
        table = "| step | action | margin (m) | torque / limit | |\n|---|---|---|---|---|\n" + "\n".join(rows[:12])
        more = f"\n\n... and {len(rows) - 12} more" if len(rows) > 12 else ""
        return f"{head}\n\n{table}{more}"

    def close(self) -> None:
        """Stop the preview thread and the server."""
        self._stop.set()
        self.server.stop()


__all__ = ["ConsolePage", "FLAG", "FPS", "SPEED"]
