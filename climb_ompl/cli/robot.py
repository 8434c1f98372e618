"""``climb-ompl robots`` and the ``climb-ompl robot`` group (``robot check``; ``robot show`` lives in viz)."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import typer

from climb_ompl.cli._app import app

robot_app = typer.Typer(help="Robot models: check a spec, show a robot.", no_args_is_help=True)
app.add_typer(robot_app, name="robot")


@app.command("robots")
def robots() -> None:
    """List the bundled robots with their number of configuration parameters and their limbs."""
    from climb_ompl.errors import RobotModelError
    from climb_ompl.model.robot import RobotModel, bundled_robots

    for name in bundled_robots():
        try:
            r = RobotModel.load(name)
        except RobotModelError as exc:  # e.g. a third-party robot whose package is not installed
            typer.echo(f"{name:14s} unavailable: {exc.reason}")
            continue
        limbs = ", ".join(f"{lb.name}({len(lb.joint_indices)})" for lb in r.limbs)
        typer.echo(f"{name:14s} nq {r.nq:2d}  mass {r.mass:5.2f} kg  {'planar' if r.planar else '3-D   '}  "
                   f"limbs: {limbs}")


@robot_app.command("check")
def check(spec: str = typer.Argument(..., help="Robot spec file or bundled robot name.")) -> None:
    """Load a robot spec and its URDF; exit 0 if valid, 2 with the file, field and reason if not.

    A valid spec also gets its limbs' reaches, and a note when its nominal posture collides with itself."""
    from climb_ompl.model.robot import RobotModel

    r = RobotModel.load(spec)
    typer.echo(f"{r.spec_path}: ok: robot {r.name!r}, nq {r.nq}, mass {r.mass:.3f} kg, "
               f"limbs {', '.join(lb.name + ' (' + lb.ik + ' IK' + _contact(lb) + ')' for lb in r.limbs)}"
               + (f"; climb defaults {', '.join(f'{k}={v}' for k, v in r.climb.items())}" if r.climb else ""))
    from climb_ompl.model.reach import hop_reach, pair_reach

    span = hop_reach(pair_reach(r))
    typer.echo("reach (first joint to hand, m): " + ", ".join(f"{lb.name} {lb.reach:.3f}" for lb in r.limbs)
               + (f"; two limbs span at most {span:.3f} m (shoulders at the nominal posture, both reaches and contact "
                  "radii): plan answers at once that a gap of the wall wider than that cannot be crossed"
                  if span else ""))
    for note in limit_notes(r) + chain_notes(r) + contact_notes(r) + posture_notes(r) + srdf_notes(r):  # warnings
        typer.echo(f"note: {note}", err=True)


#: Limits above these look like a URDF's placeholders (example-robot-data's Solo-12: +-10 rad, 1000 rad/s,
#: 1000 N m): joint speed (rad/s or m/s), torque (N m or N) and range (two whole turns).
PLACEHOLDER_SPEED, PLACEHOLDER_TORQUE, PLACEHOLDER_RANGE = 100.0, 1000.0, 4.0 * math.pi


def srdf_notes(robot: Any) -> list[str]:
    """An SRDF that may be another robot's: its robot name differs from the URDF's (:func:`same_robot_name`), or
    some of its ``disable_collisions`` pairs name links the URDF lacks (those pairs are ignored; the SRDFs
    :func:`climb_ompl.model.collision.check_srdf` refuses do not load)."""
    from climb_ompl.model.collision import same_robot_name

    if robot.srdf_links is None:
        return []
    name, pairs, unknown, bad = robot.srdf_links  # (read when the robot loaded)
    out = []
    if not same_robot_name(name, robot.model.name):
        out.append(f"srdf {robot.srdf_path}: its robot is {name!r}, the URDF's {robot.model.name!r}: the SRDF of "
                   "another robot? Its disable_collisions pairs switch off self-collision checks")
    if unknown:
        out.append(f"srdf {robot.srdf_path}: {bad} of its {len(pairs)} disable_collisions pairs name links not in "
                   f"the URDF ({', '.join(repr(x) for x in sorted(unknown)[:3])}"
                   f"{', ...' if len(unknown) > 3 else ''}); they are ignored")
    return out


