"""climb_ompl: OMPL-based planning for multi-limbed robots that climb by friction alone.

Implements Bretl's free-climbing planner (stance manifolds, static equilibrium with friction cones,
one-step and multi-step planning), MRWALLSPECT III's slope-transition gait and TreeBot's tree-climbing
planner.  ``import climb_ompl`` is cheap: it imports neither OMPL nor meshcat; the heavy modules load
when their names are first used.
"""

from __future__ import annotations

import importlib
from typing import Any

from .errors import (
    ClimbError,
    EquilibriumError,
    InputError,
    PlanFileError,
    PlannerNotFound,
    QueryError,
    RobotModelError,
    TerrainError,
)
from .terrain import Hold, Terrain, generate_wall

__version__ = "0.1.0"

# name -> module that defines it; imported on first access (PEP 562).
_LAZY = {
    "SupportRegion": "equilibrium",
    "Contact": "equilibrium",
    "support_region": "equilibrium",
    "contact_forces": "equilibrium",
    "RobotModel": "robot",
    "Stance": "stance",
    "find_transition": "onestep",
    "find_path": "onestep",
    "plan_climb": "multistep",
    "replay": "multistep",
    "ClimbSettings": "settings",
    "Plan": "plan",
    "verify": "verify_climb",
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
