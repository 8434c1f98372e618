"""``climb-ompl bench suite``: robots x terrains, each cell a verified climb or a diagnosed infeasibility.

The robots: LEMUR (Bretl et al. (2004)), the planar three-limbed robot (Bretl (2006)) where the terrain is
2-D, and the third-party quadrupeds Go1 and ANYmal-C (example-robot-data).  The terrains (:data:`TERRAINS`):
the demo wall, two generated walls whose hold normals lean 35-65 and 55-80 degrees up from the wall normal
(``generate_wall(seed=1)``), a slab leaning back 15 degrees (75 from horizontal), a wall overhanging by 10
degrees and a 3 m ramp of stepping stones (the last three written by hand and bundled: ``--terrain slab``).

Each cell runs in its own process (``--workers`` at a time) and does what a user does: the start finder
(:func:`climb_ompl.climb.start.find_start`), then :func:`climb_ompl.climb.multistep.plan_climb` (from the finder's
next start
when the stance graph is exhausted, :func:`climb_ompl.climb.multistep.climb_from_start`) up the wall by the
robot's climb length (:data:`CLIMB`, metres along the wall's slope above the start's highest hold: the goal is every
contact hold at least that far up, :func:`climb_ompl.climb.goal.climb_height`), within one budget for both
(``--budget``,
180 s), then :func:`climb_ompl.verification.climb.verify` on the plan.  A cell is ``verified``, ``unverified`` (found,
rejected by verify), ``infeasible`` (no start, an exhausted stance graph or a goal above the holds: the
diagnosis of :mod:`climb_ompl.climb.start` or :mod:`climb_ompl.climb.frontier` says why), ``budget`` (the budget was
spent:
the frontier diagnosis says where the climb stopped), ``n/a`` (a planar robot on a 3-D terrain or the
reverse) or ``crash``.  Cells already in ``DIR/cells`` are not run again (resumable).

Output: ``DIR/suite.json`` (every cell: robot, terrain, seed, status, found, verified, steps, seconds, reason),
``DIR/suite.md`` (the table) and ``DIR/suite.png`` (the heat map of the seconds, each cell marked with its
status).  The summary line gives the share of applicable cells verified and LEMUR's median time over the
generated walls divided by its time on the demo wall, in the same run.

The searches are randomised, and one seed's time is one draw of them (the spread over seeds: docs/bench.md,
"Climb suite").  ``--seed`` repeated runs every
robot x terrain at each seed (a cell per seed, the table and heat map giving how many verified and the median
time); LEMUR's ratio is then the median over the generated walls of their median times over the seeds, divided by
the demo wall's median, with each seed's own ratio listed beside it (``per_seed``).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import time
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed
from importlib import resources
from pathlib import Path
from typing import Any

import numpy as np
import typer

from climb_ompl.settings import SEED_MAX

#: The robots of the suite (bundled names), in table order.
ROBOTS: tuple[str, ...] = ("lemur", "planar-3limb", "go1", "anymal-c")

#: The terrains: name -> bundled terrain name, or file in the package (``climb_ompl/...``).
TERRAINS: dict[str, str] = {
    "demo-wall": "demo-wall",
    "wall-lean35-65": "data/queries/walls/lean35-65.yaml",
    "wall-lean55-80": "data/queries/walls/lean55-80.yaml",
    "slab": "slab",
    "overhang": "overhang",
    "stepping-stone-ramp-3m": "stepping-stone-ramp-3m",
}

#: The generated walls (LEMUR's median time over them is compared with its demo-wall time).
GENERATED: tuple[str, ...] = ("wall-lean35-65", "wall-lean55-80")

#: Climb length of the benchmark per robot, metres along the wall's slope (LEMUR 1 m wingspan, the
#: quadrupeds about 0.5 m long).
CLIMB: dict[str, float] = {"lemur": 1.2, "planar-3limb": 1.0, "go1": 0.6, "anymal-c": 0.6}

#: Budget of one cell (start finder and climb), seconds.
BUDGET = 180.0

STATUSES: tuple[str, ...] = ("verified", "unverified", "infeasible", "budget", "n/a", "crash")


def terrain_path(name: str) -> str:
    """The terrain of the suite called ``name``: a bundled name or a file path."""
    src = TERRAINS.get(name, name)
    if src.endswith((".yaml", ".yml")) and not Path(src).exists():
        return str(resources.files("climb_ompl").joinpath(src))
    return src


def run_cell(robot: str, terrain: str, climb: float, seed: int = 0, budget: float = BUDGET) -> dict[str, Any]:
    """One cell: start, climb, verify (see the module docstring); the cell's JSON-able record, with ``seconds``
    (wall clock, start and climb) and ``cpu_s`` (this process's CPU time over the same span: on a shared machine
    it shows how much of the budget the cell had)."""
    cpu0 = time.process_time()
    rec = _cell(robot, terrain, climb, seed, budget)
    rec["cpu_s"] = time.process_time() - cpu0 - rec.pop("_verify_cpu_s", 0.0)
    return rec


def _cell(robot: str, terrain: str, climb: float, seed: int, budget: float) -> dict[str, Any]:
    from climb_ompl.climb.goal import climb_height
    from climb_ompl.climb.multistep import climb_from_start, load_terrain
    from climb_ompl.climb.status import ClimbStatus
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.settings import ClimbSettings
    from climb_ompl.verification.climb import verify

    model, wall = RobotModel.load(robot), load_terrain(terrain_path(terrain))
    out: dict[str, Any] = {"robot": robot, "terrain": terrain, "climb_m": climb, "seed": seed, "budget_s": budget,
                           "found": False, "verified": False, "steps": 0, "diagnosis": []}
    dim = 2 if model.planar else 3
    if dim != wall.dim:
        return {**out, "status": "n/a", "seconds": 0.0,
                "reason": f"a {'planar' if model.planar else '3-D'} robot does not climb a {wall.dim}-D terrain"}
    t0 = time.perf_counter()
    # the start finder's start, and its next ones when the stance graph is exhausted from it (within the budget)
    res, start, tried = climb_from_start(model, wall, None, ClimbSettings.for_search("guided", robot=model,
                                                                                      time_limit=budget),
                                         climb=climb, seed=seed)
    if res is None:
        return {**out, "status": "infeasible", "seconds": time.perf_counter() - t0,
                "reason": start.explain(model.name, wall.name), "stage": "start",
                "diagnosis": [{"stance": d.stance, "reasons": d.reasons} for d in start.diagnoses]}
    height = climb_height(model, wall, start.stance, climb)  # type: ignore[arg-type]
    out.update(seconds=time.perf_counter() - t0, start=dict(sorted(start.stance.items())),  # type: ignore[union-attr]
               goal_height=height, found=res.found, stances_explored=res.stats.get("stances_explored", 0),
               starts_tried=len(tried))
    if not res.found or res.plan is None:
        spent = res.status == ClimbStatus.BUDGET
        return {**out, "status": "budget" if spent else "infeasible", "reason": res.reason,
                "stage": "budget" if spent else "exhausted" if res.status == ClimbStatus.EXHAUSTED else "climb",
                "diagnosis": res.diagnosis}
    t1, c1 = time.perf_counter(), time.process_time()
    rep = verify(res.plan)
    out.update(steps=len(res.plan.steps), verified=bool(rep.ok), verify_s=time.perf_counter() - t1,
               execution_s=res.plan.execution_s, _verify_cpu_s=time.process_time() - c1)
    if not rep.ok:
        return {**out, "status": "unverified", "reason": "; ".join(str(v) for v in rep.violations[:3])}
    return {**out, "status": "verified", "reason": ""}


# ---- the suite --------------------------------------------------------------------------------------
def cell_name(robot: str, terrain: str, seed: int = 0) -> str:
    """The file stem of a cell's record: the names, or a spec's or terrain file's stem, and the seed unless 0."""
    return f"{label(robot)}__{label(terrain)}" + (f"__seed{seed}" if seed else "")


