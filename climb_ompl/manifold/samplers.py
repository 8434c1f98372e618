"""Samplers of stance manifolds, selectable by name and mixable with uniform sampling.

One sampling core (:class:`SamplingCore`: draws configurations on or near ``C_sigma``) and two OMPL
adapters, because OMPL planners reach samplers through two different hooks:

* :class:`AmbientStateSampler`, an ``ob.StateSampler`` allocated on the **ambient**
  ``RealVectorStateSpace``: the projected space projects its samples; LazyPRM, RRTConnect, BiEST and the
  other planners that call the space's sampler use it.
* :class:`CoreValidStateSampler`, an ``ob.ValidStateSampler`` set on the SpaceInformation: PRM's roadmap
  growth calls it.

Atlas and tangent-bundle spaces sample their own charts and never call an ambient sampler while solving;
:func:`climb_ompl.manifold.stance.make_space` refuses a custom sampler there (documented in ``docs/onestep.md``).

Strategies (``SAMPLER_NAMES``):

``uniform``
    Uniform in the ambient box (OMPL's default, projected onto ``C_sigma``).
``joint-by-joint``
    Bretl (2006), section 4.3: the base first (near the contact holds), then each contact limb's joints by
    analytic IK under joint limits, the free limbs uniformly within limits; closes the chain exactly.
``straight-elbow``
    Bretl (2006), section 4.2.2 / Bretl et al. (2004), "straight-limb samples": one contact limb's elbow a small ``eps``
    from straight (atlas charts are singular exactly there), the chain closed by moving the base and
    analytic IK of the other contact limbs (a Newton step with the elbow frozen mops up what is left).
``free-limb``
    Bretl et al. (2004): for a sampled contact-chain configuration, the free-limb configurations nearest the
    equilibrium boundary (one on each side of the support region), chosen deterministically on a grid.
``lift``
    The free hand a few centimetres off a hold along the hold's normal (grab/release moves).
``reduced``
    The planar three-limbed robot's model reduction (Bretl, Latombe & Rock (2003), Eq. 2-5; Bretl (2006), appendix C):
    sample the pelvis, lift with the free-limb angles of Eq. (C3); see :mod:`climb_ompl.manifold.planar3`.

Names combine with ``+`` (``"straight-elbow+free-limb"``); every custom core is mixed with uniform
sampling at ``uniform_fraction``.

Initial phase (``straight_phase``, Bretl et al. (2004), sec. 3): the first ``straight_phase`` draws of a core, any
strategy, are ``straight-elbow`` draws (straight-limb configurations, "initially sampled explicitly"); the mix
resumes after them.  The same-bend rule that goes with it is :class:`climb_ompl.manifold.bends.SameBendCheck`.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np

from climb_ompl.errors import QueryError
from climb_ompl.manifold._ompl import ob
from climb_ompl.manifold.bends import STRAIGHT_EPS
from climb_ompl.manifold.closure import DrawClose
from climb_ompl.manifold.stance import Stance, StanceConstraint
from climb_ompl.registry import SAMPLER_NAMES, parse_sampler

if TYPE_CHECKING:  # pragma: no cover
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain

#: Straight-limb draws that open a FIND-PATH call when its initial phase is on (``straight_phase``, Bretl et al.
#: (2004), sec. 3: straight-limb configurations "initially sampled explicitly"): the value ``bench papers`` measures.
STRAIGHT_PHASE: int = 40


@dataclass(frozen=True)
class LiftTarget:
    """A hold the free limb leaves or reaches: limb name, where its hand frame touches the hold
    (:meth:`RobotModel.hand_target`) and the hold's unit normal (world, metres)."""

    limb: str
    position: np.ndarray
    normal: np.ndarray


