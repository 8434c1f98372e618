"""Stances, stance manifolds as OMPL constrained spaces, and the stance validity checker.

A *stance* says which hand is on which hold (Bretl (2006), section 3.1).  Its *stance manifold* ``C_sigma``
is the set of configurations that put every contact hand exactly on its hold; the *feasible space*
``F_sigma`` is the subset in static equilibrium, inside joint and torque limits and free of collision
(Bretl (2006), section 3.2; Bretl, Latombe & Rock (2003), section 3.1).  Here ``C_sigma`` is an OMPL constrained state
space built on the ambient ``RealVectorStateSpace`` of joint vectors, bounded by the robot's joint and base limits:

* :class:`StanceConstraint` (an ``ob.Constraint``): ``F(q) = p_hand(q) - p_hold`` for every contact hand,
  two rows per hand for planar robots (x and z) and three for 3-D robots, with analytic Pinocchio frame
  Jacobians.  Its tolerance is :data:`climb_ompl.contract.TOLERANCE`, the one ``verify`` holds a plan to.
* :func:`make_space` builds the space by name: ``projected`` (default), ``atlas``, ``tangent_bundle``.
* :class:`StanceValidityChecker` combines small :class:`ValidityCheck` objects -
  joint limits, equilibrium (CoM in the cached support region of the stance, Bretl (2006), appendix B),
  collision, torque limits (Bretl (2006), section 3.2.3) - and counts rejections by reason.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Iterator, Mapping
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from climb_ompl.contract import CONE_EDGES, HAND_CONTACT_RADIUS, TOLERANCE
from climb_ompl.errors import PlannerNotFound, QueryError
from climb_ompl.manifold._ompl import ob
from climb_ompl.registry import SPACE_NAMES

if TYPE_CHECKING:  # pragma: no cover
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain

#: Constraint tolerance in metres, shared by the planner (``ob.Constraint``) and ``verify``.
DEFAULT_TOLERANCE: float = TOLERANCE

#: Torque-check modes: per state in the checker, on the finished path only (re-plan on violation), off.
TORQUE_MODES: tuple[str, ...] = ("state", "final-path", "off")


# ---- stance -----------------------------------------------------------------------------------------
@dataclass(frozen=True)
class Stance(Mapping[str, str]):
    """Which limb is on which hold: a frozen, sorted, hashable mapping ``limb name -> hold id``.

    Build with ``Stance({"arm0": "h3", "arm1": "h7"})`` or ``Stance.of(arm0="h3")``.
    """

    pairs: tuple[tuple[str, str], ...] = ()

    def __init__(self, mapping: Mapping[str, str] | Iterable[tuple[str, str]] | None = None, /, **kw: str):
        items = dict(mapping.items() if isinstance(mapping, Mapping) else (mapping or ()))
        items.update(kw)
        object.__setattr__(self, "pairs", tuple(sorted((str(k), str(v)) for k, v in items.items())))
        holds = [h for _, h in self.pairs]
        if len(set(holds)) != len(holds):
            raise QueryError(f"stance {self}: two limbs on the same hold")

    @classmethod
    def of(cls, **limb_to_hold: str) -> Stance:
        """Stance from keyword arguments ``limb=hold``."""
        return cls(limb_to_hold)

    # Mapping protocol
    def __getitem__(self, limb: str) -> str:
        for k, v in self.pairs:
            if k == limb:
                return v
        raise KeyError(limb)

    def __iter__(self) -> Iterator[str]:
        return (k for k, _ in self.pairs)

    def __len__(self) -> int:
        return len(self.pairs)

    def __eq__(self, other: object) -> bool:
        if isinstance(other, Stance):
            return self.pairs == other.pairs
        return isinstance(other, Mapping) and dict(self.pairs) == dict(other)

    def __hash__(self) -> int:
        return hash(self.pairs)

    def __str__(self) -> str:
        return "{" + ", ".join(f"{k}:{v}" for k, v in self.pairs) + "}"

    __repr__ = __str__

    # helpers
    @property
    def limbs(self) -> tuple[str, ...]:
        """Contact limbs, sorted."""
        return tuple(k for k, _ in self.pairs)

    @property
    def hold_ids(self) -> tuple[str, ...]:
        """Hold ids in the order of :attr:`limbs`."""
        return tuple(v for _, v in self.pairs)

    def with_hold(self, limb: str, hold: str) -> Stance:
        """This stance with ``limb`` (also) placed on ``hold``."""
        d = dict(self.pairs)
        d[limb] = hold
        return Stance(d)

    def without(self, limb: str) -> Stance:
        """This stance with ``limb`` released."""
        return Stance({k: v for k, v in self.pairs if k != limb})

    def free_limbs(self, robot: RobotModel) -> tuple[str, ...]:
        """Limbs of ``robot`` not in contact, in the robot's limb order."""
        return tuple(lb.name for lb in robot.limbs if lb.name not in self)

    def contacts(self, terrain: Terrain) -> list[Any]:
        """``equilibrium.Contact`` objects of the contact holds (in :attr:`limbs` order)."""
        from climb_ompl.equilibrium import Contact

        return [Contact.from_hold(terrain.hold(h)) for h in self.hold_ids]

    def validate(self, robot: RobotModel, terrain: Terrain) -> None:
        """Check that every limb and hold exists.

        Raises:
            QueryError: naming the unknown limb or hold and listing the valid names.
        """
        names = [lb.name for lb in robot.limbs]
        for limb, hold in self.pairs:
            if limb not in names:
                raise QueryError(f"stance {self}: unknown limb {limb!r} of robot {robot.name!r}; "
                                 f"valid limbs: {', '.join(names)}")
            if hold not in terrain.hold_ids:
                raise QueryError(f"stance {self}: {terrain.no_hold(hold)}")

    def to_dict(self) -> dict[str, str]:
        """Plain ``{limb: hold}`` dict (sorted)."""
        return dict(self.pairs)


