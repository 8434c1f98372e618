"""One-step planning: FIND-TRANSITION and FIND-PATH (Bretl (2006), Fig. 17; Bretl, Latombe & Rock (2003), Alg. 1).

* :func:`find_transition` samples a configuration feasible for two adjacent stances (``F_sigma`` and
  ``F_sigma'``, Bretl (2006), Fig. 17 FIND-TRANSITION; Bretl et al. (2004), section 3: sample the smaller space, check
  the other stance's equilibrium).  With ``sigma_next=None`` it returns a feasible configuration of one
  stance (a start configuration).
* :func:`find_path` plans a path in ``F_sigma`` between two configurations with any registered OMPL
  planner on any constrained space (Bretl (2006), Fig. 17 FIND-PATH), the custom samplers of
  :mod:`climb_ompl.manifold.samplers`, and the validity checks of :mod:`climb_ompl.manifold.stance`.  The returned
  path is
  interpolated to ``max_step`` (largest joint change between stored waypoints) and every stored waypoint
  is re-projected onto the stance manifold, so hands stay on holds within ``tolerance``.

Reproducibility: with ``max_iterations`` the planner stops after that many validity checks (a count, not
wall time, so a seed gives the same path on any machine) and OMPL's and numpy's RNGs are seeded from ``seed``; the
wall-clock ``time_limit`` and the CPU-time ``cpu_limit`` remain outer guards.

Zero-dimensional stances (the double-link robot with both hands on pegs, Bretl (2006), section 2.1) are
points: they are transitions only, and :func:`find_path` refuses them.
"""

from __future__ import annotations

import dataclasses
import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np

from climb_ompl.errors import PlannerNotFound, QueryError
from climb_ompl.manifold._ompl import ANYTIME, make_planner, ob, og, ou, seed_rng
from climb_ompl.manifold.bends import SameBendCheck
from climb_ompl.manifold.samplers import LiftTarget, SamplerHooks, make_core, parse_sampler
from climb_ompl.manifold.stance import (
    DEFAULT_TOLERANCE,
    TORQUE_MODES,
    Stance,
    StanceConstraint,
    StanceValidityChecker,
    TorqueCheck,
    ambient_bounds,
    limb_hold_targets,
    make_checks,
    make_space,
    stance_region,
)
from climb_ompl.settings import ClimbSettings, check_names

if TYPE_CHECKING:  # pragma: no cover
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain

#: Wall-clock guard of a standalone FIND-PATH call, s (:class:`PathSettings`; a climb gives the budget it has left).
DEFAULT_TIME_LIMIT: float = 10.0

#: Geodesic step of the constrained space during planning (ambient distance), see :func:`find_path`.
DEFAULT_DELTA: float = 0.05

#: Planner range (the longest motion one extension tries) of every planner that has one, as a share of the
#: ambient space's maximum extent (the diagonal of the joint and base bounds, OMPL's ``getMaximumExtent``);
#: OMPL's default is 0.2.  RRTConnect checks an extension whole and keeps nothing of one that ends in a
#: collision, so long extensions spend the check budget on states it discards (docs/bench.md).
RANGE_FRACTION: float = 0.05

#: Status values of :class:`PathResult`.
STATUSES = ("exact", "no-path", "timeout", "torque-violation", "rejected")


@dataclass
class PathResult:
    """Outcome of a one-step query (FIND-PATH); "no path" is a value, not an exception.

    Attributes:
        status: ``exact`` (path found), ``no-path`` (iteration budget exhausted), ``timeout`` (time limit),
            ``torque-violation`` (every path found violated torque limits in ``final-path`` mode),
            ``rejected`` (the query could not be posed; ``stats["reason"]`` says why).
        path: configurations from start to goal (empty unless ``exact``).
        stats: planning time (``time_s``), ``checks``, ``rejections`` by reason, ``samples`` drawn by the
            custom sampler, ``roadmap_vertices``/``roadmap_edges``, planner, space, sampler, seed, the
            planner's ``range`` and the chart radius ``rho`` (``None`` where they do not apply; absent when
            the direct local path answered).
    """

    status: str
    path: list[np.ndarray] = field(default_factory=list)
    stats: dict[str, Any] = field(default_factory=dict)

    @property
    def found(self) -> bool:
        """Whether a path was found."""
        return self.status == "exact"


