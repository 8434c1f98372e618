"""The only module that imports OMPL.

OMPL 1.7.0's wheel loads ``libompl`` twice (``ompl.util`` calls ``ompl.dll_loader``, which loads the
copy in ``site-packages`` while the extensions link the bundled one); every process that imported it
then crashes at exit (double free, exit code 139).  Replacing ``ompl.dll_loader`` by a no-op after
``import ompl`` and before importing ``ompl.base``/``ompl.util`` avoids it.  A ruff rule
(``flake8-tidy-imports.banned-api`` in ``pyproject.toml``) forbids ``import ompl`` anywhere else, since
one stray import brings the crash back; ``tests/test_ompl.py`` checks both the fix and the rule.

Exposes ``ob`` (``ompl.base``), ``og`` (``ompl.geometric``), ``ou`` (``ompl.util``) and the planner
registry (:func:`make_planner` over the names of :mod:`climb_ompl.registry`).
"""

from __future__ import annotations

import ompl  # noqa: TID251  (the one allowed import)

ompl.dll_loader = lambda lib, path: None  # see module docstring

from ompl import base as ob  # noqa: E402, TID251
from ompl import geometric as og  # noqa: E402, TID251
from ompl import util as ou  # noqa: E402, TID251

from climb_ompl.registry import ANYTIME, PLANNER_NAMES, UNAVAILABLE, PlannerUnavailable, check_planner  # noqa: E402

ou.setLogLevel(ou.LOG_ERROR)

def make_planner(name: str, si: ob.SpaceInformation) -> ob.Planner:
    """Instantiate the registered planner ``name`` on ``si``.

    Args:
        name: one of :data:`PLANNER_NAMES` (case-sensitive, OMPL's class name).
        si: the (possibly constrained) space information to plan on.

    Raises:
        PlannerNotFound: ``name`` is not registered; the message lists the valid names
            (:class:`PlannerUnavailable` with the reason when it is a known but excluded planner).
    """
    check_planner(name)
    return getattr(og, name)(si)


def seed_rng(seed: int) -> None:
    """Seed OMPL's global RNG (``ompl::RNG::setSeed``).

    Must happen before the space/planner objects of a query are built.  OMPL seeds every RNG it creates
    later from this one, also when it is called again after sampling has started (OMPL then logs "Random
    number generation already started", which :func:`climb_ompl.climb.onestep.find_path` silences).  OMPL
    refuses the seed 0: in a fresh process it uses 1 instead, in a process that has sampled already it
    ignores the call; 0 is therefore mapped to 1 here, so seed 0 gives the same draws in a fresh and in
    a reused process (and OMPL's draws for seeds 0 and 1 are the same).  Seeds are taken modulo 2**32 (OMPL's
    seed is a 32-bit unsigned integer).
    """
    ou.RNG.setSeed(int(seed) % 2**32 or 1)  # a seed plus a call count may pass 2**32: wrapped, not an overflow


__all__ = ["ob", "og", "ou", "PLANNER_NAMES", "UNAVAILABLE", "ANYTIME", "PlannerUnavailable", "check_planner",
           "make_planner", "seed_rng"]
