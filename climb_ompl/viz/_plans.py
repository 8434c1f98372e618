"""Plan playback: turn a plan file (``kind`` climb, treebot or slope) into an animated scene.

``climb`` plans (:mod:`climb_ompl.plan.file`) embed the robot (``robot.spec`` + ``robot.urdf``, else it is
loaded by ``robot.name``), the terrain (``terrain.data`` in the terrain file format) and ``steps``:
``{"stance": {limb: hold}, "waypoints": [q, ...], "times": [s, ...], "action": "grab"|"release",
"limb", "hold", "forces": [{"waypoint": i, "forces": {limb: [fx, fy, fz]}}, ...]}``.  Playback shows
each step's stance during its motion, then the stance after the last step's grab or release.  Also
accepted (hand-made plans): ``terrain`` as the terrain dict itself, and ``forces`` as ``{limb: f}`` for
the whole step or one such dict per waypoint (2-D forces ``[fx, fz]`` lie in the x-z plane).

``treebot`` and ``slope`` plans are drawn from what their own modules compute
(``climb_ompl.treebot.scene_items(plan)``, ``climb_ompl.mrwallspect.slope.scene_items(plan)``), in the item
format of :mod:`climb_ompl.viz` or as a dict of arrays (see :func:`normalize_items`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import meshcat.geometry as mg
import numpy as np

from climb_ompl.errors import ClimbError, PlanFileError
from climb_ompl.model.terrain import Terrain
from climb_ompl.viz._geometry import (
    PALETTE,
    Y_TO_Z,
    Part,
    color_int,
    label_part,
    material,
    points_part,
    polyline_part,
    rotation_y_to,
    tube_part,
)
from climb_ompl.viz._scene import RobotDrawing, RobotLike, Scene, node_name

PLAN_KINDS: tuple[str, ...] = ("climb", "treebot", "slope")


def load_plan(path: str | Path) -> dict[str, Any]:
    """Read a plan file of any kind as a dict, validated against the plan schema (:mod:`climb_ompl.plan.file`).

    Raises:
        PlanFileError: unreadable file, not JSON, or schema-invalid (naming the JSON path).
    """
    from climb_ompl.plan.file import read_plan_dict

    plan = read_plan_dict(path)
    if plan.get("kind") not in PLAN_KINDS:  # the schema says so too; kept for a schema that grows kinds
        raise PlanFileError(path, "$.kind", f"must be one of {', '.join(PLAN_KINDS)}, got {plan.get('kind')!r}")
    return plan


def draw_plan(scene: Scene, plan: dict[str, Any], *, source: str = "<plan>", robot: RobotLike | None = None,
              forces: bool = True) -> None:
    """Draw and animate ``plan`` in ``scene`` according to its ``kind``.

    Raises:
        PlanFileError: unknown kind or malformed content.
        VizError: the module that draws this kind is not available.
    """
    kind = plan.get("kind")
    if kind == "climb":
        draw_climb(scene, plan, source=source, robot=robot, forces=forces)
        return
    if kind == "treebot":
        from climb_ompl.treebot import scene_items as tree_items

        draw_items(scene, tree_items(plan), source=source)
        return
    if kind == "slope":
        from climb_ompl.mrwallspect.slope import scene_items as slope_items

        draw_items(scene, slope_items(plan), source=source)
        return
    raise PlanFileError(source, "kind", f"must be one of {', '.join(PLAN_KINDS)}, got {kind!r}")


# ---- climb plans ----------------------------------------------------------------------------------------
@dataclass
class ClimbStep:
    """One step of a climb plan as playback sees it.

    Attributes:
        stance: ``{limb: hold_id}`` during the step's motion.
        waypoints: ``(n, nq)`` configurations.
        times: ``(n,)`` waypoint times from the start of the step (s), or ``None`` (derived from motion).
        forces: ``{waypoint index: {limb: force (3,)}}`` (newtons, world frame), possibly empty.
        after: the stance after the step's grab/release, or ``None``.
    """

    stance: dict[str, str]
    waypoints: np.ndarray
    times: np.ndarray | None = None
    forces: dict[int, dict[str, np.ndarray]] = field(default_factory=dict)
    after: dict[str, str] | None = None


@dataclass
class PlaybackFrame:
    """An animation frame: time (s at speed 1), configuration, step index, waypoint index or ``None``."""

    t: float
    q: np.ndarray
    step: int
    waypoint: int | None


def _force_vec(v: Any, src: str, fld: str) -> np.ndarray:
    try:
        a = np.asarray(v, dtype=float).ravel()
    except (TypeError, ValueError):
        raise PlanFileError(src, fld, f"expected a force vector, got {v!r}") from None
    if a.shape == (2,):
        a = np.array([a[0], 0.0, a[1]])
    if a.shape != (3,) or not np.all(np.isfinite(a)):
        raise PlanFileError(src, fld, f"expected 2 or 3 finite numbers, got {v!r}")
    return a


def _matrix(raw: Any, ncols: int, src: str, fld: str) -> np.ndarray:
    if not isinstance(raw, list) or not raw:
        raise PlanFileError(src, fld, "expected a non-empty list of configurations")
    try:
        W = np.array(raw, dtype=float)
    except (TypeError, ValueError):
        raise PlanFileError(src, fld, "expected lists of numbers of equal length") from None
    if W.ndim == 1:
        W = W[None, :]
    if W.ndim != 2 or W.shape[1] != ncols:
        raise PlanFileError(src, fld, f"expected configurations of {ncols} numbers (the robot's nq), got shape "
                            f"{W.shape}")
    if not np.all(np.isfinite(W)):
        raise PlanFileError(src, fld, "non-finite value")
    return W


def _stance(raw: Any, src: str, fld: str) -> dict[str, str]:
    if not isinstance(raw, dict) or not all(isinstance(v, (str, int)) for v in raw.values()):
        raise PlanFileError(src, fld, "expected an object {limb: hold_id}")
    return {str(k): str(v) for k, v in raw.items()}


def parse_climb_steps(plan: dict[str, Any], nq: int, source: str = "<plan>") -> list[ClimbStep]:
    """The steps of a climb plan, validated for playback; a plan without steps shows its start state.

    Raises:
        PlanFileError: naming the field (``steps[2].waypoints``) and the reason.
    """
    raw = plan.get("steps")
    if raw == [] and isinstance(plan.get("query"), dict):  # the start already met the goal
        start = plan["query"].get("start") or {}
        return [ClimbStep(_stance(start.get("stance"), source, "query.start.stance"),
                          _matrix([start.get("q")], nq, source, "query.start.q"))]
    if not isinstance(raw, list) or not raw:
        raise PlanFileError(source, "steps", "expected a non-empty list of steps")
    steps = []
    for i, st in enumerate(raw):
        f = f"steps[{i}]"
        if not isinstance(st, dict):
            raise PlanFileError(source, f, "expected an object with stance and waypoints")
        stance = _stance(st.get("stance"), source, f"{f}.stance")
        W = _matrix(st.get("waypoints"), nq, source, f"{f}.waypoints")
        times = None
        if st.get("times") is not None:
            times = np.asarray(st["times"], dtype=float).ravel()
            if times.shape != (len(W),) or not np.all(np.isfinite(times)) or np.any(np.diff(times) < 0):
                raise PlanFileError(source, f"{f}.times", f"expected {len(W)} non-decreasing times (one per "
                                    "waypoint)")
        forces = _parse_forces(st.get("forces"), len(W), source, f"{f}.forces")
        after = None
        if st.get("action") in ("grab", "release") and "limb" in st:
            after = dict(stance)
            if st["action"] == "grab":
                after[str(st["limb"])] = str(st.get("hold"))
            else:
                after.pop(str(st["limb"]), None)
        steps.append(ClimbStep(stance, W, times, forces, after))
    last = steps[-1]
    if last.after is not None and last.after != last.stance:  # show the final stance too
        steps.append(ClimbStep(last.after, last.waypoints[-1:]))
    return steps


def _parse_forces(raw: Any, n: int, src: str, fld: str) -> dict[int, dict[str, np.ndarray]]:
    def limbs(d: Any, where: str) -> dict[str, np.ndarray]:
        if not isinstance(d, dict):
            raise PlanFileError(src, where, "expected an object {limb: force}")
        return {str(k): _force_vec(v, src, f"{where}.{k}") for k, v in d.items()}

    if raw is None or raw == []:
        return {}
    if isinstance(raw, dict):  # one set for the whole step
        const = limbs(raw, fld)
        return {j: const for j in range(n)}
    if isinstance(raw, list) and all(isinstance(d, dict) and "waypoint" in d for d in raw):  # plan.py samples
        out = {}
        for j, d in enumerate(raw):
            w = d["waypoint"]
            if not isinstance(w, int) or not 0 <= w < n:
                raise PlanFileError(src, f"{fld}[{j}].waypoint", f"expected a waypoint index in [0, {n})")
            out[w] = limbs(d.get("forces"), f"{fld}[{j}].forces")
        return out
    if isinstance(raw, list) and len(raw) == n:
        return {j: limbs(d, f"{fld}[{j}]") for j, d in enumerate(raw)}
    raise PlanFileError(src, fld, f"expected force samples [{{waypoint, forces}}], {{limb: force}}, or {n} "
                        "such objects (one per waypoint)")


def terrain_from_plan(plan: dict[str, Any], source: str = "<plan>") -> Terrain:
    """The plan's terrain (``terrain.data``, or ``terrain`` itself in the terrain file format).

    Raises:
        PlanFileError: no terrain object; TerrainError: a malformed one.
    """
    t, where = plan.get("terrain"), "$.terrain"
    if isinstance(t, dict) and isinstance(t.get("data"), dict):
        t, where = t["data"], "$.terrain.data"
    if not isinstance(t, dict):
        raise PlanFileError(source, "terrain", "expected the terrain as an object in the terrain file format")
    return Terrain.from_dict(t, source=f"{source} ({where})")


def _step_terrains(plan: dict[str, Any], terrain: Terrain, n: int, source: str) -> list[Terrain]:
    """The terrain each of the ``n`` steps was planned on (:func:`climb_ompl.plan.events.eras_of`): a re-planned
    plan's kept steps on the terrain before its change, as ``verify`` checks them; ``terrain`` for every step of a
    plan without re-plan events (or a hand-made playback file)."""
    from climb_ompl.plan.events import eras_of

    t = plan.get("terrain")
    if not plan.get("events") or not (isinstance(t, dict) and isinstance(t.get("data"), dict)):
        return [terrain] * n
    eras = eras_of(plan["events"], t["data"], terrain, n, source)
    return [eras.of_step(k) for k in range(n)]


def robot_from_plan(plan: dict[str, Any], source: str = "<plan>") -> RobotLike:
    """The plan's robot (:func:`climb_ompl.plan.file.robot_from_plan`)."""
    from climb_ompl.plan.file import robot_from_plan as embedded

    return embedded(plan, source=source)