class SamplingCore:
    """Draws configurations of a stance (the strategies of the module docstring).

    Args:
        robot: robot model.
        terrain: terrain.
        stance: the stance sampled.
        constraint: its constraint (for projection and closure).
        name: strategy name(s), ``"a+b"`` allowed.
        seed: numpy RNG seed.
        uniform_fraction: probability of a plain uniform draw instead of the custom strategy.
        lift_targets: holds the free hand leaves/reaches (``lift``); default none.
        region: the stance's support region (``free-limb``); default from the cache.
        bounds: ambient (lower, upper).
        segment: ``(q_start, q_goal)`` of the query, for local draws (see ``local_fraction``).
        local_fraction: share of custom draws made around a random point of the straight segment from
            ``q_start`` to ``q_goal``: the base near that point and every IK branch (elbow bend) the one
            nearest it.  A stance manifold has one component per combination of elbow bends, and a draw
            with random bends often lands in another component than the query's (LEMUR's 3-hold stances have
            up to 2^3 branches); local draws keep the roadmap where the query is.
        straight_phase: the first this many draws (after OMPL's setup draws) are straight-limb configurations
            (``straight-elbow``; Bretl et al. (2004), sec. 3); 0: no initial phase.
    """

    def __init__(self, robot: RobotModel, terrain: Terrain, stance: Stance, constraint: StanceConstraint,
                 name: str = "joint-by-joint", *, seed: int = 0, uniform_fraction: float = 0.2,
                 lift_targets: Sequence[LiftTarget] = (), region: Any = None,
                 bounds: tuple[np.ndarray, np.ndarray] | None = None, eps: float = STRAIGHT_EPS,
                 segment: tuple[np.ndarray, np.ndarray] | None = None, local_fraction: float = 0.0,
                 straight_phase: int = 0):
        from climb_ompl.manifold.stance import ambient_bounds, stance_region

        self.robot, self.terrain, self.stance, self.constraint = robot, terrain, stance, constraint
        self.names = parse_sampler(name)
        self.rng = np.random.default_rng(seed)
        self.uniform_fraction = float(uniform_fraction) if self.names != ("uniform",) else 1.0
        self.lo, self.hi = bounds if bounds is not None else ambient_bounds(robot, terrain)
        self.jlo = np.maximum(np.asarray(robot.lower, float), self.lo)
        self.jhi = np.minimum(np.asarray(robot.upper, float), self.hi)
        self.eps = float(eps)
        self.lift_targets = list(lift_targets)
        self.calls = 0
        self.failures = 0
        self.straight_phase = int(straight_phase)
        #: while False, :meth:`draw` returns uniform samples without counting them (OMPL's ``setup()``
        #: draws ~200 ambient samples to estimate the space; they need no custom strategy)
        self.armed = True
        self._region = region
        self._region_fn = lambda: stance_region(robot, terrain, stance)
        self._pending: list[np.ndarray] = []
        self.base_idx = list(robot.base_indices)
        self.base_axes = robot.base_axes()  # the base translations along a world axis: {coordinate: axis}
        #: the draws and closures of the contact chains (base-moving limbs first), within the sampled bounds
        self.kernel = DrawClose.of(robot, terrain, stance, bounds=(self.jlo, self.jhi))
        self.holds = self.kernel.targets  # hand-frame targets on the contact holds
        self.free = stance.free_limbs(robot)
        self._limbs = {lb.name: lb for lb in robot.limbs}
        if "lift" in self.names and not self.lift_targets:
            self.names = tuple(n for n in self.names if n != "lift") or ("joint-by-joint",)
        if "free-limb" in self.names and not self.free:
            self.names = tuple(n for n in self.names if n != "free-limb") or ("joint-by-joint",)
        #: reference configuration: base draws around it, IK solutions nearest it (FIND-TRANSITION near a start)
        self.ref: np.ndarray | None = None
        self.segment = None if segment is None else (np.asarray(segment[0], float), np.asarray(segment[1], float))
        self.local_fraction = float(local_fraction) if self.segment is not None else 0.0
        self._radius = 0.6 * min(float(getattr(lb, "reach", 1.0) or 1.0) for lb in robot.limbs)
        self._shoulders = [(int(self._limbs[lb].joint_ids[0]), np.asarray(self.holds[lb], dtype=float),
                            float(self._limbs[lb].reach) + 1e-9)
                           for lb in self.kernel.order if not robot.moves_base(lb) and self._limbs[lb].joint_ids]
        self._base_guess = self._fit_base()
        self._reduction: Any = None
        if "reduced" in self.names:
            from climb_ompl.manifold.planar3 import Reduction

            self._reduction = Reduction(robot, terrain, stance, constraint)

    @property
    def region(self) -> Any:
        """Support region of the stance (lazily from the cache)."""
        if self._region is None:
            self._region = self._region_fn()
        return self._region

    # ---- public --------------------------------------------------------------------------------
    def draw(self) -> np.ndarray:
        """One configuration (on ``C_sigma`` for the custom strategies; uniform ones still need projecting)."""
        if not self.armed:
            return self.uniform()
        self.calls += 1
        if self._pending:
            return self._pending.pop()
        if self.calls <= self.straight_phase:
            name = "straight-elbow"  # the initial phase (Bretl et al. 2004, sec. 3)
        elif self.rng.random() < self.uniform_fraction:
            return self.uniform()
        else:
            name = self.names[int(self.rng.integers(len(self.names)))] if len(self.names) > 1 else self.names[0]
        fn = getattr(self, "_" + name.replace("-", "_"))
        if self.local_fraction and self.ref is None and self.rng.random() < self.local_fraction:
            a, b = self.segment  # type: ignore[misc]
            self.ref = a + self.rng.random() * (b - a)
            try:
                q = fn()
            finally:
                self.ref = None
        else:
            q = fn()
        if q is None:
            self.failures += 1
            return self.uniform()
        return q

    def draw_closed(self) -> np.ndarray | None:
        """One draw of the custom strategy with a single closure try and no uniform fallback
        (FIND-TRANSITION: ``None`` when the draw fails, so a failing search ends after its attempts)."""
        self.calls += 1
        if self._pending:
            return self._pending.pop()
        name = self.names[int(self.rng.integers(len(self.names)))] if len(self.names) > 1 else self.names[0]
        if name == "joint-by-joint":
            return self._joint_by_joint(tries=1)
        if name == "uniform":
            return self.uniform()
        return getattr(self, "_" + name.replace("-", "_"))()

    def uniform(self) -> np.ndarray:
        """Uniform in the ambient box."""
        return self.rng.uniform(self.lo, self.hi)

    # ---- strategies ------------------------------------------------------------------------------
    def _uniform(self) -> np.ndarray:
        return self.uniform()

    def _ik(self, limb: str, q: np.ndarray, target: np.ndarray) -> np.ndarray | None:
        """An in-limits IK solution placing ``limb``'s hand at ``target``: the one nearest :attr:`ref` when set
        (keeps elbow bends, hence the component), else a random one (:meth:`DrawClose.solve
        <climb_ompl.manifold.closure.DrawClose.solve>`)."""
        return self.kernel.solve(limb, q, target, near=self.ref, rng=self.rng)

    def _place_base(self, q: np.ndarray, radius: float) -> np.ndarray:
        """Put the base near the centroid of the contact holds (random offset <= radius), or, with a
        reference :attr:`ref`, at its base plus a Gaussian step (``radius / 4``; angles 0.15 rad)."""
        if not self.holds:
            return q
        b = self.base_idx
        if self.ref is not None:
            sd = np.array([radius / 4 if j in self.base_axes else 0.15 for j in b])
            q[b] = self.ref[b]
            return self.kernel.place(q, self.kernel.step(self.rng, sd))
        if self._base_guess is not None:
            row = self._base_guess[int(self.rng.integers(len(self._base_guess)))]
            sd = np.array([0.01 if j in self.base_axes else 0.5 * self._theta_step for j in b])
            q[b] = row + self.rng.normal(0.0, 1.0, len(b)) * sd
            return np.clip(q, self.jlo, self.jhi)
        c = np.mean([p for p in self.holds.values()], axis=0)
        for j, ax in self.base_axes.items():
            q[j] = c[ax] + self.rng.uniform(-radius, radius)
        return np.clip(q, self.jlo, self.jhi)

    def _fit_base(self, n_angles: int = 90, per_angle: int = 400) -> np.ndarray | None:
        """Base poses that pass the reach prefilter, found once per stance (the IK-based base placement).

        For each base angle of a grid, the shoulders (first limb joints) move with the base translation
        ``t``; hold ``i`` is within reach iff ``t`` lies in a disc (the reach sphere cut by the plane of the
        translations).  Points drawn in the smallest disc and kept when inside all of them give base poses
        whose every contact hold is within reach: ``(M, len(base))`` rows in :attr:`base_idx` order.

        ``None`` unless the base is translations plus exactly one rotation and no contact limb moves the
        base itself (then that limb's IK places the base), or when no pose passes (draws then fall back).
        """
        b = list(self.base_idx)
        rot = [j for j in b if j not in self.base_axes]
        tr = sorted(self.base_axes.items())
        if len(rot) != 1 or not tr or not self._shoulders or len(self._shoulders) != len(self.holds):
            return None
        import pinocchio as pin

        m, d = self.robot.model, self.robot.data
        ax = [a for _, a in tr]
        other = [k for k in range(3) if k not in ax]
        q = np.clip(np.array(self.robot.nominal_q, dtype=float), self.jlo, self.jhi)
        for j, _ in tr:
            q[j] = 0.0
        rng = np.random.default_rng(12345)
        lo_t = np.array([self.jlo[j] for j, _ in tr])
        hi_t = np.array([self.jhi[j] for j, _ in tr])
        out = []
        for th in np.linspace(self.jlo[rot[0]], self.jhi[rot[0]], n_angles, endpoint=False):
            q[rot[0]] = th
            pin.forwardKinematics(m, d, q)
            C, R = [], []
            for jid, target, reach in self._shoulders:
                sh = np.array(d.oMi[jid].translation)
                off = float(np.sum((sh[other] - target[other]) ** 2))
                if off >= reach * reach:
                    break
                C.append(target[ax] - sh[ax])  # translation putting the shoulder on the hold
                R.append(math.sqrt(reach * reach - off))
            else:
                C, R = np.array(C), np.array(R)
                k = int(np.argmin(R))
                dim = len(ax)
                X = rng.normal(size=(per_angle, dim))
                X *= (rng.uniform(size=(per_angle, 1)) ** (1.0 / dim)) / np.linalg.norm(X, axis=1, keepdims=True)
                T = C[k] + R[k] * X
                ok = np.all(np.linalg.norm(T[:, None, :] - C[None, :, :], axis=2) <= R[None, :], axis=1)
                ok &= np.all((T >= lo_t) & (T <= hi_t), axis=1)
                for t in T[ok]:
                    row = np.empty(len(b))
                    for i, j in enumerate(b):
                        row[i] = th if j == rot[0] else t[[jj for jj, _ in tr].index(j)]
                    out.append(row)
        self._theta_step = (self.jhi[rot[0]] - self.jlo[rot[0]]) / n_angles
        return np.array(out) if out else None

    def _reachable(self, q: np.ndarray) -> bool:
        """Cheap necessary condition before any IK: every contact hold within reach of its limb's
        first joint (one kinematics pass; limbs whose joints move the base are skipped)."""
        if not self._shoulders:
            return True
        import pinocchio as pin

        m, d = self.robot.model, self.robot.data
        pin.forwardKinematics(m, d, q)
        for jid, target, reach in self._shoulders:
            r = d.oMi[jid].translation - target
            if float(r[0] * r[0] + r[1] * r[1] + r[2] * r[2]) > reach * reach:
                return False
        return True

    def close_chain(self, q: np.ndarray) -> np.ndarray | None:
        """Close every contact limb of ``q`` on its hold by analytic IK (base-moving limbs first), after
        the reach prefilter; ``None`` when a hold is out of reach."""
        if not self._reachable(q):
            return None
        q = self.kernel.close(q, self.ref, rng=self.rng)
        return q if q is not None and self.constraint.satisfied(q) else None

    def _joint_by_joint(self, tries: int = 30) -> np.ndarray | None:
        """Bretl (2006), section 4.3: base, then each contact limb by IK within limits, free limbs uniformly."""
        for _ in range(tries):
            q = self.rng.uniform(self.jlo, self.jhi)
            if self.ref is not None:
                free = [j for lb in self.free for j in self._limbs[lb].joint_indices]
                q[free] = self.ref[free]
            q = self.close_chain(self._place_base(q, self._radius))
            if q is not None:
                return q
        return None

    def _straight_elbow(self, tries: int = 20) -> np.ndarray | None:
        """One contact limb's elbow at straight +- eps, the chain closed by base move + IK."""
        cands = [lb for lb in self.holds if getattr(self._limbs[lb], "elbow_index", None) is not None]
        if not cands:
            return None
        for _ in range(tries):
            limb = cands[int(self.rng.integers(len(cands)))]
            lb = self._limbs[limb]
            q = self._joint_by_joint(tries=5)
            if q is None:
                q = np.clip(self.rng.uniform(self.jlo, self.jhi), self.jlo, self.jhi)
            e = int(lb.elbow_index)
            q[e] = float(lb.elbow_straight) + (self.eps if self.rng.random() < 0.5 else -self.eps)
            # translate the base so this hand lands on its hold (exact along the base's translation axes)
            d = self.holds[limb] - self.robot.hand_position(q, limb)
            for j, ax in self.base_axes.items():
                q[j] += d[ax]
            for other in self.holds:
                if other == limb:
                    continue
                s = self._ik(other, q, self.holds[other])
                if s is None:
                    break
                q = s
            if not self.constraint.satisfied(q):
                q2 = self.constraint.project_q(q, frozen=[e])
                if q2 is None:
                    continue
                q = q2
            if np.all(q >= self.jlo) and np.all(q <= self.jhi):
                return q
        return None

    def _free_limb(self, grid: int = 9) -> np.ndarray | None:
        """Bretl et al. (2004): a contact-chain sample, kept, plus the free-limb configurations of that chain
        nearest the equilibrium boundary (in general two), queued as the next draws."""
        q = self._joint_by_joint()
        if q is None:
            return None
        self._pending.extend(free_limb_extremes(self.robot, self.region, q, self.free, self.jlo, self.jhi,
                                                grid=grid)[::-1])
        return q

    def _lift(self, tries: int = 10) -> np.ndarray | None:
        """The free hand a small distance off a hold along its normal."""
        for _ in range(tries):
            t = self.lift_targets[int(self.rng.integers(len(self.lift_targets)))]
            q = self._joint_by_joint(tries=5)
            if q is None:
                return None
            h = self.rng.uniform(0.01, 0.06)
            s = self._ik(t.limb, q, t.position + h * t.normal)
            if s is not None:
                return s
        return None

    def _reduced(self) -> np.ndarray | None:
        """Bretl (2006), appendix C: a pelvis sample lifted by Eq. (C3)."""
        return self._reduction.sample(self.rng, self.region)


