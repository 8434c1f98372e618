"""How often must the planar three-limbed robot choose an elbow bend before a release? (Bretl (2006), Fig. 10)

Run: ``python examples/fig10_elbow_bends.py [--layouts 1500] [--seed 21] [--friction 0.2 1.0]``.

Bretl (2006), Fig. 10 and 14(b): on the four-step move ``{1,2} -> {1,2,3} -> {2,3} -> {2,3,4} -> {3,4}`` the
grab of hold 4 at ``{2,3}`` is feasible for one elbow bend of the limb on hold 3 only, and the robot cannot
switch that bend at ``{2,3}``, so it must grab hold 3 with the right bend before it releases hold 1.  The paper
gives no hold layout.  This script draws random four-hold layouts (hold 3 within 0.6 m of hold 2, holds 1 and
4 within 0.7 m of 2 and 3, normals within 52 deg of up) for ``planar-3limb`` (limbs 1 on hold 1, 2 on hold 2,
3 on hold 3, then 1 on hold 4) and counts those where the choice matters.

Model reduction (Bretl, Latombe & Rock (2003), Eq. 2-4; Bretl (2006), appendix C): at ``{2,3}`` a pelvis
position with given elbow bends is feasible iff the free limb, which moves the robot's CoM abscissa by up to
``±2L/6``, can bring it into the support interval ``E_23``; by appendix C any feasible pelvis path lifts to
``F_23``.  So the components of ``F_23`` are the components of the feasible pelvis cells of each bend pair
(grid), glued where an elbow can straighten: a feasible pelvis point on the circle ``|p - h| = 2L`` of that
limb's hold, with the grid cells just inside it feasible for both bends.  A transition to ``{2,3,4}`` (grab
hold 4) or from ``{1,2,3}`` (release hold 1) is a pelvis cell where the three limbs close and the CoM lies in
``E_23``.  The choice matters when the components reached by releasing hold 1 with one bend of limb 3
contain no grab of hold 4 while those of the other bend do.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable

import numpy as np
from scipy import ndimage

from climb_ompl import RobotModel, Stance, Terrain, stance_region
from climb_ompl.manifold.planar3 import interval

BENDS = (-1, 1)


class Layout:
    """One four-hold layout: the support intervals of its stances and the limbs' CoM sums on a pelvis grid."""

    def __init__(self, robot: RobotModel, holds: list[tuple[float, float, float, float]], step: float = 0.02):
        self.L = float(robot.limbs[0].reach) / 2
        self.terrain = Terrain.from_dict({
            "name": "fig10", "dim": 2, "gravity": [0.0, -9.81],
            "holds": [{"id": str(i + 1), "position": [x, z], "normal": [math.sin(a), math.cos(a)], "friction": mu}
                      for i, (x, z, a, mu) in enumerate(holds)]})
        self.h = {str(i + 1): np.array(h[:2]) for i, h in enumerate(holds)}
        lo = np.min([h[:2] for h in holds], 0) - 2 * self.L
        hi = np.max([h[:2] for h in holds], 0) + 2 * self.L
        self.xs, self.zs, self.step = np.arange(lo[0], hi[0], step), np.arange(lo[1], hi[1], step), step
        X, Z = np.meshgrid(self.xs, self.zs, indexing="ij")
        self.shape, self.P = X.shape, np.column_stack([X.ravel(), Z.ravel()])
        self.E = {k: interval(stance_region(robot, self.terrain, Stance(s))) for k, s in (
            ("23", {"limb2": "2", "limb3": "3"}), ("12", {"limb1": "1", "limb2": "2"}))}

    def limb_sum(self, P: np.ndarray, hold: str, bend: int) -> np.ndarray:
        """Sum of the abscissas of a limb's two link centres from pelvis ``P`` to ``hold`` (NaN out of reach)."""
        L, d = self.L, self.h[hold][None, :] - P
        c2 = ((d ** 2).sum(1) - 2 * L * L) / (2 * L * L)
        t2 = bend * np.arccos(np.clip(c2, -1, 1))
        t1 = np.arctan2(d[:, 1], d[:, 0]) - np.arctan2(L * np.sin(t2), L + L * np.cos(t2))
        ex = P[:, 0] + L * np.cos(t1)
        return np.where(np.abs(c2) <= 1, (P[:, 0] + 2 * ex + self.h[hold][0]) / 2, np.nan)

    def balanced_with_free_limb(self, P: np.ndarray, chain: np.ndarray, E: tuple[float, float]) -> np.ndarray:
        """Two holds: some free-limb posture puts the CoM (six equal links) in ``E`` (Eq. 4 / C2)."""
        return ((chain + 2 * P[:, 0] - 2 * self.L) / 6 <= E[1]) & ((chain + 2 * P[:, 0] + 2 * self.L) / 6 >= E[0])

    def components_23(self) -> tuple[dict, dict, Callable[[tuple], tuple]]:
        """Feasible cells per bend pair of limbs 2 and 3 at ``{2,3}``, their labels, and the union-find root."""
        P, E = self.P, self.E["23"]
        F, lab, parent = {}, {}, {}

        def find(a: tuple) -> tuple:
            while parent[a] != a:
                parent[a] = parent[parent[a]]
                a = parent[a]
            return a

        for b2 in BENDS:
            for b3 in BENDS:
                F[b2, b3] = self.balanced_with_free_limb(P, self.limb_sum(P, "2", b2) + self.limb_sum(P, "3", b3), E)
                labels, n = ndimage.label(F[b2, b3].reshape(self.shape), structure=np.ones((3, 3)))
                lab[b2, b3] = labels.ravel()
                parent.update({(b2, b3, k): (b2, b3, k) for k in range(1, n + 1)})
        u = np.column_stack([np.cos(a := np.linspace(-np.pi, np.pi, 1440, endpoint=False)), np.sin(a)])
        for straight, other in (("3", "2"), ("2", "3")):
            C = self.h[straight][None, :] + (2 * self.L - 1e-9) * u
            inner = self._cell(self.h[straight][None, :] + (2 * self.L - self.step) * u)
            for bo in BENDS:
                ok = self.balanced_with_free_limb(C, self.limb_sum(C, other, bo) + self.limb_sum(C, straight, 1), E)
                ka, kb = ((bo, 1), (bo, -1)) if straight == "3" else ((1, bo), (-1, bo))
                for i in inner[ok]:
                    if F[ka][i] and F[kb][i]:
                        parent[find((*ka, lab[ka][i]))] = find((*kb, lab[kb][i]))
        return F, lab, find

    def _cell(self, Q: np.ndarray) -> np.ndarray:
        i = np.clip(np.rint((Q[:, 0] - self.xs[0]) / self.step).astype(int), 0, len(self.xs) - 1)
        j = np.clip(np.rint((Q[:, 1] - self.zs[0]) / self.step).astype(int), 0, len(self.zs) - 1)
        return i * len(self.zs) + j

    def analyse(self) -> dict[str, object]:
        """Per bend of limb 3: the ``F_23`` components holding a release of hold 1 / a grab of hold 4."""
        F, lab, find = self.components_23()
        P, E = self.P, self.E["23"]
        out: dict[str, object] = {}
        for b3 in BENDS:
            for name, hold in (("release1", "1"), ("grab4", "4")):
                comps: set = set()
                for b1 in BENDS:
                    for b2 in BENDS:
                        com = (self.limb_sum(P, hold, b1) + self.limb_sum(P, "2", b2) + self.limb_sum(P, "3", b3)) / 6
                        cells = np.flatnonzero((com >= E[0]) & (com <= E[1]) & F[b2, b3])
                        comps |= {find((b2, b3, lab[b2, b3][i])) for i in cells}
                out[name, b3] = comps
        return out


