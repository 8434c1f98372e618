"""What the operator's console does, apart from the page: goals planned in a worker thread, proposals, the session.

Bretl (2006), sec. 5.1: "A human operator specifies either a single-step goal (the next hold to grab or release) or a
multistep goal (a distant hold, requiring a number of steps to reach). [...] Before the path is actually executed, it
can be evaluated by the operator in a graphical user interface (GUI)."  :class:`ConsoleState` is that loop without
the page: :meth:`~ConsoleState.submit` plans a goal from the state the robot is in (in a worker thread; a goal given
while one is planned is refused with a message), the answer becomes the :class:`Proposal` the page previews;
:meth:`~ConsoleState.accept` appends its steps to the session (and writes the session file),
:meth:`~ConsoleState.reject` drops it, :meth:`~ConsoleState.undo` takes back the last accepted step and
:meth:`~ConsoleState.fail_hold` marks a hold failed and re-plans the proposal with the re-planner
(:func:`climb_ompl.climb.replan.replan`).  Every refusal is a message (:attr:`ConsoleState.message`), never an
exception out of a callback: the server stays up.
"""

from __future__ import annotations

import dataclasses
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from climb_ompl.climb.step import OperatorGoal, plan_goal, torque_fraction
from climb_ompl.errors import ClimbError
from climb_ompl.plan.events import TerrainChange
from climb_ompl.plan.file import Step, robot_from_plan
from climb_ompl.plan.session import Session, now, with_steps
from climb_ompl.settings import ClimbSettings

#: Default equilibrium margin under which a step is flagged "almost infeasible" (Bretl et al. (2004), sec. 4.3:
#: "how to communicate risk, particularly when one-step motions are 'almost feasible'"), metres.
MARGIN_THRESHOLD = 0.02