def free_limb_extremes(robot: RobotModel, region: Any, q: np.ndarray, free: Sequence[str], lo: np.ndarray,
                       hi: np.ndarray, grid: int = 9) -> list[np.ndarray]:
    """Bretl et al. (2004), sec. 3: for the contact chain of ``q``, "the configurations of the free limb that
    bring the robot closest to infeasibility with respect to the equilibrium constraint (in general, there
    are two)".

    Deterministic: a ``grid``-point lattice over the free limbs' joints within limits.  Among lattice points
    in equilibrium, the one of smallest margin (distance of the CoM to the support region's boundary), and
    the one of smallest margin on the other side of ``q``'s CoM (the CoM displaced the opposite way): on a
    planar robot, the two ends of the interval the free limb can sweep the CoM through.
    """
    idx = [j for lb in robot.limbs if lb.name in free for j in lb.joint_indices]
    if not idx:
        return []
    axes = [np.linspace(lo[j], hi[j], grid) for j in idx]
    mesh = np.stack(np.meshgrid(*axes, indexing="ij"), axis=-1).reshape(-1, len(idx))
    Q = np.repeat(q[None, :], len(mesh), axis=0)
    Q[:, idx] = mesh
    C = robot.com_batch(Q)
    m = np.asarray(region.margin(C), dtype=float)
    ok = np.flatnonzero(m >= 0)
    if not ok.size:
        return []
    first = int(ok[np.argmin(m[ok])])
    d = C[first] - np.asarray(robot.com(q), dtype=float)
    other = ok[(C[ok] - np.asarray(robot.com(q), dtype=float)) @ d < 0]
    out = [Q[first].copy()]
    if other.size:
        out.append(Q[int(other[np.argmin(m[other])])].copy())
    return out