def choice_matters(a: dict) -> bool:
    """Releasing hold 1 with one bend of limb 3 cannot reach a grab of hold 4, with the other bend it can."""
    grab4 = a["grab4", -1] | a["grab4", 1]
    return any(a["release1", -s] and not (a["release1", -s] & grab4) and a["release1", s] & grab4 for s in BENDS)


def main(layouts: int, seed: int, friction: tuple[float, float]) -> None:
    robot = RobotModel.load("planar-3limb")
    rng = np.random.default_rng(seed)
    counts = {"layouts": 0, "release and grab both possible": 0, "F_23 split between them": 0, "choice matters": 0}
    for _ in range(layouts):
        h2 = rng.uniform(0.0, 0.3, 2)
        a, r = rng.uniform(-np.pi, np.pi), rng.uniform(0.05, 0.6)
        h3 = h2 + r * np.array([np.cos(a), np.sin(a)])
        h1, h4 = h2 + rng.uniform(-0.7, 0.7, 2), h3 + rng.uniform(-0.7, 0.7, 2)
        holds = [(float(h[0]), float(h[1]), float(rng.uniform(-0.9, 0.9)), float(rng.uniform(*friction)))
                 for h in (h1, h2, h3, h4)]
        res = Layout(robot, holds).analyse()  # an empty support interval is NaN: no feasible cell
        counts["layouts"] += 1
        rel = res["release1", -1] | res["release1", 1]
        grab = res["grab4", -1] | res["grab4", 1]
        if rel and grab:
            counts["release and grab both possible"] += 1
            counts["F_23 split between them"] += len(rel | grab) >= 2
            counts["choice matters"] += choice_matters(res)
    print(counts)


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--layouts", type=int, default=1500)
    ap.add_argument("--seed", type=int, default=21)
    ap.add_argument("--friction", type=float, nargs=2, default=(0.2, 1.0))
    args = ap.parse_args()
    main(args.layouts, args.seed, tuple(args.friction))
