"""Lam et al. (TreeBot), Fig. 13 for the bundled three-branch tree: ``python -m climb_ompl.treebot.figure OUT.png``."""

from __future__ import annotations

import sys

import numpy as np


def save_figure(out: str, tree_name: str = "three-branch", target: str = "b2") -> None:
    """Draw the tree, the DP path and the body at the end of each extension, simple vs. proposed."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from climb_ompl.treebot.bark import Bark
    from climb_ompl.treebot.compare import obstacle_points
    from climb_ompl.treebot.dp import plan_path
    from climb_ompl.treebot.motion import plan_motion
    from climb_ompl.treebot.tree import Tree

    tree = Tree.load(tree_name)
    res = plan_path(tree, target)
    P = np.array([p.position for p in res.path])
    N = np.array([p.normal for p in res.path])
    pts = np.concatenate([r.points for b in tree.branches for r in b.rings])
    obs = obstacle_points(tree, target)
    bark = Bark(tree.branch(b) for b in dict.fromkeys(p.branch for p in res.path))
    fig = plt.figure(figsize=(11, 6))
    for i, method in enumerate(("simple", "proposed")):
        ax = fig.add_subplot(1, 2, i + 1, projection="3d")
        ax.scatter(*pts.T, s=1, c="0.75")
        ax.scatter(*obs.T, s=3, c="m")
        ax.plot(*P.T, "k-", lw=1.5)
        mo = plan_motion(P, N, tree.robot, method, bark=bark.nearest)  # type: ignore[arg-type]
        last = {}
        for f in mo.frames:
            if f.phase == "extend":
                last[f.step] = f
        for f in last.values():
            ax.plot(*f.body.T, "r-", lw=2)
            ax.quiver(*f.front, *(0.05 * f.front_dir), color="b")
            ax.quiver(*f.rear, *(0.05 * f.rear_dir), color="m")
        ax.set_title(f"({'ab'[i]}) {method} method")
        ax.set_box_aspect(np.ptp(pts, axis=0))
        ax.view_init(elev=15, azim=-60)
        ax.set_axis_off()
    fig.suptitle(f"TreeBot on {tree_name}, target {target}: DP path (black), body at each extension (red)")
    fig.tight_layout()
    fig.savefig(out, dpi=110)


if __name__ == "__main__":
    save_figure(sys.argv[1] if len(sys.argv) > 1 else "treebot_fig13.png")
