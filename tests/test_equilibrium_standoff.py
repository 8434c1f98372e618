"""How far from a wall of ledges the CoM may be: the support region against a closed form.

Four holds at the corners of a rectangle on the wall ``y = 0`` (``x = +-W/2``, ``z = 0`` and ``z = L``), each a
ledge whose normal leans ``beta`` from the wall's up (``+z``) towards the climber (``+y``), friction ``mu``, and
gravity leaning ``theta`` from ``-z`` towards the wall (``theta > 0``: a slab) or away from it (``theta < 0``: an
overhang), as the suite's slab and overhang express their slopes.  By the symmetry in ``x`` the forces stay in the
``y-z`` plane, and equations (B1)-(B3) of Bretl (2006), appendix B, become a two-contact problem: the top holds pull
the body towards the wall at most ``p = tan(phi - beta)`` per unit of their load, the bottom holds push it away at
most ``s = tan(phi + beta)`` (``phi = atan mu``), and the loads sum to the weight, whose line leans ``t = tan
theta``.  With the top holds' share ``a`` the moment about the CoM gives its largest stand-off at the top holds'
height, ``y_top <= L (p a + t)``, the share fixed by the force balance, ``-p a + s (1 - a) = t``:

    y_top <= L s (p + t) / (s + p),

and along the weight's line a CoM at height ``z`` may stand ``(L - z) t`` less far out.  On the suite's slab (15
degrees, mu = 0.9, beta = 20 degrees) that is 0.553 L at the top holds and 0.285 L at the bottom ones; on its
overhang (-10 degrees, mu = 1) 0.238 L and 0.414 L: a quadruped whose CoM stands 0.4 m off the wall needs a stance
longer than a metre.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from climb_ompl.equilibrium import Contact, support_region


def standoff_bound(length: float, z: float, mu: float, beta: float, theta: float) -> float:
    """The closed form of the module docstring: the largest stand-off of a CoM at height ``z``, metres."""
    phi = math.atan(mu)
    p, s, t = math.tan(phi - beta), math.tan(phi + beta), math.tan(theta)
    return length * s * (p + t) / (s + p) - (length - z) * t


def region_standoff(length: float, width: float, z: float, mu: float, beta: float, theta: float,
                    exact: bool) -> float:
    """The largest stand-off of a CoM at ``x = 0``, height ``z``, inside the support region (bisection)."""
    n = (0.0, math.sin(beta), math.cos(beta))
    contacts = [Contact((sx * width / 2, 0.0, zz), n, mu) for sx in (-1, 1) for zz in (0.0, length)]
    g = 9.81 * np.array([0.0, -math.sin(theta), -math.cos(theta)])
    region = support_region(contacts, 50.0, g, exact=exact)
    assert region.contains(np.array([0.0, 1e-3, z]))
    lo, hi = 1e-3, 5.0
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if region.contains(np.array([0.0, mid, z])) else (lo, mid)
    return lo


@pytest.mark.parametrize("name, mu, theta_deg", [("slab", 0.9, 15.0), ("overhang", 1.0, -10.0),
                                                 ("wall", 1.0, 0.0), ("steep slab", 0.6, 30.0)])
@pytest.mark.parametrize("length, width", [(0.9, 0.6), (0.45, 0.15), (1.2, 0.3)])
def test_standoff_matches_closed_form(name: str, mu: float, theta_deg: float, length: float, width: float) -> None:
    beta, theta = math.radians(20.0), math.radians(theta_deg)
    for z in (0.0, 0.5 * length, length):
        want = standoff_bound(length, z, mu, beta, theta)
        assert want > 0
        # linearised cones (8 edges, one in the y-z plane on either side): the same bound
        assert region_standoff(length, width, z, mu, beta, theta, exact=False) == pytest.approx(want, abs=1e-6)
        # second-order cones, within the projection's tolerance
        assert region_standoff(length, width, z, mu, beta, theta, exact=True) == pytest.approx(want, abs=2e-3)


def test_suite_figures() -> None:
    """The figures quoted in the module docstring (the suite's slab and overhang)."""
    beta = math.radians(20.0)
    slab = (0.9, beta, math.radians(15.0))
    over = (1.0, beta, math.radians(-10.0))
    assert standoff_bound(1.0, 1.0, *slab) == pytest.approx(0.553, abs=1e-3)
    assert standoff_bound(1.0, 0.0, *slab) == pytest.approx(0.285, abs=1e-3)
    assert standoff_bound(1.0, 1.0, *over) == pytest.approx(0.238, abs=1e-3)
    assert standoff_bound(1.0, 0.0, *over) == pytest.approx(0.414, abs=1e-3)
