"""Independent verification of a TreeBot plan (``kind: "treebot"``), Lam et al. (TreeBot).

:func:`verify_tree` re-checks the plan file's contents without the planner's code: the tree is rebuilt from
the embedded tree (its content hash checked), the bark is a triangle mesh joining consecutive rings of
surface points (Fig. 5), and the continuum body of every frame is re-derived from the gripper that holds
by the arc of Eq. 1-3 written without a gripper frame (the arc leaving point ``o`` along ``d`` that ends at
``p`` lies in the plane of ``d`` and ``p - o``: half the bending angle is the angle between ``d`` and the
chord, ``kappa = 2 sin(theta/2) / |p - o|``, ``S = theta / kappa``).  Checks:

* ``integrity``: the tree parses and matches its ``tree_hash``; the plan's own bookkeeping agrees;
* ``path``: the gripping-point path visits the rings from the trunk's first ring to the target branch's
  last one in order (the branch sequence found by walking the parents, section III), each point is the tree's
  point it names, with the tree's normal there, none is unreachable (``O = -inf``, Eq. 4), consecutive points
  are at most ``max_reach`` apart; the stated ``cost`` is the path's (Eq. 4-7: its length minus ``a0`` times the
  sum of ``n = z - 1`` over the points after the first); the front-gripper targets (``motion.targets``, drawn by
  playback) are path indices from the first point to the last, and each extension ends with the front gripper
  on its target (section V.A.1);
* ``goal``: the path ends on the target branch's last ring (on the target point if one was asked) and the
  front gripper ends there;
* ``grip_on_bark``: the gripper that holds in each frame (the rear one during an extension, the front one
  during a contraction, section V.B) is on the bark within :data:`GRIP_TOLERANCE`, not on an unreachable
  point;
* ``grip_held``: a holding gripper neither moves nor turns, and it holds where the previous phase put it (the
  rear gripper also pointing as it landed);
* ``body_shape``: the body samples lie on the arc of Eq. 1-3 from the holding gripper, along its direction,
  to the other gripper; the stated ``S``, ``kappa`` are that arc's, the stated ``phi`` its bending plane in the
  holding gripper's frame (``z`` along the gripper, ``x`` towards the surface normal at the target the step's
  phase started from, Fig. 3 and 10), and the moving gripper points along the arc's tangent at its end;
* ``body_length``: ``s_min <= S <= s_max``; ``bending``: ``kappa S <= max_bend``;
* ``collision``: no body sample inside a branch the path does not climb (the paper's obstacles: "the
  non-passing branches should be considered as obstacles", section III).

Each violation names the motion step and the frame index (``$.motion.frames[i]``); one about a stored field names
its JSON path.  ``docs/plan-file.md`` lists every stored field, who reads it and how it is checked.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from climb_ompl.verification.report import Recorder, VerifyReport

#: Largest distance of a holding gripper from the bark, metres.
GRIP_TOLERANCE = 2e-3
#: Largest distance of a body sample from the re-derived arc, metres (samples are stored to 1e-9 m).
SHAPE_TOLERANCE = 1e-6
#: Tolerance on positions that must be equal (path points, held grippers), metres.
POSITION_TOLERANCE = 1e-9
#: Tolerance on the body's length and bending limits (m, rad).
LIMIT_TOLERANCE = 1e-9
#: Tolerance on a moving gripper's stored direction against the arc's end tangent (unit vectors).
DIRECTION_TOLERANCE = 1e-6
#: Relative tolerance on the stated path cost (Eq. 4-7) against its recomputation from the path.
COST_RTOL = 1e-9

CHECKS: tuple[str, ...] = ("integrity", "path", "goal", "grip_on_bark", "grip_held", "body_shape", "body_length",
                           "bending", "collision")


# ---- the bark as triangles ---------------------------------------------------------------------------
class _Mesh:
    """The bark of some branches: triangles between consecutive rings, with the rings' unit normals.

    ``end`` marks the vertices of each branch's first and last ring (its open ends): a point whose nearest
    bark point lies on an open end is beyond that end, outside the branch.
    """

    def __init__(self, branches: list[dict[str, Any]]):
        tri, nrm, end, vid = [], [], [], []
        for b in branches:
            rings = b["rings"]
            for k in range(len(rings) - 1):
                p0, p1 = np.asarray(rings[k]["points"], float), np.asarray(rings[k + 1]["points"], float)
                n0, n1 = np.asarray(rings[k]["normals"], float), np.asarray(rings[k + 1]["normals"], float)
                n0 = n0 / np.linalg.norm(n0, axis=1, keepdims=True)
                n1 = n1 / np.linalg.norm(n1, axis=1, keepdims=True)
                e0, e1 = k == 0, k + 1 == len(rings) - 1
                m = len(p0)
                for j in range(m):
                    j2 = (j + 1) % m
                    tri += [[p0[j], p0[j2], p1[j]], [p0[j2], p1[j2], p1[j]]]
                    nrm += [[n0[j], n0[j2], n1[j]], [n0[j2], n1[j2], n1[j]]]
                    end += [[e0, e0, e1], [e0, e1, e1]]
                    obs0, obs1 = set(rings[k].get("obstacles") or []), set(rings[k + 1].get("obstacles") or [])
                    vid += [[j in obs0, j2 in obs0, j in obs1], [j2 in obs0, j2 in obs1, j in obs1]]
        self.tri = np.array(tri).reshape(-1, 3, 3)
        self.nrm = np.array(nrm).reshape(-1, 3, 3)
        self.end = np.array(end, dtype=bool).reshape(-1, 3)
        self.obstacle = np.array(vid, dtype=bool).reshape(-1, 3)

    def nearest(self, P: np.ndarray, chunk: int = 128) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """For each point: distance to the bark, signed distance (negative inside, by the interpolated ring
        normal; positive beyond an open end), whether the nearest vertex of the nearest triangle is unreachable,
        and the nearest bark point."""
        out_d, out_s, out_o, out_c = [], [], [], []
        for i in range(0, len(P), chunk):
            d, s, o, c = self._nearest(P[i:i + chunk])
            out_d.append(d), out_s.append(s), out_o.append(o), out_c.append(c)
        return np.concatenate(out_d), np.concatenate(out_s), np.concatenate(out_o), np.concatenate(out_c)

    def _nearest(self, P: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        bary, C = _closest_on_triangles(P, self.tri)
        D = np.linalg.norm(P[:, None, :] - C, axis=2)
        k = np.argmin(D, axis=1)
        rows = np.arange(len(P))
        w, c, d = bary[rows, k], C[rows, k], D[rows, k]
        n = np.einsum("pi,pij->pj", w, self.nrm[k])
        inside = np.einsum("pj,pj->p", P - c, n) < 0
        on_end = np.all(self.end[k] | (w <= 1e-12), axis=1)
        sign = np.where(inside & ~on_end, -1.0, 1.0)
        obstacle = self.obstacle[k][rows, np.argmax(w, axis=1)]
        return d, sign * d, obstacle, c


def _closest_on_triangles(P: np.ndarray, T: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Barycentric weights ``(p, t, 3)`` and points ``(p, t, 3)`` of the point of each triangle nearest to each
    point (the Voronoi-region case analysis of a triangle, vertices, edges, face)."""
    a, b, c = T[None, :, 0], T[None, :, 1], T[None, :, 2]
    p = P[:, None, :]
    ab, ac = b - a, c - a

    def dot(x: np.ndarray, y: np.ndarray) -> np.ndarray:
        return np.einsum("ptk,ptk->pt", x, y)

    d1, d2 = dot(ab, p - a), dot(ac, p - a)
    d3, d4 = dot(ab, p - b), dot(ac, p - b)
    d5, d6 = dot(ab, p - c), dot(ac, p - c)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        den = va + vb + vc
        v, w = vb / den, vc / den
        W = np.stack([1 - v - w, v, w], axis=-1)
        t_ab = d1 / (d1 - d3)
        t_ac = d2 / (d2 - d6)
        t_bc = (d4 - d3) / ((d4 - d3) + (d5 - d6))
    z = np.zeros_like(d1)
    cases = [  # later cases win: edges, then vertices (the face is the default)
        ((vc <= 0) & (d1 >= 0) & (d3 <= 0), np.stack([1 - t_ab, t_ab, z], -1)),
        ((vb <= 0) & (d2 >= 0) & (d6 <= 0), np.stack([1 - t_ac, z, t_ac], -1)),
        ((va <= 0) & (d4 - d3 >= 0) & (d5 - d6 >= 0), np.stack([z, 1 - t_bc, t_bc], -1)),
        ((d1 <= 0) & (d2 <= 0), np.stack([z + 1, z, z], -1)),
        ((d3 >= 0) & (d4 <= d3), np.stack([z, z + 1, z], -1)),
        ((d6 >= 0) & (d5 <= d6), np.stack([z, z, z + 1], -1)),
    ]
    for mask, val in cases:
        W[mask] = val[mask]
    C = W[..., :1] * a + W[..., 1:2] * b + W[..., 2:] * c
    return W, C


