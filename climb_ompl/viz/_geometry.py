"""Shapes for the meshcat scene: colours, rigid transforms, Pinocchio/Coal geometry to meshcat objects.

Everything here is pure construction (no visualizer): functions return meshcat geometry/material objects
and the 4x4 transforms that place them.  Three.js conventions that matter: a ``CylinderGeometry`` has its
axis along local ``y`` and is centred on the origin; Coal cylinders, capsules and cones have their axis
along local ``z``.
"""

from __future__ import annotations

import math
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import meshcat.geometry as mg
import numpy as np

# Rotation taking three.js's cylinder axis (local y) onto Coal's (local z): a quarter turn about x.
Y_TO_Z = np.array([[1.0, 0, 0, 0], [0, 0, -1.0, 0], [0, 1.0, 0, 0], [0, 0, 0, 1.0]])

# Pinocchio's default mesh colour (URDF visuals without a material).
_PIN_DEFAULT_RGBA = (0.9, 0.9, 0.9, 1.0)

PALETTE: dict[str, int] = {
    "robot": 0x3A6EA5,  # steel blue: robot bodies without a URDF colour
    "wall": 0xD9CBB0,  # plywood
    "obstacle": 0x8C8C8C,
    "hold_friction": 0x6A4C93,  # violet: apart from the robot's colours
    "hold_grasp": 0x2B7DE8,
    "hold_adhesion": 0x3DAA5A,
    "cone": 0xF2C14E,
    "active": 0xE8322B,  # holds of the current stance
    "com": 0x111111,
    "gravity": 0x6A1B9A,
    "support": 0x2E9E4F,
    "feasible": 0xE8892B,  # orange: the torque-limited feasible region inside the support region
    "force": 0xC2185B,
    "failed": 0x111111,  # a hold that failed (removed, moved away from, or made slippery): re-planned around
    "departure": 0xF2E600,  # yellow: where a re-planned climb leaves the old plan
}


def color_int(color: Any, default: int = 0x888888) -> int:
    """A colour as a 0xRRGGBB integer.

    Accepts an int, ``"#rrggbb"``, or an RGB(A) sequence of floats in [0, 1].
    """
    if color is None:
        return default
    if isinstance(color, (int, np.integer)) and not isinstance(color, bool):
        return int(color) & 0xFFFFFF
    if isinstance(color, str):
        s = color.lstrip("#")
        return int(s[:6], 16)
    c = np.clip(np.asarray(color, dtype=float).ravel()[:3], 0.0, 1.0)
    r, g, b = (int(round(255 * x)) for x in c)
    return (r << 16) | (g << 8) | b


def material(color: Any, opacity: float = 1.0, *, default: int = 0x888888) -> mg.MeshLambertMaterial:
    """A Lambert (matte) material of ``color`` and ``opacity`` in [0, 1]."""
    return mg.MeshLambertMaterial(color=color_int(color, default), opacity=float(opacity))


# ---- rigid transforms ---------------------------------------------------------------------------
def translation(p: Any) -> np.ndarray:
    """4x4 homogeneous translation by ``p`` (metres)."""
    T = np.eye(4)
    T[:3, 3] = np.asarray(p, dtype=float).ravel()[:3]
    return T


def rotation_y_to(direction: Any) -> np.ndarray:
    """3x3 rotation taking local ``y`` onto the unit vector along ``direction`` (shortest arc)."""
    d = np.asarray(direction, dtype=float)
    n = float(np.linalg.norm(d))
    if n < 1e-12:
        return np.eye(3)
    d = d / n
    y = np.array([0.0, 1.0, 0.0])
    c = float(y @ d)
    axis = np.cross(y, d)
    s = float(np.linalg.norm(axis))
    if s < 1e-14:  # (anti-)parallel: the error of not rotating is below 1e-14
        return np.eye(3) if c > 0 else np.diag([1.0, -1.0, -1.0])  # half turn about x
    k = axis / s
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    angle = math.atan2(s, c)
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * (K @ K)


def pose(R: np.ndarray, p: Any) -> np.ndarray:
    """4x4 homogeneous transform from a rotation and a translation."""
    T = np.eye(4)
    T[:3, :3] = R
    T[:3, 3] = np.asarray(p, dtype=float).ravel()[:3]
    return T