def limit_notes(robot: Any) -> list[str]:
    """Joint limits that look like a URDF's placeholders (:data:`PLACEHOLDER_SPEED` and the others): the
    planner takes them at their word (a plan's execution times come from the speeds, its torque checks from the
    torques, its reach from the ranges), so the spec should give the real ones."""
    act = np.asarray(robot.actuated, dtype=bool)
    names = robot.joint_names
    out = []
    for what, values, bound, unit, field in (
            ("speed", robot.velocity_limits, PLACEHOLDER_SPEED, "rad/s or m/s", "velocity_limits"),
            ("torque", robot.torque_limits, PLACEHOLDER_TORQUE, "N m or N", "torque_limits"),
            ("range", np.asarray(robot.upper) - np.asarray(robot.lower), PLACEHOLDER_RANGE + 1e-9, "rad or m",
             "joint_limits")):
        big = [j for j in np.flatnonzero(act) if np.isfinite(values[j]) and values[j] >= bound]
        if big:
            shown = ", ".join(f"{names[j]} {values[j]:g}" for j in big[:4]) + (" ..." if len(big) > 4 else "")
            why = ""
            if what == "range":  # the cost: every IK solution repeats once per whole turn of each joint's range
                turns = {lb.name: math.prod(max(1, math.ceil((robot.upper[j] - robot.lower[j]) / (2 * math.pi)))
                                            for j in lb.joint_indices) for lb in robot.limbs}
                worst = max(turns, key=lambda k: turns[k])
                if turns[worst] > 1:
                    why = (f" (each inverse-kinematics solution repeats once per whole turn in a joint's range: up to "
                           f"{turns[worst]} copies of each for limb {worst}, and planning slows down accordingly)")
            out.append(f"joint {what} limits of at least {bound:.4g} {unit} ({shown}) look like the URDF's "
                       f"placeholders: give the real ones in the spec's {field}{why}")
    effort = np.asarray(robot.model.effortLimit, dtype=float)
    free = [names[j] for j in np.flatnonzero(act) if j < len(effort) and effort[j] <= 0
            and not np.isfinite(robot.torque_limits[j])]
    if free:
        out.append(f"joint(s) {', '.join(free[:6])}{' ...' if len(free) > 6 else ''} have effort 0 (or none) in "
                   "the URDF: the planner reads that as no torque limit; give the real ones in the spec's "
                   "torque_limits")
    return out


#: A sphere contact's radius this far (metres, or this fraction of the URDF's radius if more) from the radius of
#: the URDF's collision sphere at the hand gets a note; a sphere centred farther than :data:`CENTRE_TOLERANCE`
#: from the contact's centre too.
RADIUS_TOLERANCE, RADIUS_FRACTION, CENTRE_TOLERANCE = 0.003, 0.2, 0.005


def contact_notes(robot: Any) -> list[str]:
    """A sphere contact that disagrees with the URDF's collision geometry at the hand: a foot sphere of another
    radius, or centred elsewhere (give ``contact.offset``), or a foot that is not a sphere (a mesh, a box: the
    contact is modelled as a sphere all the same; say so, with the geometry's size).  Point contacts (a tip on
    the hand's link, exempt from terrain collision) get none.  Limbs with the same finding share a note."""
    m, objs = robot.model, list(robot.collision_model.geometryObjects)
    found: dict[str, list[tuple[str, str]]] = {}  # note (with {limbs} and {geoms}) -> [(limb, geometry)]
    for lb in robot.limbs:
        c = lb.contact
        if c.type != "sphere":
            continue
        frame = m.frames[lb.frame_id]  # (a sphere with an offset has a frame of its own at its centre)
        near = []
        for o in objs:
            if o.parentJoint != frame.parentJoint:
                continue
            rel = np.asarray(frame.placement.actInv(o.placement.translation), dtype=float)
            kind = type(o.geometry).__name__
            if kind == "Sphere":
                size = 2.0 * float(o.geometry.radius)
            else:
                o.geometry.computeLocalAABB()
                box = o.geometry.aabb_local
                size = float(np.max(np.asarray(box.max_) - np.asarray(box.min_)))
            if kind != "Sphere" and _sphere_like(o, frame, c.radius):  # a mesh of the contact sphere: agrees
                continue
            if float(np.linalg.norm(rel)) <= 0.5 * size + c.radius:  # it overlaps the contact sphere
                near.append((float(np.linalg.norm(rel)), kind, o, rel, size))
        spheres = sorted((x for x in near if x[1] == "Sphere"), key=lambda x: x[0])
        if spheres:
            d, _, o, rel, _ = spheres[0]
            r_urdf = float(o.geometry.radius)
            if abs(r_urdf - c.radius) > max(RADIUS_TOLERANCE, RADIUS_FRACTION * r_urdf):
                found.setdefault(f"{{limbs}}: the contact sphere has radius {c.radius:g} m, the URDF's collision "
                                 f"sphere at the hand ({{geoms}}) {r_urdf:g} m", []).append((lb.name, o.name))
            if d > CENTRE_TOLERANCE:
                off = np.asarray(c.offset, dtype=float) + rel  # (rel is in the contact centre's frame, unturned)
                found.setdefault(f"{{limbs}}: the URDF's collision sphere at the hand ({{geoms}}) is centred {d:.3f} m "
                                 f"from the contact sphere's centre: contact.offset "
                                 f"[{', '.join(f'{v:.4g}' for v in off)}] puts it there (in the hand frame)",
                                 []).append((lb.name, o.name))
        elif near:
            d, kind, o, _, size = min(near, key=lambda x: x[0])
            what = "a mesh" if kind.startswith(("BVH", "Convex")) else f"a {kind.lower()}"
            found.setdefault(f"{{limbs}}: the URDF's collision geometry at the hand ({{geoms}}) is {what} up to "
                             f"{size:.3f} m long, not a sphere: the contact is modelled as a sphere of radius "
                             f"{c.radius:g} m about the hand frame; make sure it covers the foot's sole",
                             []).append((lb.name, o.name))
    return [text.format(limbs=("limb " if len(who) == 1 else "limbs ") + ", ".join(a for a, _ in who),
                        geoms=", ".join(b for _, b in who)) for text, who in found.items()]


