"""Helpers for the playback tests: a small real climb plan, and probes of a meshcat page in headless Chromium.

The page probes read meshcat's viewer object (``window.viewer``: its ``scene_tree`` and ``animator``)
through Playwright; Chromium is Debian's ``/usr/bin/chromium`` with SwiftShader WebGL
(:mod:`climb_ompl.viz._browser`).
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np
import pytest

from climb_ompl.viz._browser import chromium_path

requires_chromium = pytest.mark.skipif(
    chromium_path() is None, reason="no Chromium executable (apt-get install chromium; see Makefile 'chromium')")


def make_climb_plan(robot_name: str = "lemur", terrain_name: str = "demo-wall") -> dict[str, Any]:
    """A schema-valid two-step climb plan (release one hand, then move the body) for playback tests.

    The stance uses the holds nearest to the hands at the robot's nominal configuration; the motion is
    not checked for equilibrium (playback does not need it).
    """
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.plan.file import ForceSample, Plan, Step, sha256_json, sha256_text

    robot = RobotModel.load(robot_name)
    terrain = Terrain.load(terrain_name)
    q0 = np.asarray(robot.nominal_q, dtype=float)
    hands = robot.hand_positions(q0)
    stance = {lb.name: min(terrain.holds, key=lambda h, p=hands[i]: float(np.linalg.norm(h.p - p))).id
              for i, lb in enumerate(robot.limbs)}
    first = robot.limbs[0].name
    q1 = q0.copy()
    q1[robot.base_indices[0]] += 0.05
    q1[robot.limbs[0].joint_indices[0]] += 0.4
    q2 = q1.copy()
    q2[robot.base_indices[1]] += 0.08
    pairs = tuple(sorted(stance.items()))
    after = tuple(p for p in pairs if p[0] != first)
    f = (0.0, 4.0, robot.mass * 9.81 / len(pairs))
    s0 = Step(0, pairs, "release", first, stance[first], (tuple(q0), tuple(q1)), (0.0, 1.0),
              (ForceSample(0, tuple((k, f) for k, _ in pairs), tuple(0.0 for _ in q0), 0.01),), 0.01)
    s1 = Step(1, after, "grab", first, stance[first], (tuple(q1), tuple(q2)), (0.0, 0.8), (), float("nan"))
    spec = robot.spec
    urdf = Path(robot.urdf_path).read_text()
    plan = Plan(
        robot={"name": robot.name, "spec": spec, "spec_sha256": sha256_json(spec), "urdf": urdf,
               "urdf_sha256": sha256_text(urdf)},
        terrain={"name": terrain.name, "data": terrain.to_dict(), "sha256": terrain.content_hash()},
        query={"start": {"stance": stance, "q": q0.tolist()}, "goal": {"type": "height", "height": 1.0}},
        seed=0, steps=(s0, s1), settings={}, totals={"steps": 2, "execution_s": 1.8},
        versions={"numpy": np.__version__}, climb_ompl_version="0.1.0")
    d = plan.to_dict()
    d["steps"][1]["margin"] = 0.0  # JSON has no NaN
    return d


# ---- page probes (JavaScript run in the meshcat page) ------------------------------------------------
JS_CHILDREN = """(path) => {
  let node = viewer.scene_tree;
  for (const name of path) { node = node.children[name]; if (node === undefined) return null; }
  return Object.keys(node.children);
}"""

JS_ANIMATION = """() => { const a = viewer.animator;
  return {duration: a.duration, actions: a.actions.length}; }"""

# World pose (column-major 4x4) of a node relative to /meshcat (the viewer shifts /meshcat to centre the
# content), and whether it and all its ancestors are visible, at animation time t.
JS_POSE_AT = """([path, t]) => {
  const a = viewer.animator;
  if (a.actions.length > 0) { if (!a.playing) a.play(); a.pause(); a.seek(t); }
  const root = viewer.scene_tree.find(["meshcat"]).object;
  let node = viewer.scene_tree;
  for (const name of path) { node = node.children[name]; if (node === undefined) return null; }
  const obj = node.object;
  viewer.scene.updateMatrixWorld(true);
  const inv = root.matrixWorld.clone().invert();
  const rel = inv.multiply(obj.matrixWorld);
  let visible = true;
  for (let o = obj; o; o = o.parent) visible = visible && o.visible;
  return {matrix: Array.from(rel.elements), visible: visible};
}"""


def pose_at(page: Any, path: list[str], t: float) -> tuple[np.ndarray, bool]:
    """``(4x4 pose relative to /meshcat, visible)`` of scene node ``path`` at animation time ``t``."""
    res = page.evaluate(JS_POSE_AT, [path, t])
    assert res is not None, f"no scene node {'/'.join(path)}"
    return np.array(res["matrix"], dtype=float).reshape(4, 4).T, bool(res["visible"])


def distinct_colours(png: bytes) -> int:
    """Number of distinct RGB colours in a PNG."""
    import io

    from PIL import Image

    img = np.asarray(Image.open(io.BytesIO(png)).convert("RGB"))
    return len(np.unique(img.reshape(-1, 3), axis=0))


def changed_fraction(png_a: bytes, png_b: bytes) -> float:
    """Fraction of pixels that differ between two same-size PNGs."""
    import io

    from PIL import Image

    a = np.asarray(Image.open(io.BytesIO(png_a)).convert("RGB")).astype(int)
    b = np.asarray(Image.open(io.BytesIO(png_b)).convert("RGB")).astype(int)
    return float(np.mean(np.abs(a - b).sum(axis=2) > 30))
