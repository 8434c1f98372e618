"""``ClimbSettings``: every setting of a multi-step climb in one frozen value, stored whole in the plan file.

A plan file carries its query (start, goal), its seed and its :class:`ClimbSettings`; with the same
robot, terrain and library versions, :func:`climb_ompl.climb.multistep.replay` plans the same climb again
(``climb-ompl plan --replay PLAN.json``).

Search modes (:data:`SEARCH_MODES`):

``guided`` (default)
    The two-stage search of Bretl (2006), Fig. 16, with the departures below, each a named setting
    (``climb-ompl bench climb --compare paper`` plans the same climb both ways in one run; docs/climb.md).
``paper``
    Fig. 16 as published, with the priority of section 3.3.3: the cost ``n - sum ln P`` alone
    (``heuristic_weight = 0``), FIND-TRANSITION called for every adjacent stance when a node is expanded
    (``transitions = "eager"``), a failed edge's ``P`` lowered and nothing deleted
    (``max_edge_failures = 0``), EXPLORE-STANCEGRAPH resumed from its own queue
    (``resume = "queue"``), every elbow-bend combination of the closed chains tried at each sampled base
    position as in Fig. 17 (``elbow_bends = "enumerate"``), each candidate's paths planned as stage 1 found it
    (``shortcuts = false``), a stance's releases in limb order (``release_lookahead = false``),
    EXPLORE-TRANSITIONGRAPH recursive with backtracking (``stage2 = "recursive"``), ``P`` inversely proportional to
    the effort spent on the edge (``edge_p = "time"``), FIND-TRANSITION's base drawn within reach (2L) of the holds
    (``transition_base = "holds"``, Fig. 17 line 2), FIND-PATH a PRM (``planner = "LazyPRM"``) on the projected
    space with the papers' samplers (:data:`PAPER_SAMPLER`) and no direct local path first (``direct_path = false``).

The departures of ``guided`` from ``paper`` (besides FIND-PATH's planner, space and sampler, and the direct local
path ``direct_path`` tried before it):

``stage2 = "repair"``
    EXPLORE-TRANSITIONGRAPH walks the candidate once: an edge whose path fails gets ``repairs`` other transitions
    drawn; ``recursive`` is Fig. 16's: every transition found for an edge (one per component, ``repairs`` drawn
    besides stage 1's) is tried in turn, recursing along the candidate and backtracking when a branch stops.
``edge_p = "prior"``
    An edge's ``P`` is ``P_INITIAL`` times ``P_FAIL_FACTOR`` per failed connection (a fixed prior,
    :mod:`climb_ompl.climb.edges`); ``time``: ``P`` inversely proportional to the effort spent exploring the edge
    (sec. 3.3.3, after Nielsen & Kavraki 2000), counted in FIND-PATH validity checks so that a seed gives one plan.
``transition_base = "near"``
    FIND-TRANSITION draws the base about the configuration reached; ``holds``: about the nominal posture on the
    holds, anywhere within one limb reach (2L) of them in the wall's plane (Fig. 17 line 2).

``heuristic_weight``
    A* with a height heuristic (steps still needed to reach the goal height) weighted by this factor (default 10).
``transitions = "lazy"``
    FIND-TRANSITION is called when the search pops an edge, not when it expands the node.
``max_edge_failures``
    An edge is dropped after this many failed connections (default 3; 0: never, as in section 3.3.3).
``resume = "farthest"``
    After a failed candidate, the search restarts from the farthest transition reached, and from 2, 4,
    8, ... steps further back when candidates keep failing at the same node.
``elbow_bends = "keep"``
    FIND-TRANSITION keeps the elbow bends of the configuration it starts from (the component of the
    current node) instead of trying every combination.
``grab_reach``
    A grab is proposed only when the new hold's hand target lies within this many limb reaches of the
    limb's first joint where the robot stands (the node's configuration), besides the pair reach of
    Bretl (2006), sec. 4.3 (default 1.5; 0: the pair reach alone).
``keep_shape``
    The height heuristic counts a limb's height only up to where the robot's nominal shape puts it above
    the other limbs, plus a stride (:mod:`climb_ompl.climb.search`): a limb left far behind is moved up first.  The
    limbs' targets are the goal stance in the nominal shape: the lowest limb at the goal's hold height, the
    others above it by their nominal offsets.
``reexpand``
    When EXPLORE-STANCEGRAPH runs out of edges, a node already expanded is reached again at another
    configuration (FIND-TRANSITION from its parent, another base draw) and expanded from there, up to this
    many times per node, nearest the goal first: the frontier where the search stopped, then farther back
    while no node nearer the goal opens an edge (default 2; 0: a node keeps the configuration it was first
    reached at, as in Fig. 16).
``release_lookahead``
    A release is queued with the heuristic of the freed limb's best grab (one step more): the grabs the search
    would propose for it where the robot stands (:mod:`climb_ompl.climb.search`).  The height heuristic counts a free
    limb at its last hold, so every release of a stance looks the same to it; with the look-ahead the limb that
    can climb highest is released first (off: the releases of a stance are tried in limb order).  On by default
    (docs/climb.md, "Settings and their defaults").  It acts only with a height heuristic (``heuristic_weight``
    above 0).

``transition_failures``
    Stage 1 does not call FIND-TRANSITION for an edge out of a stance's component once it failed for the same edge
    (the same stances) from this many other components of that stance (default 2; 0: always called, as in
    Fig. 16; with ``transitions = "eager"`` every edge of an expanded node is called).  A node is a (stance,
    component) pair, and the search meets a stance in several components; how often an edge that failed from
    other components succeeds from one more is in docs/climb.md.
``shortcuts``
    Before stage 2 plans a candidate's paths, a limb's two successive moves (``b -> c``, later ``c -> d``) are
    folded into one (``b -> d``) wherever the steps between are found again, end in the component the candidate
    went on from and use no edge that failed in stage 2 (:mod:`climb_ompl.climb.shortcut`; not in a re-plan's search
    rejoining the old route); off: the candidate as stage 1 found it, as in Fig. 16.

A robot's defaults: a robot spec's ``climb`` section replaces library defaults for that robot, below a search
mode's own settings and the options given to a climb (:meth:`ClimbSettings.for_search`, docs/robots.md).
"""

