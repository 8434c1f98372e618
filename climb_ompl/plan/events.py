"""Terrain-change events: what a re-plan changed of a terrain's holds, and the terrain as it was before.

A re-planned plan (:mod:`climb_ompl.climb.replan`) keeps its executed steps, planned on the terrain before the
change, and records each change as an event (``events``: the changed holds as they were, with their places in the
list).  Whatever reads such a plan (the verifier, playback, a further re-plan) rebuilds the terrain each step was
planned on from it (:func:`terrain_before`).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from climb_ompl.errors import ClimbError, QueryError
from climb_ompl.model.terrain import Terrain
from climb_ompl.plan.file import sha256_json


@dataclass(frozen=True)
class TerrainChange:
    """An edit of a terrain's holds.

    Attributes:
        remove: ids of holds that are gone.
        move: ``{id: (x, y, z)}`` new positions (metres; ``(x, z)`` on a 2-D terrain).
        friction: ``{id: mu}`` new friction coefficients (>= 0).
        add: new holds, each a dict in the terrain file format (``id``, ``position``, ``normal``, ``friction``:
            required, a loaded terrain keeps no default friction).

    Positions and normals are in the terrain file's coordinates (on a terrain turned into the wall frame, the
    change recorded in a plan's ``events`` is too; the plan's terrain is in the wall frame).
    """

    remove: tuple[str, ...] = ()
    move: dict[str, tuple[float, ...]] = field(default_factory=dict)
    friction: dict[str, float] = field(default_factory=dict)
    add: tuple[dict[str, Any], ...] = ()

    def __post_init__(self) -> None:
        if isinstance(self.remove, str):  # iterated, "h94" would be the holds h, 9 and 4
            raise QueryError(f"change.remove: expected a sequence of hold ids, got the string {self.remove!r} "
                             f"(write remove=({self.remove!r},))")

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> TerrainChange:
        """A change from its dict form (:meth:`to_dict`); unknown keys are an error."""
        unknown = sorted(set(d) - {"remove", "move", "friction", "add"})
        if unknown:
            raise QueryError(f"change: unknown key(s) {', '.join(unknown)}; valid: add, friction, move, remove")
        return cls(tuple(d.get("remove", ())), {k: tuple(v) for k, v in d.get("move", {}).items()},
                   dict(d.get("friction", {})), tuple(d.get("add", ())))

    def to_dict(self) -> dict[str, Any]:
        """The change as recorded in a plan's ``events``."""
        return {"remove": list(self.remove), "move": {k: [float(x) for x in v] for k, v in self.move.items()},
                "friction": {k: float(v) for k, v in self.friction.items()}, "add": [dict(h) for h in self.add]}

    @property
    def touched(self) -> frozenset[str]:
        """Ids of the existing holds the change alters (removed, moved or with a new friction)."""
        return frozenset(self.remove) | frozenset(self.move) | frozenset(self.friction)

    def validate(self, terrain: Terrain) -> None:
        """Check the change against ``terrain``.

        Raises:
            QueryError: an unknown hold, a hold changed twice, a non-finite position, a negative friction, a
                new hold whose id exists, or no change at all.
        """
        if not (self.remove or self.move or self.friction or self.add):
            raise QueryError("change: empty (remove, move, change the friction of, or add a hold)")
        ids = set(terrain.hold_ids)
        for what, keys in (("remove", self.remove), ("move", self.move), ("friction", self.friction)):
            for k in keys:
                if k not in ids:
                    raise QueryError(f"change.{what}: {terrain.no_hold(k)}")
        both = set(self.remove) & (set(self.move) | set(self.friction))
        if both:
            raise QueryError(f"change: hold(s) {', '.join(sorted(both))} both removed and changed")
        dim = 2 if terrain.dim == 2 else 3
        for k, v in self.move.items():
            if len(v) != dim or not all(isinstance(x, (int, float)) and math.isfinite(x) for x in v):
                raise QueryError(f"change.move.{k}: expected {dim} finite coordinates, got {list(v)!r}")
        for k, mu in self.friction.items():
            if isinstance(mu, bool) or not isinstance(mu, (int, float)) or not math.isfinite(mu) or mu < 0:
                raise QueryError(f"change.friction.{k}: must be a finite number >= 0, got {mu!r}")
        for h in self.add:
            if not isinstance(h, dict):
                raise QueryError(f"change.add: {h!r} is not a hold (a mapping with id, position, normal, friction)")
            if h.get("id") in ids:
                raise QueryError(f"change.add: hold {h['id']!r} exists in terrain {terrain.name!r}: give the new "
                                 "hold an unused id (to move the hold, --move-hold)")
            if "friction" not in h:  # a loaded terrain keeps each hold's friction, not its file's default
                raise QueryError(f"change.add: hold {h.get('id')!r} has no friction: give each new hold its "
                                 "friction (or, in an --add-holds file, a default 'friction:' beside 'holds:')")

    def apply(self, terrain: Terrain) -> Terrain:
        """The changed terrain (validated like a terrain file: a zero normal or a bad field is an error).

        Positions and normals are in the coordinates of the terrain's file: on a terrain turned into the wall
        frame (:attr:`~climb_ompl.model.terrain.Terrain.frame`), moved and added holds are turned the same way."""
        self.validate(terrain)
        d = terrain.to_dict()
        move, add = self.move, self.add
        if terrain.frame is not None and terrain.dim == 3:
            from climb_ompl.model.wall_frame import frame_of

            rot, t = frame_of(terrain)
            move = {k: tuple(float(x) for x in rot @ np.asarray(v, dtype=float) + t) for k, v in move.items()}
            add = tuple(_turned(h, rot, t) for h in add)
        holds = []
        for h in d["holds"]:
            if h["id"] in self.remove:
                continue
            h = dict(h)
            if h["id"] in move:
                h["position"] = [float(x) for x in move[h["id"]]]
            if h["id"] in self.friction:
                h["friction"] = float(self.friction[h["id"]])
            holds.append(h)
        d["holds"] = holds + [dict(h) for h in add]
        return Terrain.from_dict(d, source=f"{terrain.name} (changed)")


