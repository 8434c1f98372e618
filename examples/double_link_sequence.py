"""Plan the double-link robot's climb from peg 1 to peg 4 and draw it (Bretl (2006), Fig. 3, 6 and 13).

Run: ``python examples/double_link_sequence.py [--out docs/climb_double_link.png]``.

The multi-step planner (:func:`climb_ompl.plan_climb`) finds the stance sequence 1 -> 2 -> 3 -> 2 -> 4 of
Bretl (2006), sec. 3.2.1 on the bundled ``pegs`` terrain: stance 2 is visited twice, in two components
(``F_2^1`` then ``F_2^3``, Fig. 13(b)).  One panel per step with a stance of one peg (the motion happens
there; a step onto two pegs is a single point): the two links drawn from hand a, six postures per step.
"""

from __future__ import annotations

import argparse
import math
from pathlib import Path

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402
from onestep_figures import draw_holds, draw_robot, snapshots  # noqa: E402

from climb_ompl import (
    RobotModel,  # noqa: E402
    Terrain,  # noqa: E402
    plan_climb,  # noqa: E402
    verify,  # noqa: E402
)


def main(out: Path) -> None:
    robot, terrain = RobotModel.load("double-link"), Terrain.load("pegs")
    q0 = [1.70, 0.90, 0.5 - 2 * math.pi, 1.0]  # the nominal posture on peg 1, theta1 a turn down (docs/climb.md)
    res = plan_climb(robot, terrain, {"a": "1"}, "a=4", seed=0, q_start=q0, time_limit=60, heuristic_weight=1.0,
                     step_time_limit=0.5)
    if not res.found:
        raise SystemExit(f"no plan: {res.reason}")
    plan = res.plan
    holds = [dict(plan.start_stance)["a"]] + [s.hold for s in plan.steps if s.action == "grab"]
    moves = [s for s in plan.steps if len(s.stance) == 1 and len(s.waypoints) > 1]
    fig, axes = plt.subplots(1, len(moves), figsize=(3.2 * len(moves), 3.6), sharey=True)
    for k, (ax, s) in enumerate(zip(axes, moves, strict=True)):
        for sf in terrain.surfaces:
            if sf.type == "circle":
                ax.add_patch(plt.Circle((sf.center[0], sf.center[2]), sf.radius, color="0.8", zorder=1))
        for q, a in snapshots([np.array(w) for w in s.waypoints], 6):
            draw_robot(ax, robot, q, (0, 2), a, ["C0", "C1"], lw=2.0)
        (limb, hold), = s.stance
        draw_holds(ax, terrain, (0, 2), {h.id: h.id for h in terrain.holds})
        ax.set_title(f"step {k + 1}: {limb} on peg {hold}, then {s.action} {s.limb}\u2192{s.hold}", fontsize=8)
        ax.set_aspect("equal")
        ax.set_xlim(0.0, 2.0)
        ax.set_ylim(0.3, 2.8)
    rep = verify(plan)
    fig.suptitle(f"double-link on pegs: {' -> '.join(holds)} ({len(plan.steps)} steps, "
                 f"{res.stats['total_s']:.1f} s planning, verify {'ok' if rep.ok else 'FAILED'})", fontsize=10)
    fig.tight_layout()
    out.parent.mkdir(parents=True, exist_ok=True)
    fig.savefig(out, dpi=110)
    print(f"{out}: {' -> '.join(holds)}, {len(plan.steps)} steps, verify ok={rep.ok}")


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out", type=Path, default=Path("docs/climb_double_link.png"))
    main(ap.parse_args().out)
