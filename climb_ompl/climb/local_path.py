"""The direct local path between two transitions of one stance (lift, move, place).

Bretl (2006), sec. 3.3.2: "a feasible path often exists between two feasible transitions"; PRM's local
planner applied to the query itself is tried before any sampling-based FIND-PATH.  The base and the free
limbs move linearly in joint space and each contact limb is re-closed on its hold by inverse kinematics (the
solution nearest the previous waypoint).  On 3-D walls the hand about to grab first lifts off the wall,
travels to above its new hold while the body moves, and comes down on it (Bretl, Latombe & Rock 2003,
sec. 3: lift the free hand, move it over, place it).  Variants: the lifted hand moved in joint space, body
first (the free limb frozen), hand first (body still), and through a few random via postures of the free limb
when the straight moves collide.  Waypoints are at most ``max_step`` apart in every coordinate and pass every
check of the stance (:meth:`Feasibility.valid_moving`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from climb_ompl.contract import MOTION_TOLERANCE
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.manifold.stance import Stance, hand_targets
from climb_ompl.model.wall_frame import wall_normal
from climb_ompl.settings import ClimbSettings

#: Halvings of an interval before a jump counts as a switch between inverse-kinematics branches.
REFINE_DEPTH = 4
#: Interpolation step of the joint-space lines, as a fraction of ``max_step``: the contact limbs re-closed
#: by inverse kinematics move a little more than the line, and an interval where they move more than
#: ``max_step`` is halved (docs/climb.md, "Settings and their defaults").
FOLLOW_STEP = 0.9


class LocalPath:
    """The direct local path (see the module docstring); call it with ``(stance, qa, qb, moving)``.

    Args:
        feas: the feasibility tests.
        max_step: largest joint change between waypoints (rad or m).
        lift: how far the moving hand lifts off the wall, metres (0 on planar robots).
        via_points: random via postures of the free limb tried when the straight moves fail.
        seed: seed of the via postures (with the call count: reproducible).
    """

    def __init__(self, feas: Feasibility, *, max_step: float = ClimbSettings.max_step, lift: float = ClimbSettings.lift,
                 via_points: int = ClimbSettings.via_points, seed: int = 0):
        self.feas, self.robot, self.terrain = feas, feas.robot, feas.terrain
        self.max_step, self.lift, self.via_points, self.seed = float(max_step), float(lift), int(via_points), int(seed)
        self.limbs = [lb.name for lb in self.robot.limbs]
        self.normal = wall_normal(self.terrain)
        #: calls and successes
        self.calls = self.found = 0
        #: failures by reason (``ik``, ``ik-lift``, ``ik-moving``, ``jump`` or a check's name)
        self.failures: dict[str, int] = {}

    @classmethod
    def of(cls, feas: Feasibility, settings: Any = None, *, seed: int = 0) -> LocalPath:
        """The local path of a climb with ``settings`` (default :class:`~climb_ompl.settings.ClimbSettings` ``()``;
        anything with ``max_step``, ``lift`` and ``via_points``, as :class:`~climb_ompl.climb.onestep.PathSettings`)."""
        s = settings if settings is not None else ClimbSettings()
        return cls(feas, max_step=s.max_step, lift=s.lift, via_points=s.via_points, seed=seed)

    def _fail(self, why: str) -> None:
        self.failures[why] = self.failures.get(why, 0) + 1

    def __call__(self, stance: Stance, qa: np.ndarray, qb: np.ndarray, moving: str | None) -> list[np.ndarray] | None:
        """The direct local path from ``qa`` to ``qb`` at ``stance`` (``moving``: the limb about to grab, or
        ``None``), or ``None`` if it is infeasible."""
        self.calls += 1
        path = self._plan(stance, np.asarray(qa, dtype=float), np.asarray(qb, dtype=float), moving)
        self.found += path is not None
        return path

    def _plan(self, stance: Stance, qa: np.ndarray, qb: np.ndarray, moving: str | None) -> list[np.ndarray] | None:
        """The base and the free limbs move linearly in joint
        space from ``qa`` to ``qb`` and each contact limb is re-closed on its hold by inverse kinematics
        (the solution nearest the previous waypoint).  On 3-D walls the hand of ``moving`` (the limb about
        to grab) first lifts ``lift`` metres off the wall, travels in a straight line to above its new
        hold while the body moves, and then comes down on it.  Waypoints are at most ``max_step`` apart
        in every coordinate and pass every check of the stance (joint limits, equilibrium, torque
        limits, collision, with a free hand allowed to touch the wall within
        :data:`~climb_ompl.contract.HAND_CONTACT_RADIUS` of a hold).
        """
        r = self.robot
        targets = hand_targets(r, self.terrain, stance)
        base = set(int(j) for j in r.base_indices)
        limbs = sorted(stance.limbs, key=lambda lb: (not set(r.limb(lb).joint_indices) & base, self.limbs.index(lb)))
        lift = self.lift if (moving is not None and not r.planar) else 0.0
        nrm = self.normal
        segments: list[tuple[np.ndarray, np.ndarray, np.ndarray | None, np.ndarray | None]] = []
        if lift > 0 and moving is not None:
            pa = np.asarray(r.hand_position(qa, moving), dtype=float)
            pb = np.asarray(r.hand_position(qb, moving), dtype=float)
            la, qa_up = self._lift(moving, qa, pa, nrm, lift)
            lb_, qb_up = self._lift(moving, qb, pb, nrm, lift)
            if qa_up is None or qb_up is None:
                self._fail("ik-lift")
                return None
            # lift straight off, move the lifted hand (in a straight line, else in joint space), come down;
            # or move the body first (the free limb's joints frozen, so the hand keeps its height off the
            # wall) and then the hand, or the hand first (body still) and then the body under it.  The joint-
            # space move comes second: it connects about a third of the steps whose straight hand line fails,
            # the body-first and hand-first moves about one in seventy (LEMUR on the suite's walls).
            up, down = (qa, qa, pa, pa + la), (qb, qb, pb + lb_, pb)
            variants = [[up, (qa_up, qb_up, pa + la, pb + lb_), down], [up, (qa_up, qb_up, None, None), down]]
            idx_m = np.array(r.limb(moving).joint_indices, dtype=int)
            q_body = qb_up.copy()
            q_body[idx_m] = qa_up[idx_m]
            h_body = np.asarray(r.hand_position(q_body, moving), dtype=float)
            variants.append([up, (qa_up, q_body, None, None), (q_body, qb_up, h_body, pb + lb_), down])
            q_hand = self.robot.limb_ik_nearest(moving, qa_up, pb + lb_, qa_up)
            if q_hand is not None:
                variants.append([up, (qa_up, q_hand, pa + la, pb + lb_), (q_hand, qb_up, pb + lb_, pb + lb_), down])
        else:
            variants = [[(qa, qb, None, None)]]
        for segments in variants:
            path = self._follow(stance, qa, qb, moving, limbs, targets, segments)
            if path is not None:
                return self._thin(stance, path)
        if lift > 0 and moving is not None and self.via_points > 0:
            # the free limb swings around an obstacle (often another limb): through a random via posture
            rng = np.random.default_rng([self.seed, self.calls])  # reproducible, no hash()
            r = self.robot
            idx = np.array(r.limb(moving).joint_indices, dtype=int)
            lo, hi = np.asarray(r.lower, dtype=float)[idx], np.asarray(r.upper, dtype=float)[idx]
            for _ in range(self.via_points):
                via = 0.5 * (qa_up + qb_up)
                via[idx] = rng.uniform(lo, hi)
                for lb in limbs:
                    via = self.robot.limb_ik_nearest(lb, via, targets[lb], 0.5 * (qa_up + qb_up))
                    if via is None:
                        break
                if via is None or not self.feas.valid_moving(stance, via):
                    continue
                segments = [(qa, qa, pa, pa + la), (qa_up, via, None, None), (via, qb_up, None, None),
                            (qb, qb, pb + lb_, pb)]
                path = self._follow(stance, qa, qb, moving, limbs, targets, segments)
                if path is not None:
                    return self._thin(stance, path)
        return None

    def _follow(self, stance: Any, qa: np.ndarray, qb: np.ndarray, moving: str | None, limbs: list[str],
                targets: dict[str, np.ndarray], segments: list[Any]) -> list[np.ndarray] | None:
        """Waypoints along ``segments`` (joint-space lines, the moving hand on a Cartesian line if given).

        Each waypoint re-closes the contact limbs (and places the moving hand) by inverse kinematics from
        the previous one.  Where the solution moves more than ``max_step`` in one interval (fast joint
        motion near a singular posture) the interval is halved, up to :data:`REFINE_DEPTH` times; a jump
        that survives the halvings is a switch between inverse-kinematics branches and fails the path.
        """
        out = [qa.copy()]
        prev = qa.copy()
        lim = self.max_step * (1 + 1e-9)
        for s_i, (q0, q1, h0, h1) in enumerate(segments):
            last_seg = s_i == len(segments) - 1
            span = float(np.max(np.abs(q1 - q0)))
            if h0 is not None and moving is not None:  # the joint travel of the straight hand motion
                q_end = self.robot.limb_ik_nearest(moving, q1, h1, q1 if last_seg else q0)
                if q_end is None:
                    self._fail("ik-lift")
                    return None
                span = max(span, 1.5 * float(np.max(np.abs(q_end - prev))))
            n = max(1, int(math.ceil(span / (FOLLOW_STEP * self.max_step))))
            t_prev = 0.0
            for k in range(1, n + 1):
                pending = [k / n]
                while pending:
                    t = pending[-1]
                    if last_seg and t == 1.0:
                        q = qb.copy()
                    else:
                        q = (1 - t) * q0 + t * q1
                        if h0 is not None and moving is not None:
                            q = self.robot.limb_ik_nearest(moving, q, (1 - t) * h0 + t * h1, prev)
                            if q is None:
                                self._fail("ik-moving")
                                return None
                        for lb in limbs:
                            q = self.robot.limb_ik_nearest(lb, q, targets[lb], prev)
                            if q is None:
                                self._fail("ik")
                                return None
                    if float(np.max(np.abs(q - prev))) > lim:
                        if (t - t_prev) * n * 2 ** REFINE_DEPTH <= 1.0 + 1e-9:
                            self._fail("jump")
                            return None  # a jump between IK branches
                        pending.append(0.5 * (t_prev + t))
                        continue
                    if not (last_seg and t == 1.0):  # (qb is a transition, checked when it was found)
                        bad = self.feas.why_moving(stance, q)
                        if bad is not None:
                            self._fail(bad)
                            return None
                    out.append(q)
                    prev, t_prev = q, t
                    pending.pop()
        return out

    def _lift(self, limb: str, q: np.ndarray, p: np.ndarray, nrm: np.ndarray, lift: float) -> tuple[np.ndarray,
                                                                                                     np.ndarray | None]:
        """The hand's lift-off offset (off the wall, possibly leaning towards or away from the body) and its IK."""
        import pinocchio as pin

        r = self.robot
        lbm = r.limb(limb)
        pin.forwardKinematics(r.model, r.data, q)
        sh = np.asarray(r.data.oMi[lbm.joint_ids[0]].translation, dtype=float) if lbm.joint_ids else p
        radial = (p - sh) - ((p - sh) @ nrm) * nrm
        radial = radial / np.linalg.norm(radial) if np.linalg.norm(radial) > 1e-9 else np.zeros(3)
        for d in (nrm, nrm - 0.7 * radial, nrm + 0.7 * radial, nrm - 1.5 * radial):
            off = lift * d / np.linalg.norm(d)
            sol = self.robot.limb_ik_nearest(limb, q, p + off, q)
            if sol is not None and float(np.max(np.abs(sol - q))) < 1.0:
                return off, sol
        return nrm * lift, None

    def _thin(self, stance: Stance, qs: list[np.ndarray]) -> list[np.ndarray]:
        r = self.robot
        targets = list(hand_targets(r, self.terrain, stance).items())
        out = [qs[0]]
        i = 0
        while i < len(qs) - 1:
            j = i + 1
            while j + 1 < len(qs) and float(np.max(np.abs(qs[j + 1] - qs[i]))) <= self.max_step:
                mid = 0.5 * (qs[i] + qs[j + 1])
                err = max(float(np.linalg.norm(r.hand_position(mid, lb) - p)) for lb, p in targets)
                if err > 0.2 * MOTION_TOLERANCE:
                    break
                j += 1
            out.append(qs[j])
            i = j
        return out


__all__ = ["LocalPath", "REFINE_DEPTH", "FOLLOW_STEP"]