def timeline(steps: list[ClimbStep], *, joint_speed: float = 0.5, max_dq: float = 0.04, pause: float = 0.4,
             max_frames: int = 3000) -> list[PlaybackFrame]:
    """Animation frames over a climb: waypoints sub-sampled in joint space, a pause at each stance change.

    A segment between waypoints lasts as the plan's ``times`` say, else ``max|dq| / joint_speed`` seconds
    (at least 0.05 s), and is cut into pieces of at most ``max_dq`` (rad or m) so the drawn motion follows
    the joint-space path rather than a straight line between link poses.  ``max_dq`` grows if the climb
    would exceed ``max_frames``.  ``pause``: seconds between two steps (a timed plan plays with none: on its own
    clock, in real time at speed 1).
    """
    total = sum(float(np.abs(np.diff(s.waypoints, axis=0)).max(axis=1).sum()) if len(s.waypoints) > 1 else 0.0
                for s in steps)
    max_dq = max(max_dq, total / max(max_frames - 2 * len(steps), 1))
    frames: list[PlaybackFrame] = []
    t = 0.0
    for k, step in enumerate(steps):
        if k > 0:
            t += pause
        W = step.waypoints
        frames.append(PlaybackFrame(t, W[0], k, 0))
        for j in range(1, len(W)):
            a, b = W[j - 1], W[j]
            d = float(np.abs(b - a).max())
            n = max(1, math.ceil(d / max_dq))
            dt = float(step.times[j] - step.times[j - 1]) if step.times is not None else 0.0
            if dt <= 0:
                dt = max(d / joint_speed, 0.05) if d > 0 else 0.0
            if d == 0 and dt == 0:
                continue
            for i in range(1, n + 1):
                frames.append(PlaybackFrame(t + dt * i / n, a + (b - a) * i / n, k, j if i == n else None))
            t += dt
    if len(frames) == 1:  # a single configuration: hold it so the animation has a length
        f = frames[0]
        frames.append(PlaybackFrame(pause, f.q, f.step, None))
    return frames