def label(name: str) -> str:
    """A suite robot or terrain as the table names it: its name, or the stem of a spec or terrain file."""
    return Path(name).stem if name.endswith((".yaml", ".yml")) else name


def _run_isolated(cell: dict[str, Any], path: Path, timeout: float) -> dict[str, Any]:
    """Run ``cell`` in its own process (hard ``timeout``); its record, also written to ``path``."""
    from climb_ompl._io import atomic_write_json

    cmd = [sys.executable, "-m", __name__, json.dumps(cell), str(path)]
    t0 = time.perf_counter()
    try:
        proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        err = None if proc.returncode == 0 and path.exists() else \
            ((proc.stderr or "").strip().splitlines()[-1:] or [f"exit code {proc.returncode}"])[0]
    except subprocess.TimeoutExpired:  # the child is killed before this is raised
        err = f"killed after the hard timeout of {timeout:g} s"
    if err is None:
        return json.loads(path.read_text())
    rec = {**cell, "status": "crash", "found": False, "verified": False, "steps": 0,
           "seconds": time.perf_counter() - t0, "reason": err, "diagnosis": []}
    atomic_write_json(path, rec)
    return rec


def run_suite(out: Path, *, robots: list[str] | None = None, terrains: list[str] | None = None,
              climb: float | None = None, seed: int | Sequence[int] = 0, budget: float = BUDGET, workers: int = 2,
              fresh: bool = False, progress: Any = None) -> dict[str, Any]:
    """Run (or resume) the suite into ``out``; the summary written to ``out/suite.json``.

    Args:
        out: output folder (created).
        robots, terrains: subsets of :data:`ROBOTS` and :data:`TERRAINS` (default all).
        climb: climb length for every robot, metres along the slope (default :data:`CLIMB` per robot).
        seed: the planner's seed, or several: every robot x terrain runs at each (see the module docstring).
        budget: seconds per cell (start finder and climb).
        workers: cells run at once, each in its own process.
        fresh: run every cell again, ignoring the records in ``out/cells``.
        progress: called with each cell's record as it finishes.
    """
    from climb_ompl._io import atomic_write, atomic_write_json
    from climb_ompl.bench._common import envelope

    robots, terrains = list(robots or ROBOTS), list(terrains or TERRAINS)
    seeds = [int(seed)] if isinstance(seed, int) else list(dict.fromkeys(int(x) for x in seed))
    if not seeds:
        raise ValueError("no seed given")
    cells_dir = out / "cells"
    cells_dir.mkdir(parents=True, exist_ok=True)
    cells = [{"robot": r, "terrain": t, "climb": float(climb if climb is not None else CLIMB.get(r, 1.0)),
              "seed": sd, "budget": budget, "files": _digest(r) + _digest(t)}
             for r in robots for t in terrains for sd in seeds]
    records: dict[str, dict[str, Any]] = {}
    todo = []
    for c in cells:
        p = cells_dir / f"{cell_name(c['robot'], c['terrain'], c['seed'])}.json"
        same = p.exists() and not fresh and _same_cell(json.loads(p.read_text()), c)
        if same:
            records[p.stem] = json.loads(p.read_text())
        else:
            todo.append((c, p))
    t0 = time.perf_counter()
    with ThreadPoolExecutor(max_workers=max(1, workers)) as pool:  # threads only wait on child processes
        futs = {pool.submit(_run_isolated, c, p, budget + 300.0): p.stem for c, p in todo}
        for fut in as_completed(futs):
            records[futs[fut]] = rec = fut.result()
            if progress is not None:
                progress(rec)
    rows = [records[cell_name(c["robot"], c["terrain"], c["seed"])] for c in cells]
    summary = envelope("suite", {"robots": robots, "terrains": terrains, "climb": climb, "seed": seeds[0],
                                 "seeds": seeds, "budget": budget, "workers": workers})
    summary.update(_figures(rows), wall_s=time.perf_counter() - t0, executed=len(todo), cells=rows)
    atomic_write_json(out / "suite.json", summary)
    atomic_write(out / "suite.md", table(summary))
    heat_map(summary, out / "suite.png")
    return summary