def limb_index(robot: RobotModel, limb: str) -> int:
    """Index of the limb named ``limb`` in ``robot.limbs``.

    Raises:
        QueryError: no such limb.
    """
    for i, lb in enumerate(robot.limbs):
        if lb.name == limb:
            return i
    raise QueryError(f"unknown limb {limb!r}; valid limbs: {', '.join(lb.name for lb in robot.limbs)}")


def hand_targets(robot: RobotModel, terrain: Terrain, stance: Mapping[str, str]) -> dict[str, np.ndarray]:
    """Where each contact limb's hand frame goes, ``{limb: (3,) metres}``: :meth:`RobotModel.hand_target` of
    its hold (the hold itself for a point contact, ``p + r n`` for a sphere foot, :mod:`climb_ompl.model.contact`)."""
    return {lb: robot.hand_target(lb, terrain.hold(h)) for lb, h in stance.items()}


def limb_hold_targets(robot: RobotModel, terrain: Terrain, limb: str) -> np.ndarray:
    """``(n_holds, 3)``: where ``limb``'s hand frame goes to touch each hold of ``terrain`` (file order); the
    hold positions themselves for a point contact."""
    c = robot.limb(limb).contact
    P = terrain.positions
    if c.radius == 0.0:
        return P
    N = np.array([h.n for h in terrain.holds], dtype=float).reshape(-1, 3)
    return P + c.radius * N / np.linalg.norm(N, axis=1, keepdims=True)


def contact_jacobians(robot: RobotModel, terrain: Terrain, stance: Stance, q: np.ndarray) -> np.ndarray:
    """``(len(stance), 3, nq)``: the Jacobians through which the contact forces of ``stance`` act on the
    joints (``tau = g(q) - sum_i J_i^T f_i``, Bretl 2006 sec. 3.2.3), in :attr:`Stance.limbs` order: the hand
    frame's for a point contact, :meth:`RobotModel.contact_jacobian` (the moment ``r n x f`` about a sphere
    foot's centre included) for a sphere."""
    if all(robot.limb(lb).contact.radius == 0.0 for lb in stance.limbs):
        return np.array([robot.hand_jacobian(q, lb) for lb in stance.limbs]).reshape(len(stance), 3, robot.nq)
    return np.array([robot.contact_jacobian(q, lb, terrain.hold(h).n)
                     for lb, h in stance.pairs]).reshape(len(stance), 3, robot.nq)


def constrained_axes(robot: RobotModel) -> np.ndarray:
    """World axes a contact fixes: x and z for planar robots (x-z plane), all three for 3-D robots."""
    return np.array([0, 2]) if robot.planar else np.array([0, 1, 2])


def manifold_dim(robot: RobotModel, stance: Stance) -> int:
    """Dimension of the stance manifold ``C_sigma``: ``nq`` less the coordinates the contacts fix (0 or less:
    a point, a transition only)."""
    return int(robot.nq - len(stance) * len(constrained_axes(robot)))


