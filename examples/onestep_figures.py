"""Plan and draw the one-step moves of the papers and save them in ``docs/``.

Run: ``python examples/onestep_figures.py [--out-dir docs] [--only planar3,double_link,lemur]``.

* ``onestep_planar3.png``: the planar three-limbed robot (Bretl, Latombe & Rock (2003), section 3) on ``planar-wall``
  moves its free limb from one hold of the crack to another while two limbs hold on; side view (x-z) with the
  support interval of the two-hold stance (Bretl, Latombe & Rock (2003), Eq. 1) as a band and the CoM trace.
* ``onestep_double_link.png``: the double-link robot (Bretl (2006), Fig. 3-6) on ``pegs`` holds peg 2 with hand
  a and swings hand b from peg 3 to peg 4 around the obstacles (the step 3 -> 2 -> 4 of Fig. 13; a
  one-hold stance, a 2-D torus); no equilibrium condition (Bretl (2006), section 2.1).
* ``onestep_lemur.png``: LEMUR (Bretl, Latombe & Rock (2003); Bretl et al. (2004)) on ``demo-wall`` releases a hold and
  grabs a neighbouring one: front view (x-z, the wall) and top view (x-y) with the support polygon of the three-hold
  stance.

Every path comes from :func:`climb_ompl.climb.onestep.find_path` with a fixed seed and an iteration budget
(reproducible); robots are drawn as line segments through their joints to their hands.
"""

from __future__ import annotations

import argparse
import itertools
from pathlib import Path
from typing import Any

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
import pinocchio as pin  # noqa: E402

from climb_ompl import (  # noqa: E402  # noqa: E402
    RobotModel,  # noqa: E402
    Stance,
    Terrain,  # noqa: E402
    find_path,
    find_transition,
    stance_region,
)


# ---- drawing helpers ------------------------------------------------------------------------------------
def limb_polylines(robot: RobotModel, q: np.ndarray) -> list[np.ndarray]:
    """One ``(k, 3)`` polyline per limb: the base (last base joint), the limb's own joints, the hand."""
    m, d = robot.model, robot.data
    pin.forwardKinematics(m, d, q)
    pin.updateFramePlacements(m, d)
    base_q = set(int(j) for j in robot.base_indices)
    base_jid = max(j for j in range(1, m.njoints) if m.joints[j].idx_q in base_q)
    pelvis = np.array(d.oMi[base_jid].translation)
    out = []
    for lb in robot.limbs:
        pts = [pelvis]
        for jid in lb.joint_ids:
            if m.joints[jid].idx_q not in base_q:
                pts.append(np.array(d.oMi[jid].translation))
        pts.append(np.array(d.oMf[lb.frame_id].translation))
        out.append(np.array(pts))
    return out


def draw_robot(ax: Any, robot: RobotModel, q: np.ndarray, axes: tuple[int, int], alpha: float, colors: list[str],
               lw: float = 2.0) -> None:
    """Limbs as lines (one colour per limb), joints as dots, the pelvis as a black dot."""
    a, b = axes
    for i, P in enumerate(limb_polylines(robot, q)):
        ax.plot(P[:, a], P[:, b], "-", color=colors[i % len(colors)], alpha=alpha, lw=lw, solid_capstyle="round")
        ax.plot(P[1:-1, a], P[1:-1, b], ".", color="0.3", alpha=alpha, ms=3)
    ax.plot(P[0, a], P[0, b], "o", color="k", alpha=alpha, ms=4)


def draw_holds(ax: Any, terrain: Terrain, axes: tuple[int, int], used: dict[str, str], arrows: float = 0.0,
               box: tuple[float, float, float, float] | None = None) -> None:
    """All holds as grey dots (those of ``used`` labelled and black), normals as short arrows."""
    a, b = axes
    for h in terrain.holds:
        p = h.p
        if box is not None and not (box[0] <= p[a] <= box[1] and box[2] <= p[b] <= box[3]):
            continue
        on = h.id in used
        ax.plot(p[a], p[b], "s" if on else "o", color="k" if on else "0.6", ms=6 if on else 4, zorder=5)
        if arrows:
            ax.annotate("", (p[a] + arrows * h.n[a], p[b] + arrows * h.n[b]), (p[a], p[b]),
                        arrowprops=dict(arrowstyle="->", color="0.5", lw=0.8))
        if on:
            ax.annotate(used[h.id], (p[a], p[b]), textcoords="offset points", xytext=(5, 5), fontsize=8)