def _digest(name: str) -> str:
    """The SHA-256 of a spec or terrain file given by path (a resumed suite runs an edited file again); ``""``
    for a bundled name."""
    import hashlib

    if name in ROBOTS or name in TERRAINS:
        return ""
    return hashlib.sha256(Path(name).read_bytes()).hexdigest()[:16]


def _same_cell(rec: dict[str, Any], cell: dict[str, Any]) -> bool:
    """Whether a stored record was made for ``cell`` (the same robot and terrain, files unchanged, the same
    climb, seed and budget)."""
    if (rec.get("robot"), rec.get("terrain"), rec.get("files", "")) != (cell["robot"], cell["terrain"],
                                                                       cell.get("files", "")):
        return False
    return all(abs(float(rec.get(k, math.nan)) - float(cell[c])) < 1e-9 if isinstance(cell[c], float)
               else rec.get(k) == cell[c] for k, c in (("climb_m", "climb"), ("seed", "seed"), ("budget_s", "budget")))


def _figures(rows: list[dict[str, Any]]) -> dict[str, Any]:
    """Counts per status, share verified among applicable cells, LEMUR's generated-wall ratio."""
    counts = {s: sum(r["status"] == s for r in rows) for s in STATUSES}
    applicable = len(rows) - counts["n/a"]
    out: dict[str, Any] = {"counts": counts, "applicable": applicable,
                           "verified_share": counts["verified"] / applicable if applicable else None,
                           "unexplained": [cell_name(r["robot"], r["terrain"], r.get("seed", 0)) for r in rows
                                           if r["status"] in ("crash", "unverified")]}
    seeds = list(dict.fromkeys(r.get("seed", 0) for r in rows))
    ratio = _lemur_ratio(rows, seeds)
    if ratio is not None:
        if len(seeds) > 1:
            ratio["per_seed"] = [{"seed": sd, **g} for sd in seeds
                                 if (g := _lemur_ratio([r for r in rows if r.get("seed", 0) == sd], [sd]))]
        out["lemur_generated_over_demo"] = ratio
    return out