# ---- the body arc of Eq. 1-3, without a gripper frame ---------------------------------------------------
def arc(origin: np.ndarray, direction: np.ndarray, target: np.ndarray) -> tuple[float, float, np.ndarray]:
    """``(S, kappa, e)`` of the arc leaving ``origin`` along the unit ``direction`` and ending at ``target``
    (Lam et al. (TreeBot) Eq. 1-3): ``e`` is the unit bending direction (zero for a straight body), and the
    arc is ``origin + sin(kappa s)/kappa d + (1 - cos(kappa s))/kappa e``.  ``S`` is ``inf`` when the target
    lies behind the origin on the straight line (no arc leaves along ``d`` to it)."""
    v = np.asarray(target, float) - origin
    chord = float(np.linalg.norm(v))
    along = float(v @ direction)
    side = v - along * direction
    half = math.atan2(float(np.linalg.norm(side)), along)  # theta / 2, the angle between d and the chord
    if chord == 0.0:
        return 0.0, 0.0, np.zeros(3)
    if math.sin(half) < 1e-12:
        return (chord, 0.0, np.zeros(3)) if along > 0 else (math.inf, 0.0, np.zeros(3))
    kappa = 2.0 * math.sin(half) / chord
    return 2.0 * half / kappa, kappa, side / np.linalg.norm(side)