def support_region_of(robot: RobotLike, terrain: Terrain, stance: dict[str, str]) -> Any | None:
    """The stance's support region from :mod:`climb_ompl.equilibrium`, or ``None`` if unavailable."""
    try:
        from climb_ompl.equilibrium import Contact, support_region
    except ImportError:
        return None
    import pinocchio as pin

    contacts = [Contact.from_hold(terrain.hold(h)) for _, h in sorted(stance.items())]
    mass = getattr(robot, "mass", None) or float(pin.computeTotalMass(robot.model))
    planar = bool(getattr(robot, "planar", terrain.dim == 2))
    try:
        return support_region(contacts, mass, terrain.g, planar=planar)
    except ClimbError:
        return None


def feasible_region_of(robot: RobotLike, terrain: Terrain, stance: dict[str, str], q: np.ndarray) -> Any | None:
    """The torque-limited feasible region (:func:`climb_ompl.equilibrium.feasible_region`) of ``stance`` at
    posture ``q``, or ``None`` when the robot has no torque limits, no equilibrium constraint or no model of
    its hand Jacobians and gravity torques."""
    needed = ("limbs", "hand_jacobians", "gravity_torques", "torque_limits", "actuated")
    if not all(hasattr(robot, a) for a in needed) or not getattr(robot, "equilibrium", True):
        return None
    if not np.any(np.asarray(robot.actuated) & np.isfinite(np.asarray(robot.torque_limits, dtype=float))):
        return None
    from climb_ompl.equilibrium import Contact, feasible_region

    names = [lb.name for lb in robot.limbs]
    limbs = sorted(stance)
    try:
        idx = [names.index(lb) for lb in limbs]
        contacts = [Contact.from_hold(terrain.hold(stance[lb])) for lb in limbs]
        J = np.asarray(robot.hand_jacobians(q))[idx]
        return feasible_region(contacts, robot.mass, terrain.g, J, robot.gravity_torques(q, terrain.g),
                               robot.torque_limits, robot.actuated, planar=bool(getattr(robot, "planar", False)))
    except (ClimbError, ValueError):
        return None