from __future__ import annotations

import dataclasses
import math
from dataclasses import dataclass
from typing import Any

from climb_ompl import contract
from climb_ompl.errors import PlannerNotFound, QueryError
from climb_ompl.registry import SPACE_NAMES, check_planner, parse_sampler

#: FIND-PATH's sampler in the ``paper`` mode: the papers' samplers mixed (Bretl 2006, sec. 4.2.2-4.3: joint by joint
#: under joint limits, straight elbows; Bretl et al. 2004: free-limb samples nearest the equilibrium boundary).
PAPER_SAMPLER = "joint-by-joint+straight-elbow+free-limb"

#: Search modes and the settings each one fixes (the rest keep their defaults).
SEARCH_MODES: dict[str, dict[str, Any]] = {
    "guided": {},
    "paper": {"heuristic_weight": 0.0, "transitions": "eager", "max_edge_failures": 0, "resume": "queue",
              "elbow_bends": "enumerate", "grab_reach": 0.0, "reexpand": 0, "shortcuts": False,
              "transition_failures": 0, "release_lookahead": False, "stage2": "recursive", "edge_p": "time",
              "transition_base": "holds", "direct_path": False, "planner": "SBL", "space": "projected",
              "sampler": PAPER_SAMPLER, "path_range": 0.2},
}

_CHOICES: dict[str, tuple[str, ...]] = {
    "search": tuple(SEARCH_MODES),
    "transitions": ("lazy", "eager"),
    "resume": ("farthest", "queue"),
    "elbow_bends": ("keep", "enumerate"),
    "stage2": ("repair", "recursive"),
    "edge_p": ("prior", "time"),
    "transition_base": ("near", "holds"),
    "torque": ("final-path", "state", "off"),
}


