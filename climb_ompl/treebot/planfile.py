"""TreeBot plan files (``kind: "treebot"``): the DP path and the continuum-body motion as JSON.

Top-level keys: ``schema_version`` (1, the common plan-file part), ``kind`` (``"treebot"``),
``kind_version`` (:data:`KIND_VERSION`, this content), ``climb_ompl_version``, ``seed``, ``tree`` (the
tree's YAML content plus ``tree_hash``, its :meth:`~.tree.Tree.content_hash`), ``target`` (branch and
optional point), ``path`` (gripping points: row, branch, ring, point, position, normal), ``motion`` (method,
targets, ``steps`` with the fitted arcs and ``frames`` with body samples and both gripper poses), ``cost``
and ``stats``.  ``found: false`` plans carry ``reason`` and an empty path.  The file is self-contained:
``climb-ompl verify`` re-checks it from these contents alone (:mod:`climb_ompl.verify_tree`).
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from .bark import Bark
from .dp import DPPlanner
from .motion import Method, Motion, plan_motion
from .tree import Tree

SCHEMA_VERSION = 1
#: Version of the ``treebot`` content: 2 embeds ``robot.max_bend`` and puts every grip on the bark.
KIND_VERSION = 2


def build_plan(tree: Tree, target: str, *, seed: int = 0, target_point: int | None = None,
               start_point: int | None = None, method: Method = "proposed") -> dict[str, Any]:
    """Plan the path (Lam et al. (TreeBot) Eq. 4-7) and the motion (Eq. 1-3, 8-20); the plan-file dict.

    A motion whose body would be longer than ``robot.s_max`` or bend more than ``robot.max_bend`` is no
    plan: ``found`` is false and ``reason`` says where.

    Raises:
        TreeError: unknown target branch, bad point index.
    """
    from .. import __version__

    t0 = time.perf_counter()
    planner = DPPlanner.for_tree(tree, target, target_point)
    res = planner.solve(start_point)
    t_dp = time.perf_counter() - t0
    tree_dict = tree.to_dict()
    tree_dict["tree_hash"] = tree.content_hash()
    plan: dict[str, Any] = {
        "schema_version": SCHEMA_VERSION, "kind": "treebot", "kind_version": KIND_VERSION,
        "climb_ompl_version": __version__, "seed": seed,
        "tree": tree_dict, "target": {"branch": target, "point": target_point},
        "found": res.found, "reason": res.reason,
        "path": [p.to_dict() for p in res.path],
        "cost": res.cost if res.found else None,
    }
    stats: dict[str, Any] = {**res.stats, "dp_time_s": t_dp}
    plan["motion"] = None
    if res.found:
        t1 = time.perf_counter()
        P = np.array([p.position for p in res.path])
        N = np.array([p.normal for p in res.path])
        bark = Bark(tree.branch(b) for b in dict.fromkeys(p.branch for p in res.path))
        motion = plan_motion(P, N, tree.robot, method, bark=bark.nearest)
        stats["motion_time_s"] = time.perf_counter() - t1
        S = motion.lengths()
        bend = np.array([f.posture.kappa * f.posture.S for f in motion.frames])
        stats.update({"steps": len(motion.steps), "frames": len(motion.frames),
                      "body_length_min": float(S.min()), "body_length_max": float(S.max()),
                      "bend_max": float(bend.max())})
        why = _motion_fault(tree, motion, {p.branch for p in res.path})
        if why:
            plan.update(found=False, path=[], cost=None, reason=why)
        else:
            plan["motion"] = motion.to_dict()
    plan["stats"] = stats
    return plan


def _motion_fault(tree: Tree, motion: Motion, climbed: set[str]) -> str:
    """Why the motion is no plan (empty if it is one): a body shorter than ``s_min`` or longer than ``s_max``,
    bent more than ``max_bend``, or passing through a branch the path does not climb (section III: "the
    non-passing branches should be considered as obstacles")."""
    r = tree.robot
    others = [b for b in tree.branches if b.name not in climbed]
    obstacles = Bark(others, grip=False) if others else None
    for f in motion.frames:
        p = f.posture
        where = f"in the {f.phase} of step {f.step}"
        if not r.s_min - 1e-9 <= p.S <= r.s_max + 1e-9:
            return f"the body would be {p.S:.3f} m long (s_min = {r.s_min} m, s_max = {r.s_max} m) {where}"
        if p.kappa * p.S > r.max_bend:
            return f"the body would bend {p.kappa * p.S:.3f} rad (max_bend = {r.max_bend} rad) {where}"
        if obstacles is not None:
            depth = max(obstacles.depth(x) for x in f.body[1:-1])
            if depth > 0.0:
                return f"the body would pass {depth * 1000:.1f} mm into a branch the path does not climb {where}"
    return ""