def draw_climb(scene: Scene, plan: dict[str, Any], *, source: str = "<plan>", robot: RobotLike | None = None,
               forces: bool = True, support: bool = True) -> list[PlaybackFrame]:
    """Draw and animate a ``climb`` plan; returns the frames it animated.

    Args:
        scene: the scene to draw into.
        plan: the plan dict (see module docstring).
        source: plan file name for error messages.
        robot: the robot; default :func:`robot_from_plan`.
        forces: draw contact-force arrows when the plan has forces.
        support: draw each stance's support region (from :mod:`climb_ompl.equilibrium`) and, in orange,
            the torque-limited feasible region of the step's first posture (Orsolino et al. (2020)).

    Raises:
        PlanFileError: malformed steps, terrain or robot fields; a stance naming an unknown hold.
    """
    terrain = terrain_from_plan(plan, source)
    if robot is None:
        robot = robot_from_plan(plan, source)
    steps = parse_climb_steps(plan, int(robot.model.nq), source)
    on = _step_terrains(plan, terrain, len(steps), source)  # a re-planned plan's kept steps: the terrain of their time
    for i, st in enumerate(steps):
        for limb, hid in st.stance.items():
            if hid not in on[i].hold_ids:
                raise PlanFileError(source, f"steps[{i}].stance.{limb}", f"no hold {hid!r} in the terrain the step "
                                    "was planned on")

    g = terrain.g
    scene.add_terrain(terrain, cones=False)
    drawing = scene.add_robot(robot, steps[0].waypoints[0])
    real = bool(plan.get("steps")) and all(isinstance(st, dict) and "velocities" in st for st in plan["steps"])
    frames = timeline(steps, pause=0.0 if real else 0.4)  # a timed plan plays on its own clock (at --speed 1)
    starts = [next(f.t for f in frames if f.step == k) for k in range(len(steps))]
    ends = starts[1:] + [math.inf]
    scene.add_com(g, com=drawing.com(steps[0].waypoints[0]))

    fmax = max((float(np.linalg.norm(v)) for st in steps for d in st.forces.values() for v in d.values()),
               default=0.0)
    force_len = 0.25 / fmax if (forces and fmax > 0) else 0.0  # the largest force is drawn 25 cm long
    regions: dict[tuple[Any, ...], Any] = {}
    has_support = []
    has_feasible: list[int] = []
    # Per-step items get their visibility from the animation only: a static "visible" set on the same
    # node as well lets three.js's mixer skip the keyed change (it only writes values that differ from
    # its previous frame), and the first step's items would stay visible for the whole climb.
    # a hold in contact over many steps is drawn once and shown while held; a limb's force arrow likewise
    held: dict[str, list[tuple[float, float]]] = {}
    held_on: dict[str, Terrain] = {}  # where a hold is drawn: as it was when first held
    loaded: dict[str, list[tuple[float, float]]] = {}
    for k, st in enumerate(steps):
        for hid in st.stance.values():
            held.setdefault(hid, []).append((starts[k], ends[k]))
            held_on.setdefault(hid, on[k])
    for hid, spans in sorted(held.items()):
        scene.add_held(held_on[hid], hid, path=f"stance/{node_name(hid)}")
        scene.visibility_keys(f"stance/{node_name(hid)}", spans)
    for k, st in enumerate(steps):
        drawn = False
        if support:
            key = (id(on[k]), *sorted(st.stance.values()))
            if key not in regions:
                regions[key] = support_region_of(robot, on[k], st.stance)
            if regions[key] is not None:
                drawn = scene.add_support(regions[key], g, com=drawing.com(st.waypoints[0]),
                                          path=f"support/s{k}")
                if drawn:
                    scene.visibility_keys(f"support/s{k}", [(starts[k], ends[k])])
            q0 = st.waypoints[0]
            fr = feasible_region_of(robot, on[k], st.stance, q0) if drawn else None
            if fr is not None and scene.add_support(fr, g, com=drawing.com(q0), path=f"feasible/s{k}",
                                                    color=PALETTE["feasible"], lift=0.003):
                scene.visibility_keys(f"feasible/s{k}", [(starts[k], ends[k])])
                has_feasible.append(k)
        has_support.append(drawn)
        if force_len > 0 and st.forces:
            for limb in sorted({lb for d in st.forces.values() for lb in d} & set(st.stance)):
                if limb not in loaded:
                    j0 = min(j for j, d in st.forces.items() if limb in d)
                    scene.add_arrow(f"forces/{node_name(limb)}", on[k].hold(st.stance[limb]).p,
                                    st.forces[j0][limb] * force_len)
                loaded.setdefault(limb, []).append((starts[k], ends[k]))
    for limb, spans in sorted(loaded.items()):
        scene.visibility_keys(f"forces/{node_name(limb)}", spans)

    _draw_events(scene, plan, terrain, drawing, steps, starts)
    _animate_frames(scene, drawing, frames, steps, on, has_support, force_len, set(has_feasible))
    scene.finish()
    return frames