# ---- helpers -------------------------------------------------------------------------------------------
def _check_q(robot: RobotModel, q: Any, what: str) -> np.ndarray:
    q = np.asarray(q, dtype=float).reshape(-1)
    if q.shape != (robot.nq,) or not np.all(np.isfinite(q)):
        raise QueryError(f"{what}: expected {robot.nq} finite joint values, got shape {q.shape}")
    return q


def _stance(s: Any) -> Stance:
    return s if isinstance(s, Stance) else Stance(s)


def _lift_targets(robot: RobotModel, terrain: Terrain, stance: Stance, qs: Sequence[np.ndarray],
                  tol: float = 1e-3) -> list[LiftTarget]:
    """Holds that a free limb touches in one of ``qs`` (it leaves or reaches them during the move): its hand
    frame within ``tol`` of :meth:`RobotModel.hand_target` of the hold."""
    out: list[LiftTarget] = []
    names = [lb.name for lb in robot.limbs]
    free = stance.free_limbs(robot)
    targets = {limb: limb_hold_targets(robot, terrain, limb) for limb in free}
    for q in qs:
        H = robot.hand_positions(q)
        for limb in free:
            P = targets[limb]
            d = np.linalg.norm(P - H[names.index(limb)], axis=1)
            k = int(np.argmin(d))
            if d[k] <= tol:
                out.append(LiftTarget(limb, P[k].copy(), terrain.holds[k].n))
    return out


def _seed(seed: int) -> None:
    """Seed OMPL's and numpy's RNGs.  OMPL warns when re-seeding after its first RNG was created, but the
    new seed does reach every RNG created afterwards (each query builds its own planner), so it is silenced."""
    level = ou.getLogLevel()
    ou.setLogLevel(ou.LOG_NONE)
    try:
        seed_rng(seed)
    finally:
        ou.setLogLevel(level)
    np.random.seed(seed % (2**32))


class _Budget:
    """Planner termination: a wall-clock limit, a CPU-time limit (this process's) and (reproducible) a count of
    validity checks."""

    def __init__(self, checker: StanceValidityChecker, time_limit: float, max_checks: int | None,
                 cpu_limit: float | None = None):
        self.checker, self.deadline, self.max_checks = checker, time.perf_counter() + time_limit, max_checks
        self.cpu_deadline = time.process_time() + cpu_limit if cpu_limit is not None else math.inf
        self.timed_out = False

    def __call__(self) -> bool:
        if self.max_checks is not None and self.checker.calls >= self.max_checks:
            return True
        if time.perf_counter() >= self.deadline or time.process_time() >= self.cpu_deadline:
            self.timed_out = True
            return True
        return False


def _path_qs(path: Any, n: int) -> list[np.ndarray]:
    return [np.array([path.getState(i)[j] for j in range(n)]) for i in range(path.getStateCount())]


def _densify(qs: list[np.ndarray], constraint: StanceConstraint, max_step: float) -> list[np.ndarray] | None:
    """Insert re-projected points until no joint moves more than ``max_step`` between waypoints."""
    out = [qs[0]]
    for a, b in zip(qs[:-1], qs[1:], strict=False):
        n = max(1, math.ceil(float(np.max(np.abs(b - a))) / max_step))
        prev = a
        for k in range(1, n + 1):
            if k == n:
                x = b
            else:
                x = constraint.project_q(prev + (b - prev) / (n - k + 1))
                if x is None:
                    return None
            out.append(x)
            prev = x
    # a projected point can overshoot: refine the few steps still too long (bounded passes)
    for _ in range(4):
        steps = [float(np.max(np.abs(y - x))) for x, y in zip(out[:-1], out[1:], strict=False)]
        if max(steps, default=0.0) <= max_step * (1 + 1e-9):
            return out
        new = [out[0]]
        for x, y, s in zip(out[:-1], out[1:], steps, strict=False):
            if s > max_step:
                m = constraint.project_q(0.5 * (x + y))
                if m is None:
                    return None
                new.append(m)
            new.append(y)
        out = new
    return out


