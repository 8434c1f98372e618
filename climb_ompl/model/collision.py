"""Collision checking of a robot (:class:`climb_ompl.model.robot.RobotModel`) against the terrain and itself.

Coal geometry from ``pin.buildGeomFromUrdf``: the robot against the terrain's surfaces (``plane`` as a solid
half-space behind the plane, ``box``, and 2-D ``circle`` obstacles as discs in the x-z plane) and, if enabled,
against itself.  Self-collision skips, as MoveIt does, geometry pairs on the same body or on bodies joined by a
joint (adjacent links), the spec's ``ignore_collision_pairs`` and the ``disable_collisions`` pairs of the spec's
SRDF (``pin.removeCollisionPairs``).  Near a contact limb's hold the limb's contact geometry may touch the
terrain (:mod:`climb_ompl.model.contact`): with a point contact, the geometry on the hand frame's link (a small tip at
the contact point) is exempt from terrain collision; the links a contact lists (for a sphere foot by default the
hand's link and the links moved only by the limb's last joint) may touch the terrain within ``near`` metres of
the hold; the rest of the limb may not.
"""

from __future__ import annotations

import math
from collections.abc import Iterable
from dataclasses import dataclass, field
from typing import Any, NamedTuple

import numpy as np

from climb_ompl.errors import RobotModelError

__all__ = ["CollisionChecker", "CollisionSet", "convex_hull"]


def convex_hull(geometry: Any) -> Any | None:
    """The convex hull of a Coal triangle mesh (a ``Convex`` of the hull's vertices and faces, from scipy's qhull), or
    ``None`` for other geometry (or a flat mesh, which has no hull volume).  (Coal's own
    ``buildConvexRepresentation`` keeps every vertex of the mesh, and its support search then stopped short of the
    deepest point: 1 mm short on Solo-12's foot.)

    Why the terrain is checked against hulls (:class:`CollisionChecker`, ``hulls``): Coal tests a mesh against the
    terrain's half-space through its bounding-volume tree, triangle by triangle where they overlap, and a foot
    resting on a plane overlaps it with hundreds of triangles (milliseconds per check for meshes of a few thousand
    triangles: most of a climb's time), while a hull is one support-function query (GJK/EPA).  A hull contains its
    mesh, so a posture free of the terrain with the hulls is free of it with the meshes."""
    import coal
    from scipy.spatial import ConvexHull, QhullError

    if not hasattr(geometry, "vertices") or getattr(geometry, "num_tris", 0) <= 0:
        return None
    P = np.asarray(geometry.vertices(), dtype=float)
    try:
        hull = ConvexHull(P)
    except (QhullError, ValueError):
        return None
    index = {int(v): i for i, v in enumerate(hull.vertices)}
    points, faces = coal.StdVec_Vec3s(), coal.StdVec_Triangle()
    for v in hull.vertices:
        points.append(P[int(v)])
    for a, b, c in hull.simplices:
        faces.append(coal.Triangle(index[int(a)], index[int(b)], index[int(c)]))
    return coal.Convex(points, faces)


def _rot(axis: np.ndarray, angle: float) -> np.ndarray:
    """Rotation matrix about unit ``axis`` by ``angle`` (Rodrigues, written out: a disc obstacle's placement)."""
    x, y, z = (float(v) for v in axis)
    c, s = math.cos(angle), math.sin(angle)
    t = 1.0 - c
    return np.array([[c + t * x * x, t * x * y - s * z, t * x * z + s * y],
                     [t * x * y + s * z, c + t * y * y, t * y * z - s * x],
                     [t * x * z - s * y, t * y * z + s * x, c + t * z * z]])


class SrdfLinks(NamedTuple):
    """What an SRDF's ``disable_collisions`` name, against a URDF's Pinocchio model (:func:`srdf_links`)."""

    name: str  #: the SRDF's robot name
    pairs: list[tuple[str, str]]  #: its disable_collisions link pairs
    unknown: set[str]  #: the links they name that the model lacks
    bad: int  #: the pairs naming such a link


