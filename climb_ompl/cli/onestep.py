"""``climb-ompl onestep``: plan one limb's move to a new hold (FIND-TRANSITION + FIND-PATH)."""

from __future__ import annotations

from pathlib import Path

import typer

from climb_ompl._options import check_out, check_positive, error
from climb_ompl.cli._app import app, load_wall, parse_pairs
from climb_ompl.settings import SEED_MAX, ClimbSettings, check_names


@app.command("onestep")
def onestep(
    robot: str = typer.Argument(..., help="Robot name or spec file."),
    terrain: str = typer.Argument(..., help="Terrain name or file."),
    stance: str = typer.Option(..., help="Supporting holds during the move, e.g. ne=h1,nw=h2,sw=h3."),
    limb: str = typer.Option(..., help="The moving (free) limb."),
    start_hold: str = typer.Option(..., "--from", help="Hold the free limb leaves."),
    goal_hold: str = typer.Option(..., "--to", help="Hold the free limb reaches."),
    planner: str = typer.Option(ClimbSettings.planner, help="OMPL planner name."),
    space: str = typer.Option(ClimbSettings.space, help="projected | atlas | tangent_bundle."),
    sampler: str = typer.Option("uniform", help="Sampler name(s), a+b."),
    seed: int = typer.Option(0, min=0, max=SEED_MAX, help="Seed (reproducible with --max-iterations)."),
    time_limit: float = typer.Option(10.0, help="Time limit, s."),
    max_iterations: int = typer.Option(None, min=1, help="Stop after this many validity checks (reproducible)."),
    straight_phase: int = typer.Option(0, min=0, help="First draws of the sampler that are straight-limb "
                                       "configurations (Bretl et al. 2004; needs --space projected; 0: none)."),
    same_bend: bool = typer.Option(False, help="Connect only configurations with the start's and goal's elbow "
                                   "bends (Bretl et al. 2004)."),
    out: Path = typer.Option(None, help="Write the path (JSON) here."),
) -> None:
    """Plan a one-step move; exit 1 when no path is found."""
    from climb_ompl._io import atomic_write_json
    from climb_ompl.cli.plan import settings_error
    from climb_ompl.climb.multistep import check_dimensions
    from climb_ompl.climb.onestep import find_path, step_ends
    from climb_ompl.errors import PlannerNotFound
    from climb_ompl.manifold.stance import Stance
    from climb_ompl.model.robot import RobotModel

    check_positive(time_limit, "--time-limit", "seconds")
    if start_hold == goal_hold:
        raise error(f"--from and --to: the same hold {start_hold!r}; a step moves the limb to another hold")
    if out is not None:
        check_out(out)
    try:  # a misspelt name is bad input: refused before any planning
        check_names(planner, space, sampler)
    except PlannerNotFound as exc:
        raise settings_error(exc, {}) from None
    if straight_phase and space != "projected":
        raise error(f"--straight-phase: straight-limb draws need --space projected (the {space!r} space samples "
                    "its own charts)")
    rob, ter = RobotModel.load(robot), load_wall(terrain)
    check_dimensions(rob, ter)
    s = Stance(parse_pairs(stance, "--stance"))
    names = [lb.name for lb in rob.limbs]
    if limb not in names:
        raise error(f"--limb: robot {rob.name!r} has no limb {limb!r}; its limbs: {', '.join(names)}")
    if limb in s:
        raise error(f"--limb: {limb} is in --stance; the moving limb is the one not holding during the move")
    for opt, hold in (("--from", start_hold), ("--to", goal_hold)):
        if hold not in ter.hold_ids:
            raise error(f"{opt}: {ter.no_hold(hold)}")
        held = [k for k, h in s.items() if h == hold]
        if held:
            raise error(f"{opt}: hold {hold!r} is taken by {held[0]} in --stance")
    qs, qg = step_ends(rob, ter, s, limb, start_hold, goal_hold, seed=seed)
    if qs is None:
        raise error(f"no feasible start with {limb} on {start_hold}{_why(rob, ter, s, limb, start_hold)}", 1)
    if qg is None:
        raise error(f"no feasible goal with {limb} on {goal_hold}{_why(rob, ter, s, limb, goal_hold)}", 1)
    res = find_path(rob, ter, s, qs, qg, planner=planner, space=space, sampler=sampler, seed=seed,
                    time_limit=time_limit, cpu_limit=None, max_iterations=max_iterations,
                    straight_phase=straight_phase, same_bend=same_bend)
    typer.echo(f"{res.status}: {len(res.path)} waypoints in {res.stats['time_s']:.3f} s, "
               f"rejections {res.stats['rejections']}")
    if out is not None:
        atomic_write_json(out, {"status": res.status, "stance": s.to_dict(), "robot": rob.name,
                                "terrain": ter.name, "path": [q.tolist() for q in res.path],
                                "stats": res.stats,
                                # the path's frame: a terrain turned into the wall frame records the motion
                                **({"terrain_frame": ter.to_dict()["frame"]} if ter.frame is not None else {})})
    if not res.found:
        raise typer.Exit(1)


def _why(robot: object, terrain: object, stance: object, limb: str, hold: str) -> str:
    """Why ``limb`` cannot be on ``hold`` while ``stance`` carries the robot (a transition, Bretl (2006), sec. 2.1):
    the checks that fail near the nominal stand-off (:func:`climb_ompl.climb.start.diagnose_stance`), one indented
    line each."""
    from climb_ompl.climb.start import diagnose_stance

    d = diagnose_stance(robot, terrain, stance, touching={limb: hold})
    reasons = d.reasons or ["no single check fails at the nominal stand-off (FIND-TRANSITION's random draws found "
                            "none: try another --seed)"]
    return f"; with {limb} touching {hold}, the others carrying the robot:\n" + "\n".join(f"  {r}" for r in reasons)