def _lemur_ratio(rows: list[dict[str, Any]], seeds: list[Any]) -> dict[str, Any] | None:
    """LEMUR's median time over the generated walls over its demo-wall time (each terrain's time the median over
    ``seeds``; ``cpu_ratio`` the same from the cells' CPU times), or ``None`` unless the demo wall is verified at
    every seed and each generated wall has a time at every seed (a spent budget counts with its time: the ratio is
    then a lower bound)."""
    lem: dict[str, list[dict[str, Any]]] = {}
    for r in rows:
        if r["robot"] == "lemur" and r["status"] in ("verified", "budget"):
            lem.setdefault(r["terrain"], []).append(r)
    demo = lem.get("demo-wall", [])
    if len(demo) != len(seeds) or any(r["status"] != "verified" for r in demo) \
            or any(len(lem.get(t, [])) != len(seeds) for t in GENERATED):
        return None

    def ratio(key: str) -> tuple[float, float]:
        return float(np.median([np.median([r[key] for r in lem[t]]) for t in GENERATED])), \
            float(np.median([r[key] for r in demo]))

    med, demo_s = ratio("seconds")
    out = {"median_generated_s": med, "demo_wall_s": demo_s, "ratio": med / demo_s,
           "lower_bound": any(r["status"] != "verified" for t in GENERATED for r in lem[t])}
    if all("cpu_s" in r for t in (*GENERATED, "demo-wall") for r in lem[t]):
        # the same from each cell's own CPU time: steadier than wall-clock on a shared machine
        med_c, demo_c = ratio("cpu_s")
        out["cpu_ratio"] = med_c / demo_c
    return out


def _groups(rows: list[dict[str, Any]]) -> dict[tuple[str, str], list[dict[str, Any]]]:
    """The cells by (robot, terrain), in table order (one per seed)."""
    out: dict[tuple[str, str], list[dict[str, Any]]] = {}
    for r in rows:
        out.setdefault((r["robot"], r["terrain"]), []).append(r)
    return out