#: Keyframes of a moving node are kept only where three.js's interpolation between the kept ones (linear in
#: position, spherical in orientation) would miss a dropped pose by more than these, metres and radians
#: (:func:`pose_keys`; what this saves in a page's size: docs/climb.md, "Playback").
KEY_POSITION_TOLERANCE = 2e-4
KEY_ANGLE_TOLERANCE = 1e-3


def _quaternions(mats: np.ndarray) -> np.ndarray:
    """Unit quaternions ``(n, 4)`` (x, y, z, w) of the rotations of ``mats`` ``(n, 4, 4)``, each on the same
    side as the one before it (three.js interpolates along the shorter arc either way)."""
    from scipy.spatial.transform import Rotation

    q = Rotation.from_matrix(mats[:, :3, :3]).as_quat()
    flip = np.cumprod(np.where(np.einsum("ij,ij->i", q[1:], q[:-1]) < 0, -1.0, 1.0))
    q[1:] *= flip[:, None]
    return q


def _slerp(q0: np.ndarray, q1: np.ndarray, t: np.ndarray) -> np.ndarray:
    d = float(np.clip(q0 @ q1, -1.0, 1.0))
    if d < 0:
        q1, d = -q1, -d
    om = math.acos(d)
    if om < 1e-9:
        return np.tile(q0, (len(t), 1))
    return (np.sin((1 - t) * om)[:, None] * q0 + np.sin(t * om)[:, None] * q1) / math.sin(om)


def pose_keys(times: Any, mats: Any, position_tol: float = KEY_POSITION_TOLERANCE,
              angle_tol: float = KEY_ANGLE_TOLERANCE) -> list[int]:
    """Indices of the poses to key so that interpolating between them reproduces every pose within tolerance.

    Three.js interpolates a node's keyed position linearly in time and its orientation by spherical linear
    interpolation; a pose that interpolation reproduces within ``position_tol`` (metres) and ``angle_tol``
    (radians) need not be keyed.  From each kept pose the next is the farthest one whose interpolation
    reproduces every pose in between (found by doubling, then bisection; every segment kept is checked whole).
    The first and last poses are always kept.

    Args:
        times: increasing times ``(n,)``.
        mats: 4x4 poses ``(n, 4, 4)``.

    Returns:
        Increasing indices into ``times``, starting at 0 and ending at ``n - 1``.
    """
    t = np.asarray(times, dtype=float).ravel()
    m = np.asarray(mats, dtype=float).reshape(-1, 4, 4)
    n = len(t)
    if n <= 2:
        return list(range(n))
    p, q = m[:, :3, 3], _quaternions(m)

    def ok(i: int, j: int) -> bool:
        if j <= i + 1:
            return True
        span = t[j] - t[i]
        if span <= 0:
            return False
        u = (t[i + 1:j] - t[i]) / span
        if np.max(np.linalg.norm(p[i] + u[:, None] * (p[j] - p[i]) - p[i + 1:j], axis=1)) > position_tol:
            return False
        dots = np.abs(np.einsum("ij,ij->i", _slerp(q[i], q[j], u), q[i + 1:j]))
        return bool(2.0 * math.acos(min(1.0, float(np.min(dots)))) <= angle_tol)

    keep, i = [0], 0
    while i < n - 1:
        good, probe = i + 1, i + 2
        while probe < n and ok(i, probe):
            good, probe = probe, i + 2 * (probe - i)
        probe = min(probe, n - 1)
        if probe > good and ok(i, probe):
            good = probe
        else:
            while probe - good > 1:  # good passes, probe fails
                mid = (good + probe) // 2
                good, probe = (mid, probe) if ok(i, mid) else (good, mid)
        keep.append(good)
        i = good
    return keep


def plane_frame(normal: Any) -> np.ndarray:
    """3x3 rotation whose columns are (in-plane x, in-plane y, normal) for a plane with ``normal``: the axes of a
    plane surface's ``size`` (:func:`climb_ompl.model.terrain.plane_axes`)."""
    from climb_ompl.model.terrain import plane_axes

    return plane_axes(normal)


