"""The only module that imports OMPL (ARCHITECTURE.md, "OMPL facts").

OMPL 1.7.0's wheel loads ``libompl`` twice (``ompl.util`` calls ``ompl.dll_loader``, which loads the
copy in ``site-packages`` while the extensions link the bundled one); every process that imported it
then crashes at exit (double free, exit code 139).  Replacing ``ompl.dll_loader`` by a no-op after
``import ompl`` and before importing ``ompl.base``/``ompl.util`` avoids it.  A ruff rule
(``flake8-tidy-imports.banned-api``) forbids ``import ompl`` anywhere else.

Exposes ``ob`` (``ompl.base``), ``og`` (``ompl.geometric``), ``ou`` (``ompl.util``) and the planner
registry.
"""

from __future__ import annotations

import ompl  # noqa: TID251  (the one allowed import)

ompl.dll_loader = lambda lib, path: None  # see module docstring

from ompl import base as ob  # noqa: E402, TID251
from ompl import geometric as og  # noqa: E402, TID251
from ompl import util as ou  # noqa: E402, TID251

from .errors import PlannerNotFound  # noqa: E402

ou.setLogLevel(ou.LOG_ERROR)

#: Geometric planners that work on a real-vector (possibly constrained) space, by name.
#: Left out, and why: ``STRRTstar`` needs a time dimension in the space; ``LBTRRT``/``LazyLBTRRT``,
#: ``RRTXstatic``, ``RRTsharp``, ``SST``, ``InformedRRTstar``, ``SORRTstar``, ``ABITstar``,
#: ``AITstar``, ``BITstar``, ``EITstar`` are asymptotically-optimal variants that run to the time
#: limit (or need an informed sampler on the ambient space) and add nothing to feasibility planning
#: on a stance manifold; ``LazyRRT``, ``ProjEST``, ``TRRT`` are superseded by entries listed here.
PLANNER_NAMES: tuple[str, ...] = (
    "PRM",
    "PRMstar",
    "LazyPRM",
    "LazyPRMstar",
    "SPARS",
    "SPARStwo",
    "RRT",
    "RRTConnect",
    "RRTstar",
    "BiTRRT",
    "KPIECE1",
    "BKPIECE1",
    "LBKPIECE1",
    "EST",
    "BiEST",
    "SBL",
    "STRIDE",
    "PDST",
    "FMT",
    "BFMT",
)

#: Planners whose ``solve`` runs until the time/termination condition even after a first solution.
ANYTIME = frozenset({"PRMstar", "LazyPRMstar", "SPARS", "SPARStwo", "RRTstar"})


def make_planner(name: str, si: "ob.SpaceInformation") -> "ob.Planner":
    """Instantiate the registered planner ``name`` on ``si``.

    Raises:
        PlannerNotFound: ``name`` is not registered; the message lists the valid names.
    """
    if name not in PLANNER_NAMES:
        raise PlannerNotFound("planner", name, PLANNER_NAMES)
    return getattr(og, name)(si)


def seed_rng(seed: int) -> None:
    """Seed OMPL's global RNG (must happen before the space/planner objects are built)."""
    ou.RNG.setSeed(int(seed))


__all__ = ["ob", "og", "ou", "PLANNER_NAMES", "ANYTIME", "make_planner", "seed_rng"]