def arc_samples(origin: np.ndarray, direction: np.ndarray, S: float, kappa: float, e: np.ndarray,
                k: int) -> np.ndarray:
    """``k`` points of that arc, evenly spaced along its length."""
    s = np.linspace(0.0, S, k)[:, None]
    if kappa == 0.0:
        return origin + s * direction
    return origin + np.sin(kappa * s) / kappa * direction + 2.0 * np.sin(kappa * s / 2) ** 2 / kappa * e


# ---- the verifier -------------------------------------------------------------------------------------
def _branch_chain(branches: dict[str, dict[str, Any]], target: str) -> list[str]:
    chain = [target]
    while branches[chain[-1]].get("parent") is not None and len(chain) <= len(branches):
        chain.append(branches[chain[-1]]["parent"])
    return chain[::-1]


def verify_tree(plan: dict[str, Any], source: str = "<plan>", *, max_per_check: int = 50,
                **_: Any) -> VerifyReport:
    """Re-check a TreeBot plan dict (already schema-checked, every number finite); see the module docstring.

    Args:
        plan: the plan-file dict (``kind: "treebot"``).
        source: where it came from (for messages).
        max_per_check: list at most this many violations per check (the counts stay exact).

    Raises:
        PlanFileError: the embedded tree is malformed (naming its field).
    """
    from climb_ompl.errors import PlanFileError
    from climb_ompl.treebot.tree import Tree, TreeError

    rec = Recorder(max_per_check)
    data = {k: v for k, v in plan["tree"].items() if k != "tree_hash"}
    try:
        tree = Tree.from_dict(data, source=f"{source}: $.tree")
    except TreeError as exc:
        raise PlanFileError(source, f"$.tree.{exc.field}", exc.reason) from None
    if tree.content_hash() != plan["tree"]["tree_hash"]:
        rec.add("integrity", None, None, "$.tree does not match $.tree.tree_hash (tampered tree)")
    motion = plan["motion"]
    frames = motion["frames"]
    steps = 1 + max((f["step"] for f in frames), default=-1)
    if not plan["found"]:
        rec.add("goal", None, None, f"the plan says no path was found ({plan.get('reason', '')})")
        return rec.report(0)
    branches = {b["name"]: b for b in data["branches"]}
    target = plan["target"]["branch"]
    if target not in branches:
        rec.add("goal", None, None, f"target branch {target!r} is not in the tree")
        return rec.report(steps)
    chain = _branch_chain(branches, target)
    _check_path(rec, plan, tree, branches, chain)
    _check_motion(rec, plan, tree, branches, chain)
    return rec.report(steps)