@dataclass(frozen=True)
class ClimbSettings:
    """Every setting of a climb (defaults: the ``guided`` search).

    Planner of each step (FIND-PATH, Bretl 2006 Fig. 17):
        planner: OMPL planner name (``climb-ompl planners``; default ``SBL``, the single-query bidirectional
        planner with lazy collision checking of Sanchez & Latombe (2003), on the ``tangent_bundle`` space (OMPL's
        atlas after the Tangent Bundle RRT of Kim, Um, Suh & Park (2016): the constraint evaluated lazily as it
        traverses the manifold, no halfspaces between charts) with uniform sampling; the choice is measured in
        docs/planners.md and docs/climb.md).  space: ``projected``, ``atlas`` or ``tangent_bundle`` (default
        ``tangent_bundle``).  sampler: a sampler name of :mod:`climb_ompl.manifold.samplers` (``a+b``
        mixes).
        step_time_limit: CPU-time guard of one FIND-PATH call (this process's), s (default 5): a backstop above
        what the ``path_iterations`` budget costs on the bundled robots, so that the budget ends a call first and
        reproducibly (docs/climb.md).  path_iterations: validity checks per FIND-PATH call (the reproducible
        budget, default 2000; ``None``: time only).  path_retry_growth: when a later
        candidate sequence asks again for a connection whose FIND-PATH failed, it is planned again (another seed)
        with ``path_iterations`` and ``step_time_limit`` multiplied by this factor per failure of its stance-graph
        edge so far (1, the default: the failure is remembered and returned; ANYmal-C's spec sets 2,
        docs/climb.md).  torque: ``final-path``
        (torque limits checked on the finished path, Bretl 2006 sec. 4.3), ``state`` or ``off``.
        max_step: largest joint change between stored waypoints (rad or m; default 0.02).
        path_range: FIND-PATH's planner range as a fraction of the ambient space's largest extent (``None``, the
        default: :data:`climb_ompl.climb.onestep.RANGE_FRACTION`, 0.05; the ``paper`` mode takes OMPL's own 0.2).
        straight_phase: the first this many draws of each FIND-PATH call's sampler are straight-limb configurations
        (Bretl et al. (2004), sec. 3, "initially sampled explicitly"; 0, the default: none;
        :data:`climb_ompl.manifold.samplers.STRAIGHT_PHASE`, 40, is the value measured in docs/papers.md); needs the
        ``projected`` space.  same_bend: FIND-PATH connects only configurations with the elbow bends its start and
        goal share (Bretl et al. (2004), sec. 3; :class:`climb_ompl.manifold.bends.SameBendCheck`; default false).

    FIND-TRANSITION (Bretl 2006 Fig. 17):
        transition_attempts: base positions drawn per call (default 150).  ik_tries: of those, at most this many
        reach the inverse kinematics (default 60; the rest are cut by cheap reach and CoM prefilters).
        com_slack: a draw whose CoM (limbs as before) lies farther than this outside the support region
        is skipped, m (default 0.05).  closure_slack: of the others, only a draw whose CoM lies at most this far
        outside is closed by inverse kinematics and checked, m (default 0.02; ``None``, or more than
        ``com_slack``: every one); the draws between it and ``com_slack`` still count as near the region for
        ``com_patience`` and as tries for ``ik_tries``.  The start finder's FIND-TRANSITION takes the library's
        ``com_slack`` and ``closure_slack``, not a climb's.  transition_wide: when no draw about the configuration
        reached gives a transition, this many more base draws about the nominal posture on the holds, crouched
        towards the wall (0, the default: none; :class:`climb_ompl.climb.transition.TransitionFinder`).
        transition_walk: when the draws find nothing and the CoM must move to the smaller stance's support region,
        a walk of the base towards it of at most this many steps, each chain closed at every step (0, the default:
        none; :meth:`climb_ompl.climb.transition.TransitionFinder.walk`).
        reach_patience, com_patience: a call gives up after
        this many draws without every hold within reach (default 60), or this many draws within reach without the
        CoM within ``com_slack`` of the support region (default 12); 0: it draws all ``transition_attempts``.
        elbow_bends: ``keep`` or ``enumerate`` (see the module docstring).
        clearance: smallest distance between two links of the robot at a transition, m (default 0.01).

    Local path (the direct path tried before FIND-PATH):
        lift: how far the moving hand lifts off the wall, m (default 0.04).  via_points: random via postures of
        the free limb tried when the straight moves collide (default 8).

    Stance-graph search (Bretl 2006 Fig. 16, section 3.3.3):
        search: the mode these settings started from.  heuristic_weight, transitions,
        max_edge_failures, resume: see the module docstring.  stride: height a hand gains per grab in the
        heuristic, m (``None``, the default: half the mean limb reach).  repairs: other transitions of a failed
        edge tried before its ``P`` is lowered (default 3; Fig. 16 line 2, "in each component").  grab_reach: see the
        module docstring (0: off).  keep_shape, reexpand, release_lookahead, shortcuts, transition_failures, stage2,
        edge_p, transition_base: see the module docstring.  direct_path: the direct local path is tried before
        FIND-PATH (default true; false in the ``paper`` mode, whose FIND-PATH is the papers' PRM alone).

    Whole query:
        time_limit: wall-clock guard of the whole climb, s (default 120).  margin: equilibrium margin, m
        (default 0).  cone_edges: edges of the linearised friction cones of the equilibrium check (the support
        region, :data:`climb_ompl.contract.CONE_EDGES`, 8).  torque_cone_edges: edges of the torque check's
        pyramids (default 4; inscribed, so a coarser pyramid accepts fewer contact forces: a margin on the forces;
        what a finer one costs the search is in docs/climb.md).
        force_every: contact forces stored on every n-th waypoint (default 10).  tolerance: hands-on-holds
        tolerance (:data:`climb_ompl.contract.TOLERANCE`; recorded, not a choice).  dynamic_fraction: the share of
        each joint's torque margin (its limit less the largest static torque of the step) that the dynamic torques
        of the timed motion, ``tau(q, v, a) - g(q)``, may take (default 0.1; :mod:`climb_ompl.trajectory`).
    """

    planner: str = "SBL"
    space: str = "tangent_bundle"
    sampler: str = "uniform"
    step_time_limit: float = 5.0
    path_iterations: int | None = 2000
    path_retry_growth: int = 1
    torque: str = "final-path"
    max_step: float = 0.02
    path_range: float | None = None
    straight_phase: int = 0
    same_bend: bool = False
    transition_attempts: int = 150
    ik_tries: int = 60
    com_slack: float = 0.05
    closure_slack: float | None = 0.02
    transition_wide: int = 0
    transition_walk: int = 0
    reach_patience: int = 60
    com_patience: int = 12
    elbow_bends: str = "keep"
    clearance: float = 0.01
    lift: float = 0.04
    via_points: int = 8
    search: str = "guided"
    heuristic_weight: float = 10.0
    transitions: str = "lazy"
    max_edge_failures: int = 3
    resume: str = "farthest"
    stride: float | None = None
    grab_reach: float = 1.5
    keep_shape: bool = True
    reexpand: int = 2
    release_lookahead: bool = True
    shortcuts: bool = True
    transition_failures: int = 2
    repairs: int = 3
    stage2: str = "repair"
    edge_p: str = "prior"
    transition_base: str = "near"
    direct_path: bool = True
    time_limit: float = 120.0
    margin: float = 0.0
    cone_edges: int = contract.CONE_EDGES
    torque_cone_edges: int = 4
    force_every: int = 10
    tolerance: float = contract.TOLERANCE
    dynamic_fraction: float = 0.1

    def __post_init__(self) -> None:
        for name, valid in _CHOICES.items():
            if getattr(self, name) not in valid:
                raise QueryError(f"settings.{name}: {getattr(self, name)!r} is not one of {', '.join(valid)}")
        for f in dataclasses.fields(self):
            v, kind = getattr(self, f.name), str(f.type).split(" | ")
            if kind[0] == "bool":
                if not isinstance(v, bool):
                    raise QueryError(f"settings.{f.name}: {v!r} must be true or false")
                continue
            if kind[0] not in ("int", "float") or (v is None and "None" in kind):
                continue
            if isinstance(v, bool) or not isinstance(v, (int, float)):
                raise QueryError(f"settings.{f.name}: {v!r} must be a number")
            if not math.isfinite(v) or v < 0:
                raise QueryError(f"settings.{f.name}: {v!r} must be a finite number >= 0")
            if kind[0] == "int" and v != int(v):
                raise QueryError(f"settings.{f.name}: {v!r} must be a whole number")
        if self.path_retry_growth < 1:
            raise QueryError(f"settings.path_retry_growth: {self.path_retry_growth!r} must be >= 1")
        for name in ("time_limit", "max_step", "tolerance", "transition_attempts", "ik_tries", "force_every",
                     "dynamic_fraction"):
            if getattr(self, name) <= 0:
                raise QueryError(f"settings.{name}: {getattr(self, name)!r} must be > 0")
        for name in ("cone_edges", "torque_cone_edges"):
            if getattr(self, name) < 3:
                raise QueryError(f"settings.{name}: {getattr(self, name)} must be >= 3")
        check_names(self.planner, self.space, self.sampler)
        if self.straight_phase and self.space != "projected":
            raise QueryError(f"settings.straight_phase: {self.straight_phase} straight-limb draws need the 'projected' "
                             f"space (the {self.space!r} space samples its own charts; --set space=projected)")

    @classmethod
    def for_search(cls, search: str = "guided", robot: Any = None, **overrides: Any) -> ClimbSettings:
        """The settings of a search mode (:data:`SEARCH_MODES`), with ``overrides`` on top.

        ``robot``: a :class:`~climb_ompl.model.robot.RobotModel` whose spec has a ``climb`` section; its settings
        replace
        the defaults, below the mode's own settings and ``overrides`` (defaults < robot < mode < overrides).

        Raises:
            QueryError: an unknown mode or setting, or a bad value.
        """
        if search not in SEARCH_MODES:
            raise QueryError(f"settings.search: {search!r} is not one of {', '.join(SEARCH_MODES)}")
        own = dict(getattr(robot, "climb", None) or {})
        return cls.from_dict({**own, **SEARCH_MODES[search], "search": search, **overrides})

    @classmethod
    def from_plan(cls, d: dict[str, Any], source: str = "settings") -> ClimbSettings:
        """The settings a plan file's ``settings`` were planned with: :meth:`from_dict`, a setting the file predates
        taking the value that means the search as it was before the setting existed (:data:`FORMER_DEFAULTS`), not
        today's default.  A file of this version names every setting and replays to the same plan; an older one
        replays as near its own search as this code comes.

        Raises:
            QueryError: an unknown key or a bad value, naming it.
        """
        return cls.from_dict(as_planned(d), source)

    @classmethod
    def from_dict(cls, d: dict[str, Any], source: str = "settings") -> ClimbSettings:
        """Settings from a dict (a plan file's ``settings``); missing keys take their defaults.

        Raises:
            QueryError: an unknown key or a bad value, naming it.
        """
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(d) - names)
        if unknown:
            raise QueryError(f"{source}: unknown setting(s) {', '.join(unknown)}; valid: {', '.join(sorted(names))}")
        return cls(**d)

    def to_dict(self) -> dict[str, Any]:
        """Every setting, as stored in the plan file."""
        return dataclasses.asdict(self)

    def replace(self, **changes: Any) -> ClimbSettings:
        """A copy with ``changes`` (validated)."""
        return self.from_dict({**self.to_dict(), **changes})


