"""What a limb can reach: inverse kinematics nearest a reference, reach maps and reach prefilters.

Cheap necessary conditions used before any inverse kinematics (Bretl 2006, sec. 4.3: "it is very
inefficient to check this constraint after sampling a configuration"): the largest distance between two
hands (:func:`pair_reach`), and a per-limb map of the largest distance along the wall from its first joint
to a reachable hand position, per direction and per depth across the wall (:func:`reach_maps`,
:class:`ShouldersReach`).  The map keeps every hand position the limb reaches with its joints inside their
bounds (tested against forward kinematics); it may cut thin slivers reached only with a joint at a bound.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from climb_ompl import cache
from climb_ompl.model.wall_frame import wall_normal

_REACH_MAPS: dict[Any, dict[int, Any]] = {}
#: per reach map (by identity, the map kept alongside): its joint's parent, placement, axes, planes and radius limits,
#: and the limits as an array (:meth:`ShouldersReach.many`)
_MAP_TERMS: dict[int, tuple[Any, tuple[Any, ...], np.ndarray]] = {}


def shoulders(robot: Any, q: np.ndarray) -> dict[str, np.ndarray]:
    """World position of each limb's first joint at ``q`` (the hand's position for a limb with no joints)."""
    import pinocchio as pin

    pin.forwardKinematics(robot.model, robot.data, q)
    return {lb.name: np.array(robot.data.oMi[lb.joint_ids[0] if lb.joint_ids else 0].translation, dtype=float)
            for lb in robot.limbs}


def pair_reach(robot: Any) -> dict[tuple[str, str], float]:
    """Largest distance between two holds two limbs touch at once: the shoulders' distance at the nominal posture
    plus both reaches (first joint to hand frame), plus both contact radii.

    A sphere contact of radius ``r`` puts the hand frame at ``p + r n`` for a hold at ``p`` with normal ``n``
    (:meth:`~climb_ompl.model.contact.ContactGeometry.hand_target`; an ``offset`` is inside the reach, the hand
    frame being the sphere's centre), so two holds whose normals face each other lie up to ``r_a + r_b`` farther
    apart than the hand frames touching them.
    """
    sh = shoulders(robot, np.asarray(robot.nominal_q, dtype=float))
    names = [lb.name for lb in robot.limbs]
    grow = {lb.name: robot.limb(lb.name).reach + _radius(robot, lb.name) for lb in robot.limbs}
    return {(a, b): float(np.linalg.norm(sh[a] - sh[b])) + grow[a] + grow[b] for a in names for b in names}


def hop_reach(pair: dict[tuple[str, str], float]) -> float:
    """The largest distance between a hold a limb grabs and a hold another limb is on: the largest
    :func:`pair_reach` of two different limbs (``0`` for a robot with one limb, which grabs nothing while on a
    hold)."""
    return max((r for (a, b), r in pair.items() if a != b), default=0.0)


def reachable_holds(terrain: Any, start: Any, hop: float) -> np.ndarray:
    """``(n_holds,)`` bool: the holds a climb from the holds ``start`` (ids) can ever touch, each grab within
    ``hop`` metres of a hold already touched (:func:`hop_reach`).

    A necessary condition, exact for the search's own prefilter: a grabbed hold lies within the pair reach of
    every contact hold of the stance (Bretl 2006, sec. 4.3), so, hop by hop, every hold of a climb is joined to
    the start's holds by holds at most ``hop`` apart.
    """
    from scipy.spatial import cKDTree

    pos = terrain.positions
    index = terrain.hold_index
    seen = np.zeros(len(index), dtype=bool)
    todo = [index[h] for h in start]
    seen[todo] = True
    tree = cKDTree(pos)
    reach = hop * (1.0 + 1e-9)  # (at the boundary the search's own comparison decides: never refuse it)
    while todo:
        nxt = [j for near in tree.query_ball_point(pos[todo], reach) for j in near if not seen[j]]
        nxt = sorted(set(nxt))
        seen[nxt] = True
        todo = nxt
    return seen


def _radius(robot: Any, limb: str) -> float:
    """The contact sphere's radius of ``limb`` (0 for a point contact)."""
    contact = getattr(robot.limb(limb), "contact", None)
    return float(getattr(contact, "radius", 0.0) or 0.0)


def _reach_map(robot: Any, lb: Any, normal: np.ndarray, n_dir: int = 36, dr: float = 0.02,
               dd: float = 0.04) -> tuple[np.ndarray, np.ndarray, np.ndarray, float, float, np.ndarray] | None:
    """Largest distance from a limb's first joint to a reachable hand position across the wall normal, per
    direction in the wall's plane and per depth along the normal.

    Probed once per robot with :meth:`RobotModel.limb_ik` at the nominal configuration, on planes
    perpendicular to the wall normal ``dd`` apart, on the nominal hand's side of the first joint (depths from
    ``2 dd`` on the other side to ``reach + dd`` on the hand's), along ``n_dir`` rays per plane from the reach
    sphere inwards every ``dr`` (a limb without closed-form IK: from forward-kinematics samples outwards,
    :func:`_sampled_radii`), in the first joint's frame (so it turns with the body).  A hand target deeper
    or shallower than the nominal hand has its own radius: a body pressed to the wall reaches farther along it
    than at the nominal stand-off.

    Returns:
        ``(e1, e2, e3, d0, dd, radii)``: the plane's axes and its normal turned towards the nominal hand, in the
        joint's frame, the first depth along that normal (``-2 dd``) and the spacing of the planes, and the radii
        ``(planes, n_dir)`` plus ``dr``; ``None`` for a limb without joints or moving the base.
    """
    import pinocchio as pin

    if not lb.joint_ids or set(lb.joint_indices) & set(int(j) for j in robot.base_indices):
        return None
    q0 = np.asarray(robot.nominal_q, dtype=float)
    pin.forwardKinematics(robot.model, robot.data, q0)
    jid = lb.joint_ids[0]
    m = robot.data.oMi[robot.model.parents[jid]] * robot.model.jointPlacements[jid]  # before the joint's motion
    n = np.asarray(normal, dtype=float)
    e1w = np.cross(n, [0.0, 0.0, 1.0]) if abs(n[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1w /= np.linalg.norm(e1w)
    e2w = np.cross(n, e1w)
    top = lb.reach + dr  # the reach bounds the distance from the first joint to the hand
    # depths along the normal turned towards the nominal hand (on the other side, ShouldersReach tests the reach alone)
    e3w = n if float((np.asarray(robot.hand_position(q0, lb.name)) - m.translation) @ n) >= 0.0 else -n
    depths = np.arange(-2.0 * dd, lb.reach + dd + 1e-9, dd)
    radii = np.zeros((len(depths), n_dir))
    # where the scan of a ray starts: outside the reach for a closed-form limb (a probe costs microseconds), at the
    # farthest hand position of forward-kinematics samples in its cell for a numeric one (a probe it fails costs
    # milliseconds: scanning in from the reach took minutes per limb for a humanoid's legs)
    seeds = None if lb.ik == "analytic" else _sampled_radii(robot, lb, q0, m, (e1w, e2w, e3w), depths, n_dir, dd)
    for j, d in enumerate(depths):
        centre = m.translation + d * e3w
        kmax = int(math.sqrt(max(0.0, top * top - d * d)) / dr + 1e-9)
        for i in range(n_dir):
            a = 2 * math.pi * i / n_dir
            u = math.cos(a) * e1w + math.sin(a) * e2w

            def reached(k: int, centre: np.ndarray = centre, u: np.ndarray = u) -> bool:
                return bool(robot.limb_ik(lb.name, q0, centre + k * dr * u))

            k = kmax if seeds is None else min(kmax, int(seeds[j, i] / dr))
            if k > 0 and k < kmax and reached(k):  # outwards to the last probe reached
                while k < kmax and reached(k + 1):
                    k += 1
            else:  # inwards to the first probe reached
                while k > 0 and not reached(k):
                    k -= 1
            radii[j, i] = k * dr
    # directions in the joint frame: bin k of a plane covers local angle 2 pi k / n_dir
    rot = m.rotation.T
    return rot @ e1w, rot @ e2w, rot @ e3w, float(depths[0]), float(dd), radii + dr


#: Forward-kinematics samples of a numeric limb's joints that seed its reach map (:func:`_sampled_radii`).
SEED_SAMPLES = 20000


def _sampled_radii(robot: Any, lb: Any, q0: np.ndarray, m: Any, axes: tuple[np.ndarray, ...], depths: np.ndarray,
                   n_dir: int, dd: float) -> np.ndarray:
    """``(planes, n_dir)``: per cell of a reach map (a plane's slab of thickness ``dd``, a direction's bin), the
    largest in-plane distance from the limb's first joint (placed by ``m``) of the hand over
    :data:`SEED_SAMPLES` configurations of the limb's joints drawn uniformly within their bounds (seeded: the
    same map every time); for a cell no sample reached, the largest of its eight neighbours' (0 if none).  A
    sample is reachable, so a scan that starts there and moves outwards while the inverse kinematics succeeds
    finds the map's radius with a probe or two it fails."""
    idx = np.asarray(lb.joint_indices, dtype=int)
    lo, hi = np.asarray(robot.lower, dtype=float)[idx], np.asarray(robot.upper, dtype=float)[idx]
    rng = np.random.default_rng(0)
    q = np.array(q0, dtype=float)
    rel = np.empty((SEED_SAMPLES, 3))
    for s, x in enumerate(rng.uniform(lo, hi, size=(SEED_SAMPLES, len(idx)))):
        q[idx] = x
        rel[s] = np.asarray(robot.hand_position(q, lb.name), dtype=float) - m.translation
    e1, e2, e3 = axes
    j = np.floor((rel @ e3 - depths[0]) / dd + 0.5).astype(int)  # the nearest plane
    x, y = rel @ e1, rel @ e2
    i = np.round(np.mod(np.arctan2(y, x), 2 * math.pi) / (2 * math.pi) * n_dir).astype(int) % n_dir
    out = np.zeros((len(depths), n_dir))
    ok = (j >= 0) & (j < len(depths))
    np.maximum.at(out, (j[ok], i[ok]), np.hypot(x, y)[ok])
    # a cell no sample reached, beside one that some did (a thin wedge the draws missed): its neighbours' largest
    pad = np.pad(out, ((1, 1), (0, 0)))  # no plane beyond the first and the last; the directions wrap around
    pad = np.concatenate([pad[:, -1:], pad, pad[:, :1]], axis=1)
    planes, dirs = out.shape
    near = np.max([pad[a:a + planes, b:b + dirs] for a in range(3) for b in range(3)], axis=0)
    return np.where(out > 0, out, near)


def probed_numerically(robot: Any) -> list[str]:
    """Limbs whose reach map is probed by numeric inverse kinematics (no closed form): seconds to tens of
    seconds each, once per robot and wall orientation (:func:`reach_maps`)."""
    base = {int(j) for j in robot.base_indices}
    return [lb.name for lb in robot.limbs if lb.ik != "analytic" and lb.joint_ids and not set(lb.joint_indices) & base]


def reach_maps(robot: Any, terrain: Any) -> dict[int, Any]:
    """The limbs' reach maps by first joint id, probed once per robot and wall orientation, and kept on disk
    between runs (:mod:`climb_ompl.cache`, under ``reach-maps``)."""
    n = wall_normal(terrain)
    key = _process_key(robot, n)
    if key not in _REACH_MAPS:
        entry = cache_key(robot, n)
        maps = _from_arrays(cache.load(CACHE_KIND, entry) or {})
        if maps is None:
            maps = {lb.joint_ids[0]: t for lb in robot.limbs if (t := _reach_map(robot, lb, n)) is not None}
            cache.save(CACHE_KIND, entry, _to_arrays(maps))
        _REACH_MAPS[key] = maps
    return _REACH_MAPS[key]


def maps_kept(robot: Any, terrain: Any) -> bool:
    """Whether the robot's reach maps for this wall are at hand (in this process or in the disk cache)."""
    n = wall_normal(terrain)
    return _process_key(robot, n) in _REACH_MAPS or cache.has(CACHE_KIND, cache_key(robot, n))


def _process_key(robot: Any, normal: np.ndarray) -> tuple[Any, ...]:
    """The key of a robot's reach maps for a wall normal in this process (:data:`_REACH_MAPS`)."""
    return robot.name, getattr(robot, "urdf_path", None), tuple(np.round(normal, 9))


#: The cache's subfolder of reach maps.
CACHE_KIND = "reach-maps"
_MAP_FIELDS = ("e1", "e2", "e3", "d0", "dd", "radii")


def cache_key(robot: Any, normal: np.ndarray) -> str:
    """The digest naming a robot's reach maps on disk: everything they depend on (the URDF's text, the robot's
    spec, the wall normal, the source of this module, of the robot model and of its inverse kinematics
    (:mod:`climb_ompl.model.limb_ik`) and of its construction (:mod:`climb_ompl.model.build`,
    :mod:`climb_ompl.model.joints`), the versions of Pinocchio and NumPy)."""
    import json

    import pinocchio as pin

    from climb_ompl.model import build, joints, limb_ik
    from climb_ompl.model import robot as robot_module

    spec = json.dumps(getattr(robot, "spec", None), sort_keys=True, default=str)
    src = [Path(m.__file__).read_bytes()  # type: ignore[arg-type]
           for m in (robot_module, build, joints, limb_ik, sys.modules[__name__])]
    return cache.digest(getattr(robot, "urdf_text", ""), spec, np.round(np.asarray(normal, float), 9).tobytes(),
                        *src, pin.__version__, np.__version__)


def _to_arrays(maps: dict[int, Any]) -> dict[str, np.ndarray]:
    return {f"{jid}/{f}": np.asarray(v) for jid, t in maps.items() for f, v in zip(_MAP_FIELDS, t, strict=True)}


def _from_arrays(arrays: dict[str, np.ndarray]) -> dict[int, Any] | None:
    """The maps of a cache entry, or ``None`` if it is empty or not a set of maps."""
    maps: dict[int, list[Any]] = {}
    for name, v in arrays.items():
        jid, _, f = name.partition("/")
        if not jid.isdigit() or f not in _MAP_FIELDS:
            return None
        maps.setdefault(int(jid), [None] * len(_MAP_FIELDS))[_MAP_FIELDS.index(f)] = v
    if not maps or any(v is None for t in maps.values() for v in t):
        return None
    return {jid: (t[0], t[1], t[2], float(t[3]), float(t[4]), t[5]) for jid, t in maps.items()}


def map_limits(radii: np.ndarray, margin: float = 0.015) -> np.ndarray:
    """The radius a target may have in each (plane, direction) cell of a reach map: the largest of the
    cell's three neighbouring directions, plus ``margin``.  A target between two planes takes the larger of
    their limits (:class:`ShouldersReach`)."""
    r = np.asarray(radii, dtype=float)
    return np.maximum(np.maximum(np.roll(r, 1, axis=-1), r), np.roll(r, -1, axis=-1)) + margin


class ShouldersReach:
    """A cheap test before closing the chains: each hand target inside its limb's reach map.

    ``pre`` lists ``(first joint id, where the hand frame touches the hold, reach)`` per contact limb.  The
    targets are hand frames, not holds: a sphere contact's radius is in them
    (:func:`climb_ompl.manifold.stance.hand_targets`), as it is in the probed map.  The target, in the first joint's
    frame before its motion, has a depth along the map's normal and a direction and distance in its plane;
    the distance must not exceed :func:`map_limits` of the two planes around that depth (a target deeper than
    the probed planes on the hand's side is beyond the reach).  The planes cover one side of the joint; a target
    on the other side must lie within ``reach`` of the joint (a sphere: the sum of the link offsets bounds an
    all-revolute limb; give ``math.inf`` for a limb with a prismatic joint).
    Built once per FIND-TRANSITION call and called at every base draw: the tables are prepared as plain floats
    so that a call is one forward kinematics and a few dozen float operations, stopping at the first limb out
    of reach.
    """

    def __init__(self, robot: Any, maps: dict[int, Any], pre: list[tuple[int, np.ndarray, float]]):
        m = robot.model
        self.robot = robot
        self.rows: list[tuple[Any, ...]] = []
        self._limits: list[np.ndarray] = []  # each row's limits as an array, for :meth:`many`
        self._arrays: tuple[np.ndarray, ...] | None = None  # the rows as arrays over the limbs, for :meth:`many`
        for jid, p, reach in pre:
            tab = maps.get(jid)
            if tab is None:
                continue
            known = _MAP_TERMS.get(id(tab))
            if known is None or known[0] is not tab:
                e1, e2, e3, d0, dd, radii = tab
                place = m.jointPlacements[jid]
                rot = np.asarray(place.rotation, dtype=float)
                lim = map_limits(radii)
                known = _MAP_TERMS[id(tab)] = (tab, (int(m.parents[jid]),
                                                     tuple(np.asarray(place.translation, dtype=float).tolist()),
                                                     tuple((rot @ e1).tolist()), tuple((rot @ e2).tolist()),
                                                     tuple((rot @ e3).tolist()), d0, dd,
                                                     tuple(tuple(row) for row in lim.tolist())), lim)
            self.rows.append((known[1][0], tuple(np.asarray(p, dtype=float).tolist()), float(reach) ** 2,
                              *known[1][1:]))
            self._limits.append(known[2])

    def __call__(self, q: np.ndarray) -> bool:
        """Whether every target lies within its limb's reach map at ``q``."""
        import pinocchio as pin

        if not self.rows:
            return True
        r = self.robot
        pin.forwardKinematics(r.model, r.data, q)
        frames: dict[int, tuple[list[list[float]], list[float]]] = {}
        two_pi = 2.0 * math.pi
        for parent, p, reach2, off, a1, a2, a3, d0, dd, limit in self.rows:
            if parent not in frames:
                f = r.data.oMi[parent]
                frames[parent] = (f.rotation.tolist(), f.translation.tolist())
            rot, t = frames[parent]
            dx, dy, dz = p[0] - t[0], p[1] - t[1], p[2] - t[2]
            # the target in the parent joint's frame, less the joint's placement
            lx = dx * rot[0][0] + dy * rot[1][0] + dz * rot[2][0] - off[0]
            ly = dx * rot[0][1] + dy * rot[1][1] + dz * rot[2][1] - off[1]
            lz = dx * rot[0][2] + dy * rot[1][2] + dz * rot[2][2] - off[2]
            j = int(math.floor((lx * a3[0] + ly * a3[1] + lz * a3[2] - d0) / dd))
            if j + 1 >= len(limit):
                return False  # deeper than the reach on the hand's side
            if j < 0:  # on the other side of the joint, not probed: within the limb's reach of the joint
                if lx * lx + ly * ly + lz * lz > reach2:
                    return False
                continue
            x = lx * a1[0] + ly * a1[1] + lz * a1[2]
            y = lx * a2[0] + ly * a2[1] + lz * a2[2]
            n = len(limit[j])
            k = int(round((math.atan2(y, x) % two_pi) / two_pi * n)) % n
            if math.hypot(x, y) > max(limit[j][k], limit[j + 1][k]):
                return False
        return True

    def many(self, R: np.ndarray, t: np.ndarray) -> np.ndarray:
        """:meth:`__call__` for many configurations at once, given the pose of the one joint frame carrying every
        limb tested (:class:`climb_ompl.model.base_pose.BasePose`): rotations ``R`` ``(k, 3, 3)`` and
        positions ``t`` ``(k, 3)``; ``(k,)`` bool.  The same arithmetic, in compiled code
        (:func:`climb_ompl.model.draw_kernels.within_reach`)."""
        from climb_ompl.model.draw_kernels import within_reach

        if not self.rows:
            return np.ones(len(t), dtype=bool)
        if self._arrays is None:
            self._arrays = self._stacked()
        return within_reach(np.ascontiguousarray(R, dtype=float), np.ascontiguousarray(t, dtype=float),
                            *self._arrays)

    def _stacked(self) -> tuple[np.ndarray, ...]:
        """The rows as arrays over the limbs (the limit tables padded to the largest)."""
        cols = list(zip(*self.rows, strict=True))
        limits = self._limits
        planes, dirs = max(x.shape[0] for x in limits), max(x.shape[1] for x in limits)
        LIM = np.full((len(limits), planes, dirs), -math.inf)
        for i, x in enumerate(limits):
            LIM[i, :x.shape[0], :x.shape[1]] = x
        arr = [np.ascontiguousarray(cols[i], dtype=float) for i in (1, 3, 4, 5, 6, 7, 8, 2)]
        return (*arr, LIM, np.array([x.shape[0] for x in limits], dtype=np.int64),
                np.array([x.shape[1] for x in limits], dtype=np.int64))


__all__ = ["shoulders", "pair_reach", "hop_reach", "reachable_holds", "wall_normal",
           "reach_maps", "map_limits",
           "probed_numerically", "cache_key", "maps_kept",
           "ShouldersReach"]
