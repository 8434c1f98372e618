"""``climb-ompl bench console``: the operator's console, planner and page.

**Planner.**  LEMUR's demo climb (``climb-ompl demo``'s query: 2 m above the start stance's highest hold) is
planned once; then each of its steps is planned again as the operator's single-step goal from the state before it
(``grab LIMB=HOLD`` or ``release LIMB``, :func:`climb_ompl.climb.step.plan_goal`): ``single_median_s``,
``single_p95_s`` (wall clock), ``single_cpu_median_s``, ``single_found``.  At ``multi`` states spread along the
climb, a multi-step goal about 1 m above: the limb of the next grab, to the first hold the demo climb gives that limb
at least 1 m above the one it holds or last held (``hold LIMB=HOLD``): ``multi_median_s``, ``multi_found``.

**Page** (headless Chromium, ``browser``): a scripted operator climbs the demo wall to the demo climb's goal through
the console only: it clicks holds, sets the climb, presses the buttons, lets the preview play, accepts, and marks one
hold of the first proposal failed (the console re-plans it).  ``click_ms``: from the click (page time) to the page
showing the hold selected (the hold's colour is sent in the same server callback, before that text);
``preview_ms``: from the proposal's text appearing to the preview slider's first move, page times; ``climb``: the
session's steps, its final stance, whether it meets the goal and whether ``verify`` accepts the session.
"""

from __future__ import annotations

import statistics
import time
from pathlib import Path
from typing import Any

import numpy as np
import typer

from climb_ompl.bench._common import execute
from climb_ompl.settings import SEED_MAX

#: The demo climb's rise above the start stance's highest hold, m (``climb-ompl demo``).
HEIGHT = 2.0
#: A multi-step goal's hold is at least this far above the limb's hold, m.
MULTI_RISE = 1.0


def _p95(xs: list[float]) -> float:
    return float(np.percentile(xs, 95)) if xs else float("nan")


def _goal_text(step: Any) -> str:
    return f"grab {step.limb}={step.hold}" if step.action == "grab" else f"release {step.limb}"


def planner_figures(plan: Any, robot: Any, terrain: Any, settings: Any, seed: int, multi: int) -> dict[str, Any]:
    """Single-step goals over the demo climb's steps, and ``multi`` multi-step goals about 1 m above."""
    from climb_ompl.climb.step import plan_goal

    wall, cpu, found = [], [], 0
    for i, st in enumerate(plan.steps):
        r = plan_goal(robot, terrain, dict(st.stance), st.waypoints[0], _goal_text(st), settings, seed=seed + i)
        wall.append(r.seconds)
        cpu.append(r.cpu_s)
        found += r.found
    runs = []
    for i in np.linspace(0, len(plan.steps) - 1, multi + 2)[1:-1].astype(int):
        st = plan.steps[int(i)]
        nxt = next((s for s in plan.steps[i:] if s.action == "grab"), None)
        if nxt is None:
            continue
        last = dict(st.stance).get(nxt.limb) or next(  # the hold the limb holds, or last held
            (s.hold for s in reversed(plan.steps[:i]) if s.limb == nxt.limb), dict(plan.start_stance)[nxt.limb])
        z0 = terrain.height(last)
        far = next((s for s in plan.steps[i:] if s.action == "grab" and s.limb == nxt.limb
                    and terrain.height(s.hold) >= z0 + MULTI_RISE), None)
        if far is None:
            continue
        r = plan_goal(robot, terrain, dict(st.stance), st.waypoints[0], f"hold {far.limb}={far.hold}", settings,
                      seed=seed + 1000 + int(i))
        runs.append({"step": int(i), "goal": f"hold {far.limb}={far.hold}", "rise_m": terrain.height(far.hold) - z0,
                     "found": r.found, "s": r.seconds, "cpu_s": r.cpu_s, "steps": len(r.steps)})
    ms = [r["s"] for r in runs]
    return {"single_n": len(wall), "single_found": found, "single_median_s": statistics.median(wall),
            "single_p95_s": _p95(wall), "single_max_s": max(wall), "single_cpu_median_s": statistics.median(cpu),
            "single_cpu_p95_s": _p95(cpu), "multi_n": len(runs), "multi_found": sum(r["found"] for r in runs),
            "multi_median_s": statistics.median(ms) if ms else float("nan"),
            "multi_cpu_median_s": statistics.median([r["cpu_s"] for r in runs]) if runs else float("nan"),
            "multi_runs": runs}


