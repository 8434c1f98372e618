"""``climb-ompl console``: the operator's console, a local web page (viser) to plan, preview and accept steps."""

from __future__ import annotations

import time
from pathlib import Path

import typer

from climb_ompl._options import check_out, error
from climb_ompl.cli._app import app
from climb_ompl.settings import SEED_MAX


@app.command("console")
def console_cmd(
    robot: str = typer.Option(None, "--robot", help="Robot name or spec file (a new session)."),
    terrain: str = typer.Option(None, "--terrain", help="Terrain name or file (a new session)."),
    session: Path = typer.Option(None, "--session", help="Session file: read if it exists, written after every "
                                 "decision (a malformed one is left untouched; the session goes to NAME.new.json)."),
    host: str = typer.Option("127.0.0.1", "--host", help="Address to listen on (127.0.0.1: this machine only)."),
    port: int = typer.Option(8080, "--port", min=1, max=65535, help="Port to listen on."),
    seed: int = typer.Option(0, "--seed", min=0, max=SEED_MAX, help="Seed of the first goal (each goal the next)."),
    time_limit: float = typer.Option(None, "--time-limit", help="Budget of a multi-step goal, s \\[the session's]."),
    run_for: float = typer.Option(None, "--run-for", help="Stop after this many seconds (default: until Ctrl-C)."),
) -> None:
    """Open the operator's console: click a hold, plan a step or a distant goal, preview it, accept or reject it.

    Bretl (2006), sec. 5.1: the operator gives a single-step goal (the next hold to grab or release) or a multistep
    goal, and evaluates the planner's path in a GUI before it is executed.  The page serves from this machine only
    unless --host says otherwise; it needs no network.
    """
    from climb_ompl.console import open_console

    if session is not None:
        check_out(session, "--session")
    if session is None and (robot is None or terrain is None):
        raise error("give --robot and --terrain (a new session), or --session FILE")
    page = open_console(robot, terrain, session, host=host, port=port, seed=seed, time_limit=time_limit)
    if page.state.message:
        typer.echo(f"note: {page.state.message}", err=True)
    typer.echo(f"console: {page.url}  (Ctrl-C to stop)", err=False)
    t0 = time.monotonic()
    try:
        while run_for is None or time.monotonic() - t0 < run_for:
            time.sleep(0.2)
    except KeyboardInterrupt:
        pass
    finally:
        page.close()