def srdf_links(path: Any, model: Any) -> SrdfLinks:
    """An SRDF's robot name, its ``disable_collisions`` link pairs, the links they name that ``model`` (the URDF's
    Pinocchio model) lacks, and how many pairs name one.

    Raises:
        RobotModelError: the file is not XML.
    """
    import xml.etree.ElementTree as ET

    try:
        root = ET.parse(str(path)).getroot()
    except (ET.ParseError, OSError) as exc:
        raise RobotModelError(path, "srdf", f"not readable as XML ({exc})") from None
    pairs = [(e.get("link1", ""), e.get("link2", "")) for e in root.iter("disable_collisions")]
    links = {f.name for f in model.frames}
    unknown = {x for p in pairs for x in p if x not in links}
    return SrdfLinks(root.get("name", ""), pairs, unknown, sum(1 for a, b in pairs if a in unknown or b in unknown))


def check_srdf(path: Any, model: Any, src: Any = None) -> SrdfLinks:
    """Refuse an SRDF of another robot, which Pinocchio would apply silently (:func:`srdf_links`, returned when
    the SRDF is kept): every one of its ``disable_collisions`` pairs names a link ``model`` lacks, or most do and
    its robot has another name (:func:`same_robot_name`).  Fewer are noted by ``climb-ompl robot check``.

    Raises:
        RobotModelError: naming the spec ``src`` (else the SRDF) and its field ``srdf``, the SRDF, a link it names,
            and both robots.
    """
    info = srdf_links(path, model)
    name, pairs, unknown, bad = info
    other = not same_robot_name(name, model.name)
    if pairs and (bad == len(pairs) or (other and 2 * bad > len(pairs))):
        raise RobotModelError(src or path, "srdf", f"{'' if src is None else f'{path}: '}{bad} of its {len(pairs)} "
                              "disable_collisions pairs name links not in "
                              f"the URDF (e.g. {sorted(unknown)[0]!r})"
                              + (f", and the SRDF is of robot {name!r}, the URDF of {model.name!r}" if other else "")
                              + ": an SRDF of another robot?")
    return info


def same_robot_name(a: str, b: str) -> bool:
    """Whether an SRDF's and a URDF's robot names name one robot: equal but for case, separators and a
    ``description`` suffix (example-robot-data's ``go2`` and ``go2_description``, ``icub`` and ``iCub``)."""
    def key(x: str) -> str:
        return "".join(c for c in x.lower() if c.isalnum()).removesuffix("description")

    return not a or not b or key(a) == key(b)


@dataclass
class CollisionSet:
    """The robot's geometry and one terrain's surfaces in one Pinocchio geometry model, with a broad phase per
    set of contact limbs (and clearance), and per contact limb the pairs checked by :meth:`CollisionChecker._near_hits`
    (``terrain`` ``None``: self-collision only)."""

    geom_model: Any
    datas: dict[Any, Any] = field(default_factory=dict)  # by contact limbs (and clearance)
    terrain_geoms: tuple[int, ...] = ()
    terrain: Any = None
    near_pairs: dict[int, tuple[int, ...]] = field(default_factory=dict)  # by limb: (contact link, terrain) pairs
    hull_of: dict[int, int] = field(default_factory=dict)  # a mesh's hull (checked against the terrain) -> the mesh
    hull_points: dict[int, np.ndarray] = field(default_factory=dict)  # a hull's vertices (n, 3), its own frame
    planes: dict[int, tuple[np.ndarray, float]] = field(default_factory=dict)  # a half-space: {x: n . x <= d}

    def robot_geom(self, g: int) -> int:
        """The robot geometry ``g`` stands for (itself, or the mesh a hull was built from)."""
        return self.hull_of.get(g, g)


