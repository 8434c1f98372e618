"""``make bench``: every benchmark with its default (paper-scale) parameters, one JSON file each.

Usage: ``python -m climb_ompl.bench.all --out-dir out/bench [--only NAME ...]``.  Each benchmark runs
in its own subprocess with a timeout (:func:`climb_ompl.bench._common.execute`) and prints its
one-line summary; the grid benchmark manages its own processes.  A failing benchmark is reported and the
others still run; the exit code is 1 if any failed.
"""

from __future__ import annotations

import argparse
import subprocess
import sys
from pathlib import Path

#: (name, extra CLI arguments) in the order they run; the cheap ones first.
BENCHMARKS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("equilibrium", ()),
    ("robot", ()),
    ("treebot", ()),
    ("slope", ()),
    ("onestep", ("--queries", "50", "--seed", "0")),
    ("climb", ("--height", "2.0", "--seed", "0", "--walls", "10")),
    ("replan", ("--failures", "20", "--seed", "0", "--all-held")),
    ("grid", ("--preset", "small", "--compare-serial")),
    ("papers", ("--seed", "0")),
    ("trajectory", ("--seed", "0")),
    ("console", ("--seed", "0")),
)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmarks; return 0 when all succeeded."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--out-dir", type=Path, default=Path("out/bench"))
    ap.add_argument("--only", nargs="*", default=None, help="Run only these benchmarks.")
    args = ap.parse_args(argv)
    args.out_dir.mkdir(parents=True, exist_ok=True)
    failed = []
    for name, extra in BENCHMARKS:
        if args.only and name not in args.only:
            continue
        out = args.out_dir / name if name == "grid" else args.out_dir / f"{name}.json"
        cmd = [sys.executable, "-m", "climb_ompl", "bench", name, *extra, "--out", str(out)]
        print("$ climb-ompl " + " ".join(cmd[3:]), flush=True)
        if subprocess.run(cmd).returncode != 0:
            failed.append(name)
    if failed:
        print(f"failed: {', '.join(failed)}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
