"""The bark as a triangle mesh, for putting a gripper on the tree surface (Lam et al. (TreeBot), section V.B.2).

The rings of surface points (Fig. 5) are joined ring to ring into a closed tube of triangles per
branch; :class:`Bark` finds the nearest point of that surface with Coal (a BVH distance query), so the rear
gripper of a contraction lands *on* the tree surface ("to make the target position of the rear gripper on
the tree surface"), not on the tangent plane of the front gripper's point, which leaves it up to a few
centimetres inside or above a curved bark.
"""

from __future__ import annotations

from collections.abc import Iterable

import numpy as np

from climb_ompl.treebot.tree import Branch


class Bark:
    """Nearest-point queries on the surface of some branches (their consecutive rings joined by triangles).

    Args:
        branches: the branches whose bark a gripper may hold (e.g. those the path climbs).
        grip: leave out the triangles at an unreachable point (``O = -inf``, Eq. 4), where no gripper holds.
    """

    def __init__(self, branches: Iterable[Branch], grip: bool = True):
        import coal
        from scipy.spatial import cKDTree

        verts, norms, ends, nbrs, tris = [], [], [], [], []
        base = 0
        for b in branches:
            n = b.rings[0].n
            if len(b.rings) < 2 or any(r.n != n for r in b.rings):
                continue  # a ring of another size cannot be joined point to point
            pts = np.concatenate([r.points for r in b.rings])
            verts.append(pts)
            norms.append(np.concatenate([r.normals for r in b.rings]))
            end = np.zeros((len(b.rings), n), bool)
            end[[0, -1]] = True
            ends.append(end.ravel())
            ring_start = base + np.repeat(np.arange(len(b.rings)) * n, n)
            col = np.tile(np.arange(n), len(b.rings))
            nbrs.append(np.stack([ring_start + (col - 1) % n, ring_start + (col + 1) % n], axis=1))
            obst = np.concatenate([r.obstacles for r in b.rings]) if grip else np.zeros(len(pts), bool)
            j = np.arange(n)
            for k in range(len(b.rings) - 1):
                a0, a1 = k * n + j, k * n + (j + 1) % n
                c0, c1 = a0 + n, a1 + n
                for t in (np.stack([a0, a1, c0], axis=1), np.stack([a1, c1, c0], axis=1)):
                    tris.append(base + t[~obst[t].any(axis=1)])
            base += len(pts)
        self.vertices = np.concatenate(verts)
        self.normals = np.concatenate(norms)
        self.ends = np.concatenate(ends)
        self.ring_neighbours = np.concatenate(nbrs)
        self.triangles = np.concatenate(tris).astype(int)
        self._kd = cKDTree(self.vertices)
        self.mesh = coal.BVHModelOBBRSS()
        self.mesh.beginModel(len(self.triangles), len(self.vertices))
        self.mesh.addVertices(self.vertices)
        self.mesh.addTriangles(self.triangles)
        self.mesh.endModel()
        self._probe = coal.Sphere(1e-9)

    def nearest(self, p: np.ndarray) -> np.ndarray:
        """The point of the bark nearest to ``p`` (world, metres)."""
        import coal

        req, res = coal.DistanceRequest(), coal.DistanceResult()
        coal.distance(self.mesh, coal.Transform3s(), self._probe,
                      coal.Transform3s(np.eye(3), np.asarray(p, float)), req, res)
        return np.array(res.getNearestPoint1())

    def depth(self, p: np.ndarray) -> float:
        """How far ``p`` is inside the branches, metres (0 outside): the distance to the nearest bark point when
        the surface normal at the mesh vertex nearest to that point faces away from ``p``; a point beyond a
        branch's first or last ring is outside it."""
        p = np.asarray(p, float)
        c = self.nearest(p)
        k = int(self._kd.query(c)[1])
        if float((p - c) @ self.normals[k]) >= 0.0:
            return 0.0
        if self.ends[k]:  # on the open end's rim (an edge to a ring neighbour): beyond the end
            v = self.vertices[k]
            for w in self.vertices[self.ring_neighbours[k]]:
                t = float(np.clip((c - v) @ (w - v) / max(float((w - v) @ (w - v)), 1e-300), 0.0, 1.0))
                if np.linalg.norm(v + t * (w - v) - c) <= 1e-9:
                    return 0.0
        return float(np.linalg.norm(p - c))
