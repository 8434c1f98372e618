"""Inverse kinematics of one limb: the closed forms and damped least squares behind
:meth:`climb_ompl.model.robot.RobotModel.limb_ik` and :meth:`~climb_ompl.model.robot.RobotModel.limb_ik_nearest`.

Closed forms (:func:`analytic_chain` recognises them from the URDF's joint axes):

* two revolute joints with parallel axes (the planar robots; Bretl, Latombe & Rock (2003), sec. 3; Bretl
  (2006), sec. 2.1-2.2), optionally followed by a third revolute joint whose axis is not parallel to them
  (LEMUR's yaw-yaw-pitch limb, Bretl et al. (2004), sec. 2): the pitch angle is fixed by the target's distance
  from the plane of the yaw joints, then the two yaw angles solve a planar two-link problem (law of cosines,
  one solution per elbow bend), :class:`AnalyticChain`, :func:`ik_analytic`;
* abduction-pitch-pitch legs (a quadruped's hip, thigh and knee): the abduction angle first, then the same
  two-link solve, :class:`AbductionChain`, :func:`ik_abduction`.

Every other limb is solved numerically (:func:`ik_numeric`: damped least squares on Pinocchio's frame Jacobian,
seeded restarts).  The functions take the :class:`~climb_ompl.model.robot.RobotModel` (its Pinocchio model and data,
joint bounds and hand positions) as their first argument.
"""

from __future__ import annotations

import itertools
import math
from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import cached_property
from typing import Any

import numpy as np

from climb_ompl.model.joints import elementary

__all__ = ["AnalyticChain", "AbductionChain", "analytic_chain", "ik_analytic", "ik_abduction", "ik_numeric",
           "revolute_axis", "wrap_into", "IK_STALL", "IK_STALL_GAIN"]

#: Numeric IK (damped least squares): a restart stops when its smallest error has not fallen by ``IK_STALL_GAIN``
#: of itself over the last ``IK_STALL`` iterations (iterations; relative gain).  The restarts that converge do so
#: well before such a stall (docs/robots.md, "Inverse kinematics").
IK_STALL = 20
IK_STALL_GAIN = 1e-6


#: Joint bounds narrower than this (radians, less than a turn) hold at most one value of an angle modulo a turn
#: (:func:`_into`).
_NARROW = 6.0


def _f3(v: Any) -> tuple[float, float, float]:
    """A 3-vector as three floats."""
    return float(v[0]), float(v[1]), float(v[2])


@dataclass(frozen=True)
class AnalyticChain:
    """Constants of a yaw-yaw(-pitch) limb for closed-form IK (all in the first joint's frame at angle 0).

    Hand = R(a, t1) [p_e + R(a, s t2) R_e p(t3)],  p(t3) = p_w + R_w R(b, t3) p_h  (3 joints) or p_h (2 joints).
    """

    a: np.ndarray
    s: float
    p_e: np.ndarray
    R_e: np.ndarray
    p_h: np.ndarray
    p_w: np.ndarray | None = None
    R_w: np.ndarray | None = None
    b: np.ndarray | None = None
    #: the first joint's parent joint and its placement there (read once: :func:`ik_analytic` needs them per call;
    #: read from the model at each call when not given)
    parent: int = -1
    placement: Any = None

    @cached_property
    def terms(self) -> dict[str, Any]:
        """The target-independent terms of the closed form as floats (see :func:`ik_analytic`).

        With ``w`` the part of the elbow-to-hand vector ``v = R_e p(t3)`` perpendicular to ``a`` and ``u`` that of
        ``p_e``: ``v`` is affine in ``(cos t3, sin t3)`` (Rodrigues' formula), so are ``w`` and the dot products
        the solve needs.
        """
        a = self.a
        ape = float(a @ self.p_e)
        u = self.p_e - ape * a
        out: dict[str, Any] = {"a": _f3(a), "ape": ape, "u": _f3(u), "uu": float(u @ u), "ua": _f3(np.cross(u, a))}
        if self.b is None:
            out["planar"] = float(a @ (self.p_e + self.R_e @ self.p_h))
            out["v"] = [_f3(self.R_e @ self.p_h), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0)]
            return out
        b, p_h = self.b, self.p_h
        cw = self.R_w.T @ self.R_e.T @ a  # a expressed in the pitch joint's frame
        bp = float(b @ p_h)
        p_par = bp * b
        out["alpha"], beta, gamma = float(cw @ p_par), float(cw @ (p_h - p_par)), float(cw @ _cross(b, p_h))
        out["aRpw"] = float(a @ (self.R_e @ self.p_w))
        out["rho"], out["base"] = math.hypot(beta, gamma), math.atan2(gamma, beta)
        m = self.R_e @ self.R_w
        vb = bp * (m @ b)
        # v(t3) = v0 + c vc + s vs
        out["v"] = [_f3(self.R_e @ self.p_w + vb), _f3(m @ p_h - vb), _f3(m @ np.cross(b, p_h))]
        return out