# ---- OMPL adapters ------------------------------------------------------------------------------------
class AmbientStateSampler(ob.StateSampler):
    """``ob.StateSampler`` on the ambient space drawing from a :class:`SamplingCore` (projected after)."""

    def __init__(self, space: Any, core: SamplingCore):
        super().__init__(space)
        self.core = core
        self.n = core.constraint.nq

    def _write(self, state: Any, q: np.ndarray) -> None:
        q = np.clip(q, self.core.lo, self.core.hi)
        for i in range(self.n):
            state[i] = float(q[i])

    def sampleUniform(self, state: Any) -> None:  # noqa: N802 (OMPL hook)
        self._write(state, self.core.draw())

    def sampleUniformNear(self, state: Any, near: Any, distance: float) -> None:  # noqa: N802
        c = np.array([near[i] for i in range(self.n)])
        self._write(state, c + self.core.rng.uniform(-distance, distance, self.n))

    def sampleGaussian(self, state: Any, mean: Any, stdDev: float) -> None:  # noqa: N802,N803
        c = np.array([mean[i] for i in range(self.n)])
        self._write(state, c + self.core.rng.normal(0.0, stdDev, self.n))


class CoreValidStateSampler(ob.ValidStateSampler):
    """``ob.ValidStateSampler`` (PRM's hook): draw, project onto ``C_sigma``, keep if valid."""

    def __init__(self, si: Any, core: SamplingCore, is_valid: Callable[[np.ndarray], bool], attempts: int = 20):
        super().__init__(si)
        self.core, self.is_valid, self.attempts = core, is_valid, attempts
        self.n = core.constraint.nq
        self.setNrAttempts(attempts)

    def _accept(self, state: Any, q: np.ndarray | None) -> bool:
        if q is None:
            return False
        q = self.core.constraint.project_q(q) if not self.core.constraint.satisfied(q) else q
        if q is None or not self.is_valid(q):
            return False
        for i in range(self.n):
            state[i] = float(q[i])
        return True

    def sample(self, state: Any) -> bool:  # noqa: D102 (OMPL hook)
        return any(self._accept(state, self.core.draw()) for _ in range(self.attempts))

    def sampleNear(self, state: Any, near: Any, distance: float) -> bool:  # noqa: N802,D102
        c = np.array([near[i] for i in range(self.n)])
        return any(self._accept(state, c + self.core.rng.uniform(-distance, distance, self.n))
                   for _ in range(self.attempts))


