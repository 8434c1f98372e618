"""The names a user may give: OMPL planners, constrained spaces and samplers, checked without importing OMPL.

Settings and robot specs are checked when they are read (:class:`~climb_ompl.settings.ClimbSettings`,
:mod:`climb_ompl.model.spec`), long before a plan is made; checking their names here keeps OMPL out of those
imports.  :mod:`climb_ompl.manifold._ompl` builds the planners named here, :mod:`climb_ompl.manifold.stance` the
spaces and :mod:`climb_ompl.manifold.samplers` the samplers.
"""

from __future__ import annotations

from climb_ompl.errors import PlannerNotFound

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


#: Constrained state spaces by name.
SPACE_NAMES: tuple[str, ...] = ("projected", "atlas", "tangent_bundle")

#: Sampling strategies by name (:mod:`climb_ompl.manifold.samplers`); ``"a+b"`` mixes them.
SAMPLER_NAMES: tuple[str, ...] = ("uniform", "joint-by-joint", "straight-elbow", "free-limb", "lift", "reduced")


def check_planner(name: str) -> None:
    """Raise for a name that is not a registered planner: :class:`PlannerUnavailable` (with the reason) for a known
    planner the registry leaves out (:data:`UNAVAILABLE`), else :class:`~climb_ompl.errors.PlannerNotFound`."""
    if name not in PLANNER_NAMES:
        if name in UNAVAILABLE:
            raise PlannerUnavailable(name, UNAVAILABLE[name], PLANNER_NAMES)
        raise PlannerNotFound("planner", name, PLANNER_NAMES)


def parse_sampler(name: str) -> tuple[str, ...]:
    """Split ``"a+b"`` into known strategy names.

    Raises:
        PlannerNotFound: an unknown name (lists the valid names).
    """
    parts = tuple(p.strip() for p in str(name).split("+") if p.strip())
    if not parts:
        raise PlannerNotFound("sampler", str(name), SAMPLER_NAMES)
    for p in parts:
        if p not in SAMPLER_NAMES:
            raise PlannerNotFound("sampler", p, SAMPLER_NAMES)
    return parts


__all__ = ["ANYTIME", "PLANNER_NAMES", "SAMPLER_NAMES", "SPACE_NAMES", "UNAVAILABLE", "PlannerUnavailable",
           "check_planner", "parse_sampler"]