def snapshots(path: list[np.ndarray], n: int = 6) -> list[tuple[np.ndarray, float]]:
    """``n`` evenly spaced waypoints with opacities growing from start to goal."""
    idx = np.unique(np.linspace(0, len(path) - 1, n).round().astype(int))
    return [(path[i], 0.25 + 0.75 * k / max(1, len(idx) - 1)) for k, i in enumerate(idx)]


def region_world(region: Any) -> np.ndarray:
    """Support-region vertices as world points (``basis`` rows times region coordinates)."""
    V = np.asarray(region.vertices, dtype=float)
    B = np.asarray(region.basis, dtype=float).reshape(V.shape[1], 3)
    return V @ B


def _plan(robot: RobotModel, terrain: Terrain, s: Stance, qs: np.ndarray, qg: np.ndarray, seeds: range,
          **kw: Any) -> tuple[Any, int]:
    for seed in seeds:
        res = find_path(robot, terrain, s, qs, qg, seed=seed, **kw)
        if res.found:
            return res, seed
    raise SystemExit(f"no path for stance {s} within seeds {seeds}")


def _label(ax: Any, res: Any) -> None:
    st = res.stats
    how = "lift-move-place local plan" if st.get("direct") else f"{st['planner']}/{st['sampler']}"
    ax.set_title(f"{how}: {len(res.path)} waypoints, {st['time_s']:.2f} s, "
                 f"{st['checks']} checks", fontsize=8)


def _save(fig: Any, out: Path, res: Any, seed: int) -> None:
    """Write the figure and report the path it shows."""
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    plt.close(fig)
    print(f"{out}: seed {seed}, {res.stats['time_s']:.2f} s, {len(res.path)} waypoints")


# ---- the three moves ------------------------------------------------------------------------------------
def planar3(out: Path) -> None:
    """Bretl, Latombe & Rock (2003), section 3: limbs 1/2 on the crack's edges, limb 3 moves from L4 to R4."""
    robot, terrain = RobotModel.load("planar-3limb"), Terrain.load("planar-wall")
    s = Stance(limb1="L2", limb2="R2")
    qs = qg = None
    for seed in range(20):
        qs = find_transition(robot, terrain, s, s.with_hold("limb3", "L4"), seed=seed)
        qg = find_transition(robot, terrain, s, s.with_hold("limb3", "R4"), seed=seed, near=qs) if qs is not None \
            else None
        if qs is not None and qg is not None:
            break
    assert qs is not None and qg is not None, "no transitions found"
    res, seed = _plan(robot, terrain, s, qs, qg, range(10), sampler="joint-by-joint+straight-elbow+free-limb+lift",
                      space="projected", max_iterations=20000, time_limit=30, cpu_limit=None)
    region = stance_region(robot, terrain, s)
    fig, ax = plt.subplots(figsize=(5.2, 5.4))
    xs = region_world(region)[:, 0]
    ax.axvspan(xs.min(), xs.max(), color="C2", alpha=0.15, label="support interval (limbs 1, 2)")
    for q, a in snapshots(res.path):
        draw_robot(ax, robot, q, (0, 2), a, ["C0", "C1", "C3"])
    C = robot.com_batch(np.array(res.path))
    ax.plot(C[:, 0], C[:, 2], "-", color="C2", lw=1.2, label="CoM")
    ax.plot(C[[0, -1], 0], C[[0, -1], 2], "x", color="C2")
    draw_holds(ax, terrain, (0, 2), {"L2": "limb1", "R2": "limb2", "L4": "limb3 start", "R4": "limb3 goal"},
               arrows=0.08, box=(-1, 1, 0.3, 1.6))
    ax.set_xlim(-0.7, 0.7)
    ax.set_ylim(0.35, 1.55)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m), up")
    ax.legend(loc="lower left", fontsize=7)
    _label(ax, res)
    fig.suptitle("Planar three-limbed robot, planar-wall: limb 3 moves L4 -> R4 "
                 "(Bretl, Latombe & Rock (2003), sec. 3)", fontsize=9)
    _save(fig, out, res, seed)


