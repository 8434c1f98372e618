"""A seeded generator of trees for TreeBot (trunk + branches, curvature, radius taper, surface noise).

The surface follows Lam et al. (TreeBot), section III: each branch is a bent tube discretised into rings perpendicular
to its growing direction (Fig. 5), each ring into equally spaced points with surface normals.  Normals are
computed from the discretised surface itself (cross product of the along-ring and across-ring differences),
so surface noise changes them consistently.  Unreachable points (section III) are (1) the points of a
parent covered by a child branch where it leaves the parent and (2) a few random patches ("concave bark").
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from climb_ompl.treebot.tree import Branch, Ring, RobotParams, Tree


@dataclass(frozen=True)
class BranchSpec:
    """Layout of one generated branch.

    Attributes:
        parent: index of the parent in the layout list (-1 for the trunk, which must come first).
        attach: where it leaves the parent, as a fraction of the parent's rings (0..1).
        azimuth: direction around the parent, degrees.
        elevation: angle between the branch and the parent's axis, degrees.
        rings: number of rings.
        radius: base radius, metres.
    """

    parent: int
    attach: float
    azimuth: float
    elevation: float
    rings: int
    radius: float


def _rotate(v: np.ndarray, axis: np.ndarray, angle: float) -> np.ndarray:
    """Rodrigues' rotation of ``v`` about unit ``axis`` by ``angle`` radians."""
    return v * np.cos(angle) + np.cross(axis, v) * np.sin(angle) + axis * (axis @ v) * (1 - np.cos(angle))


def _tube(rng: np.random.Generator, c0: np.ndarray, t0: np.ndarray, m: int, n: int, spacing: float, r0: float,
          taper: float, curvature: float, noise: float) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Centreline, tangents, surface points ``(m, n, 3)`` and normals ``(m, n, 3)`` of a bent, tapered tube."""
    up = np.array([0.0, 0.0, 1.0])
    t = t0 / np.linalg.norm(t0)
    u = np.cross(t, up) if abs(t @ up) < 0.95 else np.cross(t, [1.0, 0.0, 0.0])
    u /= np.linalg.norm(u)
    bend_axis = _rotate(u, t, rng.uniform(0, 2 * np.pi))
    centres, tangents, us = [], [], []
    c = c0.astype(float)
    for _ in range(m):
        centres.append(c.copy())
        tangents.append(t.copy())
        us.append(u.copy())
        c = c + spacing * t
        bend_axis = _rotate(bend_axis, t, rng.normal(0, 0.3))
        bend_axis -= (bend_axis @ t) * t
        bend_axis /= np.linalg.norm(bend_axis)
        t_new = _rotate(t, bend_axis, curvature * spacing)
        if t_new @ up < 0.15:  # branches keep growing upwards
            t_new = t
        u = u - (u @ t_new) * t_new  # parallel transport of the ring frame
        u /= np.linalg.norm(u)
        t = t_new
    centres_a, tangents_a = np.array(centres), np.array(tangents)
    ang = np.arange(n) * 2 * np.pi / n
    # Smooth bark noise: two harmonics in angle with phases drifting along the branch.
    ph = rng.uniform(0, 2 * np.pi, 4)
    k = np.arange(m)[:, None]
    wobble = (np.sin(2 * ang[None, :] + ph[0] + 0.3 * k) * rng.uniform(0.3, 1.0)
              + np.sin(3 * ang[None, :] + ph[1] + 0.2 * k) * rng.uniform(0.3, 1.0)) / 2
    radius = r0 * (1 - taper * np.arange(m) / max(m - 1, 1))[:, None] * (1 + noise * wobble)
    pts = np.empty((m, n, 3))
    for i in range(m):
        v = np.cross(tangents_a[i], us[i])
        pts[i] = centres_a[i] + radius[i][:, None] * (np.cos(ang)[:, None] * us[i] + np.sin(ang)[:, None] * v)
    d_ang = np.roll(pts, -1, axis=1) - np.roll(pts, 1, axis=1)
    d_len = np.gradient(pts, axis=0) if m > 1 else np.broadcast_to(tangents_a[:, None, :], pts.shape)
    nrm = np.cross(d_ang, d_len)
    radial = pts - centres_a[:, None, :]
    nrm *= np.sign(np.sum(nrm * radial, axis=2, keepdims=True))
    nrm /= np.linalg.norm(nrm, axis=2, keepdims=True)
    return centres_a, tangents_a, pts, nrm


def _seg_dist(p: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Distance of points ``p (..., 3)`` to the segment ``a``-``b``."""
    ab = b - a
    s = np.clip(((p - a) @ ab) / (ab @ ab), 0.0, 1.0)
    return np.linalg.norm(p - (a + s[..., None] * ab), axis=-1)


