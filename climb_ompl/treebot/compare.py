"""Proposed vs. simple motion planning (Lam et al. (TreeBot), section VI.B, Fig. 13).

Figures of merit per method, on the same planned path and the same front-gripper targets.  The paper gives
no number: Fig. 13 draws, for each "motion", the body with both grippers at the end of an extension
(red line, blue and magenta arrows) over the planned path, and calls a motion good when it is "close to the
planned path" (section V: ideally both grippers and the body lie on it).  Hence:

* **following error** (``errors``, ``mean_error``, ``max_error``): for each extension, the largest distance
  from the body *at the end of the extension* (the posture Fig. 13 draws, rear gripper included) to the
  planned path polyline (plus a lead-in of one contracted body below the start), metres;
* **swept error** (``swept_*``): the same over every sampled shape of the extension.  The paper plans
  postures only; the shapes in between are this package's interpolation (:mod:`.motion`), so this is a
  secondary figure;
* **segment error** (``segment_*``): for each extension, the largest distance from the path segment being
  climbed (between the two front-gripper targets) to the body at the end of the extension: what the
  proposed method optimises ("make the next extension motion best fit to the planned path", V.A);
* **obstacle hits**: the motions (extension + following contraction, every sampled shape) whose body comes
  within ``hit_radius`` of an obstacle: an unreachable point, or any point of a branch the path does not
  use (Lam et al. (TreeBot), section III: non-passing branches are obstacles).  In Fig. 13(a) motions 1 and 3 of the
  simple method "went through the obstacles".
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from climb_ompl.treebot.dp import PathResult, plan_path
from climb_ompl.treebot.motion import METHODS, Motion, plan_motion
from climb_ompl.treebot.tree import RobotParams, Tree


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
    """Figures of one method (see module docstring); errors in metres, one per extension in ``errors``."""

    method: str
    motions: int
    mean_error: float
    max_error: float
    errors: list[float]
    swept_mean_error: float
    swept_max_error: float
    segment_mean_error: float
    segment_max_error: float
    hits: int
    hit_motions: list[int]
    length_violations: int

    def to_dict(self) -> dict:
        """JSON form."""
        return dict(self.__dict__)


def _densify(poly: np.ndarray, spacing: float = 0.005) -> np.ndarray:
    """Points along the polyline ``poly`` at most ``spacing`` apart, vertices included."""
    out = [poly[:1]]
    for a, b in zip(poly[:-1], poly[1:], strict=False):
        k = max(1, int(np.ceil(np.linalg.norm(b - a) / spacing)))
        out.append(a + np.linspace(0.0, 1.0, k + 1)[1:, None] * (b - a))
    return np.concatenate(out)


def with_lead_in(path: np.ndarray, normals: np.ndarray, s_min: float) -> np.ndarray:
    """The path with a straight lead-in of one contracted body length below the start (in the start's tangent
    plane), where both methods put the rear gripper before the first extension."""
    d0 = path[min(len(path) - 1, 1)] - path[0]
    d0 = d0 - (d0 @ normals[0]) * normals[0]
    return np.vstack([path[0] - s_min * d0 / np.linalg.norm(d0), path])


def evaluate(motion: Motion, path: np.ndarray, normals: np.ndarray, obstacles: np.ndarray, s_min: float,
             s_max: float, hit_radius: float = 0.02) -> MethodMetrics:
    """Following, swept and segment errors, obstacle hits and body-length violations of a motion along
    ``path`` (``(P, 3)``, the points ``motion`` was planned on) with surface ``normals``."""
    ref = with_lead_in(path, normals, s_min)
    n = len(motion.steps)
    err, swept, seg, hit = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n, bool)
    last: dict[int, np.ndarray] = {}
    for f in motion.frames:
        if f.phase == "extend":
            d = float(point_polyline_distance(f.body, ref).max())
            swept[f.step] = max(swept[f.step], d)
            err[f.step] = d  # frames are in time order: the last one is the posture at the end
            last[f.step] = f.body
        if len(obstacles):
            dmin = np.linalg.norm(f.body[:, None, :] - obstacles[None], axis=2).min()
            hit[f.step] |= bool(dmin < hit_radius)
    for k in range(n):
        piece = _densify(path[motion.targets[k]:motion.targets[k + 1] + 1])
        seg[k] = float(point_polyline_distance(piece, last[k]).max())
    S = motion.lengths()
    viol = int(np.sum((S < s_min - 1e-9) | (S > s_max + 1e-9) | ~np.isfinite(S)))

    def mean(a: np.ndarray) -> float:
        return float(a.mean()) if n else 0.0

    def top(a: np.ndarray) -> float:
        return float(a.max()) if n else 0.0

    return MethodMetrics(motion.method, n, mean(err), top(err), err.tolist(), mean(swept), top(swept), mean(seg),
                         top(seg), int(hit.sum()), [int(i) for i in np.flatnonzero(hit)], viol)


def compare_path(path: np.ndarray, normals: np.ndarray, robot: RobotParams, obstacles: np.ndarray | None = None,
                 hit_radius: float = 0.02, arc_fit: str = "geometric", bark: Any = None) -> dict[str, MethodMetrics]:
    """Both methods on a given path ``(P, 3)`` with surface ``normals`` (e.g. a synthetic smooth path);
    ``arc_fit``: the proposed method's arc fit (:data:`climb_ompl.treebot.motion.ARC_FITS`); ``bark``
    (nearest bark point of a point) puts the rear gripper on the tree, as plans do."""
    obs = np.empty((0, 3)) if obstacles is None else obstacles
    out = {}
    for m in METHODS:
        mot = plan_motion(path, normals, robot, m, arc_fit=arc_fit, bark=bark)  # type: ignore[arg-type]
        out[m] = evaluate(mot, path, normals, obs, robot.s_min, robot.s_max, hit_radius)
    return out


def compare(tree: Tree, target: str, hit_radius: float = 0.02,
            result: PathResult | None = None) -> dict[str, MethodMetrics] | None:
    """Both methods on the DP path to ``target``; ``None`` when no path exists."""
    res = result or plan_path(tree, target)
    if not res.found:
        return None
    from climb_ompl.treebot.bark import Bark

    P = np.array([p.position for p in res.path])
    N = np.array([p.normal for p in res.path])
    bark = Bark(tree.branch(b) for b in dict.fromkeys(p.branch for p in res.path))
    return compare_path(P, N, tree.robot, obstacle_points(tree, target), hit_radius, bark=bark.nearest)