def double_link(out: Path) -> None:
    """Bretl (2006), Fig. 3-6, 13: hand a on peg 2, hand b swings from peg 3 to peg 4 (stance {a: 2})."""
    robot, terrain = RobotModel.load("double-link"), Terrain.load("pegs")
    s = Stance(a="2")
    # brute force: the collision-free cells of the one-hold torus and their components, so that the start
    # (b on peg 3) and goal (b on peg 4) are chosen in the same component (Bretl (2006), Fig. 4-6; peg 1's
    # transitions lie in other components: the robot goes 1 -> 2 -> 3 -> 2 -> 4, Fig. 13)
    from scipy import ndimage

    p = terrain.hold("2").p
    th = np.linspace(-2 * np.pi, 2 * np.pi, 121)
    free = np.array([[not robot.in_collision(np.array([p[0], p[2], t1, t2]), terrain, contact_limbs=("a",))
                      for t2 in th] for t1 in th])
    lab = ndimage.label(free)[0]

    def comp(q: np.ndarray) -> int:
        """The component of the free cells nearest ``q`` (a transition touches peg 3 or 4, so its own cell of the
        0.1-rad grid may hold a collision): the commonest label in the 5 x 5 cells around it, 0 if all collide."""
        i, j = np.abs(th - q[2]).argmin(), np.abs(th - q[3]).argmin()
        near = lab[max(i - 2, 0):i + 3, max(j - 2, 0):j + 3].ravel()
        near = near[near > 0]
        return int(np.bincount(near).argmax()) if near.size else 0

    q0 = find_transition(robot, terrain, s, s.with_hold("b", "3"), seed=0)
    assert q0 is not None, "no transition onto peg 3"
    lo, hi = np.asarray(robot.lower, dtype=float), np.asarray(robot.upper, dtype=float)

    def points(peg: str) -> list[np.ndarray]:
        """Every configuration with hand b on ``peg`` (both elbow bends, each joint a whole turn either way
        within its limits): Bretl (2006), sec. 2.1, the isolated transitions of a zero-dimensional stance."""
        out = []
        for sol in robot.limb_ik("b", q0, robot.hand_target("b", terrain.hold(peg))):
            for d2, d3 in itertools.product((-2 * np.pi, 0.0, 2 * np.pi), repeat=2):
                q = sol + np.array([0.0, 0.0, d2, d3])
                if np.all(q >= lo - 1e-9) and np.all(q <= hi + 1e-9):
                    out.append(q)
        return out

    starts, goals = points("3"), points("4")
    best = None
    for qs in starts:
        for qg in goals:
            if comp(qs) and comp(qs) == comp(qg):
                res = find_path(robot, terrain, s, qs, qg, seed=0, max_iterations=20000,
                                time_limit=30, cpu_limit=None, space="projected")
                if res.found:
                    best = (res, 0)
                    break
        if best is not None:
            break
    if best is None:
        raise SystemExit("double-link: no path from peg 3 to peg 4")
    res, seed = best
    fig, ax = plt.subplots(figsize=(6.0, 5.0))
    for sf in terrain.surfaces:
        if sf.type == "circle":
            ax.add_patch(plt.Circle((sf.center[0], sf.center[2]), sf.radius, color="0.75", zorder=1))
    for q, a in snapshots(res.path, 8):
        draw_robot(ax, robot, q, (0, 2), a, ["C0", "C1"], lw=2.5)
    H = np.array([robot.hand_position(q, "b") for q in res.path])
    ax.plot(H[:, 0], H[:, 2], ":", color="C1", lw=1, label="hand b")
    C = robot.com_batch(np.array(res.path))
    ax.plot(C[:, 0], C[:, 2], "-", color="C2", lw=1, label="CoM (no equilibrium condition)")
    draw_holds(ax, terrain, (0, 2), {"1": "peg 1", "2": "peg 2 (hand a)", "3": "peg 3 (b start)",
                                     "4": "peg 4 (b goal)"})
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("z (m), up")
    ax.legend(loc="lower right", fontsize=7)
    _label(ax, res)
    fig.suptitle("Double-link robot, pegs: hand a on peg 2, hand b from peg 3 to peg 4 (Bretl (2006), Fig. 3-6, 13)",
                 fontsize=9)
    _save(fig, out, res, seed)


