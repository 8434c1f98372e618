"""The operator's session file: a climb plan of the steps accepted so far, plus the record of the session.

Bretl (2006), sec. 5.1: the operator gives a goal, the planner proposes a path, and "before the path is actually
executed, it can be evaluated by the operator in a graphical user interface".  A session keeps what came of that
loop.  It is a plan file of kind ``climb`` (:class:`~climb_ompl.plan.file.Plan`) whose steps are the steps the
operator accepted, in the order they were executed, from the session's start, so that ``climb-ompl verify`` checks
it as it checks any plan and ``climb-ompl play`` plays it; a hold the operator marked failed is the plan's terrain
change (a ``replan`` event, :func:`climb_ompl.plan.events.change_event`): the steps before it are checked on the
terrain with the hold, those after it on the terrain without.  The plan's ``query.goal`` is the stance the session
has reached (a session has no single goal; the operator's goals are in the record).

The record is the file's ``session`` section (``version`` 1):

* ``created``, ``updated``: UTC timestamps (ISO 8601);
* ``goals``: every goal the operator gave, in order: ``goal`` (its text, :class:`climb_ompl.climb.step.OperatorGoal`),
  ``time``, ``at_step`` (the accepted steps before it), ``outcome`` (``accepted``, ``rejected``, ``no plan``,
  ``undone``), ``steps`` (how many were proposed), ``plan_s`` (planning time, s), ``reason`` (for ``no plan``);
* ``rejected``: the proposals the operator rejected: ``goal``, ``time``, ``at_step`` and each proposed step's
  ``action``, ``limb``, ``hold`` and ``margin``;
* ``failed_holds``: ``hold``, ``at_step``, ``time`` of each hold marked failed;
* ``undone``: the steps taken back (``undo``), each as the plan file writes a step, with the ``time``.
"""

from __future__ import annotations

import dataclasses
import datetime
import os
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from climb_ompl._io import atomic_write
from climb_ompl.errors import PlanFileError, QueryError
from climb_ompl.plan.events import TerrainChange, change_event
from climb_ompl.plan.file import Plan, Step, library_versions, read_plan_dict, robot_record

#: Version of the ``session`` section.
SESSION_VERSION = 1
#: The lists of the ``session`` section and the fields each entry must have.
LISTS: dict[str, tuple[str, ...]] = {"goals": ("goal", "time", "at_step", "outcome"),
                                     "rejected": ("goal", "time", "at_step", "steps"),
                                     "failed_holds": ("hold", "at_step", "time"),
                                     "undone": ("time", "step")}


def now() -> str:
    """The current UTC time, ISO 8601 to the millisecond."""
    return datetime.datetime.now(datetime.UTC).isoformat(timespec="milliseconds")


def empty_record() -> dict[str, Any]:
    """A new session's record."""
    t = now()
    return {"version": SESSION_VERSION, "created": t, "updated": t, **{k: [] for k in LISTS}}


def check_record(d: Any, source: str) -> dict[str, Any]:
    """The ``session`` section ``d`` of file ``source``, checked.

    Raises:
        PlanFileError: naming the JSON path of the first bad field.
    """
    if not isinstance(d, dict):
        raise PlanFileError(source, "$.session", "expected an object (the session's record)")
    if d.get("version") != SESSION_VERSION:
        raise PlanFileError(source, "$.session.version", f"expected {SESSION_VERSION}, got {d.get('version')!r}")
    for name, keys in LISTS.items():
        items = d.get(name, [])
        if not isinstance(items, list):
            raise PlanFileError(source, f"$.session.{name}", "expected a list")
        for i, item in enumerate(items):
            if not isinstance(item, dict):
                raise PlanFileError(source, f"$.session.{name}[{i}]", "expected an object")
            for k in keys:
                if k not in item:
                    raise PlanFileError(source, f"$.session.{name}[{i}].{k}", "missing")
            at = item.get("at_step", 0)
            if isinstance(at, bool) or not isinstance(at, int) or at < 0:
                raise PlanFileError(source, f"$.session.{name}[{i}].at_step", f"expected a step count >= 0, "
                                    f"got {at!r}")
    return {**empty_record(), **d}


def step_summary(s: Step) -> dict[str, Any]:
    """What the record keeps of a proposed step: ``action``, ``limb``, ``hold``, ``margin`` (m)."""
    return {"action": s.action, "limb": s.limb, "hold": s.hold, "margin": float(s.margin)}


