"""climb_ompl: OMPL-based planning for multi-limbed robots that climb by friction alone.

Implements Bretl's free-climbing planner (stance manifolds, static equilibrium with friction cones,
one-step and multi-step planning), MRWALLSPECT III's slope-transition gait and TreeBot's tree-climbing
planner.  ``import climb_ompl`` is cheap: it imports neither OMPL nor meshcat; the heavy modules load
when their names are first used.
"""

from __future__ import annotations

import importlib
from typing import Any

from climb_ompl._version import __version__
from climb_ompl.errors import (
    ClimbError,
    EquilibriumError,
    InputError,
    PlanFileError,
    PlannerNotFound,
    QueryError,
    RobotModelError,
    TerrainError,
)
from climb_ompl.model.terrain import Hold, Terrain, generate_wall

# name -> module that defines it; imported on first access (PEP 562).
_LAZY = {
    "SupportRegion": "equilibrium",
    "Contact": "equilibrium",
    "support_region": "equilibrium",
    "contact_forces": "equilibrium",
    "RobotModel": "model.robot",
    "Stance": "manifold.stance",
    "find_transition": "climb.onestep",
    "find_path": "climb.onestep",
    "plan_climb": "climb.multistep",
    "replay": "climb.multistep",
    "default_start": "climb.multistep",
    "find_start": "climb.start",
    "climb_height": "climb.goal",
    "replan": "climb.replan",
    "TerrainChange": "plan.events",
    "stance_region": "manifold.stance",
    "PLANNER_NAMES": "registry",
    "ClimbResult": "climb.multistep",
    "ClimbSettings": "settings",
    "Plan": "plan.file",
    "verify": "verification",
}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module 'climb_ompl' has no attribute {name!r}")


__all__ = [
    "ClimbError",
    "EquilibriumError",
    "InputError",
    "PlanFileError",
    "PlannerNotFound",
    "QueryError",
    "RobotModelError",
    "TerrainError",
    "Hold",
    "Terrain",
    "generate_wall",
    "__version__",
    *_LAZY,
]