def _draw_events(scene: Scene, plan: dict[str, Any], terrain: Terrain, drawing: RobotDrawing,
                 steps: list[ClimbStep], starts: list[float]) -> None:
    """Re-plan events (:mod:`climb_ompl.climb.replan`): each changed hold where it was before the change (a dark,
    larger ball: the hold that failed) and, from the step where the new plan leaves the old one, a yellow
    ball at the robot's centre of mass there (the departure)."""
    from climb_ompl.model.wall_frame import wall_normal

    for e, ev in enumerate(plan.get("events") or ()):
        if not isinstance(ev, dict) or ev.get("type") != "replan":
            continue
        for hid, before in sorted((ev.get("before") or {}).items()):
            p = np.asarray(before.get("position", ()), dtype=float)
            if p.shape == (2,):
                p = np.array([p[0], 0.0, p[1]])
            if p.shape == (3,):
                text = f"{hid} {_what_changed(ev.get('change'), hid)} at step {ev.get('at_step', '?')}"
                scene.put(f"events/e{e}/failed/{node_name(hid)}",
                          [Part("ball", mg.Sphere(0.045), material(PALETTE["failed"], 0.7), _tr(p)),
                           label_part(text, 0.07, _label_frame(p, wall_normal(terrain), terrain.g))])
        k = int(ev.get("resumed_at_step", -1))
        if 0 <= k < len(steps):
            # in front of the body (off the wall), so that the body and its regions do not hide it
            p = drawing.com(steps[k].waypoints[0]) + 0.12 * wall_normal(terrain)
            scene.put(f"events/e{e}/departure", [Part("ball", mg.Sphere(0.04),
                                                      material(PALETTE["departure"], 0.9), _tr(p))])
            scene.visibility_keys(f"events/e{e}/departure", [(starts[k], math.inf)])


def _what_changed(change: Any, hid: str) -> str:
    """What a replan event's change did to hold ``hid``: ``removed``, ``moved``, ``friction changed`` (or both)."""
    if not isinstance(change, dict):
        return "changed"
    if hid in (change.get("remove") or ()):
        return "removed"
    words = [w for w, key in (("moved", "move"), ("friction changed", "friction")) if hid in (change.get(key) or {})]
    return " and ".join(words) or "changed"


def _label_frame(p: np.ndarray, normal: np.ndarray, gravity: np.ndarray) -> np.ndarray:
    """A label's frame beside a point on the wall: its text up the wall (against gravity), facing out of it."""
    z = np.asarray(normal, dtype=float) / np.linalg.norm(normal)
    up = -np.asarray(gravity, dtype=float)
    up = up - (up @ z) * z
    y = up / np.linalg.norm(up) if np.linalg.norm(up) > 1e-9 else np.cross(z, [1.0, 0.0, 0.0])
    x = np.cross(y, z)
    T = np.eye(4)
    T[:3, :3] = np.column_stack([x, y, z])
    T[:3, 3] = p + 0.1 * y + 0.06 * z  # above the hold's ball, off the wall
    return T


