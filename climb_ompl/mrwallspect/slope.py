"""MRWALLSPECT III's transition gait between two planes across a concave or convex boundary (Kim, Kang & Choi).

Pipeline (Kim, Kang & Choi, section 3), all in the slope frame of :mod:`climb_ompl.mrwallspect.geometry`:

1. Body trajectory of lines and an arc (Eq. 7-21) for the chosen ``d``; the body advances one stride
   :math:`t_p` per gait cycle, stopping at the arc's ends (Eq. 12, 16-17, 19).
2. For every body pose :math:`S_N`, each foot is placed where the leg keeps its basic-form
   :math:`\\Upsilon` and lateral offset (Eq. 1, 23-24, section 3.3): front legs on the second plane,
   rear legs on the first, falling back to the other plane where the preferred one has no foothold.
3. Gait cycle (crawl, one leg at a time, order ``gait.leg_order``): each leg swings to its target for
   :math:`S_N` while the body stands at :math:`S_B`; then the body moves :math:`S_B \\to S_N` along the
   trajectory with all four feet attached.
4. Leg IK (analytic, Pinocchio FK round trip) at every sampled instant, Coal distance between the robot
   and both planes, the convex-edge clearance :math:`h_m > B_t` (Eq. 22, ``d`` adjusted for the fixed
   ``h``), the number of attached feet, and the equilibrium margin with suction feet as adhesion contacts
   (Kim, Kang & Choi, section 5).

``d`` is free in the paper; :func:`plan_slope` tries the robot's preferred ``d`` first, then others in
the range allowed by Eq. (10) (concave: ``R > 0``) and Eq. (22) (convex: :math:`h_m \\ge B_t` + margin),
and returns the first gait that passes every check.  The search is deterministic; ``seed`` is recorded.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from climb_ompl.errors import ARGUMENT, InputError
from climb_ompl.mrwallspect.geometry import (
    KINDS,
    BodyPose,
    BodyTrajectory,
    edge_clearance,
    foot_on_plane,
    max_d_for_clearance,
    rot_y,
)
from climb_ompl.mrwallspect.robot import FRONT, LEGS, SlopeRobot, leg_points

PLANE_LENGTH = 1.4  # m, extent of each plane away from the edge (drawing and collision)
PLANE_WIDTH = 1.0  # m, lateral extent
SLAB = 0.10  # m, thickness of the solid under each plane surface for Coal
SWING_SAMPLES = 8
BODY_SAMPLES = 6
BODY_PITCH_STEP = 0.02  # rad, largest body turn between two frames of a body move
SWING_TIME = 1.0  # s per leg swing
BODY_SPEED = 0.06  # m/s of body progress
IK_TOL = 1e-9
COLLISION_MARGIN = 0.002  # m, least Coal distance accepted between the robot and a plane (the plan's clearance)
#: Version of the ``slope`` plan content: 2 embeds the URDF, the hashes of robot and planes, and the clearance.
KIND_VERSION = 2
GRAVITY = 9.81


@dataclass
class Failure:
    """Where and why a gait candidate failed."""

    check: str
    reason: str
    where: dict[str, Any]
    progress: float  # body progress p reached, metres


@dataclass
class SlopeResult:
    """Outcome of :func:`plan_slope`.

    Attributes:
        status: ``"found"`` or ``"infeasible"``.
        reason: empty when found, else which check failed and where.
        plan: the plan dictionary (plan-file content) when found, else ``None``.
        checks: per-check results ``{name: {"ok", "value", "detail", ...}}``.
        stats: timings (s), numbers of frames, steps and candidates tried.
    """

    status: str
    reason: str
    plan: dict[str, Any] | None
    checks: dict[str, Any]
    stats: dict[str, Any] = field(default_factory=dict)

    @property
    def found(self) -> bool:
        """Whether a transition gait was found."""
        return self.status == "found"


# ---- planes ---------------------------------------------------------------------------------------
def planes(traj: BodyTrajectory, lengths: tuple[float, float] = (PLANE_LENGTH, PLANE_LENGTH)
           ) -> list[dict[str, Any]]:
    """The two foot surfaces: ``point`` (centre), ``normal``, ``direction`` (walking) and ``extent`` (m);
    ``lengths``: how far each extends from the edge."""
    out = []
    for i, (t, n) in enumerate(((traj.t1, traj.n1), (traj.t2, traj.n2))):
        sign = -1.0 if i == 0 else 1.0
        out.append({"name": f"plane{i + 1}", "point": (sign * lengths[i] / 2 * t).tolist(), "normal": n.tolist(),
                    "direction": t.tolist(), "extent": [float(lengths[i]), PLANE_WIDTH]})
    return out


def _plane_obstacles(pls: list[dict[str, Any]]) -> list[tuple[Any, Any]]:
    import coal

    obs = []
    for pl in pls:
        t, n = np.array(pl["direction"]), np.array(pl["normal"])
        rot = np.column_stack([t, np.cross(n, t), n])
        center = np.array(pl["point"]) - SLAB / 2 * n
        obs.append((coal.Box(pl["extent"][0], PLANE_WIDTH, SLAB), coal.Transform3s(rot, center)))
    return obs


def gravity_vector(tilt_deg: float) -> np.ndarray:
    """Gravity in the slope frame when the first plane is tilted by ``tilt_deg`` from a floor, m/s^2.

    ``0``: the first plane is a floor; ``90``: a vertical wall climbed upwards (``+x`` up), so a
    90-degree concave transition is wall to ceiling; ``180``: a ceiling.
    """
    a = math.radians(tilt_deg)
    return GRAVITY * np.array([-math.sin(a), 0.0, -math.cos(a)])


# ---- the gait for one d ---------------------------------------------------------------------------
class _Gait:
    """Builds and checks the gait for one value of ``d``; stops at the first failed check."""

    def __init__(self, robot: SlopeRobot, kind: str, angle: float, d: float, start_q: np.ndarray | None = None,
                 lengths: tuple[float, float] = (PLANE_LENGTH, PLANE_LENGTH)):
        self.r, self.g = robot, robot.p
        self.start_q, self.lengths = start_q, lengths
        self.traj = BodyTrajectory(kind, angle, self.g["h"], self.g["h_f"], d, self.g["X_f"])
        self.planes = planes(self.traj, lengths)
        self.obstacles = _plane_obstacles(self.planes)
        self.ups = robot.basic_upsilon()
        g = self.g
        lo, hi = abs(g["L2"] - g["L3"]) + 0.02, 0.95 * (g["L2"] + g["L3"])
        grid = np.arange(lo, hi, 0.005)
        self.upsilons = [self.ups, *sorted(grid[np.abs(grid - self.ups) > 1e-9], key=lambda u: abs(u - self.ups))]
        self.frames: list[dict[str, Any]] = []
        self.min_dist = (math.inf, None)
        self.ik_err = 0.0
        self.failure: Failure | None = None
        self.progress = -math.inf

    # foot placement (Eq. 1, 23-24)
    def _plane(self, i: int) -> tuple[np.ndarray, np.ndarray]:
        return (self.traj.n1, self.traj.t1) if i == 0 else (self.traj.n2, self.traj.t2)

    def _in_extent(self, ankle: np.ndarray, i: int) -> bool:
        n, t = self._plane(i)
        u = float((ankle - self.g["h_f"] * n) @ t)
        m = self.g["foot_radius"]
        return (-self.lengths[0] + m <= u <= -m) if i == 0 else (m <= u <= self.lengths[1] - m)

    def foothold(self, leg: str, pose: BodyPose, planes_order: tuple[int, ...]) -> tuple[np.ndarray, int] | None:
        """Ankle target of ``leg`` for a body pose: Kim, Kang & Choi, Eq. (1), (23)-(24), section 3.3.

        The basic form's :math:`\\Upsilon` is tried first on the preferred plane, then on the other;
        only when neither has a foothold is :math:`\\Upsilon` varied over the leg's workspace
        (closest to the basic value first).  That fallback extends the paper, whose fixed
        :math:`\\Upsilon` cannot follow a sharp convex edge (its conclusion leaves the link between the
        body's travel and the leg workspace open); frames record which :math:`\\Upsilon` was used.
        """
        hip, ax, la, az = self.r.leg_frame(leg, pose.origin, pose.pitch)
        for ups in self.upsilons:
            for i in planes_order:
                n, t = self._plane(i)
                cands = [a for a in foot_on_plane(hip, ax, az, self.g["foot_lateral"], la, ups, self.g["L1"],
                                                  n, self.g["h_f"], t) if self._in_extent(a, i)]
                if cands:
                    best = min(cands, key=lambda a: abs(float((a - hip) @ ax) - self.g["foot_forward"]))
                    return best, i
        return None

    def targets(self, pose: BodyPose, first: bool) -> dict[str, tuple[np.ndarray, int]] | Failure:
        out = {}
        for leg in LEGS:
            order = (0,) if first else ((1, 0) if leg in FRONT else (0, 1))
            fh = self.foothold(leg, pose, order)
            if fh is None:
                where = "plane 1" if first else "either plane"
                return Failure("reachable", f"{leg} has no foothold on {where} (Kim, Kang & Choi, Eq. 24 has "
                               f"no root in the plane's extent) with the body at case {pose.case}",
                               {"leg": leg, "case": pose.case}, self.progress)
            out[leg] = fh
        return out

    # one sampled instant
    def frame(self, t: float, pose: BodyPose, ankles: dict[str, np.ndarray], attached: dict[str, bool],
              planes_of: dict[str, int], phase: str, step: int, prev_q: np.ndarray | None) -> bool:
        legs = {}
        for leg in LEGS:
            sols = self.r.leg_ik(leg, pose.origin, pose.pitch, ankles[leg])
            if not sols:
                self.failure = Failure("reachable", f"{leg} cannot reach its ankle target "
                                       f"{np.round(ankles[leg], 4).tolist()} at t = {t:.2f} s ({phase}, step {step}, "
                                       f"case {pose.case}): out of the leg workspace or joint limits",
                                       {"t": t, "leg": leg, "phase": phase, "step": step, "case": pose.case},
                                       self.progress)
                return False
            if prev_q is not None:
                i = self.r.legs[leg].q_index
                sols.sort(key=lambda s: float(np.linalg.norm(s - prev_q[i:i + 3])))
            legs[leg] = sols[0]
        q = self.r.configuration(pose.origin, pose.pitch, legs)
        fk = self.r.ankle_positions(q)
        err = max(float(np.linalg.norm(fk[leg] - ankles[leg])) for leg in LEGS)
        self.ik_err = max(self.ik_err, err)
        dists = self.r.distances(q, self.obstacles)
        name, k, dmin = min(dists, key=lambda x: x[2])
        if dmin < self.min_dist[0]:
            self.min_dist = (dmin, {"t": t, "geometry": name, "plane": k + 1, "phase": phase, "step": step})
        if dmin <= COLLISION_MARGIN:
            self.failure = Failure("collision", f"{name} comes within {COLLISION_MARGIN * 1000:.0f} mm of plane "
                                   f"{k + 1} at t = {t:.2f} s ({phase}, step {step}, "
                                   f"case {pose.case}; Coal distance {dmin * 1000:.1f} mm)",
                                   {"t": t, "geometry": name, "plane": k + 1, "phase": phase, "step": step},
                                   self.progress)
            return False
        n_of = {0: self.traj.n1, 1: self.traj.n2}
        feet = {leg: (ankles[leg] - self.g["h_f"] * n_of[planes_of[leg]]).tolist() for leg in LEGS}
        self.frames.append({
            "t": round(t, 6), "step": step, "phase": phase, "case": pose.case,
            "body": {"origin": pose.origin.tolist(), "front": pose.front.tolist(), "pitch": pose.pitch},
            "q": q.tolist(), "attached": [bool(attached[leg]) for leg in LEGS],
            "plane": [int(planes_of[leg]) + 1 for leg in LEGS],
            "feet": [feet[leg] for leg in LEGS], "ankles": [ankles[leg].tolist() for leg in LEGS],
            "clearance": dmin,
        })
        return True

    def swing_path(self, a: np.ndarray, ia: int, b: np.ndarray, ib: int):  # noqa: ANN201
        """Ankle path of a swing, ``s in [0, 1] -> point``: lift along the start plane's normal, land along
        the target plane's; over a convex edge it passes a via point ``swing_height`` above the edge
        (foot height included) on the bisector.  Cubic Hermite segments, C1 at the via point."""
        g = self.g
        na, nb = self._plane(ia)[0], self._plane(ib)[0]
        lift = g["swing_height"] * 4.0
        if ia == ib or self.traj.kind == "concave":
            pts, tans = [a, b], [lift * na, -lift * nb]
        else:
            m = (na + nb) / np.linalg.norm(na + nb)
            via = np.array([0.0, a[1], 0.0]) + (g["swing_height"] + g["h_f"]) * m
            along = self.traj.t1 + self.traj.t2
            along *= float(np.linalg.norm(b - a)) / np.linalg.norm(along)
            pts, tans = [a, via, b], [lift * na, along, -lift * nb]
        nseg = len(pts) - 1

        def path(s: float) -> np.ndarray:
            k = min(int(s * nseg), nseg - 1)
            u = s * nseg - k
            h00, h10, h01, h11 = 2 * u**3 - 3 * u**2 + 1, u**3 - 2 * u**2 + u, -2 * u**3 + 3 * u**2, u**3 - u**2
            return h00 * pts[k] + h10 * tans[k] / nseg + h01 * pts[k + 1] + h11 * tans[k + 1] / nseg

        return path

    def build(self, max_departure_steps: int = 25) -> bool:
        g, traj = self.g, self.traj
        t_p = g["stride"]
        p = 0.0 if self.start_q is None else self.start_progress()
        if p > 1e-9:
            self.failure = Failure("start", f"the start posture's body is {p * 1000:.1f} mm past the body pose where "
                                   f"the transition begins (d = {traj.d:.3f} m)", {}, -math.inf)
            return False
        ps = [p]
        junctions = traj.junctions()
        sched = _steps_to(p, traj.p_end, t_p, junctions)
        ps.extend(sched)
        p = ps[-1]
        poses = [traj.pose(x) for x in ps]
        if self.start_q is None:
            tg = self.targets(poses[0], first=True)
            if isinstance(tg, Failure):
                self.failure = tg
                return False
        else:
            tg = {leg: (a, 0) for leg, a in self.r.ankle_positions(self.start_q).items()}
        targets = [tg]
        k = 1
        while True:
            self.progress = ps[min(k, len(ps) - 1)]
            if k >= len(ps):
                if all(targets[-1][leg][1] == 1 for leg in LEGS) or len(ps) - len(sched) > max_departure_steps:
                    break
                p += t_p
                ps.append(p)
                poses.append(traj.pose(p))
            tg = self.targets(poses[k], first=False)
            if isinstance(tg, Failure):
                self.failure = tg
                return False
            targets.append(tg)
            k += 1
        if not all(targets[-1][leg][1] == 1 for leg in LEGS):
            self.failure = Failure("reachable", "the rear feet never reach the second plane", {}, p)
            return False
        # walk the gait
        t = 0.0
        cur = {leg: targets[0][leg] for leg in LEGS}
        att = dict.fromkeys(LEGS, True)
        prev = self.start_q  # the start frame's leg IK picks the start posture's solutions
        self.progress = ps[0]
        if not self.frame(t, poses[0], {lg: cur[lg][0] for lg in LEGS}, att, {lg: cur[lg][1] for lg in LEGS},
                          "start", 0, prev):
            return False
        prev = np.array(self.frames[-1]["q"])
        for k in range(len(ps) - 1):
            pose = poses[k]
            self.progress = ps[k]
            for leg in g["leg_order"]:
                a, ia = cur[leg]
                b, ib = targets[k + 1][leg]
                if np.linalg.norm(a - b) < 1e-12 and ia == ib:
                    continue
                path = self.swing_path(a, ia, b, ib)
                for j in range(1, SWING_SAMPLES + 1):
                    s = j / SWING_SAMPLES
                    pt = path(s)
                    ankles = {lg: cur[lg][0] for lg in LEGS}
                    ankles[leg] = pt
                    att[leg] = j == SWING_SAMPLES
                    planes_of = {lg: cur[lg][1] for lg in LEGS}
                    planes_of[leg] = ib if s >= 0.5 else ia
                    t += SWING_TIME / SWING_SAMPLES
                    if not self.frame(t, pose, ankles, att, planes_of, f"swing {leg}", k, prev):
                        return False
                    prev = np.array(self.frames[-1]["q"])
                cur[leg] = (b, ib)
            dp = ps[k + 1] - ps[k]
            body_ps = _body_samples(traj, ps[k], ps[k + 1])
            dt = max(dp / BODY_SPEED, 0.2) / len(body_ps)
            for pj in body_ps:
                self.progress = pj
                t += dt
                if not self.frame(t, traj.pose(pj), {lg: cur[lg][0] for lg in LEGS}, att,
                                  {lg: cur[lg][1] for lg in LEGS}, "body", k, prev):
                    return False
                prev = np.array(self.frames[-1]["q"])
        self.steps = ps
        return True

    def start_progress(self) -> float:
        """Progress ``p`` of the start posture's body on the approach line (``p <= 0`` before the transition)."""
        o0 = self.traj.pose(0.0).origin
        o = np.array([self.start_q[0], 0.0, self.start_q[1]])
        return float((o - o0) @ self.traj.t1)


def _body_samples(traj: BodyTrajectory, p0: float, p1: float) -> list[float]:
    """Progress values of the frames of a body move from ``p0`` to ``p1`` (``p1`` last): at least
    :data:`BODY_SAMPLES`, and spaced so that the body turns at most about :data:`BODY_PITCH_STEP` between two
    frames (where the body turns fast, on a small arc or while the front crosses to the second plane, frames
    are denser), so the straight line in joint space between two frames keeps the attached feet within a
    fraction of a millimetre of their footholds."""
    fine = np.linspace(p0, p1, 257)
    pitch = np.unwrap([traj.pose(x).pitch for x in fine])
    # cumulative turn plus progress (so a straight stretch is still sampled evenly)
    measure = np.concatenate([[0.0], np.cumsum(np.abs(np.diff(pitch)) + np.diff(fine) / max(p1 - p0, 1e-12)
                                                * BODY_PITCH_STEP * BODY_SAMPLES)])
    n = max(BODY_SAMPLES, int(math.ceil(measure[-1] / BODY_PITCH_STEP)))
    out = np.interp(np.linspace(0.0, measure[-1], n + 1)[1:], measure, fine)
    out[-1] = p1
    return [float(x) for x in out]


def _steps_to(p0: float, p1: float, t_p: float, junctions: tuple[float, ...]) -> list[float]:
    from climb_ompl.mrwallspect.geometry import step_schedule

    return step_schedule(p0, p1, t_p, junctions)[1:]


# ---- checks after the build -----------------------------------------------------------------------
def _edge_check(gait: _Gait) -> dict[str, Any]:
    """Eq. (22) and the measured distance from the body's xy plane to the convex edge."""
    g, traj = gait.g, gait.traj
    need = g["B_t"] + g["clearance"]
    if traj.kind != "convex":
        return {"ok": True, "applies": False, "detail": "concave boundary: no edge under the body"}
    h_m = edge_clearance(traj.angle, g["h"], g["h_f"], traj.d)
    lo, hi = g["body_box"]["x"]
    measured = math.inf
    for f in gait.frames:
        o, pitch = np.array(f["body"]["origin"]), f["body"]["pitch"]
        rel = rot_y(pitch).T @ (np.zeros(3) - o)  # the edge point in the body frame
        if lo <= rel[0] <= hi:
            measured = min(measured, -float(rel[2]))
    ok = h_m >= need - 1e-12 and measured >= g["B_t"]
    return {"ok": bool(ok), "applies": True, "h_m_eq22": h_m,
            "h_m_measured_min": measured if math.isfinite(measured) else None, "B_t": g["B_t"],
            "required": need, "detail": f"h_m = {h_m * 1000:.1f} mm (Eq. 22), measured min {measured * 1000:.1f} mm, "
                                        f"B_t = {g['B_t'] * 1000:.1f} mm"}


def _equilibrium_check(gait: _Gait, gravity: np.ndarray, stride: int = 1) -> dict[str, Any]:
    """Margin of the CoM in the support region of the attached suction feet (adhesion contacts)."""
    try:
        from climb_ompl.equilibrium import Contact, RegionCache
    except ImportError as exc:  # the module is optional while it is being written
        return {"ok": True, "skipped": True, "detail": f"equilibrium module unavailable ({exc})"}
    g, r = gait.g, gait.r
    cache = RegionCache()
    normals = {1: gait.traj.n1, 2: gait.traj.n2}
    worst, where, margins = math.inf, None, []
    for f in gait.frames[::stride]:
        contacts = [Contact(tuple(f["feet"][j]), tuple(normals[f["plane"][j]]), g["friction"], "adhesion",
                            g["suction_force"]) for j in range(4) if f["attached"][j]]
        region = cache.get(contacts, r.mass, gravity)
        m = float(region.margin(r.com(np.array(f["q"]))))
        margins.append(m if math.isfinite(m) else None)  # None: an unbounded region (no finite margin)
        if m < worst:
            worst, where = m, {"t": f["t"], "phase": f["phase"], "step": f["step"]}
    if where is None:
        return {"ok": True, "skipped": False, "min_margin": None, "where": None, "margins": margins,
                "detail": "the attached suction feet hold the robot wherever its CoM is (unbounded support regions)"}
    return {"ok": bool(worst > 0), "skipped": False, "min_margin": worst, "where": where,
            "detail": f"min CoM margin {worst * 1000:.1f} mm in the support region of the attached suction feet "
                      f"(adhesion contacts, {g['suction_force']:g} N each) at t = {where['t']:.2f} s "
                      f"({where['phase']}, step {where['step']})",
            "margins": margins}


def _d_candidates(robot: SlopeRobot, kind: str, angle: float) -> tuple[list[float], str]:
    g = robot.p
    if kind == "concave":
        lo = g["h"] * math.tan(angle / 2) + 0.01  # Eq. (10): R = d / tan(gamma/2) - h >= 1 cm
        hi = lo + 0.3
        why = f"Eq. (10) needs d > h tan(gamma/2) = {lo - 0.01:.3f} m"
    else:
        lo = 0.02
        hi = min(max_d_for_clearance(angle, g["h"], g["h_f"], g["B_t"] + g["clearance"]), 0.6)
        why = f"Eq. (22) h_m >= B_t + clearance needs d <= {hi:.3f} m"
    if hi < lo:
        return [], why
    grid = list(np.linspace(lo, hi, 13))
    pref = min(max(g["d"], lo), hi)
    cands = sorted({round(float(x), 6) for x in [pref, *grid]}, key=lambda x: (abs(x - pref), x))
    return cands, why


def plan_slope(
    angle_deg: float,
    kind: str,
    *,
    seed: int = 0,
    tilt_deg: float = 0.0,
    d: float | None = None,
    robot: SlopeRobot | str | None = None,
    equilibrium: bool = True,
    start_q: Any = None,
    plane_lengths: tuple[float, float] = (PLANE_LENGTH, PLANE_LENGTH),
) -> SlopeResult:
    """Plan MRWALLSPECT III's transition gait across a boundary between two planes (Kim, Kang & Choi).

    Args:
        angle_deg: slope angle between the planes, degrees, in ``(0, 180)`` (Kim, Kang & Choi, Eq. 9).
        kind: ``"concave"`` (uphill / floor to wall) or ``"convex"`` (downhill / over an edge).
        seed: recorded in the plan; the planner is deterministic.
        tilt_deg: tilt of the first plane from a floor, degrees (gravity only; see :func:`gravity_vector`).
        d: marginal distance, metres; ``None`` searches the admissible range (Eq. 10, 22).
        robot: a loaded robot, a spec name/path, or ``None`` for ``mrwallspect3``.
        equilibrium: compute the equilibrium margin along the gait (adhesion contacts).
        start_q: the posture the gait starts from (slope frame: body ``x``, ``z``, pitch, then the leg joints),
            e.g. where the previous transition of a chained sequence left the robot
            (:mod:`~climb_ompl.mrwallspect.chain`).
            Its four feet on the first plane and its body on the approach line, level with the first plane,
            at or before the pose where the transition begins; the robot crawls along the first plane from
            there.  ``None``: the robot's basic form where the transition begins.
        plane_lengths: how far the first and the second plane extend from the edge, metres (feet stay on
            them; their solids are the collision obstacles).

    Returns:
        :class:`SlopeResult`; ``status == "infeasible"`` with the failed check and where, not an exception.

    Raises:
        InputError: angle outside ``(0, 180)``, unknown kind, non-positive ``d``, a start posture of the wrong
            length or not standing on the first plane.
        RobotModelError: bad robot spec or URDF.
    """
    t0 = time.perf_counter()
    _check_arguments(angle_deg, kind, d, tilt_deg)
    r = robot if isinstance(robot, SlopeRobot) else SlopeRobot.load(robot or "mrwallspect3")
    lengths = (float(plane_lengths[0]), float(plane_lengths[1]))
    if not all(math.isfinite(x) and x > 0 for x in lengths):
        raise InputError(ARGUMENT, "plane_lengths",
                         f"must be two positive lengths in metres, got {plane_lengths!r}")
    q_start = None if start_q is None else _check_start(r, start_q, lengths[0])
    angle = math.radians(angle_deg)
    cands, why = _candidates(r, kind, angle_deg, d)
    query = _query(angle_deg, kind, tilt_deg, d, q_start, lengths)
    stats: dict[str, Any] = {"candidates_tried": 0}
    gravity = gravity_vector(tilt_deg)
    found, best_fail, checks = _search_d(r, kind, angle, cands, q_start, lengths, gravity, equilibrium, stats)
    stats["plan_time_s"] = time.perf_counter() - t0
    if found is None:
        return _infeasible(best_fail, why, stats)
    stats["total_time_s"] = time.perf_counter() - t0
    stats.update(frames=len(found.frames), steps=len(found.steps) - 1, d=found.traj.d, R=found.traj.R,
                 duration_s=found.frames[-1]["t"])
    plan = _plan_dict(r, found, query, seed, gravity, checks, stats)
    return SlopeResult("found", "", plan, checks, stats)


def _check_arguments(angle_deg: float, kind: str, d: float | None, tilt_deg: float) -> None:
    """:class:`InputError` naming the first bad argument of :func:`plan_slope` among ``kind``, ``angle``, ``d`` and
    ``tilt``."""
    if kind not in KINDS:
        raise InputError(ARGUMENT, "kind", f"must be one of {', '.join(KINDS)}, got {kind!r}")
    if not (isinstance(angle_deg, (int, float)) and math.isfinite(angle_deg) and 0.0 < angle_deg < 180.0):
        raise InputError(ARGUMENT, "angle", f"must be a slope angle in degrees in (0, 180), got {angle_deg!r}")
    if d is not None and not (math.isfinite(d) and d > 0):
        raise InputError(ARGUMENT, "d", f"must be a positive distance in metres, got {d!r}")
    if not math.isfinite(tilt_deg):
        raise InputError(ARGUMENT, "tilt", f"must be finite, got {tilt_deg!r}")


def _candidates(r: SlopeRobot, kind: str, angle_deg: float, d: float | None) -> tuple[list[float], str]:
    """The values of ``d`` to try, metres, and why the range is what it is: the admissible range (Eq. 10, 22) when
    ``d`` is ``None``, else ``d`` alone.

    Raises:
        InputError: a given ``d`` that leaves a concave transition no arc (Eq. 10: ``R > 0``).
    """
    angle = math.radians(angle_deg)
    if d is None:
        return _d_candidates(r, kind, angle)
    low = r.p["h"] * math.tan(angle / 2)
    if kind == "concave" and float(d) <= low:  # Eq. (10): R = d / tan(gamma/2) - h must be positive
        raise InputError(ARGUMENT, "d", f"{d:g} m gives the body no arc at a concave {angle_deg:g} deg slope: "
                         f"Eq. (10) needs d > h tan(gamma/2) = {low:.4f} m")
    return [float(d)], "d given"


def _query(angle_deg: float, kind: str, tilt_deg: float, d: float | None, q_start: np.ndarray | None,
           lengths: tuple[float, float]) -> dict[str, Any]:
    """The plan's ``query``: what was asked (``start_q`` and ``plane_lengths`` only when given)."""
    query: dict[str, Any] = {"angle": float(angle_deg), "kind": kind, "tilt": float(tilt_deg), "d": d}
    if q_start is not None:
        query["start_q"] = q_start.tolist()
    if lengths != (PLANE_LENGTH, PLANE_LENGTH):
        query["plane_lengths"] = list(lengths)
    return query


def _search_d(r: SlopeRobot, kind: str, angle: float, cands: list[float], q_start: np.ndarray | None,
              lengths: tuple[float, float], gravity: np.ndarray, equilibrium: bool, stats: dict[str, Any]
              ) -> tuple[_Gait | None, Failure | None, dict[str, Any]]:
    """Build the gait for each ``d`` of ``cands`` in turn (``angle`` in radians) until one passes every check.

    Returns:
        ``(gait, None, checks)`` for the first gait that passes, else ``(None, failure, {})`` with the failure that
        got furthest (``None`` when no candidate was tried); ``stats["candidates_tried"]`` counts the candidates.
    """
    best_fail: Failure | None = None
    for dc in cands:
        stats["candidates_tried"] += 1
        gait = _Gait(r, kind, angle, dc, q_start, lengths)
        if kind == "convex":
            edge = edge_clearance(angle, r.p["h"], r.p["h_f"], dc)
            if edge < r.p["B_t"] + r.p["clearance"]:
                fail = Failure("edge_clearance", f"Eq. (22): h_m = {edge * 1000:.1f} mm < B_t + clearance = "
                               f"{(r.p['B_t'] + r.p['clearance']) * 1000:.1f} mm for d = {dc:.3f} m", {"d": dc}, -1.0)
                best_fail = best_fail or fail
                continue
        if gait.build():
            checks = _final_checks(gait, gravity, equilibrium)
            failed = [k for k, v in checks.items() if not v["ok"]]
            if not failed:
                return gait, None, checks
            fail = Failure(failed[0], checks[failed[0]]["detail"], {"d": dc, **(checks[failed[0]].get("where") or {})},
                           math.inf)
        else:
            fail = gait.failure
            fail.where["d"] = dc
        if best_fail is None or fail.progress > best_fail.progress:
            best_fail = fail
    return None, best_fail, {}


def _infeasible(best_fail: Failure | None, why: str, stats: dict[str, Any]) -> SlopeResult:
    """The :class:`SlopeResult` of a search that found no gait: the failure that got furthest, or no admissible
    ``d`` (``why``)."""
    if best_fail is None:
        reason = f"no admissible d: {why}"
        checks = {"d_range": {"ok": False, "detail": reason}}
    else:
        reason = (f"{best_fail.check} failed: {best_fail.reason} (best of {stats['candidates_tried']} values of d, "
                  f"d = {best_fail.where.get('d', float('nan')):.3f} m)")
        checks = {best_fail.check: {"ok": False, "detail": best_fail.reason, "where": best_fail.where}}
    return SlopeResult("infeasible", reason, None, checks, stats)


def _check_start(r: SlopeRobot, start_q: Any, length: float) -> np.ndarray:
    """``start_q`` as an array, or :class:`InputError` when it cannot start a gait on the first plane."""
    try:
        q = np.asarray(start_q, dtype=float).reshape(-1)
    except (TypeError, ValueError):
        raise InputError(ARGUMENT, "start_q", "must be a list of numbers") from None
    if len(q) != r.nq or not np.all(np.isfinite(q)):
        raise InputError(ARGUMENT, "start_q", f"must be {r.nq} finite numbers (body x, z, pitch, 4 x 3 leg "
                         f"joints), got {len(q)}")
    H = r.p["h"] + r.p["h_f"]
    if abs(q[2]) > 1e-6 or abs(q[1] - H) > 1e-6:
        raise InputError(ARGUMENT, "start_q", f"the body must stand level on the first plane (pitch 0, "
                         f"height {H:g} m), got pitch {q[2]:.4g} rad, height {q[1]:.4g} m")
    for leg, a in r.ankle_positions(q).items():
        u = float(a[0])
        if abs(float(a[2]) - r.p["h_f"]) > 1e-6 or not -length + r.p["foot_radius"] <= u <= -r.p["foot_radius"]:
            raise InputError(ARGUMENT, "start_q", f"{leg}'s foot is not on the first plane (ankle at "
                             f"{np.round(a, 4).tolist()})")
    return q


def _final_checks(gait: _Gait, gravity: np.ndarray, equilibrium: bool) -> dict[str, Any]:
    n_att = [sum(f["attached"]) for f in gait.frames]
    checks: dict[str, Any] = {
        "reachable": {"ok": True, "detail": f"all {4 * len(gait.frames)} ankle targets reached within joint limits"},
        "ik_round_trip": {"ok": gait.ik_err <= IK_TOL, "value": gait.ik_err,
                          "detail": f"max |FK(IK(target)) - target| = {gait.ik_err:.2e} m (Pinocchio FK)"},
        "collision": {"ok": gait.min_dist[0] > COLLISION_MARGIN, "value": gait.min_dist[0], "where": gait.min_dist[1],
                      "detail": f"min Coal distance robot-planes {gait.min_dist[0] * 1000:.1f} mm"},
        "support": {"ok": min(n_att) >= 3, "value": min(n_att), "detail": f"at least {min(n_att)} feet attached"},
        "edge_clearance": _edge_check(gait),
    }
    if equilibrium:
        eq = _equilibrium_check(gait, gravity)
        margins = eq.pop("margins", None)
        if margins is not None:
            for f, m in zip(gait.frames, margins, strict=True):
                f["equilibrium_margin"] = m
        checks["equilibrium"] = eq
    return checks


def _plan_dict(r: SlopeRobot, gait: _Gait, query: dict[str, Any], seed: int, gravity: np.ndarray,
               checks: dict[str, Any], stats: dict[str, Any]) -> dict[str, Any]:
    from climb_ompl._version import __version__
    from climb_ompl.plan.file import robot_record, sha256_json

    traj = gait.traj
    pls = gait.planes
    return {
        "schema_version": 1,
        "kind": "slope",
        "kind_version": KIND_VERSION,
        "climb_ompl_version": __version__,
        "seed": int(seed),
        "query": query,
        "planes": pls,
        "planes_sha256": sha256_json(pls),
        "clearance": COLLISION_MARGIN,
        "gravity": gravity.tolist(),
        "robot": {**robot_record(r), "legs": list(LEGS)},
        "trajectory": {"kind": traj.kind, "angle_rad": traj.angle, "d": traj.d, "R": traj.R, "h": traj.h,
                       "h_f": traj.h_f, "P_S": traj.P_S.tolist(), "P_E": traj.P_E.tolist(),
                       "P_R": traj.P_R.tolist(), "steps": list(gait.steps)},
        "frames": gait.frames,
        "checks": checks,
        "stats": stats,
    }


# ---- drawing --------------------------------------------------------------------------------------
def scene_items(plan: dict[str, Any]) -> dict[str, Any]:
    """What to draw for a slope plan, as plain numpy arrays (no meshcat import).

    Returns:
        The scene-item format of :mod:`climb_ompl.viz` (``"times"`` (T,) s and ``"items"``: the two planes
        as thin boxes, the body box with a pose per frame, each leg as a polyline hip - joint 2 - knee -
        ankle per frame, each foot as a sphere visible while attached, the path of :math:`O_B`), plus the
        same content by frame for other users: ``"planes"`` ``[{"name", "corners" (4, 3)}]``,
        ``"body_box"`` ``{"size" (3,), "center" (3,) in the body frame}`` and ``"frames"``
        ``[{"t", "body_pose" (4, 4) world-from-body, "legs" [(4, 3) per leg], "feet" (4, 3) soles,
        "attached" (4,) bool}]``.  Slope frame, metres.
    """
    from climb_ompl.mrwallspect.robot import Leg

    g = plan["robot"]["spec"]["gait"]
    out_planes = []
    for pl in plan["planes"]:
        p, n, t = (np.asarray(pl[k], dtype=float) for k in ("point", "normal", "direction"))
        lat = np.cross(n, t)
        a, b = pl["extent"][0] / 2, pl["extent"][1] / 2
        out_planes.append({"name": pl["name"], "corners": np.array([p + sa * a * t + sb * b * lat for sa, sb in
                                                                     ((-1, -1), (1, -1), (1, 1), (-1, 1))])})
    box = g["body_box"]
    lo = np.array([box["x"][0], box["y"][0], box["z"][0]])
    hi = np.array([box["x"][1], box["y"][1], box["z"][1]])
    X, Yf, Yr = g["X_f"], g["Y_f"], g["Y_r"]
    hips = {"leg1": (X, Yf / 2, 1.0), "leg2": (X, -Yf / 2, -1.0), "leg3": (0.0, Yr / 2, 1.0),
            "leg4": (0.0, -Yr / 2, -1.0)}
    legs = {n: Leg(n, np.array([x, y, 0.0]), _rz(side * math.pi / 2), side, 1.0, 3 + 3 * i, np.zeros(3), np.zeros(3))
            for i, (n, (x, y, side)) in enumerate(hips.items())}
    frames = []
    for f in plan["frames"]:
        q = np.asarray(f["q"], dtype=float)
        origin = np.array([q[0], 0.0, q[1]])
        T = np.eye(4)
        T[:3, :3] = rot_y(q[2])
        T[:3, 3] = origin
        pts = [np.array(leg_points(g, legs[n], origin, q[2], q[legs[n].q_index:legs[n].q_index + 3]))
               for n in LEGS]
        frames.append({"t": float(f["t"]), "body_pose": T, "legs": pts, "feet": np.asarray(f["feet"], dtype=float),
                       "attached": np.asarray(f["attached"], dtype=bool)})
    size, center = hi - lo, (hi + lo) / 2
    items: list[dict[str, Any]] = []
    for pl, quad in zip(plan["planes"], out_planes, strict=True):
        n, t = np.asarray(pl["normal"], dtype=float), np.asarray(pl["direction"], dtype=float)
        T = np.eye(4)
        T[:3, :3] = np.column_stack([t, np.cross(n, t), n])
        T[:3, 3] = quad["corners"].mean(axis=0) - 0.005 * n
        items.append({"name": pl["name"], "kind": "box", "size": [pl["extent"][0], pl["extent"][1], 0.01],
                      "pose": T, "color": "#8b6b4a", "opacity": 0.8})
    offset = np.eye(4)
    offset[:3, 3] = center
    items.append({"name": "body", "kind": "box", "size": size, "poses": [f["body_pose"] @ offset for f in frames],
                  "color": "#3070b0"})
    for j, n in enumerate(LEGS):
        items.append({"name": n, "kind": "polyline", "points": [f["legs"][j] for f in frames], "color": "#202020",
                      "radius": 0.012})
        items.append({"name": f"{n}_foot", "kind": "sphere", "radius": g["foot_radius"],
                      "positions": np.array([f["feet"][j] for f in frames]), "color": "#30a030",
                      "visible": [bool(f["attached"][j]) for f in frames]})
    items.append({"name": "body_path", "kind": "polyline", "color": "#e08020", "radius": 0.004,
                  "points": np.array([f["body_pose"][:3, 3] for f in frames])})
    return {"times": np.array([f["t"] for f in frames]), "items": items, "planes": out_planes,
            "body_box": {"size": size, "center": center}, "frames": frames}


def _rz(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
