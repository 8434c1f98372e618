"""The operator's goals: one step from the state the robot is in, a distant goal, or a sequence of one-step goals.

Bretl (2006), sec. 5.1, on how LEMUR's planner was used: "A human operator specifies either a single-step goal (the
next hold to grab or release) or a multistep goal (a distant hold, requiring a number of steps to reach). As output,
the planner either generates a path (a list of joint-angle waypoints and feedforward torques) [...] or indicates
that such a path could not be found."  Bretl et al. (2004), sec. 3.1: "for each stance sigma, the user specifies a
desired adjacent stance sigma'".

A single-step goal names the adjacent stance ``sigma'`` (grab a hold with a free limb, release a limb, or the whole
stance); it is planned by the climbing core itself (:func:`climb_ompl.climb.multistep.plan_climb` with ``sigma'`` as
its goal stance, from the configuration the robot is in: FIND-TRANSITION, then the path to the transition), so the
step carries what any plan's step does (waypoints, times, contact forces, feed-forward torques, margin), and a
refusal carries the frontier's diagnosis (which check blocked the step, from which stance).  A multi-step goal (a
hold for a limb, a height, a climb of some metres) is a query of the same planner from the same state.  A sequence
of one-step goals (Bretl et al. (2004), sec. 2.3: "the user must provide each one-step motion goal") is planned goal
by goal and stops at the first infeasible one, naming it.
"""

from __future__ import annotations

import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from climb_ompl.climb.goal import Goal, climb_height
from climb_ompl.climb.multistep import plan_climb
from climb_ompl.climb.status import ClimbStatus
from climb_ompl.climb.warm import WarmStart
from climb_ompl.errors import QueryError
from climb_ompl.plan.file import Step

#: The kinds of goal an operator gives: one step (``grab``, ``release``, ``stance``) or many (``hold``, ``height``,
#: ``climb``).
ONE_STEP = ("grab", "release", "stance")
MULTI_STEP = ("hold", "height", "climb")
#: Default time budget of a single-step goal, s: an adjacent stance is one FIND-TRANSITION and one path away.
STEP_TIME_LIMIT = 10.0
#: A single-step goal's search explores at most this many ``(stance, component)`` nodes: the current stance in its
#: components (Bretl (2006), sec. 4.2.3), not a detour through other stances.
STEP_STANCES = 4
#: A single-step goal is tried with this many seeds before it is refused: FIND-TRANSITION draws a bounded number of
#: random configurations around the one the robot is in (Bretl (2006), Fig. 17), and another seed's draws often find
#: a transition the first missed.
STEP_TRIES = 4