# ---- FIND-TRANSITION ------------------------------------------------------------------------------------
def find_transition(robot: RobotModel, terrain: Terrain, sigma: Stance | dict[str, str],
                    sigma_next: Stance | dict[str, str] | None = None, *, seed: int = 0, attempts: int = 600,
                    margin: float = 0.0, near: np.ndarray | None = None,
                    elbow_bends: str = "keep", wide: int = 0) -> np.ndarray | None:
    """A configuration feasible at both ``sigma`` and ``sigma_next`` (Bretl 2006, Fig. 17, FIND-TRANSITION).

    The one implementation of :class:`climb_ompl.climb.transition.TransitionFinder`, with the climb's default
    checks (equilibrium with the fewer contacts binds, Bretl et al. 2004 sec. 3; torque limits per state;
    collision with the larger stance's hands exempt).

    Args:
        robot, terrain: the robot and terrain.
        sigma: current stance.
        sigma_next: adjacent stance (one limb placed or released), or ``None`` for a feasible
            configuration of ``sigma`` alone.
        seed: RNG seed.
        attempts: base positions drawn at most (fewer when no draw puts every hold within reach, or none
            within reach brings the CoM near the support region: :data:`climb_ompl.climb.transition.REACH_PATIENCE`,
            :data:`~climb_ompl.climb.transition.COM_PATIENCE`).
        margin: equilibrium margin, metres.
        near: reference configuration: base draws around it, elbow bends kept from it (default: the
            nominal posture placed on the holds, :func:`climb_ompl.climb.transition.nominal_near`).
        elbow_bends: ``keep`` (those of ``near``) or ``enumerate`` (every combination, Fig. 17 line 3).
        wide: when the draws about ``near`` find nothing, this many more about the nominal posture on the holds
            (:meth:`climb_ompl.climb.transition.TransitionFinder._wide`; 0: none, as in the climb by default).

    Returns:
        The configuration, or ``None`` when none was found within ``attempts``.

    Raises:
        QueryError: unknown limb/hold, or stances that are not adjacent.
    """
    from climb_ompl.climb.transition import TransitionFinder, nominal_near
    from climb_ompl.manifold.feasibility import Feasibility
    from climb_ompl.settings import ClimbSettings

    s0 = _stance(sigma)
    s1 = s0 if sigma_next is None else _stance(sigma_next)
    s0.validate(robot, terrain)
    s1.validate(robot, terrain)
    big, small = (s0, s1) if len(s0) >= len(s1) else (s1, s0)
    if any(big.get(k) != v for k, v in small.items()) or len(big) - len(small) > 1:
        raise QueryError(f"stances {s0} and {s1} are not adjacent (they must differ by one limb placed)")
    d = ClimbSettings()
    feas = Feasibility.of(robot, terrain, d, margin=margin)
    finder = TransitionFinder.of(feas, d, attempts=attempts, ik_tries=attempts, elbow_bends=elbow_bends, wide=wide)
    q0 = nominal_near(robot, terrain, small) if near is None else _check_q(robot, near, "near")
    return finder.find(s0, s1, q0, seed=int(seed))


#: Wide draws of FIND-TRANSITION for a step's ends (:func:`step_ends`;
#: :meth:`climb_ompl.climb.transition.TransitionFinder._wide`).
STEP_ENDS_WIDE = 200


def step_ends(robot: RobotModel, terrain: Terrain, stance: Stance | dict[str, str], limb: str, start_hold: str,
              goal_hold: str, *, seed: int = 0) -> tuple[np.ndarray | None, np.ndarray | None]:
    """The start (``limb`` touching ``start_hold``) and goal (touching ``goal_hold``) of a one-step move while
    ``stance`` carries the robot: two FIND-TRANSITIONs (:func:`find_transition`), the goal drawn about the start
    so that both lie in one component (the elbow bends kept; Bretl 2006, sec. 4.2.3).

    Drawn about the nominal posture, the start may leave the goal hold out of the body's reach where a climb,
    arriving from earlier steps, stands elsewhere (Go1 on the stepping-stone ramp: a front foot's step of a plan
    that ``climb-ompl plan`` found had no goal about the nominal start).  So each call adds wide draws
    (:data:`STEP_ENDS_WIDE`) to its local ones, and when no goal is found about the start, the goal is found
    first and the start about it.

    Returns:
        ``(start, goal)``; ``None`` for an end with no configuration (when neither was found, both).
    """
    s = _stance(stance)
    a, b = s.with_hold(limb, start_hold), s.with_hold(limb, goal_hold)
    qs = find_transition(robot, terrain, a, s, seed=seed, wide=STEP_ENDS_WIDE)
    qg = None if qs is None else find_transition(robot, terrain, s, b, seed=seed, near=qs, wide=STEP_ENDS_WIDE)
    if qg is not None:
        return qs, qg
    qg2 = find_transition(robot, terrain, s, b, seed=seed, wide=STEP_ENDS_WIDE)  # the goal first, a start about it
    qs2 = None if qg2 is None else find_transition(robot, terrain, a, s, seed=seed, near=qg2, wide=STEP_ENDS_WIDE)
    if qs2 is not None:
        return qs2, qg2
    return (None, qg2) if qs is None else (qs, None)


