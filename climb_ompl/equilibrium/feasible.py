"""Torque-limited feasible regions: the CoM positions where a posture's joints can hold the robot.

Orsolino et al. (2020) ("Feasible Region: an Actuation-Aware Extension of the Support Region", IEEE
T-RO) extend the support region with the joint-torque limits of the current posture: with the joint
configuration fixed (so the contact Jacobians ``J_i`` and the gravity torques ``g(q)`` are fixed), the
feasible region is the set of CoM positions at which contact forces exist inside the (linearised)
friction cones that balance the robot's weight (Bretl, Latombe & Rock (2003) eq. (7)) and keep every
joint torque ``tau = g(q) - sum_i J_i^T f_i`` within ``|tau_j| <= tau_max_j`` (Bretl (2006) sec. 3.2.3).
It is the projection of a polytope, like the support region; Orsolino et al. compute it by iterative
projection, here the shadow-vertex simplex of :mod:`._simplex` gives it exactly in one pass.

It always lies inside the support region of the same cones (the torque rows only remove forces).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

from climb_ompl.equilibrium._contacts import (
    CONE_EDGES,
    Contact,
    as_contacts,
    check_mass_gravity,
    check_planar_contacts,
    linearise,
)
from climb_ompl.equilibrium._simplex import SimplexError
from climb_ompl.equilibrium.forces import _check_torque_args, torque_rows
from climb_ompl.equilibrium.region import (
    CLIP,
    TOL_LP,
    SupportRegion,
    _Problem,
    _projection_tableau,
    check_cone_edges,
    make_region,
)
from climb_ompl.errors import EquilibriumError


def feasible_region(
    contacts: Sequence[Contact | Any],
    mass: float,
    gravity: Any,
    jacobians: Any,
    gravity_torques: Any,
    torque_limits: Any,
    actuated: Any,
    *,
    planar: bool = False,
    cone_edges: int = CONE_EDGES,
    clip: float = CLIP,
) -> SupportRegion:
    """The torque-limited feasible region of one posture (Orsolino et al. (2020)).

    Args:
        contacts: the ``k`` contacts.
        mass: kg.  gravity: m/s^2.
        jacobians: ``(k, 3, nq)`` position Jacobians of the contact points at the posture.
        gravity_torques: ``(nq,)`` generalised gravity torques ``g(q)`` at the posture, N m (or N).
        torque_limits: ``(nq,)`` limits, N m (``inf`` where unlimited).
        actuated: ``(nq,)`` bool mask of actuated joints (the others are not limited).
        planar: 2-D problem (x-z plane): the region is an interval.
        cone_edges: edges of the inscribed friction pyramids (the default is :func:`support_region`'s).
        clip: half-width of the box bounding unbounded regions, metres.

    Returns:
        A :class:`SupportRegion` (same coordinates, membership and margin tests), ``is_empty`` when no
        CoM position works, e.g. when a joint that no contact loads cannot hold its own gravity torque.

    Raises:
        EquilibriumError: bad input (naming the value).
    """
    cs = as_contacts(contacts)
    m, g = check_mass_gravity(mass, gravity, planar)
    if planar:
        check_planar_contacts(cs)
    k = check_cone_edges(cone_edges)
    if not (np.isfinite(clip) and clip > 0):
        raise EquilibriumError(f"clip: must be finite and > 0 m, got {clip!r}")
    J, gt, lim, act = _check_torque_args(len(cs), jacobians, gravity_torques, torque_limits, actuated)
    pb = _Problem(cs, m, g, planar)
    lin = linearise(cs, pb.weight, k, planar)
    meta = dict(planar=planar, exact=False, cone_edges=k, tol=TOL_LP)
    rows = torque_rows(lin, pb.weight, J, gt, lim, act & np.isfinite(lim))
    if rows is None:
        return make_region(pb, None, clip, 0, meta)
    M, tau0, L = rows
    tab = _projection_tableau(pb, lin, clip, M, tau0 - L, tau0 + L)
    try:
        if not tab.phase1():
            return make_region(pb, None, clip, 1, meta)
        if planar:
            ends = []
            for sign in (-1.0, 1.0):
                tab.maximise(np.array([sign]))
                ends.append(np.array(tab.value()) + tab.x0)  # type: ignore[attr-defined]
            pts = np.array(ends)
        else:
            pts = tab.shadow_vertices() + tab.x0  # type: ignore[attr-defined]
    except SimplexError as exc:  # pragma: no cover - not seen on the oracle stances
        raise EquilibriumError(f"feasible region: the tableau simplex stalled ({exc})") from None
    return make_region(pb, pts, clip, 1, meta, ordered=not planar)