def _group_text(rs: list[dict[str, Any]]) -> str:
    """A robot x terrain over several seeds: how many verified, the median (and range of) their times and steps."""
    if len(rs) == 1:
        return _cell_text(rs[0])
    ok = [r for r in rs if r["status"] == "verified"]
    if all(r["status"] == "n/a" for r in rs):
        return "n/a"
    text = f"verified {len(ok)}/{len(rs)}"
    if ok:
        sec, steps = [r["seconds"] for r in ok], [r["steps"] for r in ok]
        text += f": median {np.median(sec):.0f} s ({min(sec):.0f}-{max(sec):.0f}), {min(steps)}-{max(steps)} steps"
    others = sorted({r["status"] for r in rs} - {"verified"})
    return text + (f"; also {', '.join(others)}" if others else "")


def _cell_text(r: dict[str, Any]) -> str:
    cpu = f", CPU {r['cpu_s']:.0f} s" if "cpu_s" in r else ""
    if r["status"] == "verified":
        return f"verified: {r['steps']} steps, {r['seconds']:.0f} s{cpu}"
    if r["status"] == "n/a":
        return "n/a"
    return f"{r['status']} ({r['seconds']:.0f} s{cpu})"


def table(summary: dict[str, Any]) -> str:
    """The suite as a markdown table (robots x terrains), then one line per cell without a plan saying why."""
    rows = summary["cells"]
    robots = list(dict.fromkeys(r["robot"] for r in rows))
    terrains = list(dict.fromkeys(r["terrain"] for r in rows))
    by = _groups(rows)
    multi = len({r.get("seed", 0) for r in rows}) > 1
    lines = ["| robot | " + " | ".join(map(label, terrains)) + " |", "|---" * (len(terrains) + 1) + "|"]
    for rb in robots:
        lines.append(f"| {label(rb)} | " + " | ".join(_group_text(by[(rb, t)]) for t in terrains) + " |")
    f = summary
    lines += ["", f"{f['counts']['verified']} of {f['applicable']} applicable cells verified"
              + (f" ({100 * f['verified_share']:.0f} %)" if f["verified_share"] is not None else "")
              + (" (a cell per seed)." if multi else ".")]
    if "lemur_generated_over_demo" in f:
        g = f["lemur_generated_over_demo"]
        lines.append(f"LEMUR: median over the generated walls {g['median_generated_s']:.1f} s, demo wall "
                     f"{g['demo_wall_s']:.1f} s{' (medians over the seeds)' if multi else ''}: ratio "
                     f"{'>= ' if g['lower_bound'] else ''}{g['ratio']:.2f}"
                     + (" (a budget spent counts as its time)" if g["lower_bound"] else "")
                     + (f"; from CPU times {g['cpu_ratio']:.2f}." if "cpu_ratio" in g else "."))
        if g.get("per_seed"):
            lines.append("Each seed's own ratio: " + ", ".join(f"seed {p['seed']}: {p['ratio']:.2f}"
                                                               for p in g["per_seed"]) + ".")
    why = [r for r in rows if r["status"] not in ("verified", "n/a")]
    if why:
        lines += ["", "Cells without a verified climb (the first cause diagnosed):", ""]
        for r in why:
            at = f" (seed {r.get('seed', 0)})" if multi else ""
            lines.append(f"- {label(r['robot'])} on {label(r['terrain'])}{at}: {r['status']}: {_first_cause(r)}")
    na = [r for r in rows if r["status"] == "n/a"]
    if na:
        lines += ["", "Not applicable: " + "; ".join(sorted({f"{label(r['robot'])} ({r['reason']})" for r in na}))
                  + "."]
    return "\n".join(lines) + "\n"


