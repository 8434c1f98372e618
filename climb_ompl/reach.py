"""What a limb can reach: inverse kinematics nearest a reference, reach maps and reach prefilters.

Cheap necessary conditions used before any inverse kinematics (Bretl 2006, sec. 4.3: "it is very
inefficient to check this constraint after sampling a configuration"): the largest distance between two
hands (:func:`pair_reach`), and a per-limb map of the largest in-plane distance from its first joint to a
reachable hold (:func:`reach_maps`, :func:`shoulders_reach`).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

_REACH_MAPS: dict[Any, dict[int, Any]] = {}
#: per reach map (by identity, the map kept alongside): its joint's parent, placement, axes and radius limits
_MAP_TERMS: dict[int, tuple[Any, tuple[Any, ...]]] = {}


def ik_nearest(robot: Any, limb: str, q: np.ndarray, target: np.ndarray, ref: np.ndarray) -> np.ndarray | None:
    """The inverse-kinematics solution of ``limb`` placing its hand at ``target`` whose limb joints are
    nearest ``ref`` (``q`` otherwise), or ``None`` when the target is out of reach."""
    return robot.limb_ik_nearest(limb, q, target, ref)


def angle_joints(robot: Any) -> np.ndarray:
    """``(nq,)`` bool: which coordinates are angles (revolute joints); the others are translations."""
    out = np.ones(robot.nq, dtype=bool)
    m = robot.model
    for jid in range(1, m.njoints):
        j = m.joints[jid]
        name = j.shortname()
        if j.nq == 1 and ("Prismatic" in name or name.endswith(("PX", "PY", "PZ"))):
            out[j.idx_q] = False
    return out


def shoulders(robot: Any, q: np.ndarray) -> dict[str, np.ndarray]:
    """World position of each limb's first joint at ``q`` (the hand's position for a limb with no joints)."""
    import pinocchio as pin

    pin.forwardKinematics(robot.model, robot.data, q)
    return {lb.name: np.asarray(robot.data.oMi[lb.joint_ids[0] if lb.joint_ids else 0].translation, dtype=float)
            for lb in robot.limbs}


def pair_reach(robot: Any) -> dict[tuple[str, str], float]:
    """Largest distance between two holds two limbs touch at once: the shoulders' distance at the nominal posture
    plus both reaches (first joint to hand frame), plus both contact radii.

    A sphere contact of radius ``r`` puts the hand frame at ``p + r n`` for a hold at ``p`` with normal ``n``
    (:meth:`climb_ompl.contact.Contact.hand_target`; an ``offset`` is inside the reach, the hand frame being the
    sphere's centre), so two holds whose normals face each other lie up to ``r_a + r_b`` farther apart than
    the hand frames touching them.
    """
    sh = shoulders(robot, np.asarray(robot.nominal_q, dtype=float))
    names = [lb.name for lb in robot.limbs]
    grow = {lb.name: robot.limb(lb.name).reach + _radius(robot, lb.name) for lb in robot.limbs}
    return {(a, b): float(np.linalg.norm(sh[a] - sh[b])) + grow[a] + grow[b] for a in names for b in names}


def _radius(robot: Any, limb: str) -> float:
    """The contact sphere's radius of ``limb`` (0 for a point contact)."""
    contact = getattr(robot.limb(limb), "contact", None)
    return float(getattr(contact, "radius", 0.0) or 0.0)


def wall_normal(terrain: Any) -> np.ndarray:
    """The terrain's wall normal: its first plane surface, else the holds' mean normal made horizontal."""
    for srf in terrain.surfaces:
        if srf.type == "plane" and srf.normal is not None:
            return np.asarray(srf.normal, dtype=float)
    n = np.mean([h.n for h in terrain.holds], axis=0)
    n = n - (n @ terrain.up) * terrain.up
    return n / np.linalg.norm(n) if np.linalg.norm(n) > 1e-9 else np.array([0.0, 1.0, 0.0])


def _reach_map(robot: Any, lb: Any, normal: np.ndarray, n_dir: int = 36,
               dr: float = 0.02) -> tuple[np.ndarray, np.ndarray, np.ndarray] | None:
    """Largest in-plane distance from a limb's first joint to a reachable hand position, per direction.

    Probed once per robot with :meth:`RobotModel.limb_ik` at the nominal configuration, on the plane of the
    nominal hand perpendicular to the wall normal, in the first joint's frame (so it turns with the body).
    """
    import pinocchio as pin

    if not lb.joint_ids or set(lb.joint_indices) & set(int(j) for j in robot.base_indices):
        return None
    q0 = np.asarray(robot.nominal_q, dtype=float)
    pin.forwardKinematics(robot.model, robot.data, q0)
    jid = lb.joint_ids[0]
    m = robot.data.oMi[robot.model.parents[jid]] * robot.model.jointPlacements[jid]  # before the joint's motion
    n = normal
    e1w = np.cross(n, [0.0, 0.0, 1.0]) if abs(n[2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    e1w /= np.linalg.norm(e1w)
    e2w = np.cross(n, e1w)
    hand = np.asarray(robot.hand_position(q0, lb.name), dtype=float)
    centre = m.translation + ((hand - m.translation) @ n) * n  # shoulder projected on the hand plane
    radii = np.zeros(n_dir)
    for i in range(n_dir):
        a = 2 * math.pi * i / n_dir
        u = math.cos(a) * e1w + math.sin(a) * e2w
        rad = 0.0
        x = dr
        while x <= 1.2 * lb.reach + 1e-9:
            if robot.limb_ik(lb.name, q0, centre + x * u):
                rad = x
            x += dr
        radii[i] = rad
    # directions in the joint frame: bin k of the table covers local angle 2 pi k / n_dir
    return m.rotation.T @ e1w, m.rotation.T @ e2w, radii + dr


def reach_maps(robot: Any, terrain: Any) -> dict[int, Any]:
    """The limbs' reach maps by first joint id, probed once per robot and wall orientation."""
    n = wall_normal(terrain)
    key = (robot.name, getattr(robot, "urdf_path", None), tuple(np.round(n, 9)))
    if key not in _REACH_MAPS:
        _REACH_MAPS[key] = {lb.joint_ids[0]: t for lb in robot.limbs if (t := _reach_map(robot, lb, n)) is not None}
    return _REACH_MAPS[key]


class ShouldersReach:
    """A cheap test before closing the chains: each hand target inside its limb's reach map.

    ``pre`` lists ``(first joint id, where the hand frame touches the hold, reach)`` per contact limb.  The
    targets are hand frames, not holds: a sphere contact's radius is in them
    (:func:`climb_ompl.stance.hand_targets`), as it is in the probed map.  In the target's direction (in the
    plane of the map, in the first joint's frame before its motion) its in-plane distance must not exceed the
    map's radius there (the largest of three neighbouring directions) plus 1 cm.  Built once per
    FIND-TRANSITION call and called at every base draw: the tables are prepared as plain floats so that a call
    is one forward kinematics and a few dozen float operations, stopping at the first limb out of reach.
    """

    def __init__(self, robot: Any, maps: dict[int, Any], pre: list[tuple[int, np.ndarray, float]]):
        m = robot.model
        self.robot = robot
        self.rows: list[tuple[int, tuple[float, ...], tuple[float, ...], tuple[float, ...], tuple[float, ...],
                              tuple[float, ...]]] = []
        for jid, p, _ in pre:
            tab = maps.get(jid)
            if tab is None:
                continue
            known = _MAP_TERMS.get(id(tab))
            if known is None or known[0] is not tab:
                e1, e2, radii = tab
                place = m.jointPlacements[jid]
                rot = np.asarray(place.rotation, dtype=float)
                r = np.asarray(radii, dtype=float)
                limit = np.maximum(np.maximum(np.roll(r, 1), r), np.roll(r, -1)) + 0.01
                known = _MAP_TERMS[id(tab)] = (tab, (int(m.parents[jid]),
                                                     tuple(np.asarray(place.translation, dtype=float).tolist()),
                                                     tuple((rot @ e1).tolist()), tuple((rot @ e2).tolist()),
                                                     tuple(limit.tolist())))
            parent, off, a1, a2, limit = known[1]
            self.rows.append((parent, tuple(np.asarray(p, dtype=float).tolist()), off, a1, a2, limit))

    def __call__(self, q: np.ndarray) -> bool:
        """Whether every target lies within its limb's reach map at ``q``."""
        import pinocchio as pin

        if not self.rows:
            return True
        r = self.robot
        pin.forwardKinematics(r.model, r.data, q)
        frames: dict[int, tuple[list[list[float]], list[float]]] = {}
        two_pi = 2.0 * math.pi
        for parent, p, off, a1, a2, limit in self.rows:
            if parent not in frames:
                f = r.data.oMi[parent]
                frames[parent] = (f.rotation.tolist(), f.translation.tolist())
            rot, t = frames[parent]
            dx, dy, dz = p[0] - t[0], p[1] - t[1], p[2] - t[2]
            # the target in the parent joint's frame, less the joint's placement
            lx = dx * rot[0][0] + dy * rot[1][0] + dz * rot[2][0] - off[0]
            ly = dx * rot[0][1] + dy * rot[1][1] + dz * rot[2][1] - off[1]
            lz = dx * rot[0][2] + dy * rot[1][2] + dz * rot[2][2] - off[2]
            x = lx * a1[0] + ly * a1[1] + lz * a1[2]
            y = lx * a2[0] + ly * a2[1] + lz * a2[2]
            n = len(limit)
            k = int(round((math.atan2(y, x) % two_pi) / two_pi * n)) % n
            if math.hypot(x, y) > limit[k]:
                return False
        return True


__all__ = ["ik_nearest", "angle_joints", "shoulders", "pair_reach", "wall_normal", "reach_maps", "ShouldersReach"]