def _check_path(rec: Recorder, plan: dict[str, Any], tree: Any, branches: dict[str, Any], chain: list[str]) -> None:
    rows: list[tuple[str, int]] = []
    for b, nxt in zip(chain, chain[1:] + [None], strict=True):
        last = len(branches[b]["rings"]) - 1 if nxt is None else int(branches[nxt]["attach_ring"])
        rows += [(b, r) for r in range(last + 1)]
    path = plan["path"]
    if len(path) != len(rows):
        rec.add("path", None, None, f"{len(path)} gripping points, but the rings from the trunk to "
                f"{chain[-1]!r} are {len(rows)}")
    r = tree.robot
    prev = None
    for i, (pt, (b, k)) in enumerate(zip(path, rows, strict=False)):
        if (pt["branch"], pt["ring"], pt["row"]) != (b, k, i):
            rec.add("path", None, None, f"$.path[{i}] is on ring {pt['ring']} of {pt['branch']!r} (row {pt['row']}); "
                    f"row {i} is ring {k} of {b!r}")
            continue
        ring = tree.branch(b).rings[k]
        j = pt["point"]
        if not 0 <= j < ring.n:
            rec.add("path", None, None, f"$.path[{i}].point: no point {j} on ring {k} of {b!r}")
            continue
        pos = np.asarray(pt["position"], float)
        err = float(np.linalg.norm(pos - ring.points[j]))
        if err > POSITION_TOLERANCE:
            rec.add("path", None, None, f"$.path[{i}].position is {err:.3g} m from point {j} of ring {k} of {b!r}, "
                    "which it names")
        nrm = float(np.linalg.norm(np.asarray(pt["normal"], float) - ring.normals[j]))
        if nrm > POSITION_TOLERANCE:
            rec.add("path", None, None, f"$.path[{i}].normal is {nrm:.3g} from the tree's normal at point {j} of ring "
                    f"{k} of {b!r}")
        if ring.obstacles[j]:
            rec.add("path", None, None, f"point {i} is point {j} of ring {k} of {b!r}, an unreachable point")
        if prev is not None and np.linalg.norm(pos - prev) > r.max_reach + POSITION_TOLERANCE:
            rec.add("path", None, None, f"points {i - 1} and {i} are {np.linalg.norm(pos - prev):.4f} m apart, over "
                    f"max_reach = {r.max_reach} m")
        prev = pos
    tp = plan["target"].get("point")
    if path and tp is not None and path[-1]["point"] != tp:
        rec.add("goal", None, None, f"the path ends on point {path[-1]['point']}, not on the target point {tp}")
    _check_cost(rec, plan, tree)