def _click(op: Any, hid: str, out: dict[str, list[float]]) -> bool:
    """Click hold ``hid``; record the page's milliseconds until it shows the hold selected (and until the server's
    callback ran); whether the click selected it."""
    got = op.click_latency(hid)
    if got is None:
        out["missed"].append(1.0)
        return False
    out["click_ms"].append(got[0])
    out["to_server_ms"].append(got[1])
    return True


def _propose(op: Any, button: str, goal: str, out: dict[str, list[float]]) -> None:
    """Press ``button``; wait for the proposal of ``goal``; record when its preview started."""
    from climb_ompl.console.operator import JS_SLIDER

    text = f"proposal for {goal}"
    op.watch(text)
    op.page.evaluate(JS_SLIDER)
    op.press(button)
    arrived = op.seen(text, 600.0)
    op.page.wait_for_timeout(1200)
    moves = op.page.evaluate("() => window.__slider")
    started = [t for t, v in moves if v not in ("0", None) and t >= arrived]
    if started:
        out["preview_ms"].append(started[0] - arrived)


def scripted_climb(console: Any, goal_height: float, *, chunk: float = 0.3, clicks: int = 12,
                   max_goals: int = 16) -> dict[str, Any]:
    """The scripted operator's climb (see the module docstring) in headless Chromium."""
    from climb_ompl.console.operator import browse
    from climb_ompl.verification import verify

    st = console.state
    out: dict[str, list[float]] = {"click_ms": [], "to_server_ms": [], "preview_ms": [], "server_side": [],
                                   "missed": []}
    failed = None
    reach = max(float(lb.reach) for lb in console.robot.limbs)
    t0 = time.perf_counter()
    with browse(console) as op:
        _, q = st.session.state()
        com = console.robot.com(q)
        above = sorted(console.hold_pos, key=lambda h: np.linalg.norm(console.hold_pos[h] - com - [0, 0, 0.6]))
        for hid in above[:clicks]:  # holds about 0.6 m above the robot
            _click(op, hid, out)
            op.page.wait_for_timeout(200)
        for _ in range(max_goals):
            terrain = st.session.terrain()
            stance, q = st.session.state()
            if min(terrain.height(h) for h in stance.values()) >= goal_height - reach:
                break
            top = max(terrain.height(h) for h in stance.values())
            c = round(min(chunk, max(0.05, goal_height - reach - top + 0.01)), 2)
            op.page.get_by_label("Climb (m)").fill(f"{c:g}")
            op.page.wait_for_timeout(300)
            _propose(op, "Climb (multi-step)", f"climb {c:g}", out)
            if st.proposal is None:
                break
            if failed is None and len(st.proposal.holds()) > 1:
                failed = st.proposal.holds()[1]
                if not _click(op, failed, out):  # the click missed it (behind the robot): selected server-side,
                    console.select(failed)      # counted in ``selected_server_side``
                    out["server_side"].append(1.0)
                op.watch(f"hold {failed} failed")
                op.press("Hold failed (selected)")
                op.seen(f"hold {failed} failed", 600.0)
                op.wait_idle(600.0)
                if st.proposal is None:
                    continue
            op.press("Accept")
            op.wait_text(f"Session: {st.session.n_steps} steps accepted")
        blocked = list(op.blocked)
    terrain = st.session.terrain()
    stance, _ = st.session.state()
    report = verify(st.session.plan)
    def med(xs: list[float]) -> float:
        return statistics.median(xs) if xs else float("nan")

    return {"click_ms": out["click_ms"], "to_server_ms": out["to_server_ms"], "clicks_missed": len(out["missed"]),
            "preview_ms": out["preview_ms"], "selected_server_side": len(out["server_side"]),
            "click_median_ms": med(out["click_ms"]), "click_p95_ms": _p95(out["click_ms"]),
            "click_max_ms": max(out["click_ms"], default=float("nan")),
            "to_server_median_ms": med(out["to_server_ms"]),
            "preview_median_ms": med(out["preview_ms"]), "preview_p95_ms": _p95(out["preview_ms"]),
            "preview_max_ms": max(out["preview_ms"], default=float("nan")),
            "climb": {"steps": st.session.n_steps, "stance": stance, "failed": st.session.failed,
                      "goal_height": goal_height, "met": min(terrain.height(h) for h in stance.values())
                      >= goal_height - reach, "verified": bool(report.ok), "verify": report.summary(),
                      "s": time.perf_counter() - t0, "goals": [g["goal"] for g in st.session.record["goals"]]},
            "blocked_requests": blocked}


