"""What a valid climb plan is: the tolerances and resolutions shared by the planner and
:mod:`climb_ompl.verification.climb`.

The planner builds plans to these numbers and the verifier holds them to the same numbers; both import
them from here, so they cannot drift apart.

* :data:`TOLERANCE` - every contact hand is within this distance of its hold at every waypoint (metres).
  It is the tolerance of the stance constraint given to OMPL (``ob.Constraint``), whose own default
  (1e-4) would let hands drift off their holds along a path.
* :data:`MOTION_TOLERANCE` - between two waypoints, the straight joint-space segment cuts across the
  curved stance manifold; hands may leave their holds by at most this chord error (metres).
* :data:`RESOLUTION` - joint-space step (max-norm, rad or m) between the states checked on the motion
  between two waypoints.
* :data:`HAND_CONTACT_RADIUS` - a free hand may touch the terrain within this distance of a hold (it is
  leaving or reaching it); anywhere else, and for every other link, any contact is a collision.
* :data:`CONE_EDGES` - edges of the inscribed friction pyramids of the linearised equilibrium tests: the
  support regions the planner tests the CoM against, and the verifier's per-point LP (whose negative answers an
  exact second-order-cone program re-decides).  The planner's torque check may use coarser pyramids
  (:attr:`climb_ompl.settings.ClimbSettings.torque_cone_edges`): inscribed, they accept fewer contact forces,
  so a plan they accept is accepted by the verifier too.
"""

from __future__ import annotations

#: Hands-on-holds tolerance at waypoints, metres.
TOLERANCE: float = 1e-5
#: Hands-on-holds tolerance on the straight-line motion between waypoints, metres.
MOTION_TOLERANCE: float = 1e-4
#: Joint-space step between checked states on the motion between waypoints (max-norm, rad or m).
RESOLUTION: float = 0.05
#: A free hand may touch the terrain within this distance of a hold, metres.
HAND_CONTACT_RADIUS: float = 0.05
#: Edges of the linearised friction cones of the equilibrium tests (planner and verifier).
CONE_EDGES: int = 8

__all__ = ["TOLERANCE", "MOTION_TOLERANCE", "RESOLUTION", "HAND_CONTACT_RADIUS", "CONE_EDGES"]
