"""Steps from a stance to the nearest of several target stances: the heuristic of a search whose goal is a set of
stances (:class:`climb_ompl.climb.goal.Goal` ``"stances"``, where a re-plan rejoins the route of the plan it repairs,
:mod:`climb_ompl.climb.replan`).

For one target, a release and a grab per limb on another hold (one of them when the limb is free on one side),
plus the strides its hand travels: ``2 d / stride`` from the limb's hold, or its last hold while free, to the
target's (each limb needs about one release and one grab per stride, as in the height heuristic of
:mod:`climb_ompl.climb.search`).  A rejoining search evaluates it for every target at every stance it meets (tens of
targets: the stances of the rest of the old route), so the targets are laid out once as arrays.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import numpy as np

from climb_ompl.model.terrain import Terrain


class StanceGap:
    """The estimated steps from a stance to the nearest of ``targets``.

    Args:
        terrain: the terrain of the holds.
        limbs: the robot's limb names.
        targets: target stances, each as ``(limb, hold)`` pairs.
        stride: height a hand gains per grab, m (the search's stride).
    """

    def __init__(self, terrain: Terrain, limbs: Sequence[str], targets: Sequence[Sequence[tuple[str, str]]],
                 stride: float):
        self.limbs = list(limbs)
        self._col = {lb: i for i, lb in enumerate(self.limbs)}
        self._index = terrain.hold_index
        self._positions = terrain.positions
        want = np.full((len(targets), len(self.limbs)), -1, dtype=int)
        for t, target in enumerate(targets):
            for limb, hold in target:
                want[t, self._col[limb]] = self._index[hold]
        self._want = want
        self._wants = want >= 0
        self._at = self._positions[np.maximum(want, 0)]  # (targets, limbs, 3): the target holds' positions
        self._per_metre = 2.0 / max(float(stride), 1e-9)

    def _holds(self, pairs: Mapping[str, str]) -> np.ndarray:
        out = np.full(len(self.limbs), -1, dtype=int)
        for limb, hold in pairs.items():
            out[self._col[limb]] = self._index[hold]
        return out

    def __call__(self, stance: Mapping[str, str], where: Mapping[str, str]) -> float:
        """Steps from ``stance`` to the nearest target (``where``: each limb's hold, or its last one while free)."""
        if not len(self._want):
            return float("inf")
        have, last = self._holds(stance), self._holds(where)
        other = self._want != have  # (targets, limbs): limbs to move
        steps = other * ((have >= 0).astype(float) + self._wants)
        travel = other & self._wants & (last >= 0)
        d = np.linalg.norm(self._at - self._positions[np.maximum(last, 0)], axis=2)
        return float((steps + np.where(travel, self._per_metre * d, 0.0)).sum(axis=1).min())


__all__ = ["StanceGap"]
