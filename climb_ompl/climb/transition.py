"""FIND-TRANSITION (Bretl 2006, Fig. 17): a configuration feasible at two adjacent stances.

This is the one implementation, used by the start finder (:func:`climb_ompl.climb.start.start_configuration`), the
one-step API (:func:`climb_ompl.climb.onestep.find_transition`), the benchmark query generator and the stance-graph
search.

Bretl (2006), Fig. 17 lines 1-5, samples the pelvis position, closes every contact chain analytically for
each combination of elbow bends, and keeps the first sample in equilibrium (appendix C).  Here the base
coordinates are drawn around a reference configuration ``near`` (half of the draws shifted towards the
centre of the smaller stance's support region through the CoM's Jacobian with respect to the base), each
contact limb of the larger stance is closed by :meth:`RobotModel.limb_ik_nearest`, the solution nearest ``near``
(:meth:`RobotModel.limb_ik`, every solution, with ``elbow_bends="enumerate"``; base-moving limbs first), and
the first draw passing the transition checks of :meth:`Feasibility.transition_checks` is returned; the draws,
the closures and the shift are the kernel's (:class:`climb_ompl.manifold.closure.DrawClose`,
:func:`~climb_ompl.manifold.closure.com_shift`).  The
elbow bends are either kept from ``near`` (``elbow_bends="keep"``: the search stays in the component of the
node it expands, Bretl 2006 sec. 4.2.3) or every combination is tried at each draw
(``elbow_bends="enumerate"``, as in Fig. 17 line 3).  With ``keep``, the hand about to grab also takes its own
bend at ``near`` when a solution with it exists, the other bend only when none does: a grab whose elbow flips
must swing the limb through straight, which the direct local path often finds no room for (LEMUR's limbs move
in one plane and cross each other), and stage 2 then spends FIND-PATH calls on it (docs/climb.md).  Cheap necessary
conditions cut draws before the inverse kinematics: each hold within its limb's reach map
(:mod:`climb_ompl.model.reach`)
and the CoM not far outside the support region (the limbs as at ``near``: within :data:`CLOSURE_SLACK`, a
measured bound, to be closed), tested on chunks of draws at once (:meth:`TransitionFinder._draws`).  A call gives
up when none of its first :data:`REACH_PATIENCE` draws has every hold within reach, or none of its first
:data:`COM_PATIENCE` draws within reach has the CoM near the region (within ``com_slack``).
"""

from __future__ import annotations

import itertools
import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from climb_ompl.contract import TOLERANCE
from climb_ompl.manifold.closure import DrawClose, closest_com, com_shift
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.manifold.stance import Stance, hand_targets
from climb_ompl.model.base_pose import BasePose
from climb_ompl.model.reach import ShouldersReach, reach_maps, shoulders
from climb_ompl.model.terrain import Terrain
from climb_ompl.model.wall_frame import wall_normal
from climb_ompl.settings import ClimbSettings

#: Largest number of elbow-bend combinations tried at one base draw (``elbow_bends="enumerate"``).
MAX_BEND_COMBINATIONS = 16

#: Base draws after which a call gives up when none has put every hold within its limb's reach map (the setting
#: ``reach_patience``; the measurements behind the default: docs/climb.md, "Settings and their defaults").
REACH_PATIENCE: int = ClimbSettings.reach_patience  # 60

#: Draws within reach after which a call gives up when none has put the CoM within ``com_slack`` of the support
#: region (the setting ``com_patience``).  Every other draw is shifted towards the region's centre (by the CoM's
#: Jacobian), so a call that succeeds has one of its first draws near the region (docs/climb.md).
COM_PATIENCE: int = ClimbSettings.com_patience  # 12

#: Of the draws within ``com_slack`` of the support region, only those whose CoM (limbs as in the reference
#: configuration) lies at most this far outside it are closed by inverse kinematics and checked, metres (the setting
#: ``closure_slack``); the others still count as near the region for :data:`COM_PATIENCE` and as tries for
#: ``ik_tries``, so a call draws and stops as if it had closed them.  Closing the chains moves the CoM a little; how
#: far the draws that became transitions lay outside is in docs/climb.md.
CLOSURE_SLACK: float | None = ClimbSettings.closure_slack  # 0.02

