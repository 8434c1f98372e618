"""The pose of the body the limbs hang from, for many base configurations at once.

FIND-TRANSITION (:mod:`climb_ompl.climb.transition`) draws the base about a reference configuration and tests each draw
against cheap necessary conditions before any inverse kinematics: every hand target within its limb's reach map
(:class:`climb_ompl.model.reach.ShouldersReach`) and the CoM near the support region.  Both depend on the draw only
through
the pose of the body carrying the limbs' first joints (the CoM too when only the base moves: the limbs keep their
joints).  Computed one draw at a time, each test costs a forward kinematics and Python arithmetic (docs/climb.md
says how much of FIND-TRANSITION's time that was); here the pose of a whole batch of draws is composed from the
joints between the world and that body, in compiled code (:mod:`climb_ompl.model.draw_kernels`).

Supported: a chain of one-coordinate joints (prismatic or revolute about any axis: a spec's ``base.joints``), or a
composite joint made of them (the ``planar`` and ``spatial`` bases :mod:`climb_ompl.model.spec` builds), each
pose the product of its joints' placements and motions (Pinocchio's convention, also inside a composite joint).
:meth:`BasePose.of` checks the composition against Pinocchio's forward kinematics at a few configurations and gives
``None`` for anything else (a free-flyer, a spherical joint), where the callers test the draws one at a time.
"""

from __future__ import annotations

from typing import Any

import numpy as np

from climb_ompl.model.joints import elementary as _elementary

#: Largest difference from Pinocchio's forward kinematics accepted by :meth:`BasePose.of` (metres and rotation
#: matrix entries).
CHECK_TOLERANCE = 1e-9


def _cross(axis: np.ndarray) -> np.ndarray:
    """The cross-product matrix ``K`` of ``axis`` (``K v = axis x v``)."""
    x, y, z = (float(v) for v in axis)
    return np.array([[0.0, -z, y], [z, 0.0, -x], [-y, x, 0.0]])