@dataclass(frozen=True)
class AbductionChain:
    """Constants of an abduction-pitch-pitch leg (a quadruped's hip, thigh and knee) for closed-form IK.

    The first joint turns about ``a`` (its own frame); the next two have parallel axes, so the hand's
    component along their axis is a constant.  In the first joint's frame at angle 0, with ``b2`` the second
    joint's axis there, the first angle solves ``(R(a, t1) b2) . t = k`` for a target ``t``; the other two
    then solve the planar two-link problem of ``sub`` (:class:`AnalyticChain` of the last two joints).
    """

    a: np.ndarray
    b2: np.ndarray
    k: float
    sub_limb: Any
    sub: AnalyticChain
    #: as :attr:`AnalyticChain.parent` and :attr:`AnalyticChain.placement` (:func:`_first_frame`)
    parent: int = -1
    placement: Any = None

    @cached_property
    def terms(self) -> tuple[float, np.ndarray, np.ndarray]:
        """``a . b2``, ``b2``'s part across ``a`` and ``a`` cross that part (:func:`ik_abduction`)."""
        a, b2 = self.a, self.b2
        perp = b2 - (a @ b2) * a
        return float(a @ b2), perp, _cross(a, perp)


def _same(a: np.ndarray, b: np.ndarray) -> bool:
    """``np.allclose(a, b, atol=1e-12)`` (its default ``rtol = 1e-5``) without its per-call overhead: the
    inverse kinematics de-duplicates its solutions with it a few hundred thousand times per climb."""
    return bool(np.all(np.abs(a - b) <= 1e-12 + 1e-5 * np.abs(b)))


def _same_values(a: tuple[float | None, ...], b: tuple[float | None, ...]) -> bool:
    """:func:`_same` on the joint values of two closed-form candidates (floats; the solutions they give differ only
    there)."""
    return all(abs(x - y) <= 1e-12 + 1e-5 * abs(y) for x, y in zip(a, b, strict=True))  # type: ignore[operator]


def _unique(sols: list[np.ndarray], idx: list[int]) -> list[np.ndarray]:
    """``sols`` without the later of any two that are :func:`_same`, in order.  The solutions differ only at
    ``idx`` (a limb's joints), so each is compared only with those in its own and the neighbouring cells of a grid
    on those coordinates whose spacing exceeds :func:`_same`'s tolerance: linear in the number of solutions, where
    comparing every pair is quadratic (a URDF's placeholder range of +-10 rad gives a leg's IK about a hundred
    whole-turn copies of each solution)."""
    if len(sols) < 8:
        out: list[np.ndarray] = []
        for sol in sols:
            if not any(_same(sol, r_) for r_ in out):
                out.append(sol)
        return out
    vals = [[float(sol[i]) for i in idx] for sol in sols]
    w = 2e-3 + 2e-5 * max(abs(v) for row in vals for v in row)  # > 1e-12 + 1e-5 |b| for every value
    cells: dict[tuple[int, ...], list[np.ndarray]] = {}
    offsets = list(itertools.product((-1, 0, 1), repeat=len(idx)))
    out = []
    for sol, row in zip(sols, vals, strict=True):
        cell = tuple(math.floor(v / w) for v in row)
        near = (tuple(c + d for c, d in zip(cell, o, strict=True)) for o in offsets)
        if any(_same(sol, r_) for n in near for r_ in cells.get(n, ())):
            continue
        cells.setdefault(cell, []).append(sol)
        out.append(sol)
    return out


