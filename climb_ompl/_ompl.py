"""The only module that imports OMPL.

OMPL 1.7.0's wheel loads ``libompl`` twice (``ompl.util`` calls ``ompl.dll_loader``, which loads the
copy in ``site-packages`` while the extensions link the bundled one); every process that imported it
then crashes at exit (double free, exit code 139).  Replacing ``ompl.dll_loader`` by a no-op after
``import ompl`` and before importing ``ompl.base``/``ompl.util`` avoids it.  A ruff rule
(``flake8-tidy-imports.banned-api`` in ``pyproject.toml``) forbids ``import ompl`` anywhere else, since
one stray import brings the crash back; ``tests/test_ompl.py`` checks both the fix and the rule.

Exposes ``ob`` (``ompl.base``), ``og`` (``ompl.geometric``), ``ou`` (``ompl.util``) and the planner
registry (:data:`PLANNER_NAMES`, :func:`make_planner`).
"""

from __future__ import annotations

import ompl  # noqa: TID251  (the one allowed import)

ompl.dll_loader = lambda lib, path: None  # see module docstring

from ompl import base as ob  # noqa: E402, TID251
from ompl import geometric as og  # noqa: E402, TID251
from ompl import util as ou  # noqa: E402, TID251

from .errors import PlannerNotFound  # noqa: E402

ou.setLogLevel(ou.LOG_ERROR)

#: Geometric planners that work on a real-vector state space and on a constrained (projected) space
#: built on one, by name; each is an ``og.<name>`` class taking a SpaceInformation.  Measured with OMPL
#: 1.7.0 and a Python validity checker: every entry solves a 2-D wall problem and a projected-sphere
#: problem (``tests/test_ompl.py``).  KPIECE1, BKPIECE1, LBKPIECE1, ProjEST, SBL, STRIDE and PDST use the
#: space's default projection; FMT and BFMT draw a fixed number of samples (``setNumSamples``) and need
#: about 1.5 s on a constrained space with the default 1000.
PLANNER_NAMES: tuple[str, ...] = (
    "PRM",
    "PRMstar",
    "LazyPRM",
    "LazyPRMstar",
    "RRT",
    "RRTConnect",
    "RRTstar",
    "TRRT",
    "LazyRRT",
    "KPIECE1",
    "BKPIECE1",
    "LBKPIECE1",
    "EST",
    "BiEST",
    "ProjEST",
    "SBL",
    "STRIDE",
    "PDST",
    "FMT",
    "BFMT",
)

#: Planners deliberately left out of the registry, with the reason (measured on OMPL 1.7.0 from PyPI).
UNAVAILABLE: dict[str, str] = {
    "SPARS": "crashes the process in solve() (segfault/abort, also with a C++ validity checker)",
    "SPARStwo": "crashes the process in solve() (segfault/abort, also with a C++ validity checker)",
    "BiTRRT": "not exposed by the OMPL 1.7.0 Python bindings (use TRRT)",
    "STRRTstar": "needs a space-time state space (a time dimension)",
    "SST": "a kinodynamic-style planner: no exact solution on the 2-D test problem within 1 s",
    "LBTRRT": "asymptotically near-optimal: runs to the time limit, nothing gained for feasibility",
    "LazyLBTRRT": "asymptotically near-optimal: runs to the time limit, nothing gained for feasibility",
    "RRTXstatic": "asymptotically optimal: runs to the time limit, nothing gained for feasibility",
    "RRTsharp": "asymptotically optimal: runs to the time limit, nothing gained for feasibility",
    "InformedRRTstar": "needs an informed sampler of the ambient space, meaningless on a stance manifold",
    "SORRTstar": "needs an informed sampler of the ambient space, meaningless on a stance manifold",
    "BITstar": "needs an informed sampler of the ambient space, meaningless on a stance manifold",
    "ABITstar": "needs an informed sampler of the ambient space, meaningless on a stance manifold",
    "AITstar": "needs an informed sampler of the ambient space, meaningless on a stance manifold",
    "EITstar": "needs an informed sampler of the ambient space, meaningless on a stance manifold",
}

#: Planners whose ``solve`` runs until the time/termination condition even after a first solution.
ANYTIME = frozenset({"PRMstar", "LazyPRMstar", "RRTstar"})


class PlannerUnavailable(PlannerNotFound):
    """A known OMPL planner that the registry leaves out; the message gives the reason and the valid names."""

    def __init__(self, name: str, reason: str, valid: tuple[str, ...]):
        super().__init__("planner", name, valid)
        self.reason = reason
        self.args = (f"planner {name!r} is not available: {reason}; valid names: {', '.join(valid)}",)

    def __str__(self) -> str:
        return str(self.args[0])


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


def check_planner(name: str) -> None:
    """Raise for a name that is not a registered planner: :class:`PlannerUnavailable` (with the reason) for a known
    planner the registry leaves out (:data:`UNAVAILABLE`), else :class:`~climb_ompl.errors.PlannerNotFound`."""
    if name not in PLANNER_NAMES:
        if name in UNAVAILABLE:
            raise PlannerUnavailable(name, UNAVAILABLE[name], PLANNER_NAMES)
        raise PlannerNotFound("planner", name, PLANNER_NAMES)


def seed_rng(seed: int) -> None:
    """Seed OMPL's global RNG (``ompl::RNG::setSeed``).

    Must happen before the space/planner objects of a query are built.  OMPL seeds every RNG it creates
    later from this one, also when it is called again after sampling has started (OMPL then logs "Random
    number generation already started", which :func:`climb_ompl.onestep.find_path` silences).  OMPL
    refuses the seed 0: in a fresh process it uses 1 instead, in a process that has sampled already it
    ignores the call; 0 is therefore mapped to 1 here, so seed 0 gives the same draws in a fresh and in
    a reused process (and OMPL's draws for seeds 0 and 1 are the same).  Seeds are taken modulo 2**32 (OMPL's
    seed is a 32-bit unsigned integer).
    """
    ou.RNG.setSeed(int(seed) % 2**32 or 1)  # a seed plus a call count may pass 2**32: wrapped, not an overflow


__all__ = ["ob", "og", "ou", "PLANNER_NAMES", "UNAVAILABLE", "ANYTIME", "PlannerUnavailable", "make_planner",
           "seed_rng"]