def change_event(terrain: dict[str, Any], change: TerrainChange, at_step: int, resumed_at: int) -> dict[str, Any]:
    """The re-plan event a plan records when ``change`` alters its terrain (``terrain``: the plan file's terrain
    record before the change, ``{"name", "data", "sha256"}``) after ``at_step`` executed steps, its new steps from
    ``resumed_at`` on: the change, the changed holds as they were (with their places in the list) and the hash of
    the terrain before it (:func:`terrain_before` rebuilds that terrain from them)."""
    before = {h["id"]: {**h, "index": i} for i, h in enumerate(terrain["data"]["holds"]) if h["id"] in change.touched}
    return {"type": "replan", "at_step": at_step, "resumed_at_step": resumed_at, "change": change.to_dict(),
            "before": before, "terrain_sha256_before": terrain["sha256"]}


def _turned(hold: dict[str, Any], rot: np.ndarray, t: np.ndarray) -> dict[str, Any]:
    """A new hold (the terrain file format) in a turned terrain's frame: a point ``p`` of its file is
    ``rot @ p + t`` there, a normal ``rot @ n`` (a malformed field is left for the terrain's validation)."""
    out = dict(hold)
    try:
        out["position"] = [float(x) for x in rot @ np.asarray(hold["position"], dtype=float) + t]
        out["normal"] = [float(x) for x in rot @ np.asarray(hold["normal"], dtype=float)]
    except (KeyError, TypeError, ValueError):
        pass
    return out


def well_formed_before(before: Any) -> bool:
    """Whether a re-plan event's ``before`` is ``{hold id: hold dict with its ``id`` and its ``index`` (a whole
    number) in the terrain's list}``, as :func:`climb_ompl.climb.replan.splice` records it."""
    return isinstance(before, dict) and all(
        isinstance(h, dict) and h.get("id") == k and isinstance(h.get("index"), int)
        and not isinstance(h["index"], bool) and h["index"] >= 0 for k, h in before.items())


def terrain_before(data: dict[str, Any], event: dict[str, Any]) -> dict[str, Any] | None:
    """The terrain dict before a re-plan event, rebuilt from the terrain dict after it: the holds it added
    dropped, the changed holds put back as they were (``event["before"]``, with their places in the list).
    ``None`` when the event does not record whole holds (files written before it did) or the rebuilt terrain's
    hash is not ``terrain_sha256_before``."""
    before = event.get("before") or {}
    if not well_formed_before(before):
        return None
    change = event.get("change") or {}
    adds = change.get("add", ()) if isinstance(change, dict) else ()
    added = {h.get("id") for h in adds if isinstance(h, dict)} if isinstance(adds, list) else set()
    holds = [h for h in data["holds"] if h["id"] not in added and h["id"] not in before]
    for h in sorted(before.values(), key=lambda x: x["index"]):
        holds.insert(int(h["index"]), {k: v for k, v in h.items() if k != "index"})
    out = {**data, "holds": holds}
    if sha256_json({k: v for k, v in out.items() if k != "description"}) != event.get("terrain_sha256_before"):
        return None
    return out