# ---- primitive builders -------------------------------------------------------------------------
@dataclass
class Part:
    """One meshcat object with its placement relative to the node that owns it.

    Attributes:
        name: child node name (unique within the owner).
        geometry: meshcat geometry.
        material: meshcat material.
        transform: 4x4 placement in the owner's frame.
        kind: ``"mesh"``, ``"line"`` or ``"points"`` (which meshcat object type to build).
    """

    name: str
    geometry: Any
    material: Any
    transform: np.ndarray
    kind: str = "mesh"

    def object(self) -> Any:
        """The meshcat ``Object`` (mesh, line or points) for ``set_object``."""
        if self.kind == "line":
            return mg.Line(self.geometry, self.material)
        if self.kind == "points":
            return mg.Points(self.geometry, self.material)
        return mg.Mesh(self.geometry, self.material)


def cone_parts(apex: Any, axis: Any, half_angle: float, height: float, color: Any, opacity: float,
               name: str = "cone") -> list[Part]:
    """A solid cone with its apex at ``apex`` opening along ``axis`` with ``half_angle`` (radians)."""
    r = height * math.tan(min(half_angle, math.radians(85.0)))
    geom = mg.Cylinder(height, radiusTop=max(r, 1e-4), radiusBottom=0.0)
    R = rotation_y_to(axis)
    centre = np.asarray(apex, dtype=float) + R[:, 1] * height / 2
    return [Part(name, geom, material(color, opacity), pose(R, centre))]


def segment_parts(p0: Any, p1: Any, radius: float, color: Any, opacity: float = 1.0,
                  name: str = "segment") -> list[Part]:
    """A cylinder of ``radius`` from ``p0`` to ``p1`` (empty if they coincide)."""
    a, b = np.asarray(p0, dtype=float), np.asarray(p1, dtype=float)
    length = float(np.linalg.norm(b - a))
    if length < 1e-9:
        return []
    geom = mg.Cylinder(length, radius)
    return [Part(name, geom, material(color, opacity), pose(rotation_y_to(b - a), (a + b) / 2))]


def arrow_parts(color: Any, *, shaft_radius: float = 0.006, head_radius: float = 0.016,
                head_fraction: float = 0.25) -> list[Part]:
    """A unit arrow from the origin along local ``+y`` (scale the owner's y axis to set its length)."""
    shaft = 1.0 - head_fraction
    mat = material(color)
    return [
        Part("shaft", mg.Cylinder(shaft, shaft_radius), mat, translation([0, shaft / 2, 0])),
        Part("head", mg.Cylinder(head_fraction, radiusTop=0.0, radiusBottom=head_radius), mat,
             translation([0, shaft + head_fraction / 2, 0])),
    ]


def polyline_part(points: np.ndarray, color: Any, name: str = "line", closed: bool = False) -> Part:
    """A 1-pixel polyline through ``points`` ``(N, 3)``."""
    pts = np.asarray(points, dtype=np.float32).reshape(-1, 3)
    if closed and len(pts) > 2:
        pts = np.vstack([pts, pts[:1]])
    geom = mg.PointsGeometry(pts.T)
    return Part(name, geom, mg.LineBasicMaterial(color=color_int(color)), np.eye(4), kind="line")


def polygon_parts(points: np.ndarray, color: Any, opacity: float = 0.45, name: str = "polygon") -> list[Part]:
    """A filled convex polygon (triangle fan over ``points`` ``(k, 3)``, k >= 3) with its outline."""
    pts = np.asarray(points, dtype=float).reshape(-1, 3)
    k = len(pts)
    faces = np.array([[0, i, i + 1] for i in range(1, k - 1)], dtype=np.uint32)
    fill = Part(f"{name}_fill", mg.TriangularMeshGeometry(pts, faces), material(color, opacity), np.eye(4))
    return [fill, polyline_part(pts, color, name=f"{name}_edge", closed=True)]