@dataclass
class Proposal:
    """Steps the planner proposes for a goal, waiting for the operator's decision.

    Attributes:
        goal: the goal's text; steps: the steps (from the state the robot is in); seconds: planning time, s.
        margins: each step's smallest equilibrium margin, m; torques: each step's largest torque / limit.
        note: how it came (``""``, or that it was re-planned after a hold failed).
        arrived: when it arrived (:func:`time.perf_counter`).
    """

    goal: str
    steps: list[Step]
    seconds: float
    margins: list[float]
    torques: list[float]
    note: str = ""
    arrived: float = 0.0

    def flagged(self, threshold: float) -> list[int]:
        """The steps whose margin is under ``threshold`` (m): "almost infeasible"."""
        return [i for i, m in enumerate(self.margins) if m < threshold]

    def holds(self) -> list[str]:
        """The holds the proposal grabs, in order."""
        return [s.hold for s in self.steps if s.action == "grab"]

    def timeline(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """The proposal's motion as ``(times (n,), configurations (n, nq), step of each (n,))``: the steps' waypoints
        one after the other at their stored times, s."""
        ts, qs, ks = [], [], []
        t0 = 0.0
        for k, s in enumerate(self.steps):
            for t, w in zip(s.times, s.waypoints, strict=True):
                ts.append(t0 + float(t))
                qs.append(w)
                ks.append(k)
            t0 += s.duration
        return np.asarray(ts, dtype=float), np.asarray(qs, dtype=float), np.asarray(ks, dtype=int)


def configuration_at(times: np.ndarray, qs: np.ndarray, t: float) -> np.ndarray:
    """The configuration at time ``t`` (s) of a timeline: linear between waypoints (as a step's motion is
    executed, :class:`~climb_ompl.plan.file.Step`), clamped at both ends."""
    if len(times) == 0:
        raise ValueError("empty timeline")
    i = int(np.searchsorted(times, t, side="right"))
    if i <= 0:
        return qs[0].copy()
    if i >= len(times):
        return qs[-1].copy()
    t0, t1 = times[i - 1], times[i]
    a = 0.0 if t1 <= t0 else (t - t0) / (t1 - t0)
    return (1 - a) * qs[i - 1] + a * qs[i]


class ConsoleState:
    """The console's session, proposal and worker thread (see the module docstring).

    Args:
        session: the session to go on with.
        path: the session file written after every decision (``None``: none written).
        seed: seed of the first goal (each goal gets the next).
        time_limit: budget of a multi-step goal's search, s (default: the session's settings).
        on_change: called (from whichever thread) after every change, for the page to redraw.

    Attributes:
        message: the last message for the operator (a refusal names the planner's diagnosis); log: every one.
        proposal: the proposal waiting for a decision, or ``None``.
        busy: the goal being planned (its text), or ``None``.
    """

    def __init__(self, session: Session, path: str | Path | None = None, *, seed: int = 0,
                 time_limit: float | None = None, on_change: Callable[[str], None] | None = None):
        self.session, self.path, self.seed = session, None if path is None else Path(path), int(seed)
        self.robot = robot_from_plan(session.plan)
        self.settings = ClimbSettings.from_plan(session.plan.settings, source=f"{session.source}: $.settings")
        if time_limit is not None:
            self.settings = self.settings.replace(time_limit=float(time_limit))
        self.on_change = on_change or (lambda what: None)
        self.lock = threading.Lock()
        self.message = ""
        self.log: list[str] = []
        self.proposal: Proposal | None = None
        self.busy: str | None = None
        self.worker: threading.Thread | None = None
        self.threshold = MARGIN_THRESHOLD

    # ---- goals ----------------------------------------------------------------------------------------
    def submit(self, goal: str, *, wait: bool = False) -> str | None:
        """Plan ``goal`` (its text, :class:`~climb_ompl.climb.step.OperatorGoal`) in a worker thread from the state
        the robot is in.  Returns the refusal message (a goal being planned, a proposal waiting, a malformed goal),
        or ``None`` when planning started (``wait``: and finished)."""
        with self.lock:
            if self.busy is not None:
                return self._say(f"refused {goal}: still planning {self.busy}; wait for its answer")
            if self.proposal is not None:
                return self._say(f"refused {goal}: accept or reject the proposal for {self.proposal.goal} first")
            try:
                g = OperatorGoal.parse(goal)
                g.validate(self.robot, self.session.terrain())
            except ClimbError as exc:
                return self._say(f"refused: {exc}")
            self.busy = str(g)
            self.message = f"planning {g} ..."
            self.worker = threading.Thread(target=self._plan, args=(g,), daemon=True, name="console-planner")
            self.worker.start()
        self.on_change("busy")
        if wait:
            self.worker.join()
        return None

    def _plan(self, goal: OperatorGoal) -> None:
        """The worker: plan ``goal``, then hold its proposal or say why there is none."""
        stance, q = self.session.state()
        seed = self.seed + len(self.session.record["goals"])
        try:
            res = plan_goal(self.robot, self.session.terrain(), stance, q, goal, self.settings, seed=seed)
        except Exception as exc:  # noqa: BLE001  (the server stays up whatever the planner raises)
            with self.lock:
                self.busy = None
                self._say(f"no plan for {goal}: {exc}")
                self.session.refused(str(goal), str(exc))
            self.on_change("refused")
            return
        with self.lock:
            self.busy = None
            if res.found:
                self.proposal = self._proposal(str(goal), res.steps, res.seconds)
                self._say(f"proposal for {goal}: {len(res.steps)} step(s) in {res.seconds:.2f} s")
            else:
                self.session.refused(str(goal), res.reason, res.seconds)
                self._say(f"no plan for {goal} ({res.seconds:.2f} s): {res.reason}")
        self.on_change("proposal" if res.found else "refused")

    def _proposal(self, goal: str, steps: list[Step], seconds: float, note: str = "") -> Proposal:
        return Proposal(goal, list(steps), seconds, [float(s.margin) for s in steps],
                        [torque_fraction(self.robot, s) for s in steps], note, time.perf_counter())

    def _say(self, text: str) -> str:
        self.message = text
        self.log.append(text)
        return text

    # ---- decisions ------------------------------------------------------------------------------------
    def accept(self) -> str | None:
        """Append the proposal's steps to the session (and write the session file); the refusal, or ``None``."""
        with self.lock:
            if self.busy is not None or self.proposal is None:
                return self._say("nothing to accept" if self.proposal is None else "refused: still planning")
            p = self.proposal
            try:
                self.session.accept(p.goal, p.steps, p.seconds)
            except ClimbError as exc:
                return self._say(f"refused: {exc}")
            self.proposal = None
            self._save()
            self._say(f"accepted {p.goal}: {len(p.steps)} step(s); {self.session.n_steps} steps in the session")
        self.on_change("accepted")
        return None

    def reject(self) -> str | None:
        """Drop the proposal (recorded as rejected); the refusal, or ``None``."""
        with self.lock:
            if self.proposal is None:
                return self._say("nothing to reject")
            p = self.proposal
            self.session.reject(p.goal, p.steps, p.seconds)
            self.proposal = None
            self._save()
            self._say(f"rejected {p.goal}")
        self.on_change("rejected")
        return None

    def undo(self) -> str | None:
        """Take back the last accepted step (a proposal waiting is dropped); the refusal, or ``None``."""
        with self.lock:
            if self.busy is not None:
                return self._say("refused undo: still planning")
            try:
                last = self.session.undo()
            except ClimbError as exc:
                return self._say(f"refused: {exc}")
            self.proposal = None
            self._save()
            self._say(f"undone: step {last.index} ({last.action} {last.limb} {last.hold})")
        self.on_change("undone")
        return None

    def fail_hold(self, hold: str) -> str | None:
        """Mark ``hold`` failed and, when a proposal waits, re-plan it from the state the robot is in with the
        re-planner (warm, rejoining the proposal's route); the refusal, or ``None``.  Runs in the caller's thread
        (the page calls it from its own)."""
        from climb_ompl.climb.replan import replan

        with self.lock:
            if self.busy is not None:
                return self._say(f"refused hold failed ({hold}): still planning {self.busy}")
            p, s = self.proposal, self.session
            if p is None or hold not in {h for st in p.steps for h in (st.hold, *dict(st.stance).values())}:
                try:  # nothing planned relies on it: the terrain changes from now on
                    s.fail_hold(hold)
                except ClimbError as exc:
                    return self._say(f"refused: {exc}")
                self._save()
                self._say(f"hold {hold} marked failed")
                changed = "failed"
            else:
                self.busy = f"re-plan after {hold} failed"
                changed = ""
        if changed:
            self.on_change(changed)
            return None
        self.on_change("busy")
        return self._replan(p, hold, replan)

    def _replan(self, p: Proposal, hold: str, replan: Callable[..., Any]) -> str | None:
        s, n = self.session, self.session.n_steps
        stance, _ = s.state()
        goal = OperatorGoal.parse(p.goal).as_goal(self.robot, s.terrain(), stance).to_dict()
        t = time.perf_counter()
        try:
            if hold in stance.values():
                raise ClimbError(f"hold {hold}: the robot holds it now; undo the steps to before it was grabbed first")
            res = replan(s.proposal_plan(p.steps, goal), n, TerrainChange(remove=(hold,)), robot=self.robot,
                         seed=self.seed + len(s.record["goals"]), time_limit=self.settings.time_limit)
        except ClimbError as exc:
            with self.lock:
                self.busy = None
            self.on_change("refused")
            return self._say(f"refused: {exc}")
        secs = time.perf_counter() - t
        with self.lock:
            self.busy = None
            if res.found and res.plan is not None and res.resumed_at == n:
                s.plan = with_steps(dataclasses.replace(res.plan, query=s.plan.query), res.plan.steps[:n])
                s.record["failed_holds"].append({"hold": hold, "at_step": n, "time": now()})
                self.proposal = self._proposal(p.goal, list(res.plan.steps[n:]), secs, f"re-planned after {hold} "
                                               f"failed ({res.used})")
                self._save()
                self._say(f"hold {hold} failed: re-planned {p.goal}, {len(self.proposal.steps)} step(s) in "
                          f"{secs:.2f} s")
                what = "proposal"
            else:
                s.fail_hold(hold)
                self.proposal = None
                self._save()
                self._say(f"hold {hold} failed; no new plan for {p.goal}: {res.climb.reason}")
                what = "refused"
        self.on_change(what)
        return None

    def set_threshold(self, metres: float) -> None:
        """The margin under which a proposed step is flagged, m."""
        self.threshold = float(metres)
        self.on_change("threshold")

    def _save(self) -> None:
        if self.path is not None:
            try:
                self.session.save(self.path)
            except ClimbError as exc:
                self.message = f"session not written: {exc}"


__all__ = ["ConsoleState", "MARGIN_THRESHOLD", "Proposal", "configuration_at"]