class BasePose:
    """The world pose of joint ``jid``'s frame as a function of the configuration coordinates that move it.

    Attributes:
        jid: the joint whose frame (Pinocchio's ``oMi[jid]``) is computed.
        coords: the coordinates (indices into ``q``) that move it, in the order :meth:`poses` reads them.
        steps: per joint from the world to ``jid``, its placement ``(R, p)`` then its motion
            ``(kind, axis, column of coords)``.
    """

    def __init__(self, jid: int, coords: list[int], steps: list[tuple[Any, ...]]):
        self.jid, self.coords, self.steps = jid, np.asarray(coords, dtype=int), steps

    @classmethod
    def of(cls, robot: Any, jid: int) -> "BasePose | None":
        """The pose of joint ``jid``'s frame for ``robot``, or ``None`` when a joint between the world and it is not
        supported (see the module docstring) or the composition differs from Pinocchio's forward kinematics."""
        m = robot.model
        chain = []
        j = int(jid)
        while j > 0:
            chain.append(j)
            j = int(m.parents[j])
        if not chain:
            return None
        steps: list[tuple[Any, ...]] = []
        coords: list[int] = []
        for j in reversed(chain):
            jm = m.joints[j]
            place = m.jointPlacements[j]
            steps.append(("place", np.asarray(place.rotation, dtype=float), np.asarray(place.translation, dtype=float)))
            if jm.shortname() == "JointModelComposite":  # its joints in turn, each placed in the one before
                comp = jm.extract()
                parts = [(sub, comp.jointPlacements[k], int(sub.idx_q))  # (its own place in q, in a model)
                         for k, sub in enumerate(comp.joints)]
            else:
                parts = [(jm, None, int(jm.idx_q))]
            for sub, pl, iq in parts:
                kind = _elementary(sub)
                if kind is None or sub.nq != 1:
                    return None
                if pl is not None:
                    steps.append(("place", np.asarray(pl.rotation, dtype=float), np.asarray(pl.translation,
                                                                                            dtype=float)))
                steps.append((kind[0], kind[1], len(coords)))
                coords.append(iq)
        # consecutive placements as one; identity placements left out
        merged: list[tuple[Any, ...]] = []
        for st in steps:
            if st[0] == "place" and merged and merged[-1][0] == "place":
                _, R0, p0 = merged.pop()
                st = ("place", R0 @ st[1], p0 + R0 @ st[2])
            merged.append(st)
        steps = [st for st in merged if not (st[0] == "place" and np.array_equal(st[1], np.eye(3))
                                              and not np.any(st[2]))]
        out = cls(int(jid), coords, steps)
        return out if out._agrees(robot) else None

    def carries_mass(self, robot: Any) -> bool:
        """Whether every body with mass is ``jid``'s or hangs from it: then the CoM is ``jid``'s pose applied to the
        CoM in its frame, which only the joints below it change (:meth:`com_local`)."""
        m = robot.model
        for j in range(m.njoints):
            a = j
            while a > 0 and a != self.jid:
                a = int(m.parents[a])
            if a != self.jid and float(m.inertias[j].mass) > 0.0:
                return False
        return True

    def com_local(self, robot: Any, q: np.ndarray) -> np.ndarray:
        """The CoM at ``q`` in ``jid``'s frame (see :meth:`carries_mass`)."""
        import pinocchio as pin

        c = np.asarray(pin.centerOfMass(robot.model, robot.data, np.asarray(q, dtype=float), False), dtype=float)
        f = robot.data.oMi[self.jid]  # (centerOfMass ran the forward kinematics)
        return np.asarray(f.rotation, dtype=float).T @ (c - np.asarray(f.translation, dtype=float))

    def _agrees(self, robot: Any) -> bool:
        """Whether :meth:`poses` matches Pinocchio's ``oMi[jid]`` at the nominal configuration and a few draws
        about it."""
        import pinocchio as pin

        rng = np.random.default_rng(0)
        q0 = np.asarray(robot.nominal_q, dtype=float)
        qs = [q0] + [q0 + rng.normal(0.0, 0.3, len(q0)) for _ in range(3)]
        R, p = self.poses(np.array([q[self.coords] for q in qs]))
        for i, q in enumerate(qs):
            pin.forwardKinematics(robot.model, robot.data, q)
            f = robot.data.oMi[self.jid]
            if (np.abs(R[i] - np.asarray(f.rotation)).max() > CHECK_TOLERANCE
                    or np.abs(p[i] - np.asarray(f.translation)).max() > CHECK_TOLERANCE):
                return False
        return True

    def poses(self, X: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The frame's rotations ``(k, 3, 3)`` and positions ``(k, 3)`` for the coordinates ``X``
        ``(k, len(coords))`` (the steps composed in turn, one draw at a time, in compiled code:
        :func:`climb_ompl.model.draw_kernels.poses`)."""
        from climb_ompl.model.draw_kernels import poses

        return poses(np.ascontiguousarray(X, dtype=float), *self._arrays())

    def _arrays(self) -> tuple[np.ndarray, ...]:
        """:attr:`steps` as the arrays of :func:`climb_ompl.model.draw_kernels.poses` (built once)."""
        arr = getattr(self, "_steps_arrays", None)
        if arr is None:
            from climb_ompl.model.draw_kernels import PLACE, PRISMATIC, REVOLUTE

            n = len(self.steps)
            kinds, cols = np.zeros(n, dtype=np.int64), np.zeros(n, dtype=np.int64)
            mats, vecs = np.zeros((n, 3, 3)), np.zeros((n, 3))
            for s, step in enumerate(self.steps):
                if step[0] == "place":
                    kinds[s], mats[s], vecs[s] = PLACE, step[1], step[2]
                else:
                    kinds[s], vecs[s], cols[s] = (PRISMATIC if step[0] == "P" else REVOLUTE), step[1], step[2]
                    if step[0] == "R":
                        mats[s] = _cross(step[1]) @ _cross(step[1])
            arr = self._steps_arrays = (kinds, mats, vecs, cols)
        return arr


__all__ = ["BasePose", "CHECK_TOLERANCE"]