def tube_part(points: np.ndarray, radius: float, color: Any, opacity: float = 1.0, name: str = "tube",
              sides: int = 8) -> Part:
    """A tube of ``radius`` along the polyline ``points`` ``(N, 3)`` as one triangle mesh (no end caps)."""
    P = np.asarray(points, dtype=float).reshape(-1, 3)
    keep = np.r_[True, np.linalg.norm(np.diff(P, axis=0), axis=1) > 1e-9]
    P = P[keep]
    if len(P) < 2:
        P = np.vstack([P[:1], P[:1] + [0.0, 0.0, 1e-4]])
    T = np.gradient(P, axis=0)
    T /= np.maximum(np.linalg.norm(T, axis=1, keepdims=True), 1e-12)
    ref = np.array([0.0, 0.0, 1.0]) if abs(T[0, 2]) < 0.9 else np.array([1.0, 0.0, 0.0])
    n = ref - (ref @ T[0]) * T[0]
    n /= np.linalg.norm(n)
    ang = np.linspace(0.0, 2 * math.pi, sides, endpoint=False)
    verts = []
    for i in range(len(P)):  # parallel transport of the ring's normal along the curve
        n = n - (n @ T[i]) * T[i]
        n /= max(np.linalg.norm(n), 1e-12)
        b = np.cross(T[i], n)
        verts.append(P[i] + radius * (np.outer(np.cos(ang), n) + np.outer(np.sin(ang), b)))
    V = np.vstack(verts)
    faces = []
    for i in range(len(P) - 1):
        for k in range(sides):
            a, b2 = i * sides + k, i * sides + (k + 1) % sides
            c, d = a + sides, b2 + sides
            faces += [[a, b2, d], [a, d, c]]
    return Part(name, mg.TriangularMeshGeometry(V, np.asarray(faces, dtype=np.uint32)), material(color, opacity),
                np.eye(4))


def label_part(text: str, height: float, frame: np.ndarray, *, color: Any = 0x111111, name: str = "label") -> Part:
    """A line of text, ``height`` metres tall, on a card facing along ``frame``'s z axis (its x along the text,
    its y up the text), centred at ``frame``'s origin.  The viewer draws no text of its own: the text is
    rendered by Matplotlib into a PNG with a transparent background that textures the card."""
    import io

    from matplotlib.figure import Figure  # (a bare Figure: pyplot's backend and state are left alone)

    dpi, px = 100, 48  # the text 48 px tall in the texture
    fig = Figure(figsize=(max(1, len(text)) * 0.62 * px / dpi, 1.4 * px / dpi), dpi=dpi)
    fig.patch.set_alpha(0.0)
    fig.text(0.5, 0.5, text, ha="center", va="center", fontsize=px * 72 / dpi * 0.75,
             color=f"#{color_int(color):06x}", fontweight="bold")
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=dpi, transparent=True)
    w_px, h_px = fig.get_size_inches() * dpi
    tex = mg.ImageTexture(image=mg.PngImage(buf.getvalue()))
    mat = mg.MeshBasicMaterial(map=tex, transparent=True, color=0xFFFFFF, side=0)  # front faces: unmirrored
    card_h = height * 1.4
    card = mg.Box([card_h * float(w_px / h_px), card_h, 1e-4])
    return Part(name, card, mat, np.asarray(frame, dtype=float))


def points_part(points: np.ndarray, color: Any, size: float, name: str = "points") -> Part:
    """A point cloud of ``points`` ``(N, 3)``, each ``size`` metres across."""
    pts = np.asarray(points, dtype=np.float32).reshape(-1, 3)
    rgb = np.array([(color_int(color) >> s & 0xFF) / 255.0 for s in (16, 8, 0)], dtype=np.float32)
    cols = np.tile(rgb, (len(pts), 1))
    return Part(name, mg.PointsGeometry(pts.T, cols.T), mg.PointsMaterial(size=size), np.eye(4), kind="points")


# ---- Pinocchio / Coal geometry -------------------------------------------------------------------
class UnsupportedGeometry(Exception):
    """A Coal geometry type the viewer cannot draw (a plane or half-space); it is skipped."""