def _animate_frames(scene: Scene, drawing: RobotDrawing, frames: list[PlaybackFrame], steps: list[ClimbStep],
                    on: list[Terrain], has_support: list[bool], force_len: float,
                    has_feasible: set[int] = frozenset()) -> None:
    """Key every drawn item's pose at every frame; ``on[k]``: the terrain step ``k`` was planned on."""
    g = on[0].g
    poses: dict[str, tuple[list[float], list[np.ndarray]]] = {}  # keyed at the end, the redundant poses left out

    def pose(path: str, t: float, T: np.ndarray) -> None:
        ts, Ts = poses.setdefault(path, ([], []))
        ts.append(t)
        Ts.append(T)

    for fr in frames:
        for node, T in drawing.placements(fr.q):
            pose(node, fr.t, T)
            scene.see(T[:3, 3], focus=True)
        com = drawing.com(fr.q)
        pose("com", fr.t, _tr(com))
        if has_support[fr.step]:
            pose(f"support/s{fr.step}", fr.t, Scene.plane_offset(com, g))
        if fr.step in has_feasible:
            pose(f"feasible/s{fr.step}", fr.t, Scene.plane_offset(com, g))
        st = steps[fr.step]
        if force_len > 0 and fr.waypoint in st.forces:
            for limb, f in sorted(st.forces[fr.waypoint].items()):
                if limb in st.stance:
                    T = Scene.arrow_transform(on[fr.step].hold(st.stance[limb]).p, f * force_len)
                    length = float(np.linalg.norm(T[:3, 1]))
                    T[:3, 1] /= max(length, 1e-9)
                    scene.key(fr.t, f"forces/{node_name(limb)}", transform=T, scale=[1.0, length, 1.0])
    for path, (ts, Ts) in poses.items():
        scene.key_poses(path, ts, Ts)


# ---- generic items (TreeBot, slope gait) ----------------------------------------------------------------
_ITEM_COLOURS = (0x2B7DE8, 0x3DAA5A, 0xE8892B, 0x8E44AD, 0x16A085, 0xC0392B, 0x7F8C8D)


def _xyz(a: Any, src: str, fld: str) -> np.ndarray:
    """Points as ``(..., 3)`` floats; 2-D points ``(..., 2)`` are in the x-z plane."""
    try:
        arr = np.asarray(a, dtype=float)
    except (TypeError, ValueError):
        raise PlanFileError(src, fld, "expected numbers") from None
    if arr.ndim == 0 or arr.shape[-1] not in (2, 3):
        raise PlanFileError(src, fld, f"expected points with 2 or 3 coordinates, got shape {arr.shape}")
    if arr.shape[-1] == 2:
        arr = np.stack([arr[..., 0], np.zeros(arr.shape[:-1]), arr[..., 1]], axis=-1)
    return arr


def _hint_colour(key: str, i: int) -> int:
    k = key.lower()
    for word, col in (("obstacle", 0xC0392B), ("grip", 0x27AE60), ("target", 0x27AE60), ("surface", 0xA0826D),
                      ("ring", 0x8B5A2B), ("path", 0x2B7DE8), ("body", 0xE8892B), ("rear", 0x8E44AD),
                      ("front", 0x16A085), ("foot", 0x8E44AD), ("leg", 0x34495E), ("plane", 0xD9CBB0)):
        if word in k:
            return col
    return _ITEM_COLOURS[i % len(_ITEM_COLOURS)]


def _is_point_array(v: Any) -> bool:
    try:
        a = np.asarray(v, dtype=float)
    except (TypeError, ValueError):
        return False
    return a.ndim == 2 and a.shape[1] in (2, 3) and a.shape[0] > 0


