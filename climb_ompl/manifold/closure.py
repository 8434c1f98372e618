"""The kernel under FIND-TRANSITION: draw the base about a reference, close the contact chains, shift the CoM.

Bretl (2006), Fig. 17 lines 1-5, samples the pelvis position and closes every contact chain by inverse kinematics;
Bretl et al. (2004), sec. 3, samples the smaller stance's space and checks the other's equilibrium.  Every caller
here does the same three things, and this module does them once:

* **draw** (:meth:`DrawClose.step`, :meth:`DrawClose.place`, :meth:`DrawClose.batch`): base coordinates drawn
  about a reference configuration, a normal step per coordinate (its spread in metres or radians), plus, for a
  share of the draws, a random part of the shift that moves the CoM towards a target;
* **close** (:meth:`DrawClose.close`, :meth:`DrawClose.combinations`): each contact limb's hand put on its hold by
  the inverse-kinematics solution nearest a reference (:meth:`RobotModel.limb_ik_nearest
  <climb_ompl.model.robot.RobotModel.limb_ik_nearest>`; optionally a random one, or every one), in the robot's
  closing order (:meth:`RobotModel.closing_order <climb_ompl.model.robot.RobotModel.closing_order>`: base-moving
  limbs first, their inverse kinematics placing the base);
* **shift** (:func:`com_shift`): the change of the base coordinates that moves the CoM onto the centre of a
  support region (Bretl (2006), appendix B), to first order, through the CoM's Jacobian
  (:meth:`RobotModel.com_jacobian <climb_ompl.model.robot.RobotModel.com_jacobian>`).

Its users: FIND-TRANSITION's draws about the configuration reached and its wide draws
(:class:`climb_ompl.climb.transition.TransitionFinder`), the local search of :func:`closest_com` (the start finder and
FIND-TRANSITION's walk) and the samplers of stance manifolds (:class:`climb_ompl.manifold.samplers.SamplingCore`).
Each consumes its random numbers in its own order, so a seed gives the same draws as each did on its own.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable, Iterator, Mapping
from typing import Any

import numpy as np

from climb_ompl.manifold.stance import Stance, hand_targets


def com_shift(robot: Any, region: Any, q: np.ndarray, base: np.ndarray) -> np.ndarray:
    """The change of the base coordinates ``base`` that moves the CoM at ``q`` onto the centre of ``region``'s
    vertices, to first order: least squares through the columns ``base`` of the CoM's Jacobian, in the region's
    plane (:class:`~climb_ompl.equilibrium.region.SupportRegion` coordinates), metres or radians per coordinate."""
    c0 = np.asarray(robot.com(q), dtype=float)
    jc = np.asarray(robot.com_jacobian(q), dtype=float)[:, np.asarray(base, dtype=int)]
    err = np.asarray(region.vertices, dtype=float).mean(axis=0) - region.coords(c0)[0]
    return np.linalg.lstsq(region.basis @ jc, err, rcond=None)[0]


class DrawClose:
    """Draws of the base about a reference and closures of one stance's contact chains (the module docstring).

    Args:
        robot: the robot.
        targets: where each contact limb's hand frame goes, ``{limb: (3,)}`` (:func:`hand_targets`).
        last: limbs closed after the others (hands already on their holds; base-moving limbs still first).
        bounds: ``(lower, upper)`` of the configuration, ``(nq,)`` each (default the joint bounds): drawn base
            coordinates are clipped to them, and a solution outside them is refused.
    """

    def __init__(self, robot: Any, targets: Mapping[str, np.ndarray], *, last: Iterable[str] = (),
                 bounds: tuple[np.ndarray, np.ndarray] | None = None):
        self.robot, self.targets = robot, dict(targets)
        self.base = np.asarray(robot.base_indices, dtype=int)
        lo, hi = bounds if bounds is not None else (robot.lower, robot.upper)
        self.lo, self.hi = np.asarray(lo, dtype=float), np.asarray(hi, dtype=float)
        self._bounded = bounds is not None
        #: the limbs in the order they are closed
        self.order: list[str] = robot.closing_order(self.targets, last)
        #: the limb whose inverse kinematics failed at the last :meth:`close` (``None`` when every limb closed)
        self.failed: str | None = None

    @classmethod
    def of(cls, robot: Any, terrain: Any, stance: Stance, **kw: Any) -> DrawClose:
        """The kernel for ``stance``'s holds on ``terrain`` (``kw``: see the class)."""
        return cls(robot, hand_targets(robot, terrain, stance), **kw)

    # ---- draws --------------------------------------------------------------------------------------
    def step(self, rng: np.random.Generator, sd: np.ndarray, shift: Callable[[], np.ndarray] | None = None,
             share: tuple[float, float] = (0.3, 1.2)) -> np.ndarray:
        """A step of the base coordinates: ``normal(0, sd)`` per coordinate, plus, with ``shift``, the shift it
        returns times a share drawn uniformly in ``share`` (drawn after the normals; ``shift`` is called only then)."""
        step = rng.normal(0.0, 1.0, len(self.base)) * sd
        if shift is not None:
            s = shift()
            step = step + s * rng.uniform(*share)
        return step

    def place(self, ref: np.ndarray, step: np.ndarray) -> np.ndarray:
        """``ref`` with its base coordinates moved by ``step``, clipped to the bounds."""
        q = np.array(ref, dtype=float)
        b = self.base
        q[b] = np.minimum(np.maximum(q[b] + step, self.lo[b]), self.hi[b])
        return q

    def batch(self, rng: np.random.Generator, near: np.ndarray, idx: list[int], sd: np.ndarray,
              shift: Callable[[], np.ndarray], free_idx: np.ndarray) -> tuple[np.ndarray, set[int]]:
        """FIND-TRANSITION's draws ``idx`` about ``near`` at once
        (:meth:`climb_ompl.climb.transition.TransitionFinder.find`): draw ``a > 0`` moves the base by
        ``normal(0, sd (1 + a / 20))``, odd draws plus ``shift()`` times a share in ``[0.3, 1.2]`` (:meth:`step`
        with a spread growing with ``a``), and every third draw (``a % 3 == 2``) puts the free limbs' joints
        ``free_idx`` anywhere within their bounds.  The random numbers are drawn in the order one draw at a time takes
        them (``standard_normal`` for ``normal(0, 1)``, ``low + (high - low) * random()`` for ``uniform``: the same
        values).  Returns the configurations ``(len(idx), nq)`` and the rows whose free limbs moved."""
        base, nb = self.base, len(self.base)
        k = len(idx)
        Q = np.repeat(near[None, :], k, axis=0)
        moved = [i for i, a in enumerate(idx) if a > 0 and nb]
        free_rows: set[int] = set()
        if not moved and not free_idx.size:
            return Q, free_rows
        N, U = np.zeros((k, nb)), np.zeros(k)
        F = np.empty((k, free_idx.size))
        normal, uniform = rng.standard_normal, rng.random
        for i, a in enumerate(idx):
            if a > 0 and nb:
                normal(out=N[i])
                if a % 2 == 1:
                    U[i] = uniform()
            if free_idx.size and a % 3 == 2:
                uniform(out=F[i])
                free_rows.add(i)
        if free_rows:
            rows = sorted(free_rows)
            lo_f = self.lo[free_idx]
            Q[np.ix_(rows, free_idx)] = lo_f + (self.hi[free_idx] - lo_f) * F[rows]
        if moved:
            a_s = np.array(idx)
            step = N * sd * (1.0 + a_s / 20.0)[:, None]
            odd = a_s % 2 == 1
            step[odd] = step[odd] + shift() * (0.3 + (1.2 - 0.3) * U[odd])[:, None]
            Q[np.ix_(moved, base)] = np.minimum(np.maximum(near[base] + step[moved], self.lo[base]), self.hi[base])
        return Q, free_rows

    # ---- closure ------------------------------------------------------------------------------------
    def solve(self, limb: str, q: np.ndarray, target: np.ndarray | None = None, near: np.ndarray | None = None, *,
              rng: np.random.Generator | None = None, same_bend: bool = False,
              prefer_bend: bool = False) -> np.ndarray | None:
        """``limb``'s hand put on ``target`` (default its hold's target) from ``q``: the solution nearest ``near``
        (``same_bend``, ``prefer_bend``: as :meth:`~climb_ompl.model.robot.RobotModel.limb_ik_nearest`), or without
        ``near`` one drawn with ``rng``; within the bounds, when given; ``None`` when there is none."""
        r = self.robot
        target = self.targets[limb] if target is None else target
        if near is not None and not self._bounded:
            return r.limb_ik_nearest(limb, q, target, near, same_bend=same_bend, prefer_bend=prefer_bend)
        sols = r.limb_ik(limb, q, target)
        if self._bounded:
            sols = [s for s in sols if np.all(s >= self.lo - 1e-9) and np.all(s <= self.hi + 1e-9)]
        if not sols:
            return None
        if near is not None:
            idx = list(r.limb(limb).joint_indices)
            return min(sols, key=lambda x: float(np.sum((x[idx] - near[idx]) ** 2)))
        if rng is None:
            raise ValueError("a closure without a reference configuration draws its solution: give rng")
        return np.asarray(sols[int(rng.integers(len(sols)))], dtype=float)

    def close(self, q: np.ndarray, near: np.ndarray | None = None, *, limbs: Iterable[str] | None = None,
              keep: Iterable[str] = (), prefer: str | None = None,
              rng: np.random.Generator | None = None) -> np.ndarray | None:
        """``q`` with the contact limbs' chains closed, ``limbs`` in that order (default :attr:`order`): each limb by
        the solution nearest ``near`` (the limbs in ``keep`` only with the elbow bend of ``near``, ``prefer`` with it
        first), or, without ``near``, by one drawn with ``rng`` (:meth:`solve`).  ``None`` at the first limb with no
        solution, named by :attr:`failed`."""
        kept = set(keep)
        self.failed = None
        for lb in self.order if limbs is None else limbs:
            sol = self.solve(lb, q, near=near, rng=rng, same_bend=lb in kept, prefer_bend=lb == prefer)
            if sol is None:
                self.failed = lb
                return None
            q = sol
        return q

    def combinations(self, q: np.ndarray, near: np.ndarray, limbs: list[str],
                     on_fail: Callable[[str], None] = lambda limb: None) -> Iterator[np.ndarray]:
        """Every combination of the solutions of ``limbs`` (in that order), each limb's nearest ``near`` first
        (Bretl (2006), Fig. 17 line 3: every elbow bend); ``on_fail`` is called with a limb each time it has no
        solution."""
        if not limbs:
            yield q
            return
        lb, rest = limbs[0], limbs[1:]
        sols = self.robot.limb_ik(lb, q, self.targets[lb])
        if not sols:
            on_fail(lb)
            return
        idx = list(self.robot.limb(lb).joint_indices)
        for s in sorted(sols, key=lambda x: float(np.sum((x[idx] - near[idx]) ** 2))):
            yield from self.combinations(s, near, rest, on_fail)