def run(seed: int = 0, multi: int = 6, browser: bool = True, session: str | None = None) -> dict[str, Any]:
    """The planner's figures and, with ``browser``, the page's (``session``: where the scripted climb's session
    file is written)."""
    import tempfile

    from climb_ompl.climb.multistep import default_start, plan_climb
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.settings import ClimbSettings

    robot, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    stance, q0 = default_start(robot, wall, seed=seed)
    goal = max(wall.height(h) for h in stance.values()) + HEIGHT
    settings = ClimbSettings.for_search("guided", robot=robot)
    t = time.process_time()
    res = plan_climb(robot, wall, stance, goal, settings, seed=seed, q_start=q0)
    out: dict[str, Any] = {"demo_steps": len(res.plan.steps) if res.plan else 0,
                           "demo_cpu_s": time.process_time() - t}
    if res.plan is None:
        return {**out, "reason": res.reason}
    out.update(planner_figures(res.plan, robot, wall, settings, seed, multi))
    if browser:
        from climb_ompl.console import open_console

        path = Path(session) if session else Path(tempfile.mkdtemp()) / "session.json"
        path.unlink(missing_ok=True)  # the scripted climb starts a new session there
        page = open_console("lemur", "demo-wall", path, port=_free_port(), seed=seed)
        try:
            out.update(scripted_climb(page, goal))
        finally:
            page.close()
        out["session_file"] = str(path)
    return out


def _free_port() -> int:
    import socket

    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def summary(result: dict[str, Any]) -> str:
    """One line: single-step and multi-step times, the page's latencies, the scripted climb."""
    if "single_n" not in result:
        return f"demo climb not found: {result.get('reason', '')}"
    text = (f"single step: {result['single_found']}/{result['single_n']} found, median {result['single_median_s']:.3f}"
            f" s, p95 {result['single_p95_s']:.3f} s (CPU median {result['single_cpu_median_s']:.3f} s); multi-step "
            f"~1 m: {result['multi_found']}/{result['multi_n']} found, median {result['multi_median_s']:.2f} s")
    if "climb" in result:
        c = result["climb"]
        text += (f"; page: click -> highlight median {result['click_median_ms']:.0f} ms, p95 "
                 f"{result['click_p95_ms']:.0f} (to the server {result['to_server_median_ms']:.0f}), plan -> preview "
                 f"median {result['preview_median_ms']:.0f} ms, p95 {result['preview_p95_ms']:.0f}; scripted climb: "
                 f"{c['steps']} steps, failed {c['failed']}, goal met {c['met']}, {c['verify']}")
    return text


def command(
    seed: int = typer.Option(0, min=0, max=SEED_MAX, help="Seed of the demo climb and of every goal."),
    multi: int = typer.Option(6, min=0, help="Multi-step goals (about 1 m above) along the demo climb."),
    browser: bool = typer.Option(True, "--browser/--no-browser", help="Also the page, in headless Chromium."),
    session: Path = typer.Option(None, help="Write the scripted climb's session file here."),
    out: Path = typer.Option(None, help="Write the JSON result here."),
) -> None:
    """The operator's console: single-step and multi-step plan times, click and preview latencies in the browser,
    a scripted 2 m climb with a hold failed, verified."""
    execute("console", dict(seed=seed, multi=multi, browser=browser,
                            session=None if session is None else str(session.resolve())), out, timeout=3600.0)