# ---- FIND-PATH --------------------------------------------------------------------------------------------
@dataclass(frozen=True)
class PathSettings:
    """The options of one FIND-PATH call (Bretl (2006), Fig. 17; :func:`find_path`).

    One set of defaults: those of a climb's FIND-PATH (:meth:`of` a default
    :class:`~climb_ompl.settings.ClimbSettings`) for every option the climb sets (planner, space, sampler, the
    budgets ``max_iterations`` = ``path_iterations`` and ``cpu_limit`` = ``step_time_limit``, tolerance,
    ``max_step``, margin, torque mode, the cones' edges, the local path's ``lift`` and ``via_points``), and for the
    others what the climb leaves at these defaults.  The standalone one-step API (:func:`find_path` with no
    settings) uses these; the CLI ``climb-ompl onestep`` gives ``time_limit`` and ``max_iterations`` itself.

    Attributes:
        planner: a name of :data:`climb_ompl.manifold._ompl.PLANNER_NAMES` (``SBL``, Sanchez & Latombe (2003), chosen
            from the planner comparison, docs/planners.md; Bretl et al. (2004) used a lazy PRM, ``LazyPRM``).
        space: ``projected``, ``atlas`` or ``tangent_bundle``.
        sampler: a name (or ``a+b``) of :data:`climb_ompl.manifold.samplers.SAMPLER_NAMES`; custom samplers need the
            ``projected`` space.
        time_limit: wall-clock guard, s (a climb gives the budget it has left).
        cpu_limit: CPU-time guard, s (this process's time: the same on a loaded machine), or ``None``.
        max_iterations: stop after this many validity checks (reproducible runs); ``None``: the guards only.
        tolerance: constraint tolerance, metres (shared with ``verify``).
        max_step: largest joint change between stored waypoints, radians or metres.
        margin: equilibrium margin, metres.
        collision: check collisions.
        torque: ``state`` (per state), ``final-path`` (check the finished path, re-plan with per-state checks on a
            violation, within the budget) or ``off``.
        simplify: shorten the path (OMPL's vertex reduction, seeded; deterministic).
        uniform_fraction: share of uniform samples mixed into a custom sampler.
        range_: planner range (the longest motion one extension tries, for every planner that has one: the RRT,
            EST, KPIECE and SBL families, STRIDE, LazyPRM), default ``range_fraction`` (:data:`RANGE_FRACTION`, a
            climb's ``path_range``) of the ambient space's
            maximum extent.
        rho: chart radius of the atlas and tangent-bundle spaces, default OMPL's
            (:func:`climb_ompl.manifold.stance.make_space`).
        fmt_samples: number of samples of FMT/BFMT (drawn up front, regardless of the time limit).
        delta: geodesic step of the constrained space (ambient distance between projected points of a motion, each
            one validity-checked); default :data:`DEFAULT_DELTA`.  The returned path is densified to ``max_step``
            regardless, and every densified waypoint is validity-checked (with the torque check in ``final-path``
            mode), so a larger ``delta`` never lets an unchecked state through.
        direct: on a stance of two or more contacts, first try the direct local path
            (:class:`climb_ompl.climb.local_path.LocalPath`: the free hand that leaves or reaches a hold is lifted,
            moved and placed; every waypoint checked, torque included); the planner runs only when it fails
            (``stats["direct"]``).
        local_fraction: share of custom draws made near the query's segment (see
            :class:`climb_ompl.manifold.samplers.SamplingCore`).
        straight_phase: the sampler's first this many draws are straight-limb configurations (Bretl et al. (2004),
            sec. 3; :class:`~climb_ompl.manifold.samplers.SamplingCore`); needs the ``projected`` space; 0: none.
        same_bend: connect only configurations with the elbow bends that the start and goal share (Bretl et al.
            (2004), sec. 3; :class:`climb_ompl.manifold.bends.SameBendCheck`, ``stats["bend_free"]`` the limbs they
            bend opposite ways, left free); the direct local path's answer is kept only when it obeys the rule too.
        cone_edges: edges of the linearised friction cones of the equilibrium check.
        torque_cone_edges: edges of the torque check's friction pyramids.
        lift, via_points: the direct local path's (:class:`~climb_ompl.climb.local_path.LocalPath`).
    """

    planner: str = ClimbSettings.planner
    space: str = ClimbSettings.space
    sampler: str = ClimbSettings.sampler
    time_limit: float = DEFAULT_TIME_LIMIT
    cpu_limit: float | None = ClimbSettings.step_time_limit
    max_iterations: int | None = ClimbSettings.path_iterations
    tolerance: float = ClimbSettings.tolerance
    max_step: float = ClimbSettings.max_step
    margin: float = ClimbSettings.margin
    collision: bool = True
    torque: str = ClimbSettings.torque
    simplify: bool = True
    uniform_fraction: float = 0.2
    range_: float | None = None
    range_fraction: float = RANGE_FRACTION
    rho: float | None = None
    fmt_samples: int = 100
    delta: float | None = None
    direct: bool = True
    local_fraction: float = 0.5
    straight_phase: int = ClimbSettings.straight_phase
    same_bend: bool = ClimbSettings.same_bend
    cone_edges: int = ClimbSettings.cone_edges
    torque_cone_edges: int = ClimbSettings.torque_cone_edges
    lift: float = ClimbSettings.lift
    via_points: int = ClimbSettings.via_points

    @classmethod
    def of(cls, settings: ClimbSettings | None = None, **changes: Any) -> PathSettings:
        """The options of a climb's FIND-PATH with ``settings`` (default :class:`~climb_ompl.settings.ClimbSettings`
        ``()``), with ``changes`` (e.g. ``time_limit=30``): every FIND-PATH setting of a climb read in one place."""
        s = settings if settings is not None else ClimbSettings()
        kw = dict(planner=s.planner, space=s.space, sampler=s.sampler, cpu_limit=s.step_time_limit,
                  max_iterations=s.path_iterations, tolerance=s.tolerance, max_step=s.max_step, margin=s.margin,
                  torque=s.torque, cone_edges=s.cone_edges, torque_cone_edges=s.torque_cone_edges, lift=s.lift,
                  via_points=s.via_points, range_fraction=RANGE_FRACTION if s.path_range is None else s.path_range,
                  straight_phase=s.straight_phase, same_bend=s.same_bend)
        return cls(**kw).replace(**changes)

    def replace(self, **changes: Any) -> PathSettings:
        """A copy with ``changes``.

        Raises:
            TypeError: an option that is none of the attributes (the message lists them).
        """
        names = [f.name for f in dataclasses.fields(self)]
        unknown = sorted(set(changes) - set(names))
        if unknown:
            raise TypeError(f"find_path: unknown option(s) {', '.join(unknown)}; options: {', '.join(names)}")
        return dataclasses.replace(self, **changes) if changes else self


