"""Gaits of specific robots: MRWALLSPECT III's slope transition between two planes, and chains of them
(Kim, Kang & Choi).

``from climb_ompl.mrwallspect import plan_slope`` loads Pinocchio and Coal only when first used.
"""

from __future__ import annotations

import importlib
from typing import Any

_LAZY = {"plan_slope": "slope", "scene_items": "slope", "SlopeResult": "slope", "SlopeRobot": "robot",
         "BodyTrajectory": "geometry", "plan_chain": "chain", "hill": "chain"}


def __getattr__(name: str) -> Any:
    if name in _LAZY:
        return getattr(importlib.import_module(f".{_LAZY[name]}", __name__), name)
    raise AttributeError(f"module 'climb_ompl.mrwallspect' has no attribute {name!r}")


__all__ = list(_LAZY)
