"""``climb-ompl bench trajectory``: timing a climb plan and exporting it.

Plans LEMUR's 2 m demo climb (``climb-ompl demo``: the start finder's stance on ``demo-wall``, seed 0) and Go1's
0.6 m climb of the bundled 15-degree stepping-stone ramp (the climb suite's cell), then, on each plan with its
timing taken out, measures the CPU time of timing every step (:func:`climb_ompl.trajectory.retime.time_plan`; the
one-off import of toppra, which pulls in scipy and matplotlib, is measured apart), the climb's duration (timed
against constant joint speed, the timing plans had before), the largest dynamic torque over its allowance
(``dynamic_fraction`` of the static torque margin), the steps slowed for it, the base's top speed, what the
verifier's timing checks report, and the CPU time of each export (CSV, NPZ, ROS 2 bag; with ``--video`` the wall
time of an MP4 at 10x).  Figures: docs/trajectory.md.
"""

from __future__ import annotations

import dataclasses
import tempfile
import time
from pathlib import Path
from typing import Any

import typer

NAME = "trajectory"


def lemur_plan(seed: int = 0, height: float = 2.0, time_limit: float = 300.0) -> Any:
    """LEMUR's demo climb: ``height`` metres above the start stance's highest hold on ``demo-wall``."""
    from climb_ompl.climb.multistep import plan_climb
    from climb_ompl.climb.start import find_start
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain

    robot, wall = RobotModel.load("lemur"), Terrain.load("demo-wall")
    start = find_start(robot, wall, seed=seed)
    z0 = max(wall.height(h) for h in start.stance.values())
    return plan_climb(robot, wall, start.stance, z0 + height, q_start=start.q, time_limit=time_limit, seed=seed).plan


def go1_plan(seed: int = 0, climb: float = 0.6, time_limit: float = 180.0) -> Any:
    """Go1's climb of the bundled stepping-stone ramp, as the climb suite runs it."""
    from climb_ompl.climb.multistep import climb_from_start, load_terrain
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.settings import ClimbSettings

    robot = RobotModel.load("go1")
    wall = load_terrain("stepping-stone-ramp-3m")
    settings = ClimbSettings.for_search("guided", robot=robot, time_limit=time_limit)
    res = climb_from_start(robot, wall, None, settings, climb=climb, seed=seed)[0]
    return None if res is None else res.plan


def _untimed(plan: Any) -> Any:
    from climb_ompl.climb.assembly import waypoint_times
    from climb_ompl.plan.file import robot_from_plan

    robot = robot_from_plan(plan)
    steps = tuple(dataclasses.replace(s, velocities=(), accelerations=(),
                                      times=tuple(waypoint_times(robot, list(s.q)))) for s in plan.steps)
    return dataclasses.replace(plan, steps=steps), robot


def measure(plan: Any, video: bool = False) -> dict[str, Any]:
    """The figures of one plan; see the module docstring."""
    from climb_ompl.export.rosbag import write_bag
    from climb_ompl.export.samples import plan_samples
    from climb_ompl.export.table import write_csv, write_npz
    from climb_ompl.settings import ClimbSettings
    from climb_ompl.trajectory.retime import time_plan
    from climb_ompl.verification.climb import verify

    old, robot = _untimed(plan)
    c0 = time.process_time()
    import toppra  # noqa: F401  (its import, measured apart)

    c1 = time.process_time()
    timed, info = time_plan(old, robot)
    c2 = time.process_time()
    rep = verify(timed)
    out: dict[str, Any] = {
        "robot": robot.name, "steps": len(plan.steps), "waypoints": sum(len(s.waypoints) for s in plan.steps),
        "timing_cpu_s": c2 - c1, "toppra_import_cpu_s": c1 - c0, "duration_s": info["execution_s"],
        "constant_speed_s": old.execution_s, "dynamic_ratio": info["dynamic_ratio"],
        "slowed_steps": info["slowed_steps"], "base_speed": info["base_speed"],
        "fraction": float(plan.settings.get("dynamic_fraction", ClimbSettings.dynamic_fraction)), "verified": rep.ok,
        "timing_violations": rep.counts.get("timing", 0), "dynamics_violations": rep.counts.get("dynamics", 0)}
    with tempfile.TemporaryDirectory(prefix="bench-trajectory-") as tmp:
        for fmt, fn in (("csv", lambda p: write_csv(plan_samples(timed, robot), p)),
                        ("npz", lambda p: write_npz(plan_samples(timed, robot), p)),
                        ("ros2-bag", lambda p: write_bag(timed, robot, p))):
            c = time.process_time()
            fn(Path(tmp) / f"out.{fmt}")
            out[f"export_{fmt}_cpu_s"] = time.process_time() - c
        if video:
            from climb_ompl.export.video import write_video

            w = time.perf_counter()
            write_video(timed.to_dict(), Path(tmp) / "out.mp4", fps=10, speedup=10, robot=robot)
            out["export_mp4_wall_s"] = time.perf_counter() - w
    return out


def run(seed: int = 0, go1: bool = True, video: bool = False) -> dict[str, Any]:
    """Measure; see the module docstring.  Returns the JSON-able figures."""
    rows = []
    for name, make in (("lemur-demo-2m", lemur_plan), ("go1-ramp-0.6m", go1_plan)):
        if name.startswith("go1") and not go1:
            continue
        plan = make(seed)
        rows.append({"case": name, "found": plan is not None, **(measure(plan, video) if plan is not None else {})})
    return {"seed": seed, "rows": rows}


def summary(result: dict[str, Any]) -> str:
    """One line per plan: timing CPU, duration, dynamics."""
    parts = []
    for r in result["rows"]:
        if not r["found"]:
            parts.append(f"{r['case']}: no plan")
            continue
        parts.append(
            f"{r['case']}: {r['steps']} steps timed in {r['timing_cpu_s']:.2f} s CPU "
            f"(+{r['toppra_import_cpu_s']:.2f} s import), {r['duration_s']:.1f} s of climb "
            f"(constant speed: {r['constant_speed_s']:.1f} s), dynamic torque <= {r['dynamic_ratio']:.2f} of its "
            f"allowance, {r['slowed_steps']} steps slowed, verify {'ok' if r['verified'] else 'FAILED'}; "
            f"bag {r['export_ros2-bag_cpu_s']:.2f} s CPU")
    return "; ".join(parts)


def command(
    out: Path = typer.Option(None, "--out", help="write the JSON result here"),
    seed: int = typer.Option(0, min=0, help="seed of both plans"),
    go1: bool = typer.Option(True, "--go1/--no-go1", help="also Go1's ramp climb (about a minute of planning)"),
    video: bool = typer.Option(False, "--video", help="also time an MP4 export (needs chromium; minutes)"),
) -> None:
    """Time LEMUR's 2 m demo plan and Go1's ramp climb, check their dynamics, and time the exports."""
    from climb_ompl.bench._common import execute

    execute(NAME, {"seed": seed, "go1": go1, "video": video}, out)