# ---- constraint ---------------------------------------------------------------------------------------
class StanceConstraint(ob.Constraint):
    """Hands on holds: ``F(q) = [p_i(q) - h_i]_{i in sigma}`` restricted to :func:`constrained_axes`, where
    ``h_i`` is where the hand frame touches the hold (:func:`hand_targets`: the hold, or ``p + r n`` for a
    sphere foot).

    The stance manifold ``C_sigma = {q : F(q) = 0}`` of Bretl (2006), section 3.1 (Bretl, Latombe & Rock (2003), section
    3.1: "the fixed positions of two feet at the supporting holds reduce the number of DOF's of the contact chain
    to 2").  ``function``/``jacobian`` are OMPL's hot path: one Pinocchio FK + frame-Jacobian call each,
    written into OMPL's numpy views.

    Args:
        robot: the robot model.
        terrain: terrain with the holds.
        stance: the stance (validated here).
        tolerance: ``|F(q)|`` tolerance in metres (default :data:`DEFAULT_TOLERANCE`).
    """

    def __init__(self, robot: RobotModel, terrain: Terrain, stance: Stance, tolerance: float = DEFAULT_TOLERANCE):
        stance.validate(robot, terrain)
        self.robot, self.terrain, self.stance = robot, terrain, stance
        self.axes = constrained_axes(robot)
        self.limb_idx = np.array([limb_index(robot, lb) for lb in stance.limbs], dtype=int)
        self.targets = np.array([p[self.axes] for p in hand_targets(robot, terrain, stance).values()]
                                ).reshape(-1, len(self.axes))
        self.nq = int(robot.nq)
        self.co_dim = len(self.limb_idx) * len(self.axes)
        if self.co_dim == 0:
            raise QueryError(f"stance {stance}: no contact, nothing to constrain")
        # OMPL needs a positive manifold dimension; a zero-dimensional stance (a point, Bretl (2006), section 2.1)
        # is only ever projected onto from Python (FIND-TRANSITION), never planned on.
        super().__init__(self.nq, min(self.co_dim, self.nq - 1), float(tolerance))
        self.tol, self.max_iter = float(tolerance), 50
        #: Newton gives up when the squared residual has not dropped 4x over this many iterations
        self.stall = 4
        self._damp = 1e-12 * np.eye(self.co_dim)
        self.setMaxIterations(self.max_iter)
        self._ix = np.ix_(self.limb_idx, self.axes)

    @property
    def manifold_dim(self) -> int:
        """Dimension of ``C_sigma`` (``nq - co_dim``); 0 for a transition-only stance."""
        return self.nq - self.co_dim

    def residual(self, q: np.ndarray) -> np.ndarray:
        """``F(q)`` as a ``(co_dim,)`` array, metres."""
        return (self.robot.hand_positions(q)[self._ix] - self.targets).ravel()

    def jac(self, q: np.ndarray) -> np.ndarray:
        """``dF/dq`` as a ``(co_dim, nq)`` array."""
        return self.robot.hand_jacobians(q)[self.limb_idx][:, self.axes, :].reshape(self.co_dim, self.nq)

    def function(self, x: np.ndarray, out: np.ndarray) -> None:  # noqa: D102 (OMPL hook)
        out[:] = (self.robot.hand_positions(x)[self._ix] - self.targets).ravel()

    def jacobian(self, x: np.ndarray, out: np.ndarray) -> None:  # noqa: D102 (OMPL hook)
        out[:, :] = self.robot.hand_jacobians(x)[self.limb_idx][:, self.axes, :].reshape(self.co_dim, self.nq)

    def newton(self, x: np.ndarray, frozen: np.ndarray | None = None) -> bool:
        """Gauss-Newton projection of ``x`` (in place) onto ``C_sigma``: ``x -= J^+ F(x)`` until ``|F| <= tol``.

        One Pinocchio kinematics pass (positions and Jacobians together) per iteration; the minimum-norm
        step ``J^T (J J^T + lambda I)^-1 F`` is a ``co_dim``-square solve (cheaper than ``lstsq``; the tiny
        damping keeps a straight elbow's rank drop finite).  Fails fast: when the residual has not halved
        over :attr:`stall` iterations (a sample far off the manifold or an unreachable hold) it stops
        instead of spending all :attr:`max_iter` iterations.
        """
        tol2 = self.tol * self.tol
        ix, li, ax = self._ix, self.limb_idx, self.axes
        free = None if frozen is None or len(frozen) == 0 else np.setdiff1d(np.arange(self.nq), frozen)
        eye = self._damp
        hist: list[float] = []
        stall = self.stall
        for it in range(self.max_iter):
            P, J = self.robot.hands_and_jacobians(x)
            f = (P[ix] - self.targets).ravel()
            n2 = float(np.dot(f, f))
            if n2 <= tol2:
                return True
            hist.append(n2)
            if it >= stall and n2 > 0.25 * hist[it - stall]:
                return False
            Jc = J[li][:, ax, :].reshape(self.co_dim, self.nq)
            if free is not None:
                Jc = Jc[:, free]
            try:
                y = np.linalg.solve(Jc @ Jc.T + eye, f)
            except np.linalg.LinAlgError:
                return False
            if free is None:
                x -= Jc.T @ y
            else:
                x[free] -= Jc.T @ y
            if not np.all(np.abs(x) < 1e6):
                return False
        return False

    def project(self, x: Any) -> bool:  # noqa: D102 (OMPL hook: one Python call per projection)
        if isinstance(x, np.ndarray):
            return self.newton(x)
        v = np.fromiter((x[i] for i in range(self.nq)), dtype=float, count=self.nq)
        ok = self.newton(v)
        for i in range(self.nq):
            x[i] = float(v[i])
        return ok

    def error(self, q: np.ndarray) -> float:
        """Largest hand-to-hold distance in metres (over the constrained axes)."""
        r = self.residual(q).reshape(-1, len(self.axes))
        return float(np.linalg.norm(r, axis=1).max())

    def satisfied(self, q: np.ndarray, tol: float | None = None) -> bool:
        """``True`` when every contact hand is within ``tol`` (default: the tolerance) of its hold."""
        return self.error(q) <= (self.tol if tol is None else tol)

    def project_q(self, q: np.ndarray, frozen: Iterable[int] = ()) -> np.ndarray | None:
        """Newton-project a copy of ``q`` onto ``C_sigma``; ``None`` if it does not converge.

        Args:
            q: configuration.
            frozen: joint indices kept fixed (e.g. a straight elbow, Bretl (2006), section 4.2.2).
        """
        x = np.array(q, dtype=float)
        ok = self.newton(x, np.asarray(list(frozen), dtype=int))
        return x if ok and self.satisfied(x) else None