def _cross(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``np.cross`` for two 3-vectors, ten times cheaper (no axis handling)."""
    a0, a1, a2 = (float(v) for v in a)
    b0, b1, b2 = (float(v) for v in b)
    return np.array((a1 * b2 - a2 * b1, a2 * b0 - a0 * b2, a0 * b1 - a1 * b0))


def wrap_into(angle: float, lo: float, hi: float, eps: float = 1e-12) -> list[float]:
    """All values ``angle + 2 pi k`` inside ``[lo, hi]`` (joints bounded by more than 2 pi have several)."""
    two_pi = 2.0 * math.pi
    k0 = math.ceil((lo - eps - angle) / two_pi)
    first = angle + k0 * two_pi
    if first > hi + eps:
        return []
    if angle + (k0 + 1) * two_pi > hi + eps:  # one value (always so for a joint bounded by less than 2 pi)
        return [min(max(first, lo), hi)]
    out = []
    k = k0
    while angle + k * two_pi <= hi + eps:
        out.append(min(max(angle + k * two_pi, lo), hi))
        k += 1
    return out


def _into(angle: float, lo: float, hi: float) -> list[float]:
    """:func:`wrap_into` with its default ``eps``, the same values to the bit (a zero's sign included), and the
    common case first: an angle inside bounds narrower than :data:`_NARROW` is its only value, clamped to them."""
    if hi - lo < _NARROW and lo - 1e-12 <= angle <= hi + 1e-12:
        return [min(max(angle + 0.0, lo), hi)]  # (+ 0.0: wrap_into adds zero turns, which makes -0.0 0.0)
    return wrap_into(angle, lo, hi)


def revolute_axis(m: Any, j: int) -> np.ndarray | None:
    """Unit axis of revolute joint ``j`` in its own frame, or ``None`` for any other joint (read from its type,
    :func:`climb_ompl.model.joints.elementary`)."""
    kind = elementary(m.joints[j])
    return kind[1] if kind is not None and kind[0] == "R" else None


def analytic_chain(m: Any, pin: Any, lb: Any) -> AnalyticChain | AbductionChain | None:
    """Closed-form IK constants if the limb is yaw-yaw or yaw-yaw-pitch (see :class:`AnalyticChain`), or
    abduction-pitch-pitch (:class:`AbductionChain`, a quadruped's leg)."""
    jids = lb.joint_ids
    if len(jids) not in (2, 3):
        return None
    if len(jids) == 3 and m.parents[jids[1]] == jids[0] and revolute_axis(m, jids[0]) is not None:
        sub_limb = replace(lb, joint_ids=jids[1:], joint_indices=lb.joint_indices[1:])
        sub = analytic_chain(m, pin, sub_limb)
        a = revolute_axis(m, jids[0])
        R2 = np.array(m.jointPlacements[jids[1]].rotation)
        if sub is not None and sub.b is None and abs(abs(float(a @ (R2 @ sub.a))) - 1.0) > 1e-9:
            # hand component along the parallel axes (joint 2's frame): constant whatever t2, t3
            k = float(sub.a @ (sub.p_e + sub.R_e @ sub.p_h))
            b2 = R2 @ sub.a
            return AbductionChain(a, b2, k + float(b2 @ np.array(m.jointPlacements[jids[1]].translation)),
                                  sub_limb, sub, parent=int(m.parents[jids[0]]),
                                  placement=m.jointPlacements[jids[0]].copy())
    axes = []
    for j in jids:
        ax = revolute_axis(m, j)
        if ax is None:
            return None
        axes.append(ax)
    for k in range(1, len(jids)):
        if m.parents[jids[k]] != jids[k - 1]:
            return None
    fr = m.frames[lb.frame_id]
    if fr.parentJoint != jids[-1]:
        return None
    a = axes[0]
    R_e = np.array(m.jointPlacements[jids[1]].rotation)
    p_e = np.array(m.jointPlacements[jids[1]].translation)
    dot = float(a @ (R_e @ axes[1]))
    if abs(abs(dot) - 1.0) > 1e-9:
        return None
    s = 1.0 if dot > 0 else -1.0
    p_h = np.array(fr.placement.translation)
    if len(jids) == 2:
        return AnalyticChain(a, s, p_e, R_e, p_h, parent=int(m.parents[jids[0]]),
                             placement=m.jointPlacements[jids[0]].copy())
    R_w = np.array(m.jointPlacements[jids[2]].rotation)
    p_w = np.array(m.jointPlacements[jids[2]].translation)
    b = axes[2]
    if abs(abs(float(a @ (R_e @ (R_w @ b)))) - 1.0) < 1e-9:
        return None  # a third parallel axis: a redundant planar 3R limb, solved numerically
    return AnalyticChain(a, s, p_e, R_e, p_h, p_w, R_w, b, parent=int(m.parents[jids[0]]),
                         placement=m.jointPlacements[jids[0]].copy())


def _first_frame(robot: Any, lb: Any, c: AnalyticChain | AbductionChain) -> Any:
    """The world placement of ``lb``'s first joint at angle 0, after forward kinematics: its parent joint's placement
    times its own, from the chain's (read once, :func:`analytic_chain`) or, for a chain built without them, the
    model's."""
    m, d = robot.model, robot.data
    if c.placement is None:
        j1 = lb.joint_ids[0]
        return d.oMi[m.parents[j1]] * m.jointPlacements[j1]
    return d.oMi[c.parent] * c.placement


def _arrays(q: Any, target: Any, ref: Any) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """``q``, ``target`` and ``ref`` as float arrays (sequences accepted; arrays already so pass unchanged)."""
    if not (isinstance(q, np.ndarray) and q.dtype == np.float64 and q.flags.c_contiguous):
        q = np.ascontiguousarray(q, dtype=float)
    if not (isinstance(target, np.ndarray) and target.dtype == np.float64 and target.shape == (3,)):
        target = np.asarray(target, dtype=float).reshape(3)
    if ref is not None and not (isinstance(ref, np.ndarray) and ref.dtype == np.float64):
        ref = np.asarray(ref, dtype=float)
    return q, target, ref


def ik_analytic(robot: Any, lb: Any, c: AnalyticChain, q: np.ndarray, target: np.ndarray,
                 ref: np.ndarray | None = None,
                 bend: tuple[int, float, float] | None = None, prefer: bool = False) -> list[np.ndarray]:
    """Every closed-form solution of an :class:`AnalyticChain` (see :meth:`~climb_ompl.model.robot.RobotModel.limb_ik`);
    with ``ref``, only the one nearest ``ref``, and with ``bend`` (``(index into q, straight value, sign)``) too,
    only among those whose elbow bends that way (``prefer``: the nearest of any bend when none does)."""
    q, target, ref = _arrays(q, target, ref)
    out, scale = _analytic_angles(robot, lb, c, q, target)
    return _solutions(robot, lb, target, [(v, 1e-8 * scale, q) for v in out], ref, bend, prefer)


def _analytic_angles(robot: Any, lb: Any, c: AnalyticChain, q: np.ndarray,
                     target: np.ndarray) -> tuple[list[tuple[float, float, float | None]], float]:
    """The candidate angles of :func:`ik_analytic` (the limb's joints, ``None`` for a missing third) before the check
    that the hand lies on the target, and the scale of that check (one plus the target's distance from the first
    joint).

    In the first joint's frame (target ``t``, unit axis ``a``), the pitch angle ``t3`` is fixed by
    ``a . hand = a . t``; then ``hand - (a . hand) a = u + R(a, phi) w`` (``phi = s t2``) has the length of
    ``t``'s part across ``a``, which gives ``phi`` by the law of cosines, and ``t1`` turns that vector onto
    ``t``.  Written on floats (:attr:`AnalyticChain.terms`): it is called a few hundred thousand times per
    climb, so the joint bounds are read once per call and an angle inside bounds narrower than a turn is taken as
    it is (:func:`_into`).
    """
    pin, m, d = robot._pin, robot.model, robot.data
    k = c.terms
    pin.forwardKinematics(m, d, q)
    tx, ty, tz = _first_frame(robot, lb, c).actInv(target).tolist()
    ax, ay, az = k["a"]
    ta = ax * tx + ay * ty + az * tz
    scale = 1.0 + math.sqrt(tx * tx + ty * ty + tz * tz)
    idx = lb.joint_indices
    lower, upper = robot.lower, robot.upper
    if c.b is None:
        if abs(ta - k["planar"]) > 1e-9 * scale:
            return [], scale
        t3s: list[float | None] = [None]
    else:
        rhs = ta - k["ape"] - k["aRpw"] - k["alpha"]
        rho = k["rho"]
        if rho < 1e-12 or abs(rhs) > rho * (1 + 1e-12):
            return [], scale
        off = math.acos(max(-1.0, min(1.0, rhs / rho)))
        t3s = [k["base"] + off, k["base"] - off]
    px, py, pz = tx - ta * ax, ty - ta * ay, tz - ta * az  # t across a
    ux, uy, uz = k["u"]
    uax, uay, uaz = k["ua"]  # u x a = -(a x u)
    (v0x, v0y, v0z), (vcx, vcy, vcz), (vsx, vsy, vsz) = k["v"]
    i1, i2 = idx[0], idx[1]
    lo1, hi1, lo2, hi2 = lower.item(i1), upper.item(i1), lower.item(i2), upper.item(i2)
    pp = (px * px + py * py + pz * pz) - k["uu"]
    out: list[tuple[float, float, float | None]] = []
    for t3 in t3s:
        t3_vals: list[float | None] = [None]
        cs, sn = 0.0, 0.0
        if t3 is not None:
            lo3, hi3 = lower.item(idx[2]), upper.item(idx[2])
            t3_vals = _into(t3, lo3, hi3)
            if not t3_vals:
                continue
            cs, sn = math.cos(t3), math.sin(t3)
        vx, vy, vz = v0x + cs * vcx + sn * vsx, v0y + cs * vcy + sn * vsy, v0z + cs * vcz + sn * vsz
        av = ax * vx + ay * vy + az * vz
        wx, wy, wz = vx - av * ax, vy - av * ay, vz - av * az
        A = ux * wx + uy * wy + uz * wz
        B = uax * wx + uay * wy + uaz * wz  # u . (a x w)
        C = (pp - (wx * wx + wy * wy + wz * wz)) / 2.0
        r = math.hypot(A, B)
        if r < 1e-12 or abs(C) > r * (1 + 1e-12):
            continue
        g0, g1 = math.atan2(B, A), math.acos(max(-1.0, min(1.0, C / r)))
        # a x w and a x z = a x u + cos(phi) a x w - sin(phi) w (w is across a)
        awx, awy, awz = ay * wz - az * wy, az * wx - ax * wz, ax * wy - ay * wx
        for phi in {g0 + g1, g0 - g1}:
            cp, sp = math.cos(phi), math.sin(phi)
            zx, zy, zz = ux + cp * wx + sp * awx, uy + cp * wy + sp * awy, uz + cp * wz + sp * awz
            azx, azy, azz = cp * awx - sp * wx - uax, cp * awy - sp * wy - uay, cp * awz - sp * wz - uaz
            t1 = math.atan2(azx * px + azy * py + azz * pz, zx * px + zy * py + zz * pz)
            t2 = c.s * phi
            for v1 in _into(t1, lo1, hi1):
                for v2 in _into(t2, lo2, hi2):
                    for v3 in t3_vals:
                        out.append((v1, v2, v3))
    return out, scale


Candidate = tuple[tuple[float, float, float | None], float, np.ndarray]
"""A closed form's candidate: its angles of the limb's joints (``None`` for a missing third), the tolerance of the
check that its hand lies on the target, and the configuration whose limb joints it replaces."""


def _solutions(robot: Any, lb: Any, target: np.ndarray, cands: list[Candidate], ref: np.ndarray | None,
               bend: tuple[int, float, float] | None, prefer: bool,
               nearest: Callable[[Candidate], Any] | None = None) -> list[np.ndarray]:
    """The closed forms' solutions from their candidates: each one whose hand lies within its tolerance of the target
    (guards degenerate cases).  With ``ref``, only the nearest to ``ref`` with the elbow ``bend`` (see
    :func:`ik_analytic`; ``nearest``: the sort key, by default the squared distance over the limb's joints), the
    candidates checked nearest first until one is; without, all of them, duplicates dropped."""
    if not cands:
        return []
    pin, m, d = robot._pin, robot.model, robot.data
    fid = lb.frame_id
    tgx, tgy, tgz = target.tolist()
    upd = pin.updateFramePlacement
    idx = lb.joint_indices
    i1, i2 = idx[0], idx[1]
    i3 = idx[2] if len(idx) > 2 else -1

    def exact(cand: Candidate) -> np.ndarray | None:
        """The configuration of the candidate if its hand lies on the target, else ``None``."""
        v, tol, base = cand
        sol = base.copy()
        sol[i1], sol[i2] = v[0], v[1]
        if v[2] is not None:
            sol[i3] = v[2]
        pin.forwardKinematics(m, d, sol)
        hx, hy, hz = upd(m, d, fid).translation.tolist()
        ex, ey, ez = hx - tgx, hy - tgy, hz - tgz
        return sol if math.sqrt(ex * ex + ey * ey + ez * ez) <= tol else None

    if ref is not None:
        if nearest is None:
            r0, r1 = ref.item(i1), ref.item(i2)
            r2 = ref.item(i3) if i3 >= 0 else 0.0

            def nearest(c: Candidate) -> float:
                v = c[0]
                return (v[0] - r0) ** 2 + (v[1] - r1) ** 2 + (0.0 if v[2] is None else (v[2] - r2) ** 2)
        if len(cands) > 1:
            cands = sorted(cands, key=nearest)
        k_b, straight, sign = (-1, 0.0, 0.0) if bend is None else (list(idx).index(bend[0]), bend[1], bend[2])
        other: np.ndarray | None = None  # with ``prefer``: the nearest exact solution of the other bend
        for cand in cands:
            if k_b >= 0:
                e = cand[0][k_b]
                wrong = e is None or ((e > straight) - (e < straight)) != sign
            else:
                wrong = False
            if wrong and (not prefer or other is not None):
                continue
            sol = exact(cand)
            if sol is not None:
                if not wrong:
                    return [sol]
                other = sol
        return [] if other is None else [other]
    res = [sol for sol in map(exact, cands) if sol is not None]
    return _unique(res, list(idx))


def ik_abduction(robot: Any, lb: Any, c: AbductionChain, q: np.ndarray, target: np.ndarray,
                 ref: np.ndarray | None = None, bend: tuple[int, float, float] | None = None,
                 prefer: bool = False) -> list[np.ndarray] | None:
    """Closed-form IK of an abduction-pitch-pitch leg (:class:`AbductionChain`): every first-joint angle
    solving ``alpha + beta cos t1 + gamma sin t1 = k``, each followed by the two-link solve.

    With ``ref`` (and ``bend``, ``prefer``, as :func:`ik_analytic`), only the solution of the full list nearest
    ``ref`` (:meth:`~climb_ompl.model.robot.RobotModel.limb_ik_nearest` on it: squared distances summed as NumPy sums
    them, ties to the one nearest ``q``), found by checking the nearest candidates only; ``None`` when two candidates
    are duplicates within :func:`_same` (the full list keeps only the first: take the nearest from it)."""
    q, target, ref = _arrays(q, target, ref)
    robot._pin.forwardKinematics(robot.model, robot.data, q)
    t = np.array(_first_frame(robot, lb, c).actInv(target))
    ab2, perp, cross = c.terms  # (the dot products as NumPy rounds them: float sums differ in the last bit)
    alpha, beta, gamma = ab2 * float(c.a @ t), float(perp @ t), float(cross @ t)
    rho = math.hypot(beta, gamma)
    if rho < 1e-12 or abs(c.k - alpha) > rho * (1 + 1e-12):
        return []
    base_ang, off = math.atan2(gamma, beta), math.acos(max(-1.0, min(1.0, (c.k - alpha) / rho)))
    i1 = lb.joint_indices[0]
    groups: list[list[Candidate]] = []  # per first-joint angle
    for t1 in {base_ang + off, base_ang - off}:
        for v1 in wrap_into(t1, robot.lower[i1], robot.upper[i1]):
            q1 = q.copy()
            q1[i1] = v1
            angles, scale = _analytic_angles(robot, c.sub_limb, c.sub, q1, target)
            groups.append([((v1, v[0], v[1]), 1e-8 * scale, q1) for v in angles])
    if ref is None:  # each angle's two-link solutions without duplicates, then all of them
        return _unique([sol for g in groups for sol in _solutions(robot, lb, target, g, None, None, False)],
                       list(lb.joint_indices))
    cands = [cand for g in groups for cand in g]
    vals = [cand[0] for cand in cands]
    if any(_same_values(a, b) for i, a in enumerate(vals) for b in vals[:i]):
        return None
    idx = lb.joint_indices
    r = [ref.item(i) for i in idx]
    q_l = [q.item(i) for i in idx]

    def nearest(cand: Candidate) -> tuple[float, float]:
        v = cand[0]
        d0, d1, d2 = v[0] - r[0], v[1] - r[1], v[2] - r[2]  # type: ignore[operator]
        return d0 * d0 + d1 * d1 + d2 * d2, math.fsum((x - y) ** 2 for x, y in zip(v, q_l, strict=True))

    return _solutions(robot, lb, target, cands, ref, bend, prefer, nearest)


def ik_numeric(robot: Any, lb: Any, q: np.ndarray, target: np.ndarray, tol: float,
               max_iter: int = 200, restarts: int = 8) -> list[np.ndarray]:
    """At most one solution by damped least squares on the hand frame's Jacobian (Pinocchio), from ``q`` and then
    from up to ``restarts`` seeded random starts within the joint bounds; a restart stops after ``max_iter``
    iterations or when its error stalls (:data:`IK_STALL`).  An all-revolute limb's target farther than
    :attr:`Limb.reach <climb_ompl.model.robot.Limb.reach>` from its first joint is refused at once."""
    pin, m, d = robot._pin, robot.model, robot.data
    idx = np.array(lb.joint_indices)
    lo, hi = robot.lower[idx], robot.upper[idx]
    revolute = robot.all_revolute(lb.name)
    if revolute and np.linalg.norm(target - robot.limb_fk(q, lb)[0]) > lb.reach + 1e-9:
        return []  # farther than the sum of the link lengths
    eye = np.eye(3)
    rng = np.random.default_rng(0)
    lwa = pin.ReferenceFrame.LOCAL_WORLD_ALIGNED
    for attempt in range(restarts + 1):
        x = q.copy()
        if attempt:
            x[idx] = rng.uniform(lo, hi)
        lam = 1e-2
        err_prev = np.inf
        best: list[float] = []  # the smallest error so far, per iteration
        for it in range(max_iter):
            J = pin.computeFrameJacobian(m, d, x, lb.frame_id, lwa)[:3, idx]  # (it places the joints too)
            e = target - pin.updateFramePlacement(m, d, lb.frame_id).translation
            err = math.sqrt(float(e @ e))  # np.linalg.norm's own formula, without its overhead
            if err < tol:
                return [x]
            best.append(min(err, best[-1]) if best else err)
            if it >= IK_STALL and best[-1 - IK_STALL] - best[-1] < IK_STALL_GAIN * best[-1 - IK_STALL]:
                break  # stuck (a local minimum, or a target outside the limits): the next restart
            lam = max(lam * 0.5, 1e-4) if err < err_prev else min(lam * 4.0, 1.0)  # floor: J J^T may be singular
            err_prev = err
            dq = J.T @ np.linalg.solve(J @ J.T + lam**2 * eye, e)
            x[idx] = np.minimum(np.maximum(x[idx] + dq, lo), hi)  # np.clip, without its overhead
    return []
