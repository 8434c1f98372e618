"""Plot one stance's support polygon (linearised and exact cones) and save ``docs/support_polygon.png``.

Run: ``python examples/plot_support_polygon.py [--out docs/support_polygon.png]``.
A LEMUR-like 3-hold stance on the generated wall ``generate_wall(0, normal_up_deg=(55, 80))``, seen from
above (gravity along -z, so the region's coordinates are world x and the stand-off y from the wall).
"""

from __future__ import annotations

import argparse
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from climb_ompl import generate_wall  # noqa: E402
from climb_ompl.equilibrium import contact_forces, support_region  # noqa: E402


def main(out: Path) -> None:
    wall = generate_wall(0, normal_up_deg=(55.0, 80.0))
    P = wall.positions
    centre = np.array([0.0, 0.0, 1.5])
    d = P - centre
    r = np.linalg.norm(d, axis=1)
    ang = np.arctan2(d[:, 2], d[:, 0])
    holds = []
    for a0 in (np.pi / 2, -np.pi / 6, -5 * np.pi / 6):  # one hold up, two below left and right
        da = np.abs((ang - a0 + np.pi) % (2 * np.pi) - np.pi)
        cand = np.where((r > 0.2) & (r < 0.45) & (da < np.pi / 3))[0]
        holds.append(wall.holds[int(cand[np.argmin(da[cand])])])
    mass = 7.0  # LEMUR (Bretl (2006), section 5.1)
    fig, ax = plt.subplots(figsize=(6.4, 4.6))
    for k, style in ((4, ":"), (8, "--")):
        reg = support_region(holds, mass, wall.g, cone_edges=k)
        V = np.vstack([reg.vertices, reg.vertices[:1]])
        ax.plot(V[:, 0], V[:, 1], style, label=f"linearised, {k} edges")
    exact = support_region(holds, mass, wall.g, exact=True)
    V = np.vstack([exact.vertices, exact.vertices[:1]])
    ax.fill(V[:, 0], V[:, 1], alpha=0.25, color="C2")
    ax.plot(V[:, 0], V[:, 1], "-", color="C2", label="exact (second-order cones)")
    for h in holds:
        ax.plot(h.position[0], h.position[1], "ks")
        ax.annotate(f"{h.id} z={h.position[2]:.2f}", (h.position[0], h.position[1]), textcoords="offset points",
                    xytext=(4, 6), fontsize=8)
    com = np.r_[exact.vertices.mean(axis=0), 1.5]
    res = contact_forces(holds, mass, wall.g, com)
    ax.plot(com[0], com[1], "o", color="C3",
            label=f"CoM, margin {exact.margin(com) * 100:.1f} cm, friction used {res.ratio:.2f}")
    ax.axhline(0.0, color="0.5", lw=0.8)
    ax.set_xlabel("x along the wall (m)")
    ax.set_ylabel("y: stand-off from the wall (m)")
    ax.set_title("Support polygon of a 3-hold stance (seen from above)")
    ax.set_aspect("equal")
    ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.2), ncol=2)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=120)
    print(f"saved {out}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path(__file__).resolve().parents[1] / "docs" / "support_polygon.png")
    main(ap.parse_args().out)
