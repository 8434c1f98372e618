"""Independent verification of a climb plan: a check of the planner's result that does not trust the planner.

:func:`verify` re-tests a :class:`~climb_ompl.plan.file.Plan` without trusting the planner: it rebuilds the
robot from the spec and URDF *embedded in the plan* and the terrain from the embedded terrain dict
(checking both content hashes), and re-checks every waypoint and the straight-line motion between
consecutive waypoints, sampled at a joint-space ``resolution``:

* ``hands_on_holds``: every contact hand is at its hold (a sphere foot's centre ``r`` off the hold along
  its normal, so the sphere's surface touches it), within ``tolerance`` at waypoints (the
  tolerance shared with the planner's OMPL constraint) and within ``motion_tolerance`` between them;
* ``equilibrium``: forces inside the friction cones balance gravity with the CoM where it is, decided by
  this module's own per-point LP (inscribed ``cone_edges``-sided pyramids, Bretl, Latombe & Rock (2003), Eq. 1/6/7;
  then :data:`FINE_EDGES`-sided ones), with an exact second-order-cone program (Bretl (2006), appendix B)
  deciding the points both LPs reject (an inscribed pyramid's forces lie in the cone, so the LPs accept no
  point the cones reject).  The
  support-region code of :mod:`climb_ompl.equilibrium` is deliberately not used.  Skipped (with the
  torque limits) for a robot declaring ``equilibrium: false``, which grabs pegs (Bretl (2006), sec. 2.1);
* ``torque_limits``: the same program with ``|tau_j| <= tau_max_j`` on the actuated joints, where
  ``tau = g(q) - sum_i J_i^T f_i`` (Bretl (2006), section 3.2.3), ``J_i`` the Jacobian of the contact point;
* ``joint_limits``, ``collision`` with the terrain (contact hands exempt, and free hands within
  :data:`HAND_CONTACT_RADIUS` of a hold, which they are leaving or reaching) and ``self_collision``;
* ``stance_change``: the start stance matches the query, each step changes one contact (one grab or one
  release), a grab takes a free hold with a free limb, a release keeps at least one contact;
* ``continuity``: each step starts where the previous one ended (the start configuration for step 0);
* ``timing``: times increase and no joint exceeds its speed limit between waypoints; for a timed step (with
  velocities and accelerations) the checks of :mod:`climb_ompl.verification.timing`: at rest at its ends, speeds and
  accelerations within limits, velocities continuous; ``dynamics``: the dynamic torques of the timed motion within
  the plan's ``dynamic_fraction`` of the static torque margin;
* ``forces``: the plan's stored contact forces lie in their cones, balance gravity (force and moment
  about the CoM) and give the stored feed-forward torques, inside the torque limits; a sample's margin is not
  negative, a step's ``margin`` is the least of its samples';
* ``goal``: the final stance meets the query's goal; ``integrity``: hashes and sizes, and each re-plan event
  explains its terrains: its change applied to the terrain before it (rebuilt from its ``before`` holds, which
  must give ``terrain_sha256_before``) gives the terrain after it, and it resumed at a step of the plan, at or
  before ``at_step``.

``docs/plan-file.md`` lists every stored field, who reads it and how it is checked.

Each violation names its step, waypoint (a fractional index for interpolated states) and check.
"""

from __future__ import annotations

import math
import os
import tempfile
from collections import Counter
from dataclasses import dataclass
from typing import Any

import numpy as np

from climb_ompl.contract import CONE_EDGES, HAND_CONTACT_RADIUS, MOTION_TOLERANCE, RESOLUTION, TOLERANCE
from climb_ompl.errors import PlanFileError
from climb_ompl.model.terrain import Hold, Terrain
from climb_ompl.plan.events import terrain_eras
from climb_ompl.plan.file import Plan, read_plan_dict, robot_from_plan, sha256_json, sha256_text
from climb_ompl.settings import ClimbSettings
from climb_ompl.verification.report import VerifyReport, Violation
from climb_ompl.verification.timing import check_timed_step

#: Relative tolerance of force/moment balance and torque checks (times m|g|).
BALANCE_RTOL = 1e-6
#: Edges of the finer inscribed pyramids tried where the ``cone_edges`` ones reject a point, before the SOCP:
#: the edges of a 32-sided pyramid reach cos(pi/32) = 99.5 % of the friction coefficient.
FINE_EDGES = 32

CHECKS: tuple[str, ...] = ("integrity", "stance_change", "continuity", "timing", "dynamics", "hands_on_holds",
                           "joint_limits", "equilibrium", "torque_limits", "collision", "self_collision",
                           "forces", "goal")


