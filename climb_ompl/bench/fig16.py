"""``climb-ompl bench fig16``: the two-stage search of Bretl (2006), Fig. 16, as published (``--search paper``) on
the papers' three robots: LEMUR's 2 m climb of the demo wall, the double-link robot between the pegs (Fig. 13's
route 1 -> 2 -> 3 -> 2 -> 4) and the planar three-limbed robot on its crack (Bretl, Latombe & Rock 2003).

Each run records whether a plan was found and verified, its steps and holds, the CPU time of the process
(``time.process_time``) and where the search's time went: FIND-TRANSITION calls, FIND-PATH calls and the rest
(stage 1's bookkeeping, the start, the plan's assembly), from the search's counters.  ``--set NAME=VALUE`` changes
one setting of the mode (a departure, to measure what it costs or buys).  docs/papers.md takes its Fig. 16 row from
these files (``make papers``).
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import numpy as np
import typer

from climb_ompl.settings import SEED_MAX

#: The cases: robot, terrain, start stance (``None``: the default start), goal (a height in metres, or ``LIMB=HOLD``),
#: start configuration (``None``: the start finder's).
CASES: dict[str, dict[str, Any]] = {
    "lemur": {"robot": "lemur", "terrain": "demo-wall", "start": None, "height": 2.0, "q_start": None},
    # the double-link robot's start as in its test: theta1 a whole turn down (docs/climb.md)
    "double-link": {"robot": "double-link", "terrain": "pegs", "start": {"a": "1"}, "goal": "a=4",
                    "q_start": [1.70, 0.90, 0.5 - 2 * np.pi, 1.0]},
    "planar": {"robot": "planar-3limb", "terrain": "planar-wall", "start": None, "goal": 2.0, "q_start": None},
}


def _goal(case: dict[str, Any], rob: Any, ter: Any, stance: Any) -> Any:
    """The case's goal: ``height`` metres of mean hold height above the start (as ``bench papers``' climb), else
    its ``goal``."""
    if "height" not in case:
        return case["goal"]
    from climb_ompl.bench.papers import robot_reach

    z0 = float(np.mean([ter.hold(h).p[2] for h in stance.values()]))
    return z0 + 0.5 * robot_reach(rob) + case["height"]


def run(case: str = "lemur", seed: int = 0, time_limit: float = 600.0,
        changes: dict[str, Any] | None = None) -> dict[str, Any]:
    """One climb of ``case`` (:data:`CASES`) with the ``paper`` search and ``changes`` on top, at ``seed``."""
    from climb_ompl.climb.multistep import default_start, load_robot, load_terrain, plan_climb
    from climb_ompl.settings import ClimbSettings
    from climb_ompl.verification.climb import verify

    c = CASES[case]
    rob, ter = load_robot(c["robot"]), load_terrain(c["terrain"])
    cpu0, t0 = time.process_time(), time.perf_counter()
    if c["start"] is None:
        stance, q0 = default_start(rob, ter, seed=seed)
    else:
        stance, q0 = c["start"], c["q_start"]
    settings = ClimbSettings.for_search("paper", robot=rob, time_limit=time_limit, **(changes or {}))
    res = plan_climb(rob, ter, stance, _goal(c, rob, ter, dict(stance)), settings, q_start=q0, seed=seed)
    cpu, wall = time.process_time() - cpu0, time.perf_counter() - t0
    st = res.stats
    t_tr, t_fp = float(sum(st.get("transition_times_s", []))), float(sum(st.get("onestep_times_s", [])))
    out: dict[str, Any] = {
        "case": case, "robot": c["robot"], "terrain": c["terrain"], "seed": seed, "time_limit": time_limit,
        "changes": changes or {}, "found": res.found, "status": getattr(res.status, "value", str(res.status)),
        "cpu_s": cpu, "wall_s": wall,
        "reason": res.reason, "stances_explored": st.get("stances_explored"), "candidates": st.get("candidates"),
        "transition_calls": st.get("transition_calls"), "path_calls": st.get("path_calls"),
        "path_timeouts": st.get("path_timeouts"), "path_failures": st.get("path_failures"),
        "time_split_s": {"find_transition": t_tr, "find_path": t_fp,
                         "rest": max(0.0, float(st.get("total_s", wall)) - t_tr - t_fp)}}
    if res.found:
        plan = res.plan
        grabbed = [s.hold for s in plan.steps if s.action == "grab"]
        out.update(steps=len(plan.steps), verified=bool(verify(plan).ok),
                   route=" -> ".join([*sorted(dict(stance).values()), *grabbed]))
    return out


def summary(result: dict[str, Any]) -> str:
    """One line: the case, found or not, steps, CPU time and where the time went."""
    sp = result["time_split_s"]
    head = (f"{result['case']} seed {result['seed']}: " + (f"{result['steps']} steps, verified {result['verified']}"
                                                          if result["found"] else f"no plan ({result['status']})"))
    return (f"{head}; CPU {result['cpu_s']:.0f} s; FIND-TRANSITION {sp['find_transition']:.0f} s, FIND-PATH "
            f"{sp['find_path']:.0f} s ({result['path_calls']} calls, {result['path_timeouts']} on the time guard), "
            f"rest {sp['rest']:.0f} s; {result['stances_explored']} nodes, {result['candidates']} candidates")


def command(
    case: str = typer.Option("lemur", "--case", help=f"One of: {', '.join(CASES)}."),
    seed: int = typer.Option(0, "--seed", min=0, max=SEED_MAX, help="Seed of the climb."),
    time_limit: float = typer.Option(600.0, "--time-limit", help="Budget of the climb's search, s."),
    set_: list[str] = typer.Option(None, "--set", help="NAME=VALUE: a setting changed from the paper mode's."),
    out: Path = typer.Option(None, "--out", help="Write the result JSON here."),
) -> None:
    """Fig. 16 as published (``--search paper``) on one of the papers' robots (docs/papers.md, docs/climb.md)."""
    import yaml

    from climb_ompl._options import check_positive, error
    from climb_ompl.bench._common import execute
    from climb_ompl.errors import ClimbError
    from climb_ompl.settings import ClimbSettings

    if case not in CASES:
        raise error(f"--case: {case!r} is not one of {', '.join(CASES)}")
    check_positive(time_limit, "--time-limit", "seconds")
    changes: dict[str, Any] = {}
    for item in set_ or []:
        key, eq, text = item.partition("=")
        if not eq or not key.strip():
            raise error(f"--set: expected NAME=VALUE, got {item!r}")
        changes[key.strip()] = yaml.safe_load(text)
    try:
        ClimbSettings.for_search("paper", **changes)
    except ClimbError as exc:
        raise error(f"--set: {exc}") from None
    execute("fig16", {"case": case, "seed": seed, "time_limit": time_limit, "changes": changes}, out,
            timeout=3 * time_limit + 600)