@dataclass
class Session:
    """An operator's session: the plan of the accepted steps and the record (see the module docstring).

    Attributes:
        plan: the climb plan of the accepted steps (its terrain the terrain as it is now).
        record: the ``session`` section.
        source: the file the session was read from (``"<new>"`` otherwise).
    """

    plan: Plan
    record: dict[str, Any] = field(default_factory=empty_record)
    source: str = "<new>"

    # ---- making, reading, writing ---------------------------------------------------------------------
    @classmethod
    def start(cls, robot: Any, terrain: Any, stance: dict[str, str], q: Any, settings: dict[str, Any],
              seed: int = 0) -> Session:
        """A new session of ``robot`` on ``terrain`` from ``stance`` in configuration ``q`` (no step yet)."""
        from climb_ompl._version import __version__

        stance = {str(k): str(v) for k, v in stance.items()}
        plan = Plan(robot=robot_record(robot),
                    terrain={"name": terrain.name, "data": terrain.to_dict(), "sha256": terrain.content_hash()},
                    query={"start": {"stance": stance, "q": [float(x) for x in np.asarray(q, dtype=float)]},
                           "goal": {"type": "stance", "stance": dict(stance)}},
                    seed=int(seed), steps=(), settings=dict(settings), totals=_totals(()),
                    versions=library_versions(), climb_ompl_version=__version__)
        return cls(plan)

    @classmethod
    def of_plan(cls, plan: Plan) -> Session:
        """A session that goes on from a plan: its steps are the session's first accepted steps."""
        rec = empty_record()
        rec["goals"].append({"goal": _goal_text(plan.query["goal"]), "time": rec["created"], "at_step": 0,
                             "outcome": "accepted", "steps": len(plan.steps), "from": plan.source})
        return cls(with_steps(plan, plan.steps), rec, plan.source)

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> Session:
        """Read a session file, or a climb plan file to go on from (:meth:`of_plan`).

        Raises:
            PlanFileError: unreadable, not a climb plan, or a malformed ``session`` section (naming the field).
        """
        d = read_plan_dict(path)
        rec = d.pop("session", None)
        plan = Plan._from_valid(d, str(path))
        if rec is None:
            return cls.of_plan(plan)
        return cls(plan, check_record(rec, str(path)), str(path))

    def to_dict(self) -> dict[str, Any]:
        """The session file as a JSON-able dict: the plan file's, with the ``session`` section."""
        return {**self.plan.to_dict(), "session": self.record}

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the session file atomically (no partial file on failure)."""
        import json

        self.record["updated"] = now()
        return atomic_write(path, json.dumps(self.to_dict(), indent=1, sort_keys=True, allow_nan=False) + "\n")

    # ---- the state ----------------------------------------------------------------------------------
    @property
    def n_steps(self) -> int:
        """The number of accepted steps."""
        return len(self.plan.steps)

    def state(self) -> tuple[dict[str, str], np.ndarray]:
        """The stance and configuration the robot is in (after the last accepted step, else the start)."""
        if self.plan.steps:
            last = self.plan.steps[-1]
            return dict(last.stance_after), np.asarray(last.waypoints[-1], dtype=float)
        return dict(self.plan.start_stance), np.asarray(self.plan.query["start"]["q"], dtype=float)

    def terrain(self) -> Any:
        """The terrain as it is now (holds marked failed removed)."""
        return self.plan.embedded_terrain()

    @property
    def failed(self) -> list[str]:
        """The holds marked failed, in order."""
        return [str(x["hold"]) for x in self.record["failed_holds"]]

    # ---- the operator's decisions -------------------------------------------------------------------
    def _goal(self, goal: str, outcome: str, steps: int, **extra: Any) -> None:
        self.record["goals"].append({"goal": str(goal), "time": now(), "at_step": self.n_steps, "outcome": outcome,
                                     "steps": steps, **extra})

    def accept(self, goal: str, steps: list[Step], plan_s: float = 0.0) -> None:
        """Append a proposal's steps (planned from :meth:`state`) as executed.

        Raises:
            QueryError: the first step does not start in the stance the robot is in.
        """
        if not steps:
            raise QueryError(f"goal {goal}: no steps to accept")
        stance, q = self.state()
        if dict(steps[0].stance) != stance or not np.allclose(steps[0].waypoints[0], q, atol=1e-9):
            raise QueryError(f"goal {goal}: the proposal does not start where the robot is (stance {stance})")
        self._goal(goal, "accepted", len(steps), plan_s=float(plan_s))
        self.plan = with_steps(self.plan, (*self.plan.steps, *steps))

    def reject(self, goal: str, steps: list[Step], plan_s: float = 0.0) -> None:
        """Record a proposal the operator rejected (its steps' summaries, :func:`step_summary`)."""
        self._goal(goal, "rejected", len(steps), plan_s=float(plan_s))
        self.record["rejected"].append({"goal": str(goal), "time": now(), "at_step": self.n_steps,
                                        "steps": [step_summary(s) for s in steps]})

    def refused(self, goal: str, reason: str, plan_s: float = 0.0) -> None:
        """Record a goal the planner found no steps for, with its reason."""
        self._goal(goal, "no plan", 0, plan_s=float(plan_s), reason=str(reason))

    def undo(self) -> Step:
        """Take back the last accepted step; a hold marked failed after it stays failed (its event then comes
        before the step that is now next).

        Raises:
            QueryError: no step to take back.
        """
        if not self.plan.steps:
            raise QueryError("undo: no accepted step to take back")
        last = self.plan.steps[-1]
        n = self.n_steps - 1
        events = tuple({**e, "at_step": min(int(e["at_step"]), n), "resumed_at_step": min(int(e["resumed_at_step"]), n)}
                       for e in self.plan.events)
        self.plan = with_steps(dataclasses.replace(self.plan, events=events), self.plan.steps[:-1])
        for x in self.record["failed_holds"]:
            x["at_step"] = min(int(x["at_step"]), n)
        self.record["undone"].append({"time": now(), "step": last.to_dict()})
        return last

    def fail_hold(self, hold: str) -> None:
        """Mark ``hold`` failed: it is removed from the terrain from now on (a ``replan`` event at the current
        step), the steps already accepted stay checked on the terrain with it.

        Raises:
            QueryError: an unknown hold, or a hold the robot holds now (it cannot stand on it and re-plan).
        """
        stance, _ = self.state()
        if hold in stance.values():
            limb = next(k for k, v in stance.items() if v == hold)
            raise QueryError(f"hold {hold}: {limb} holds it now; undo the steps to before it was grabbed first")
        change = TerrainChange(remove=(hold,))
        self.plan = self.with_change(change)
        self.record["failed_holds"].append({"hold": hold, "at_step": self.n_steps, "time": now()})

    def with_change(self, change: TerrainChange) -> Plan:
        """The session's plan with ``change`` applied to its terrain after the accepted steps (the event recorded)."""
        terrain = change.apply(self.terrain())
        event = change_event(self.plan.terrain, change, self.n_steps, self.n_steps)
        return dataclasses.replace(self.plan, terrain={"name": self.plan.terrain["name"], "data": terrain.to_dict(),
                                                       "sha256": terrain.content_hash()},
                                   events=(*self.plan.events, event))

    def proposal_plan(self, steps: list[Step], goal: dict[str, Any]) -> Plan:
        """The session's plan with ``steps`` appended and ``goal`` as its query's goal: what the re-planner takes
        when a hold fails under a proposal (``at_step`` the accepted steps)."""
        plan = with_steps(self.plan, (*self.plan.steps, *steps))
        return dataclasses.replace(plan, query={**plan.query, "goal": goal})


def with_steps(plan: Plan, steps: Any) -> Plan:
    """``plan`` with ``steps`` (re-indexed), its totals and its goal (the stance reached) to match."""
    steps = tuple(dataclasses.replace(s, index=i) for i, s in enumerate(steps))
    final = dict(steps[-1].stance_after) if steps else dict(plan.start_stance)
    return dataclasses.replace(plan, steps=steps, totals={**plan.totals, **_totals(steps)},
                               query={**plan.query, "goal": {"type": "stance", "stance": final}})


def _totals(steps: Any) -> dict[str, Any]:
    return {"steps": len(steps), "execution_s": float(sum(s.duration for s in steps)),
            "waypoints": int(sum(len(s.waypoints) for s in steps)),
            "grabs": sum(1 for s in steps if s.action == "grab"),
            "releases": sum(1 for s in steps if s.action == "release")}


def _goal_text(goal: dict[str, Any]) -> str:
    """A plan's query goal as an operator goal's text."""
    if goal.get("type") == "height":
        return f"height {goal['height']:g}"
    if goal.get("type") == "hold":
        return f"hold {goal['limb']}={goal['hold']}"
    return "stance " + ",".join(f"{k}={v}" for k, v in sorted(dict(goal.get("stance", {})).items()))


__all__ = ["LISTS", "SESSION_VERSION", "Session", "check_record", "empty_record", "now", "step_summary", "with_steps"]