# ---- the per-point equilibrium programs ------------------------------------------------------------
def _tangent_basis(n: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Two unit tangents of a unit normal; for normals in the x-z plane the first lies in it too."""
    t1 = np.cross(n, [0.0, 1.0, 0.0])
    if np.linalg.norm(t1) < 1e-9:
        t1 = np.cross(n, [1.0, 0.0, 0.0])
    t1 /= np.linalg.norm(t1)
    return t1, np.cross(n, t1)


class _ContactSet:
    """Force parametrisation of a set of holds for the LP: ``f_i = G_i @ x_i`` with bounds on ``x``."""

    def __init__(self, holds: list[Hold], edges: int):
        self.holds = holds
        blocks, lo, hi = [], [], []
        for h in holds:
            n = h.n / np.linalg.norm(h.n)
            if h.type == "grasp":
                # inner box of the ball ||f|| <= max_force
                b = float(h.max_force) / math.sqrt(3.0)
                blocks.append(np.eye(3))
                lo += [-b] * 3
                hi += [b] * 3
                continue
            t1, t2 = _tangent_basis(n)
            ang = 2 * np.pi * np.arange(edges) / edges
            gen = (n[:, None] + h.friction * (np.cos(ang) * t1[:, None] + np.sin(ang) * t2[:, None]))
            if h.type == "adhesion":
                gen = np.hstack([gen, -n[:, None]])  # a pull along -n of at most max_force
                lo += [0.0] * edges + [0.0]
                hi += [None] * edges + [float(h.max_force)]
            else:
                lo += [0.0] * edges
                hi += [None] * edges
            blocks.append(gen)
        self.blocks = blocks
        self.sizes = [b.shape[1] for b in blocks]
        self.offsets = np.concatenate([[0], np.cumsum(self.sizes)]).astype(int)
        self.col_lo = np.array(lo, dtype=float)
        self.col_hi = np.array([np.inf if b is None else b for b in hi], dtype=float)
        self.nx = int(self.offsets[-1])

    def forces(self, x: np.ndarray) -> np.ndarray:
        return np.array([b @ x[o:o + s] for b, o, s in zip(self.blocks, self.offsets[:-1], self.sizes, strict=True)])


def _skew(v: np.ndarray) -> np.ndarray:
    return np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])


def _balance_rows(holds: list[Hold], mass: float, gravity: np.ndarray, com: np.ndarray,
                  planar: bool) -> tuple[np.ndarray, np.ndarray]:
    """Rows ``A f = b`` over the stacked forces ``f`` (3k): force and moment balance about the CoM."""
    k = len(holds)
    a_force = np.hstack([np.eye(3)] * k)
    a_moment = np.hstack([_skew(h.p - com) for h in holds])
    rows = [a_force, a_moment]
    rhs = [-mass * gravity, np.zeros(3)]
    if planar:  # no force out of the x-z plane
        ay = np.zeros((k, 3 * k))
        ay[np.arange(k), 3 * np.arange(k) + 1] = 1.0
        rows.append(ay)
        rhs.append(np.zeros(k))
    return np.vstack(rows), np.concatenate(rhs)


@dataclass
class _Torque:
    jacobians: np.ndarray  # (k, 3, nq) hand position Jacobians
    gravity_torques: np.ndarray  # (nq,)
    limits: np.ndarray  # (nq,)
    actuated: np.ndarray  # (nq,) bool
    passive: np.ndarray  # (nq,) bool: unactuated and not a base coordinate (must carry no torque)


def _lp_feasible(cs: _ContactSet, mass: float, gravity: np.ndarray, com: np.ndarray, planar: bool,
                 torque: _Torque | None) -> bool:
    """Per-point LP (HiGHS) with inscribed pyramids: feasible implies the exact cones are too."""
    a_bal, b_bal = _balance_rows(cs.holds, mass, gravity, com, planar)
    g_big = np.zeros((3 * len(cs.holds), cs.nx))
    for i, (b, o, s) in enumerate(zip(cs.blocks, cs.offsets[:-1], cs.sizes, strict=True)):
        g_big[3 * i:3 * i + 3, o:o + s] = b
    a_eq, b_eq = a_bal @ g_big, b_bal
    a_ub = b_ub = None
    if torque is not None:
        jt = np.vstack(list(torque.jacobians)).T @ g_big if len(cs.holds) else np.zeros((len(torque.limits), 0))
        # tau = g - J^T f:  -lim <= g - jt x <= lim   <=>   jt x <= g + lim,  -jt x <= lim - g
        act = torque.actuated
        a_ub = np.vstack([jt[act], -jt[act]])
        b_ub = np.concatenate([torque.gravity_torques[act] + torque.limits[act],
                               torque.limits[act] - torque.gravity_torques[act]])
        if torque.passive.any():
            eps = BALANCE_RTOL * mass * float(np.linalg.norm(gravity))
            a_ub = np.vstack([a_ub, jt[torque.passive], -jt[torque.passive]])
            b_ub = np.concatenate([b_ub, torque.gravity_torques[torque.passive] + eps,
                                   eps - torque.gravity_torques[torque.passive]])
    return _feasible(a_eq, b_eq, a_ub, b_ub, cs.col_lo, cs.col_hi)


_LP: list[Any] = []  # this process's HiGHS instance for the per-point LPs (default options, quiet)


def _feasible(a_eq: np.ndarray, b_eq: np.ndarray, a_ub: np.ndarray | None, b_ub: np.ndarray | None,
              col_lo: np.ndarray, col_hi: np.ndarray) -> bool:
    """Whether ``a_eq x = b_eq``, ``a_ub x <= b_ub``, ``col_lo <= x <= col_hi`` has a solution: HiGHS with its
    default options (as scipy's ``linprog(method="highs")`` runs it, without linprog's 1-2 ms of checks and
    conversions per call), the model passed whole each time (no warm start)."""
    import highspy

    from climb_ompl.equilibrium._highs import dense_lp, quiet_highs

    if not _LP:
        _LP.append(quiet_highs())
    h = _LP[0]
    n_ub = 0 if b_ub is None else len(b_ub)
    a = a_eq if a_ub is None else np.vstack([a_eq, a_ub])
    h.passModel(dense_lp(a, np.concatenate([b_eq, np.full(n_ub, -np.inf)]),
                         np.concatenate([b_eq, np.zeros(0) if b_ub is None else b_ub]), col_lo, col_hi))
    h.run()
    return bool(h.getModelStatus() == highspy.HighsModelStatus.kOptimal)


def _socp_feasible(holds: list[Hold], mass: float, gravity: np.ndarray, com: np.ndarray, planar: bool,
                   torque: _Torque | None) -> bool:
    """Per-point SOCP (cvxpy) with the exact friction cones (Bretl (2006), appendix B)."""
    import cvxpy as cp

    k = len(holds)
    f = cp.Variable((k, 3))
    cons = []
    for i, h in enumerate(holds):
        n = h.n / np.linalg.norm(h.n)
        p_t = np.eye(3) - np.outer(n, n)
        if h.type == "grasp":
            cons.append(cp.norm(f[i]) <= float(h.max_force))
        elif h.type == "adhesion":
            cons += [cp.norm(p_t @ f[i]) <= h.friction * (n @ f[i] + float(h.max_force)),
                     n @ f[i] >= -float(h.max_force)]
        else:
            cons.append(cp.norm(p_t @ f[i]) <= h.friction * (n @ f[i]))
    a_bal, b_bal = _balance_rows(holds, mass, gravity, com, planar)
    cons.append(a_bal @ cp.reshape(f, (3 * k,), order="C") == b_bal)
    if torque is not None:
        jt = np.vstack(list(torque.jacobians)).T  # (nq, 3k)
        tau = torque.gravity_torques - jt @ cp.reshape(f, (3 * k,), order="C")
        act = np.flatnonzero(torque.actuated)
        if act.size:
            cons.append(cp.abs(tau[act]) <= torque.limits[act])
        pas = np.flatnonzero(torque.passive)
        if pas.size:
            cons.append(cp.abs(tau[pas]) <= BALANCE_RTOL * mass * float(np.linalg.norm(gravity)))
    prob = cp.Problem(cp.Minimize(0), cons)
    try:
        prob.solve(solver="CLARABEL")
    except cp.error.SolverError:
        return False
    return prob.status in ("optimal", "optimal_inaccurate")


# ---- robot and terrain from the plan ---------------------------------------------------------------
def goal_met(goal: dict[str, Any], stance: dict[str, str], terrain: Terrain, reach: float) -> bool:
    """Whether a stance meets a query goal.

    ``{"type": "height", "height": h}``: every contact hold is at or above ``h - reach`` (metres along
    minus gravity, :meth:`Terrain.height`), where ``reach`` is the robot's largest limb reach;
    ``{"type": "hold", "limb", "hold"}``: that limb is on that hold; ``{"type": "stance", "stance": {...}}``:
    exactly that stance.
    """
    if goal["type"] == "height":
        return bool(stance) and all(terrain.height(h) >= goal["height"] - reach - 1e-12
                                    for h in stance.values())
    if goal["type"] == "hold":
        return stance.get(goal["limb"]) == goal["hold"]
    return dict(stance) == dict(goal["stance"])


# ---- the verifier ---------------------------------------------------------------------------------
def verify(plan: Plan | str | os.PathLike[str], *, tolerance: float = TOLERANCE,
           motion_tolerance: float = MOTION_TOLERANCE, resolution: float = RESOLUTION, cone_edges: int = CONE_EDGES,
           robot: Any = None, max_per_check: int = 50) -> VerifyReport:
    """Re-check a climb plan, independently of the planner (see the module docstring for the checks).

    Args:
        plan: a :class:`Plan` or the path of a climb plan file (:func:`climb_ompl.verification.verify` takes a
            plan file of any kind).
        tolerance: hands-on-holds tolerance at waypoints, metres.
        motion_tolerance: hands-on-holds tolerance between waypoints, metres.
        resolution: joint-space (max-norm) step between the states checked between waypoints.
        cone_edges: edges of the inscribed friction pyramids of the fast LP (the exact SOCP decides
            where the LP finds no forces).
        robot: a robot model to use instead of rebuilding it from the plan (tests only).
        max_per_check: stop recording a check's violations after this many (the count stays exact).

    Returns:
        A :class:`VerifyReport`; ``report.ok`` is ``True`` when the plan passes every check.

    Raises:
        PlanFileError: ``plan`` is a path to an unreadable or schema-invalid file.
    """
    if not isinstance(plan, Plan):
        return verify_dict(read_plan_dict(plan), str(plan), validated=True, tolerance=tolerance,
                           motion_tolerance=motion_tolerance, resolution=resolution, cone_edges=cone_edges,
                           robot=robot, max_per_check=max_per_check)
    v = _Verifier(plan, tolerance, motion_tolerance, resolution, cone_edges, max_per_check)
    v.robot = robot
    return v.run()


def verify_dict(d: dict[str, Any], source: str = "<plan>", *, validated: bool = False, tolerance: float = TOLERANCE,
                motion_tolerance: float = MOTION_TOLERANCE, resolution: float = RESOLUTION,
                cone_edges: int = CONE_EDGES, robot: Any = None, max_per_check: int = 50) -> VerifyReport:
    """:func:`verify` of a climb plan file's content ``d`` (``source`` names it in messages): what the file stores,
    its steps' ``duration`` included (a :class:`Plan` derives it from the times).  ``validated``: ``d`` comes from
    :func:`~climb_ompl.plan.file.read_plan_dict`, which checked it against the schema already.

    Raises:
        PlanFileError: ``d`` is not a climb plan, or (unless ``validated``) not a valid one.
    """
    if d.get("kind") != "climb":  # TreeBot and slope-transition plans have their own verifiers
        raise PlanFileError(source, "$.kind", f"a {d.get('kind')!r} plan, not a climb: verify it with "
                            "climb_ompl.verify (climb_ompl.verification.verify), which takes every kind")
    plan = Plan._from_valid(d, source) if validated else Plan.from_dict(d, source)
    v = _Verifier(plan, tolerance, motion_tolerance, resolution, cone_edges, max_per_check)
    v.robot = robot
    v.written_durations = {i: st["duration"] for i, st in enumerate(d["steps"]) if "duration" in st}
    return v.run()


class _Verifier:
    def __init__(self, plan: Plan, tol: float, mtol: float, res: float, edges: int, cap: int):
        self.plan, self.tol, self.mtol, self.res, self.edges, self.cap = plan, tol, mtol, res, edges, cap
        self.out: list[Violation] = []
        self.counts: Counter[str] = Counter()
        self.states = self.lp = self.socp = 0
        self._contact_sets: dict[Any, _ContactSet] = {}
        self.robot: Any = None
        self._hold_targets: dict[str, np.ndarray] = {}
        self.written_durations: dict[int, Any] = {}  # step position -> the file's ``duration`` (a file was read)

    def add(self, check: str, step: int | None, wp: float | None, msg: str) -> None:
        self.counts[check] += 1
        if self.counts[check] <= self.cap:
            self.out.append(Violation(check, step, wp, msg))

    def report(self) -> VerifyReport:
        return VerifyReport(tuple(self.out), self.states, len(self.plan.steps), self.lp, self.socp,
                            dict(sorted(self.counts.items())))

    # ---- plan level -----------------------------------------------------------------------------
    def run(self) -> VerifyReport:
        p = self.plan
        if sha256_json(p.robot["spec"]) != p.robot["spec_sha256"]:
            self.add("integrity", None, None, "$.robot.spec does not match $.robot.spec_sha256")
        if sha256_text(p.robot["urdf"]) != p.robot["urdf_sha256"]:
            self.add("integrity", None, None, "$.robot.urdf does not match $.robot.urdf_sha256")
        if sha256_json({k: v for k, v in p.terrain["data"].items() if k != "description"}) != p.terrain["sha256"]:
            self.add("integrity", None, None, "$.terrain.data does not match $.terrain.sha256")
        self.eras = terrain_eras(p)
        self.terrain = self.final_terrain = self.eras.terrains[-1]  # the plan's own terrain
        for problem in self.eras.problems:
            self.add("integrity", None, None, problem)
        if self.robot is None:
            with tempfile.TemporaryDirectory(prefix="climb-verify-") as tmp:
                self.robot = robot_from_plan(p, tmp)
                return self._run_with_robot()
        return self._run_with_robot()

    def _era(self, step: int) -> Terrain:
        """The terrain step ``step`` was executed on (:meth:`climb_ompl.plan.events.TerrainEras.of_step`)."""
        return self.eras.of_step(step)

    def _use_terrain(self, terrain: Terrain) -> None:
        if terrain is not self.terrain:
            self.terrain = terrain
            self._hold_targets = {}

    def _run_with_robot(self) -> VerifyReport:
        p = self.plan
        r = self.robot
        self.g = self.terrain.g
        self.planar = bool(getattr(r, "planar", False)) or self.terrain.dim == 2
        nq = r.nq
        self.limbs = {lb.name: lb for lb in r.limbs}
        base = np.zeros(nq, dtype=bool)
        base[list(getattr(r, "base_indices", []))] = True
        act = np.asarray(r.actuated, dtype=bool)
        self.torque_limits = np.asarray(r.torque_limits, dtype=float)
        self.actuated = act & np.isfinite(self.torque_limits)
        self.passive = ~act & ~base
        start_q = np.asarray(p.query["start"]["q"], dtype=float)
        if start_q.shape != (nq,):
            self.add("integrity", None, None, f"$.query.start.q has {start_q.size} values, robot has nq = {nq}")
            return self.report()
        stance = dict(p.start_stance)
        self._use_terrain(self._era(0))
        if self._check_stance_valid(None, stance) and not p.steps:
            self._check_state(None, None, start_q, stance, self.tol)  # with steps, step 0's first waypoint
        prev_end = start_q
        for i, s in enumerate(p.steps):
            if s.index != i:
                self.add("integrity", i, None, f"$.steps[{i}].index = {s.index}: each step's index is its place "
                         "(re-plan events name the steps by it)")
            self._use_terrain(self._era(s.index))
            q = s.q
            if q.ndim != 2 or q.shape[1] != nq or len(s.times) != len(q):
                self.add("integrity", s.index, None,
                         f"waypoints shape {q.shape} / {len(s.times)} times do not match nq = {nq}")
                return self.report()
            self._check_step_stance(s, stance)
            if np.max(np.abs(q[0] - prev_end)) > 1e-9:
                self.add("continuity", s.index, 0, f"$.steps[{s.index}].waypoints[0] is "
                         f"{np.max(np.abs(q[0] - prev_end)):.3g} away from "
                         + ("the start configuration $.query.start.q" if i == 0 else
                            f"where $.steps[{i - 1}] ended"))
            self._check_timing(s)
            self._check_motion(s)
            self._check_forces(s)
            # the transition (last waypoint) must also hold in the stance after the grab/release
            self._check_state(s.index, len(q) - 1, q[-1], dict(s.stance_after), self.tol, transition=True,
                              after=f"; the stance after the {s.action} of $.steps[{i}]")
            stance = dict(s.stance_after)
            prev_end = q[-1]
        if self.terrain is not self.final_terrain:
            # the state the plan ends in was last checked on the terrain before a re-plan event (no new step
            # followed it): it must hold on the changed terrain too
            self._use_terrain(self.final_terrain)
            if self._check_stance_valid(None, stance):
                self._check_state(None, None, prev_end, stance, self.tol)
        self._use_terrain(self.final_terrain)
        if set(stance.values()) <= set(self.terrain.hold_ids) and \
                not goal_met(p.query["goal"], stance, self.terrain, self._reach()):  # (unknown holds: reported)
            self.add("goal", None, None, f"final stance {stance} does not meet the goal $.query.goal = "
                     f"{p.query['goal']}")
        if p.totals.get("steps") != len(p.steps):
            self.add("integrity", None, None, f"$.totals.steps = {p.totals.get('steps')} but the plan has "
                     f"{len(p.steps)} steps")
        return self.report()

    def _reach(self) -> float:
        return max(float(getattr(lb, "reach", 0.0)) for lb in self.robot.limbs)

    def _check_stance_valid(self, step: int | None, stance: dict[str, str]) -> bool:
        ok = True
        for limb, hold in stance.items():
            if limb not in self.limbs:
                self.add("stance_change", step, None, f"unknown limb {limb!r}")
                ok = False
            if hold not in self.terrain.hold_ids:
                self.add("stance_change", step, None, f"unknown hold {hold!r}")
                ok = False
        if len(set(stance.values())) != len(stance):
            self.add("stance_change", step, None, f"two limbs on one hold in {stance}")
            ok = False
        if not stance:
            self.add("stance_change", step, None, "no contact at all (the robot would fall)")
            ok = False
        return ok

    def _check_step_stance(self, s: Any, stance: dict[str, str]) -> None:
        if dict(s.stance) != stance:
            self.add("stance_change", s.index, None, f"$.steps[{s.index}].stance {dict(s.stance)} is not "
                     + (f"the start stance $.query.start.stance {stance}" if s.index == 0 else
                        f"the stance reached by the previous step {stance}"))
        if s.action == "grab":
            if s.limb in stance:
                self.add("stance_change", s.index, None, f"$.steps[{s.index}]: grab with limb {s.limb!r} already on "
                         f"{stance[s.limb]!r}")
            if s.hold in stance.values():
                self.add("stance_change", s.index, None, f"$.steps[{s.index}]: grab of hold {s.hold!r}, which is "
                         "already held")
        elif stance.get(s.limb) != s.hold:
            self.add("stance_change", s.index, None, f"$.steps[{s.index}]: release of {s.limb!r} from {s.hold!r}, "
                     "but the stance "
                     f"has it on {stance.get(s.limb)!r}")
        self._check_stance_valid(s.index, dict(s.stance_after))

    def _check_timing(self, s: Any) -> None:
        t = np.asarray(s.times, dtype=float)
        if abs(t[0]) > 1e-12:
            self.add("timing", s.index, 0, f"$.steps[{s.index}].times[0]: first waypoint at t = {t[0]:.6g} s, not 0")
        stored = self.written_durations.get(s.index)
        if stored is not None and not (isinstance(stored, (int, float)) and abs(float(stored) - t[-1]) <= 1e-9):
            self.add("timing", s.index, None, f"$.steps[{s.index}].duration = {stored!r} s, but the step's times end "
                     f"at {t[-1]:.6g} s")
        if s.timed:
            fraction = float(self.plan.settings.get("dynamic_fraction", ClimbSettings.dynamic_fraction))
            check_timed_step(self.robot, s, fraction, self.add)
            return
        dt = np.diff(t)
        dq = np.abs(np.diff(s.q, axis=0))
        vmax = np.asarray(self.robot.velocity_limits, dtype=float)
        for k in range(len(dt)):
            if dt[k] < 0:
                self.add("timing", s.index, k + 1, f"$.steps[{s.index}].times[{k + 1}]: time goes back by "
                         f"{-dt[k]:.3g} s")
                continue
            need = np.max(dq[k] / vmax) if dq[k].any() else 0.0
            if need > dt[k] * (1 + 1e-9) + 1e-12:
                j = int(np.argmax(dq[k] / vmax))
                names = getattr(self.robot, "joint_names", ())
                joint = repr(names[j]) if j < len(names) and names[j] else str(j)
                self.add("timing", s.index, k + 1, f"$.steps[{s.index}].times[{k + 1}]: joint {joint} (coordinate "
                         f"{j}) moves {dq[k][j]:.4g} in "
                         f"{dt[k]:.4g} s, over its speed limit {vmax[j]:.4g}")

    def _check_motion(self, s: Any) -> None:
        q = s.q
        stance = dict(s.stance)
        self._check_state(s.index, 0, q[0], stance, self.tol)
        for k in range(1, len(q)):
            n_sub = int(math.ceil(float(np.max(np.abs(q[k] - q[k - 1]))) / self.res))
            for j in range(1, n_sub):
                a = j / n_sub
                self._check_state(s.index, k - 1 + a, (1 - a) * q[k - 1] + a * q[k], stance, self.mtol)
            self._check_state(s.index, k, q[k], stance, self.tol)

    def _check_state(self, step: int | None, wp: float | None, q: np.ndarray, stance: dict[str, str], tol: float,
                     transition: bool = False, after: str = "") -> None:
        r = self.robot
        self.states += 1
        known = self.terrain.hold_ids
        holds = [self.terrain.hold(h) for _, h in sorted(stance.items()) if h in known]
        limbs = [lb for lb, h in sorted(stance.items()) if h in known and lb in self.limbs]
        if len(limbs) != len(stance):
            return  # reported by the stance checks
        for lb, h in zip(limbs, holds, strict=True):
            # a sphere foot's centre sits at p + r n, its surface on the hold (climb_ompl.model.contact)
            err = float(np.linalg.norm(np.asarray(r.hand_position(q, lb)) - r.hand_target(lb, h)))
            if err > tol:
                self.add("hands_on_holds", step, wp, f"hand of {lb!r} is {err:.3g} m from hold {h.id!r} "
                         f"(tolerance {tol:.0e}{after})")
        if transition:
            # joint limits and collision were checked at this configuration with the step's stance;
            # the new stance adds the grabbed hand (checked above) and its own equilibrium
            self._equilibrium(step, wp, q, holds, limbs)
            return
        lo, hi = np.asarray(r.lower), np.asarray(r.upper)
        bad = np.flatnonzero((q < lo - 1e-9) | (q > hi + 1e-9))
        for j in bad[:3]:
            self.add("joint_limits", step, wp, f"q[{j}] = {q[j]:.6g} outside [{lo[j]:.6g}, {hi[j]:.6g}]")
        touching = self._touching(q, limbs)
        if r.in_collision(q, self.terrain, contact_limbs=tuple(limbs) + touching):
            self.add("collision", step, wp, "robot collides with the terrain")
        if r.self_collision(q):
            self.add("self_collision", step, wp, "robot collides with itself")
        self._equilibrium(step, wp, q, holds, limbs)

    def _touching(self, q: np.ndarray, limbs: list[str]) -> tuple[str, ...]:
        """Free limbs whose hand is within :data:`HAND_CONTACT_RADIUS` of where it touches a hold (allowed to touch
        the wall)."""
        out = []
        for lb in self.limbs:
            if lb not in limbs:
                h = np.asarray(self.robot.hand_position(q, lb), dtype=float)
                P = self._hold_targets.get(lb)
                if P is None:
                    P = self._hold_targets[lb] = np.array([self.robot.hand_target(lb, x) for x in self.terrain.holds]
                                                          ).reshape(-1, 3)
                if float(np.min(np.linalg.norm(P - h, axis=1))) <= HAND_CONTACT_RADIUS:
                    out.append(lb)
        return tuple(out)

    def _jacobian(self, q: np.ndarray, limb: str, hold: Hold) -> np.ndarray:
        """``(3, nq)`` Jacobian of the point where ``limb`` touches ``hold``: the hand frame's for a point contact,
        the sphere's surface point (``r n x f`` about the centre included) for a sphere foot."""
        return np.asarray(self.robot.contact_jacobian(q, limb, hold.n), dtype=float)

    def _contacts(self, holds: list[Hold], edges: int) -> _ContactSet:
        """The force parametrisation of ``holds`` (kept: a stance's waypoints share it)."""
        key = (edges, tuple((h.id, *np.asarray(h.p).tolist(), *np.asarray(h.n).tolist(), float(h.friction),
                             h.type, h.max_force) for h in holds))
        if key not in self._contact_sets:
            self._contact_sets[key] = _ContactSet(holds, edges)
        return self._contact_sets[key]

    def _equilibrium(self, step: int, wp: float, q: np.ndarray, holds: list[Hold], limbs: list[str]) -> None:
        r = self.robot
        if not r.equilibrium:
            return  # a robot grabbing pegs (Bretl (2006), sec. 2.1): no equilibrium nor torque condition, as planned
        if not holds:
            self.add("equilibrium", step, wp, "no contact carries the robot (it would fall)")
            return
        com = np.asarray(r.com(q), dtype=float)
        jac = np.array([self._jacobian(q, lb, h) for lb, h in zip(limbs, holds, strict=True)]
                       ).reshape(len(limbs), 3, r.nq)
        torque = _Torque(jac, np.asarray(r.gravity_torques(q, self.g), dtype=float), self.torque_limits,
                         self.actuated, self.passive)
        self.lp += 1
        if _lp_feasible(self._contacts(holds, self.edges), r.mass, self.g, com, self.planar, torque):
            return
        # near the boundary: finer inscribed pyramids (still sufficient) before the exact cones' SOCP, which
        # costs about 25 ms a call through cvxpy against 0.3 ms
        cs = self._contacts(holds, FINE_EDGES)
        self.lp += 1
        if _lp_feasible(cs, r.mass, self.g, com, self.planar, torque):
            return
        self.socp += 1
        if _socp_feasible(holds, r.mass, self.g, com, self.planar, torque):
            return
        # diagnose: is equilibrium itself impossible, or only within the torque limits?
        self.lp += 1
        if _lp_feasible(cs, r.mass, self.g, com, self.planar, None):
            self.add("torque_limits", step, wp, f"no contact forces keep every joint torque within its limit "
                     f"(stance {dict(zip(limbs, [h.id for h in holds], strict=True))})")
            return
        self.socp += 1
        if _socp_feasible(holds, r.mass, self.g, com, self.planar, None):
            self.add("torque_limits", step, wp, "no contact forces keep every joint torque within its limit")
        else:
            self.add("equilibrium", step, wp, f"CoM {np.round(com, 4).tolist()} admits no contact forces in the "
                     f"friction cones of {[h.id for h in holds]}")

    def _check_forces(self, s: Any) -> None:
        r = self.robot
        stance = dict(s.stance)
        if not set(stance.values()) <= set(self.terrain.hold_ids):  # reported by the stance checks
            return
        mg = r.mass * float(np.linalg.norm(self.g))
        eps = max(BALANCE_RTOL * mg, 1e-6)
        if not s.forces and r.equilibrium:  # a peg-grabbing robot needs none (Bretl (2006), sec. 2.1)
            self.add("forces", s.index, None, "no contact forces stored for this step")
        least = min((fs.margin for fs in s.forces), default=0.0)
        if not abs(s.margin - least) <= 1e-12 * max(1.0, abs(least)):  # (a NaN margin fails too)
            self.add("forces", s.index, None, f"$.steps[{s.index}].margin = {s.margin:.6g} m is not the least margin "
                     f"of its force samples ({least:.6g} m)")
        for m, fs in enumerate(s.forces):
            at = f"$.steps[{s.index}].forces[{m}]"
            if not 0 <= fs.waypoint < len(s.waypoints):
                self.add("forces", s.index, None, f"{at}: force sample at waypoint {fs.waypoint} out of range")
                continue
            q = s.q[fs.waypoint]
            forces = dict(fs.forces)
            extra = sorted(set(forces) - set(stance))
            if extra:
                self.add("forces", s.index, fs.waypoint, f"{at}.forces: forces on limbs not in contact: {extra}")
                continue
            limbs = sorted(stance)
            f = np.array([forces.get(lb, (0.0, 0.0, 0.0)) for lb in limbs], dtype=float).reshape(-1, 3)
            holds = [self.terrain.hold(stance[lb]) for lb in limbs]
            com = np.asarray(r.com(q), dtype=float)
            net = f.sum(axis=0) + r.mass * self.g
            mom = sum((np.cross(h.p - com, fi) for h, fi in zip(holds, f, strict=True)), np.zeros(3))
            if np.linalg.norm(net) > eps:
                self.add("forces", s.index, fs.waypoint, f"{at}.forces: forces do not balance gravity (residual "
                         f"{np.linalg.norm(net):.3g} N)")
            if np.linalg.norm(mom) > eps:
                self.add("forces", s.index, fs.waypoint, f"{at}.forces: forces do not balance the moment of gravity "
                         f"about the CoM (residual {np.linalg.norm(mom):.3g} N m)")
            for lb, h, fi in zip(limbs, holds, f, strict=True):
                n = h.n / np.linalg.norm(h.n)
                fn = float(n @ fi)
                ft = float(np.linalg.norm(fi - fn * n))
                if h.type == "grasp":
                    bad = np.linalg.norm(fi) > float(h.max_force) + eps
                elif h.type == "adhesion":
                    bad = ft > h.friction * (fn + float(h.max_force)) + eps or fn < -float(h.max_force) - eps
                else:
                    bad = ft > h.friction * fn + eps or fn < -eps
                if bad:
                    self.add("forces", s.index, fs.waypoint, f"{at}.forces: force on {lb!r} at {h.id!r} leaves "
                             f"its friction cone (normal {fn:.4g} N, tangential {ft:.4g} N, mu {h.friction})")
            tau = np.asarray(fs.torques, dtype=float)
            if tau.shape != (r.nq,):
                self.add("forces", s.index, fs.waypoint, f"{at}.torques: {tau.size} torques for nq = {r.nq}")
                continue
            jac = [self._jacobian(q, lb, h) for lb, h in zip(limbs, holds, strict=True)]
            expect = np.asarray(r.gravity_torques(q, self.g), dtype=float)
            for j_i, fi in zip(jac, f, strict=True):
                expect = expect - j_i.T @ fi
            scale = eps * max(1.0, float(np.max(np.abs(expect))))
            if np.max(np.abs(expect - tau)) > scale:
                self.add("forces", s.index, fs.waypoint, f"{at}.torques: stored torques differ from g(q) - J^T f by "
                         f"{np.max(np.abs(expect - tau)):.3g} N m")
            over = np.flatnonzero(self.actuated & (np.abs(tau) > self.torque_limits + eps))
            for j in over[:3]:
                self.add("torque_limits", s.index, fs.waypoint, f"{at}.torques: stored torque tau[{j}] = "
                         f"{tau[j]:.4g} N m over the limit {self.torque_limits[j]:.4g}")
            if fs.margin < -self.tol:
                self.add("forces", s.index, fs.waypoint, f"{at}.margin: stored equilibrium margin {fs.margin:.3g} m is "
                         "negative")


__all__ = ["verify", "verify_dict", "VerifyReport", "Violation", "CHECKS", "TOLERANCE", "MOTION_TOLERANCE",
           "RESOLUTION", "robot_from_plan", "goal_met"]