#: Wide draws (:meth:`TransitionFinder._wide`): the smallest stand-off drawn, as a fraction of the nominal posture's,
#: and the spread of the other base translations, metres (twice that in radians for the angles).
WIDE_STANDOFF = 0.4
WIDE_SD = 0.1

#: Where a draw's CoM (limbs as in the reference configuration) lies (:meth:`TransitionFinder._draws`): within
#: ``closure_slack`` of the support region, farther out but within ``com_slack``, farther out than that.
CLOSE, OUTSIDE, FAR = 0, 1, 2


@dataclass
class _Call:
    """The state of one :meth:`TransitionFinder.find` call.

    Attributes:
        big, small: the larger and the smaller stance.
        near: the reference configuration.
        kernel: the draws and closures of ``big``'s chains (:class:`~climb_ompl.manifold.closure.DrawClose`).
        limbs: the limbs closed, in order (base-moving limbs first; a limb whose closure failed moves up to just after
            them when ``reorder``).
        on_hold: the limbs of ``big`` whose hands are on their holds at ``near``.
        keep: the limbs whose elbow bend is kept (``elbow_bends="keep"``: ``on_hold``).
        grabbing: the hand about to grab, if any (its own bend first).
        region: the smaller stance's support region (``None`` for a robot without equilibrium condition).
        reorder: whether a failed limb moves up (the limbs close independently, :meth:`TransitionFinder._pose`).
        fixed: the number of base-moving limbs (they stay first).
        checks: the transition checks, built at the first closure (most calls that fail close no chain).
        shifts: :func:`~climb_ompl.manifold.closure.com_shift` about ``near``, once computed.
    """

    big: Stance
    small: Stance
    near: np.ndarray
    kernel: DrawClose
    limbs: list[str]
    on_hold: set[str]
    keep: set[str]
    grabbing: str | None
    region: Any
    reorder: bool
    fixed: int
    checks: list[Any] = field(default_factory=list)
    shifts: list[np.ndarray] = field(default_factory=list)

    def shift(self) -> np.ndarray:
        """:func:`~climb_ompl.manifold.closure.com_shift` about ``near``, computed when a draw first moves the base (a
        call whose first draw, ``near`` closed, is a transition needs none)."""
        if not self.shifts:
            base = self.kernel.base
            self.shifts.append(com_shift(self.kernel.robot, self.region, self.near, base)
                               if self.region is not None and len(base) and len(self.region.vertices)
                               else np.zeros(len(base)))
        return self.shifts[0]


