"""Compiled loops of FIND-TRANSITION's batch prefilters (numba, cached on disk).

FIND-TRANSITION (:mod:`climb_ompl.climb.transition`) tests its base draws in chunks before any inverse kinematics: the
pose
of the body carrying the limbs (:meth:`climb_ompl.model.base_pose.BasePose.poses`), every hand target within its limb's
reach map (:meth:`climb_ompl.model.reach.ShouldersReach.many`) and the CoM's distance outside the support region
(:meth:`climb_ompl.equilibrium.region.SupportRegion.outside_many`, whose loop is in
:mod:`climb_ompl.equilibrium._kernels`).  On NumPy arrays each test would be a few dozen array calls per chunk,
whatever the chunk's size (what that cost: docs/climb.md).  These loops do the same arithmetic, in the same order,
one draw at a time; those functions call them.  Their one-draw-at-a-time counterparts (:meth:`ShouldersReach.__call__`,
:meth:`SupportRegion.outside_by_more_than`, Pinocchio's forward kinematics) are the tests' oracles.

The first call compiles them (a few seconds, once per machine: ``cache=True`` writes the machine code next to this
file); later processes load it.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: :func:`poses` step kinds: a fixed placement, a prismatic joint, a revolute joint.
PLACE, PRISMATIC, REVOLUTE = 0, 1, 2


@njit(cache=True)
def poses(X: np.ndarray, kinds: np.ndarray, mats: np.ndarray, vecs: np.ndarray,
          cols: np.ndarray) -> tuple[np.ndarray, np.ndarray]:  # pragma: no cover - compiled
    """Rotations ``(k, 3, 3)`` and positions ``(k, 3)`` of a chain of steps for the coordinates ``X`` ``(k, n)``:
    step ``s`` is a placement (``mats[s]``, ``vecs[s]``), a prismatic joint along ``vecs[s]`` or a revolute joint
    about ``vecs[s]`` (Rodrigues' formula; ``mats[s]`` holds ``K K``, ``K`` the axis's cross-product matrix), moved by
    ``X[:, cols[s]]``."""
    k = X.shape[0]
    R_out = np.empty((k, 3, 3))
    p_out = np.empty((k, 3))
    R = np.empty((3, 3))
    tmp = np.empty((3, 3))
    rot = np.empty((3, 3))
    kk = np.empty((3, 3))
    p = np.empty(3)
    for i in range(k):
        for a in range(3):
            p[a] = 0.0
            for b in range(3):
                R[a, b] = 1.0 if a == b else 0.0
        for s in range(kinds.shape[0]):
            kind = kinds[s]
            if kind == PLACE or kind == PRISMATIC:
                x = 1.0 if kind == PLACE else X[i, cols[s]]
                for a in range(3):
                    p[a] = p[a] + (R[a, 0] * vecs[s, 0] + R[a, 1] * vecs[s, 1] + R[a, 2] * vecs[s, 2]) * x
                if kind == PLACE:
                    for a in range(3):
                        for b in range(3):
                            tmp[a, b] = R[a, 0] * mats[s, 0, b] + R[a, 1] * mats[s, 1, b] + R[a, 2] * mats[s, 2, b]
                    R[:, :] = tmp
            else:
                ux, uy, uz = vecs[s, 0], vecs[s, 1], vecs[s, 2]
                kk[0, 0], kk[0, 1], kk[0, 2] = 0.0, -uz, uy
                kk[1, 0], kk[1, 1], kk[1, 2] = uz, 0.0, -ux
                kk[2, 0], kk[2, 1], kk[2, 2] = -uy, ux, 0.0
                sn, cs = math.sin(X[i, cols[s]]), math.cos(X[i, cols[s]])
                # I + sin K + (1 - cos) K K, K the cross-product matrix of the unit axis (K K in mats[s])
                for a in range(3):
                    for b in range(3):
                        rot[a, b] = (1.0 if a == b else 0.0) + sn * kk[a, b] + (1.0 - cs) * mats[s, a, b]
                for a in range(3):
                    for b in range(3):
                        tmp[a, b] = R[a, 0] * rot[0, b] + R[a, 1] * rot[1, b] + R[a, 2] * rot[2, b]
                R[:, :] = tmp
        R_out[i] = R
        p_out[i] = p
    return R_out, p_out


@njit(cache=True)
def within_reach(R: np.ndarray, t: np.ndarray, P: np.ndarray, OFF: np.ndarray, A1: np.ndarray, A2: np.ndarray,
                 A3: np.ndarray, D0: np.ndarray, DD: np.ndarray, REACH2: np.ndarray, LIM: np.ndarray,
                 NPL: np.ndarray, NDIR: np.ndarray) -> np.ndarray:  # pragma: no cover - compiled
    """Per pose ``(R[i], t[i])`` of the carrying frame, whether every target ``P[l]`` lies within its limb's reach map
    (the arithmetic of :meth:`climb_ompl.model.reach.ShouldersReach.__call__`, one row ``l`` per limb)."""
    k, n = t.shape[0], P.shape[0]
    out = np.ones(k, dtype=np.bool_)
    two_pi = 2.0 * math.pi
    for i in range(k):
        for m in range(n):
            dx, dy, dz = P[m, 0] - t[i, 0], P[m, 1] - t[i, 1], P[m, 2] - t[i, 2]
            lx = dx * R[i, 0, 0] + dy * R[i, 1, 0] + dz * R[i, 2, 0] - OFF[m, 0]
            ly = dx * R[i, 0, 1] + dy * R[i, 1, 1] + dz * R[i, 2, 1] - OFF[m, 1]
            lz = dx * R[i, 0, 2] + dy * R[i, 1, 2] + dz * R[i, 2, 2] - OFF[m, 2]
            j = int(math.floor((lx * A3[m, 0] + ly * A3[m, 1] + lz * A3[m, 2] - D0[m]) / DD[m]))
            if j + 1 >= NPL[m]:
                out[i] = False  # deeper than the reach on the hand's side
                break
            if j < 0:  # on the other side of the joint: within the limb's reach of it
                if lx * lx + ly * ly + lz * lz > REACH2[m]:
                    out[i] = False
                    break
                continue
            x = lx * A1[m, 0] + ly * A1[m, 1] + lz * A1[m, 2]
            y = lx * A2[m, 0] + ly * A2[m, 1] + lz * A2[m, 2]
            nd = NDIR[m]
            kk = int(np.rint((math.atan2(y, x) % two_pi) / two_pi * nd)) % nd
            if math.hypot(x, y) > max(LIM[m, j, kk], LIM[m, j + 1, kk]):
                out[i] = False
                break
    return out


__all__ = ["poses", "within_reach", "PLACE", "PRISMATIC", "REVOLUTE"]