def normalize_items(data: Any) -> dict[str, Any]:
    """Scene items in the documented format (:mod:`climb_ompl.viz`) from whatever a planner returned.

    Accepted: ``{"items": [...], ...}`` (as is); a bare list of items; or a dict of plain arrays, read
    by shape: ``(N, 3)``/``(N, 2)`` arrays become points (polylines if the key names a path or line),
    lists of ``{"points": ...}`` become polylines, and ``frames`` (a list of per-frame dicts with an
    optional ``t``) become animated items: ``(k, 3)`` arrays a polyline per frame, ``(3,)`` arrays a
    moving sphere, or a moving cylinder along ``<key>_dir`` when that exists.  Keys ending in ``normals``
    or ``_dir`` are not drawn on their own.
    """
    if isinstance(data, (list, tuple)):
        return {"items": list(data)}
    if not isinstance(data, dict):
        return {"items": []}
    if "items" in data:
        return data
    out: dict[str, Any] = {k: data[k] for k in ("terrain", "dt", "times") if k in data}
    items: list[dict[str, Any]] = []
    for i, (key, val) in enumerate(data.items()):
        if key in ("terrain", "dt", "times", "frames") or key.endswith(("normals", "_dir")):
            continue
        col = _hint_colour(key, i)
        if isinstance(val, (list, tuple)) and val and all(isinstance(d, dict) and "points" in d for d in val):
            for j, d in enumerate(val):
                items.append({"name": f"{key}_{j}", "kind": "polyline", "points": d["points"], "color": col,
                              "closed": bool(d.get("closed", False))})
        elif _is_point_array(val):
            line = any(w in key.lower() for w in ("path", "line", "curve", "edge"))
            n = len(np.asarray(val))
            items.append({"name": key, "kind": "polyline" if line else "points", "points": val, "color": col,
                          "radius": 0.006 if line else (0.012 if n <= 64 else 0.008)})
    frames = data.get("frames")
    if isinstance(frames, (list, tuple)) and frames and all(isinstance(f, dict) for f in frames):
        if "times" not in out and all("t" in f for f in frames):
            out["times"] = [float(f["t"]) for f in frames]
        first = frames[0]
        for i, key in enumerate(first):
            if key.endswith("_dir") or not all(key in f for f in frames):
                continue
            try:
                arrs = [np.asarray(f[key], dtype=float) for f in frames]
            except (TypeError, ValueError):
                continue
            col = _hint_colour(key, i + 3)
            if all(a.ndim == 2 and a.shape[1] in (2, 3) for a in arrs):
                items.append({"name": key, "kind": "polyline", "points": arrs, "color": col, "radius": 0.012})
            elif all(a.shape in ((3,), (2,)) for a in arrs):
                pos = _xyz(np.array(arrs), "<items>", f"frames.{key}")
                if all(f"{key}_dir" in f for f in frames):
                    dirs = np.array([np.asarray(f[f"{key}_dir"], dtype=float).ravel()[:3] for f in frames])
                    poses = []
                    for p, d in zip(pos, dirs, strict=True):
                        T = np.eye(4)
                        T[:3, :3] = rotation_y_to(d) @ Y_TO_Z[:3, :3].T  # local z along d
                        T[:3, 3] = p + (d / max(np.linalg.norm(d), 1e-12)) * 0.03
                        poses.append(T)
                    items.append({"name": key, "kind": "cylinder", "radius": 0.02, "length": 0.06, "poses": poses,
                                  "color": col})
                else:
                    items.append({"name": key, "kind": "sphere", "radius": 0.02, "positions": pos, "color": col})
    out["items"] = items
    return out


def draw_items(scene: Scene, data: Any, *, source: str = "<items>") -> None:
    """Draw scene items (see :func:`normalize_items`) and animate their per-frame values.

    Raises:
        PlanFileError: an item of unknown kind or with malformed arrays.
    """
    data = normalize_items(data)
    if not isinstance(data.get("items"), (list, tuple)):
        raise PlanFileError(source, "items", "expected a list of items or {'items': [...]}")
    items = list(data["items"])
    terrain = data.get("terrain")
    if isinstance(terrain, dict):
        terrain = Terrain.from_dict(terrain, source=f"{source} ($.terrain)")
    if terrain is not None:
        scene.add_terrain(terrain, cones=bool(data.get("cones", False)))
    n_frames = _frame_count(items)
    times = data.get("times")
    if times is not None:
        times = np.asarray(times, dtype=float).ravel()
        if n_frames > 1 and len(times) != n_frames:
            raise PlanFileError(source, "times", f"expected {n_frames} times (one per frame), got {len(times)}")
    else:
        times = np.arange(max(n_frames, 1)) * float(data.get("dt", 0.1))
    for i, item in enumerate(items):
        _draw_item(scene, item, times, source, f"items[{i}]")
    scene.finish()


def _point_sets(raw: Any, src: str, fld: str) -> tuple[list[np.ndarray], bool]:
    """``(sets, per_frame)``: one ``(N, 3)`` set (static) or one per frame (lengths may differ)."""
    if isinstance(raw, (list, tuple)) and raw and np.ndim(raw[0]) == 2:
        return [_xyz(r, src, f"{fld}[{j}]").reshape(-1, 3) for j, r in enumerate(raw)], True
    arr = _xyz(raw, src, fld)
    if arr.ndim == 3:
        return list(arr), True
    return [arr.reshape(-1, 3)], False


