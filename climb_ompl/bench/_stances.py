"""The stance sets of ``climb-ompl bench equilibrium``: LEMUR-like wall stances, and the widened set a search meets.

The widened set (:func:`wide_stances`) is what the stance search proposes and what users write, not only what a
LEMUR climb holds: 2-4 holds on a vertical wall (the plane ``y = 0``, gravity ``-z``), each hold 0.15-0.5 m from the
stance centre; each normal leans from the wall normal ``+y`` upwards by 10-85 degrees and sideways within a spread
drawn per stance (0-45 degrees); friction 0.3-1.0.  Many of these regions are empty, as they are for most candidate
stances of a search.  :func:`planar_stances` gives the same draw in the x-z plane (the planar interval of Bretl,
Latombe & Rock (2003) eq. (1)).  Every draw comes from one seeded numpy stream: the same seed gives the same set.
"""

from __future__ import annotations

import math
from typing import Any

#: Robot mass of every benchmark stance, kg (LEMUR's).
MASS = 7.0
#: Gravity of the widened set, m/s^2 (Klampt's support polygon assumes gravity along -z).
GRAVITY = (0.0, 0.0, -9.81)


def lemur_stances(n: int, seed: int, holds: int) -> list[tuple[list[Any], float, Any]]:
    """``n`` LEMUR-like stances: ``holds`` holds among the nearest ones to a random hold of
    :func:`climb_ompl.model.terrain.generate_wall` ``(seed + i)``."""
    import numpy as np

    from climb_ompl.equilibrium import Contact
    from climb_ompl.model.terrain import generate_wall

    out = []
    rng = np.random.default_rng(seed)
    for i in range(n):
        w = generate_wall(seed + i)
        P = w.positions
        centre = P[rng.integers(len(P))]
        near = np.argsort(np.linalg.norm(P - centre, axis=1))[: 3 * holds]
        pick = rng.choice(near, size=holds, replace=False)
        out.append(([Contact.from_hold(w.holds[j]) for j in pick], MASS, w.g))
    return out


def _normal(rng: Any, spread_deg: float, planar: bool) -> tuple[float, float, float]:
    """A hold normal leaning up from ``+y`` by 10-85 degrees and sideways by at most ``spread_deg`` (planar: the
    wall normal is ``-x`` rotated up in the x-z plane)."""
    up = math.radians(rng.uniform(10.0, 85.0))
    if planar:
        return (-math.cos(up), 0.0, math.sin(up))
    side = math.radians(rng.uniform(-spread_deg, spread_deg))
    return (math.cos(up) * math.sin(side), math.cos(up) * math.cos(side), math.sin(up))


def wide_stances(n: int, seed: int, holds: tuple[int, int] = (2, 4),
                 planar: bool = False) -> list[tuple[list[Any], float, Any]]:
    """``n`` random stances of the widened set (module docstring); hold counts uniform in ``holds`` (inclusive).

    Planar stances lie in the x-z plane: a wall ``x = 0`` facing ``-x``, holds spread along ``z``.
    """
    import numpy as np

    from climb_ompl.equilibrium import Contact

    rng = np.random.default_rng(seed)
    out = []
    for _ in range(n):
        k = int(rng.integers(holds[0], holds[1] + 1))
        spread = float(rng.uniform(0.0, 45.0))
        contacts = []
        for _ in range(k):
            r, a = float(rng.uniform(0.15, 0.5)), float(rng.uniform(0.0, 2 * math.pi))
            if planar:
                pos = (float(rng.uniform(-0.02, 0.02)), 0.0, r * math.sin(a))
            else:
                pos = (r * math.cos(a), float(rng.uniform(-0.02, 0.02)), r * math.sin(a))
            contacts.append(Contact(pos, _normal(rng, spread, planar), float(rng.uniform(0.3, 1.0))))
        out.append((contacts, MASS, GRAVITY))
    return out