def _first_cause(r: dict[str, Any]) -> str:
    """The first diagnosed cause of a cell without a plan, on one line."""
    if r["status"] in ("n/a", "crash", "unverified"):
        return r.get("reason", "")
    for d in r.get("diagnosis") or []:
        for reason in d.get("reasons", []):
            return f"{_stance_text(d['stance'])} {reason}"
        for e in d.get("failures", []):
            for reason in e.get("reasons", []):
                if not reason.startswith("transition:"):
                    step = "" if e["action"] == "reach" else f"{e['action']} {e['limb']} {e['hold']}: "
                    return f"at {_stance_text(d['stance'])}, {step}{reason}"
    return r.get("reason", "").splitlines()[0] if r.get("reason") else ""


def _stance_text(stance: dict[str, str]) -> str:
    return "{" + ", ".join(f"{k}:{v}" for k, v in sorted(stance.items())) + "}"


def heat_map(summary: dict[str, Any], path: Path) -> None:
    """Robots x terrains: colour the seconds of verified cells, grey the others, each marked with its status."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from climb_ompl._io import atomic_write

    rows = summary["cells"]
    robots = list(dict.fromkeys(r["robot"] for r in rows))
    terrains = list(dict.fromkeys(r["terrain"] for r in rows))
    by = _groups(rows)
    vals = np.full((len(robots), len(terrains)), np.nan)
    for i, rb in enumerate(robots):
        for j, t in enumerate(terrains):
            ok = [r["seconds"] for r in by[(rb, t)] if r["status"] == "verified"]
            if ok:
                vals[i, j] = float(np.median(ok))
    fig, ax = plt.subplots(figsize=(1.6 * len(terrains) + 2.5, 0.8 * len(robots) + 1.8))
    ax.imshow(np.full(vals.shape, 0.85), cmap="gray", vmin=0, vmax=1, aspect="auto")  # grey under the others
    im = ax.imshow(np.ma.masked_invalid(vals), cmap="viridis_r", vmin=0, vmax=float(summary["params"]["budget"]),
                   aspect="auto")
    for i, rb in enumerate(robots):
        for j, t in enumerate(terrains):
            rs = by[(rb, t)]
            r = rs[0]
            if len(rs) > 1:
                n_ok = int(sum(x["status"] == "verified" for x in rs))
                txt = f"{n_ok}/{len(rs)} verified" + (f"\nmedian {vals[i, j]:.0f} s" if n_ok else "")
            else:
                txt = f"{r['steps']} steps\n{r['seconds']:.0f} s" if r["status"] == "verified" else r["status"]
            ax.text(j, i, txt, ha="center", va="center", fontsize=8,
                    color="white" if vals[i, j] > 0.5 * summary["params"]["budget"]
                    else "black")  # viridis_r is dark at long times (NaN compares False)
    ax.set_xticks(range(len(terrains)), [label(t) for t in terrains], rotation=20, ha="right")
    ax.set_yticks(range(len(robots)), [label(rb) for rb in robots])
    fig.colorbar(im, ax=ax, label="seconds to a verified climb")
    ax.set_title("climb suite: robots x terrains")
    fig.tight_layout()
    tmp = path.with_suffix(".tmp.png")
    fig.savefig(tmp, dpi=110)
    plt.close(fig)
    atomic_write(path, tmp.read_bytes())
    tmp.unlink()


def summary(result: dict[str, Any]) -> str:
    """One line: cells verified of the applicable ones, counts by status, LEMUR's generated-wall ratio."""
    c = result["counts"]
    others = ", ".join(f"{k} {v}" for k, v in c.items() if v and k != "verified")
    line = f"verified {c['verified']}/{result['applicable']} applicable cells" + (f"; {others}" if others else "")
    g = result.get("lemur_generated_over_demo")
    if g:
        line += f"; LEMUR generated walls / demo wall: {'>= ' if g['lower_bound'] else ''}{g['ratio']:.2f} " \
                f"({g['median_generated_s']:.0f} s / {g['demo_wall_s']:.0f} s" \
                + (f", medians over seeds {', '.join(str(p['seed']) for p in g['per_seed'])})" if g.get("per_seed")
                   else ")") + (f"; from CPU times {g['cpu_ratio']:.2f}" if "cpu_ratio" in g else "")
    return line


