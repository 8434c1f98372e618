"""The start finder: candidate start stances among the lowest holds, ranked, tried in turn, and why none works.

A climb starts from a stance with a feasible configuration (Bretl 2006, sec. 3.3: the query gives the start
stance and configuration).  When the user gives none, :func:`find_start` builds one:

1. **Candidates** (:func:`candidate_stances`): the robot's nominal hand layout, shrunk or spread about its
   centroid, is placed in the wall's plane just above the lowest holds, at the middle of the wall first
   and then to either side and a little higher; each limb takes the nearest free hold
   (:func:`lowest_stance`).  The wall's plane is spanned by the direction across the wall (the wall normal
   crossed with "up") and "up" made parallel to the wall, where up is minus gravity
   (:func:`wall_axes`): a slab, an overhang or a ramp is laid out along its own slope.
2. **Ranking**: at the nominal stand-off (the nominal posture with its base moved onto the holds,
   :func:`climb_ompl.climb.transition.nominal_near`) the CoM's signed distance to the stance's support region
   (Bretl 2006, appendix B) scores a candidate.  Candidates whose region holds the CoM come first, in the
   order above (middle bottom, nominal shape first); the others follow, nearest the region first.
3. **Trial**: FIND-TRANSITION on the stance alone (:class:`climb_ompl.climb.transition.TransitionFinder`,
   :func:`start_configuration`; when the CoM at the nominal stand-off lies outside the region, also from the
   configuration of :func:`~climb_ompl.manifold.closure.closest_com` nearest the region's centre) until one gives a
   configuration from which some limb
   can let go of its hold (:func:`releasable`: a climb's first step is a release); when no candidate tried
   has one, the first configuration found.
4. **Diagnosis** (:func:`diagnose_stance`): when none does, the best few candidates say why, check by check:
   reach (which limb cannot reach which hold, its distance against the limb's reach), equilibrium (the
   CoM's distance to the support region, or an empty region), joint limits (naming the coordinates),
   collision (naming the colliding links, :meth:`RobotModel.collisions`) and torque limits, at the
   configuration that closes every chain from the nominal stand-off, plus the reasons the finder's draws
   were rejected.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from climb_ompl.climb.transition import TransitionFinder, base_beyond_bounds, nominal_near
from climb_ompl.manifold.closure import DrawClose, closest_com
from climb_ompl.manifold.feasibility import Feasibility
from climb_ompl.manifold.stance import Stance, TorqueCheck, limb_hold_targets
from climb_ompl.model.terrain import Terrain
from climb_ompl.model.wall_frame import wall_normal

#: Scales of the nominal hand layout tried at each place, in order.
SCALES: tuple[float, ...] = (0.7, 0.6, 0.8, 0.5, 0.9, 1.0)

#: Stretches of the layout along the wall's slope added by the ``release`` ranking (:func:`candidate_stances`).
STRETCHES: tuple[float, ...] = (1.25, 1.5)

#: Stand-offs of the CoM at which the ``release`` ranking scores a candidate, as fractions of the nominal posture's
#: (for a robot whose base can move towards the wall; see :func:`release_score`).
CROUCH: tuple[float, ...] = (1.0, 0.8, 0.6, 0.4)

#: Draws of FIND-TRANSITION per candidate (:func:`start_configuration`).
ATTEMPTS: int = 400


@dataclass(frozen=True)
class Candidate:
    """A candidate start stance.

    Attributes:
        stance: ``{limb: hold}``.
        score: signed distance of the CoM at the nominal stand-off to the stance's support region, metres
            (positive inside, ``-inf`` for an empty region; 0 for a robot without equilibrium condition).
        order: its place in the layout order (middle bottom, nominal shape first).
    """

    stance: dict[str, str]
    score: float
    order: int


@dataclass
class StartDiagnosis:
    """Why a candidate stance gave no start configuration.

    Attributes:
        stance: the candidate.
        score: its :attr:`Candidate.score`.
        reasons: one line per failing check (``"reach: ..."``, ``"equilibrium: ..."``, ``"joint limits: ..."``,
            ``"collision: ..."``, ``"torque limits: ..."``).
        rejections: FIND-TRANSITION's draws rejected, by reason (``ik`` or a check's name).
    """

    stance: dict[str, str]
    score: float
    reasons: list[str]
    rejections: dict[str, int] = field(default_factory=dict)

    @property
    def checks(self) -> list[str]:
        """The names of the failing checks, in :attr:`reasons` order."""
        return [r.split(":", 1)[0] for r in self.reasons]

    def __str__(self) -> str:
        st = "{" + ", ".join(f"{k}:{v}" for k, v in sorted(self.stance.items())) + "}"
        rej = ", ".join(f"{k} {v}" for k, v in sorted(self.rejections.items(), key=lambda x: -x[1]))
        lines = [f"{st}:", *(f"  {r}" for r in self.reasons or ["no single check fails at the nominal stand-off"])]
        if rej:
            lines.append(f"  draws rejected: {rej}")
        return "\n".join(lines)


@dataclass
class StartResult:
    """Outcome of :func:`find_start`.

    Attributes:
        stance: the start stance found, or ``None``.
        q: its configuration, or ``None``.
        tried: the candidates tried, in order.
        candidates: number of distinct candidate stances.
        diagnoses: for the best few candidates when none worked, why.
        spent: the time budget (seconds) that stopped the search before every candidate was tried, else ``None``.
    """

    stance: dict[str, str] | None
    q: np.ndarray | None
    tried: list[Candidate]
    candidates: int
    diagnoses: list[StartDiagnosis] = field(default_factory=list)
    spent: float | None = None

    @property
    def found(self) -> bool:
        """Whether a start stance and configuration were found."""
        return self.stance is not None

    def explain(self, robot: str = "the robot", terrain: str = "the terrain") -> str:
        """Why no start was found, for the best candidates (multi-line text); empty when one was found."""
        if self.found:
            return ""
        head = (f"no feasible start stance for {robot} near the bottom of {terrain} "
                f"({len(self.tried)} of {self.candidates} candidate stances tried")
        head += ")" if self.spent is None else (f", the start finder's budget of {self.spent:g} s spent: a larger "
                                                "time limit tries more)")
        if not self.diagnoses:
            return head + ": the terrain has too few holds for the robot's limbs"
        return head + "; the best candidates fail on:\n" + "\n".join(str(d) for d in self.diagnoses)

    def advice(self, robot: Any = None) -> str:
        """What a user can do about a start not found (one line; empty when one was found): give a start stance,
        unless every candidate diagnosed fails on equilibrium, where another stance of those holds is likely to
        fail the same check; first, given the ``robot``, a nominal posture facing away from the wall
        (:func:`facing_away`), which no stance can mend."""
        if self.found:
            return ""
        away = facing_away(robot) if robot is not None else None
        if away:
            return f"the spec's {away}"
        if self.diagnoses and all("equilibrium" in d.checks for d in self.diagnoses):
            return ("every candidate diagnosed fails on equilibrium: the friction cones of these holds do not "
                    "hold the robot's weight in any posture found near the bottom (a stance given with --start is "
                    "checked the same way); holds whose normals lean further up, more friction or a wall tilted back "
                    "make stances feasible")
        return "give a start stance with --start"


#: In the nominal posture of a robot with a spatial base, the hands' mean distance to the wall should be at least
#: this much (metres) less than the CoM's (the bundled robots: 0.07 to 0.39 m less).
WALL_SIDE = 0.02


def facing_away(robot: Any) -> str | None:
    """A sentence when the nominal posture of a robot with a spatial base does not have its hands between the body
    and the wall (the plane ``y = 0`` climbed from ``+y``, the frame every terrain is turned into): then every hold
    is out of reach from the postures the start finder draws about it.  ``None`` otherwise."""
    if (robot.spec.get("base") or {}).get("type") != "spatial" or not robot.limbs:
        return None
    hands = np.array([robot.hand_position(robot.nominal_q, lb.name) for lb in robot.limbs])
    com = np.asarray(robot.com(robot.nominal_q), dtype=float)
    if float(np.mean(hands[:, 1])) <= float(com[1]) - WALL_SIDE:
        return None
    return (f"nominal posture does not have the hands between the body and the wall (the plane y = 0, climbed on "
            f"its +y side): their mean y is {np.mean(hands[:, 1]):.3f} m, the CoM's {com[1]:.3f} m; the base's "
            "reference orientation (base.reference_rpy) may turn the belly away from the wall, and every hold "
            "would then be out of reach")


# ---- layout --------------------------------------------------------------------------------------------
def wall_axes(terrain: Terrain) -> tuple[np.ndarray, np.ndarray]:
    """``(across, up_wall)``: unit vectors spanning the wall's plane.

    ``across`` is the wall normal crossed with up (minus gravity), ``up_wall`` is up made parallel to the
    wall (``across x normal``).  A 2-D terrain's plane is x-z (normal ``y``).  On a floor (gravity along the
    normal) ``across`` is any direction in the plane.
    """
    n = np.array([0.0, 1.0, 0.0]) if terrain.dim == 2 else np.asarray(wall_normal(terrain), dtype=float)
    a = np.cross(n, terrain.up)
    if np.linalg.norm(a) < 1e-9:
        a = np.cross(n, [1.0, 0.0, 0.0]) if abs(n[0]) < 0.9 else np.cross(n, [0.0, 0.0, 1.0])
    a = a / np.linalg.norm(a)
    v = np.cross(a, n)
    return a, v / np.linalg.norm(v)


def _layout(robot: Any, scale: float) -> np.ndarray:
    """The nominal hand positions shrunk by ``scale`` about their centroid, ``(L, 3)``."""
    hands = np.asarray(robot.hand_positions(np.asarray(robot.nominal_q, dtype=float)), dtype=float)
    return hands.mean(axis=0) + scale * (hands - hands.mean(axis=0))


def lowest_stance(robot: Any, terrain: Terrain, scale: float = 0.7, *, centre: float | None = None,
                  lift: float = 0.05, stretch: float = 1.0) -> dict[str, str]:
    """A start stance near the bottom of the wall, shaped like the nominal pose.

    The nominal hand layout, shrunk by ``scale`` about its centroid, is placed in the wall's plane
    (:func:`wall_axes`) at ``centre`` across the wall (default: the median hold) with its lowest hand
    ``lift`` metres above the lowest hold there; each limb (in the robot's order) takes the free hold whose
    hand target (:func:`~climb_ompl.manifold.stance.limb_hold_targets`) is nearest in the wall's plane.  ``stretch``
    lengthens the layout along the wall's slope (about its centroid) by that factor.
    """
    a, v = wall_axes(terrain)
    hands = _layout(robot, scale)
    P = terrain.positions
    pu, pv, hu, hv = P @ a, P @ v, hands @ a, hands @ v
    if stretch != 1.0:
        hv = hv.mean() + float(stretch) * (hv - hv.mean())
    xc = float(np.median(pu)) if centre is None else float(centre)
    near_x = np.abs(pu - xc) <= np.ptp(hu) + 1e-9
    zlow = float(pv[near_x].min()) if near_x.any() else float(pv.min())
    su, sv = xc - hu.mean(), zlow - hv.min() + lift
    out: dict[str, str] = {}
    used: set[int] = set()
    for i, lb in enumerate(robot.limbs):
        T = limb_hold_targets(robot, terrain, lb.name)  # where this hand frame goes on each hold
        tu, tv = T @ a, T @ v
        d = np.linalg.norm(np.stack([tu - (hu[i] + su), tv - (hv[i] + sv)], axis=1), axis=1)
        for j in np.argsort(d, kind="stable"):
            if int(j) not in used:
                used.add(int(j))
                out[lb.name] = terrain.holds[int(j)].id
                break
    return out


def _score(robot: Any, terrain: Terrain, feas: Feasibility, stance: Stance) -> float:
    """Signed distance of the CoM at the nominal stand-off to the support region of ``stance``, metres."""
    if not robot.equilibrium:
        return 0.0
    region = feas.region(stance)
    if region.is_empty:
        return -float("inf")
    return float(region.margin(robot.com(nominal_near(robot, terrain, stance))))


def release_score(robot: Any, terrain: Terrain, feas: Feasibility, stance: Stance) -> float:
    """How well the stance lets every limb go, at the stand-offs the robot can take: the largest, over the CoM at
    the nominal stand-off (:func:`~climb_ompl.climb.transition.nominal_near`) moved towards the wall to each fraction
    :data:`CROUCH` of its stand-off, of the smallest signed distance to the support regions of the stance without
    one of its limbs (Bretl 2006, appendix B), metres; ``-inf`` when one of them is empty.  A robot whose base cannot
    move along the wall normal is scored at the nominal stand-off only; a robot without equilibrium condition
    scores 0.

    On a wall of ledges the support region lets the CoM stand off the wall at most a fraction of the stance's length
    (tests/test_equilibrium_standoff.py: 0.29 to 0.55 of it on the suite's slab, 0.24 to 0.41 on its overhang): a
    quadruped whose nominal stand-off is a compact stance's length balances on three feet only crouched on a longer
    stance, which the nominal ranking does not see."""
    if not robot.equilibrium:
        return 0.0
    regions = [feas.region(stance.without(lb)) for lb in stance.limbs]
    if len(stance) < 2 or any(r.is_empty for r in regions):
        return -float("inf")
    n = np.asarray(wall_normal(terrain), dtype=float)
    com = np.asarray(robot.com(nominal_near(robot, terrain, stance)), dtype=float)
    off = float(n @ (com - np.mean([terrain.hold(h).p for h in stance.hold_ids], axis=0)))
    _, dirs = robot.base_translations()
    fracs = CROUCH if dirs.size and float(np.max(np.abs(n @ dirs))) > 0.5 else (1.0,)
    return max(min(float(r.margin(com - n * off * (1.0 - f))) for r in regions) for f in fracs)


def candidate_stances(robot: Any, terrain: Terrain, feas: Feasibility | None = None,
                      rank: str = "nominal") -> list[Candidate]:
    """Distinct candidate start stances among the lowest holds, ranked (see the module docstring).

    ``rank="release"``: the layouts also stretched along the wall's slope (:data:`STRETCHES`), every candidate
    ranked by :func:`release_score` (largest first; the layout order on ties)."""
    if rank not in ("nominal", "release"):
        raise ValueError(f"candidate_stances: rank must be 'nominal' or 'release', got {rank!r}")
    feas = feas if feas is not None else _feasibility(robot, terrain)
    if len(terrain.holds) < len(robot.limbs):
        return []
    a, v = wall_axes(terrain)
    hands = _layout(robot, SCALES[0])
    width, height = float(np.ptp(hands @ a)), float(np.ptp(hands @ v))
    pu = terrain.positions @ a
    mid = float(np.median(pu))
    step = max(0.5 * width, 0.05)
    centres = [mid] + [c for k in (1, 2) for c in (mid - k * step, mid + k * step) if pu.min() <= c <= pu.max()]
    seen: set[tuple[tuple[str, str], ...]] = set()
    out: list[Candidate] = []
    stretches = (1.0, *STRETCHES) if rank == "release" else (1.0,)
    for lift in (0.05, 0.05 + 0.5 * height):
        for centre in centres:
            for scale in SCALES:
                for stretch in stretches:
                    st = lowest_stance(robot, terrain, scale, centre=None if centre == mid else centre, lift=lift,
                                       stretch=stretch)
                    key = tuple(sorted(st.items()))
                    if key in seen or len(st) < len(robot.limbs):
                        continue
                    seen.add(key)
                    out.append(Candidate(st, _score(robot, terrain, feas, Stance(st)), len(out)))
    if rank == "release":
        scored = [(release_score(robot, terrain, feas, Stance(c.stance)), c) for c in out]
        return [c for _, c in sorted(scored, key=lambda x: (-x[0], x[1].order))]
    return sorted(out, key=lambda c: (0, c.order) if c.score >= 0 else (1, -c.score, c.order))


# ---- trial and diagnosis ------------------------------------------------------------------------------
def _feasibility(robot: Any, terrain: Terrain) -> Feasibility:
    return Feasibility.of(robot, terrain)


def diagnose_stance(robot: Any, terrain: Terrain, stance: Any, feas: Feasibility | None = None,
                    rejections: dict[str, int] | None = None, *,
                    touching: dict[str, str] | None = None, near: np.ndarray | None = None,
                    where: str = "the nominal stand-off") -> StartDiagnosis:
    """Why ``stance`` has no feasible configuration near the nominal stand-off, check by check.

    From :func:`~climb_ompl.climb.transition.nominal_near` each contact limb (base-moving limbs first) is closed
    on its hold by the inverse-kinematics solution nearest the nominal posture.  A limb that cannot close
    is a reach failure (its hold's distance from the limb's first joint against its reach); otherwise the
    closed configuration is checked for joint limits, equilibrium (the CoM's distance to the support region),
    collision (the colliding links by name) and torque limits.  ``rejections``: FIND-TRANSITION's rejected
    draws by reason, reported alongside.  ``touching``: limbs whose hands also stay on their holds without
    carrying load (``{limb: hold}``): a release is a transition, a configuration of both stances (Bretl 2006,
    sec. 2.1), so the released hand is closed on its hold too and may touch the terrain there.  ``near``: the
    reference configuration instead of the nominal stand-off (e.g. where a climb stopped), called ``where``
    in the reasons.
    """
    from climb_ompl.model.reach import shoulders

    feas = feas if feas is not None else _feasibility(robot, terrain)
    sigma = stance if isinstance(stance, Stance) else Stance(dict(stance))
    given_near = near is not None
    if near is None:
        near = nominal_near(robot, terrain, sigma)
        score = _score(robot, terrain, feas, sigma)
    else:
        near = np.asarray(near, dtype=float)
        score = 0.0 if not robot.equilibrium else -float("inf") if feas.region(sigma).is_empty else \
            float(feas.region(sigma).margin(robot.com(near)))
    reasons: list[str] = []
    beyond_base = [] if given_near else base_beyond_bounds(robot, terrain, sigma)
    if beyond_base:  # the rest follows from it (hands metres from their holds)
        scale = terrain.scale_note()
        reasons.append(f"base bounds: the base cannot get to these holds: {', '.join(beyond_base)} (the bounds of "
                       "the robot's base joints, from its URDF or spec; a terrain far from its file's origin can "
                       "be moved nearer)" + (f"; {scale}" if scale else ""))
    both = Stance({**dict(sigma), **dict(touching or {})})  # the released hand stays on its hold too
    if robot.equilibrium:
        region = feas.region(sigma)
        if region.is_empty:
            reasons.append("equilibrium: no contact forces within the friction cones of these holds balance "
                           "gravity (empty support region)")
        elif score < 0:
            best, n, q_in = closest_com(robot, terrain, both, sigma, feas, near)
            more = (f"; the nearest of {n} configurations with every chain closed, within the joint limits and "
                    f"free of collision, the base drawn about it towards the region (a local search, not a "
                    f"proof), {'has it inside' if best >= 0 else f'is {-best:.3f} m outside'}") if n else \
                "; no configuration with every chain closed near it is free of collision and within the limits"
            if n and best >= 0 and q_in is not None:  # what still fails there, or that nothing does
                there = _closed_reasons(robot, terrain, sigma, feas, q_in, 0.0, both.limbs)
                more += (": there, " + "; ".join(there) if there else ", and there every check passes" + (
                    ": FIND-TRANSITION's draws about where the robot stood missed it, a walk of the base gets there "
                    "(--set transition_walk=100)" if given_near else ""))
            reasons.append(f"equilibrium: at {where} the CoM is {-score:.3f} m outside the support region" + more)
    kernel = DrawClose.of(robot, terrain, both)
    targets = kernel.targets
    q = near.copy()
    sh = shoulders(robot, near)
    unreachable = []
    for lb in kernel.order:  # every limb tried (base-moving limbs first), the unreachable ones named
        sol = kernel.solve(lb, q, near=near)
        if sol is None:
            unreachable.append(lb)
        else:
            q = sol
    for lb in unreachable:
        dist, reach = float(np.linalg.norm(targets[lb] - sh[lb])), float(robot.limb(lb).reach)
        why = "out of reach" if dist > reach else "no inverse-kinematics solution within the joint limits"
        beyond = limits_needed(robot, lb, near, targets[lb]) if dist <= reach else []
        if beyond:
            why += "; the solution nearest them needs " + ", ".join(
                f"{name} = {v:.3f} outside [{a:.3f}, {b:.3f}]" for name, v, a, b in beyond)
        elif dist <= reach and not free_solutions(robot, lb, near, targets[lb]):  # within the reach sphere
            why = ("no inverse-kinematics solution, not even beyond the joint limits (the hold lies within the "
                   "limb's reach sphere but outside its workspace from this base pose)")
        reasons.append(f"reach: limb {lb} cannot reach hold {both[lb]} from {where}, {why} (its hand "
                       f"target is {dist:.3f} m from the limb's first joint; reach {reach:.3f} m)")
    if not unreachable:
        reasons += _closed_reasons(robot, terrain, sigma, feas, q, score, both.limbs)
    return StartDiagnosis(dict(sigma), score, reasons, dict(rejections or {}))


def limits_needed(robot: Any, limb: str, q: np.ndarray, target: np.ndarray) -> list[tuple[str, float, float, float]]:
    """For a hand target the limb reaches only beyond its joint limits (the base and the other limbs as at ``q``):
    the joints of the inverse-kinematics solution with the least total excess over the limits, as ``(name,
    value, lower, upper)`` for each joint outside them; empty when a solution lies within the limits or none
    exists even with the limb's joints free over at least a turn."""
    idx = list(robot.limb(limb).joint_indices)
    lo, hi = np.asarray(robot.lower, dtype=float), np.asarray(robot.upper, dtype=float)

    def excess(x: np.ndarray) -> float:
        return float(np.sum(np.maximum(0.0, lo[idx] - x[idx]) + np.maximum(0.0, x[idx] - hi[idx])))

    sols = free_solutions(robot, limb, q, target)
    if not sols:
        return []
    best = min(sols, key=excess)
    names = getattr(robot, "joint_names", None) or [f"q[{j}]" for j in range(robot.nq)]
    return [(names[j], float(best[j]), float(lo[j]), float(hi[j])) for j in idx if best[j] < lo[j] - 1e-9
            or best[j] > hi[j] + 1e-9]


def free_solutions(robot: Any, limb: str, q: np.ndarray, target: np.ndarray) -> list[np.ndarray]:
    """The inverse-kinematics solutions placing ``limb``'s hand at ``target`` (the base and the other limbs as at
    ``q``) with the limb's joints bounded only by a turn either way (its own limits, where wider, kept)."""
    import copy

    idx = list(robot.limb(limb).joint_indices)
    free = copy.copy(robot)  # the same model, with this limb's joints bounded only by a turn either way
    free.lower, free.upper = np.array(robot.lower, dtype=float), np.array(robot.upper, dtype=float)
    free.lower[idx], free.upper[idx] = np.minimum(free.lower[idx], -np.pi), np.maximum(free.upper[idx], np.pi)
    return list(free.limb_ik(limb, np.asarray(q, dtype=float), target))


def _closed_reasons(robot: Any, terrain: Terrain, sigma: Stance, feas: Feasibility, q: np.ndarray,
                    score: float, touching: tuple[str, ...] = ()) -> list[str]:
    """The checks a configuration with every chain closed fails, each with its details."""
    out = []
    lo, hi = np.asarray(robot.lower, dtype=float), np.asarray(robot.upper, dtype=float)
    bad = np.flatnonzero((q < lo - 1e-9) | (q > hi + 1e-9))
    if bad.size:
        names = getattr(robot, "joint_names", None) or [f"q[{j}]" for j in range(robot.nq)]
        out.append("joint limits: " + ", ".join(f"{names[j]} = {q[j]:.3f} outside [{lo[j]:.3f}, {hi[j]:.3f}]"
                                                 for j in bad[:4]))
    if robot.equilibrium and score >= 0:  # (reported at the nominal stand-off when already outside there)
        m = float(feas.region(sigma).margin(robot.com(q)))
        if m < feas.margin:
            out.append(f"equilibrium: with the chains closed the CoM is {-m:.3f} m outside the support region")
    limbs = touching or sigma.limbs
    pairs = robot.collisions(q, terrain, contact_limbs=limbs, clearance=feas.clearance)
    if pairs:  # links in contact, then those only closer than the clearance kept between links
        hit = sorted({f"{a} with {b}" for a, b in robot.collisions(q, terrain, contact_limbs=limbs)})
        near = sorted({f"{a} with {b}" for a, b in pairs} - set(hit))
        for what, shown in (("collision: ", hit), (f"clearance: closer than {feas.clearance:g} m: ", near)):
            if shown:
                out.append(what + ", ".join(shown[:6]) + (f" (+{len(shown) - 6} more)" if len(shown) > 6 else ""))
    # (torque limits only where the CoM is over the support region: outside it, equilibrium is the reason)
    region = feas.region(sigma) if robot.equilibrium else None
    if region is not None and not bad.size and not region.is_empty and region.margin(robot.com(q)) >= 0.0 and \
            not TorqueCheck(robot, terrain, sigma, region, cone_edges=feas.cone_edges)(q):
        out.append("torque limits: no contact forces in the friction cones keep every joint torque within its "
                   "limit" + _worst_torque(robot, terrain, sigma, q))
    return out


def _worst_torque(robot: Any, terrain: Terrain, sigma: Stance, q: np.ndarray) -> str:
    """``"; least needed: <joint> at <ratio> x its limit (<torque> of <limit> N m)"``: the joint that limits
    the balanced contact forces (the exact cones' smallest largest torque ratio,
    :func:`climb_ompl.equilibrium.torque_feasible`), or ``""`` when there is no balance at all."""
    from climb_ompl.equilibrium import torque_feasible
    from climb_ompl.manifold.stance import contact_jacobians

    g = terrain.g
    res = torque_feasible(sigma.contacts(terrain), robot.mass, g, robot.com(q),
                          contact_jacobians(robot, terrain, sigma, q), robot.gravity_torques(q, g),
                          robot.torque_limits, robot.actuated, planar=bool(robot.planar))
    if res.feasible:
        return " (the check's inscribed friction pyramids; the exact cones hold it)"
    if res.worst is None or not np.isfinite(res.utilisation):
        return ""
    lim = float(robot.torque_limits[res.worst])
    return (f"; at best {robot.joint_names[res.worst]} needs {res.utilisation:.2f} x its limit "
            f"({res.utilisation * lim:.3g} of {lim:.3g} N m)")


def releasable(feas: Feasibility, sigma: Stance, q: np.ndarray, *, seed: int = 0) -> bool:
    """Whether some limb can let go of its hold from ``q``: a stance-graph edge out of ``sigma`` exists (a
    release is a transition, a configuration of both stances, Bretl 2006 sec. 2.1).  A robot with one limb on a
    hold, or without an equilibrium condition, always can.  Each limb in turn: a non-empty support region
    without it, then ``q`` itself or FIND-TRANSITION from ``q`` onto the smaller stance, as the search does."""
    if len(sigma) < 2 or not feas.robot.equilibrium:
        return True
    finder = TransitionFinder(feas, ik_tries=60)
    for limb in sigma.limbs:
        small = sigma.without(limb)
        if not feas.region_ok(small):
            continue
        if feas.valid(small, q) or finder.find(sigma, small, q, seed=seed) is not None:
            return True
    return False


def start_configuration(robot: Any, terrain: Terrain, stance: Any, *, seed: int = 0, near: Any = None,
                        attempts: int = ATTEMPTS, feas: Feasibility | None = None, closest: bool = True,
                        finder: TransitionFinder | None = None) -> np.ndarray | None:
    """A feasible configuration of ``stance``: the one way a start configuration is found (step 3 of the module
    docstring; :func:`find_start` for each candidate, :func:`climb_ompl.climb.multistep.plan_climb` for a given start
    stance).

    1. FIND-TRANSITION on the stance alone (Bretl 2006, Fig. 17, :class:`~climb_ompl.climb.transition.TransitionFinder`,
       at most 60 of its ``attempts`` draws closed) about ``near`` (default: the nominal posture placed on the holds,
       :func:`~climb_ompl.climb.transition.nominal_near`);
    2. when it finds none, with ``closest`` and a robot with an equilibrium condition: from the configuration of
       :func:`~climb_ompl.manifold.closure.closest_com` nearest the support region's centre (searched about the
       same reference; where the CoM at the nominal stand-off lies outside the region, FIND-TRANSITION's CoM
       prefilter cuts most draws, a quadruped on a vertical wall): that configuration if it passes every check,
       else FIND-TRANSITION from there.

    ``feas``: the feasibility tests (default: the climb's default settings); ``finder``: the FIND-TRANSITION to use
    (its :attr:`~climb_ompl.climb.transition.TransitionFinder.failures` then count the rejected draws).  ``None``
    when neither step gives one.
    """
    sigma = stance if isinstance(stance, Stance) else Stance(dict(stance))
    sigma.validate(robot, terrain)
    feas = feas if feas is not None else _feasibility(robot, terrain)
    finder = finder if finder is not None else TransitionFinder(feas, ik_tries=60)
    ref = nominal_near(robot, terrain, sigma) if near is None else np.asarray(near, dtype=float).copy()
    q = finder.find(sigma, sigma, ref, seed=seed, attempts=attempts)
    if q is not None or not closest or not robot.equilibrium:
        return q
    return _from_closest(feas, sigma, finder, seed, ref, attempts)


def _from_closest(feas: Feasibility, sigma: Stance, finder: TransitionFinder, seed: int, ref: np.ndarray | None = None,
                  attempts: int = ATTEMPTS) -> np.ndarray | None:
    """Step 2 of :func:`start_configuration`: the configuration of :func:`~climb_ompl.manifold.closure.closest_com`
    nearest the support region's centre, searched about ``ref`` (default the nominal posture on the holds), if it
    passes every check, else FIND-TRANSITION from there; ``None`` when the CoM was never brought inside."""
    robot, terrain = feas.robot, feas.terrain
    ref = nominal_near(robot, terrain, sigma) if ref is None else ref
    best, _, q = closest_com(robot, terrain, sigma, sigma, feas, ref, seed=seed, stop_inside=False)
    if q is None or best < feas.margin:
        return None
    if feas.why(feas.transition_checks(sigma, sigma), q) is None:
        return q
    return finder.find(sigma, sigma, q, seed=seed, attempts=attempts)


def find_start(robot: Any, terrain: Terrain, *, seed: int = 0, max_candidates: int = 12, diagnose: int = 3,
               feas: Feasibility | None = None, rank: str = "nominal", time_limit: float | None = None,
               skip: Any = ()) -> StartResult:
    """A start stance and configuration near the bottom of the wall (see the module docstring).

    Args:
        robot, terrain: the robot and terrain.
        seed: seed of FIND-TRANSITION.
        max_candidates: candidate stances tried at most (best ranked first).
        diagnose: when none works, the number of candidates (best first) whose failure is explained.
        feas: the feasibility tests (default: the climb's default settings).
        rank: ``nominal`` (the module docstring's ranking) or ``release`` (stretched layouts too, ranked by
            :func:`release_score`: a start from which every limb can let go at a crouched stand-off).
        time_limit: wall-clock seconds after which no further candidate is tried (the one under way finishes;
            ``None``: no limit).  A robot whose limbs have no closed-form inverse kinematics can take minutes per
            candidate.
        skip: stances (mappings limb -> hold) passed over: starts already tried
            (:func:`climb_ompl.climb.multistep.climb_from_start`).

    Returns:
        A :class:`StartResult`: the stance and configuration, or the diagnoses (``spent`` when the time limit
        stopped it).
    """
    t0 = time.perf_counter()
    feas = feas if feas is not None else _feasibility(robot, terrain)
    cands = candidate_stances(robot, terrain, feas, rank)
    if skip:
        passed = {tuple(sorted(dict(x).items())) for x in skip}
        cands = [c for c in cands if tuple(sorted(c.stance.items())) not in passed]
    tried: list[Candidate] = []
    rejections: list[dict[str, int]] = []
    first: StartResult | None = None  # the first start found, kept if none can let go of a limb
    spent = None
    for c in cands[:max_candidates]:
        if tried and time_limit is not None and time.perf_counter() - t0 >= time_limit:
            spent = float(time_limit)
            break
        sigma = Stance(c.stance)
        finder = TransitionFinder(feas, ik_tries=60)
        q = start_configuration(robot, terrain, sigma, seed=seed, feas=feas, closest=c.score < 0, finder=finder)
        tried.append(c)
        if q is not None:
            found = StartResult(dict(c.stance), q, list(tried), len(cands))
            if releasable(feas, sigma, q, seed=seed):
                return found
            first = first or found
            continue
        rejections.append(dict(finder.failures))
    if first is not None:
        first.tried = tried
        return first
    diags = [diagnose_stance(robot, terrain, c.stance, feas, rej)
             for c, rej in list(zip(tried, rejections, strict=True))[:diagnose]]  # (every candidate failed here)
    return StartResult(None, None, tried, len(cands), diags, spent)


__all__ = ["Candidate", "StartDiagnosis", "StartResult", "wall_axes", "lowest_stance", "candidate_stances",
           "diagnose_stance", "limits_needed", "free_solutions", "releasable", "start_configuration",
           "find_start",
           "SCALES", "ATTEMPTS", "STRETCHES", "CROUCH", "release_score"]