def find_path(robot: RobotModel, terrain: Terrain, sigma: Stance | dict[str, str], q_start: Any, q_goal: Any,
              settings: PathSettings | None = None, *, seed: int = 0, **options: Any) -> PathResult:
    """Plan a path in the feasible space ``F_sigma`` from ``q_start`` to ``q_goal`` (Bretl (2006), Fig. 17, FIND-PATH).

    Args:
        robot, terrain: the robot and terrain.
        sigma: the stance (limb -> hold) held during the move.
        q_start, q_goal: configurations on the stance manifold, feasible.
        settings: the options (:class:`PathSettings`; default ``PathSettings()``, a climb's defaults;
            :meth:`PathSettings.of` a climb's settings).
        seed: seed of OMPL's and numpy's RNGs.
        **options: options changed from ``settings`` (the attributes of :class:`PathSettings`, e.g.
            ``planner="RRTConnect", max_iterations=20000``).

    Returns:
        A :class:`PathResult`.

    Raises:
        PlannerNotFound: unknown planner, space, sampler or torque mode.
        QueryError: unknown limb/hold, a zero-dimensional stance, or a start/goal off the manifold or infeasible.
        TypeError: an unknown option.
    """
    opts = (settings if settings is not None else PathSettings()).replace(**options)
    query = _PathQuery(robot, terrain, _stance(sigma), q_start, q_goal, opts, int(seed))
    direct = query.direct()
    return direct if direct is not None else query.plan()


