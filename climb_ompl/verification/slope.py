"""Independent verification of a slope-transition plan (``kind: "slope"``), Kim, Kang & Choi (MRWALLSPECT III).

:func:`verify_slope` re-checks the plan file's contents without the gait planner's code.  The robot is
rebuilt with Pinocchio from the URDF embedded in the plan (hashes checked), the two planes from the plan
(hash checked) as Coal solids (concave boundary: a thick slab under each plane; convex boundary: the wedge
between them, one convex prism), and the body trajectory is re-derived from the paper's equations: the body
lines :math:`\\Pi_{ih}` (Eq. 7-8) at ``h_f + h`` above the foot surfaces, the arc of radius ``R`` (Eq. 10
concave, Eq. 11 convex) tangent to both, its centre ``P_R`` and its ends ``P_S``, ``P_E``.

The motion between two consecutive frames is the straight line between their configurations ``q``; it is
checked at frames and at states in between, at most ``resolution`` apart (max-norm, rad or m):

* ``integrity``: the planes, robot spec and URDF match their hashes; configurations fit the robot; a plan
  started from a given posture (``query.start_q``, a chained transition) starts from it; the query's ``tilt``,
  ``d`` and ``plane_lengths`` are the plan's gravity, ``d`` and plane extents; ``robot.legs`` are the spec's limbs
  in order; the frames' ``phase`` and ``step`` labels are those of the crawl gait (section 3: a step's swings,
  one leg at a time with the other three attached, then its body move with all four);
* ``trajectory``: the stated ``R``, ``P_S``, ``P_E``, ``P_R`` are those of Eq. 7-11 for the stated kind,
  angle, ``d``, ``h``, ``h_f``, and the planes meet at that angle; at every frame the body's origin ``O`` and
  front ``F`` (``|F - O| = X_f``) follow the line-arc-line trajectory: concave, both on it (Eq. 12-18);
  convex, on it before and after the transition and, during it, on the arc's tangent at ``P_T`` with
  ``|P_T - O| = X_f (gamma - theta_R) / gamma`` (Eq. 19-21); the pitch is Eq. 15's; ``q`` carries that pose;
* ``feet_on_planes``: an attached foot's sole is on the plane it claims (within the plane's extent), its
  ankle (Pinocchio FK) is ``h_f`` above it, and it does not slide while attached; at every frame the stored
  ``ankles`` and ``feet`` (soles, swinging feet included) are those of the frame's ``q``;
* ``support``: at least three feet attached at every instant (a foot attached at both ends of an interval
  holds during it);
* ``joint_limits``: every joint within the URDF limits;
* ``clearance``: every collision body of the robot at least the plan's ``clearance`` from both planes (Coal); a
  frame's stored ``clearance`` is that distance;
* ``equilibrium``: contact forces in the attached suction feet's adhesion cones (:mod:`climb_ompl.equilibrium`,
  contact kind ``"adhesion"``, ``suction_force`` and ``friction`` of the robot spec) balance gravity with the
  centre of mass where it is: inside the stance's support region, else an exact per-point cone program; a
  frame's stored ``equilibrium_margin`` is the CoM's signed distance to that region's boundary;
* ``goal``: the transition is complete: at the last frame all four feet hold plane 2 and ``O`` is past ``P_E``.

Each violation names the gait step and the frame (fractional between frames) with its time; one about a stored
field names its JSON path (``$.frames[3].ankles[1]``).  ``docs/plan-file.md`` lists every stored field, who reads
it and how it is checked.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from climb_ompl.verification.report import Recorder, VerifyReport

#: Tolerance at frames: feet on planes, ankle heights, trajectory and pose agreement, and the stored per-frame values
#: (ankles, soles, clearance, equilibrium margin) against their recomputation, metres.
TOLERANCE = 1e-6
#: Tolerance on an attached foot's ankle between frames (the chord of the straight line in ``q``), metres.
MOTION_TOLERANCE = 5e-4
#: Joint-space step between the states checked between frames (max-norm, rad or m).
RESOLUTION = 0.02
#: Thickness of the solid modelled under each plane of a concave boundary, metres.
SLAB = 0.5

CHECKS: tuple[str, ...] = ("integrity", "trajectory", "feet_on_planes", "support", "joint_limits", "clearance",
                           "equilibrium", "goal")


def _rot_y(a: float) -> np.ndarray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


# ---- the trajectory of Eq. 7-11, from the plane geometry ----------------------------------------------------
class _Trajectory:
    """The line-arc-line body trajectory in the sagittal (x-z) plane, Kim, Kang & Choi Eq. 7-11.

    Both body lines lie ``H = h_f + h`` above their foot surfaces ``n_i . p = c_i``; the arc of radius ``R``
    touches both, with its centre on the robot's side of both lines (concave) or on the far side (convex).
    """

    def __init__(self, kind: str, gamma: float, d: float, h: float, h_f: float, planes: list[dict[str, Any]]):
        self.kind, self.gamma = kind, gamma
        self.n = [np.asarray(p["normal"], float) / np.linalg.norm(p["normal"]) for p in planes]
        self.t = [np.asarray(p["direction"], float) / np.linalg.norm(p["direction"]) for p in planes]
        self.c = [float(n @ np.asarray(p["point"], float)) for n, p in zip(self.n, planes, strict=True)]
        H = h_f + h
        self.R = d / math.tan(gamma / 2) - h if kind == "concave" else d / math.tan(gamma / 2) + h  # Eq. 10 / 11
        off = H + self.R if kind == "concave" else H - self.R
        A = np.array([[self.n[0][0], self.n[0][2]], [self.n[1][0], self.n[1][2]]])
        x, z = np.linalg.solve(A, [self.c[0] + off, self.c[1] + off])
        self.P_R = np.array([x, 0.0, z])
        s = 1.0 if kind == "concave" else -1.0
        self.P_S = self.P_R - s * self.R * self.n[0]
        self.P_E = self.P_R - s * self.R * self.n[1]

    def distance(self, p: np.ndarray) -> float:
        """Distance (x-z plane) from ``p`` to the trajectory: line 1 up to ``P_S``, the arc, line 2 from ``P_E``."""
        p = np.array([p[0], 0.0, p[2]])
        t1, t2 = self.t
        d1 = np.linalg.norm(p - (self.P_S + min(float((p - self.P_S) @ t1), 0.0) * t1))
        d2 = np.linalg.norm(p - (self.P_E + max(float((p - self.P_E) @ t2), 0.0) * t2))
        a, b, v = self.P_S - self.P_R, self.P_E - self.P_R, p - self.P_R
        on_arc = (np.cross(a, v) @ np.cross(a, b) >= 0) and (np.cross(v, b) @ np.cross(a, b) >= 0)
        d3 = abs(np.linalg.norm(v) - self.R) if on_arc else math.inf
        return float(min(d1, d2, d3))


# ---- the verifier ------------------------------------------------------------------------------------------
def verify_slope(plan: dict[str, Any], source: str = "<plan>", *, resolution: float = RESOLUTION,
                 max_per_check: int = 50, **_: Any) -> VerifyReport:
    """Re-check a slope-transition plan dict (schema-checked, every number finite); see the module docstring.

    Args:
        plan: the plan-file dict (``kind: "slope"``).
        source: where it came from (for messages).
        resolution: joint-space step between the states checked between frames.
        max_per_check: list at most this many violations per check (the counts stay exact).

    Raises:
        PlanFileError: the embedded URDF cannot be loaded, or the robot spec lacks a parameter.
    """
    return _SlopeVerifier(plan, source, resolution, Recorder(max_per_check)).run()


class _SlopeVerifier:
    def __init__(self, plan: dict[str, Any], source: str, resolution: float, rec: Recorder):
        import pinocchio as pin

        from climb_ompl.errors import PlanFileError

        self.plan, self.src, self.res, self.rec = plan, source, resolution, rec
        rob = plan["robot"]
        try:
            self.model = pin.buildModelFromXML(rob["urdf"])
            self.geom = pin.buildGeomFromUrdfString(self.model, rob["urdf"], pin.COLLISION)
        except (ValueError, RuntimeError) as exc:
            raise PlanFileError(source, "$.robot.urdf", f"cannot load the embedded URDF ({exc})") from None
        self.data, self.gdata = self.model.createData(), pin.GeometryData(self.geom)
        g = rob["spec"]["gait"]
        try:
            self.X_f, self.h_f = float(g["X_f"]), float(g["h_f"])
            self.friction, self.suction = float(g["friction"]), float(g["suction_force"])
        except (KeyError, TypeError, ValueError) as exc:
            raise PlanFileError(source, "$.robot.spec.gait", f"missing or bad parameter ({exc})") from None
        limbs = {lb["name"]: lb["hand_frame"] for lb in rob["spec"].get("limbs", [])}
        self.ankles = []
        for leg in rob["legs"]:
            fid = self.model.getFrameId(limbs.get(leg, f"{leg}_ankle"))
            if fid >= self.model.nframes:
                raise PlanFileError(source, "$.robot.legs", f"no ankle frame for {leg!r} in the URDF")
            self.ankles.append(fid)
        self.mass = float(sum(i.mass for i in self.model.inertias))
        self.n = [np.asarray(p["normal"], float) / np.linalg.norm(p["normal"]) for p in plan["planes"]]
        self.regions: dict[Any, Any] = {}

    # -- plan level ---------------------------------------------------------------------------------------
    def run(self) -> VerifyReport:
        from climb_ompl.plan.file import sha256_json, sha256_text

        p, rec = self.plan, self.rec
        if sha256_json(p["planes"]) != p["planes_sha256"]:
            rec.add("integrity", None, None, "$.planes do not match $.planes_sha256 (tampered planes)")
        if sha256_json(p["robot"]["spec"]) != p["robot"]["spec_sha256"]:
            rec.add("integrity", None, None, "$.robot.spec does not match $.robot.spec_sha256")
        if sha256_text(p["robot"]["urdf"]) != p["robot"]["urdf_sha256"]:
            rec.add("integrity", None, None, "$.robot.urdf does not match $.robot.urdf_sha256")
        frames = p["frames"]
        steps = 1 + max(f["step"] for f in frames)
        bad = [i for i, f in enumerate(frames) if len(f["q"]) != self.model.nq]
        if bad:
            rec.add("integrity", frames[bad[0]]["step"], bad[0], f"$.frames[{bad[0]}].q has "
                    f"{len(frames[bad[0]]['q'])} values, the robot has nq = {self.model.nq}")
            return rec.report(steps)
        start = p.get("query", {}).get("start_q")
        if start is not None and (len(start) != self.model.nq
                                  or float(np.max(np.abs(np.asarray(frames[0]["q"], float) - start))) > TOLERANCE):
            rec.add("integrity", frames[0]["step"], 0, "the first frame is not the start posture the query gives "
                    "($.query.start_q)")
        self.traj = self._check_trajectory()
        self._check_query()
        self._check_labels(frames)
        self.obstacles = self._plane_solids()
        self.g = np.asarray(p["gravity"], float)
        self.lo, self.hi = np.asarray(self.model.lowerPositionLimit), np.asarray(self.model.upperPositionLimit)
        for i, f in enumerate(frames):
            q = np.asarray(f["q"], float)
            att = np.asarray(f["attached"], bool)
            self._check_frame(i, f, q, att)
            self._check_state(f["step"], float(i), f["t"], q, f, att, TOLERANCE, frame=i)
            if i + 1 < len(frames):
                self._check_interval(i, f, frames[i + 1])
        last = frames[-1]
        o = np.asarray(last["body"]["origin"], float)
        if self.traj is not None and (not all(last["attached"]) or any(k != 2 for k in last["plane"])
                                      or float((o - self.traj.P_E) @ self.traj.t[1]) < -TOLERANCE):
            rec.add("goal", last["step"], len(frames) - 1, "the transition is not complete: the last frame does not "
                    "have all four feet attached on plane 2 and the body origin past P_E")
        return rec.report(steps)

    def _check_trajectory(self) -> _Trajectory | None:
        p, rec = self.plan, self.rec
        tr = p["trajectory"]
        g = tr["angle_rad"]
        t1, t2 = (np.asarray(pl["direction"], float) for pl in p["planes"])
        n1 = self.n[0]
        between = math.acos(float(np.clip(t1 @ t2 / np.linalg.norm(t1) / np.linalg.norm(t2), -1, 1)))
        kind = "concave" if float(n1 @ t2) > 0 else "convex"
        if abs(between - g) > 1e-9 or kind != tr["kind"]:
            rec.add("trajectory", None, None, f"the planes meet at a {kind} {math.degrees(between):.3f} deg boundary, "
                    f"the trajectory is for a {tr['kind']} {math.degrees(g):.3f} deg one")
        q = p.get("query") or {}
        if q.get("kind") != tr["kind"] or not isinstance(q.get("angle"), (int, float)) \
                or abs(math.radians(float(q["angle"])) - g) > 1e-9:
            rec.add("integrity", None, None, f"the query asks for a {q.get('kind')} {q.get('angle')} deg slope "
                    f"($.query.kind, .angle), the plan crosses a {tr['kind']} {math.degrees(g):.6g} deg one")
        for k, (pl, n) in enumerate(zip(p["planes"], self.n, strict=True)):
            t = np.asarray(pl["direction"], float)
            if abs(float(n @ t)) > 1e-9 or abs(float(n @ np.asarray(pl["point"], float))) > 1e-9 \
                    or abs(float(n[1])) > 1e-9:
                rec.add("trajectory", None, None, f"plane {k + 1} does not contain the boundary edge (the y axis) "
                        "with its direction in it")
        if tr["kind"] == "concave" and tr["d"] / math.tan(g / 2) - tr["h"] <= 0:
            rec.add("trajectory", None, None, "Eq. 10 gives no arc (d / tan(gamma/2) <= h)")
            return None
        traj = _Trajectory(tr["kind"], g, tr["d"], tr["h"], tr["h_f"], p["planes"])
        if abs(traj.R - tr["R"]) > TOLERANCE:
            eq = 10 if tr["kind"] == "concave" else 11
            rec.add("trajectory", None, None, f"$.trajectory.R = {tr['R']:.6g} m, Eq. {eq} gives {traj.R:.6g} m for "
                    f"$.trajectory.d = {tr['d']:.6g} m")
        for name in ("P_S", "P_E", "P_R"):
            err = float(np.linalg.norm(np.asarray(tr[name], float) - getattr(traj, name)))
            if err > TOLERANCE:
                rec.add("trajectory", None, None, f"$.trajectory.{name} is {err:.3g} m from the one of Eq. 7-11 for "
                        f"$.trajectory.d = {tr['d']:.6g} m")
        spec = self.plan["robot"]["spec"]["gait"]
        if abs(tr["h"] - spec["h"]) > 1e-12 or abs(tr["h_f"] - spec["h_f"]) > 1e-12:
            rec.add("trajectory", None, None, "$.trajectory.h, .h_f are not the robot's")
        return traj

    def _check_query(self) -> None:
        """What the plan says it was asked (``query``) against what it holds: the gravity of the first plane's tilt
        (``|g|`` as stored; the first plane ``tilt`` degrees from a floor, so ``g`` points along
        ``(-sin tilt, 0, -cos tilt)`` in the slope frame), the ``d`` and the plane lengths asked for; and the legs
        in the order of the robot spec's limbs (playback draws ``feet[j]`` and the legs in that order)."""
        p, rec = self.plan, self.rec
        q = p.get("query") or {}
        g = np.asarray(p["gravity"], float)
        tilt = q.get("tilt")
        if isinstance(tilt, (int, float)) and float(np.linalg.norm(g)) > 0:
            a = math.radians(float(tilt))
            err = float(np.linalg.norm(g / np.linalg.norm(g) - [-math.sin(a), 0.0, -math.cos(a)]))
            if err > 1e-9:
                rec.add("integrity", None, None, f"$.gravity {np.round(g, 4).tolist()} m/s^2 is not along the gravity "
                        f"of the first plane's tilt ($.query.tilt = {float(tilt):g} deg)")
        if isinstance(q.get("d"), (int, float)) and abs(float(q["d"]) - p["trajectory"]["d"]) > 1e-12:
            rec.add("integrity", None, None, f"$.trajectory.d = {p['trajectory']['d']:.6g} m, but the query asked for "
                    f"$.query.d = {float(q['d']):.6g} m")
        lengths = q.get("plane_lengths")
        if isinstance(lengths, list) and len(lengths) == 2:
            for k, (pl, want) in enumerate(zip(p["planes"], lengths, strict=True)):
                if isinstance(want, (int, float)) and abs(pl["extent"][0] - float(want)) > 1e-12:
                    rec.add("integrity", None, None, f"$.planes[{k}].extent[0] = {pl['extent'][0]:g} m, but the query "
                            f"asked for $.query.plane_lengths[{k}] = {float(want):g} m")
        names = [lb.get("name") for lb in p["robot"]["spec"].get("limbs", []) if isinstance(lb, dict)]
        if names and list(p["robot"]["legs"]) != names:
            rec.add("integrity", None, None, f"$.robot.legs = {p['robot']['legs']} is not the robot spec's limbs in "
                    f"order ({names})")

    def _check_labels(self, frames: list[dict[str, Any]]) -> None:
        """The frames' ``phase`` and ``step`` labels against the crawl gait they label (Kim, Kang & Choi, section 3):
        frame 0 is the ``start`` of step 0; in a ``swing <leg>`` frame every other leg is attached, in a ``body``
        frame all four; a step's swings come before its body move, and the step number goes up by one, only after
        a body move."""
        rec, legs = self.rec, list(self.plan["robot"]["legs"])
        known = {"start", "body", *(f"swing {leg}" for leg in legs)}
        if frames[0]["phase"] != "start" or frames[0]["step"] != 0:
            rec.add("integrity", frames[0]["step"], 0, f"$.frames[0] is {frames[0]['phase']!r} of step "
                    f"{frames[0]['step']}, not the start of step 0")
        for i, f in enumerate(frames):
            ph, att = f["phase"], f["attached"]
            if ph not in known or (ph == "start" and i > 0):
                rec.add("integrity", f["step"], i, f"$.frames[{i}].phase = {ph!r} is not a phase of the gait (start "
                        "at frame 0, swing <leg> of the robot's legs, body)")
            elif ph == "body" and not all(att):
                rec.add("integrity", f["step"], i, f"$.frames[{i}].phase = 'body' but not every foot is attached "
                        f"($.frames[{i}].attached = {att})")
            elif ph.startswith("swing "):
                j = legs.index(ph[len("swing "):])
                if not all(a for k, a in enumerate(att) if k != j):
                    rec.add("integrity", f["step"], i, f"$.frames[{i}].phase = {ph!r} but a foot other than "
                            f"{legs[j]}'s is detached ($.frames[{i}].attached = {att})")
            if i == 0:
                continue
            prev = frames[i - 1]
            up = f["step"] - prev["step"]
            if up not in (0, 1) or (up == 1 and prev["phase"] != "body") or \
                    (up == 0 and prev["phase"] == "body" and ph != "body"):
                rec.add("integrity", f["step"], i, f"$.frames[{i}].step = {f['step']} ({ph!r}) after {prev['phase']!r} "
                        f"of step {prev['step']}: a step's swings come before its body move, and the next step begins "
                        "after it")

    def _plane_solids(self) -> list[Any]:
        """Coal solids of the planes: a slab under each (concave) or the wedge between them (convex)."""
        import coal

        def hull(points: list[np.ndarray]) -> Any:
            v = coal.StdVec_Vec3s()
            for x in points:
                v.append(np.asarray(x, float))
            return coal.Convex.convexHull(v, False, "")

        corners = []
        for pl, n in zip(self.plan["planes"], self.n, strict=True):
            t = np.asarray(pl["direction"], float)
            lat = np.cross(n, t)
            c = np.asarray(pl["point"], float)
            a, b = pl["extent"][0] / 2, pl["extent"][1] / 2
            corners.append([c + sa * a * t + sb * b * lat for sa in (-1, 1) for sb in (-1, 1)])
        if self.plan["trajectory"]["kind"] == "convex":
            return [hull(corners[0] + corners[1])]
        return [hull(cs + [x - SLAB * n for x in cs]) for cs, n in zip(corners, self.n, strict=True)]

    # -- per frame ------------------------------------------------------------------------------------------
    def _check_frame(self, i: int, f: dict[str, Any], q: np.ndarray, att: np.ndarray) -> None:
        rec, step = self.rec, f["step"]
        o, fr, pitch = (np.asarray(f["body"][k], float) for k in ("origin", "front", "pitch"))
        pitch = float(pitch)
        where = f"(t = {f['t']:.2f} s)"
        if abs(q[0] - o[0]) > TOLERANCE or abs(q[1] - o[2]) > TOLERANCE or abs(q[2] - pitch) > TOLERANCE \
                or abs(o[1]) > TOLERANCE:
            rec.add("trajectory", step, i, f"q does not put the body at its stated origin and pitch "
                    f"($.frames[{i}].body) {where}")
        u = _rot_y(pitch) @ np.array([1.0, 0.0, 0.0])
        if np.linalg.norm(fr - (o + self.X_f * u)) > TOLERANCE:
            rec.add("trajectory", step, i, f"the front F ($.frames[{i}].body.front) is not X_f = {self.X_f} m ahead "
                    f"of O along the body (Eq. 15) {where}")
        tr = self.traj
        if tr is None:
            return
        if tr.kind == "concave":
            dev = max(tr.distance(o), tr.distance(fr))
        else:
            dev = self._convex_deviation(o, fr, pitch)
        if dev > TOLERANCE:
            rec.add("trajectory", step, i, f"the body is {dev * 1000:.3f} mm off the line-arc-line trajectory {where}")

    def _convex_deviation(self, o: np.ndarray, fr: np.ndarray, pitch: float) -> float:
        """How far a convex-transition body pose is from Eq. 19-21 (line 1, the arc's tangent, or line 2)."""
        tr = self.traj
        g = tr.gamma
        theta = -pitch if pitch < -1e-12 else pitch  # the body turns by theta_R in [0, gamma] over the edge
        if theta <= 1e-9:  # before the transition: on line 1, the front not past P_S
            return max(tr.distance(o), tr.distance(fr), max(float((fr - tr.P_S) @ tr.t[0]), 0.0))
        if theta >= g - 1e-9:  # after it: on line 2, the origin past P_E
            return max(tr.distance(o), tr.distance(fr), max(float((tr.P_E - o) @ tr.t[1]), 0.0))
        u = (fr - o) / np.linalg.norm(fr - o)
        p_t = tr.P_R + tr.R * (_rot_y(pitch) @ tr.n[0])  # the arc's point whose tangent is the body axis
        off_line = float(np.linalg.norm(np.cross(p_t - o, u)))
        ratio = abs(float((p_t - o) @ u) - self.X_f * (g - theta) / g)  # Eq. 21
        return max(off_line, ratio)

    def _check_interval(self, i: int, a: dict[str, Any], b: dict[str, Any]) -> None:
        rec = self.rec
        qa, qb = np.asarray(a["q"], float), np.asarray(b["q"], float)
        att = np.asarray(a["attached"], bool) & np.asarray(b["attached"], bool)
        if b["t"] < a["t"]:
            rec.add("integrity", b["step"], i + 1, f"time goes back from {a['t']} s to {b['t']} s "
                    f"($.frames[{i + 1}].t)")
        for j in np.flatnonzero(att):
            if np.linalg.norm(np.asarray(a["feet"][j], float) - np.asarray(b["feet"][j], float)) > TOLERANCE \
                    or a["plane"][j] != b["plane"][j]:
                rec.add("feet_on_planes", b["step"], i + 1, f"attached foot {j + 1} slides between frames {i} and "
                        f"{i + 1}")
        if att.sum() < 3:
            rec.add("support", b["step"], i + 0.5, f"only {int(att.sum())} feet attached between frames {i} and "
                    f"{i + 1} (t = {a['t']:.2f}-{b['t']:.2f} s)")
        n_sub = int(math.ceil(float(np.max(np.abs(qb - qa))) / self.res))
        for k in range(1, n_sub):
            s = k / n_sub
            self._check_state(b["step"], i + s, (1 - s) * a["t"] + s * b["t"], (1 - s) * qa + s * qb, a, att,
                              MOTION_TOLERANCE)

    def _check_state(self, step: int, wp: float, t: float, q: np.ndarray, f: dict[str, Any], att: np.ndarray,
                     tol: float, frame: int | None = None) -> None:
        """Check configuration ``q`` (frame ``f``'s, or between it and the next: the feet of ``f`` held) at
        ``wp``; at a frame (its index ``frame``) the frame's stored values too (:meth:`_check_stored`)."""
        import coal
        import pinocchio as pin

        rec = self.rec
        rec.states += 1
        where = f"(t = {t:.2f} s)"
        bad = np.flatnonzero((q < self.lo - 1e-9) | (q > self.hi + 1e-9))
        for j in bad[:3]:
            rec.add("joint_limits", step, wp, f"q[{j}] = {q[j]:.6g} outside [{self.lo[j]:.6g}, {self.hi[j]:.6g}] "
                    f"{where}")
        pin.framesForwardKinematics(self.model, self.data, q)
        pin.updateGeometryPlacements(self.model, self.data, self.geom, self.gdata, q)
        if int(att.sum()) < 3:
            rec.add("support", step, wp, f"only {int(att.sum())} feet attached {where}")
        contacts = []
        for j in np.flatnonzero(att):
            k = f["plane"][j] - 1
            pl, n = self.plan["planes"][k], self.n[k]
            sole = np.asarray(f["feet"][j], float)
            rel = sole - np.asarray(pl["point"], float)
            t_dir = np.asarray(pl["direction"], float)
            inside = abs(float(rel @ t_dir)) <= pl["extent"][0] / 2 + TOLERANCE and \
                abs(float(rel @ np.cross(n, t_dir))) <= pl["extent"][1] / 2 + TOLERANCE
            if abs(float(rel @ n)) > TOLERANCE or not inside:
                rec.add("feet_on_planes", step, wp, f"foot {j + 1} is not on plane {k + 1} (its sole is "
                        f"{float(rel @ n) * 1000:.3f} mm from it{'' if inside else ', outside its extent'}) {where}")
            ankle = np.asarray(self.data.oMf[self.ankles[j]].translation)
            err = float(np.linalg.norm(ankle - (sole + self.h_f * n)))
            if err > tol and frame is None:  # (at a frame: every foot, by _check_stored, naming the field)
                rec.add("feet_on_planes", step, wp, f"foot {j + 1}'s ankle is {err * 1000:.3f} mm from h_f above its "
                        f"sole on plane {k + 1} {where}")
            contacts.append((tuple(sole), tuple(n)))
        req = coal.DistanceRequest()
        worst = (math.inf, "")
        for gi, obj in enumerate(self.geom.geometryObjects):
            m = self.gdata.oMg[gi]
            tf = coal.Transform3s(m.rotation, m.translation)
            for solid in self.obstacles:
                d = coal.distance(obj.geometry, tf, solid, coal.Transform3s(), req, coal.DistanceResult())
                worst = min(worst, (float(d), obj.name))
        if worst[0] < self.plan["clearance"] - 1e-9:
            rec.add("clearance", step, wp, f"{worst[1]} is {worst[0] * 1000:.2f} mm from a plane, under the plan's "
                    f"clearance {self.plan['clearance'] * 1000:g} mm {where}")
        if contacts:
            self._equilibrium(step, wp, where, q, contacts)
        if frame is not None:
            self._check_stored(frame, f, q, worst[0], contacts)

    def _check_stored(self, i: int, f: dict[str, Any], q: np.ndarray, clearance: float,
                      contacts: list[tuple[tuple[float, ...], tuple[float, ...]]]) -> None:
        """Frame ``i``'s stored values that playback, the side view or a controller read, against what they are at
        its ``q`` (Pinocchio FK and Coal done at ``q``): each ankle (``ankles``) and each sole (``feet``: ``h_f``
        below the ankle along the normal of its plane, attached or swinging) within :data:`TOLERANCE`; the
        robot-planes distance (``clearance``, Coal, the planes' solids of this module) within :data:`TOLERANCE`;
        the CoM's signed distance to the boundary of the attached feet's support region (``equilibrium_margin``,
        ``null`` for an unbounded region) within :data:`TOLERANCE`."""
        import pinocchio as pin

        rec, step, where = self.rec, f["step"], f"(t = {f['t']:.2f} s)"
        legs = self.plan["robot"]["legs"]
        for j, fid in enumerate(self.ankles):
            ankle = np.asarray(self.data.oMf[fid].translation)
            if "ankles" in f:
                err = float(np.linalg.norm(ankle - np.asarray(f["ankles"][j], float)))
                if err > TOLERANCE:
                    rec.add("feet_on_planes", step, i, f"$.frames[{i}].ankles[{j}] is {err * 1000:.3f} mm from "
                            f"{legs[j]}'s ankle at $.frames[{i}].q (Pinocchio FK) {where}")
            k = f["plane"][j] - 1
            err = float(np.linalg.norm(ankle - self.h_f * self.n[k] - np.asarray(f["feet"][j], float)))
            if err > TOLERANCE:
                rec.add("feet_on_planes", step, i, f"$.frames[{i}].feet[{j}] is {err * 1000:.3f} mm from the sole of "
                        f"{legs[j]} at $.frames[{i}].q (h_f below its ankle along the normal of plane "
                        f"$.frames[{i}].plane[{j}] = {k + 1}) {where}")
        if "clearance" in f and abs(f["clearance"] - clearance) > TOLERANCE:
            rec.add("clearance", step, i, f"$.frames[{i}].clearance = {f['clearance'] * 1000:.3f} mm, but the robot is "
                    f"{clearance * 1000:.3f} mm from the planes at q (Coal) {where}")
        if "equilibrium_margin" in f and contacts:
            com = np.array(pin.centerOfMass(self.model, self.data, q))
            m = float(self._region(contacts).margin(com))
            stored = f["equilibrium_margin"]
            if (stored is None) != (not math.isfinite(m)) or \
                    (stored is not None and abs(float(stored) - m) > TOLERANCE):
                rec.add("equilibrium", step, i, f"$.frames[{i}].equilibrium_margin = {stored}, but the CoM is "
                        f"{m:.6g} m inside the support region of the attached feet {where}")

    def _region(self, contacts: list[tuple[tuple[float, ...], tuple[float, ...]]]) -> Any:
        """The support region of the attached suction feet (adhesion contacts), computed once per contact set."""
        from climb_ompl.equilibrium import Contact, support_region

        key = tuple(np.round(np.array(contacts), 12).ravel())
        if key not in self.regions:
            self.rec.lp += 1
            cs = [Contact(p, n, self.friction, "adhesion", self.suction) for p, n in contacts]
            self.regions[key] = support_region(cs, self.mass, self.g)
        return self.regions[key]

    def _equilibrium(self, step: int, wp: float, where: str, q: np.ndarray,
                     contacts: list[tuple[tuple[float, ...], tuple[float, ...]]]) -> None:
        import pinocchio as pin

        from climb_ompl.equilibrium import Contact, torque_feasible

        rec = self.rec
        cs = [Contact(p, n, self.friction, "adhesion", self.suction) for p, n in contacts]
        com = np.array(pin.centerOfMass(self.model, self.data, q))
        if self._region(contacts).contains(com):
            return
        rec.socp += 1
        nq = self.model.nq
        res = torque_feasible(cs, self.mass, self.g, com, np.zeros((len(cs), 3, nq)), np.zeros(nq),
                              np.full(nq, np.inf), np.zeros(nq, bool))
        if res.status == "no_equilibrium":
            rec.add("equilibrium", step, wp, f"CoM {np.round(com, 4).tolist()} admits no forces in the adhesion cones "
                    f"of the {len(cs)} attached feet {where}")


__all__ = ["verify_slope", "CHECKS", "TOLERANCE", "MOTION_TOLERANCE", "RESOLUTION"]
