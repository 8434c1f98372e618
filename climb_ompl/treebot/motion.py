"""TreeBot's motion along a planned path: the front-gripper based scheme of Lam et al., section V.

1. *Path segmentation* (V.A.1): front-gripper targets are path points a constant path length ``step``
   apart; the path between two targets is a segment.
2. Each *extension* keeps the rear gripper fixed and moves the front gripper to the next target; the body
   is the arc of Eq. 1-3 in the rear gripper's frame (V.B.1).
3. Each *contraction* keeps the front gripper fixed and brings the rear gripper to a body length ``S_min``
   behind it, turned towards the direction that makes the *next* extension follow the next segment:
   Eq. 8-18 (``method="proposed"``, Fig. 13b), or simply the front gripper's direction
   (``method="simple"``, Fig. 13a).  The rear pose follows Eq. 19-20 in the front gripper frame of Fig. 10
   (surface normal on ``x``): a holding gripper's direction is seated in the surface's tangent plane, so
   the rear gripper lands on that plane; given the bark (:class:`.bark.Bark`), it then grips the nearest
   point of the tree surface, not a point up to a few centimetres inside or above a curved bark.
4. The climb starts with the rear gripper on the path's first point (heading along the first segment) and
   the front gripper on the first path point at least ``S_min`` ahead, so both grippers start on the tree.

Along each extension or contraction the body shape is sampled at ``frames`` instants by interpolating the
arc parameters between the start and end shapes, in the frame of the gripper that holds (rear during an
extension, front during a contraction), so every sampled arc starts exactly at the holding gripper.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from climb_ompl.treebot.body import Posture, arc_end_tangent, arc_points, gripper_frame, interpolate, posture
from climb_ompl.treebot.fit import contraction, fit_segment, rear_direction, seated_direction
from climb_ompl.treebot.tree import RobotParams

Method = Literal["proposed", "simple"]
METHODS: tuple[str, ...] = ("proposed", "simple")
#: Arc fits of the proposed method: by geometric error, or the paper's algebraic least squares (Eq. 11-17).
ARC_FITS: tuple[str, ...] = ("geometric", "algebraic")


@dataclass
class Frame:
    """One sampled body shape.

    Attributes:
        step: index of the extension/contraction pair (0-based).
        phase: ``"extend"`` or ``"contract"``.
        body: ``(k, 3)`` arc samples from the rear gripper to the front gripper, world, metres.
        rear, front: gripper positions (world, metres); ``body[0]`` and ``body[-1]``.
        rear_dir, front_dir: unit body tangents at the grippers, pointing from rear to front.
        posture: arc parameters in the holding gripper's frame.
    """

    step: int
    phase: str
    body: np.ndarray
    rear: np.ndarray
    front: np.ndarray
    rear_dir: np.ndarray
    front_dir: np.ndarray
    posture: Posture

    def to_dict(self) -> dict:
        """JSON form."""
        return {"step": self.step, "phase": self.phase, "body": np.round(self.body, 9).tolist(),
                "rear": {"position": self.rear.tolist(), "direction": self.rear_dir.tolist()},
                "front": {"position": self.front.tolist(), "direction": self.front_dir.tolist()},
                "phi": self.posture.phi, "kappa": self.posture.kappa, "S": self.posture.S}


@dataclass
class Motion:
    """The whole motion: targets, per-step fits and sampled frames.

    Attributes:
        method: ``"proposed"`` or ``"simple"``.
        targets: path indices of the front-gripper targets (the first is the start).
        steps: per extension: target index, extension posture, rear direction ``v_rg`` and fitted arc.
        frames: sampled body shapes, in time order.
    """

    method: str
    targets: list[int]
    steps: list[dict] = field(default_factory=list)
    frames: list[Frame] = field(default_factory=list)

    def lengths(self) -> np.ndarray:
        """Body length ``S`` of every frame, metres."""
        return np.array([f.posture.S for f in self.frames])

    def to_dict(self) -> dict:
        """JSON form (``steps`` and ``frames``)."""
        return {"method": self.method, "targets": self.targets, "steps": self.steps,
                "frames": [f.to_dict() for f in self.frames]}


def segment_targets(points: np.ndarray, step: float) -> list[int]:
    """Indices of front-gripper targets: from each target, the farthest path point at most ``step`` further
    along the path (at least the next point); the last point always ends the list (Lam et al. (TreeBot), V.A.1)."""
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])
    out = [0]
    while out[-1] < len(points) - 1:
        i = out[-1]
        j = int(np.searchsorted(s, s[i] + step, side="right")) - 1
        out.append(max(j, i + 1))
    return out


def _sweep(origin: np.ndarray, R: np.ndarray, a: Posture, b: Posture, frames: int, k: int):
    """Arcs (world) from posture ``a`` to ``b`` in the gripper frame ``(origin, R)``, with end tangents."""
    for t in np.linspace(0.0, 1.0, frames)[1:] if frames > 1 else [1.0]:
        p = b if t == 1.0 else interpolate(a, b, float(t))
        pts = origin + arc_points(p, k) @ R.T
        yield p, pts, R @ arc_end_tangent(p)


def _on_bark(bark: Callable[[np.ndarray], np.ndarray], rear: np.ndarray, front: np.ndarray, Rf: np.ndarray,
             s_min: float) -> np.ndarray:
    """The bark point nearest to ``rear``, or, when the contracted arc to it is shorter than ``s_min`` (snapping
    to a convex bark shortens it), the bark point nearest to the point of the ray from the front gripper
    through ``rear`` whose arc is ``s_min`` long (bisection along the ray)."""
    def length(t: float) -> tuple[float, np.ndarray]:
        p = bark(front + t * u)
        return posture(Rf.T @ (p - front)).S, p

    lo = float(np.linalg.norm(rear - front))
    u = (rear - front) / lo
    s_lo, p = length(lo)
    if s_lo >= s_min:
        return p
    hi = lo
    for _ in range(8):
        hi *= 1.5
        s_hi, p_hi = length(hi)
        if s_hi >= s_min:
            break
    else:
        return p  # no bark point far enough on this side: the plan's length check refuses it
    for _ in range(40):
        mid = 0.5 * (lo + hi)
        s_mid, p_mid = length(mid)
        if s_mid >= s_min:
            hi, p_hi = mid, p_mid
        else:
            lo = mid
    return p_hi


def plan_motion(points: np.ndarray, normals: np.ndarray, robot: RobotParams, method: Method = "proposed",
                frames: int = 6, samples: int = 12, arc_fit: str = "geometric",
                bark: Callable[[np.ndarray], np.ndarray] | None = None) -> Motion:
    """Motion of TreeBot following the path ``points`` (``(P, 3)``, world, metres) with surface ``normals``.

    Args:
        points: the planned gripping points, start first.
        normals: unit surface normals at ``points``.
        robot: body parameters (``s_min``, ``step``; ``s_max`` is checked by the caller).
        method: ``"proposed"`` (Eq. 8-18) or ``"simple"`` (rear takes the front gripper's direction).
        frames: body shapes sampled per extension and per contraction.
        samples: points per sampled arc.
        arc_fit: ``"geometric"`` (default) or ``"algebraic"`` (the paper's Eq. 11-17), see :func:`.fit.fit_segment`.
        bark: nearest point of the tree surface to a point (e.g. :meth:`.bark.Bark.nearest`); the rear
            gripper of each contraction is put there.  ``None`` keeps it on the front gripper's tangent plane.
    """
    if method not in METHODS:
        raise ValueError(f"unknown method {method!r}; valid: {', '.join(METHODS)}")
    if arc_fit not in ARC_FITS:
        raise ValueError(f"unknown arc fit {arc_fit!r}; valid: {', '.join(ARC_FITS)}")
    P, N = np.asarray(points, float), np.asarray(normals, float)
    targets = segment_targets(P, robot.step)
    motion = Motion(method, targets)

    def want(seg: int, front_dir: np.ndarray) -> np.ndarray:
        if method == "simple":
            return front_dir
        fit = fit_segment(P[targets[seg]:targets[seg + 1] + 1], geometric=arc_fit == "geometric")
        return rear_direction(fit, robot.s_min)

    # Initial pose: the rear gripper on the start point, seated and heading along the first segment, the
    # front gripper on the first path point at least a contracted body length S_min ahead; both hold the tree.
    first = P[targets[1]] - P[0]
    rear_dir = seated_direction(first, N[0])
    rear, rear_normal = P[0].copy(), N[0]
    ahead = np.flatnonzero(np.linalg.norm(P - P[0], axis=1) >= robot.s_min)
    front = P[min(int(ahead[0]) if ahead.size else targets[1], targets[1])].copy()
    for seg in range(len(targets) - 1):
        # Extension: rear holds; front goes to the next target.
        Rr = gripper_frame(rear_dir, rear_normal)
        a = posture(Rr.T @ (front - rear))
        b = posture(Rr.T @ (P[targets[seg + 1]] - rear))
        for p, pts, tan in _sweep(rear, Rr, a, b, frames, samples):
            motion.frames.append(Frame(seg, "extend", pts, rear.copy(), pts[-1].copy(), rear_dir.copy(), tan, p))
        front, front_dir = motion.frames[-1].front, motion.frames[-1].front_dir
        step = {"step": seg, "target": targets[seg + 1], "extension": {"phi": b.phi, "kappa": b.kappa, "S": b.S}}
        if seg + 1 < len(targets) - 1:
            # Contraction: front holds; rear comes to s_min behind, turned towards v_rg.
            nf = N[targets[seg + 1]]
            # The front gripper holds the bark: its direction is seated in the tangent plane (Fig. 10).
            front_dir = seated_direction(front_dir, nf)
            v = want(seg + 1, front_dir)
            new_rear, _, th = contraction(front, front_dir, nf, v, robot.s_min)
            Rf = gripper_frame(-front_dir, nf)  # the body seen from the front gripper, backwards
            if bark is not None:  # Eq. 19-20 put it on the tangent plane; the gripper holds the bark itself
                new_rear = _on_bark(bark, new_rear, front, Rf, robot.s_min)
            a = posture(Rf.T @ (rear - front))
            b = posture(Rf.T @ (new_rear - front))
            for p, pts, tan in _sweep(front, Rf, a, b, frames, samples):
                motion.frames.append(Frame(seg, "contract", pts[::-1].copy(), pts[-1].copy(), front.copy(), -tan,
                                           front_dir.copy(), p))
            # The last sample ends exactly where the rear gripper grips; it keeps the body's direction there.
            rear, rear_dir, rear_normal = motion.frames[-1].rear, motion.frames[-1].rear_dir, nf
            end = motion.frames[-1].posture
            step.update({"v_rg": v.tolist(), "theta_rg": th,
                         "contraction": {"kappa": end.kappa, "S": end.S, "phi": end.phi}})
        motion.steps.append(step)
    return motion