def lemur(out: Path) -> None:
    """LEMUR releases one hold and grabs a neighbouring one (the benchmark's first query).

    Bretl, Latombe & Rock (2003); Bretl et al. (2004).
    """
    from climb_ompl.bench._runs import make_queries

    robot, terrain = RobotModel.load("lemur"), Terrain.load("demo-wall")
    query = make_queries("lemur", "demo-wall", 1, seed=0)[0]
    s = Stance(query["stance"])
    qs, qg = np.asarray(query["q_start"], dtype=float), np.asarray(query["q_goal"], dtype=float)
    res, seed = _plan(robot, terrain, s, qs, qg, range(10), sampler="joint-by-joint+straight-elbow+free-limb+lift",
                      space="projected", max_iterations=40000, time_limit=60, cpu_limit=None)
    region = stance_region(robot, terrain, s)
    free = s.free_limbs(robot)[0]
    names = {h: lb for lb, h in s.items()}
    P = np.array([robot.hand_position(q, free) for q in (qs, qg)])
    for q, tag in ((qs, "release"), (qg, "grab")):
        h = terrain.positions[np.argmin(np.linalg.norm(terrain.positions - robot.hand_position(q, free), axis=1))]
        names[terrain.holds[int(np.argmin(np.linalg.norm(terrain.positions - h, axis=1)))].id] = f"{free} {tag}"
    C = robot.com_batch(np.array(res.path))
    c0 = C[0]
    box = (c0[0] - 0.6, c0[0] + 0.6, c0[2] - 0.6, c0[2] + 0.6)
    fig, (ax, ay) = plt.subplots(1, 2, figsize=(10, 5.2))
    colors = ["C0", "C1", "C3", "C4"]
    for q, a in snapshots(res.path):
        draw_robot(ax, robot, q, (0, 2), a, colors)
        draw_robot(ay, robot, q, (0, 1), a, colors)
    Hf = np.array([robot.hand_position(q, free) for q in res.path])
    for axx, (i, j) in ((ax, (0, 2)), (ay, (0, 1))):
        axx.plot(Hf[:, i], Hf[:, j], ":", color="0.3", lw=1, label=f"free hand {free}")
        axx.plot(C[:, i], C[:, j], "-", color="C2", lw=1.2, label="CoM")
        axx.set_aspect("equal")
    draw_holds(ax, terrain, (0, 2), names, box=box)
    ax.plot(P[:, 0], P[:, 2], "*", color="C5", ms=10, zorder=6)
    ax.set_xlim(box[0], box[1])
    ax.set_ylim(box[2], box[3])
    ax.set_xlabel("x (m), along the wall")
    ax.set_ylabel("z (m), up")
    ax.legend(loc="lower left", fontsize=7)
    _label(ax, res)
    V = region_world(region)
    if len(V) >= 3:
        V = np.vstack([V, V[:1]])
        ay.fill(V[:, 0], V[:, 1], color="C2", alpha=0.15, label=f"support polygon {s}")
    ay.axhline(0.0, color="0.4", lw=2)
    ay.text(box[0] + 0.02, -0.02, "wall (y = 0)", fontsize=7, va="top")
    ay.set_xlim(box[0], box[1])
    ay.set_ylim(-0.15, 0.35)
    ay.set_xlabel("x (m)")
    ay.set_ylabel("y (m), out of the wall")
    ay.legend(loc="upper left", fontsize=7)
    ay.set_title("top view (gravity into the page): support polygon and CoM", fontsize=8)
    fig.suptitle(f"LEMUR, demo-wall: limb {free} released and grabbed on a neighbouring hold "
                 "(three-hold stance, Bretl et al. (2004))", fontsize=9)
    _save(fig, out, res, seed)


FIGURES = {"planar3": planar3, "double_link": double_link, "lemur": lemur}


def main() -> None:
    """Command line: plan and save the chosen figures."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out-dir", type=Path, default=Path(__file__).resolve().parents[1] / "docs")
    ap.add_argument("--only", default=",".join(FIGURES), help="comma-separated subset of " + ", ".join(FIGURES))
    args = ap.parse_args()
    args.out_dir.mkdir(parents=True, exist_ok=True)
    for name in args.only.split(","):
        FIGURES[name.strip()](args.out_dir / f"onestep_{name.strip()}.png")


if __name__ == "__main__":
    main()