@dataclass(frozen=True)
class OperatorGoal:
    """One goal of the operator, in words as the command line and the session file write it.

    Attributes:
        kind: ``grab`` (``limb`` takes ``hold``), ``release`` (``limb`` lets go), ``stance`` (exactly ``stance``,
            adjacent to the current one), ``hold`` (``limb`` on ``hold``, in as many steps as it takes),
            ``height`` (every hold held at or above ``value`` minus the reach, m) or ``climb`` (``value`` metres
            above the current stance).
    """

    kind: str
    limb: str | None = None
    hold: str | None = None
    stance: tuple[tuple[str, str], ...] = ()
    value: float | None = None

    @classmethod
    def parse(cls, text: str) -> OperatorGoal:
        """A goal from its text: ``grab LIMB=HOLD``, ``release LIMB``, ``stance L1=H1,L2=H2``, ``hold LIMB=HOLD``,
        ``height METRES`` or ``climb METRES``.

        Raises:
            QueryError: none of these (the message lists them).
        """
        kind, _, arg = str(text).strip().partition(" ")
        arg = arg.strip()
        forms = "grab LIMB=HOLD, release LIMB, stance L1=H1,L2=H2,..., hold LIMB=HOLD, height METRES, climb METRES"
        try:
            if kind in ("grab", "hold") and arg.count("=") == 1:
                limb, hold = (x.strip() for x in arg.split("="))
                if limb and hold:
                    return cls(kind, limb=limb, hold=hold)
            elif kind == "release" and arg and "=" not in arg:
                return cls(kind, limb=arg)
            elif kind == "stance" and arg:
                pairs = [tuple(x.strip() for x in p.split("=")) for p in arg.split(",")]
                if all(len(p) == 2 and all(p) for p in pairs):
                    return cls(kind, stance=tuple(sorted(pairs)))  # type: ignore[arg-type]
            elif kind in ("height", "climb") and arg:
                v = float(arg)
                if np.isfinite(v):
                    return cls(kind, value=v)
        except ValueError:
            pass
        raise QueryError(f"goal {text!r}: expected one of {forms}")

    def __str__(self) -> str:
        if self.kind in ("grab", "hold"):
            return f"{self.kind} {self.limb}={self.hold}"
        if self.kind == "release":
            return f"release {self.limb}"
        if self.kind == "stance":
            return "stance " + ",".join(f"{k}={v}" for k, v in self.stance)
        return f"{self.kind} {self.value:g}"

    @property
    def one_step(self) -> bool:
        """Whether the goal is one step (grab, release or an adjacent stance)."""
        return self.kind in ONE_STEP

    def validate(self, robot: Any, terrain: Any) -> None:
        """Check that the goal's limbs and holds exist.

        Raises:
            QueryError: naming the unknown limb or hold.
        """
        limbs = [lb.name for lb in robot.limbs]
        pairs = list(self.stance) if self.kind == "stance" else [(self.limb, self.hold)]
        for limb, hold in pairs:
            if limb is not None and limb not in limbs:
                raise QueryError(f"goal {self}: unknown limb {limb!r}; valid limbs: {', '.join(limbs)}")
            if hold is not None and hold not in terrain.hold_ids:
                raise QueryError(f"goal {self}: {terrain.no_hold(hold)}")

    def target(self, stance: Mapping[str, str]) -> dict[str, str]:
        """The adjacent stance a one-step goal asks for, from ``stance``.

        Raises:
            QueryError: the goal is no single step from ``stance`` (a limb that already holds grabs, a free limb
                is released, the last contact is released, or the stance differs by more than one limb).
        """
        now = dict(stance)
        if self.kind == "grab":
            if self.limb in now:
                raise QueryError(f"goal {self}: limb {self.limb} already holds {now[self.limb]} (release it first)")
            if self.hold in now.values():
                raise QueryError(f"goal {self}: hold {self.hold} is already held")
            return {**now, str(self.limb): str(self.hold)}
        if self.kind == "release":
            if self.limb not in now:
                raise QueryError(f"goal {self}: limb {self.limb} holds nothing (holding: "
                                 f"{', '.join(sorted(now)) or 'none'})")
            if len(now) == 1:
                raise QueryError(f"goal {self}: {self.limb} is the robot's last contact")
            return {k: v for k, v in now.items() if k != self.limb}
        if self.kind == "stance":
            nxt = dict(self.stance)
            if len(set(now.items()) ^ set(nxt.items())) != 1:
                raise QueryError(f"goal {self}: not adjacent to the current stance {stance_text(now)} (one limb "
                                 f"grabs or releases at a time)")
            return nxt
        raise QueryError(f"goal {self}: a multi-step goal has no single adjacent stance")

    def as_goal(self, robot: Any, terrain: Any, stance: Mapping[str, str]) -> Goal:
        """The planner's :class:`~climb_ompl.climb.goal.Goal` from ``stance``."""
        if self.one_step:
            return Goal("stance", stance=tuple(sorted(self.target(stance).items())))
        if self.kind == "hold":
            return Goal("hold", limb=self.limb, hold=self.hold)
        if self.kind == "height":
            return Goal("height", height=float(self.value))  # type: ignore[arg-type]
        return Goal("height", height=climb_height(robot, terrain, stance, float(self.value)))  # type: ignore[arg-type]


def stance_text(stance: Mapping[str, str]) -> str:
    """A stance as ``{limb:hold, ...}``, limbs sorted."""
    return "{" + ", ".join(f"{k}:{v}" for k, v in sorted(stance.items())) + "}"


@dataclass
class GoalResult:
    """The planner's answer to one operator goal.

    Attributes:
        goal: the goal.
        found: whether steps were found.
        steps: the steps (indices from 0), for a one-step goal exactly one.
        reason: why there are none: the planner's diagnosis (the check that failed, the frontier stance).
        status: how the query ended (:class:`~climb_ompl.climb.status.ClimbStatus`).
        diagnosis: the frontier stances (dicts) when there are no steps.
        seconds: wall-clock planning time, s; cpu_s: its CPU time, s.
    """

    goal: OperatorGoal
    found: bool
    steps: list[Step] = field(default_factory=list)
    reason: str = ""
    status: ClimbStatus | None = None
    diagnosis: list[dict[str, Any]] = field(default_factory=list)
    seconds: float = 0.0
    cpu_s: float = 0.0

    @property
    def end(self) -> tuple[dict[str, str], np.ndarray] | None:
        """The stance and configuration after the steps (``None`` when none were found)."""
        if not self.steps:
            return None
        return dict(self.steps[-1].stance_after), np.asarray(self.steps[-1].waypoints[-1], dtype=float)


