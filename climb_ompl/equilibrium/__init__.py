"""Static equilibrium of a multi-limbed robot on holds (independent of OMPL and of the robot module).

* :func:`support_region` / :class:`SupportRegion` / :class:`RegionCache`: the CoM positions in
  equilibrium for a stance (Bretl, Latombe & Rock (2003) eqs. (1), (6), (7); Bretl (2006) appendix B).
* :func:`contact_forces`: the most robust contact forces for one CoM position (exact cones, cvxpy).
* :func:`torque_feasible` / :class:`TorqueChecker`: contact forces that also respect joint torque
  limits (Bretl (2006) sec. 3.2.3), exact (an SOCP handed to Clarabel) or fast (a small tableau-simplex LP
  behind prefilters).
* :func:`feasible_region`: the CoM positions where a fixed posture's joints can hold the robot within
  their torque limits (Orsolino et al. (2020)).
"""

from __future__ import annotations

from climb_ompl.equilibrium._contacts import CONE_EDGES, CONTACT_KINDS, Contact
from climb_ompl.equilibrium.feasible import feasible_region
from climb_ompl.equilibrium.forces import ForceResult, TorqueChecker, TorqueResult, contact_forces, torque_feasible
from climb_ompl.equilibrium.region import CLIP, RegionCache, SupportRegion, iterative_projection, support_region

__all__ = [
    "CLIP",
    "CONE_EDGES",
    "CONTACT_KINDS",
    "Contact",
    "ForceResult",
    "RegionCache",
    "SupportRegion",
    "TorqueChecker",
    "TorqueResult",
    "contact_forces",
    "feasible_region",
    "iterative_projection",
    "support_region",
    "torque_feasible",
]
