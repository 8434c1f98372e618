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

from climb_ompl.errors import QueryError
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
                    raise QueryError(f"change.{what}: no hold {k!r} in terrain {terrain.name!r}")
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


__all__ = ["TerrainChange", "terrain_before", "well_formed_before"]
