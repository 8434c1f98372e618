"""Side view of a slope-transition plan (matplotlib, imported only when drawing): Kim, Kang & Choi, Fig. 12-15 style."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np


def side_view(plans: list[dict[str, Any]], path: str | Path, every: int = 1) -> Path:
    """Draw each plan's planes, body trajectory arc, body at every body step and the legs (x-z plane).

    Args:
        plans: plan dictionaries (``kind: slope``), one panel each.
        path: PNG file to write.
        every: draw every ``every``-th body step.

    Returns:
        The path written.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from climb_ompl.mrwallspect.slope import scene_items

    ncol = min(2, len(plans))
    nrow = -(-len(plans) // ncol)
    fig, axes = plt.subplots(nrow, ncol, figsize=(5.0 * ncol, 4.0 * nrow), squeeze=False)
    for ax in axes.flat[len(plans):]:
        ax.set_visible(False)
    for ax, plan in zip(axes.flat, plans, strict=False):
        sc = scene_items(plan)
        for pl in plan["planes"]:
            c, t = np.asarray(pl["point"]), np.asarray(pl["direction"])
            a, b = c - t * pl["extent"][0] / 2, c + t * pl["extent"][0] / 2
            ax.plot([a[0], b[0]], [a[2], b[2]], color="saddlebrown", lw=2.5)
        tr = plan["trajectory"]
        pr, ps = np.asarray(tr["P_R"]), np.asarray(tr["P_S"])
        ax.plot(*pr[[0, 2]], "+", color="grey")
        frames = plan["frames"]
        body_end = [i for i, f in enumerate(frames) if f["phase"] == "start" or
                    (f["phase"] == "body" and (i + 1 == len(frames) or frames[i + 1]["phase"] != "body"))]
        box = plan["robot"]["spec"]["gait"]["body_box"]
        for n, i in enumerate(body_end[::every]):
            s = sc["frames"][i]
            T = s["body_pose"]
            corners = np.array([[box["x"][0], 0, box["z"][0]], [box["x"][1], 0, box["z"][0]],
                                [box["x"][1], 0, box["z"][1]], [box["x"][0], 0, box["z"][1]],
                                [box["x"][0], 0, box["z"][0]]])
            w = corners @ T[:3, :3].T + T[:3, 3]
            alpha = 0.25 + 0.75 * n / max(len(body_end[::every]) - 1, 1)
            ax.plot(w[:, 0], w[:, 2], color="tab:blue", lw=1, alpha=alpha)
            for j in (0, 2):  # left legs (front, rear): the side facing the viewer
                pts = s["legs"][j]
                ax.plot(pts[:, 0], pts[:, 2], color="k", lw=0.8, alpha=alpha)
        orig = np.array([f["body"]["origin"] for f in frames])
        front = np.array([f["body"]["front"] for f in frames])
        ax.plot(orig[:, 0], orig[:, 2], color="tab:orange", lw=1, label="O_B")
        ax.plot(front[:, 0], front[:, 2], color="tab:red", lw=1, ls="--", label="F_B")
        ax.plot(*ps[[0, 2]], "o", ms=3, color="tab:green")
        q = plan["query"]
        ax.set_title(f"{q['kind']} {q['angle']:g}°: d = {tr['d']:.3f} m, R = {tr['R']:.3f} m", fontsize=9)
        ax.set_aspect("equal")
        ax.set_xlabel("x, m")
        ax.set_ylabel("z, m")
        ax.legend(fontsize=7, loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return Path(path)