# ---- spaces ---------------------------------------------------------------------------------------------
def ambient_bounds(robot: RobotModel, terrain: Terrain | None = None) -> tuple[np.ndarray, np.ndarray]:
    """Finite lower/upper bounds of the ambient space: joint limits, base bounds clipped to the terrain."""
    lo, hi = np.array(robot.lower, dtype=float), np.array(robot.upper, dtype=float)
    if terrain is not None and len(terrain.holds):
        P = terrain.positions
        span = max(float(getattr(lb, "reach", 1.0) or 1.0) for lb in robot.limbs) * 2.0 + 0.5
        axes = robot.base_axes()  # the base translations along a world axis
        for j in robot.base_indices:
            if not (np.isfinite(lo[j]) and np.isfinite(hi[j])) or hi[j] - lo[j] > 1e3:
                axis = axes.get(int(j))
                if axis is not None:
                    lo[j] = max(lo[j], P[:, axis].min() - span)
                    hi[j] = min(hi[j], P[:, axis].max() + span)
    lo = np.where(np.isfinite(lo), lo, -math.pi)
    hi = np.where(np.isfinite(hi), hi, math.pi)
    return lo, hi


@dataclass
class SpaceBundle:
    """The OMPL objects of one stance query; keeps Python references alive (OMPL holds raw pointers)."""

    kind: str
    constraint: StanceConstraint
    ambient: Any
    space: Any
    si: Any
    keep: list[Any] = field(default_factory=list)

    def state(self, q: np.ndarray) -> Any:
        """A new OMPL state of :attr:`space` holding ``q``."""
        s = ob.State(self.space)
        for i, v in enumerate(np.asarray(q, dtype=float)):
            s[i] = float(v)
        return s


