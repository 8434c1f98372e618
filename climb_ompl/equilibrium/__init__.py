"""Static equilibrium of a multi-limbed robot on holds (independent of OMPL and of the robot module).

* :func:`support_region` / :class:`SupportRegion` / :class:`RegionCache`: the CoM positions in
  equilibrium for a stance (seed 000 eqs. (1), (6), (7); seed 001 appendix B).
* :func:`contact_forces`: the most robust contact forces for one CoM position (exact cones, cvxpy).
* :func:`torque_feasible` / :class:`TorqueChecker`: contact forces that also respect joint torque
  limits (seed 001 section 3.2.3), exact (cvxpy) or fast (HiGHS LP with prefilters).
"""

from __future__ import annotations

from ._contacts import CONTACT_KINDS, Contact
from .forces import ForceResult, TorqueChecker, TorqueResult, contact_forces, torque_feasible
from .region import CLIP, RegionCache, SupportRegion, iterative_projection, support_region

__all__ = [
    "CLIP",
    "CONTACT_KINDS",
    "Contact",
    "ForceResult",
    "RegionCache",
    "SupportRegion",
    "TorqueChecker",
    "TorqueResult",
    "contact_forces",
    "iterative_projection",
    "support_region",
    "torque_feasible",
]