#: Base draws of :func:`closest_com`.
CLOSEST_DRAWS: int = 200


def closest_com(robot: Any, terrain: Any, closed: Stance, sigma: Stance, feas: Any, near: np.ndarray, *,
                draws: int = CLOSEST_DRAWS, seed: int = 0, stop_inside: bool = True) -> \
        tuple[float, int, np.ndarray | None]:
    """How near the support region of ``sigma`` the CoM gets over configurations with every limb of ``closed``
    on its hold, within the joint limits and free of collision (hands touching their holds allowed): the
    largest signed distance found (positive inside, :meth:`SupportRegion.margin`) and the number of such
    configurations met, and the configuration of the largest (``None`` when none was met).  ``stop_inside``:
    stop at the first configuration whose CoM is inside the region (else go on towards its centre).

    A local search, not a proof: the base coordinates are drawn about the best so far (starting at ``near``, a
    spread of 0.05 m and 0.15 rad halving every quarter of the draws), half of the draws shifted towards the
    region's centre by a share in ``[0.1, 0.5]`` of :func:`com_shift`, and each limb is closed by the
    inverse-kinematics solution nearest ``near`` (Bretl 2006, Fig. 17 lines 1-5, as
    :class:`~climb_ompl.climb.transition.TransitionFinder`); ``feas`` gives the region and the clearance.
    """
    region = feas.region(sigma)
    if region.is_empty:
        return -float("inf"), 0, None
    rng = np.random.default_rng(seed)
    kernel = DrawClose.of(robot, terrain, closed)
    lo, hi = kernel.lo, kernel.hi
    angles = robot.angle_joints[kernel.base]
    best_q, best, met, found = np.asarray(near, dtype=float), -float("inf"), 0, None
    for i in range(draws):
        sd = np.where(angles, 0.15, 0.05) * 0.5 ** (4 * i // max(draws, 1))
        q = best_q
        if i:
            shift = (lambda at=best_q: com_shift(robot, region, at, kernel.base)) if i % 2 else None
            q = kernel.place(best_q, kernel.step(rng, sd, shift, share=(0.1, 0.5)))
        q = kernel.close(q, near)
        if q is None:
            continue
        if np.any(q < lo - 1e-9) or np.any(q > hi + 1e-9) or robot.in_collision(
                q, terrain, contact_limbs=closed.limbs, clearance=feas.clearance):
            continue
        met += 1
        m = float(region.margin(robot.com(q)))
        if m > best:
            best, best_q, found = m, q, q
            if m >= 0 and stop_inside:
                break
    return best, met, found


__all__ = ["DrawClose", "com_shift", "closest_com", "CLOSEST_DRAWS"]