def _check_cost(rec: Recorder, plan: dict[str, Any], tree: Any) -> None:
    """The stated ``cost`` against the path's, Lam et al. (TreeBot) Eq. 4-7: ``-V`` of the start state is the sum of
    the distances between consecutive points minus ``a0`` times the sum of ``n = z - 1`` (``z`` the unit normal's
    component against gravity) over the points after the first."""
    path, cost = plan["path"], plan.get("cost")
    if not path or not isinstance(cost, (int, float)):
        return
    P = np.array([p["position"] for p in path], float)
    N = np.array([p["normal"] for p in path], float)
    N = N / np.linalg.norm(N, axis=1, keepdims=True)
    want = float(np.linalg.norm(np.diff(P, axis=0), axis=1).sum() - tree.a0 * (N[1:] @ tree.up - 1.0).sum())
    if abs(float(cost) - want) > COST_RTOL * max(1.0, abs(want)):
        rec.add("path", None, None, f"$.cost = {float(cost):.9g} m, but the path's (Eq. 4-7: length minus a0 times "
                f"the sum of n) is {want:.9g} m")


def _check_targets(rec: Recorder, plan: dict[str, Any], frames: list[dict[str, Any]]) -> list[int] | None:
    """The front-gripper targets (``motion.targets``, path indices; Lam et al. (TreeBot), section V.A.1): the first
    point first, increasing, the last point last, one per extension after the start, and each extension ends with
    the front gripper on its target.  Returns them when they are path indices, else ``None``."""
    path, targets = plan["path"], plan["motion"]["targets"]
    steps = 1 + max(f["step"] for f in frames)
    if not targets or targets[0] != 0 or targets[-1] != len(path) - 1 or len(targets) != steps + 1 \
            or any(b <= a for a, b in zip(targets, targets[1:], strict=False)):
        rec.add("path", None, None, f"$.motion.targets = {targets} are not {steps + 1} increasing path indices from 0 "
                f"to {len(path) - 1} (one per extension, after the start)")
        return None
    last = {}
    for i, f in enumerate(frames):
        if f["phase"] == "extend":
            last[f["step"]] = i
    for s, i in sorted(last.items()):
        goal = np.asarray(path[targets[s + 1]]["position"], float)
        off = float(np.linalg.norm(np.asarray(frames[i]["front"]["position"], float) - goal))
        if off > POSITION_TOLERANCE:
            rec.add("path", s, i, f"the extension ends with the front gripper {off:.3g} m from its target, path point "
                    f"$.motion.targets[{s + 1}] = {targets[s + 1]}")
    return list(targets)