def make_space(constraint: StanceConstraint, kind: str = "projected", *, bounds: tuple[np.ndarray, np.ndarray]
               | None = None, delta: float = 0.05, sampler_allocator: Any = None,
               rho: float | None = None) -> SpaceBundle:
    """Build the constrained state space ``kind`` of a stance.

    Args:
        constraint: the stance constraint.
        kind: ``projected`` (default), ``atlas`` or ``tangent_bundle``.
        bounds: ambient (lower, upper); default :func:`ambient_bounds`.
        delta: geodesic step of the constrained space (ambient distance).
        sampler_allocator: optional ``ob.StateSamplerAllocator`` set on the **ambient** space (the projected
            space projects its samples onto the manifold).
        rho: chart radius of the atlas and tangent-bundle spaces (ambient distance; Kingston, Moll & Kavraki
            (2019)); default OMPL's (0.25).

    Raises:
        PlannerNotFound: unknown ``kind`` (lists the valid names).
        QueryError: a custom sampler was asked for an atlas/tangent-bundle space, which sample their charts.
    """
    if kind not in SPACE_NAMES:
        raise PlannerNotFound("constrained space", kind, SPACE_NAMES)
    if sampler_allocator is not None and kind != "projected":
        raise QueryError(f"custom samplers work only with the 'projected' space: the {kind!r} space samples "
                         "its own charts and never calls an ambient sampler while solving; use sampler='uniform'")
    lo, hi = bounds if bounds is not None else ambient_bounds(constraint.robot, constraint.terrain)
    rv = ob.RealVectorStateSpace(constraint.nq)
    b = ob.RealVectorBounds(constraint.nq)
    for i in range(constraint.nq):
        b.setLow(i, float(lo[i]))
        b.setHigh(i, float(hi[i]))
    rv.setBounds(b)
    if sampler_allocator is not None:
        rv.setStateSamplerAllocator(sampler_allocator)
    if kind == "projected":
        space = ob.ProjectedStateSpace(rv, constraint)
        si = ob.ConstrainedSpaceInformation(space)
    elif kind == "atlas":
        space = ob.AtlasStateSpace(rv, constraint)
        si = ob.ConstrainedSpaceInformation(space)
    else:
        space = ob.TangentBundleStateSpace(rv, constraint)
        si = ob.TangentBundleSpaceInformation(space)
    space.setDelta(float(delta))
    if rho is not None and kind != "projected":
        space.setRho(float(rho))
    return SpaceBundle(kind, constraint, rv, space, si, [b, sampler_allocator])


# ---- validity ---------------------------------------------------------------------------------------
class ValidityCheck(Protocol):
    """One small feasibility test; its ``name`` counts its rejections."""

    name: str

    def __call__(self, q: np.ndarray) -> bool: ...


class JointLimitsCheck:
    """``lower <= q <= upper`` (Bretl (2006), section 4.3: LEMUR's joint limits)."""

    name = "joint_limits"

    def __init__(self, robot: RobotModel, slack: float = 1e-9):
        self.lo = np.asarray(robot.lower, dtype=float) - slack
        self.hi = np.asarray(robot.upper, dtype=float) + slack

    def __call__(self, q: np.ndarray) -> bool:
        return bool(np.all(q >= self.lo) and np.all(q <= self.hi))


class EquilibriumCheck:
    """Static equilibrium: the CoM lies in the stance's support region (Bretl, Latombe & Rock (2003),
    Eq. 1; Bretl (2006), app. B).

    The region depends on the stance only, so it comes from a :class:`equilibrium.RegionCache` and each
    state costs one CoM evaluation and a point-in-polygon (2-D: interval) test, never an LP.

    Args:
        margin: required distance of the CoM from the region's boundary, metres (0: plain membership).
    """

    name = "equilibrium"

    def __init__(self, robot: RobotModel, region: Any, margin: float = 0.0):
        self.robot, self.region, self.margin = robot, region, float(margin)

    def __call__(self, q: np.ndarray) -> bool:
        # SupportRegion.contains/margin (climb_ompl.equilibrium) are the one membership test; the plain
        # containment has a pure-Python fast path for one 3-D point
        if self.margin > 0:
            return bool(self.region.margin(self.robot.com(q)) >= self.margin)
        return bool(self.region.contains(self.robot.com(q)))