def command(
    out: Path = typer.Option(..., "--out", help="Output folder (suite.json, suite.md, suite.png, cells/)."),
    robot: list[str] = typer.Option(None, "--robot", help="Robot (repeatable; default: every robot of the suite), or a "
                                                           "robot spec file (then give --climb)."),
    terrain: list[str] = typer.Option(None, "--terrain", help="Terrain (repeatable; default: every terrain), or a "
                                                               "terrain file."),
    climb: float = typer.Option(None, "--climb", help="Climb length for every robot, m along the slope "
                                "(default: per robot, lemur 1.2, quadrupeds 0.6)."),
    seed: list[int] = typer.Option([0], "--seed", min=0, max=SEED_MAX, help="Seed of the planner (repeatable: "
                                   "every cell at each seed, the table giving medians)."),
    budget: float = typer.Option(BUDGET, "--budget", help="Seconds per cell (start finder and climb)."),
    workers: int = typer.Option(2, "--workers", min=1, help="Cells run at once, each in its own process."),
    fresh: bool = typer.Option(False, "--fresh", help="Run every cell again (default: resume from DIR/cells)."),
) -> None:
    """Robots x terrains: a verified climb or a diagnosed infeasibility per cell (JSON, table, heat map)."""
    from climb_ompl._options import check_positive
    from climb_ompl.errors import ARGUMENT, InputError
    from climb_ompl.model.robot import RobotModel
    from climb_ompl.model.terrain import Terrain

    check_positive(budget, "--budget", "seconds")
    if climb is not None:
        check_positive(climb, "--climb", "metres")
    terrains, robots = [], []
    for t in terrain or []:
        if t not in TERRAINS and not _is_file(t):
            raise InputError(ARGUMENT, "--terrain", f"unknown suite terrain {t!r}; one of {', '.join(TERRAINS)}, "
                             "or a terrain file")
        if t not in TERRAINS:
            t = str(Path(t).resolve())
            Terrain.load(t)  # a bad file: its message and exit code 2, before any cell runs
        terrains.append(t)
    for r in robot or []:
        if r not in ROBOTS and not _is_file(r):
            raise InputError(ARGUMENT, "--robot", f"unknown suite robot {r!r}; one of {', '.join(ROBOTS)}, "
                             "or a robot spec file")
        if r not in ROBOTS:
            r = str(Path(r).resolve())
            RobotModel.load(r)
            if climb is None:
                raise InputError(ARGUMENT, "--climb", f"give the climb length for {label(r)} (a spec file): "
                                 "the suite's lengths are per bundled robot")
        robots.append(r)
    for kind, names, bundled in (("--robot", robots, ROBOTS), ("--terrain", terrains, tuple(TERRAINS))):
        labels = [label(x) for x in names]
        for x, lab in zip(names, labels, strict=True):
            if (x not in bundled and lab in bundled) or labels.count(lab) > 1:
                raise InputError(ARGUMENT, kind, f"{x!r} would share the name {lab!r} (a file's stem) with "
                                 "another robot or terrain of the suite; rename the file")
    res = run_suite(out, robots=robots or None, terrains=terrains or None, climb=climb, seed=seed, budget=budget,
                    workers=workers, fresh=fresh,
                    progress=lambda r: typer.echo(f"  {label(r['robot'])} x {label(r['terrain'])}"
                                                  + (f" (seed {r.get('seed', 0)})" if len(seed) > 1 else "")
                                                  + f": {_cell_text(r)}"))
    typer.echo(f"[suite] {summary(res)}  -> {out / 'suite.json'}")


def _is_file(name: str) -> bool:
    return name.endswith((".yaml", ".yml")) and Path(name).is_file()


def _child(cell_json: str, path: str) -> None:
    from climb_ompl._io import atomic_write_json

    c = json.loads(cell_json)
    atomic_write_json(path, {**run_cell(c["robot"], c["terrain"], c["climb"], c["seed"], c["budget"]),
                             "files": c.get("files", "")})


if __name__ == "__main__":
    _child(sys.argv[1], sys.argv[2])
