"""Proposed vs. simple motion planning (seed 004 section VI.B, Fig. 13).

Two figures of merit per method, on the same planned path and the same front-gripper targets:

* **path-following error**: for each extension ("motion" in Fig. 13), the largest distance from the body
  (every sampled arc of that extension) to the planned path polyline, metres;
* **obstacle hits**: the motions (extension + following contraction) whose body comes within
  ``hit_radius`` of an obstacle: an unreachable point, or any point of a branch the path does not use
  (seed 004 section III: non-passing branches are obstacles).  In Fig. 13(a) motions 1 and 3 of the simple
  method "went through the obstacles".
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .dp import PathResult, plan_path
from .motion import METHODS, Motion, plan_motion
from .tree import Tree


def point_polyline_distance(points: np.ndarray, poly: np.ndarray) -> np.ndarray:
    """Distance of each of ``points (N, 3)`` to the polyline ``poly (P, 3)``, metres."""
    a, b = poly[:-1], poly[1:]
    ab = b - a
    L2 = np.maximum(np.sum(ab * ab, axis=1), 1e-300)
    ap = points[:, None, :] - a[None, :, :]
    s = np.clip(np.sum(ap * ab[None], axis=2) / L2[None], 0.0, 1.0)
    d = np.linalg.norm(ap - s[..., None] * ab[None], axis=2)
    return d.min(axis=1)


def obstacle_points(tree: Tree, target: str) -> np.ndarray:
    """Obstacles for the body: unreachable points of every branch and every point of non-passing branches."""
    passing = {b.name for b in tree.branch_chain(target)}
    out = []
    for b in tree.branches:
        for r in b.rings:
            out.append(r.points[r.obstacles] if b.name in passing else r.points)
    return np.concatenate(out) if out else np.empty((0, 3))


@dataclass
class MethodMetrics:
    """Figures of one method (see module docstring); errors in metres."""

    method: str
    motions: int
    mean_error: float
    max_error: float
    errors: list[float]
    hits: int
    hit_motions: list[int]
    length_violations: int

    def to_dict(self) -> dict:
        """JSON form."""
        return dict(self.__dict__)


def evaluate(motion: Motion, path: np.ndarray, obstacles: np.ndarray, s_min: float, s_max: float,
             hit_radius: float = 0.02) -> MethodMetrics:
    """Following error, obstacle hits and body-length violations of a motion."""
    n = len(motion.steps)
    err, hit = np.zeros(n), np.zeros(n, bool)
    for f in motion.frames:
        if f.phase == "extend":
            err[f.step] = max(err[f.step], float(point_polyline_distance(f.body, path).max()))
        if len(obstacles):
            d = np.linalg.norm(f.body[:, None, :] - obstacles[None], axis=2).min()
            hit[f.step] |= bool(d < hit_radius)
    S = motion.lengths()
    viol = int(np.sum((S < s_min - 1e-9) | (S > s_max + 1e-9) | ~np.isfinite(S)))
    return MethodMetrics(motion.method, n, float(err.mean()) if n else 0.0, float(err.max()) if n else 0.0,
                         err.tolist(), int(hit.sum()), [int(i) for i in np.flatnonzero(hit)], viol)


def compare(tree: Tree, target: str, hit_radius: float = 0.02,
            result: PathResult | None = None) -> dict[str, MethodMetrics] | None:
    """Both methods on the DP path to ``target``; ``None`` when no path exists."""
    res = result or plan_path(tree, target)
    if not res.found:
        return None
    P = np.array([p.position for p in res.path])
    N = np.array([p.normal for p in res.path])
    obs = obstacle_points(tree, target)
    # Reference for the following error: the path plus a straight lead-in of one contracted body length
    # below the start, where both methods put the rear gripper before the first extension.
    d0 = P[min(len(P) - 1, 1)] - P[0]
    d0 -= (d0 @ N[0]) * N[0]
    ref = np.vstack([P[0] - tree.robot.s_min * d0 / np.linalg.norm(d0), P])
    out = {}
    for m in METHODS:
        mot = plan_motion(P, N, tree.robot, m)  # type: ignore[arg-type]
        out[m] = evaluate(mot, ref, obs, tree.robot.s_min, tree.robot.s_max, hit_radius)
    return out