class TransitionFinder:
    """FIND-TRANSITION for one robot on one terrain (see the module docstring).

    Args:
        feas: the feasibility tests (robot, terrain, margin, cone model, clearance).
        attempts: base draws per call.
        ik_tries: of those, at most this many reach the inverse kinematics.
        com_slack: skip a draw whose CoM lies farther than this outside the support region, metres.
        elbow_bends: ``keep`` or ``enumerate``.
        tolerance: hands-on-holds tolerance, metres.
        wide: when the draws about ``near`` find nothing, this many more drawn about the nominal posture on the
            holds, crouched towards the wall (:meth:`_wide`; 0: none).
        walk: when those find nothing either, a walk of at most this many steps of the base towards the smaller
            stance's support region (:meth:`walk`; 0: none).
        reach_patience, com_patience: give up after this many draws none of which has every hold within reach,
            or this many draws within reach none of which has the CoM within ``com_slack`` of the support region
            (:data:`REACH_PATIENCE`, :data:`COM_PATIENCE`; 0: draw all ``attempts``).
        closure_slack: close only the draws whose CoM lies at most this far outside the support region
            (:data:`CLOSURE_SLACK`; ``None``, or more than ``com_slack``: every draw within ``com_slack``).  Not
            applied to the wide draws, whose limbs move farther as they close.
        base_draws: ``near`` (draws about the reference configuration) or ``holds`` (every draw about the nominal
            posture on the holds, within one limb reach of them: :meth:`_wide` with a ``radius``; the setting
            ``transition_base``).
    """

    def __init__(self, feas: Feasibility, *, attempts: int = 150, ik_tries: int = 60, com_slack: float = 0.05,
                 elbow_bends: str = "keep", tolerance: float = TOLERANCE, wide: int = 0, walk: int = 0,
                 reach_patience: int = REACH_PATIENCE, com_patience: int = COM_PATIENCE,
                 closure_slack: float | None = CLOSURE_SLACK, base_draws: str = "near"):
        self.feas, self.robot, self.terrain = feas, feas.robot, feas.terrain
        self.attempts, self.ik_tries, self.com_slack = int(attempts), int(ik_tries), float(com_slack)
        self.elbow_bends, self.tolerance, self.wide = elbow_bends, float(tolerance), int(wide)
        self.walk_steps, self.base_draws = int(walk), base_draws
        self.reach_patience, self.com_patience = int(reach_patience), int(com_patience)
        self.closure_slack = self.com_slack if closure_slack is None else min(float(closure_slack), self.com_slack)
        r = self.robot
        self._li = {lb.name: i for i, lb in enumerate(r.limbs)}
        self.base = np.array(r.base_indices, dtype=int)
        self._base_set = frozenset(self.base.tolist())
        self.lo, self.hi = np.asarray(r.lower, dtype=float), np.asarray(r.upper, dtype=float)
        #: draws that failed, by reason (``ik`` or a check's name)
        self.failures: dict[str, int] = {}
        #: ``(draw index of the success or -1, IK tries, base draws made)`` per call
        self.stats: list[tuple[int, int, int]] = []
        self._maps: dict[int, Any] | None = None  # reach maps, looked up once (they depend on robot and wall)
        self._base_pose: tuple[BasePose | None] | None = None  # (:meth:`_pose`, once looked up)

    @classmethod
    def of(cls, feas: Feasibility, settings: ClimbSettings | None = None, **changes: Any) -> TransitionFinder:
        """The finder a climb with ``settings`` (default: :class:`~climb_ompl.settings.ClimbSettings` ``()``) uses, with
        ``changes`` (e.g. ``attempts=300``): every FIND-TRANSITION setting read in one place."""
        s = settings if settings is not None else ClimbSettings()
        kw = dict(attempts=s.transition_attempts, ik_tries=s.ik_tries, com_slack=s.com_slack,
                  closure_slack=s.closure_slack, elbow_bends=s.elbow_bends, tolerance=s.tolerance,
                  wide=s.transition_wide, walk=s.transition_walk, reach_patience=s.reach_patience,
                  com_patience=s.com_patience, base_draws=s.transition_base)
        return cls(feas, **{**kw, **changes})

    def _fail(self, why: str) -> None:
        self.failures[why] = self.failures.get(why, 0) + 1

    def _call(self, sigma: Stance, nxt: Stance, near: np.ndarray) -> _Call | None:
        """The state of a call between ``sigma`` and ``nxt`` about ``near``; ``None`` when the smaller stance's
        support region is empty (no transition)."""
        r = self.robot
        big, small = (sigma, nxt) if len(sigma) >= len(nxt) else (nxt, sigma)
        region = self.feas.region(small) if r.equilibrium else None
        if region is not None and region.is_empty:
            return None
        kernel = DrawClose.of(r, self.terrain, big)  # where each hand frame touches its hold
        hands = np.asarray(r.hand_positions(near), dtype=float)
        on_hold = {lb for lb in big.limbs
                   if float(np.linalg.norm(hands[self._li[lb]] - kernel.targets[lb])) <= 0.5 * self.tolerance}
        limbs = r.closing_order(big.limbs, on_hold)
        keep = self.elbow_bends == "keep"
        # the limb whose closure failed goes first at the next draw (failures repeat from draw to draw): the same
        # closures, in fewer inverse-kinematics calls, where the limbs close independently (one solution each,
        # every limb hanging from the one body the base coordinates place; base-moving limbs stay first)
        return _Call(big, small, near, kernel, limbs, on_hold, on_hold if keep else set(),
                     next((lb for lb in nxt.limbs if lb not in sigma), None), region,
                     keep and self._pose() is not None, sum(1 for lb in limbs if r.moves_base(lb)))

    def _closed(self, call: _Call, q: np.ndarray, first: bool) -> np.ndarray | None:
        """The first closure of ``q``'s chains passing the transition checks (``first``: the hands on their holds
        stay: the base has not moved); with ``elbow_bends="keep"`` the solution nearest ``near`` per limb (only the
        bend of ``near`` for the hands on hold, the grabbing hand's bend first), with ``enumerate`` every
        combination of bends, nearest first, at most :data:`MAX_BEND_COMBINATIONS`."""
        k, big = call.kernel, call.big
        todo = [lb for lb in call.limbs if not (first and lb in call.on_hold)]  # base unmoved: hand still on
        if self.elbow_bends == "keep":
            qk = k.close(q, call.near, limbs=todo, keep=call.keep, prefer=call.grabbing)
            if qk is None:
                self._fail("ik")
            candidates: Any = [] if qk is None else [qk]
        else:
            k.failed = None
            candidates = itertools.islice(k.combinations(q, call.near, todo, lambda lb: self._fail("ik")),
                                          MAX_BEND_COMBINATIONS)
        for qc in candidates:
            hands_c = self.robot.hand_positions(qc)
            err_h = max(float(np.linalg.norm(hands_c[self._li[lb]] - k.targets[lb])) for lb in big.limbs)
            if err_h > 0.5 * self.tolerance:
                self._fail("ik")
                continue
            if not call.checks:
                call.checks.extend(self.feas.transition_checks(call.small, big))
            bad = self.feas.why(call.checks, qc)
            if bad is None:
                return qc
            self._fail(bad)
        if call.reorder and k.failed is not None and call.limbs.index(k.failed) > call.fixed:
            call.limbs.remove(k.failed)
            call.limbs.insert(call.fixed, k.failed)
        return None

    def _reach_test(self, call: _Call) -> ShouldersReach | None:
        """The reach prefilter of ``call``'s draws: each hold of a limb hanging from the base within its reach map,
        a hand not yet on its hold first (the likeliest out of reach); ``None`` when no limb has one."""
        r = self.robot
        pre = [(r.limb(lb).joint_ids[0], call.kernel.targets[lb],
                float(r.limb(lb).reach) if r.all_revolute(lb) else math.inf)
               for lb in sorted(call.big.limbs, key=lambda x: x in call.on_hold)
               if r.limb(lb).joint_ids and not r.moves_base(lb)]
        if not pre:
            return None
        if self._maps is None:
            self._maps = reach_maps(r, self.terrain)
        return ShouldersReach(r, self._maps, pre)

    def find(self, sigma: Stance, nxt: Stance, near: np.ndarray, *, seed: int, attempts: int | None = None,
             skip_first: bool = False) -> np.ndarray | None:
        """A transition between ``sigma`` and ``nxt`` (or a feasible configuration of ``sigma`` when
        ``nxt == sigma``), drawn around ``near``.

        Args:
            sigma, nxt: adjacent stances (one limb placed or released), or the same stance twice.
            near: the reference configuration (the draws start from it; the first draw is ``near`` itself
                with the chains closed, unless ``skip_first``).
            seed: RNG seed.
            attempts: base draws (default: the finder's).

        Returns:
            The configuration, or ``None`` after ``attempts`` draws.
        """
        call = self._call(sigma, nxt, near)
        if call is None:
            return None
        r, base = self.robot, self.base
        rng = np.random.default_rng(seed)
        sd = np.where(r.angle_joints[base], 0.12, 0.04)
        n_att = self.attempts if attempts is None else int(attempts)
        reach_ok = self._reach_test(call)
        free_idx = np.array(sorted(j for lb in r.limbs if lb.name not in call.big for j in lb.joint_indices
                                   if j not in self._base_set), dtype=int)
        if self.base_draws == "holds" and len(base):  # Fig. 17 line 2: the base among the holds, not about ``near``
            qc = self._wide(call, reach_ok, free_idx, seed, draws=n_att, radius=self._hold_radius(call.big))
            self.stats.append((n_att if qc is not None else -1, 0, n_att))
            return qc
        ik_tries = draws = com_far = 0
        in_reach = com_near = False
        stream = self._draws(call, rng, range(1 if skip_first else 0, n_att), sd, free_idx, reach_ok)
        for a_i, q, reach_pass, far in stream:
            draws += 1
            if not reach_pass:
                if not in_reach and self.reach_patience and a_i >= self.reach_patience:
                    break  # no draw so far puts every hold within reach: the body cannot get there from ``near``
                continue
            in_reach = True
            if far is not None:  # (the first draw is ``near`` itself, closed: no prefilter)
                if far == FAR:
                    com_far += 1  # the CoM (limbs as in ``near``) is far outside the support region
                    if not com_near and self.com_patience and com_far >= self.com_patience:
                        break  # no draw so far brings the CoM near the region: the body cannot balance about ``near``
                    continue
                com_near = True
            ik_tries += 1
            if ik_tries > self.ik_tries:
                break
            if far == OUTSIDE:
                continue  # near the region, but farther outside than a closure ever brings it in (CLOSURE_SLACK)
            qc = self._closed(call, q, a_i == 0)
            if qc is not None:
                self.stats.append((a_i, ik_tries, draws))
                return qc
        qc = self._fallbacks(call, reach_ok, free_idx, seed)
        self.stats.append((n_att if qc is not None else -1, ik_tries, draws))
        return qc

    def _fallbacks(self, call: _Call, reach_ok: Any, free_idx: np.ndarray, seed: int) -> np.ndarray | None:
        """When the draws about ``near`` found nothing: the wide draws (``wide``), then the walk (``walk``)."""
        qc = None
        if self.wide and len(self.base):
            qc = self._wide(call, reach_ok, free_idx, seed)
        if qc is None and self.walk_steps and call.region is not None and len(self.base):
            qc = self.walk(call.big, call.small, call.near, seed)
        return qc

    def _draws(self, call: _Call, rng: np.random.Generator, indices: range, sd: np.ndarray, free_idx: np.ndarray,
               reach_ok: ShouldersReach | None) -> Any:
        """The base draws of :meth:`find`, in order, each with its prefilters: ``(index, q, every hold within reach,
        where the CoM lies)``, the last :data:`FAR` (farther than ``com_slack`` outside the support region),
        :data:`OUTSIDE` (farther than ``closure_slack``), :data:`CLOSE` or ``None`` when not tested.

        The draws are :meth:`DrawClose.batch <climb_ompl.manifold.closure.DrawClose.batch>`'s, made in chunks (the
        first draw alone, then 16, then the rest; 16 and the rest when the first is skipped).  A call that goes past
        17 draws mostly draws all of them (LEMUR's failed grabs and releases on the generated walls: 589k of the
        708k draws at seed 2 of lean35-65 were made by calls that went past the 120th).  Where the limbs hang from
        one body whose pose the base coordinates set (:class:`climb_ompl.model.base_pose.BasePose`), the prefilters
        of a chunk are computed on arrays, otherwise one draw at a time as it is consumed; the arrays' arithmetic may
        differ from the one-at-a-time one in the last bit, which changes a decision only at an exact tie.  The CoM of
        a draw whose limbs are as in ``near`` is the body's pose applied to ``near``'s CoM in the body's frame."""
        r, region, near = self.robot, call.region, call.near
        pose = self._pose() if len(self.base) else None
        c_local = None
        start, size = indices.start, 1 if indices.start == 0 else 16
        while start < indices.stop:
            idx = list(range(start, min(indices.stop, start + size)))
            start, size = idx[-1] + 1, 16 if size == 1 else indices.stop
            Q, free_rows = call.kernel.batch(rng, near, idx, sd, call.shift, free_idx)
            if pose is None or len(idx) < 4:  # one draw at a time, as consumed (the first alone: cheaper than arrays)
                for i, a in enumerate(idx):
                    q = Q[i]
                    ok = reach_ok is None or reach_ok(q)
                    far = None if not ok or a == 0 or region is None else self._com_level(region, r.com(q))
                    yield a, q, ok, far
                continue
            R, t = pose.poses(Q[:, pose.coords])
            ok = reach_ok.many(R, t) if reach_ok is not None else np.ones(len(idx), dtype=bool)
            far_all: list[int | None] = [None] * len(idx)
            test = [i for i, a in enumerate(idx) if ok[i] and a > 0 and region is not None]
            if test:
                if c_local is None:
                    c_local = pose.com_local(r, near)
                C = R[test] @ c_local + t[test]
                for j, i in enumerate(test):
                    if i in free_rows:  # the free limbs moved: the CoM of the whole configuration
                        C[j] = r.com(Q[i])
                for i, v in zip(test, self._com_levels(region, C), strict=True):
                    far_all[i] = v
            for i, a in enumerate(idx):
                yield a, Q[i], bool(ok[i]), far_all[i]

    def _com_levels(self, region: Any, C: np.ndarray) -> list[int]:
        """:meth:`_com_level` of many CoMs ``(k, 3)`` at once."""
        levels = np.where(region.outside_many(C, self.com_slack), FAR, CLOSE)
        if self.closure_slack < self.com_slack:
            near_rows = np.flatnonzero(levels == CLOSE)
            if len(near_rows):
                levels[near_rows[region.outside_many(C[near_rows], self.closure_slack)]] = OUTSIDE
        return levels.tolist()

    def _com_level(self, region: Any, com: np.ndarray) -> int:
        """Where ``com`` lies: :data:`FAR` (farther than ``com_slack`` outside ``region``), :data:`OUTSIDE` (farther
        than ``closure_slack``) or :data:`CLOSE`."""
        if region.outside_by_more_than(com, self.com_slack):
            return FAR
        if self.closure_slack < self.com_slack and region.outside_by_more_than(com, self.closure_slack):
            return OUTSIDE
        return CLOSE

    def _pose(self) -> Any:
        """The :class:`~climb_ompl.model.base_pose.BasePose` of the one body every limb hangs from, when the base
        coordinates (all of them, and they alone) place it and it carries all the mass (``None`` otherwise: the
        draws' prefilters one at a time, and the limbs closed in their first order)."""
        if self._base_pose is None:
            parents = {int(self.robot.model.parents[lb.joint_ids[0]]) for lb in self.robot.limbs if lb.joint_ids}
            pose = BasePose.of(self.robot, parents.pop()) if len(parents) == 1 else None
            ok = pose is not None and set(pose.coords.tolist()) == self._base_set \
                and pose.carries_mass(self.robot)
            self._base_pose = (pose if ok else None,)
        return self._base_pose[0]

    def walk(self, big: Stance, small: Stance, near: np.ndarray, seed: int) -> np.ndarray | None:
        """A transition found by walking the base towards the support region of ``small``, every chain of ``big``
        closed at each step (:func:`~climb_ompl.manifold.closure.closest_com`, stopping at the first configuration
        whose CoM is inside; at most ``walk`` steps), if it passes the transition checks.

        The draws of :meth:`find` jump once from ``near``: a release whose CoM must move 0.2 m (ANYmal-C letting go
        of a hind foot on a 45-degree slab, its CoM 0.19 m outside the three feet's region) closes no chain from
        that far, while a walk of small steps, each re-closed, keeps the feet on their holds as the body moves.
        Bretl (2006), Fig. 17, samples the pelvis; this is the same sample, reached in steps."""
        best, _, q = closest_com(self.robot, self.terrain, big, small, self.feas, near, draws=self.walk_steps,
                                 seed=seed, stop_inside=True)
        if q is None or best < self.feas.margin:
            return None
        bad = self.feas.why(self.feas.transition_checks(small, big), q)
        if bad is not None:
            self._fail(bad)
            return None
        return q

    def _hold_radius(self, big: Stance) -> float:
        """The radius within which ``transition_base = "holds"`` draws the base about the holds of ``big``: the
        largest reach of their limbs, the ``2L`` of Bretl (2006), Fig. 17 line 2 (a limb of two links of length
        ``L``), m."""
        return max(float(self.robot.limb(lb).reach) for lb in big.limbs)

    def _wide(self, call: _Call, reach_ok: Any, free_idx: np.ndarray, seed: int, *, draws: int | None = None,
              radius: float | None = None) -> np.ndarray | None:
        """The wide draws of :meth:`find` (``wide``): the base drawn about the nominal posture placed on the holds
        of ``big`` (:func:`nominal_near`), its stand-off from the wall anywhere between :data:`WIDE_STANDOFF` times
        the nominal one and the nominal one, the other translations :data:`WIDE_SD` metres and the angles
        ``2 WIDE_SD`` radians about it, half of the draws shifted towards the centre of the smaller stance's
        support region.  Bretl (2006), Fig. 17 line 1, samples the pelvis among the holds, not about where the
        robot stands: a body that must crouch or slide along the wall to balance (a quadruped on a slab or an
        overhang, whose support region leaves the CoM a stand-off of at most a fraction of the stance's length)
        lies outside the local draws' spread.  ``draws``: how many (default ``wide``); ``radius``: the base's
        translation along the wall drawn uniformly in a disc of this radius, m, instead of normally with
        :data:`WIDE_SD` (``transition_base = "holds"``: every draw, with the reach prefilter keeping those within
        reach of every hold, as Fig. 17 line 2 samples the pelvis "within distance 2L from holds j, k, g")."""
        r, base, region, big = self.robot, self.base, call.region, call.big
        rng = np.random.default_rng([int(seed), 7])
        ref = nominal_near(r, self.terrain, big)
        ref[free_idx] = call.near[free_idx]
        tr, dirs = r.base_translations()
        ang = np.array([j not in tr for j in base.tolist()])
        n = wall_normal(self.terrain)
        hold_c = np.mean([self.terrain.hold(h).p for h in big.hold_ids], axis=0)
        origin = np.mean(list(shoulders(r, ref).values()), axis=0)
        standoff = float(n @ (origin - hold_c))
        cols = [list(base).index(j) for j in tr]
        shift = np.zeros(len(base))
        if region is not None and len(region.vertices):
            shift = com_shift(r, region, ref, base)
        for k in range(self.wide if draws is None else draws):
            d = rng.normal(0.0, WIDE_SD, 3)
            d -= (d @ n) * n
            if radius is not None:  # uniform in the disc of ``radius`` along the wall
                d *= radius * math.sqrt(rng.uniform()) / max(float(np.linalg.norm(d)), 1e-12)
            d += n * standoff * (rng.uniform(WIDE_STANDOFF, 1.0) - 1.0)
            step = np.zeros(len(base))
            if cols:
                step[cols] = np.linalg.lstsq(dirs, d, rcond=None)[0]
            step[ang] = rng.normal(0.0, 2.0 * WIDE_SD, int(ang.sum()))
            if k % 2 == 1:
                step = step + shift * rng.uniform(0.3, 1.2)
            q = call.kernel.place(ref, step)
            if free_idx.size and k % 3 == 2:
                q[free_idx] = rng.uniform(self.lo[free_idx], self.hi[free_idx])
            if reach_ok is not None and not reach_ok(q):
                continue
            if region is not None and region.outside_by_more_than(r.com(q), self.com_slack):
                continue  # (com_slack: closure_slack is measured on draws about ``near``, these are drawn farther)
            qc = self._closed(call, q, False)
            if qc is not None:
                return qc
        return None

    def points(self, q: np.ndarray, sigma: Stance, nxt: Stance) -> list[np.ndarray]:
        """Every transition from ``q`` (at the single-contact stance ``sigma``) onto the zero-dimensional
        stance ``nxt``, nearest ``q`` first.

        Fig. 16 line 2 tries a transition "in each component" of ``F_sigma cap F_sigma'``; for a
        zero-dimensional ``nxt`` each point is one (Bretl 2006 sec. 2.1: "there are two configurations,
        q1 and q2, that place hands at both Holds 1 and 2", times the whole-turn variants of joints
        bounded by +-2 pi).  All are enumerated by inverse kinematics (base-moving limbs first), and those
        passing the transition checks are kept.
        """
        r = self.robot
        qs = [q]
        for lb in r.closing_order(nxt.limbs):
            qs = [s for x in qs for s in r.limb_ik(lb, x, r.hand_target(lb, self.terrain.hold(nxt[lb])))]
        checks = self.feas.transition_checks(sigma, nxt)
        return sorted((x for x in qs if self.feas.why(checks, x) is None), key=lambda x: float(np.sum((x - q) ** 2)))


