"""``climb-ompl bench replan``: re-planning after a hold fails, warm against from scratch, in the same run.

The climb of ``climb-ompl bench climb`` is planned once with its search kept.  Then, at ``failures`` steps
drawn at random (seeded) along it, the hold that the next grab takes fails (``change``: ``remove``, the hold
breaks, the default; ``move``, it sits :data:`MOVE` metres from where the map put it, in a random direction
across its normal; ``friction``, it is more slippery than mapped: :data:`FRICTION` times its friction), and
the climb is re-planned
from the state reached to the same goal twice: **warm** (:func:`climb_ompl.climb.replan.replan` with the first
search: rejoin the old route, re-use transitions, paths and edge probabilities that the change leaves valid;
as the API does, a search from scratch with the time the warm ones left, ``used_scratch`` counts them)
and **from scratch** (:func:`climb_ompl.climb.multistep.plan_climb` from the same state on the changed terrain, no
knowledge).  Every warm plan is verified against the changed terrain.  A failure whose re-plan would start
from a stance holding the failed hold (nothing to re-plan from) is skipped.

Keys: ``n``, ``found_warm``, ``found_scratch``, ``verified_warm``, ``median_s_warm``, ``median_s_scratch``,
``median_steps_ratio`` (median over failures found both ways of the warm re-plan's new steps / the new steps of the
plan from scratch from the same state on the same changed wall), ``median_total_steps_ratio`` (the same with the
kept steps counted on both sides),
``median_ratio`` (median over failures of warm / scratch time), ``ratio_of_medians``, ``p95_s_warm``, ``change``,
``median_cpu_s_warm``, ``median_cpu_s_scratch``, ``median_cpu_ratio`` (the same on process CPU time, which
other jobs on a shared machine inflate far less than wall time), ``median_relying_share``, ``runs`` (one per
failure: step, failed hold and its change, resumed step, times, steps of each plan, ``relying`` and
``remaining``, the warm re-plan's searches).  With ``all_held`` (``--all-held``), ``all_held``: every hold the
first plan releases fails in turn, removed two steps after its first release (where the state reached no longer
relies on it: the kept steps held it, the new ones may not), and each re-plan goes through the README's flow,
replan, verify, play (drawn in a meshcat scene as ``climb-ompl play`` draws it): ``holds``, ``found``,
``verified``, ``played``, ``failures`` (hold, step and what went wrong, one per hold that did not go through).

**What bounds the ratio.**  Of the old steps left after the resumed step (``remaining``), those up to where the
old route no longer relies on the failed hold (``relying``, :func:`climb_ompl.climb.replan.rejoin_index`) must be
planned
anew: the hold is in their stance, or they grab it.  A hold stays in the stance while the other limbs move, so
this is several steps even for a failure early in the climb; a warm re-plan that planned exactly that many
steps, at the per-step cost of a search from scratch, would take ``relying / remaining`` of its time.  The
median of that share over the failures (``median_relying_share``) is the ratio's bound by this count (LEMUR's
demo climb at seed 0: 0.34).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from climb_ompl.bench._common import execute
from climb_ompl.settings import SEED_MAX

#: Kinds of hold failure: the hold breaks, sits elsewhere, or is more slippery.
CHANGES = ("remove", "move", "friction")
#: How far a moved hold sits from where the map put it, metres.
MOVE = 0.03
#: Friction of a slippery hold, as a share of its mapped friction.
FRICTION = 0.7


def failure(terrain: Any, hold: str, change: str, rng: Any) -> Any:
    """The :class:`~climb_ompl.plan.events.TerrainChange` of ``hold`` failing as ``change`` says."""
    import numpy as np

    from climb_ompl.plan.events import TerrainChange

    if change == "remove":
        return TerrainChange(remove=(hold,))
    h = terrain.hold(hold)
    if change == "friction":
        return TerrainChange(friction={hold: FRICTION * float(h.friction)})
    n = np.asarray(h.normal, dtype=float)
    if terrain.dim == 2:  # across the normal in the x-z plane
        d = np.cross(n, [0.0, 1.0, 0.0]) * rng.choice([-1.0, 1.0])
    else:
        d = rng.normal(size=3)
        d -= d.dot(n) * n
    p = np.asarray(h.position, dtype=float) + MOVE * d / np.linalg.norm(d)
    if terrain.frame is not None:  # a change is written in the terrain file's coordinates (TerrainChange.apply)
        from climb_ompl.model.wall_frame import frame_of

        rot, t = frame_of(terrain)
        p = rot.T @ (p - t)
    return TerrainChange(move={hold: tuple(float(x) for x in (p[[0, 2]] if terrain.dim == 2 else p))})


def run(robot: str = "lemur", terrain: str = "demo-wall", height: float = 2.0, failures: int = 20, seed: int = 0,
        time_limit: float = 120.0, change: str = "remove", all_held: bool = False,
        rejoin: bool | None = None) -> dict[str, Any]:
    """Plan the climb, then re-plan it warm and from scratch at ``failures`` random steps (and with ``all_held``,
    :func:`every_held_hold`)."""
    import time

    import numpy as np

    from climb_ompl.climb.multistep import default_start, load_robot, load_terrain, plan_climb
    from climb_ompl.climb.replan import rejoin_index, replan, state_before
    from climb_ompl.verification.climb import verify

    if change not in CHANGES:
        raise ValueError(f"change: {change!r} is not one of {', '.join(CHANGES)}")
    rob, ter = load_robot(robot), load_terrain(terrain)
    start = default_start(rob, ter, seed=seed)
    if start is None:
        raise ValueError(f"no start stance for {robot} on {terrain}")
    stance, q0 = start
    z0 = max(ter.height(h) for h in stance.values())  # along minus gravity (a slab's, a ramp's)
    t0 = time.perf_counter()
    first = plan_climb(rob, ter, stance, z0 + height, q_start=q0, seed=seed, time_limit=time_limit, keep_search=True)
    out: dict[str, Any] = {"first_found": first.found, "first_s": time.perf_counter() - t0}
    if not first.found or first.plan is None:
        return {**out, "n": 0, "reason": first.reason}
    plan = first.plan
    grabs = [i for i, s in enumerate(plan.steps) if s.action == "grab"]
    rng = np.random.default_rng(seed)
    # failures at steps 1.. (at step 0 nothing was executed: that is a plan on another terrain, not a re-plan)
    steps = sorted(1 + int(k) for k in rng.choice(grabs[-1], size=min(failures, grabs[-1]), replace=False))
    runs = []
    for k in steps:
        j = next(i for i in grabs if i >= k)
        edit = failure(ter, plan.steps[j].hold, change, rng)
        t1, c1 = time.perf_counter(), time.process_time()
        w = replan(plan, k, edit, warm=first.search, robot=rob, rejoin=rejoin)
        tw, cw = time.perf_counter() - t1, time.process_time() - c1
        st, q = state_before(plan, w.resumed_at)
        if set(st.values()) & edit.touched:  # the start stance holds the hold: nothing to re-plan from
            continue
        t2, c2 = time.perf_counter(), time.process_time()
        s = plan_climb(rob, edit.apply(ter), st, plan.query["goal"], seed=seed, q_start=q, time_limit=time_limit)
        ts, cs = time.perf_counter() - t2, time.process_time() - c2
        ok = bool(w.found and w.plan is not None and verify(w.plan).ok)
        relying = rejoin_index(plan, w.resumed_at, edit.touched) - w.resumed_at
        runs.append({"at_step": k, "hold": plan.steps[j].hold, "change": edit.to_dict(),
                     "resumed_at": w.resumed_at,
                     "found_warm": w.found, "verified_warm": ok, "s_warm": tw, "steps_warm": len(w.plan.steps) if
                     w.plan else 0, "found_scratch": s.found, "s_scratch": ts,
                     "steps_scratch": w.resumed_at + (len(s.plan.steps) if s.plan else 0),
                     "reason_warm": w.climb.reason,
                     "used": w.used, "cpu_s_warm": cw, "cpu_s_scratch": cs, "relying": relying,
                     "remaining": len(plan.steps) - w.resumed_at, "searches": w.stats.get("searches", [])})
    tw_all = np.array([r["s_warm"] for r in runs])
    ts_all = np.array([r["s_scratch"] for r in runs])
    both = [r for r in runs if r["found_warm"] and r["found_scratch"] and r["steps_scratch"] > r["resumed_at"]]
    if all_held:
        out["all_held"] = every_held_hold(plan, rob, first.search)
    return {**out, "n": len(runs), "old_steps": len(plan.steps), "change": change,
            "median_steps_ratio": float(np.median([(r["steps_warm"] - r["resumed_at"]) /
                                                   (r["steps_scratch"] - r["resumed_at"]) for r in both]))
            if both else None,
            "median_total_steps_ratio": float(np.median([r["steps_warm"] / r["steps_scratch"] for r in both]))
            if both else None,
            "found_warm": sum(r["found_warm"] for r in runs), "found_scratch": sum(r["found_scratch"] for r in runs),
            "verified_warm": sum(r["verified_warm"] for r in runs),
            "used_scratch": sum(r["used"] == "scratch" for r in runs),
            "median_s_warm": float(np.median(tw_all)), "median_s_scratch": float(np.median(ts_all)),
            "median_ratio": float(np.median(tw_all / ts_all)), "p95_s_warm": float(np.percentile(tw_all, 95)),
            "ratio_of_medians": float(np.median(tw_all) / np.median(ts_all)),
            "median_cpu_s_warm": float(np.median([r["cpu_s_warm"] for r in runs])),
            "median_cpu_s_scratch": float(np.median([r["cpu_s_scratch"] for r in runs])),
            "median_cpu_ratio": float(np.median([r["cpu_s_warm"] / r["cpu_s_scratch"] for r in runs])),
            "median_relying_share": float(np.median([r["relying"] / r["remaining"] for r in runs])),
            "runs": runs}


def every_held_hold(plan: Any, robot: Any, search: Any) -> dict[str, Any]:
    """Every hold ``plan`` releases fails in turn, removed two steps after its first release (once the state reached
    no longer relies on it: the hand that let go of it has moved), where the plan has steps left then; each re-plan
    goes through replan, verify and play: the counts and, per hold that did not go through, what went wrong (module
    docstring, ``all_held``)."""
    from climb_ompl.climb.replan import replan
    from climb_ompl.errors import ClimbError
    from climb_ompl.plan.events import TerrainChange
    from climb_ompl.verification.climb import verify
    from climb_ompl.viz import Scene, draw_plan, open_visualizer

    tried: dict[str, int] = {}
    for i, s in enumerate(plan.steps):
        if s.action == "release" and s.hold not in tried and i + 2 < len(plan.steps):
            tried[s.hold] = i + 2
    counts = {"holds": len(tried), "found": 0, "verified": 0, "played": 0}
    failures = []
    with open_visualizer() as vis:
        for hold, k in tried.items():
            res = replan(plan, k, TerrainChange(remove=(hold,)), warm=search, robot=robot)
            why = None if res.found and res.plan is not None else f"no re-plan: {res.climb.reason.splitlines()[0]}"
            if why is None:
                counts["found"] += 1
                report = verify(res.plan)
                why = None if report.ok else f"verify: {report.violations[0]}"
            if why is None:
                counts["verified"] += 1
                try:
                    vis.delete()
                    draw_plan(Scene(vis), res.plan.to_dict(), robot=robot)
                    counts["played"] += 1
                except ClimbError as exc:
                    why = f"play: {exc}"
            if why is not None:
                failures.append({"hold": hold, "at_step": k, "why": why})
    return {**counts, "failures": failures}


def summary(result: dict[str, Any]) -> str:
    """One line: failures, found warm / from scratch, median times and their ratio."""
    if not result.get("n"):
        return f"first climb found={result.get('first_found')}: {result.get('reason', '')}"
    return (f"n={result['n']} found warm={result['found_warm']} (verified {result['verified_warm']}) "
            f"scratch={result['found_scratch']} median warm={result['median_s_warm']:.1f}s "
            f"scratch={result['median_s_scratch']:.1f}s ratio={result['median_ratio']:.2f} "
            f"p95 warm={result['p95_s_warm']:.1f}s cpu median warm={result['median_cpu_s_warm']:.1f}s "
            f"scratch={result['median_cpu_s_scratch']:.1f}s ratio={result['median_cpu_ratio']:.2f} "
            f"steps relying on the failed hold: median {result['median_relying_share']:.2f} of those left"
            + (f"; new steps vs from scratch: median ratio {result['median_steps_ratio']:.2f} (all steps "
               f"{result['median_total_steps_ratio']:.2f})" if result.get("median_steps_ratio") is not None else "")
            + ("; every held hold failed in turn: {holds} holds, re-planned {found}, verified {verified}, played "
               "{played}".format(**result["all_held"]) if result.get("all_held") else ""))


def command(
    robot: str = typer.Option("lemur", help="Robot name or spec file."),
    terrain: str = typer.Option("demo-wall", help="Terrain name or file."),
    height: float = typer.Option(2.0, help="Climb this many metres above the start stance's highest hold."),
    failures: int = typer.Option(20, help="Number of hold failures along the climb."),
    seed: int = typer.Option(0, min=0, max=SEED_MAX, help="Seed of the planner and of the failure draws."),
    time_limit: float = typer.Option(120.0, help="Budget of each search, s."),
    change: str = typer.Option("remove", help="How the hold fails: remove (it breaks), move (it sits 3 cm "
                                              "away), friction (70 % of its friction)."),
    all_held: bool = typer.Option(False, "--all-held", help="Also fail every hold the plan holds in turn, each "
                                  "re-plan through replan, verify and play (a few minutes more)."),
    rejoin: bool = typer.Option(None, "--rejoin/--no-rejoin", help="The warm re-plans search first for a way back "
                                "onto the old route \\[replan's default: only when no hold was removed]."),
    out: Path = typer.Option(None, help="Write the JSON result here."),
) -> None:
    """Re-planning after a hold fails: warm vs from scratch (same failures, same run)."""
    from climb_ompl._options import check_positive

    check_positive(time_limit, "--time-limit", "seconds")
    if change not in CHANGES:
        from climb_ompl._options import error

        raise error(f"--change: {change!r} is not one of {', '.join(CHANGES)}")
    execute("replan", dict(robot=robot, terrain=terrain, height=height, failures=failures, seed=seed,
                           time_limit=time_limit, change=change, all_held=all_held, rejoin=rejoin), out,
            timeout=600.0 + (2 * failures + 1) * (time_limit + 60.0) + (3600.0 if all_held else 0.0))
