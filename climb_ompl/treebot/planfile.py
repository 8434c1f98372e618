"""TreeBot plan files (``kind: "treebot"``): the DP path and the continuum-body motion as JSON.

Top-level keys: ``schema_version`` (1), ``kind`` (``"treebot"``), ``climb_ompl_version``, ``seed``,
``tree`` (the tree's YAML content plus ``tree_hash``, its sha256), ``target`` (branch and optional point),
``path`` (gripping points: row, branch, ring, point, position, normal), ``motion`` (method, targets,
``steps`` with the fitted arcs and ``frames`` with body samples and both gripper poses), ``cost`` and
``stats``.  ``found: false`` plans carry ``reason`` and an empty path.
"""

from __future__ import annotations

import time
from typing import Any

import numpy as np

from .dp import DPPlanner
from .motion import Method, plan_motion
from .tree import Tree

SCHEMA_VERSION = 1


def build_plan(tree: Tree, target: str, *, seed: int = 0, target_point: int | None = None,
               start_point: int | None = None, method: Method = "proposed") -> dict[str, Any]:
    """Plan the path (seed 004 Eq. 4-7) and the motion (Eq. 1-3, 8-20) and return the plan-file dict.

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
        "schema_version": SCHEMA_VERSION, "kind": "treebot", "climb_ompl_version": __version__, "seed": seed,
        "tree": tree_dict, "target": {"branch": target, "point": target_point},
        "found": res.found, "reason": res.reason,
        "path": [p.to_dict() for p in res.path],
        "cost": res.cost if res.found else None,
    }
    stats: dict[str, Any] = {**res.stats, "dp_time_s": t_dp}
    if res.found:
        t1 = time.perf_counter()
        P = np.array([p.position for p in res.path])
        N = np.array([p.normal for p in res.path])
        motion = plan_motion(P, N, tree.robot, method)
        stats["motion_time_s"] = time.perf_counter() - t1
        S = motion.lengths()
        stats.update({"steps": len(motion.steps), "frames": len(motion.frames),
                      "body_length_min": float(S.min()), "body_length_max": float(S.max())})
        plan["motion"] = motion.to_dict()
    else:
        plan["motion"] = None
    plan["stats"] = stats
    return plan