class CollisionChecker:
    """The collision queries of one robot (:meth:`RobotModel.in_collision
    <climb_ompl.model.robot.RobotModel.in_collision>`
    and its siblings delegate here).  Built once the robot's limbs and collision geometry are final; the terrain's
    collision sets are built on first use and cached (up to 16 terrains).

    Args:
        robot: the :class:`~climb_ompl.model.robot.RobotModel` (its Pinocchio model and data, collision geometry, limbs
            and SRDF).
        ignore: the spec's ``ignore_collision_pairs`` (pairs of link names).
        src: the spec's name, for error messages.
        hulls: check the URDF's collision meshes against the terrain as their convex hulls (:func:`convex_hull`;
            the spec's ``collision_meshes: convex``, the default); self-collision keeps the meshes, whose hollows
            other links may nest in (a leg beside a body).
    """

    def __init__(self, robot: Any, ignore: Any, src: str, hulls: bool = True):
        self.robot = robot
        self._pin = robot._pin
        self.model = robot.model
        self.collision_model = robot.collision_model
        self.limbs = robot.limbs
        self.srdf_path = robot.srdf_path
        self._limb_index = robot._limb_index
        self._ignore = self._ignore_pairs(ignore or [], src)
        self._self_pairs = self._compute_self_pairs()
        self._hand_geoms = self._compute_hand_geoms()
        #: per limb, the geometry that may touch the terrain within ``contact.near`` of its hold
        self.near_geoms = self._compute_near_geoms(src)
        self._self_set: CollisionSet | None = None
        self._terrain_sets: dict[int, CollisionSet] = {}
        self._hulls: dict[int, Any] | None = None if hulls else {}  # by robot geometry: its hull (built on first use)

    @property
    def hulls(self) -> dict[int, Any]:
        """The convex hull of each collision mesh checked against the terrain, by geometry index (built on first
        use; empty with ``hulls`` off or without meshes)."""
        if self._hulls is None:
            objs = self.collision_model.geometryObjects
            self._hulls = {i: h for i in range(len(objs)) if (h := convex_hull(objs[i].geometry)) is not None}
        return self._hulls

    @property
    def data(self) -> Any:
        """The robot's Pinocchio data (the placements of the last check)."""
        return self.robot.data

    @property
    def self_collision_enabled(self) -> bool:
        """The robot's :attr:`~climb_ompl.model.robot.RobotModel.self_collision_enabled` (its spec's
        ``self_collision``)."""
        return bool(self.robot.self_collision_enabled)

    def self_collision(self, q: np.ndarray) -> bool:
        """True if two of the robot's links collide (pairs that are not adjacent and not ignored).

        Always False for robots whose spec sets ``self_collision: false``.
        """
        if not self.self_collision_enabled or not self._self_pairs:
            return False
        if self._self_set is None:
            self._self_set = self._make_collision_set(None)
        mgr = self._self_set.datas[frozenset()]
        return bool(self._pin.computeCollisions(self.model, self.data, mgr, np.asarray(q, dtype=float), True))

    def in_collision(self, q: np.ndarray, terrain: Any = None,
                     contact_limbs: Iterable[Any] = (), clearance: float = 0.0) -> bool:
        """True if the robot at ``q`` hits the terrain's surfaces or (if enabled) itself.

        Args:
            q: configuration.
            terrain: a :class:`climb_ompl.model.terrain.Terrain` (its ``surfaces``), or ``None`` for self-collision
            only.
            contact_limbs: limbs whose hands are at holds: their contact geometry may touch the terrain
                near the hold (:mod:`climb_ompl.model.contact`: a point contact's tip anywhere; a contact's
                ``links`` within ``near`` metres of the terrain's hold nearest to the hand).
            clearance: two links of the robot closer than this (metres) count as colliding (Coal's
                security margin on the self-collision pairs; the terrain pairs keep none).
        """
        if (terrain is None or not getattr(terrain, "surfaces", ())) and clearance <= 0.0:
            return self.self_collision(q)
        cs, limbs, mgr = self._collision_manager(terrain, contact_limbs, clearance)
        if self._pin.computeCollisions(self.model, self.data, mgr, np.asarray(q, dtype=float), True):
            return True
        return any(self._near_hits(li, cs, mgr._keep[1], first=True) for li in limbs if cs.near_pairs.get(li))

    def collisions(self, q: np.ndarray, terrain: Any = None, contact_limbs: Iterable[Any] = (),
                   clearance: float = 0.0) -> list[tuple[str, str]]:
        """The colliding pairs behind :meth:`in_collision` (same arguments), by name, for diagnostics.

        Returns:
            ``(link, link)`` for a self-collision, ``(link, "terrain <k> <type>")`` for the robot against the
            terrain's surface ``k``; empty exactly when :meth:`in_collision` is False.
        """
        q = np.asarray(q, dtype=float)
        cs, limbs, mgr = self._collision_manager(terrain, contact_limbs, clearance)
        gm, gd = mgr._keep
        self._pin.computeCollisions(self.model, self.data, gm, gd, q, False)
        pairs = [(cp.first, cp.second) for k, cp in enumerate(gm.collisionPairs)
                 if gd.activeCollisionPairs[k] and gd.collisionResults[k].isCollision()]
        for li in limbs:
            pairs += self._near_hits(li, cs, gd, first=False)
        return [(self._geom_label(cs, a), self._geom_label(cs, b)) for a, b in pairs]

    def _geom_label(self, cs: CollisionSet, g: int) -> str:
        if g in cs.terrain_geoms:
            k = cs.terrain_geoms.index(g)
            return f"terrain {k} {cs.terrain.surfaces[k].type}"
        return str(self.model.frames[cs.geom_model.geometryObjects[g].parentFrame].name)

    def _collision_manager(self, terrain: Any, contact_limbs: Iterable[Any],
                           clearance: float) -> tuple[CollisionSet, frozenset[int], Any]:
        """The collision set of ``terrain`` (cached) and its broad phase for these contact limbs and clearance."""
        cs = self._terrain_sets.get(id(terrain))
        if cs is None or cs.terrain is not terrain:
            if len(self._terrain_sets) > 16:
                self._terrain_sets.clear()
            cs = self._make_collision_set(terrain)
            self._terrain_sets[id(terrain)] = cs
        limbs = frozenset(self._limb_index(lb) for lb in contact_limbs)
        key = limbs if clearance <= 0.0 else (limbs, float(clearance))
        mgr = cs.datas.get(key)
        if mgr is None:
            gd = cs.geom_model.createData()
            for k, pair in enumerate(cs.geom_model.collisionPairs):
                g1, g2 = pair.first, pair.second
                robot_pair = g1 not in cs.terrain_geoms and g2 not in cs.terrain_geoms
                if robot_pair and clearance > 0.0:
                    gd.collisionRequests[k].security_margin = float(clearance)
                r1, r2 = cs.robot_geom(g1), cs.robot_geom(g2)
                for li in limbs:
                    hg = self._hand_geoms[li].union(self.near_geoms[li])
                    if (r1 in hg and g2 in cs.terrain_geoms) or (r2 in hg and g1 in cs.terrain_geoms):
                        gd.deactivateCollisionPair(k)
                    if (r1 in self.near_geoms[li] and g2 in cs.terrain_geoms) or (
                            r2 in self.near_geoms[li] and g1 in cs.terrain_geoms):
                        gd.collisionRequests[k].enable_contact = True  # checked by _near_hits
                        gd.collisionRequests[k].num_max_contacts = 8
            mgr = cs.datas[key] = self._manager(cs.geom_model, gd)
        return cs, limbs, mgr

    def _near_hits(self, li: int, cs: CollisionSet, gd: Any, first: bool) -> list[tuple[int, int]]:
        """Pairs (geometry, terrain geometry) where a contact link of limb ``li`` touches the terrain farther
        than ``contact.near`` from its hold (the terrain's hold nearest to the hand).  ``gd`` (with contacts
        requested on those pairs) and ``self.data`` hold the placements of the last check.  ``first``: stop at
        the first such pair."""
        pin = self._pin
        out: list[tuple[int, int]] = []
        pairs = cs.near_pairs.get(li, ())
        if not pairs:
            return out
        lb = self.limbs[li]
        hand = np.array(pin.updateFramePlacement(self.model, self.data, lb.frame_id).translation)
        P = cs.terrain.positions
        hold = P[int(np.argmin(np.linalg.norm(P - hand, axis=1)))]
        cps = cs.geom_model.collisionPairs
        for k in pairs:
            if not pin.computeCollision(cs.geom_model, gd, k):
                continue
            a, b = cps[k].first, cps[k].second
            pts, plane = cs.hull_points.get(a), cs.planes.get(b)
            if pts is not None and plane is not None:  # a hull in a half-space: where its vertices sink (Coal
                M = gd.oMg[a]  # gives one contact point there; a mesh gives one per triangle that sinks)
                X = pts @ np.asarray(M.rotation).T + np.asarray(M.translation)
                sunk = X[X @ plane[0] <= plane[1]]
                far = bool(len(sunk)) and float(np.max(np.linalg.norm(sunk - hold, axis=1))) > lb.contact.near
            else:
                far = any(np.linalg.norm(np.asarray(c.pos) - hold) > lb.contact.near
                          for c in gd.collisionResults[k].getContacts())
            if far:
                out.append((cps[k].first, cps[k].second))
                if first:
                    return out
        return out

    def _manager(self, gm: Any, gd: Any) -> Any:
        """A broad phase over the active pairs of ``gd``: axis-aligned boxes first, Coal's narrow phase after.

        The naive (all-pairs box test) manager is the fastest here: with a few tens of geometries and an
        unbounded wall half-space, tree managers cost more than they prune (``climb-ompl bench robot``).
        """
        mgr = self._pin.BroadPhaseManager_NaiveCollisionManager(self.model, gm, gd)
        mgr._keep = (gm, gd)  # the manager refers to both; keep them alive with it
        return mgr

    def collision_pairs(self) -> list[tuple[str, str]]:
        """Names of the robot geometry pairs tested for self-collision (empty when disabled)."""
        if not self.self_collision_enabled:
            return []
        objs = self.collision_model.geometryObjects
        return [(objs[i].name, objs[j].name) for i, j in self._self_pairs]

    def _make_collision_set(self, terrain: Any) -> CollisionSet:
        import coal

        pin = self._pin
        gm = self.collision_model.copy()
        gm.removeAllCollisionPairs()
        if self.self_collision_enabled:
            for i, j in self._self_pairs:
                gm.addCollisionPair(pin.CollisionPair(i, j))
        n_robot = gm.ngeoms
        tg: list[int] = []
        for k, s in enumerate(getattr(terrain, "surfaces", ()) if terrain is not None else ()):
            c = np.asarray(s.center, dtype=float)
            if s.type == "plane":
                n = np.asarray(s.normal, dtype=float)
                n = n / np.linalg.norm(n)
                geom, placement = coal.Halfspace(n, float(n @ c)), pin.SE3.Identity()
            elif s.type == "box":
                geom, placement = coal.Box(*[float(x) for x in s.size]), pin.SE3(np.eye(3), c)
            elif s.type == "circle":  # a disc in the x-z plane: a cylinder along y
                geom = coal.Cylinder(float(s.radius), 1.0)
                placement = pin.SE3(_rot(np.array([1.0, 0.0, 0.0]), math.pi / 2), c)
            else:  # pragma: no cover - terrain.py validates surface types
                continue
            tg.append(gm.addGeometryObject(pin.GeometryObject(f"terrain_{k}_{s.type}", 0, 0, placement, geom)))
        hull_of: dict[int, int] = {}
        if tg:  # each mesh against the terrain as its hull: a copy of its geometry object with the hull's shape
            for gi, hull in self.hulls.items():
                o = gm.geometryObjects[gi]
                hull_of[gm.addGeometryObject(pin.GeometryObject(f"{o.name}_hull", o.parentJoint, o.parentFrame,
                                                                o.placement, hull))] = gi
        face = {gi: hi for hi, gi in hull_of.items()}
        for gi in range(n_robot):
            for gj in tg:
                gm.addCollisionPair(pin.CollisionPair(face.get(gi, gi), gj))
        cs = CollisionSet(gm, terrain_geoms=tuple(tg), terrain=terrain, hull_of=hull_of,
                          hull_points={hi: np.asarray(gm.geometryObjects[hi].geometry.points(), dtype=float)
                                       for hi in hull_of},
                          planes={g: (np.asarray(gm.geometryObjects[g].geometry.n, dtype=float),
                                      float(gm.geometryObjects[g].geometry.d)) for g in tg
                                  if type(gm.geometryObjects[g].geometry).__name__ == "Halfspace"})
        for li, near in enumerate(self.near_geoms):
            ks = tuple(k for k, cp in enumerate(gm.collisionPairs)
                       if (cs.robot_geom(cp.first) in near and cp.second in tg)
                       or (cs.robot_geom(cp.second) in near and cp.first in tg))
            if ks:
                cs.near_pairs[li] = ks
        cs.datas[frozenset()] = self._manager(gm, gm.createData())
        return cs

    def _compute_self_pairs(self) -> list[tuple[int, int]]:
        """Geometry pairs tested for self-collision: not on one body nor on adjacent bodies (MoveIt's default),
        not ignored by the spec, not disabled by the SRDF."""
        m = self.model
        objs = list(self.collision_model.geometryObjects)
        allowed = self._srdf_allowed_pairs()
        pairs = []
        for i in range(len(objs)):
            for j in range(i + 1, len(objs)):
                ji, jj = objs[i].parentJoint, objs[j].parentJoint
                if ji == jj or m.parents[ji] == jj or m.parents[jj] == ji:
                    continue  # same body or bodies joined by a joint (they touch at the joint)
                li, lj = m.frames[objs[i].parentFrame].name, m.frames[objs[j].parentFrame].name
                if frozenset((li, lj)) in self._ignore:
                    continue
                if allowed is not None and (i, j) not in allowed:
                    continue
                pairs.append((i, j))
        return pairs

    def _srdf_allowed_pairs(self) -> set[tuple[int, int]] | None:
        """Geometry pairs left after removing the SRDF's ``disable_collisions`` (``pin.removeCollisionPairs``)."""
        if self.srdf_path is None:
            return None
        pin = self._pin
        gm = self.collision_model.copy()
        gm.addAllCollisionPairs()
        try:
            pin.removeCollisionPairs(self.model, gm, str(self.srdf_path))
        except (RuntimeError, ValueError, OSError) as exc:
            raise RobotModelError(self.srdf_path, "srdf", f"Pinocchio cannot read it ({exc})") from None
        return {(min(p.first, p.second), max(p.first, p.second)) for p in gm.collisionPairs}

    def _hand_link_geoms(self, lb: Any) -> frozenset[int]:
        """Geometry on the link of ``lb``'s hand frame (an operational frame: the link it hangs on)."""
        m = self.model
        hosts = {lb.frame_id}
        fid = lb.frame_id
        while m.frames[fid].type != self._pin.FrameType.BODY and m.frames[fid].parentFrame != fid:
            fid = m.frames[fid].parentFrame
            hosts.add(fid)
        return frozenset(i for i, o in enumerate(self.collision_model.geometryObjects) if o.parentFrame in hosts)

    def _compute_hand_geoms(self) -> list[frozenset[int]]:
        """Per limb, the geometry exempt from terrain collision anywhere while in contact (point contacts:
        the tip on the hand's link)."""
        return [self._hand_link_geoms(lb) if lb.contact.type == "point" else frozenset() for lb in self.limbs]

    def _compute_near_geoms(self, src: str) -> list[tuple[int, ...]]:
        """Per limb, the geometry that may touch the terrain within ``contact.near`` of the hold.

        Default: none for a point contact; for a sphere, the hand's link and the links moved only by the
        limb's last joint.  A spec's ``contact.links`` replaces the default.
        """
        m, objs = self.model, list(self.collision_model.geometryObjects)
        links = {f.name: i for i, f in enumerate(m.frames) if f.type == self._pin.FrameType.BODY}
        out = []
        for k, lb in enumerate(self.limbs):
            c = lb.contact
            if c.links is not None:
                for name in c.links:
                    if name not in links:
                        raise RobotModelError(src, f"limbs[{k}].contact.links", f"unknown link {name!r}")
                hosts = {links[n] for n in c.links}
                geoms = {i for i, o in enumerate(objs) if o.parentFrame in hosts}
            elif c.type == "point":
                geoms = set()
            else:
                last = lb.joint_ids[-1] if lb.joint_ids else m.frames[lb.frame_id].parentJoint
                geoms = set(self._hand_link_geoms(lb)) | {i for i, o in enumerate(objs) if o.parentJoint == last}
            out.append(tuple(sorted(geoms - self._hand_geoms[k])))
        return out

    def _ignore_pairs(self, raw: Any, src: str) -> set[frozenset[str]]:
        links = {f.name for f in self.model.frames if f.type == self._pin.FrameType.BODY}
        out = set()
        for i, pair in enumerate(raw):
            if not isinstance(pair, (list, tuple)) or len(pair) != 2:
                raise RobotModelError(src, f"ignore_collision_pairs[{i}]", "expected a pair [link, link]")
            for name in pair:
                if name not in links:
                    raise RobotModelError(src, f"ignore_collision_pairs[{i}]", f"unknown link {name!r}")
            out.add(frozenset(pair))
        return out