#: Settings whose default is not what a plan file written before they existed was planned with, and the value that
#: means the search without them (:meth:`ClimbSettings.from_plan`): the release look-ahead came as an option (off) and
#: later became the default; the others came on (the pair reach alone before ``grab_reach``, no cap of a limb's
#: height before ``keep_shape``, no re-expansion, no shortcuts, every edge called from every component, every draw
#: within ``com_slack`` closed before ``closure_slack``).
FORMER_DEFAULTS: dict[str, Any] = {"release_lookahead": False, "grab_reach": 0.0, "keep_shape": False, "reexpand": 0,
                                   "shortcuts": False, "transition_failures": 0, "closure_slack": None}


def as_planned(settings: dict[str, Any]) -> dict[str, Any]:
    """A plan file's ``settings`` with every setting the file predates at its :data:`FORMER_DEFAULTS` value: what the
    plan was made with, as far as this code knows (:meth:`ClimbSettings.from_plan` reads them; the hints after a
    replay or a re-plan are given them)."""
    return {**FORMER_DEFAULTS, **settings}

#: Settings that a robot spec's ``climb`` section and ``climb-ompl plan --set`` do not give: the search mode is
#: chosen per climb (``--search``), the tolerance is recorded, not a choice.
NOT_GIVEN: tuple[str, ...] = ("search", "tolerance")

