"""``climb-ompl step``: the operator's goals from the state the robot is in, appended to a session file.

Bretl (2006), sec. 5.1: "A human operator specifies either a single-step goal (the next hold to grab or release) or a
multistep goal (a distant hold, requiring a number of steps to reach)."  Exit codes: 0 every goal planned (the steps
appended to the session), 1 a goal with no step (the planner's reason printed; the goals before it are kept),
2 bad input (a malformed goal, file or option; nothing written).
"""

from __future__ import annotations

from pathlib import Path

import typer

from climb_ompl._options import check_out, check_positive, error
from climb_ompl.cli._app import app, load_wall
from climb_ompl.settings import SEED_MAX


@app.command("step")
def step_cmd(
    state: Path = typer.Argument(None, help="A session or plan file: the robot is in its last state (omit it to "
                                 "start a session with --robot and --terrain)."),
    goal: list[str] = typer.Option(..., "--goal", help="A goal, in order (repeatable): 'grab LIMB=HOLD', "
                                   "'release LIMB', 'stance L1=H1,L2=H2,...' (one step each), or 'hold LIMB=HOLD', "
                                   "'height METRES', 'climb METRES' (as many steps as it takes)."),
    out: Path = typer.Option(..., "--out", help="The session file written (atomically; may be the STATE file)."),
    robot: str = typer.Option(None, "--robot", help="Robot name or spec file (a new session)."),
    terrain: str = typer.Option(None, "--terrain", help="Terrain name or file (a new session)."),
    seed: int = typer.Option(0, "--seed", min=0, max=SEED_MAX, help="Seed: the same seed gives the same steps."),
    time_limit: float = typer.Option(None, "--time-limit", help="Budget of each goal's search, s "
                                     "\\[the session's; a one-step goal at most 10 s]."),
) -> None:
    """Plan goals from the robot's state, each from where the one before ended; append the steps to a session.

    A sequence of goals stops at the first one without a step, naming it and the check that failed (exit 1); the
    steps of the goals before it are written.  The session file is a plan file: ``climb-ompl verify`` and
    ``climb-ompl play`` take it.
    """
    from climb_ompl.climb.step import GoalResult, OperatorGoal, plan_goal, stance_text, torque_fraction
    from climb_ompl.errors import QueryError
    from climb_ompl.settings import ClimbSettings

    check_out(out)
    goals = [OperatorGoal.parse(g) for g in goal]  # a malformed goal: exit 2 before any planning
    if time_limit is not None:
        check_positive(time_limit, "--time-limit", "seconds")
    session = _session(state, robot, terrain, seed)
    from climb_ompl.plan.file import robot_from_plan

    rob = robot_from_plan(session.plan)
    settings = ClimbSettings.from_plan(session.plan.settings, source=f"{session.source}: $.settings")
    if time_limit is not None:
        settings = settings.replace(time_limit=time_limit)
    wall = session.terrain()  # accepting steps does not change it
    for g in goals:  # an unknown limb or hold: exit 2 before any planning
        g.validate(rob, wall)
    code = 0
    for i, g in enumerate(goals):
        stance, q = session.state()
        try:
            res = plan_goal(rob, wall, stance, q, g, settings, seed=seed + i)
        except QueryError as exc:  # no single step from the state the goals before it reached
            res = GoalResult(g, False, reason=str(exc))
        if not res.found:
            session.refused(str(g), res.reason, res.seconds)
            typer.echo(f"goal {i + 1} ({g}): no step from stance {stance_text(stance)} in {res.seconds:.2f} s: "
                       f"{res.reason}")
            code = 1
            break
        session.accept(str(g), res.steps, res.seconds)
        margin = min(s.margin for s in res.steps)
        frac = max(torque_fraction(rob, s) for s in res.steps)
        typer.echo(f"goal {i + 1} ({g}): {len(res.steps)} step(s) in {res.seconds:.2f} s; smallest margin "
                   f"{margin:.3f} m, largest torque {100 * frac:.0f} % of its limit")
    session.save(out)
    typer.echo(f"session: {session.n_steps} steps -> {out}")
    if code:
        raise typer.Exit(code)


def _session(state: Path | None, robot: str | None, terrain: str | None, seed: int) -> object:
    """The session to go on from: ``state`` (a session or plan file), else a new one of ``robot`` on ``terrain`` at
    their default start."""
    from climb_ompl.plan.session import Session

    if state is not None:
        if robot is not None or terrain is not None:
            raise error("--robot/--terrain: give either a STATE file or --robot and --terrain, not both")
        return Session.load(state)
    if robot is None or terrain is None:
        raise error("give a STATE file (a session or plan) or --robot and --terrain to start a session")
    from climb_ompl.climb.multistep import check_dimensions, default_start
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.settings import ClimbSettings

    rob, wall = RobotModel.load(robot), load_wall(terrain)
    check_dimensions(rob, wall)
    start = default_start(rob, wall, seed=seed)
    if start is None:
        raise error(f"no start stance found for {rob.name} on {wall.name} (climb-ompl plan says why)", 1)
    settings = ClimbSettings.for_search("guided", robot=rob)
    return Session.start(rob, wall, start[0], start[1], settings.to_dict(), seed)
