"""Why a climb ended without a plan: the frontier of the stance-graph search and the checks that stopped it.

When EXPLORE-STANCEGRAPH (Bretl 2006, Fig. 16) is exhausted or the time budget is spent, the stances explored
nearest the goal (the *frontier*: smallest heuristic of the search, :class:`climb_ompl.climb.heuristic.GoalHeuristic`,
highest hold first on ties) are where the climb stopped.  For the best few, :func:`diagnose_frontier` lists
the edges out of them that would have brought the robot nearer the goal and what stopped each one:

* **reach**: the new hold lies beyond the pair reach of the grabbing limb and a limb on a hold (the
  necessary condition of Bretl (2006), sec. 4.3, :func:`climb_ompl.model.reach.pair_reach`);
* **equilibrium**: releasing the limb leaves a stance with an empty support region (Bretl 2006, appendix B);
* **reach from where the robot stood**: the new hold lies beyond ``grab_reach`` limb reaches of the limb's
  first joint at the configuration the search reached (the prefilter of
  :class:`climb_ompl.climb.heuristic.EdgeProposals`);
* **FIND-TRANSITION found no transition**: the stance after the step is then diagnosed check by check by
  :func:`climb_ompl.climb.start.diagnose_stance` (reach or inverse kinematics, equilibrium with the CoM's distance
  to the region, joint limits, collision naming the links, torque limits), the same diagnosis as the start
  finder's;
* **no path**: FIND-PATH found no path to the transition (Bretl 2006, sec. 3.3.3: the edge's probability
  was lowered).

Edges not tried before the budget ran out are counted.  For a height goal above every hold of the terrain,
:func:`goal_beyond_terrain` says so without any search.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol

import numpy as np

from climb_ompl.climb.start import diagnose_stance
from climb_ompl.manifold.stance import Stance, limb_hold_targets
from climb_ompl.model.reach import shoulders

if TYPE_CHECKING:
    from climb_ompl.climb.edges import EdgeBook, TransitionCache
    from climb_ompl.climb.heuristic import EdgeProposals, GoalHeuristic
    from climb_ompl.climb.nodes import NodeKey
    from climb_ompl.manifold.feasibility import Feasibility
    from climb_ompl.model.terrain import Terrain
    from climb_ompl.settings import ClimbSettings


class SearchRecord(Protocol):
    """What the frontier diagnosis reads of a search that found no plan
    (:class:`climb_ompl.climb.search.StanceGraphSearch` is one).

    Attributes:
        robot, terrain, settings: the query's robot model, terrain and climb settings.
        feas: its feasibility tests (support regions, stance diagnosis).
        limbs: the robot's limb names.
        explored: the ``(stance, component)`` keys of the nodes explored.
        exhausted: the search ended with no edge left to try (else its budget ran out).
        heuristic: the goal heuristic, ``heuristic(stance, last)`` (estimated steps).
        proposals: its edge proposals (``pair_reach``, m, by limb pair; ``beyond``: grabs ``grab_reach`` left out).
        edges: its edges' stage-2 failures (``fails``).
        transitions: its FIND-TRANSITION results by edge (``by_edge``: a configuration, ``None`` when none found).
    """

    robot: Any
    terrain: Terrain
    settings: ClimbSettings
    feas: Feasibility
    limbs: list[str]
    explored: set[NodeKey]
    exhausted: bool
    heuristic: GoalHeuristic
    proposals: EdgeProposals
    edges: EdgeBook
    transitions: TransitionCache

    def frontier(self) -> list[Any]:
        """The stances explored, nearest the goal first."""
        ...

#: How the reason of a climb whose goal lies beyond a gap from its start begins (:func:`goal_beyond_reach`).
CUT_OFF = "the goal cannot be met from this start"
#: Frontier stances diagnosed, and failed edges shown per stance.
FRONTIER_STANCES = 3
EDGES_PER_STANCE = 2
#: Frontier stances looked at, nearest the goal first, for the :data:`FRONTIER_STANCES` listed.
SCANNED = 20


@dataclass
class EdgeFailure:
    """An edge out of a frontier stance that would have brought the robot nearer the goal, and why it failed.

    Attributes:
        action, limb, hold: the step (``grab`` or ``release`` of ``hold`` by ``limb``, ``release L, then grab``
            after a release that was taken); ``reach`` (no limb nor hold) when every hold above is out of reach.
        steps_to_goal: the search's height heuristic after the step.
        reasons: one line per failing check (``"reach: ..."``, ``"equilibrium: ..."``, ``"collision: ..."``,
            ``"path: ..."``, ...).
    """

    action: str
    limb: str
    hold: str
    steps_to_goal: float
    reasons: list[str]

    @property
    def checks(self) -> list[str]:
        """The names of the failing checks, in :attr:`reasons` order."""
        return [r.split(":", 1)[0] for r in self.reasons]

    def to_dict(self) -> dict[str, Any]:
        """The failure as a JSON-able dict."""
        return {"action": self.action, "limb": self.limb, "hold": self.hold,
                "steps_to_goal": round(self.steps_to_goal, 3), "reasons": list(self.reasons)}


@dataclass
class FrontierStance:
    """A stance of the frontier and the edges out of it that failed.

    Attributes:
        stance: ``{limb: hold}``.
        height: its highest hold's height along minus gravity, metres.
        lowest: its lowest hold's height, metres (a height goal needs every contact hold near it, not one).
        steps_to_goal: the search's height heuristic at this stance.
        failures: the failed edges nearest the goal first (at most :data:`EDGES_PER_STANCE`).
        untried: edges towards the goal not tried when the search stopped.
        exhausted: the search ended with no edge left to try (else its budget ran out): the untried edges were
            never proposed from here.
    """

    stance: dict[str, str]
    height: float
    steps_to_goal: float
    failures: list[EdgeFailure] = field(default_factory=list)
    untried: int = 0
    exhausted: bool = False
    lowest: float | None = None

    def to_dict(self) -> dict[str, Any]:
        """The frontier stance as a JSON-able dict."""
        low = {} if self.lowest is None else {"lowest": round(self.lowest, 4)}
        return {"stance": dict(sorted(self.stance.items())), "height": round(self.height, 4), **low,
                "steps_to_goal": round(self.steps_to_goal, 3), "failures": [f.to_dict() for f in self.failures],
                "untried": self.untried}

    def __str__(self) -> str:
        if self.lowest is None:
            held = f"highest hold at {self.height:.3f} m"
        elif f"{self.lowest:.3f}" == f"{self.height:.3f}":
            held = f"{'holds' if len(self.stance) > 1 else 'hold'} at {self.height:.3f} m"
        else:
            held = f"holds {self.lowest:.3f} to {self.height:.3f} m high"
        lines = [f"{Stance(self.stance)} ({held}, about {self.steps_to_goal:.1f} steps from the goal by the search's "
                 "estimate):"]
        for f in self.failures:
            if f.action == "reach":
                lines += [f"  {r}" for r in f.reasons]
                continue
            lines.append(f"  release {f.limb} from {f.hold}:" if f.action == "release" else
                         f"  {f.action} {f.limb} -> {f.hold}:")
            lines += [f"    {r}" for r in f.reasons]
        if self.untried:
            lines.append(f"  {self.untried} step(s) towards the goal " + (
                "never proposed from here (the search's prefilters left them out, and it ran out of steps to try)"
                if self.exhausted else "not tried before the search stopped"))
        if not self.failures and not self.untried:
            lines.append("  no step from here brings the robot nearer the goal")
        return "\n".join(lines)


def goal_beyond_terrain(goal: Any, terrain: Any, reach: float) -> str | None:
    """For a height goal that no stance of the terrain can meet (every contact hold must be at or above
    ``height - reach``): why, naming the highest hold; else ``None``."""
    if getattr(goal, "type", None) != "height" or not terrain.holds:
        return None
    need = float(goal.height) - float(reach)
    top = max(terrain.holds, key=lambda h: terrain.height(h))
    if terrain.height(top) >= need:
        return None
    return (f"the goal height {float(goal.height):.3f} m needs every contact hold at or above {need:.3f} m "
            f"(goal height minus the largest limb reach {float(reach):.3f} m), but the highest hold of "
            f"{terrain.name!r}, {top.id}, is at {terrain.height(top):.3f} m (heights along minus gravity)")


def goal_beyond_reach(goal: Any, terrain: Any, start: Any, pair: dict[tuple[str, str], float],
                      reach: float) -> str | None:
    """For a goal no climb from the holds of stance ``start`` (``{limb: hold}``) can meet: why, naming the highest
    hold within reach and the nearest hold the goal needs; else ``None``.

    The holds within reach are those joined to the start's by hops of at most :func:`climb_ompl.model.reach.hop_reach`
    (:func:`climb_ompl.model.reach.reachable_holds`, a necessary condition the search's own prefilter enforces): a
    gap of the wall wider than any two limbs can span is proved at once, where the search would spend its budget
    on the holds below it.  ``pair``: :func:`climb_ompl.model.reach.pair_reach`; ``reach``: the largest limb reach (a
    height goal's allowance, :class:`climb_ompl.climb.goal.Goal`).
    """
    from scipy.spatial import cKDTree

    from climb_ompl.model.reach import hop_reach, reachable_holds

    hop = hop_reach(pair)
    holds = list(terrain.holds)
    if hop <= 0.0 or not holds or not start:
        return None
    ok = reachable_holds(terrain, list(dict(start).values()), hop)
    index = terrain.hold_index
    if goal.type == "height":
        need = [i for i, h in enumerate(holds) if terrain.height(h) >= float(goal.height) - float(reach)]
        if not need or ok[need].any():
            return None
    else:
        sets = [[p[1] for p in x] for x in goal.stances] if goal.type == "stances" else \
            [[goal.hold]] if goal.type == "hold" else [list(dict(goal.stance or ()).values())]
        sets = [x for x in sets if x]
        if not sets or any(ok[[index[h] for h in x]].all() for x in sets):
            return None
        need = sorted({index[h] for x in sets for h in x if not ok[index[h]]})
    within = np.flatnonzero(ok)
    top = max(within.tolist(), key=lambda i: terrain.height(holds[i]))
    # the gap named: for a height goal, the nearest hold out of reach above the highest within reach (else the
    # nearest the goal needs); for a goal of holds, the nearest of the goal's holds out of reach
    above = [i for i in np.flatnonzero(~ok).tolist() if terrain.height(holds[i]) > terrain.height(holds[top])]
    beyond = np.asarray(above if goal.type == "height" and above else need, dtype=int)
    d, j = cKDTree(terrain.positions[within]).query(terrain.positions[beyond])
    k = int(np.argmin(d))
    far, near = holds[int(beyond[k])], holds[int(within[int(j[k])])]
    what = (f"every contact hold at or above {float(goal.height) - float(reach):.3f} m" if goal.type == "height"
            else f"hold {holds[need[0]].id}" if len(need) == 1 else "holds " + ", ".join(holds[i].id for i in need))
    which = "the nearest hold above them" if goal.type == "height" and above else "the nearest the goal needs"
    return (f"no climb from the start stance can reach {what}: hop by hop, each grab at most {hop:.3f} m from a "
            "hold already touched (the largest distance two limbs span: their shoulders' distance plus both "
            f"reaches and contact radii), it reaches {len(within)} of the terrain's {len(holds)} holds, the highest "
            f"{holds[top].id} at {terrain.height(holds[top]):.3f} m; {which}, {far.id} at "
            f"{terrain.height(far):.3f} m, is {float(d[k]):.3f} m from {near.id} (a gap wider than the robot can "
            "span)")


def _stance_height(search: SearchRecord, stance: Any) -> float:
    return max(search.terrain.height(h) for h in stance.hold_ids)


def _release_block(search: SearchRecord, stance: Any, limb: str) -> list[str] | None:
    """Why releasing ``limb`` is not proposed (an empty support region after it), or ``None``."""
    if search.feas.region_ok(stance.without(limb)):
        return None
    return [f"equilibrium: with {limb} released no contact forces within the friction cones of the remaining "
            "holds balance gravity (empty support region)"]


def _reach_block(search: SearchRecord, stance: Any, limb: str, hold: Any) -> tuple[float, str] | None:
    """Why grabbing ``hold`` with ``limb`` is not proposed (the pair-reach filter): ``(excess, line)``."""
    far = []
    for k, h in stance.pairs:
        c = search.terrain.hold(h)
        d, r = float(np.linalg.norm(hold.p - c.p)), float(search.proposals.pair_reach[(limb, k)])
        if d > r:
            far.append((d - r, f"reach: hold {hold.id} is {d:.3f} m from hold {c.id} of limb {k}, beyond the two "
                               f"limbs' reach ({r:.3f} m: their shoulders' distance plus both reaches)"))
    return max(far) if far else None


#: How a failure's reason begins when the ``grab_reach`` prefilter, not a check, kept the grab from being tried.
NOT_PROPOSED = "reach: not proposed"


def only_beyond_grab_reach(diagnosis: list[dict[str, Any]]) -> bool:
    """Whether every failed step listed in a frontier diagnosis (:meth:`FrontierStance.to_dict` dicts) is a grab
    the ``grab_reach`` prefilter did not propose, and no step towards the goal was left untried: the search could
    not go on from there however long it ran."""
    reasons = [r for d in diagnosis for f in d.get("failures", ()) for r in f.get("reasons", ())]
    return bool(reasons) and all(str(r).startswith(NOT_PROPOSED) for r in reasons) and \
        not any(d.get("untried") for d in diagnosis)


def _status(search: SearchRecord, keys: list[Any], nxt: Any) -> str | list[str]:
    """What became of the edge from the nodes ``keys`` to ``nxt``: ``"taken"``, ``"untried"``, ``"no
    transition"``, or the reasons of a path failure or of the ``grab_reach`` prefilter."""
    fails = sum(search.edges.fails.get((k, nxt), 0) for k in keys)
    tried = [k for k in keys if (k, nxt) in search.transitions.by_edge]
    if any(search.transitions.by_edge[(k, nxt)] is not None for k in tried) and not fails:
        return "taken"
    if fails:
        return [f"path: FIND-PATH found no path to a transition onto this stance ({fails} failure(s))"]
    if tried:
        return "no transition"
    far = [search.proposals.beyond[(k, nxt)] for k in keys if (k, nxt) in search.proposals.beyond]
    if far:
        d, lim = min(far)
        return [f"{NOT_PROPOSED}, the hold's hand target is {d:.3f} m from the limb's first joint where the "
                f"robot stood, beyond {lim:.3f} m ({search.settings.grab_reach:g} times the limb's reach: the "
                "grab_reach setting)"]
    return "untried"


def _standing(search: SearchRecord, stance: Any, keys_by_stance: dict[Any, list[Any]]) -> np.ndarray | None:
    """A configuration the search reached at ``stance`` (a transition into it or out of one of its nodes), or
    ``None``."""
    keys = set(keys_by_stance.get(stance, []))
    for (key, nxt), q in search.transitions.by_edge.items():
        if q is not None and (nxt == stance or key in keys):
            return np.asarray(q, dtype=float)
    return None


def diagnose_frontier(search: SearchRecord, stances: int = FRONTIER_STANCES,
                      edges: int = EDGES_PER_STANCE) -> list[FrontierStance]:
    """The frontier of a search that found no plan, and why its steps towards the goal failed.

    A step from a stance with every limb on a hold is a release followed by a grab with the same limb: when
    the release was taken, the grabs after it are examined.  Grabs count when they bring the robot nearer the
    goal (a smaller height heuristic than the frontier stance's).  When every hold above the frontier
    stance's highest hold is beyond the pair reach of a free limb, the nearest of them is named.

    The stance nearest the goal is always listed; after it, stances from which no step towards the goal was
    tried (when the budget ran out they are the ones just reached) are left out for the next ones, among the
    :data:`SCANNED` nearest, whose failures say why the climb did not go on.

    Args:
        search: the search (a :class:`SearchRecord`, such as :class:`~climb_ompl.climb.search.StanceGraphSearch`)
            after its ``run`` returned no plan.
        stances: number of frontier stances diagnosed (nearest the goal first).
        edges: failed steps shown per stance (nearest the goal first), besides the reach line.
    """
    keys_by_stance: dict[Any, list[Any]] = {}
    for key in search.explored:
        keys_by_stance.setdefault(key[0], []).append(key)
    out: list[FrontierStance] = []
    for sigma in search.frontier()[:SCANNED]:
        fs = _diagnose_stance(search, sigma, keys_by_stance, edges)
        if out and not fs.failures:  # nothing tried towards the goal from here: says no more than the first
            continue
        out.append(fs)
        if len(out) == stances:
            break
    return out


def _diagnose_stance(search: SearchRecord, sigma: Any, keys_by_stance: dict[Any, list[Any]],
                     edges: int) -> FrontierStance:
    """One frontier stance of :func:`diagnose_frontier`: its failed steps towards the goal and the untried ones."""
    from climb_ompl.manifold.stance import Stance

    h0, top = search.heuristic(sigma, ()), _stance_height(search, sigma)
    fs = FrontierStance(dict(sigma), top, h0, exhausted=bool(search.exhausted),
                        lowest=min(search.terrain.height(h) for h in sigma.hold_ids))
    # (sort key, heuristic, step, limb, hold, next stance, touching, why); the sort key puts first the steps
    # whose hold lies within the limb's reach from where the robot stood (their failure says more)
    cands: list[tuple[tuple[int, float, float], float, str, str, str, Any, Any, str | list[str]]] = []
    froms: list[tuple[Any, list[str], str | None]] = []  # (stance, free limbs, limb released before)
    free = [lb for lb in search.limbs if lb not in sigma]
    if free:
        froms.append((sigma, free, None))
    else:
        for limb in sigma.limbs:
            nxt = sigma.without(limb)
            why: str | list[str] | None = _release_block(search, sigma, limb)
            why = why if why is not None else _status(search, keys_by_stance[sigma], nxt)
            if why == "taken":
                froms.append((nxt, [limb], limb))
            elif why == "untried":
                fs.untried += 1
            else:
                cands.append(((0, h0 + 1.0, 0.0), h0 + 1.0, "release", limb, sigma[limb], nxt, {limb: sigma[limb]},
                              why))
    above, reach_lines = 0, []
    for st, limbs, released in froms:
        keys = keys_by_stance.get(st, [])
        ref = _standing(search, st, keys_by_stance)
        sh = shoulders(search.robot, ref) if ref is not None else None
        for limb in limbs:
            targets = limb_hold_targets(search.robot, search.terrain, limb)
            last = ((limb, sigma[limb]),) if released else ()
            for hi, hold in enumerate(search.terrain.holds):
                if hold.id in st.hold_ids or (released and hold.id == sigma[limb]):
                    continue
                nxt = st.with_hold(limb, hold.id)
                h = search.heuristic(nxt, last)
                up = search.terrain.height(hold) > top
                blocked = _reach_block(search, st, limb, hold)
                if blocked is not None:
                    if up:
                        reach_lines.append(blocked)
                    continue
                above += up
                if h >= h0:
                    continue  # not towards the goal
                why = _status(search, keys, nxt)
                if why == "untried":
                    fs.untried += 1
                elif why != "taken":
                    label = f"release {released}, then grab" if released else "grab"
                    excess = 0.0 if sh is None else float(
                        np.linalg.norm(targets[hi] - sh[limb])
                        - search.robot.limb(limb).reach)
                    # equal estimates (a row of holds): the hold nearest the limb's first joint first, the
                    # short step whose failure says most (not the first hold id in string order)
                    key = (0, h, excess) if excess <= 0 else (1, excess, 0.0)
                    cands.append((key, h, label, limb, hold.id, nxt, None, why))
    for _, h, action, limb, hold, nxt, touching, why in sorted(cands, key=lambda c: c[:5])[:edges]:
        if why == "no transition":  # the stance after the step, check by check, from where the robot stood
            ref = _standing(search, sigma if touching else nxt.without(limb), keys_by_stance)
            d = diagnose_stance(search.robot, search.terrain, Stance(dict(nxt)), search.feas, touching=touching,
                                **({} if ref is None else {"near": ref, "where": "the configuration reached"}))
            where = "at the nominal stand-off" if ref is None else "from the configuration reached"
            why = [f"transition: FIND-TRANSITION found no feasible transition ({len(nxt)} holds after the step)"] \
                + (d.reasons or [f"no single check fails on its own {where}: the draws missed a configuration "
                                 "passing them all at once, which more draws may find (--set transition_wide=200, "
                                 "--set transition_walk=100)"])
        fs.failures.append(EdgeFailure(action, limb, hold, h, list(why)))
    if reach_lines and not above:  # the blocking cause first
        fs.failures.insert(0, EdgeFailure("reach", "", "", h0, [
            "reach: every hold above this stance is beyond the pair reach of the free limb; the nearest: "
            + min(reach_lines)[1].split(": ", 1)[1]]))
    return fs


def explain(search: SearchRecord, stances: int = FRONTIER_STANCES) -> tuple[str, list[FrontierStance]]:
    """The diagnosis of :func:`diagnose_frontier` as text (one block per frontier stance), and the stances."""
    diags = diagnose_frontier(search, stances)
    if not diags:
        return "", diags
    return ("the climb stopped at these stances (nearest the goal first):\n" + "\n".join(str(d) for d in diags),
            diags)


__all__ = ["CUT_OFF", "EdgeFailure", "FrontierStance", "SearchRecord", "goal_beyond_terrain", "goal_beyond_reach",
           "diagnose_frontier",
           "explain",
           "FRONTIER_STANCES", "EDGES_PER_STANCE", "SCANNED"]
