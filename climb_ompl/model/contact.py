"""How a limb's end-effector touches a hold: the contact geometry of a robot spec's ``limbs[i].contact``.

A limb touches the terrain at one point of its end-effector.  Two geometries are modelled:

* ``point`` (the default): the hand frame *is* the contact point, so the hand frame sits on the hold (the
  small tips of the bundled robots; the point-contact model of Bretl et al. (2004) and Bretl (2006)).
* ``sphere`` of radius ``r`` (a quadruped's rubber foot): the hand frame is the sphere's centre and the
  contact lies on the sphere's surface along the hold normal ``n``, so for a hold at ``p`` the hand frame
  sits at ``p + r n`` (:meth:`ContactGeometry.hand_target`) and the contact point of a hand at ``c`` is ``c - r n``
  (:meth:`ContactGeometry.contact_point`).  ``offset`` moves the sphere's centre from the named hand frame (in
  that frame's coordinates): the robot model then adds a frame at the centre and uses it as the limb's
  hand frame.

Near its hold a limb's geometry touches the terrain on purpose.  Two kinds of exemption from terrain
collision follow from the contact (``climb_ompl.model.robot.RobotModel.in_collision``):

* ``point``: the geometry on the hand's own link is exempt (a tip touching its hold), as in every
  bundled robot;
* the ``links`` listed (default for ``sphere``: the hand's link and every link moved only by the limb's
  last joint, e.g. a lower leg) may touch the terrain within ``near`` metres of the hold: a collision of
  such a link with the terrain counts only if one of Coal's contact points (the deepest points of the
  overlap) lies farther than ``near`` from the hold.

Spec syntax (per limb)::

    contact: {type: sphere, radius: 0.02}                    # Go1's foot
    contact: {type: sphere, radius: 0.03, offset: [0, 0, 0.0225], near: 0.06, links: [LF_FOOT, LF_SHANK]}
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from climb_ompl._io import number_hint
from climb_ompl.errors import RobotModelError

__all__ = ["CONTACT_TYPES", "DEFAULT_NEAR", "ContactGeometry", "POINT", "parse_contact"]

#: Contact geometries a spec may name.
CONTACT_TYPES = ("point", "sphere")

#: Default distance from the hold within which the contact links may touch the terrain, metres.
DEFAULT_NEAR: float = 0.05

_FIELDS = {"type", "radius", "offset", "links", "near"}


@dataclass(frozen=True)
class ContactGeometry:
    """The contact model of one limb.

    Attributes:
        type: ``point`` or ``sphere``.
        radius: sphere radius, metres (0 for a point).
        offset: sphere centre in the spec's hand frame, metres (zeros: the frame is the centre).
        links: link names that may touch the terrain near the hold, or ``None`` for the default (see the
            module docstring).
        near: distance from the hold within which those links may touch the terrain, metres.
    """

    type: str = "point"
    radius: float = 0.0
    offset: tuple[float, float, float] = (0.0, 0.0, 0.0)
    links: tuple[str, ...] | None = None
    near: float = DEFAULT_NEAR

    def hand_target(self, position: Any, normal: Any) -> np.ndarray:
        """Where the hand frame goes for a hold at ``position`` with outward unit ``normal``: ``p + r n``."""
        p = np.asarray(position, dtype=float).reshape(3)
        if self.radius == 0.0:
            return p.copy()
        n = np.asarray(normal, dtype=float).reshape(3)
        return p + self.radius * n / np.linalg.norm(n)

    def contact_point(self, hand: Any, normal: Any) -> np.ndarray:
        """The point touching a hold of outward ``normal`` when the hand frame is at ``hand``: ``c - r n``."""
        c = np.asarray(hand, dtype=float).reshape(3)
        if self.radius == 0.0:
            return c.copy()
        n = np.asarray(normal, dtype=float).reshape(3)
        return c - self.radius * n / np.linalg.norm(n)


POINT = ContactGeometry()


#: Largest contact radius and offset from the hand frame, metres.
MAX_SIZE = 10.0


def _number(raw: Any, src: str, fld: str, positive: bool) -> float:
    if isinstance(raw, bool) or not isinstance(raw, (int, float)) or not np.isfinite(raw):
        raise RobotModelError(src, fld, f"expected a number, got {raw!r}{number_hint(raw)}")
    if raw < 0 or (positive and raw == 0):
        raise RobotModelError(src, fld, f"must be {'positive' if positive else 'non-negative'}, got {raw!r}")
    return float(raw)


def parse_contact(raw: Any, src: str, fld: str) -> ContactGeometry:
    """Check and build a limb's ``contact`` section (``None``: a point contact).

    Raises:
        RobotModelError: unknown field or type, a radius that is not positive, a bad offset, links or near.
    """
    if raw is None:
        return POINT
    if not isinstance(raw, dict):
        raise RobotModelError(src, fld, "expected a mapping such as {type: sphere, radius: 0.02}")
    unknown = sorted(set(raw) - _FIELDS)
    if unknown:
        raise RobotModelError(src, f"{fld}.{unknown[0]}", f"unknown field; known: {', '.join(sorted(_FIELDS))}")
    kind = raw.get("type", "point")
    if kind not in CONTACT_TYPES:
        raise RobotModelError(src, f"{fld}.type", f"must be one of {', '.join(CONTACT_TYPES)}, got {kind!r}")
    if kind == "sphere":
        if "radius" not in raw:
            raise RobotModelError(src, f"{fld}.radius", "missing required field (a sphere contact needs a radius)")
        radius = _number(raw["radius"], src, f"{fld}.radius", positive=True)
        if radius > MAX_SIZE:
            raise RobotModelError(src, f"{fld}.radius", f"{radius:g} m is beyond {MAX_SIZE:g} m (metres: a foot, not "
                                  "a planet)")
    else:
        if "radius" in raw or "offset" in raw:
            key = "radius" if "radius" in raw else "offset"
            raise RobotModelError(src, f"{fld}.{key}", "only a sphere contact has a radius and an offset")
        radius = 0.0
    off = raw.get("offset", [0.0, 0.0, 0.0])
    if (not isinstance(off, list) or len(off) != 3
            or not all(isinstance(x, (int, float)) and not isinstance(x, bool) and np.isfinite(x) for x in off)):
        raise RobotModelError(src, f"{fld}.offset", f"expected a list of 3 finite numbers (metres), got {off!r}")
    if max(abs(float(x)) for x in off) > MAX_SIZE:
        raise RobotModelError(src, f"{fld}.offset", f"{off!r}: beyond {MAX_SIZE:g} m from the hand frame (metres)")
    links = raw.get("links")
    if links is not None and (not isinstance(links, list) or not all(isinstance(x, str) for x in links)):
        raise RobotModelError(src, f"{fld}.links", "expected a list of link names")
    near = _number(raw.get("near", DEFAULT_NEAR), src, f"{fld}.near", positive=False)
    return ContactGeometry(kind, radius, tuple(float(x) for x in off), None if links is None else tuple(links), near)