def _sphere_like(o: Any, frame: Any, radius: float) -> bool:
    """Whether the collision mesh ``o`` is (part of) the contact sphere of ``radius`` metres about ``frame`` (the
    contact centre's): every vertex within the sphere and the farthest on it, within :data:`RADIUS_TOLERANCE` (or
    :data:`RADIUS_FRACTION` of the radius), as a foot's sole modelled as a sphere or a half sphere is.  Other
    geometry (a box, a cylinder): ``False``."""
    g = o.geometry
    pts = g.points() if hasattr(g, "points") else g.vertices() if hasattr(g, "vertices") else None
    if pts is None or not len(pts):
        return False
    M = frame.placement.actInv(o.placement)
    d = np.linalg.norm(np.asarray(pts, dtype=float) @ np.asarray(M.rotation).T + np.asarray(M.translation), axis=1)
    tol = max(RADIUS_TOLERANCE, RADIUS_FRACTION * radius)
    return bool(abs(float(d.max()) - radius) <= tol)


#: An ``elbow_straight`` this far (rad) from the elbow angle that puts the hand farthest from the limb's first joint
#: (within the joint's bounds, the other joints nominal) gets a note.
STRAIGHT_TOLERANCE = 0.35


def _moves_hand(robot: Any, limb: str, iq: int, q0: np.ndarray) -> bool:
    """Whether turning coordinate ``iq`` by 0.3 from ``q0`` moves ``limb``'s hand frame's origin (not only turns it)."""
    q = q0.copy()
    q[iq] += 0.3 if q0[iq] + 0.3 <= robot.upper[iq] else -0.3
    return float(np.linalg.norm(np.asarray(robot.hand_position(q, limb)) - robot.hand_position(q0, limb))) > 1e-6