def plan_goal(robot: Any, terrain: Any, stance: Mapping[str, str], q: Any, goal: OperatorGoal | str,
              settings: Any, *, seed: int = 0) -> GoalResult:
    """Plan one operator goal from the state the robot is in.

    Args:
        robot, terrain: the robot model and the terrain (as it is now: holds marked failed removed).
        stance: the current stance (limb -> hold); q: the current configuration (``nq`` values).
        goal: the goal (or its text, :meth:`OperatorGoal.parse`).
        settings: the climb's :class:`~climb_ompl.settings.ClimbSettings`; a one-step goal gets at most
            :data:`STEP_TIME_LIMIT` seconds of it.
        seed: seed of every random choice (the same seed gives the same steps).

    Returns:
        A :class:`GoalResult`; ``found`` is false with the planner's reason when no step was found.

    Raises:
        QueryError: a malformed goal, or one that is no single step from ``stance``; an unknown limb or hold.
    """
    goal = goal if isinstance(goal, OperatorGoal) else OperatorGoal.parse(goal)
    stance = dict(stance)
    target = goal.as_goal(robot, terrain, stance)
    warm = None
    if goal.one_step:  # the step itself first, and no detour (STEP_STANCES)
        settings = settings.replace(time_limit=min(settings.time_limit, STEP_TIME_LIMIT))
        nxt = dict(target.stance or ())
        (limb, hold), = set(stance.items()) ^ set(nxt.items())
        action = ("grab", limb, hold) if limb in nxt else ("release", limb, hold)
        warm = WarmStart(hints=((action,),), max_stances=STEP_STANCES)
    t, c = time.perf_counter(), time.process_time()
    first = None
    for k in range(STEP_TRIES if goal.one_step else 1):  # FIND-TRANSITION's draws are random: draw again
        res = plan_climb(robot, terrain, stance, target, settings, seed=seed + 1000003 * k,
                         q_start=np.asarray(q, dtype=float), warm=warm)
        first = first or res
        if res.found or time.perf_counter() - t > settings.time_limit:
            break
    if not res.found:
        res = first
    seconds, cpu = time.perf_counter() - t, time.process_time() - c
    if not res.found or res.plan is None:
        why = _step_block(robot, terrain, stance, goal, q) if goal.kind in ("grab", "release") else ""
        return GoalResult(goal, False, [], why + res.reason, res.status, res.diagnosis, seconds, cpu)
    steps = list(res.plan.steps)
    if goal.one_step and len(steps) != 1:  # the search went round: not the one step asked for
        return GoalResult(goal, False, [], f"goal {goal}: no direct step; the planner reached that stance only in "
                          f"{len(steps)} steps (give it as a multi-step goal)", ClimbStatus.EXHAUSTED, [], seconds, cpu)
    return GoalResult(goal, True, steps, "", res.status, [], seconds, cpu)


def _step_block(robot: Any, terrain: Any, stance: dict[str, str], goal: OperatorGoal, q: Any) -> str:
    """Why the grab or release ``goal`` fails from configuration ``q``: the checks that fail there
    (:func:`climb_ompl.climb.start.diagnose_stance`), one line each, then a blank line.  A grab is checked with the
    limb closed on its new hold while the stance still carries the load; a release with the stance that remains
    (the released hand still touching its hold), so that a release that leaves no equilibrium says so."""
    from climb_ompl.climb.start import diagnose_stance

    limb = str(goal.limb)
    if goal.kind == "grab":
        checked, touching, what = stance, {limb: str(goal.hold)}, f"with {limb} on {goal.hold}"
    else:
        checked = {k: h for k, h in stance.items() if k != limb}
        touching, what = {limb: stance[limb]}, f"with {limb} released from {stance[limb]}"
    d = diagnose_stance(robot, terrain, checked, touching=touching, near=np.asarray(q, dtype=float),
                        where="the configuration the robot is in")
    if not d.reasons:
        return ""
    return (f"{what} from the configuration the robot is in:\n" + "\n".join(f"  {r}" for r in d.reasons) + "\n")


def torque_fraction(robot: Any, step: Step) -> float:
    """The step's largest feed-forward joint torque as a fraction of that joint's limit (``|tau_j| / tau_max_j``
    over the force samples and the joints with a finite limit; 0 when no joint has one)."""
    lim = np.asarray(robot.torque_limits, dtype=float)
    ok = np.isfinite(lim) & (lim > 0)
    if not ok.any() or not step.forces:
        return 0.0
    tau = np.abs(np.array([f.torques for f in step.forces], dtype=float))
    return float(np.max(tau[:, ok] / lim[ok]))


def plan_goals(robot: Any, terrain: Any, stance: Mapping[str, str], q: Any, goals: Sequence[OperatorGoal | str],
               settings: Any, *, seed: int = 0) -> list[GoalResult]:
    """Plan a sequence of goals one after the other, each from the state the previous one reached; the answers in
    order, the last one the first infeasible goal when one is (the goals after it are not planned)."""
    out: list[GoalResult] = []
    stance, q = dict(stance), np.asarray(q, dtype=float)
    for i, g in enumerate(goals):
        r = plan_goal(robot, terrain, stance, q, g, settings, seed=seed + i)
        out.append(r)
        if not r.found or r.end is None:
            break
        stance, q = r.end
    return out


__all__ = ["GoalResult", "MULTI_STEP", "ONE_STEP", "OperatorGoal", "STEP_TIME_LIMIT", "plan_goal", "plan_goals",
           "stance_text", "torque_fraction"]
