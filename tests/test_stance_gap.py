"""The heuristic of a goal made of stances (:class:`climb_ompl.climb.stance_gap.StanceGap`) against a limb-by-limb count
written out here: per target, a release and a grab for each limb on another hold, plus two steps per stride its
hand travels; the nearest target counts."""

from __future__ import annotations

import math

import numpy as np
import pytest

from climb_ompl.climb.stance_gap import StanceGap
from climb_ompl.manifold.stance import Stance
from climb_ompl.model.terrain import Terrain

LIMBS = ("a", "b", "c", "d")


def _by_hand(terrain, stance, where, targets, stride):
    best = math.inf
    for target in targets:
        want, h = dict(target), 0.0
        for limb in LIMBS:
            if want.get(limb) == stance.get(limb):
                continue
            h += (limb in stance) + (limb in want)
            if limb in want and limb in where:
                h += 2.0 * math.dist(terrain.hold(where[limb]).position, terrain.hold(want[limb]).position) / stride
        best = min(best, h)
    return best


def test_matches_a_limb_by_limb_count_on_random_stances():
    wall = Terrain.load("demo-wall")
    ids = list(wall.hold_ids)
    rng = np.random.default_rng(3)

    def stance(n):
        holds = rng.choice(ids, size=n, replace=False)
        return Stance(dict(zip(rng.choice(LIMBS, size=n, replace=False), holds, strict=True)))

    targets = [tuple(sorted(stance(int(rng.integers(3, 5))).pairs)) for _ in range(12)]
    gap = StanceGap(wall, LIMBS, targets, stride=0.3)
    for _ in range(200):
        s = stance(int(rng.integers(2, 5)))
        free = [lb for lb in LIMBS if lb not in s]
        where = {**{lb: str(rng.choice(ids)) for lb in free if rng.random() < 0.7}, **dict(s.pairs)}
        assert gap(s, where) == pytest.approx(_by_hand(wall, s, where, targets, 0.3), abs=1e-9)


def test_a_target_stance_is_zero_steps_away_and_one_limb_off_is_a_release_and_a_grab_away():
    wall = Terrain.load("demo-wall")
    a, b, c, d, e = wall.hold_ids[:5]
    target = (("a", a), ("b", b), ("c", c))
    gap = StanceGap(wall, LIMBS, [target], stride=0.3)
    assert gap(Stance(dict(target)), dict(target)) == 0.0
    moved = Stance({"a": a, "b": b, "c": d})
    far = 2.0 * float(np.linalg.norm(wall.hold(d).p - wall.hold(c).p)) / 0.3
    assert gap(moved, dict(moved)) == pytest.approx(2.0 + far)  # release c from d, grab c
    assert StanceGap(wall, LIMBS, [], stride=0.3)(moved, dict(moved)) == math.inf
    assert gap(Stance({"a": a, "b": b, "c": c, "d": e}), {}) == 1.0  # only d's release