class _PathQuery:
    """One FIND-PATH call (:func:`find_path`): the query checked and posed (the constraint, the checks, the space,
    the sampler), then the direct local path, then the planner."""

    def __init__(self, robot: RobotModel, terrain: Terrain, sig: Stance, q_start: Any, q_goal: Any,
                 opts: PathSettings, seed: int):
        self.t0, self.c0 = time.perf_counter(), time.process_time()
        self.robot, self.terrain, self.sig, self.opts, self.seed = robot, terrain, sig, opts, seed
        check_names(opts.planner, opts.space, opts.sampler)
        if opts.torque not in TORQUE_MODES:
            raise PlannerNotFound("torque mode", opts.torque, TORQUE_MODES)
        self.custom = parse_sampler(opts.sampler) != ("uniform",) or opts.straight_phase > 0
        if opts.straight_phase > 0 and opts.space != "projected":
            raise QueryError(f"straight_phase={opts.straight_phase} needs the 'projected' space: the {opts.space!r} "
                             "space samples its own charts")
        self.qs, self.qg = _check_q(robot, q_start, "q_start"), _check_q(robot, q_goal, "q_goal")
        self.con = con = StanceConstraint(robot, terrain, sig, opts.tolerance)
        if con.manifold_dim <= 0:
            raise QueryError(f"stance {sig} is zero-dimensional for robot {robot.name!r} (a point): "
                             "it is a transition only, there is no path to plan")
        for q, what in ((self.qs, "q_start"), (self.qg, "q_goal")):
            err = con.error(q)
            if err > opts.tolerance:
                raise QueryError(f"{what} violates the stance {sig}: a hand is {err:.3g} m from its hold "
                                 f"(tolerance {opts.tolerance:g} m)")
        _seed(seed)
        # Bretl (2006), sec. 2.1: a peg-grabbing robot has no equilibrium (nor torque) condition
        self.torque = opts.torque if robot.equilibrium else "off"
        self.replans = self.torque_rejected = self.dense_rejected = self.samples_setup = 0
        self._pose()

    def _pose(self) -> None:
        """The checks, the sampler, the constrained space and the validity checker (the checker needs the space
        information, the sampler hooks need the checker: built in that order); the ends checked."""
        robot, terrain, sig, opts = self.robot, self.terrain, self.sig, self.opts
        self.region = stance_region(robot, terrain, sig, cone_edges=opts.cone_edges) if robot.equilibrium else None
        self.lifts = _lift_targets(robot, terrain, sig, [self.qs, self.qg])
        near: dict[str, list[np.ndarray]] = {}
        for lt in self.lifts:
            near.setdefault(lt.limb, []).append(lt.position)
        checks = make_checks(robot, terrain, sig, margin=opts.margin, collision=opts.collision,
                             cone_edges=opts.cone_edges, torque_cone_edges=opts.torque_cone_edges,
                             torque="state" if self.torque == "state" else "off", region=self.region, near=near)
        self.bend = SameBendCheck(robot, sig, self.qs, self.qg) if opts.same_bend else None
        if self.bend is not None:
            checks.insert(1, self.bend)  # cheap: after the joint limits
        bounds = ambient_bounds(robot, terrain)
        self.core = None
        if self.custom:
            self.core = make_core(robot, terrain, sig, self.con, opts.sampler, seed=self.seed,
                                  uniform_fraction=opts.uniform_fraction, region=self.region, bounds=bounds,
                                  lift_targets=self.lifts, segment=(self.qs, self.qg),
                                  local_fraction=opts.local_fraction, straight_phase=opts.straight_phase)
        self.bundle = make_space(self.con, opts.space, bounds=bounds,
                                 delta=DEFAULT_DELTA if opts.delta is None else float(opts.delta), rho=opts.rho)
        self.checker = checker = StanceValidityChecker(self.bundle.si, checks, robot.nq)
        final = TorqueCheck(robot, terrain, sig, self.region, cone_edges=opts.torque_cone_edges) \
            if self.torque == "final-path" else None
        for q, what in ((self.qs, "q_start"), (self.qg, "q_goal")):
            why = next((c.name for c in [*checks, *([final] if final else [])] if not c(q)), None)
            if why is not None:
                raise QueryError(f"{what} is infeasible at stance {sig}: fails the {why} check")
        checker.calls = 0
        checker.rejections = {c.name: 0 for c in checker.checks}
        # the finished path's torque check (its own: the ends' has solved their LPs)
        self.torque_check = TorqueCheck(robot, terrain, sig, self.region, cone_edges=opts.torque_cone_edges) \
            if self.torque == "final-path" else None

    def stats(self, path_q: list[np.ndarray], **extra: Any) -> dict[str, Any]:
        """The call's statistics (:class:`PathResult`)."""
        core, opts = self.core, self.opts
        return {
            "time_s": time.perf_counter() - self.t0,
            "planner": opts.planner,
            "space": opts.space,
            "sampler": opts.sampler,
            "seed": self.seed,
            "checks": self.checker.calls,
            "rejections": dict(sorted(self.checker.rejections.items())),
            "samples": (core.calls - self.samples_setup) if core is not None else None,
            "samples_total": core.calls if core is not None else None,
            "torque_mode": self.torque,
            "torque_rejected_states": self.torque_rejected,
            "replans": self.replans,
            "dense_rejected_states": self.dense_rejected,
            "waypoints": len(path_q),
            "manifold_dim": self.con.manifold_dim,
            "bend_free": None if self.bend is None else list(self.bend.free),
            **extra,
        }

    def direct(self) -> PathResult | None:
        """The direct local path's answer (``opts.direct``, a stance of two or more contacts), or ``None``."""
        if not (self.opts.direct and len(self.sig) > 1):
            return None
        from climb_ompl.climb.local_path import LocalPath
        from climb_ompl.manifold.feasibility import Feasibility

        opts = self.opts
        feas = Feasibility(self.robot, self.terrain, margin=opts.margin, cone_edges=opts.cone_edges,
                           torque_cone_edges=opts.torque_cone_edges)
        moving = self.lifts[0].limb if self.lifts else None
        path_q = LocalPath.of(feas, opts, seed=self.seed)(self.sig, self.qs, self.qg, moving)
        if path_q is None or (self.bend is not None and not all(self.bend(q) for q in path_q)):
            return None
        return PathResult("exact", path_q, self.stats(path_q, direct=True, roadmap_vertices=0, roadmap_edges=0))

    def _planner(self) -> tuple[Any, Any]:
        """The OMPL problem and planner, set up (the custom sampler armed after the planner's own setup draws)."""
        bundle, opts, core = self.bundle, self.opts, self.core
        if core is not None:
            core.armed = False
            hooks = SamplerHooks(core, self.checker.valid_q)
            bundle.ambient.setStateSamplerAllocator(hooks.state_allocator)
            bundle.si.setValidStateSamplerAllocator(hooks.valid_allocator)
            bundle.keep.append(hooks)
        bundle.si.setStateValidityChecker(self.checker)
        bundle.si.setup()
        start, goal = bundle.state(self.qs), bundle.state(self.qg)
        if opts.space != "projected":
            bundle.space.anchorChart(start())
            bundle.space.anchorChart(goal())
        pdef = ob.ProblemDefinition(bundle.si)
        pdef.setStartAndGoalStates(start, goal, opts.tolerance)
        pl = make_planner(opts.planner, bundle.si)
        if opts.planner in ("FMT", "BFMT"):
            pl.setNumSamples(opts.fmt_samples)  # FMT/BFMT draw all their samples up front, ignoring the time limit
        if hasattr(pl, "setRange"):
            pl.setRange(float(opts.range_) if opts.range_ is not None
                        else opts.range_fraction * bundle.space.getMaximumExtent())
        pl.setProblemDefinition(pdef)
        pl.setup()
        if core is not None:
            core.armed = True
        self.samples_setup = core.calls if core is not None else 0
        return pdef, pl

    def plan(self) -> PathResult:
        """The planner's answer: solve, then simplify, densify and re-check the path; a path violating the torque
        limits (``final-path``) or with a densified waypoint that fails a check is planned again (see
        :meth:`_accept`)."""
        pdef, pl = self._planner()
        opts = self.opts
        budget = _Budget(self.checker, opts.time_limit - (time.perf_counter() - self.t0), opts.max_iterations,
                         None if opts.cpu_limit is None else opts.cpu_limit - (time.process_time() - self.c0))
        ptc = ob.PlannerTerminationCondition(ob.PlannerTerminationConditionFn(budget))
        status, path_q = "no-path", []
        while True:
            solved = pl.solve(ptc)
            if not (bool(solved) and pdef.hasExactSolution()):
                status = "timeout" if budget.timed_out else ("torque-violation" if self.torque_rejected else "no-path")
                break
            path = pdef.getSolutionPath()
            if opts.simplify and opts.planner not in ANYTIME:
                og.PathSimplifier(self.bundle.si).reduceVertices(path)
            verdict, dense = self._accept(_path_qs(path, self.robot.nq), pdef, pl)
            if verdict == "again":
                continue
            if verdict == "exact":
                status, path_q = "exact", dense
            break
        stats = self.stats(path_q, direct=False)
        pd = ob.PlannerData(self.bundle.si)
        pl.getPlannerData(pd)
        stats["roadmap_vertices"] = int(pd.numVertices())
        stats["roadmap_edges"] = int(pd.numEdges())
        stats["range"] = float(pl.getRange()) if hasattr(pl, "getRange") else None
        stats["rho"] = float(self.bundle.space.getRho()) if opts.space != "projected" else None
        return PathResult(status, path_q, stats)

    def _accept(self, path_q: list[np.ndarray], pdef: Any, pl: Any) -> tuple[str, list[np.ndarray]]:
        """A solution path's verdict: ``exact`` with its waypoints densified to ``max_step``, ``no-path`` (it cannot
        be densified on the manifold, or the geodesic step cannot be halved further), or ``again`` after setting up
        a new solve: with the torque check per state when a densified waypoint violates the torque limits (Bretl
        (2006), section 4.3 postpones torque limits to post-processing; LazyPRM's ``clearValidity``), or with the
        geodesic step halved when a densified waypoint between two checked states fails a check (an obstacle
        thinner than ``delta``)."""
        checker = self.checker
        dense = _densify(path_q, self.con, self.opts.max_step)
        if dense is None:
            return "no-path", []
        if self.torque_check is not None:
            bad = [q for q in dense if not self.torque_check(q)]
            if bad:
                self.torque_rejected += len(bad)
                self.replans += 1
                checker.checks.append(self.torque_check)
                checker.rejections.setdefault("torque", 0)
                self.torque_check = None
                pdef.clearSolutionPaths()
                if hasattr(pl, "clearValidity"):
                    pl.clearValidity()
                else:
                    pl.clear()
                    pl.setProblemDefinition(pdef)
                    pl.setup()
                return "again", []
        # the densified waypoints lie between states OMPL checked (at most ``delta`` apart): check them too,
        # so that every stored waypoint is feasible whatever the geodesic step
        nbad = sum(1 for q in dense[1:-1] if not checker.valid_q(q))
        if not nbad:
            return "exact", dense
        self.dense_rejected += nbad
        self.replans += 1
        d = float(self.bundle.space.getDelta())
        if d <= 0.01:
            return "no-path", []
        self.bundle.space.setDelta(max(0.01, d / 2))
        pl.clear()
        pdef.clearSolutionPaths()
        pl.setProblemDefinition(pdef)
        pl.setup()
        return "again", []


__all__ = ["PathResult", "PathSettings", "find_transition", "step_ends", "STEP_ENDS_WIDE", "find_path",
           "DEFAULT_TIME_LIMIT", "RANGE_FRACTION", "DEFAULT_TOLERANCE", "STATUSES"]
