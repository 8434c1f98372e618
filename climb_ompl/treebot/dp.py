"""TreeBot's dynamic-programming path (Lam et al., section IV, Eq. 4-7) and its incremental update (IV.B).

States ``S_{i,j}`` are the points of the rings from the start ring (row 0) to the target ring (row m-1)
(Fig. 7).  An action moves to any point of the next ring.  Its value (Eq. 4) is

    Q(S_{i,j}, S_{i+1,k}) = -D(S_{i,j}, S_{i+1,k}) + a0 * n_{i+1,k} + O_{i+1,k}

with ``D`` the Euclidean distance, ``n = z - 1`` (Eq. 5; ``z`` the component of the unit normal against
gravity, so the top side of a branch, where gravity does not pull the gripper out, costs nothing) and
``O = -inf`` at unreachable points.  The reachability constraint of the robot adds ``Q = -inf`` when
``D > max_reach``.  State values run top-down (Eq. 6-7):

    V_{m-1,k} = 0 for the target point(s),   V_{i,j} = max_k (V_{i+1,k} + Q(S_{i,j}, S_{i+1,k})),

so Eq. 6 (``V_{m-2,j} = Q(S_{m-2,j}, S_{m-1,t})``) is the first step of the recursion.  With ``m`` rings
of ``n`` points the work is O(m n^2).  Because the values are computed from the top down, re-measuring
rings changes only the values at and below the highest changed ring (section IV.B):
:meth:`DPPlanner.update` recomputes exactly those rows.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from climb_ompl.errors import ARGUMENT
from climb_ompl.treebot.tree import Ring, Tree, TreeError

NEG_INF = -np.inf


@dataclass(frozen=True)
class PathPoint:
    """One gripping point of the path.

    Attributes:
        row: DP row (0 = start ring).
        branch: branch name.
        ring: ring index within the branch.
        point: point index within the ring.
        position: world position, metres.
        normal: unit outward surface normal.
    """

    row: int
    branch: str
    ring: int
    point: int
    position: np.ndarray
    normal: np.ndarray

    def to_dict(self) -> dict:
        """JSON form."""
        return {"row": self.row, "branch": self.branch, "ring": self.ring, "point": self.point,
                "position": self.position.tolist(), "normal": self.normal.tolist()}


@dataclass
class PathResult:
    """Outcome of a DP query (no path is a status, not an exception).

    Attributes:
        found: a path exists.
        path: gripping points, start ring first (empty if not found).
        cost: ``-V`` of the start state: total distance minus ``a0 * sum(n)``, metres (inf if not found).
        reason: why no path exists (empty if found).
        stats: counters (rows, states, edges evaluated, rows recomputed by the last update).
    """

    found: bool
    path: list[PathPoint]
    cost: float
    reason: str = ""
    stats: dict = field(default_factory=dict)


def rewards(ring: Ring, up: np.ndarray, a0: float) -> np.ndarray:
    """Per-point reward of entering a point: ``a0 * n + O`` (Lam et al. (TreeBot), Eq. 4-5), ``-inf`` at obstacles."""
    r = a0 * (ring.normals @ up - 1.0)
    return np.where(ring.obstacles, NEG_INF, r)


def action_values(a: Ring, b: Ring, reward_b: np.ndarray, max_reach: float) -> np.ndarray:
    """``Q`` of every action from ring ``a`` to ring ``b`` (Eq. 4), ``(n_a, n_b)``; ``-inf`` beyond reach."""
    d = np.linalg.norm(a.points[:, None, :] - b.points[None, :, :], axis=2)
    q = -d + reward_b[None, :]
    q[d > max_reach] = NEG_INF
    return q


class DPPlanner:
    """Dynamic-programming planner over a fixed sequence of rings (Lam et al. (TreeBot), Eq. 4-7).

    Args:
        rings: the rows of Fig. 7, start ring first, target ring last.
        up: unit vector against gravity.
        a0: weight of the pull-out term, metres.
        max_reach: longest admissible step between consecutive gripping points, metres.
        target_point: index of the target point on the last ring (``S_{m,t}``); ``None`` lets the
            planner choose any reachable point of the target ring.
        labels: ``(branch, ring)`` of each row, for the path and the messages.
    """

    def __init__(self, rings: list[Ring], up: np.ndarray, a0: float, max_reach: float,
                 target_point: int | None = None, labels: list[tuple[str, int]] | None = None):
        if len(rings) < 2:
            raise ValueError("the DP needs a start ring and a distinct target ring (Lam et al., section IV.A)")
        self.rings = list(rings)
        self.up = np.asarray(up, float)
        self.a0, self.max_reach, self.target_point = float(a0), float(max_reach), target_point
        self.labels = labels or [("", i) for i in range(len(rings))]
        self.V: list[np.ndarray] = [np.empty(0)] * len(rings)
        self.best: list[np.ndarray] = [np.empty(0, int)] * len(rings)  # argmax successor per state
        self.edges = 0
        self.rows_recomputed = 0
        self._init_last()
        self._recompute(len(rings) - 2)

    @classmethod
    def for_tree(cls, tree: Tree, target: str, target_point: int | None = None) -> "DPPlanner":
        """Planner from the trunk's first ring to the last ring of branch ``target``."""
        labels = tree.ring_sequence(target)
        if len(labels) < 2:
            raise TreeError(tree.source, "target", f"branch {target!r} ends on the start ring; the target must lie "
                            "above the start (Lam et al. (TreeBot), section IV.A)")
        rings = [tree.branch(b).rings[r] for b, r in labels]
        if target_point is not None and not 0 <= target_point < rings[-1].n:
            raise TreeError(ARGUMENT, "target_point", f"expected a point index in 0..{rings[-1].n - 1}, "
                            f"got {target_point}")
        return cls(rings, tree.up, tree.a0, tree.robot.max_reach, target_point, labels)

    def _init_last(self) -> None:
        last = self.rings[-1]
        v = np.where(last.obstacles, NEG_INF, 0.0)
        if self.target_point is not None:
            keep = np.full(last.n, NEG_INF)
            keep[self.target_point] = v[self.target_point]
            v = keep
        self.V[-1] = v
        self.best[-1] = np.full(last.n, -1)

    def _recompute(self, top: int) -> None:
        """Recompute rows ``top, top-1, ..., 0`` (Eq. 7)."""
        for i in range(top, -1, -1):
            rb = rewards(self.rings[i + 1], self.up, self.a0)
            tot = action_values(self.rings[i], self.rings[i + 1], rb, self.max_reach) + self.V[i + 1][None, :]
            k = np.argmax(tot, axis=1)
            v = tot[np.arange(len(k)), k]
            self.V[i] = np.where(self.rings[i].obstacles, NEG_INF, v)
            self.best[i] = k
            self.edges += tot.size
        self.rows_recomputed = top + 1

    def update(self, changed: dict[int, Ring]) -> int:
        """Replace re-measured rings (row -> new ring) and recompute only the affected rows (section IV.B).

        A change of row ``r`` alters the actions into and out of ``r``, hence ``V`` of rows ``<= r`` only.

        Returns:
            the number of rows recomputed (``max(changed) + 1``, or all rows if the target ring changed).
        """
        if not changed:
            self.rows_recomputed = 0
            return 0
        for r, ring in changed.items():
            self.rings[r] = ring
        top = max(changed)
        if top == len(self.rings) - 1:
            self._init_last()
            top -= 1
        self._recompute(top)
        return self.rows_recomputed

    def solve(self, start_point: int | None = None) -> PathResult:
        """Read the optimal path off the state values (Lam et al. (TreeBot), "Optimal Path").

        Args:
            start_point: start on this point of the first ring; ``None``: the first-ring state of maximum value.
        """
        v0 = self.V[0]
        j = int(np.argmax(v0)) if start_point is None else int(start_point)
        stats = {"rows": len(self.rings), "states": int(sum(r.n for r in self.rings)), "edges": int(self.edges),
                 "rows_recomputed": int(self.rows_recomputed)}
        if not np.isfinite(v0[j]):
            return PathResult(False, [], float("inf"), self._reason(start_point), stats)
        path, i = [], 0
        while True:
            b, r = self.labels[i]
            path.append(PathPoint(i, b, r, j, self.rings[i].points[j].copy(), self.rings[i].normals[j].copy()))
            if i == len(self.rings) - 1:
                break
            j, i = int(self.best[i][j]), i + 1
        return PathResult(True, path, float(-v0[path[0].point]), "", stats)

    def _reason(self, start_point: int | None) -> str:
        def name(i: int) -> str:
            b, r = self.labels[i]
            return f"ring {r} of branch {b!r}" if b else f"ring {i}"

        last = self.rings[-1]
        if self.target_point is not None and last.obstacles[self.target_point]:
            return f"the target point {self.target_point} of {name(len(self.rings) - 1)} is unreachable (obstacle)"
        if last.obstacles.all():
            return f"every point of the target {name(len(self.rings) - 1)} is unreachable"
        if start_point is not None and self.rings[0].obstacles[start_point]:
            return f"the start point {start_point} of {name(0)} is unreachable (obstacle)"
        for i in range(len(self.rings) - 2, -1, -1):
            if not np.isfinite(self.V[i]).any():
                return (f"no point of {name(i)} reaches a point of {name(i + 1)} that leads to the target "
                        f"(obstacles, or steps longer than max_reach = {self.max_reach} m)")
        return f"no path from start point {start_point} of {name(0)} to the target"


def plan_path(tree: Tree, target: str, *, target_point: int | None = None,
              start_point: int | None = None) -> PathResult:
    """Optimal gripping-point path from the trunk's first ring to the last ring of ``target`` (Eq. 4-7).

    Raises:
        TreeError: unknown target branch.
    """
    return DPPlanner.for_tree(tree, target, target_point).solve(start_point)