class CollisionCheck:
    """Terrain and self collision (Coal via the robot model).

    Contact limbs' hands are exempt from terrain collision (they touch their holds).  A free limb's hand
    is exempt too while it is within ``radius`` metres of a hold it grabs or releases during the move
    (``near``), so the move can start and end with that hand on its hold.

    Args:
        robot, terrain: robot and terrain.
        contact_limbs: limbs in contact.
        near: ``{free limb: [(3,) hold positions]}`` where that limb's hand is exempt.
        radius: exemption radius, metres.
        clearance: smallest distance between two links of the robot, metres (see
            :meth:`RobotModel.in_collision`).
    """

    name = "collision"

    def __init__(self, robot: RobotModel, terrain: Terrain, contact_limbs: Iterable[str],
                 near: Mapping[str, list[np.ndarray]] | None = None, radius: float = HAND_CONTACT_RADIUS,
                 clearance: float = 0.0):
        self.robot, self.terrain, self.limbs = robot, terrain, tuple(contact_limbs)
        self.clearance = float(clearance)
        self.near = [(limb_index(robot, lb), lb, np.asarray(ps, dtype=float).reshape(-1, 3))
                     for lb, ps in sorted((near or {}).items()) if len(ps)]
        self.radius = float(radius)

    def __call__(self, q: np.ndarray) -> bool:
        limbs = self.limbs
        if self.near:
            H = self.robot.hand_positions(q)
            extra = tuple(lb for i, lb, P in self.near
                          if np.min(np.linalg.norm(P - H[i], axis=1)) <= self.radius)
            if extra:
                limbs = tuple(sorted(limbs + extra))
        return not self.robot.in_collision(q, self.terrain, contact_limbs=limbs, clearance=self.clearance)


class TorqueCheck:
    """Joint torque limits with some admissible contact forces (Bretl (2006), section 3.2.3).

    Wraps :class:`equilibrium.TorqueChecker` (one small simplex LP behind cheap prefilters), its prefilter
    using the stance's cached support region.  The checker (and the support region of its own cone model, when
    that differs from ``region``'s) is built at the first call: most checks a climb builds are never called, an
    earlier check rejecting every configuration they see.  ``cone_edges`` is checked at once.

    Args:
        region: the stance's support region for the prefilter (computed with ``cone_edges`` when omitted or
            when it was built with another number of edges).
        cone_edges: edges of the inscribed friction pyramids of the torque LP.
    """

    name = "torque"

    def __init__(self, robot: RobotModel, terrain: Terrain, stance: Stance, region: Any = None,
                 cone_edges: int = CONE_EDGES):
        from climb_ompl.equilibrium.region import check_cone_edges

        self.robot, self.terrain, self.stance = robot, terrain, stance
        self.limb_idx = np.array([limb_index(robot, lb) for lb in stance.limbs], dtype=int)
        self.cone_edges = check_cone_edges(cone_edges)
        self._region = region  # (until the checker is built)
        self._checker: Any = None
        self.g = terrain.g
        self.sphere = any(robot.limb(lb).contact.radius > 0.0 for lb in stance.limbs)

    @property
    def checker(self) -> Any:
        """The stance's :class:`equilibrium.TorqueChecker` (built at the first use)."""
        if self._checker is None:
            from climb_ompl.equilibrium import TorqueChecker

            robot, region, ce = self.robot, self._region, self.cone_edges
            if region is None or getattr(region, "cone_edges", ce) != ce:
                region = stance_region(robot, self.terrain, self.stance, cone_edges=ce)
            self._checker = TorqueChecker(self.stance.contacts(self.terrain), robot.mass, self.g, robot.torque_limits,
                                          robot.actuated, planar=bool(robot.planar), region=region, cone_edges=ce)
            self._region = None
        return self._checker

    def __call__(self, q: np.ndarray) -> bool:
        if self.sphere:  # the force acts on the sphere's surface, not its centre
            J = contact_jacobians(self.robot, self.terrain, self.stance, q)
        else:
            J = self.robot.hand_jacobians(q)[self.limb_idx]
        return bool(self.checker(self.robot.com(q), J, self.robot.gravity_torques(q, self.g)))