class SamplerHooks:
    """Allocators for both OMPL hooks sharing one core; keeps every allocated sampler alive."""

    def __init__(self, core: SamplingCore, is_valid: Callable[[np.ndarray], bool]):
        self.core, self.is_valid = core, is_valid
        self.allocated: list[Any] = []
        self.state_allocator = ob.StateSamplerAllocator(self._alloc_state)
        self.valid_allocator = ob.ValidStateSamplerAllocator(self._alloc_valid)

    def _alloc_state(self, space: Any) -> Any:
        s = AmbientStateSampler(space, self.core)
        self.allocated.append(s)
        return s

    def _alloc_valid(self, si: Any) -> Any:
        s = CoreValidStateSampler(si, self.core, self.is_valid)
        self.allocated.append(s)
        return s


def make_core(robot: RobotModel, terrain: Terrain, stance: Stance, constraint: StanceConstraint, name: str,
              **kw: Any) -> SamplingCore:
    """Build a :class:`SamplingCore`; checks that ``reduced`` is used only on the planar three-limbed robot.

    Raises:
        PlannerNotFound: unknown sampler name.
        QueryError: ``reduced`` on another robot.
    """
    names = parse_sampler(name)
    if "reduced" in names:
        from climb_ompl.manifold.planar3 import supports

        if not supports(robot, stance):
            raise QueryError(f"sampler 'reduced' is the planar three-limbed robot's model reduction "
                             f"(two contact limbs); not applicable to robot {robot.name!r} at stance {stance}")
    return SamplingCore(robot, terrain, stance, constraint, name, **kw)


__all__ = [
    "SAMPLER_NAMES",
    "STRAIGHT_EPS",
    "STRAIGHT_PHASE",
    "parse_sampler",
    "LiftTarget",
    "SamplingCore",
    "AmbientStateSampler",
    "CoreValidStateSampler",
    "SamplerHooks",
    "make_core",
    "free_limb_extremes",
]