def generate_tree(seed: int, *, layout: list[BranchSpec] | None = None, n_branches: int = 3,
                  points_per_ring: int = 16, ring_spacing: float = 0.05, trunk_rings: int = 24,
                  trunk_radius: float = 0.09, taper: float = 0.3, curvature: float = 1.0, noise: float = 0.08,
                  obstacle_patches: int = 3, robot: RobotParams | None = None, name: str | None = None) -> Tree:
    """Generate a random tree; the same arguments give the same tree.

    Args:
        seed: RNG seed.
        layout: explicit branch layout (trunk first); default: a trunk and ``n_branches - 1`` random branches.
        n_branches: number of branches including the trunk (used without ``layout``).
        points_per_ring: points per ring ``n`` (Lam et al. (TreeBot), Fig. 7 columns).
        ring_spacing: distance between ring centres, metres.
        trunk_rings: rings of the trunk (used without ``layout``).
        trunk_radius: trunk base radius, metres.
        taper: relative radius loss from base to tip of each branch (0..1).
        curvature: bending of the centreline, rad/m.
        noise: relative amplitude of the radius noise.
        obstacle_patches: number of random unreachable patches.
        robot: TreeBot parameters stored in the tree.
        name: tree name (default ``tree-<seed>``).
    """
    rng = np.random.default_rng(seed)
    if layout is None:
        layout = [BranchSpec(-1, 0.0, 0.0, 0.0, trunk_rings, trunk_radius)]
        for i in range(1, n_branches):
            par = int(rng.integers(0, i))
            layout.append(BranchSpec(par, float(rng.uniform(0.45, 0.9)), float(rng.uniform(0, 360)),
                                     float(rng.uniform(30, 55)), int(rng.integers(10, 20)),
                                     layout[par].radius * float(rng.uniform(0.55, 0.75))))
    tubes: list[tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]] = []
    attach_idx: list[int | None] = []
    for spec in layout:
        if spec.parent < 0:
            c0, t0, a_idx = np.zeros(3), np.array([0.0, 0.0, 1.0]), None
        else:
            pc, pt, ppts, _ = tubes[spec.parent]
            a_idx = int(round(spec.attach * (len(pc) - 1)))
            ref = ppts[a_idx, 0] - pc[a_idx]
            ref /= np.linalg.norm(ref)
            side = _rotate(ref, pt[a_idx], np.radians(spec.azimuth))
            t0 = _rotate(pt[a_idx], np.cross(pt[a_idx], side) / np.linalg.norm(np.cross(pt[a_idx], side)),
                         np.radians(spec.elevation))
            r_par = float(np.linalg.norm(ppts[a_idx] - pc[a_idx], axis=1).mean())
            c0 = pc[a_idx] + t0 * (r_par / np.sin(np.radians(spec.elevation)) + spec.radius * 0.5)
        tubes.append(_tube(rng, c0, t0, spec.rings, points_per_ring, ring_spacing, spec.radius, taper,
                           curvature, noise))
        attach_idx.append(a_idx)
    obstacles = [np.zeros(t[2].shape[:2], bool) for t in tubes]
    # (1) A child covers the parent's surface where it leaves it: no room above those points.
    for spec, tube in zip(layout, tubes, strict=False):
        if spec.parent < 0:
            continue
        pc = tubes[spec.parent][0]
        a_idx = attach_idx[layout.index(spec)]
        dist = _seg_dist(tubes[spec.parent][2], pc[a_idx], tube[0][0])
        obstacles[spec.parent] |= dist < spec.radius * 0.9
    # (2) Random concave patches, kept off the first ring (the start).
    for _ in range(obstacle_patches):
        b = int(rng.integers(0, len(tubes)))
        m, n = obstacles[b].shape
        if m < 4:
            continue
        i0, j0 = int(rng.integers(2, m - 1)), int(rng.integers(0, n))
        for di in range(int(rng.integers(1, 3))):
            for dj in range(int(rng.integers(1, 4))):
                obstacles[b][min(i0 + di, m - 1), (j0 + dj) % n] = True
    names = ["trunk"] + [f"b{i + 1}" for i in range(1, len(layout))]
    branches = []
    for i, (spec, tube) in enumerate(zip(layout, tubes, strict=False)):
        rings = tuple(Ring(tube[2][k], tube[3][k], obstacles[i][k]) for k in range(spec.rings))
        branches.append(Branch(names[i], None if spec.parent < 0 else names[spec.parent], attach_idx[i], rings))
    return Tree(name or f"tree-{seed}", tuple(branches), robot=robot or RobotParams(), source=f"<generated {seed}>")


def three_branch_layout() -> list[BranchSpec]:
    """A layout shaped like the test tree of Lam et al. (TreeBot), Fig. 11: a trunk that forks into branches 2 and 3."""
    return [BranchSpec(-1, 0.0, 0.0, 0.0, 22, 0.09),
            BranchSpec(0, 0.8, 30.0, 35.0, 18, 0.065),
            BranchSpec(0, 0.8, 210.0, 40.0, 16, 0.06)]