def _check_motion(rec: Recorder, plan: dict[str, Any], tree: Any, branches: dict[str, Any], chain: list[str]) -> None:
    motion, path, r = plan["motion"], plan["path"], tree.robot
    frames = motion["frames"]
    if not frames or not path:
        rec.add("goal", None, None, "the plan has no motion")
        return
    goal = np.asarray(path[-1]["position"], float)
    end = np.asarray(frames[-1]["front"]["position"], float)
    if np.linalg.norm(end - goal) > POSITION_TOLERANCE:
        rec.add("goal", frames[-1]["step"], len(frames) - 1,
                f"the front gripper ends {np.linalg.norm(end - goal):.3g} m from the path's last point "
                f"($.motion.frames[{len(frames) - 1}].front.position)")
    if frames[-1]["phase"] != "extend":
        rec.add("goal", frames[-1]["step"], len(frames) - 1, "the motion does not end with an extension to the target")
    bark = _Mesh(list(branches.values()))
    others = [b for n, b in branches.items() if n not in chain]
    obstacles = _Mesh(others) if others else None
    targets = _check_targets(rec, plan, frames)
    holders = []
    held = None
    for i, f in enumerate(frames):
        rec.states += 1
        extend = f["phase"] == "extend"
        hold, move = ("rear", "front") if extend else ("front", "rear")
        h = np.asarray(f[hold]["position"], float)
        hd = np.asarray(f[hold]["direction"], float)
        key = (f["step"], f["phase"])
        if held is not None and held[0] == key:
            moved = float(np.linalg.norm(h - held[1]))
            if moved > POSITION_TOLERANCE:
                rec.add("grip_held", f["step"], i, f"the {hold} gripper holds but moved {moved:.3g} m "
                        f"($.motion.frames[{i}].{hold}.position)")
            turned = float(np.linalg.norm(hd - held[2]))
            if turned > POSITION_TOLERANCE:
                rec.add("grip_held", f["step"], i, f"the {hold} gripper holds but turned: $.motion.frames[{i}].{hold}"
                        f".direction is {turned:.3g} from the phase's first frame's")
        elif held is not None:
            came = np.asarray(frames[i - 1][hold]["position"], float)  # where the previous phase put it
            off = float(np.linalg.norm(h - came))
            if off > POSITION_TOLERANCE:
                rec.add("grip_held", f["step"], i, f"the {hold} gripper holds {off:.3g} m from where the previous "
                        f"phase put it ($.motion.frames[{i}].{hold}.position)")
            turned = float(np.linalg.norm(hd - np.asarray(frames[i - 1][hold]["direction"], float)))
            if hold == "rear" and turned > POSITION_TOLERANCE:  # (the front one is seated on the bark as it grips)
                rec.add("grip_held", f["step"], i, f"the rear gripper holds turned from how it landed: "
                        f"$.motion.frames[{i}].rear.direction is {turned:.3g} from the previous frame's")
        held = (key, h, hd)
        holders.append(h)
        normal = None
        if targets is not None and f["step"] + 1 < len(targets):  # the surface the holding gripper's frame leans on
            normal = np.asarray(path[targets[f["step"] if extend else f["step"] + 1]]["normal"], float)
        _check_body(rec, f, i, hold, move, r, normal)
    d, _, obst, _ = bark.nearest(np.array(holders))
    for i, (di, oi) in enumerate(zip(d, obst, strict=True)):
        f = frames[i]
        who = "rear" if f["phase"] == "extend" else "front"
        if di > GRIP_TOLERANCE:
            rec.add("grip_on_bark", f["step"], i, f"the {who} gripper holds {di * 1000:.1f} mm off the bark "
                    f"(tolerance {GRIP_TOLERANCE * 1000:g} mm; $.motion.frames[{i}].{who}.position)")
        elif oi:
            rec.add("grip_on_bark", f["step"], i, f"the {who} gripper holds at an unreachable point "
                    f"($.motion.frames[{i}].{who}.position)")
    if obstacles is not None:
        body = np.concatenate([np.asarray(f["body"], float)[1:-1] for f in frames])
        owner = np.repeat(np.arange(len(frames)), [max(len(f["body"]) - 2, 0) for f in frames])
        _, sd, _, _ = obstacles.nearest(body)
        for i in np.unique(owner[sd < 0]):
            depth = -float(sd[owner == i].min())
            rec.add("collision", frames[i]["step"], int(i), f"the body ($.motion.frames[{i}].body) is "
                    f"{depth * 1000:.1f} mm inside a branch the path does not climb")


