"""``climb-ompl bench slope``: MRWALLSPECT III transition planning time and the crossable angles (Kim, Kang & Choi).

Sweeps signed slope angles (negative: convex edge, going down; positive: concave corner, going up),
plans each transition with :func:`climb_ompl.mrwallspect.slope.plan_slope` (full checks: IK, Pinocchio FK,
Coal collision, Eq. 22, equilibrium with adhesion contacts), and records the planning time, the ``d``
chosen and the reason of every failure.  Baseline, measured in the same run: the paper's gait at the
robot's preferred ``d`` without the ``d`` search and without the equilibrium check (35 degrees concave).
``plot`` writes a PNG: planning time per angle, feasible and infeasible angles marked.
"""

from __future__ import annotations

import time
from pathlib import Path
from typing import Any

import typer

NAME = "slope"


def run(step: float = 5.0, max_angle: float = 90.0, tilt: float = 0.0, repeats: int = 1,
        plot: str | None = None) -> dict[str, Any]:
    """Measure; see the module docstring.  Returns the JSON-able figures."""
    import numpy as np

    from climb_ompl.mrwallspect.robot import SlopeRobot
    from climb_ompl.mrwallspect.slope import plan_slope

    robot = SlopeRobot.load("mrwallspect3")
    plan_slope(35.0, "concave", robot=robot)  # warm-up (imports, first LP)
    t0 = time.perf_counter()
    for _ in range(max(repeats, 1)):
        plan_slope(35.0, "concave", robot=robot, d=robot.p["d"], equilibrium=False)
    baseline = (time.perf_counter() - t0) / max(repeats, 1)
    rows = []
    angles = [a for a in np.arange(-max_angle, max_angle + 1e-9, step) if abs(a) > 1e-9]
    for a in angles:
        kind = "concave" if a > 0 else "convex"
        times = []
        for _ in range(max(repeats, 1)):
            t1 = time.perf_counter()
            res = plan_slope(abs(float(a)), kind, robot=robot, tilt_deg=tilt)
            times.append(time.perf_counter() - t1)
        eq = res.checks.get("equilibrium", {})
        rows.append({"angle": float(a), "kind": kind, "found": res.found, "time_s": float(np.median(times)),
                     "d": res.stats.get("d"), "candidates": res.stats["candidates_tried"],
                     "frames": res.stats.get("frames"), "min_margin": eq.get("min_margin"),
                     "min_clearance": res.checks.get("collision", {}).get("value") if res.found else None,
                     "reason": res.reason})
    ok = [r["angle"] for r in rows if r["found"]]

    def _contiguous(sign: float) -> float:
        best = 0.0
        for r in sorted(rows, key=lambda r: abs(r["angle"])):
            if np.sign(r["angle"]) != sign:
                continue
            if not r["found"]:
                break
            best = abs(r["angle"])
        return best

    t_found = [r["time_s"] for r in rows if r["found"]]
    t_inf = [r["time_s"] for r in rows if not r["found"]]
    result = {
        "tilt": tilt,
        "angles": len(rows),
        "feasible": len(ok),
        "max_concave_deg": _contiguous(1.0),
        "max_convex_deg": _contiguous(-1.0),
        "time_found_median_s": float(np.median(t_found)) if t_found else None,
        "time_found_max_s": float(np.max(t_found)) if t_found else None,
        "time_infeasible_median_s": float(np.median(t_inf)) if t_inf else None,
        "baseline_fixed_d_s": baseline,
        "ratio_vs_baseline": float(np.median(t_found)) / baseline if t_found else None,
        "rows": rows,
    }
    if plot:
        _plot(result, Path(plot))
        result["plot"] = plot
    return result


def _plot(result: dict[str, Any], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    rows = result["rows"]
    fig, ax = plt.subplots(figsize=(7.5, 3.6))
    for found, style, label in ((True, "o", "crossable"), (False, "x", "infeasible")):
        sel = [r for r in rows if r["found"] == found]
        ax.plot([r["angle"] for r in sel], [r["time_s"] for r in sel], style, label=label,
                color="tab:green" if found else "tab:red")
    lo, hi = -result["max_convex_deg"], result["max_concave_deg"]
    ax.axvspan(lo, hi, color="tab:green", alpha=0.08)
    ax.axhline(result["baseline_fixed_d_s"], color="grey", ls="--", lw=0.8, label="baseline (fixed d, 35° concave)")
    ax.set_xlabel("slope angle, degrees (negative: convex edge, positive: concave corner)")
    ax.set_ylabel("planning time, s")
    ax.set_title(f"MRWALLSPECT III transitions (tilt {result['tilt']:g}°): crossable {lo:g}° .. {hi:g}°")
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def summary(result: dict[str, Any]) -> str:
    """One line: the crossable range and the planning times."""
    tf = result["time_found_median_s"]
    return (f"crossable -{result['max_convex_deg']:g}..+{result['max_concave_deg']:g} deg (convex..concave), "
            f"{result['feasible']}/{result['angles']} angles; planning "
            f"{(tf or float('nan')) * 1e3:.0f} ms median when found, "
            f"{(result['time_infeasible_median_s'] or float('nan')) * 1e3:.0f} ms when infeasible; "
            f"baseline fixed-d gait {result['baseline_fixed_d_s'] * 1e3:.0f} ms "
            f"(x{(result['ratio_vs_baseline'] or float('nan')):.1f})")


def command(
    out: Path = typer.Option(None, "--out", help="write the JSON result here"),
    step: float = typer.Option(5.0, min=0.1, max=90.0, help="angle step, degrees"),
    max_angle: float = typer.Option(90.0, "--max-angle", min=1.0, max=179.0, help="sweep -max..max degrees"),
    tilt: float = typer.Option(0.0, min=-360.0, max=360.0, help="first plane's tilt from a floor, degrees (90: a "
                               "wall)"),
    repeats: int = typer.Option(1, min=1, max=100, help="repeats per angle (median time)"),
    plot: Path = typer.Option(None, "--plot", help="write a PNG of time per angle and the crossable range"),
) -> None:
    """Planning time per transition over slope angles and the range of crossable angles."""
    from climb_ompl.bench._common import execute

    execute(NAME, {"step": step, "max_angle": max_angle, "tilt": tilt, "repeats": repeats,
                   "plot": str(plot.resolve()) if plot else None}, out)