def nominal_near(robot: Any, terrain: Terrain, stance: Stance) -> np.ndarray:
    """The nominal configuration with its base moved so that the contact hands' centroid sits on the
    centroid of their targets on the holds (:func:`~climb_ompl.manifold.stance.hand_targets`; three Gauss-Newton
    steps on the base coordinates), within the joint bounds: where a start search begins."""
    return np.clip(_nominal_unbounded(robot, terrain, stance), robot.lower, robot.upper)


def base_beyond_bounds(robot: Any, terrain: Terrain, stance: Stance, slack: float = 0.05) -> list[str]:
    """The base coordinates that :func:`nominal_near` had to clip by more than ``slack`` (m or rad), as
    ``"base_z = 3.87 outside [-0.5, 3.5]"``: holds the base's bounds (its URDF joints, its spec) keep it away
    from, wherever the limbs reach."""
    q = _nominal_unbounded(robot, terrain, stance)
    return [f"{robot.joint_names[j]} = {q[j]:.3g} outside [{robot.lower[j]:.3g}, {robot.upper[j]:.3g}]"
            for j in robot.base_indices if not robot.lower[j] - slack <= q[j] <= robot.upper[j] + slack]


def _nominal_unbounded(robot: Any, terrain: Terrain, stance: Stance) -> np.ndarray:
    """:func:`nominal_near` before the joint bounds.

    Three Gauss-Newton steps on every base coordinate at once: the smallest change in metres and radians
    together.  For a target far from the nominal posture that answer turns the base as well as moving it (a
    ramp's stones 4 m from its file's origin: the base pitched a radian, beyond its bounds, and no start was
    found), so when it leaves the base's bounds the translations move the hands first, and every base
    coordinate then takes up what they leave."""
    q = np.asarray(robot.nominal_q, dtype=float).copy()
    base = np.array(robot.base_indices, dtype=int)
    names = [lb.name for lb in robot.limbs]
    idx = [names.index(x) for x in stance.limbs]
    target = np.mean(list(hand_targets(robot, terrain, stance).values()), axis=0)
    out = _centroid_steps(robot, q, base, idx, target)
    lo, hi = np.asarray(robot.lower, dtype=float)[base], np.asarray(robot.upper, dtype=float)[base]
    if np.any((out[base] < lo) | (out[base] > hi)):  # (the translations looked up only then: the rare case)
        moves = base[~robot.angle_joints[base]]
        if len(moves):
            out = _centroid_steps(robot, _centroid_steps(robot, q, moves, idx, target), base, idx, target)
    return out


def _centroid_steps(robot: Any, q: np.ndarray, cols: np.ndarray, idx: list[int], target: np.ndarray) -> np.ndarray:
    """``q`` after three Gauss-Newton steps of the coordinates ``cols`` moving the centroid of the hands ``idx``
    onto ``target`` (least squares through the hands' Jacobians, :meth:`RobotModel.hands_and_jacobians`)."""
    q = q.copy()
    for _ in range(3):
        P, J = robot.hands_and_jacobians(q)
        h0 = np.asarray(P, dtype=float)[idx].mean(axis=0)
        jac = np.asarray(J, dtype=float)[idx].mean(axis=0)[:, cols]
        q[cols] += np.linalg.lstsq(jac, target - h0, rcond=None)[0]
    return q


__all__ = ["TransitionFinder", "nominal_near", "base_beyond_bounds", "MAX_BEND_COMBINATIONS", "REACH_PATIENCE",
           "COM_PATIENCE", "CLOSURE_SLACK"]
