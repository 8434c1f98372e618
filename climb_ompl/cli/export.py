"""``climb-ompl export``: a climb plan as a ROS 2 bag, a CSV or NPZ table of samples, or an MP4 or GIF video.

A plan written before plans were timed is timed first (:mod:`climb_ompl.trajectory`).  Bad input (an unknown
format, a plan of another kind, an output that cannot be written) exits 2 with one line and writes nothing.
"""

from __future__ import annotations

from pathlib import Path

import typer

from climb_ompl._options import check_out, check_positive, error
from climb_ompl.cli._app import app

FORMATS = ("ros2-bag", "csv", "npz", "mp4", "gif")


@app.command("export")
def export(
    plan: Path = typer.Argument(..., help="Climb plan file (JSON)."),
    fmt: str = typer.Option(..., "--format", help=f"One of {', '.join(FORMATS)}."),
    out: Path = typer.Option(..., "--out", help="Output file (a new folder for ros2-bag)."),
    rate: float = typer.Option(None, "--rate", help="csv/npz: samples per second (default: the plan's own samples, "
                               "one per waypoint)."),
    fps: float = typer.Option(10.0, "--fps", help="mp4/gif: frames per second."),
    speedup: float = typer.Option(10.0, "--speedup", help="mp4/gif: seconds of climb per second of video."),
    size: str = typer.Option("640x400", "--size", help="mp4/gif: WIDTHxHEIGHT in pixels."),
) -> None:
    """Export a climb plan's timed trajectory: a ROS 2 bag for a controller, a table, or a video."""
    from climb_ompl.plan.file import Plan, read_plan_dict, robot_from_plan

    if fmt not in FORMATS:
        raise error(f"--format: {fmt!r} is not one of {', '.join(FORMATS)}")
    for value, name, unit in ((fps, "--fps", "frames per second"), (speedup, "--speedup", "")):
        check_positive(value, name, unit)
    if rate is not None:
        check_positive(rate, "--rate", "samples per second")
    w, _, h = size.partition("x")
    if not (w.isdigit() and h.isdigit() and 16 <= int(w) <= 3840 and 16 <= int(h) <= 2160):
        raise error(f"--size: expected WIDTHxHEIGHT between 16x16 and 3840x2160, got {size!r}")
    if fmt in ("mp4", "gif") and out.suffix.lower() != f".{fmt}":  # the encoder follows the suffix
        raise error(f"--out: {str(out)!r} does not end in .{fmt}, the --format asked for")
    if fmt == "ros2-bag":
        if out.exists() or out.is_symlink():
            raise error(f"--out: {str(out)!r} exists already (a bag is a new folder)")
        folder = out.parent if str(out.parent) else Path(".")
        if not folder.is_dir():
            raise error(f"--out: folder {str(folder)!r} does not exist")
    else:
        check_out(out)
    d = read_plan_dict(plan)
    if d["kind"] != "climb":
        raise error(f"{plan}: a {d['kind']} plan has no joint trajectory to export (export takes climb plans)")
    p = Plan._from_valid(d, str(plan))
    robot = robot_from_plan(p)
    if fmt in ("csv", "npz"):
        from climb_ompl.export.samples import plan_samples
        from climb_ompl.export.table import write_csv, write_npz

        s = plan_samples(p, robot, rate)
        written = (write_csv if fmt == "csv" else write_npz)(s, out)
        typer.echo(f"wrote {written} ({len(s.t)} samples, {s.t[-1] if len(s.t) else 0.0:.1f} s of climb)")
    elif fmt == "ros2-bag":
        from climb_ompl.export.rosbag import write_bag

        typer.echo(f"wrote {write_bag(p, robot, out)} ({len(p.steps)} steps)")
    else:
        from climb_ompl.export.samples import timed
        from climb_ompl.export.video import write_video

        tp = timed(p, robot)
        done = write_video(tp.to_dict(), out, fps=fps, speedup=speedup, size=(int(w) // 2 * 2, int(h) // 2 * 2),
                           robot=robot)
        typer.echo(f"wrote {done} ({tp.execution_s:.1f} s of climb at x{speedup:g})")
