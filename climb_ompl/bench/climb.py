"""``climb-ompl bench climb``: the multi-step planner on LEMUR (Bretl (2006), section 5.3; Bretl et al. (2004)).

One run plans a climb of ``height`` metres above the start stance (goal: every contact hold at or above
``z0 + height - reach``, :class:`climb_ompl.climb.goal.Goal`), verifies the plan with
:func:`climb_ompl.verification.climb.verify`, and records: ``success`` (found and verified), ``steps``,
``total_s`` (planning wall time), ``cpu_s`` (its process CPU time, which other jobs on a shared machine
inflate far less), ``onestep_calls`` (FIND-TRANSITION + FIND-PATH calls),
``onestep_median_s`` (median time of a step's motion planning: the direct local path or OMPL),
``stances_explored``, ``execution_s``.  With ``--walls N`` it also plans on ``N`` generated walls
(``generate_wall(seed=k)`` with the demo wall's parameters, ``k = 0 .. N-1``) and reports the success
rate.  ``--plot`` writes the histogram of one-step planning times (Bretl et al. (2004) report 0.09-17.3 s, mean
1.02 s, on a 1 GHz PowerPC).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from climb_ompl.bench._common import execute
from climb_ompl.errors import QueryError
from climb_ompl.settings import SEED_MAX


def _one(robot_name: str, terrain: Any, height: float, seed: int, time_limit: float,
         settings: dict[str, Any] | None = None) -> dict[str, Any]:
    import time

    from climb_ompl.climb.multistep import plan_climb
    from climb_ompl.climb.start import find_start
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.verification.climb import verify

    robot = RobotModel.load(robot_name)
    t0, c0 = time.perf_counter(), time.process_time()
    start = find_start(robot, terrain, seed=seed)
    if start.stance is None or start.q is None:
        return {"terrain": terrain.name, "success": False, "reason": start.explain(robot.name, terrain.name),
                "total_s": time.perf_counter() - t0}
    stance, q0 = start.stance, start.q
    z0 = max(terrain.height(h) for h in stance.values())
    res = plan_climb(robot, terrain, stance, z0 + height, q_start=q0, seed=seed,
                     **{**(settings or {}), "time_limit": time_limit})
    total, cpu = time.perf_counter() - t0, time.process_time() - c0
    s = res.stats
    out: dict[str, Any] = {
        "terrain": terrain.name, "found": res.found, "steps": s.get("steps", 0), "total_s": total, "cpu_s": cpu,
        "onestep_calls": s.get("onestep_calls", 0), "stances_explored": s.get("stances_explored", 0),
        "path_timeouts": s.get("path_timeouts", 0),
        "execution_s": s.get("execution_s", 0.0), "candidates": s.get("candidates", 0), "reason": res.reason,
        "goal_height": z0 + height, "start": dict(sorted(stance.items())),
    }
    times = [float(t) for t in s.get("step_times_s", [])]
    out["onestep_times_s"] = times
    out["onestep_median_s"] = float(sorted(times)[len(times) // 2]) if times else 0.0
    if res.found and res.plan is not None:
        t1 = time.perf_counter()
        rep = verify(res.plan)
        out.update(verified=rep.ok, violations=len(rep.violations), verify_s=time.perf_counter() - t1)
    else:
        out.update(verified=False, violations=None)
    out["success"] = bool(out["found"] and out["verified"])
    return out


def run(robot: str = "lemur", terrain: str = "demo-wall", height: float = 2.0, seed: int = 0,
        time_limit: float = 120.0, walls: int = 0, plot: str | None = None, search: str = "guided",
        sampler: str | None = None, compare: str | list[str] | None = "paper") -> dict[str, Any]:
    """Plan (and verify) the climb on ``terrain`` and on ``walls`` generated walls; see the module docstring.

    ``search`` and ``sampler`` choose the settings (:class:`climb_ompl.settings.ClimbSettings`); with
    ``compare`` (search modes, or settings as ``key=value,...``: :func:`compare_settings`; one or a list) the
    main terrain is also planned with each other choice in the same run, reported under ``compare`` (a list).
    """
    from climb_ompl.climb.multistep import load_terrain
    from climb_ompl.model.terrain import generate_wall

    settings: dict[str, Any] = {"search": search, **({"sampler": sampler} if sampler else {})}
    # every --compare checked before the first climb
    others = [{**settings, **compare_settings(c)} for c in ([compare] if isinstance(compare, str) else compare or [])
              if c]
    main = _one(robot, load_terrain(terrain), height, seed, time_limit, settings)
    result: dict[str, Any] = {k: main[k] for k in ("success", "steps", "total_s", "cpu_s", "onestep_calls",
                                                   "onestep_median_s", "stances_explored", "execution_s",
                                                   "verified", "reason", "goal_height")}
    result["runs"] = [main]
    if walls > 0:
        gen = [_one(robot, generate_wall(k, height=3.0), height, seed, time_limit, settings) for k in range(walls)]
        result["walls"] = {"n": walls, "successes": sum(r["success"] for r in gen),
                           "success_rate": sum(r["success"] for r in gen) / walls,
                           "generator": "generate_wall(seed=k, height=3.0), other parameters at their defaults",
                           "runs": gen}
    result["settings"] = settings
    if others:
        result["compare"] = []
    for other in others:
        c = _one(robot, load_terrain(terrain), height, seed, time_limit, other)
        result["compare"].append({"settings": other, **{k: c[k] for k in (
            "success", "steps", "total_s", "cpu_s", "onestep_calls", "stances_explored", "reason")}})
    if plot:
        _histogram([t for r in [main, *result.get("walls", {}).get("runs", [])] for t in r["onestep_times_s"]],
                   Path(plot))
        result["plot"] = plot
    return result


def compare_settings(text: str) -> dict[str, Any]:
    """The settings of ``--compare``: a search mode (``paper``) or ``key=value`` pairs separated by commas
    (``planner=LazyPRM,space=projected,sampler=joint-by-joint+straight-elbow+free-limb+lift``), checked
    against :class:`climb_ompl.settings.ClimbSettings`.

    Raises:
        QueryError: an unknown mode, setting or value.
    """
    import json

    from climb_ompl.settings import SEARCH_MODES, ClimbSettings

    if "=" not in text:
        if text not in SEARCH_MODES:
            raise QueryError(f"--compare: {text!r} is neither a search mode ({', '.join(SEARCH_MODES)}) nor "
                             "key=value settings")
        return {"search": text}
    out: dict[str, Any] = {}
    for item in text.split(","):
        key, sep, value = item.partition("=")
        if not sep or not key.strip():
            raise QueryError(f"--compare: {item!r} is not key=value")
        try:
            out[key.strip()] = json.loads(value)
        except ValueError:
            out[key.strip()] = value.strip()
    ClimbSettings.from_dict(out, source="--compare")
    return out


def _histogram(times: list[float], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    fig, ax = plt.subplots(figsize=(6, 3.5))
    if times:
        bins = np.logspace(np.log10(max(min(times), 1e-3)), np.log10(max(times) + 1e-9), 30)
        ax.hist(times, bins=bins, color="tab:blue")
        ax.set_xscale("log")
    ax.set_xlabel("one-step planning time (s)")
    ax.set_ylabel("steps")
    ax.set_title(f"LEMUR one-step times (n = {len(times)}, median {np.median(times) if times else 0:.3f} s)")
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def summary(result: dict[str, Any]) -> str:
    """One line: success, steps, planning time, one-step calls and times, stances explored (+ walls)."""
    line = (f"success={result['success']} steps={result['steps']} total={result['total_s']:.1f}s "
            f"cpu={result['cpu_s']:.1f}s "
            f"onestep_calls={result['onestep_calls']} onestep_median={result['onestep_median_s']:.3f}s "
            f"stances={result['stances_explored']}")
    if "walls" in result:
        w = result["walls"]
        times = [r["total_s"] for r in w["runs"] if r["success"]]
        line += f" walls={w['successes']}/{w['n']}"
        if times:
            cpus = [r["cpu_s"] for r in w["runs"] if r["success"]]
            line += (f" walls_s={min(times):.0f}-{max(times):.0f} (median {sorted(times)[len(times) // 2]:.0f}; "
                     f"cpu {min(cpus):.0f}-{max(cpus):.0f})")
    for c in result.get("compare", []):
        line += (f" | {c['settings']}: success={c['success']} steps={c['steps']} total={c['total_s']:.1f}s "
                 f"cpu={c['cpu_s']:.1f}s")
    return line


def command(
    robot: str = typer.Option("lemur", help="Robot name or spec file."),
    terrain: str = typer.Option("demo-wall", help="Terrain name or file."),
    height: float = typer.Option(2.0, help="Climb this many metres above the start stance's highest hold."),
    seed: int = typer.Option(0, min=0, max=SEED_MAX, help="Seed of the planner."),
    time_limit: float = typer.Option(120.0, help="Planning budget per climb, s."),
    walls: int = typer.Option(0, help="Also plan on this many generated walls (generate_wall(seed=k))."),
    plot: Path = typer.Option(None, help="Write the histogram of one-step times (PNG) here."),
    out: Path = typer.Option(None, help="Write the JSON result here."),
    search: str = typer.Option("guided", help="Search mode: guided | paper."),
    sampler: str = typer.Option(None, help="FIND-PATH sampler (default: the climb's)."),
    compare: list[str] = typer.Option(["paper"], help="Also plan the main terrain with this search mode, or "
                                      "with these settings: key=value,key=value (repeatable; '' for none)."),
) -> None:
    """Multi-step climbing: success, steps, time, one-step calls (Bretl (2006), section 5.3)."""
    from climb_ompl._options import check_positive

    check_positive(time_limit, "--time-limit", "seconds")
    for c in compare:
        if c:
            compare_settings(c)  # a bad --compare is an error before any climb (exit 2)
    execute("climb", dict(robot=robot, terrain=terrain, height=height, seed=seed, time_limit=time_limit,
                          walls=walls, plot=str(plot) if plot else None, search=search, sampler=sampler,
                          compare=[c for c in compare if c] or None), out,
            timeout=600.0 + (walls + 2) * (time_limit + 120.0))