def chain_notes(robot: Any) -> list[str]:
    """What each limb's chain says about the spec:

    * a joint between the limb's first joint and its hand that no limb lists: the planner never moves it (it
      keeps its nominal value), which a user may mean (a locked wrist) or not (a knee left out);
    * an ``elbow_straight`` far from where the limb is straightest: the elbow bends name the stance manifold's
      components (Bretl 2006, sec. 4.2.3) and the straight-elbow sampler straightens the elbow there;
    * no closed-form inverse kinematics: the start finder and the first steps of a climb probe the limb's reach
      numerically, which takes tens of seconds per limb."""
    from climb_ompl.cache import note as cache_note
    from climb_ompl.model.reach import probed_numerically, shoulders

    m, q0 = robot.model, np.asarray(robot.nominal_q, dtype=float)
    listed = {j for lb in robot.limbs for j in lb.joint_ids}
    out = []
    for lb in robot.limbs:
        path = list(m.supports[m.frames[lb.frame_id].parentJoint])
        between = [j for j in path[path.index(lb.joint_ids[0]):] if j not in listed
                   and m.joints[j].nq > 0] if lb.joint_ids else []
        moving = [m.names[j] for j in between if _moves_hand(robot, lb.name, m.joints[j].idx_q, q0)]
        turning = [m.names[j] for j in between if m.names[j] not in moving]
        if moving:
            out.append(f"limb {lb.name}: joint(s) {', '.join(moving)} move its hand but are in no limb: the "
                       "planner keeps them at their nominal value (list them in the limb's joints if they should move)")
        if turning:
            out.append(f"limb {lb.name}: joint(s) {', '.join(turning)} lie between its first joint and its hand "
                       "frame but only turn the frame about its origin (the contact point does not move): kept at "
                       "their nominal value, which leaves the contact unchanged")
        if lb.elbow_index is not None and lb.joint_ids:
            e = lb.elbow_index
            angles = np.linspace(robot.lower[e], robot.upper[e], 721)
            first = shoulders(robot, q0)[lb.name]  # the first joint does not move with the elbow
            dist = []
            for a in angles:
                q = q0.copy()
                q[e] = a
                dist.append(float(np.linalg.norm(robot.hand_position(q, lb.name) - first)))
            dist_a = np.asarray(dist)
            given = float(lb.elbow_straight or 0.0)  # the straightest angle nearest it (a joint may turn twice)
            best = float(min(angles[dist_a >= dist_a.max() - 1e-9], key=lambda a: abs(a - given)))
            if abs(best - given) > STRAIGHT_TOLERANCE:
                out.append(f"limb {lb.name}: its elbow is straightest (the hand farthest from the first joint) at "
                           f"{best:.3f}, but elbow_straight is {given:g}: give the angle "
                           "where the limb is straight (or its bound nearest it)")
    slow = probed_numerically(robot)
    if slow:
        out.append(f"limb(s) {', '.join(slow)} have no closed-form inverse kinematics: the start finder "
                   "probes their reach numerically once per wall orientation (5-25 s per limb on a 2-core machine: "
                   "lemur-hooks' limbs 4 s, a Unitree G1's arms 10 s and legs 25 s; "
                   f"{cache_note()}), and each step costs more than with a closed form")
    return out


def posture_notes(robot: Any) -> list[str]:
    """What the nominal posture says about the spec: links that collide there, and links closer there than the
    clearance every transition keeps (``ClimbSettings.clearance`` with the robot's climb defaults): a pair of
    links that close in every posture (a leg's upper link beside the base) makes every transition infeasible."""
    from climb_ompl.climb.start import facing_away
    from climb_ompl.settings import ClimbSettings

    clearance = ClimbSettings.for_search("guided", robot=robot).clearance
    touching = sorted({f"{a} with {b}" for a, b in robot.collisions(robot.nominal_q)})
    near = sorted({f"{a} with {b}" for a, b in robot.collisions(robot.nominal_q, clearance=clearance)} - set(touching))
    out = []
    away = facing_away(robot)
    if away:
        out.append(f"the {away}")
    if touching:
        out.append(f"the nominal posture self-collides: {_listed(touching)}; check the spec's nominal angles (the "
                   "knees' bend) and srdf/ignore_collision_pairs")
    if near:
        counts = near_in_postures(robot, near, clearance)
        shares = ", ".join(f"{p} in {k}" for p, k in counts.items())
        out.append(f"in the nominal posture {_listed(near)} are closer than the clearance of {clearance:g} m that "
                   f"every transition keeps between links; of {POSTURES} postures drawn within the joint limits "
                   f"(seed 0), {shares}: a pair that close in (nearly) every posture belongs in "
                   "ignore_collision_pairs (or the SRDF); for one close in a few, a nominal posture that spreads the "
                   "limbs, or a smaller climb: {clearance: ...}")
    return out


#: Postures :func:`near_in_postures` draws.
POSTURES = 200


def near_in_postures(robot: Any, pairs: list[str], clearance: float, n: int = POSTURES,
                     seed: int = 0) -> dict[str, int]:
    """In how many of ``n`` configurations drawn uniformly within the joint bounds (seeded) each pair of links
    (``"a with b"``, as :func:`posture_notes` names them) is closer than ``clearance`` metres: whether a pair is
    that close "in every posture" (a link beside the body it hangs from) or only in the nominal one."""
    rng = np.random.default_rng(seed)
    counts = dict.fromkeys(pairs, 0)
    for _ in range(n):
        got = {f"{a} with {b}" for a, b in robot.collisions(robot.random_configuration(rng), clearance=clearance)}
        for p in pairs:
            counts[p] += p in got
    return counts


def _listed(pairs: list[str]) -> str:
    return ", ".join(pairs[:6]) + (f" (+{len(pairs) - 6} more)" if len(pairs) > 6 else "")


def _contact(lb: Any) -> str:
    """A limb's contact for the check line: ``, sphere r=0.02 m``, or nothing for a point contact."""
    c = lb.contact
    return "" if c.type == "point" else f", {c.type} r={c.radius:g} m"
