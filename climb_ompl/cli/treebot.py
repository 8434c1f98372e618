"""``climb-ompl treebot plan|generate|validate|list``: TreeBot's tree-climbing planner (Lam et al.)."""

from __future__ import annotations

from pathlib import Path

import typer

from climb_ompl.cli._app import app
from climb_ompl.errors import ARGUMENT
from climb_ompl.settings import SEED_MAX

treebot_app = typer.Typer(help="TreeBot (Lam et al.): plan a climb over a tree of branches.", no_args_is_help=True)
app.add_typer(treebot_app, name="treebot")


def _load(tree: str, seed: int):
    from climb_ompl.treebot.generate import generate_tree
    from climb_ompl.treebot.tree import Tree

    if tree == "generated":
        return generate_tree(seed)
    return Tree.load(tree)


@treebot_app.command("plan")
def plan(
    tree: str = typer.Option(..., "--tree", help="Bundled tree name, YAML path, or 'generated' (uses --seed)."),
    target: str = typer.Option(..., "--target", help="Target branch: the path ends on its last ring."),
    out: Path = typer.Option(..., "--out", help="Plan JSON file (written atomically)."),
    seed: int = typer.Option(0, "--seed", min=0, max=SEED_MAX,
                             help="Seed of the generated tree; recorded in the plan."),
    target_point: int = typer.Option(None, "--target-point", help="Point index on the target ring (default: best)."),
    start_point: int = typer.Option(None, "--start-point", help="Point index on the start ring (default: best)."),
    method: str = typer.Option("proposed", "--method", help="Motion method: proposed (Eq. 8-20) or simple."),
) -> None:
    """Plan the gripping-point path (DP, Eq. 4-7) and the body motion; exit 1 if no path exists."""
    from climb_ompl._io import atomic_write_json
    from climb_ompl.treebot.motion import METHODS
    from climb_ompl.treebot.planfile import build_plan
    from climb_ompl.treebot.tree import TreeError

    if method not in METHODS:
        raise TreeError(ARGUMENT, "--method", f"unknown method {method!r}; valid: {', '.join(METHODS)}")
    t = _load(tree, seed)
    if start_point is not None and not 0 <= start_point < t.root.rings[0].n:
        raise TreeError(ARGUMENT, "--start-point", f"expected 0..{t.root.rings[0].n - 1}, got {start_point}")
    try:
        p = build_plan(t, target, seed=seed, target_point=target_point, start_point=start_point, method=method)
    except TreeError as exc:  # build_plan's argument, named by its option here
        if exc.path == ARGUMENT and exc.field == "target_point":
            raise TreeError(ARGUMENT, "--target-point", exc.reason) from None
        raise
    if not p["found"]:
        typer.echo(f"no path to branch {target!r}: {p['reason']}", err=True)
        # SystemExit, not typer.Exit: cli.main() drops the code of a typer.Exit under standalone_mode=False.
        raise SystemExit(1)
    atomic_write_json(out, p, allow_nan=False)
    s = p["stats"]
    typer.echo(f"wrote {out}: {len(p['path'])} gripping points, cost {p['cost']:.3f} m, {s['steps']} steps, "
               f"body {s['body_length_min']:.3f}-{s['body_length_max']:.3f} m, DP {s['dp_time_s'] * 1e3:.1f} ms")


@treebot_app.command("generate")
def generate(
    out: Path = typer.Option(..., "--out", help="Output YAML file (written atomically)."),
    seed: int = typer.Option(0, "--seed", min=0, max=SEED_MAX, help="RNG seed: the same seed gives the same tree."),
    branches: int = typer.Option(3, "--branches", min=1, max=50, help="Number of branches including the trunk."),
    points: int = typer.Option(16, "--points", min=3, max=256, help="Points per ring."),
    rings: int = typer.Option(24, "--rings", min=4, max=1000, help="Rings of the trunk."),
) -> None:
    """Generate a random tree (trunk + branches, curvature, taper, noise, obstacles)."""
    from climb_ompl._io import atomic_write
    from climb_ompl.treebot.generate import generate_tree

    t = generate_tree(seed, n_branches=branches, points_per_ring=points, trunk_rings=rings)
    atomic_write(out, t.to_yaml())
    typer.echo(f"wrote {out}: {len(t.branches)} branches, {sum(len(b.rings) for b in t.branches)} rings")


@treebot_app.command("validate")
def validate(file: str = typer.Argument(..., help="Tree file or bundled tree name.")) -> None:
    """Check a tree file; exit 0 if valid, 2 with the file, field and reason if not."""
    from climb_ompl.treebot.tree import Tree

    t = Tree.load(file)
    typer.echo(f"{t.source}: ok: tree {t.name!r}, {len(t.branches)} branches, "
               f"{sum(len(b.rings) for b in t.branches)} rings")


@treebot_app.command("list")
def list_trees() -> None:
    """List the bundled trees."""
    from climb_ompl.treebot.tree import Tree, bundled_trees

    for name in bundled_trees():
        t = Tree.load(name)
        typer.echo(f"{name:16s} branches: {', '.join(b.name for b in t.branches)}")
