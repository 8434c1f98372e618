"""TreeBot plan files (``kind: "treebot"``): the DP path and the continuum-body motion as JSON.

Top-level keys: ``schema_version`` (1, the common plan-file part), ``kind`` (``"treebot"``),
``kind_version`` (:data:`KIND_VERSION`, this content), ``climb_ompl_version``, ``seed``, ``tree`` (the
tree's YAML content plus ``tree_hash``, its :meth:`~.tree.Tree.content_hash`), ``target`` (branch and
optional point), ``path`` (gripping points: row, branch, ring, point, position, normal), ``motion`` (method,
targets, ``steps`` with the fitted arcs and ``frames`` with body samples and both gripper poses), ``cost``
and ``stats``.  ``found: false`` plans carry ``reason`` and an empty path.  The file is self-contained:
``climb-ompl verify`` re-checks it from these contents alone (:mod:`climb_ompl.verification.tree`).
"""

from __future__ import annotations

import dataclasses
import time
from typing import Any

import numpy as np

from climb_ompl.treebot.bark import Bark
from climb_ompl.treebot.dp import DPPlanner
from climb_ompl.treebot.motion import Method, Motion, plan_motion
from climb_ompl.treebot.tree import Ring, Tree

SCHEMA_VERSION = 1
#: Version of the ``treebot`` content: 2 embeds ``robot.max_bend`` and puts every grip on the bark.
KIND_VERSION = 2


#: Clearances tried between the path and the branches it does not climb, metres: when the body of a motion
#: passes through such a branch, the points of the climbed branches this close to it are made unreachable
#: and the path is planned again (the paper's path "is planned to keep away from the obstacle to a certain
#: distance", section V).
CLEARANCES: tuple[float, ...] = (0.0, 0.03, 0.06, 0.1)


def build_plan(tree: Tree, target: str, *, seed: int = 0, target_point: int | None = None,
               start_point: int | None = None, method: Method = "proposed") -> dict[str, Any]:
    """Plan the path (Lam et al. (TreeBot) Eq. 4-7) and the motion (Eq. 1-3, 8-20); the plan-file dict.

    A motion whose body would be shorter than ``robot.s_min``, longer than ``robot.s_max``, bend more than
    ``robot.max_bend`` or pass through a branch the path does not climb is no plan; a collision is retried
    with the path kept further from the other branches (:data:`CLEARANCES`).  If every try fails, ``found``
    is false and ``reason`` says why.

    Raises:
        TreeError: unknown target branch, bad point index.
    """
    from climb_ompl._version import __version__

    tree_dict = tree.to_dict()
    tree_dict["tree_hash"] = tree.content_hash()
    plan: dict[str, Any] = {
        "schema_version": SCHEMA_VERSION, "kind": "treebot", "kind_version": KIND_VERSION,
        "climb_ompl_version": __version__, "seed": seed,
        "tree": tree_dict, "target": {"branch": target, "point": target_point},
        "found": False, "reason": "", "path": [], "cost": None, "motion": None,
    }
    stats: dict[str, Any] = {"dp_time_s": 0.0, "motion_time_s": 0.0}
    why = ""
    for clearance in CLEARANCES:
        t0 = time.perf_counter()
        planning = _keep_clear(tree, target, clearance)
        res = DPPlanner.for_tree(planning, target, target_point).solve(start_point)
        stats["dp_time_s"] += time.perf_counter() - t0
        stats.update(res.stats)
        if not res.found:
            why = why or res.reason  # with a clearance, a lost path keeps the earlier reason
            break
        t1 = time.perf_counter()
        P = np.array([p.position for p in res.path])
        N = np.array([p.normal for p in res.path])
        bark = Bark(planning.branch(b) for b in dict.fromkeys(p.branch for p in res.path))
        motion = plan_motion(P, N, tree.robot, method, bark=bark.nearest)
        stats["motion_time_s"] += time.perf_counter() - t1
        S = motion.lengths()
        bend = np.array([f.posture.kappa * f.posture.S for f in motion.frames])
        stats.update({"steps": len(motion.steps), "frames": len(motion.frames), "clearance": clearance,
                      "body_length_min": float(S.min()), "body_length_max": float(S.max()),
                      "bend_max": float(bend.max())})
        fault, collision = _motion_fault(tree, motion, {p.branch for p in res.path})
        if not fault:
            plan.update(found=True, reason="", path=[p.to_dict() for p in res.path], cost=res.cost,
                        motion=motion.to_dict())
            break
        why = fault
        if not collision:
            break
    if not plan["found"]:
        plan["reason"] = why
    plan["stats"] = stats
    return plan


def _keep_clear(tree: Tree, target: str, clearance: float) -> Tree:
    """The tree with the points of the branches climbed to ``target`` within ``clearance`` of a vertex of
    another branch made unreachable (``O = -inf``, Eq. 4)."""
    if clearance <= 0.0:
        return tree
    from scipy.spatial import cKDTree

    climbed = {b for b, _ in tree.ring_sequence(target)}
    others = [r.points for b in tree.branches if b.name not in climbed for r in b.rings]
    if not others:
        return tree
    kd = cKDTree(np.concatenate(others))
    branches = []
    for b in tree.branches:
        if b.name in climbed:
            rings = tuple(Ring(r.points, r.normals, r.obstacles | (kd.query(r.points)[0] < clearance))
                          for r in b.rings)
            b = dataclasses.replace(b, rings=rings)
        branches.append(b)
    return dataclasses.replace(tree, branches=tuple(branches))


def _motion_fault(tree: Tree, motion: Motion, climbed: set[str]) -> tuple[str, bool]:
    """Why the motion is no plan (empty if it is one) and whether that is a collision: a body shorter than
    ``s_min`` or longer than ``s_max``, bent more than ``max_bend``, or passing through a branch the path does
    not climb (section III: "the non-passing branches should be considered as obstacles")."""
    r = tree.robot
    others = [b for b in tree.branches if b.name not in climbed]
    obstacles = Bark(others, grip=False) if others else None
    for f in motion.frames:
        p = f.posture
        where = f"in the {f.phase} of step {f.step}"
        if not r.s_min - 1e-9 <= p.S <= r.s_max + 1e-9:
            return f"the body would be {p.S:.3f} m long (s_min = {r.s_min} m, s_max = {r.s_max} m) {where}", False
        if p.kappa * p.S > r.max_bend:
            return f"the body would bend {p.kappa * p.S:.3f} rad (max_bend = {r.max_bend} rad) {where}", False
        if obstacles is not None:
            depth = max(obstacles.depth(x) for x in f.body[1:-1])
            if depth > 0.0:
                return (f"the body would pass {depth * 1000:.1f} mm into a branch the path does not climb {where}",
                        True)
    return "", False