def geometry_parts(gobj: Any, default_color: int = PALETTE["robot"]) -> list[Part]:
    """meshcat parts for a Pinocchio ``GeometryObject`` (placed in the geometry object's own frame).

    Boxes, spheres, ellipsoids, cylinders, cones and capsules map to three.js primitives; meshes are read
    from ``meshPath`` (STL, OBJ, DAE) with ``meshScale`` when the file exists, else triangulated from the
    Coal BVH or convex model.

    Raises:
        UnsupportedGeometry: planes and half-spaces (infinite: nothing sensible to draw).
    """
    import coal

    geo = gobj.geometry
    rgba = tuple(float(x) for x in np.asarray(gobj.meshColor).ravel()[:4])
    if len(rgba) == 4 and np.allclose(rgba, _PIN_DEFAULT_RGBA):
        mat = material(default_color)
    else:
        mat = material(rgba[:3], rgba[3] if len(rgba) == 4 else 1.0)
    eye = np.eye(4)
    if isinstance(geo, coal.Box):
        return [Part("shape", mg.Box(list(2 * np.asarray(geo.halfSide, dtype=float))), mat, eye)]
    if isinstance(geo, coal.Sphere):
        return [Part("shape", mg.Sphere(float(geo.radius)), mat, eye)]
    if isinstance(geo, coal.Ellipsoid):
        return [Part("shape", mg.Ellipsoid(list(np.asarray(geo.radii, dtype=float))), mat, eye)]
    if isinstance(geo, coal.Capsule):
        r, h = float(geo.radius), float(geo.halfLength)
        return [
            Part("body", mg.Cylinder(2 * h, r), mat, Y_TO_Z),
            Part("cap0", mg.Sphere(r), mat, translation([0, 0, -h])),
            Part("cap1", mg.Sphere(r), mat, translation([0, 0, h])),
        ]
    if isinstance(geo, coal.Cone):
        cone = mg.Cylinder(2 * float(geo.halfLength), radiusTop=0.0, radiusBottom=float(geo.radius))
        return [Part("shape", cone, mat, Y_TO_Z)]
    if isinstance(geo, coal.Cylinder):
        return [Part("shape", mg.Cylinder(2 * float(geo.halfLength), float(geo.radius)), mat, Y_TO_Z)]
    if isinstance(geo, (coal.Plane, coal.Halfspace)):
        raise UnsupportedGeometry(type(geo).__name__)
    mesh = _mesh_from_file(gobj) if int(getattr(geo, "num_tris", 0) or 0) <= MESH_TRIANGLES else None
    if mesh is not None:
        scale = np.diag([*np.asarray(gobj.meshScale, dtype=float).ravel()[:3], 1.0])
        return [Part("shape", mesh, mat, scale)]
    verts, faces = _mesh_arrays(geo)
    if verts is None:
        raise UnsupportedGeometry(type(geo).__name__)
    verts, faces = simplify_mesh(verts, faces, MESH_TRIANGLES)
    return [Part("shape", mg.TriangularMeshGeometry(verts, faces), mat, eye)]


#: Triangles of one mesh in the scene, at most.  A mesh file with more is drawn from the Coal model Pinocchio
#: loaded (its vertices already scaled), simplified by :func:`simplify_mesh`: Go1's trunk (example-robot-data)
#: has 351 394 triangles in a 29 MB DAE file, and its playback page, every mesh file embedded once per link,
#: weighed 93 MB.
MESH_TRIANGLES = 8000
#: Bytes of a mesh file embedded in the scene as it is, at most; a larger one is drawn from the Coal model too.
#: A DAE file's text costs about 140 bytes a triangle, the Coal model's arrays about 20: Go2's hips (7252
#: triangles, 1 MB each) made its page 14 MB.
MESH_FILE_BYTES = 200_000