def _check_body(rec: Recorder, f: dict[str, Any], i: int, hold: str, move: str, r: Any,
                normal: np.ndarray | None = None) -> None:
    """Frame ``i``'s body against the arc of Eq. 1-3 from the ``hold`` gripper to the ``move`` one: its samples, the
    stated ``S``, ``kappa`` and ``phi`` (in the holding gripper's frame leaning on ``normal``, when known), the moving
    gripper's direction, and the robot's length and bending limits."""
    o = np.asarray(f[hold]["position"], float)
    d = np.asarray(f[hold]["direction"], float)
    n = float(np.linalg.norm(d))
    if n < 1e-9:
        rec.add("body_shape", f["step"], i, f"the {hold} gripper has no direction")
        return
    d = d / n if hold == "rear" else -d / n  # the body leaves the holding gripper along d
    p = np.asarray(f[move]["position"], float)
    S, kappa, e = arc(o, d, p)
    body = np.asarray(f["body"], float)
    if not math.isfinite(S):
        rec.add("body_shape", f["step"], i, "no arc leaves the holding gripper along its direction to the other one")
        return
    line = arc_samples(o, d, S, kappa, e, 400)
    pts = body if hold == "rear" else body[::-1]
    dev = float(np.max(np.min(np.linalg.norm(pts[:, None, :] - line[None], axis=2), axis=1)))
    ds = S / 399.0 * (1.0 + kappa * S)  # spacing of the dense samples (chord error below it)
    if np.linalg.norm(pts[0] - o) > SHAPE_TOLERANCE or np.linalg.norm(pts[-1] - p) > SHAPE_TOLERANCE \
            or dev > SHAPE_TOLERANCE + ds:
        rec.add("body_shape", f["step"], i, f"the body samples ($.motion.frames[{i}].body) leave the arc of Eq. 1-3 "
                f"from the {hold} gripper to the {move} one ($.motion.frames[{i}].{move}.position) by "
                f"{dev * 1000:.2f} mm")
    if abs(S - f["S"]) > 1e-6 * max(1.0, S) or abs(kappa - f["kappa"]) > 1e-6 * max(1.0, kappa):
        rec.add("body_shape", f["step"], i, f"$.motion.frames[{i}].S = {f['S']:.6g} m, $.motion.frames[{i}].kappa = "
                f"{f['kappa']:.6g} 1/m; the arc has "
                f"S = {S:.6g} m, kappa = {kappa:.6g} 1/m")
    a = kappa * S
    tangent = math.cos(a) * d + math.sin(a) * e  # at the moving gripper, away from the holding one
    want = tangent if hold == "rear" else -tangent  # a gripper's direction points from the rear to the front
    err = float(np.linalg.norm(np.asarray(f[move]["direction"], float) - want))
    if err > DIRECTION_TOLERANCE:
        rec.add("body_shape", f["step"], i, f"$.motion.frames[{i}].{move}.direction is {err:.3g} from the arc's "
                f"tangent at the {move} gripper")
    if normal is not None and kappa > 0.0:
        x = normal - (normal @ d) * d
        if np.linalg.norm(x) > 1e-9:
            x = x / np.linalg.norm(x)
            bend = math.cos(f["phi"]) * x + math.sin(f["phi"]) * np.cross(d, x)
            off = 2.0 * math.sin(a / 2) ** 2 / kappa * float(np.linalg.norm(bend - e))  # where its end would be
            if off > SHAPE_TOLERANCE:
                rec.add("body_shape", f["step"], i, f"$.motion.frames[{i}].phi = {f['phi']:.6g} rad bends the body in "
                        f"another plane: its end would be {off * 1000:.3f} mm from the {move} gripper")
    if S < r.s_min - LIMIT_TOLERANCE or S > r.s_max + LIMIT_TOLERANCE:
        rec.add("body_length", f["step"], i, f"body length {S:.4f} m outside [{r.s_min}, {r.s_max}] m")
    if kappa * S > r.max_bend + LIMIT_TOLERANCE:
        rec.add("bending", f["step"], i, f"the body bends {kappa * S:.3f} rad, over max_bend = {r.max_bend} rad")


__all__ = ["verify_tree", "arc", "arc_samples", "CHECKS", "GRIP_TOLERANCE", "SHAPE_TOLERANCE"]
