"""TreeBot: linear-time path and motion planning for a tree-climbing robot (Lam et al.).

* :mod:`.tree` - the tree of branches of rings of surface points, its YAML format and loader;
* :mod:`.generate` - a seeded tree generator;
* :mod:`.dp` - the dynamic-programming path (Eq. 4-7) and its incremental update (section IV.B);
* :mod:`.body`, :mod:`.fit`, :mod:`.motion` - continuum-body kinematics (Eq. 1-3), plane/arc fit and the
  rear gripper's direction (Eq. 8-20), the motion along the path;
* :mod:`.compare` - proposed vs. simple motion planning (Fig. 13);
* :mod:`.planfile`, :mod:`.scene` - the plan file and what playback draws.
"""

from __future__ import annotations

from climb_ompl.treebot.compare import compare
from climb_ompl.treebot.dp import DPPlanner, PathPoint, PathResult, plan_path
from climb_ompl.treebot.generate import BranchSpec, generate_tree, three_branch_layout
from climb_ompl.treebot.motion import Motion, plan_motion
from climb_ompl.treebot.planfile import build_plan
from climb_ompl.treebot.scene import scene_items
from climb_ompl.treebot.tree import Branch, Ring, RobotParams, Tree, TreeError, bundled_trees

__all__ = [
    "Branch", "BranchSpec", "DPPlanner", "Motion", "PathPoint", "PathResult", "RobotParams", "Ring", "Tree",
    "TreeError", "build_plan", "bundled_trees", "compare", "generate_tree", "plan_motion", "plan_path",
    "scene_items", "three_branch_layout",
]