def simplify_mesh(verts: np.ndarray, faces: np.ndarray, max_triangles: int) -> tuple[np.ndarray, np.ndarray]:
    """A triangle mesh with at most ``max_triangles`` triangles, by vertex clustering (Rossignac & Borrel 1993).

    The vertices are binned in a grid of cubes; each occupied cube becomes one vertex, the mean of its
    vertices; triangles whose corners fall in fewer than three cubes vanish, as do repeats of a triangle.
    The cube's side starts from the mesh's area per triangle allowed and is scaled until the result has between
    60 % and 100 % of ``max_triangles`` (12 tries, the finest result within the limit kept; then coarser until
    one is within it).  The triangles keep their orientation.  A mesh within the limit is returned as it is.

    Args:
        verts: vertices ``(n, 3)``.
        faces: triangles ``(m, 3)``, indices into ``verts``.
        max_triangles: the limit (>= 1).

    Returns:
        ``(vertices, faces)``: the vertices used, ``float`` ``(k, 3)``, and the triangles, ``int`` ``(l, 3)``.
    """
    v = np.asarray(verts, dtype=float).reshape(-1, 3)
    f = np.asarray(faces, dtype=np.int64).reshape(-1, 3)
    if len(f) <= max_triangles:
        return v, f
    lo = v.min(axis=0)
    a, b, c = v[f[:, 0]], v[f[:, 1]], v[f[:, 2]]
    area = 0.5 * float(np.linalg.norm(np.cross(b - a, c - a), axis=1).sum())
    ext = float(np.max(np.ptp(v, axis=0))) or 1.0
    side = max(math.sqrt(2.0 * area / max_triangles), 1e-6 * ext)
    best: tuple[np.ndarray, np.ndarray] | None = None
    fine, coarse = 0.0, math.inf  # sides known to give too many triangles, and few enough
    tries = 0
    while True:
        tries += 1
        cell = np.floor((v - lo) / side).astype(np.int64)
        _, inv = np.unique(cell, axis=0, return_inverse=True)
        inv = inv.ravel()
        count = np.bincount(inv).astype(float)
        merged = np.stack([np.bincount(inv, weights=v[:, k]) for k in range(3)], axis=1) / count[:, None]
        nf = inv[f]
        nf = nf[(nf[:, 0] != nf[:, 1]) & (nf[:, 1] != nf[:, 2]) & (nf[:, 0] != nf[:, 2])]
        _, first = np.unique(np.sort(nf, axis=1), axis=0, return_index=True)
        nf = nf[np.sort(first)]
        if len(nf) <= max_triangles:
            coarse = side
            if best is None or len(nf) > len(best[1]):
                used, remap = np.unique(nf, return_inverse=True)
                best = merged[used], remap.reshape(-1, 3)
        else:
            fine = side
        if best is not None and (len(best[1]) >= 0.6 * max_triangles or tries >= 12):
            return best
        if tries >= 12:  # still too many: coarser until within the limit (one cube holds no triangle)
            side *= 2.0
            continue
        # triangles scale about as the inverse square of the side; bisect once both bounds are known
        guess = side * math.sqrt(max(len(nf), 1) / (0.8 * max_triangles))
        side = 0.5 * (fine + coarse) if fine > 0 and coarse < math.inf else guess


def _mesh_from_file(gobj: Any) -> Any | None:
    path = Path(str(getattr(gobj, "meshPath", "") or ""))
    loaders = {".stl": mg.StlMeshGeometry, ".obj": mg.ObjMeshGeometry, ".dae": mg.DaeMeshGeometry}
    loader = loaders.get(path.suffix.lower())
    if loader is None or not path.is_file() or path.stat().st_size > MESH_FILE_BYTES:
        return None
    mesh = loader.from_file(str(path))
    if path.suffix.lower() == ".dae" and isinstance(mesh.contents, str):
        mesh.contents = without_images(mesh.contents)
    return mesh


def without_images(dae: str) -> str:
    """A COLLADA document without its image library: the page is self-contained, and the viewer would look for
    each texture file beside the page (ANYmal's meshes name 20 JPEG files; each request failed, with an error in
    the console).  The meshes keep their materials' colours."""
    return re.sub(r"<library_images>.*?</library_images>|<library_images\s*/>", "", dae, flags=re.S)


def _mesh_arrays(geo: Any) -> tuple[np.ndarray | None, np.ndarray | None]:
    """Vertices ``(n, 3)`` and triangles ``(m, 3)`` of a Coal BVH model or convex polytope."""
    if hasattr(geo, "tri_indices") and hasattr(geo, "vertices"):
        verts = np.asarray(geo.vertices(), dtype=float)
        tris = geo.tri_indices
        faces = np.array([[tris(i)[j] for j in range(3)] for i in range(geo.num_tris)], dtype=np.uint32)
        return verts, faces.reshape(-1, 3)
    if hasattr(geo, "points") and hasattr(geo, "polygons"):
        verts = np.asarray(geo.points(), dtype=float)
        faces = []
        for i in range(geo.num_polygons):
            poly = geo.polygons(i)
            idx = [poly[j] for j in range(poly.size())]
            faces.extend([idx[0], idx[k], idx[k + 1]] for k in range(1, len(idx) - 1))
        return verts, np.asarray(faces, dtype=np.uint32).reshape(-1, 3)
    return None, None