@dataclass(frozen=True)
class TerrainEras:
    """The terrains a re-planned plan's steps were executed on: ``terrains[0]`` before the first re-plan event,
    ``terrains[j + 1]`` after event ``j``, whose new steps begin at step ``resumed[j]``.

    Attributes:
        resumed: each event's ``resumed_at_step`` (``-1`` where it is not a step number).
        terrains: the terrains ``T_0 .. T_n``; a terrain an event cannot rebuild (a file from before events recorded
            whole holds) is the plan's own.
        problems: what the events get wrong, one sentence each naming the JSON path (read by the verifier).
    """

    resumed: tuple[int, ...]
    terrains: tuple[Terrain, ...]
    problems: tuple[str, ...] = ()

    def of_step(self, step: int) -> Terrain:
        """The terrain step ``step`` was executed on: after the last event whose new steps include it (the last
        ``j`` with ``resumed[j] <= step``), else the terrain before the first event."""
        j = max((j for j, k in enumerate(self.resumed) if k <= step), default=-1)
        return self.terrains[j + 1]


def terrain_eras(plan: Any) -> TerrainEras:
    """The terrains a plan's steps were executed on (a :class:`~climb_ompl.plan.file.Plan`): a re-planned plan's kept
    steps on the terrain before its change (rebuilt by :func:`terrain_before`), its new steps on the changed one;
    one terrain for a plan without re-plan events."""
    return eras_of(plan.events, plan.terrain["data"], plan.embedded_terrain(), len(plan.steps), plan.source)


def eras_of(events: Any, data: dict[str, Any], own: Terrain, n_steps: int, source: str) -> TerrainEras:
    """:func:`terrain_eras` from the pieces of a plan file: its ``events``, its terrain dict ``data`` (after every
    event), that terrain read (``own``), its number of steps and the file's name (for messages)."""
    events = [e for e in (events or ()) if isinstance(e, dict) and e.get("type") == "replan"]
    problems: list[str] = []
    datas: list[dict[str, Any] | None] = [None] * len(events) + [data]
    for j in range(len(events) - 1, -1, -1):
        after = datas[j + 1]
        datas[j] = None if after is None else terrain_before(after, events[j])
        if after is not None and datas[j] is None and well_formed_before(events[j].get("before")):
            # whole holds recorded, but the terrain they rebuild is not the one the event names: playback draws
            # those holds, and the kept steps would be checked on the plan's terrain instead of their own
            problems.append(f"$.events[{j}].before: the terrain it rebuilds (the terrain after the event with these "
                            f"holds put back) does not have the hash $.events[{j}].terrain_sha256_before")
    terrains = [own if d is None or j == len(events) else
                Terrain.from_dict(d, source=f"{source} (the terrain before event {j})")
                for j, d in enumerate(datas)]
    ks = [k if isinstance(k := e.get("resumed_at_step", 0), int) and not isinstance(k, bool) else -1
          for e in events]  # (-1: not a step, reported)
    for j, e in enumerate(events):
        problems += _event_problems(j, e, ks, n_steps, terrains[j] if datas[j] is not None else None,
                                    terrains[j + 1])
    return TerrainEras(tuple(ks), tuple(terrains), tuple(problems))


def _event_problems(j: int, event: dict[str, Any], ks: list[int], n: int, before: Terrain | None,
                    after: Terrain) -> list[str]:
    """What re-plan event ``j`` gets wrong.  It must say where its new steps begin (``resumed_at_step``, a step of the
    plan's ``n``: a later re-plan that backed off further may resume before an earlier one), and its recorded change,
    applied to the terrain before it (rebuilt from its ``before`` holds), must give the terrain after it: the holds
    ``before`` records are exactly those the change alters.  (Without it a file could check its kept steps on holds
    it made up.)"""
    out: list[str] = []
    k = ks[j]
    if event.get("before") is not None and not well_formed_before(event["before"]):
        out.append(f"$.events[{j}].before: expected {{hold id: the hold as it was, with its index in the terrain's "
                   "list}")
    if not 0 <= k <= n:
        out.append(f"$.events[{j}].resumed_at_step = {k}: not a step of the plan's {n}")
    at = event.get("at_step")
    if not isinstance(at, int) or isinstance(at, bool) or at < k:
        out.append(f"$.events[{j}].at_step = {at!r}: the steps executed when the terrain changed are at least those "
                   f"the re-plan kept (resumed_at_step = {k})")
    if before is None:
        return out  # a file from before events recorded whole holds: its steps are checked on the plan's terrain
    try:
        change = TerrainChange.from_dict(dict(event.get("change") or {}))
        made = change.apply(before)
    except (ClimbError, TypeError, ValueError, AttributeError) as exc:
        return out + [f"$.events[{j}].change cannot be applied to the terrain before it: {exc}"]
    touched = set(change.touched)
    recorded = set((event.get("before") or {}).keys())
    if recorded != touched:
        out.append(f"$.events[{j}].before records holds {sorted(recorded)} but its change alters {sorted(touched)}")
    elif made.content_hash() != after.content_hash():
        out.append(f"$.events[{j}]: its change applied to the terrain before it does not give the terrain after it")
    return out


__all__ = ["TerrainChange", "TerrainEras", "change_event", "eras_of", "terrain_before", "terrain_eras",
           "well_formed_before"]