#: Largest seed (OMPL seeds its generator with a 32-bit unsigned integer); seeds are integers from 0 to this.
SEED_MAX = 2**32 - 1


def unknown_setting(key: str) -> str | None:
    """``unknown setting; valid: ...`` (the names one may give, :data:`NOT_GIVEN` aside) when ``key`` is not a
    setting, else ``None`` (also for the names of :data:`NOT_GIVEN`, which their callers refuse in their own
    words)."""
    names = sorted(f.name for f in dataclasses.fields(ClimbSettings))
    if key in names:
        return None
    return f"unknown setting; valid: {', '.join(n for n in names if n not in NOT_GIVEN)}"


def setting_error(exc: QueryError) -> tuple[str, str]:
    """The setting a :class:`ClimbSettings` error names (``settings.<name>: <reason>``) and its reason (``""`` and
    the whole message when it names none)."""
    name, _, reason = str(exc).partition(": ")
    return (name.removeprefix("settings."), reason) if name.startswith("settings.") else ("", str(exc))


def check_names(planner: str, space: str, sampler: str) -> None:
    """Raise :class:`~climb_ompl.errors.PlannerNotFound` for an unknown planner, space or sampler name, and
    :class:`~climb_ompl.errors.QueryError` for a custom sampler on a space other than ``projected`` (the atlas
    and tangent-bundle spaces sample their own charts)."""
    check_planner(planner)  # an excluded planner says why
    if space not in SPACE_NAMES:
        raise PlannerNotFound("constrained space", space, SPACE_NAMES)
    if parse_sampler(sampler) != ("uniform",) and space != "projected":
        raise QueryError(f"custom sampler {sampler!r} needs the 'projected' space: the {space!r} space samples "
                         "its own charts (use sampler='uniform', or space='projected')")


__all__ = ["ClimbSettings", "FORMER_DEFAULTS", "NOT_GIVEN", "PAPER_SAMPLER", "SEARCH_MODES", "SEED_MAX", "as_planned",
           "check_names", "setting_error", "unknown_setting"]