class StanceValidityChecker(ob.StateValidityChecker):
    """OMPL validity checker running :class:`ValidityCheck` s in order, counting rejections by reason.

    Args:
        si: the (constrained) space information.
        checks: checks in evaluation order (cheap first).
        nq: configuration dimension.
    """

    def __init__(self, si: Any, checks: list[ValidityCheck], nq: int):
        super().__init__(si)
        self.checks = list(checks)
        self.nq = nq
        self.calls = 0
        self.rejections: dict[str, int] = {c.name: 0 for c in self.checks}
        self._rng = range(nq)

    def to_q(self, state: Any) -> np.ndarray:
        """The state's values as a numpy vector."""
        return np.fromiter((state[i] for i in self._rng), dtype=float, count=self.nq)

    def reason(self, q: np.ndarray) -> str | None:
        """Name of the first failing check, or ``None`` when ``q`` is valid (counts as a call)."""
        self.calls += 1
        for c in self.checks:
            if not c(q):
                self.rejections[c.name] += 1
                return c.name
        return None

    def isValid(self, state: Any) -> bool:  # noqa: N802 (OMPL hook)
        return self.reason(self.to_q(state)) is None

    def valid_q(self, q: np.ndarray) -> bool:
        """Whether ``q`` passes every check."""
        return self.reason(np.asarray(q, dtype=float)) is None


def stance_region(robot: RobotModel, terrain: Terrain, stance: Stance, cache: Any = None,
                  cone_edges: int = CONE_EDGES) -> Any:
    """The (cached) support region of ``stance`` for ``robot`` (Bretl 2006, appendix B):
    :func:`climb_ompl.equilibrium.support_region` of the stance's contacts, the robot's mass and the
    terrain's gravity."""

    cache = cache if cache is not None else _CACHE
    if cache is None:
        cache = _default_cache()
    return cache.get(stance.contacts(terrain), robot.mass, terrain.g, planar=bool(robot.planar),
                     cone_edges=int(cone_edges))


_CACHE: Any = None


def _default_cache() -> Any:
    global _CACHE
    if _CACHE is None:
        from climb_ompl.equilibrium import RegionCache

        _CACHE = RegionCache()
    return _CACHE


def make_checks(robot: RobotModel, terrain: Terrain, stance: Stance, *, margin: float = 0.0,
                collision: bool = True, torque: str = "final-path", region: Any = None,
                near: Mapping[str, list[np.ndarray]] | None = None,
                cone_edges: int = CONE_EDGES, torque_cone_edges: int | None = None) -> list[ValidityCheck]:
    """The standard checks of a stance, cheap first: joint limits, equilibrium, collision, torque.

    For a robot with ``equilibrium: false`` (Bretl (2006), sec. 2.1, the double-link robot on pegs) only joint
    limits and collision: the equilibrium and torque checks are skipped.

    Args:
        margin: equilibrium margin in metres.
        collision: include the collision check.
        torque: ``state`` (per-state check here), ``final-path`` or ``off`` (no per-state check).
        near: free limbs' holds where their hands are exempt from terrain collision (see :class:`CollisionCheck`).
        cone_edges: edges of the linearised friction cones of the equilibrium and torque checks alike.
        torque_cone_edges: edges of the torque check's pyramids (default: ``cone_edges``).

    Raises:
        PlannerNotFound: unknown torque mode.
    """
    if torque not in TORQUE_MODES:
        raise PlannerNotFound("torque mode", torque, TORQUE_MODES)
    checks: list[ValidityCheck] = [JointLimitsCheck(robot)]
    if not robot.equilibrium:
        # Bretl (2006), sec. 2.1: a peg-grabbing robot is feasible when collision-free with a hand at a hold
        # (the stance constraint); no equilibrium, hence no torque check
        if collision:
            checks.append(CollisionCheck(robot, terrain, stance.limbs, near))
        return checks
    region = region if region is not None else stance_region(robot, terrain, stance, cone_edges=cone_edges)
    checks.append(EquilibriumCheck(robot, region, margin))
    if collision:
        checks.append(CollisionCheck(robot, terrain, stance.limbs, near))
    if torque == "state":
        checks.append(TorqueCheck(robot, terrain, stance, region,
                                  cone_edges=cone_edges if torque_cone_edges is None else torque_cone_edges))
    return checks


__all__ = [
    "DEFAULT_TOLERANCE",
    "SPACE_NAMES",
    "TORQUE_MODES",
    "Stance",
    "StanceConstraint",
    "SpaceBundle",
    "make_space",
    "ambient_bounds",
    "ValidityCheck",
    "JointLimitsCheck",
    "EquilibriumCheck",
    "CollisionCheck",
    "TorqueCheck",
    "StanceValidityChecker",
    "make_checks",
    "stance_region",
    "limb_index",
    "constrained_axes",
    "manifold_dim",
    "hand_targets",
    "limb_hold_targets",
    "contact_jacobians",
]
