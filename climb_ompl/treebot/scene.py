"""What to draw for a TreeBot plan (pure numpy, no meshcat): used by ``climb-ompl play``."""

from __future__ import annotations

from typing import Any

import numpy as np


def scene_items(plan: dict[str, Any]) -> dict[str, Any]:
    """Drawable items of a ``kind: "treebot"`` plan dict.

    Returns:
        A dict of numpy arrays (world frame, metres):

        * ``rings``: list of ``{"branch", "ring", "points" (n, 3), "closed": True}`` ring polylines;
        * ``surface_points`` ``(N, 3)``, ``surface_normals`` ``(N, 3)``, ``obstacle_points`` ``(K, 3)``;
        * ``path`` ``(P, 3)``: the planned gripping points in order (polyline);
        * ``frames``: list (time order) of ``{"t", "step", "phase", "body" (k, 3), "rear" (3,),
          "rear_dir" (3,), "front" (3,), "front_dir" (3,)}``: the body arc polyline and both gripper poses;
        * ``gripping_points`` ``(G, 3)``: where the front gripper grips (the motion's targets).
    """
    rings, pts, nrm, obs = [], [], [], []
    for b in plan["tree"]["branches"]:
        for k, r in enumerate(b["rings"]):
            p = np.asarray(r["points"], float)
            n = np.asarray(r["normals"], float)
            rings.append({"branch": b["name"], "ring": k, "points": p, "closed": True})
            pts.append(p)
            nrm.append(n / np.linalg.norm(n, axis=1, keepdims=True))
            if r.get("obstacles"):
                obs.append(p[np.asarray(r["obstacles"], int)])
    path = np.array([q["position"] for q in plan.get("path") or []], float).reshape(-1, 3)
    frames = []
    motion = plan.get("motion") or {}
    for i, f in enumerate(motion.get("frames", [])):
        frames.append({"t": float(i), "step": f["step"], "phase": f["phase"],
                       "body": np.asarray(f["body"], float),
                       "rear": np.asarray(f["rear"]["position"], float),
                       "rear_dir": np.asarray(f["rear"]["direction"], float),
                       "front": np.asarray(f["front"]["position"], float),
                       "front_dir": np.asarray(f["front"]["direction"], float)})
    grips = path[motion.get("targets", [])] if len(path) else np.empty((0, 3))
    return {"rings": rings, "surface_points": np.concatenate(pts), "surface_normals": np.concatenate(nrm),
            "obstacle_points": np.concatenate(obs) if obs else np.empty((0, 3)), "path": path,
            "frames": frames, "gripping_points": grips}
