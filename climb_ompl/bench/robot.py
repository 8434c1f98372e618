"""``climb-ompl bench robot``: per-call cost of the robot model's hot functions.

Times ``com``, ``hand_positions`` + ``hand_jacobians`` and ``in_collision`` (wall + self-collision, the
four hands in contact) for a robot (default ``lemur``) at random configurations near the nominal stance,
the batch CoM rate, and the full validity-relevant evaluation (CoM + hands + collision).  Target: the
full evaluation below 50 us per configuration from Python.  Baseline (same run): a bare Pinocchio
``centerOfMass`` call, so the ratios say how much our wrapper adds.
"""

from __future__ import annotations

from pathlib import Path
from typing import Any

import typer

from climb_ompl.settings import SEED_MAX

NAME = "robot"


def _per_call(fn: Any, args: list[Any], repeat: int) -> float:
    import time

    best = float("inf")
    for _ in range(repeat):
        t0 = time.perf_counter()
        for a in args:
            fn(a)
        best = min(best, (time.perf_counter() - t0) / len(args))
    return best * 1e6


def run(robot: str = "lemur", n: int = 2000, repeat: int = 5, batch: int = 20000, seed: int = 0) -> dict[str, Any]:
    """Measure; returns microseconds per call (best of ``repeat`` passes over ``n`` configurations)."""
    import numpy as np
    import pinocchio as pin

    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain

    r = RobotModel.load(robot)
    rng = np.random.default_rng(seed)
    span = 0.15 * (r.upper - r.lower)
    Q = [np.clip(r.nominal_q + rng.uniform(-span, span), r.lower, r.upper) for _ in range(n)]
    wall = Terrain.from_dict({"name": "bench-wall", "dim": 2 if r.planar else 3,
                              "holds": [{"id": "h", "position": [0, 0] if r.planar else [0, 0, 0],
                                         "normal": [0, 1] if r.planar else [0, 1, 0]}],
                              "surfaces": [] if r.planar else [{"type": "plane", "point": [0, 0, 0],
                                                               "normal": [0, 1, 0]}]})
    contact = [lb.name for lb in r.limbs]
    r.in_collision(Q[0], wall, contact)  # build the collision set once (cached per terrain and stance)

    def full(q: Any) -> None:
        r.com(q)
        r.hands_and_jacobians(q)
        r.in_collision(q, wall, contact)

    res = {
        "robot": robot, "nq": r.nq, "n_geoms": int(r.collision_model.ngeoms), "n_self_pairs": len(r.collision_pairs()),
        "baseline_pin_com_us": _per_call(lambda q: pin.centerOfMass(r.model, r.data, q, False), Q, repeat),
        "com_us": _per_call(r.com, Q, repeat),
        "hand_positions_us": _per_call(r.hand_positions, Q, repeat),
        "hands_and_jacobians_us": _per_call(lambda q: (r.hand_positions(q), r.hand_jacobians(q)), Q, repeat),
        "hands_and_jacobians_one_pass_us": _per_call(r.hands_and_jacobians, Q, repeat),
        "in_collision_us": _per_call(lambda q: r.in_collision(q, wall, contact), Q, repeat),
        "self_collision_us": _per_call(r.self_collision, Q, repeat),
        "full_evaluation_us": _per_call(full, Q, repeat),
    }
    QB = np.array([Q[i % n] for i in range(batch)])
    res["batch_com_per_s"] = batch / (_per_call(r.com_batch, [QB], repeat) * 1e-6)
    res["com_overhead_ratio"] = res["com_us"] / res["baseline_pin_com_us"]
    res["target_full_us"] = 50.0
    res["meets_target"] = bool(res["full_evaluation_us"] < 50.0)
    return res


def summary(result: dict[str, Any]) -> str:
    """One line: the per-call figures in microseconds."""
    r = result
    return (f"{r['robot']} (nq {r['nq']}): com {r['com_us']:.2f} us, hands+jacobians "
            f"{r['hands_and_jacobians_us']:.2f} us, in_collision {r['in_collision_us']:.2f} us, full "
            f"{r['full_evaluation_us']:.2f} us (target < {r['target_full_us']:.0f}), batch com "
            f"{r['batch_com_per_s'] / 1e6:.2f} M/s")


def command(
    out: Path = typer.Option(None, "--out", help="Write the JSON result here."),
    robot: str = typer.Option("lemur", help="Bundled robot name or spec path."),
    n: int = typer.Option(2000, help="Configurations per pass."),
    repeat: int = typer.Option(5, help="Passes (the best is reported)."),
    batch: int = typer.Option(20000, help="Batch size for the batch CoM rate."),
    seed: int = typer.Option(0, min=0, max=SEED_MAX, help="RNG seed of the configurations."),
) -> None:
    """Per-call time of com, hands + Jacobians and in_collision; batch CoM rate."""
    from climb_ompl.bench._common import execute

    execute(NAME, dict(robot=robot, n=n, repeat=repeat, batch=batch, seed=seed), out)