def _frame_count(items: list[Any]) -> int:
    n = 0
    for it in items:
        if not isinstance(it, dict):
            continue
        if it.get("points") is not None:
            try:
                sets, per_frame = _point_sets(it["points"], "<items>", "points")
            except PlanFileError:
                continue
            if per_frame:
                n = max(n, len(sets))
        for key, static_ndim in (("poses", 2), ("positions", 1), ("visible", 0)):
            if it.get(key) is not None:
                a = np.asarray(it[key], dtype=object if key == "visible" else float)
                if a.ndim > static_ndim:
                    n = max(n, a.shape[0])
    return n


def _draw_item(scene: Scene, item: Any, times: np.ndarray, src: str, fld: str) -> None:
    if not isinstance(item, dict):
        raise PlanFileError(src, fld, "expected an object with name and kind")
    kind = item.get("kind", item.get("type"))
    path = f"items/{node_name(item.get('name', fld))}"
    color = color_int(item.get("color"), 0x555555)
    opacity = float(item.get("opacity", 1.0))
    if kind in ("points", "polyline"):
        sets, per_frame = _point_sets(item.get("points"), src, f"{fld}.points")
        radius = float(item.get("radius", 0.01 if kind == "points" else 0.0))
        closed = bool(item.get("closed", False))
        for j, P in enumerate(sets):
            if len(P) == 0:
                continue
            scene.see(P, focus=True)
            sub = f"{path}/f{j}" if per_frame else path
            if kind == "points":
                parts = ([Part(f"p{m}", mg.Sphere(radius), material(color, opacity), _tr(p)) for m, p in enumerate(P)]
                         if len(P) <= 64 else [points_part(P, color, 2 * radius)])
            elif radius > 0:
                Q = np.vstack([P, P[:1]]) if closed and len(P) > 2 else P
                parts = [tube_part(Q, radius, color, opacity)]
            else:
                parts = [polyline_part(P, color, closed=closed)]
            scene.put(sub, parts)  # a per-frame node's visibility comes from the animation only (see above)
            if per_frame and j < len(times):
                end = times[j + 1] if j + 1 < len(times) else math.inf
                scene.visibility_keys(sub, [(times[j], end)])
        return
    if kind == "box":
        size = np.asarray(item.get("size", [0.05, 0.05, 0.05]), dtype=float)
        parts = [Part("box", mg.Box(list(size)), material(color, opacity), np.eye(4))]
    elif kind == "sphere":
        parts = [Part("sphere", mg.Sphere(float(item.get("radius", 0.02))), material(color, opacity), np.eye(4))]
    elif kind == "cylinder":
        cyl = mg.Cylinder(float(item.get("length", 0.1)), float(item.get("radius", 0.02)))
        parts = [Part("cylinder", cyl, material(color, opacity), Y_TO_Z)]
    else:
        raise PlanFileError(src, f"{fld}.kind", f"must be points, polyline, box, sphere or cylinder, got {kind!r}")
    poses = _poses(item, src, fld)
    scene.put(path, parts, transform=poses[0])
    for T in poses:
        scene.see(T[:3, 3], focus=True)
    if len(poses) > 1:
        for j, T in enumerate(poses[: len(times)]):
            scene.key(float(times[j]), path, transform=T)
    vis = item.get("visible")
    if vis is not None and np.ndim(vis) == 1:
        for j, v in enumerate(list(vis)[: len(times)]):
            scene.key(float(times[j]), path, visible=bool(v))


def _tr(p: np.ndarray) -> np.ndarray:
    T = np.eye(4)
    T[:3, 3] = p
    return T


def _poses(item: dict[str, Any], src: str, fld: str) -> list[np.ndarray]:
    """The item's poses: one static pose or one per frame (``pose``/``poses`` 4x4, ``position(s)``)."""
    if item.get("poses") is not None:
        P = np.asarray(item["poses"], dtype=float)
        if P.ndim != 3 or P.shape[1:] != (4, 4):
            raise PlanFileError(src, f"{fld}.poses", f"expected (T, 4, 4) transforms, got shape {P.shape}")
        return list(P)
    if item.get("pose") is not None:
        P = np.asarray(item["pose"], dtype=float)
        if P.shape != (4, 4):
            raise PlanFileError(src, f"{fld}.pose", f"expected a 4x4 transform, got shape {P.shape}")
        return [P]
    if item.get("positions") is not None:
        return [_tr(p) for p in _xyz(item["positions"], src, f"{fld}.positions").reshape(-1, 3)]
    if item.get("position") is not None:
        return [_tr(_xyz(item["position"], src, f"{fld}.position").reshape(3))]
    return [np.eye(4)]
