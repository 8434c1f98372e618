"""``docs/planners.md`` from a comparison database (``climb-ompl bench planners-doc``, ``make compare``).

Reads the ``grid_runs`` table of a grid database (:mod:`climb_ompl.bench._runs`) and writes a Markdown page with
its figures: success against the validity-check budget and against time, time distributions, success rates
with Wilson 95 % score intervals (Wilson 1927), a planner x space heat map, the custom sampler's effect per
planner, success per query set, and the recommendation the data supports with how sure it is (whether the
best configuration's interval separates from the next ones, the best and the climb's default paired by query
and seed), with the configurations solving as many runs as the default or more broken down by query set.

Every run has a budget of validity checks (``max_iterations``) and a wall-clock guard (``time_limit``); a run
ends at whichever comes first (:func:`climb_ompl.climb.onestep.find_path`).  The page counts, per configuration, the
runs the guard stopped before their check budget (:func:`guard_stopped`): their figures depend on the load of
the machine that ran them, not on the budget alone.
"""

from __future__ import annotations

import math
from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path
from typing import Any

#: Two-sided 95 % normal quantile.
Z95 = 1.959963984540054


def climb_default() -> tuple[str, str, str]:
    """``(planner, space, sampler)`` of the climb's FIND-PATH (the :class:`ClimbSettings` defaults)."""
    from climb_ompl.settings import ClimbSettings

    d = ClimbSettings()
    return d.planner, d.space, d.sampler


def wilson(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """Wilson score interval of a binomial proportion ``k / n`` (Wilson 1927); ``(0, 1)`` when ``n == 0``."""
    if n <= 0:
        return 0.0, 1.0
    p = k / n
    den = 1.0 + z * z / n
    centre = (p + z * z / (2 * n)) / den
    half = z / den * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    # exact at the ends (the bound is 0 at k = 0 and 1 at k = n; rounding would leave 1e-17)
    return (0.0 if k == 0 else max(0.0, centre - half)), (1.0 if k == n else min(1.0, centre + half))


def guard_stopped(r: dict[str, Any]) -> bool:
    """Whether the wall-clock guard, not the check budget, ended run ``r`` (a ``grid_runs`` result).

    ``find_path``'s guard fires ``time_limit`` seconds after the call started, and ``time`` counts from the
    same start, so a run the guard stopped has ``time >= time_limit``; it stopped before its budget when it
    had made fewer than ``max_iterations`` validity checks (``states_sampled``).  An unsolved run so stopped
    has the status ``timeout``; a solved one is an anytime planner returning its path at the guard (or a path
    found as the guard fired).  Without a check budget every run that reached ``time_limit`` counts.  Runs the
    hard timeout killed or that crashed are counted apart (``timed_out``, ``crashed``)."""
    if r.get("crashed") or r.get("timed_out") or r["time"] < r["time_limit"]:
        return False
    budget = r.get("max_iterations")
    return budget is None or (r.get("states_sampled") or 0) < budget


def config_of(r: dict[str, Any]) -> str:
    """``planner/space/sampler`` (the custom sampler combination abbreviated to ``custom``)."""
    return f"{r['planner']}/{r['space']}/{'uniform' if r['sampler'] == 'uniform' else 'custom'}"


def table(results: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per configuration: runs, solved, success rate and its Wilson interval, median time and validity checks
    of solved runs, crashes and hard timeouts, runs the guard stopped before their check budget (``guard``, of
    them unsolved ``guard_unsolved``, their median checks ``guard_checks``); sorted by success rate, then
    lower bound, then median time."""
    import numpy as np

    groups: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for r in results:
        groups[config_of(r)].append(r)
    rows = []
    for cfg, rs in groups.items():
        ok = [r for r in rs if r["solved"]]
        guard = [r for r in rs if guard_stopped(r)]
        lo, hi = wilson(len(ok), len(rs))
        rows.append({"config": cfg, "planner": rs[0]["planner"], "space": rs[0]["space"],
                     "sampler": "uniform" if rs[0]["sampler"] == "uniform" else "custom",
                     "runs": len(rs), "solved": len(ok), "rate": len(ok) / len(rs), "lo": lo, "hi": hi,
                     "median_s": float(np.median([r["time"] for r in ok])) if ok else None,
                     "median_checks": float(np.median([r["states_sampled"] or 0 for r in ok])) if ok else None,
                     "crashed": sum(bool(r.get("crashed")) for r in rs),
                     "timed_out": sum(bool(r.get("timed_out")) for r in rs),
                     "guard": len(guard), "guard_unsolved": sum(not r["solved"] for r in guard),
                     "guard_checks": float(np.median([r["states_sampled"] or 0 for r in guard])) if guard else None})
    rows.sort(key=lambda x: (-x["rate"], -x["lo"], x["median_s"] if x["median_s"] is not None else math.inf,
                             x["config"]))
    return rows


def recommendation(rows: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """The best configuration and how sure the data is: the configurations whose Wilson interval overlaps
    the best one's (``tied``), and whether the best one's lower bound is above every other's upper bound."""
    if not rows:
        return {"best": None, "tied": [], "separated": False}
    best = rows[0]
    tied = [r["config"] for r in rows[1:] if r["hi"] >= best["lo"]]
    return {"best": best["config"], "tied": tied, "separated": not tied, "rank": {r["config"]: i + 1
                                                                                 for i, r in enumerate(rows)}}


def _pct(x: float) -> str:
    return f"{100 * x:.0f} %"


def success_rank(rows: Sequence[dict[str, Any]], config: str) -> tuple[int, int] | None:
    """``(rank, shared)`` of ``config`` by success rate alone: 1 + the configurations with a strictly higher
    rate, and how many others have the same rate; ``None`` when ``config`` is not in ``rows``."""
    row = next((r for r in rows if r["config"] == config), None)
    if row is None:
        return None
    better = sum(r["rate"] > row["rate"] for r in rows)
    same = sum(r["rate"] == row["rate"] for r in rows) - 1
    return better + 1, same


def default_rank_sentence(rows: Sequence[dict[str, Any]], config: str) -> str:
    """Where the climb's default configuration ``config`` stands in ``rows`` (the page's wording)."""
    rk = next((i + 1 for i, r in enumerate(rows) if r["config"] == config), None)
    if rk is None:
        return f"The climb's FIND-PATH default ({config}, `ClimbSettings`) is not in this run."
    row = rows[rk - 1]
    by_rate, shared = success_rank(rows, config)  # type: ignore[misc]
    return (f"The climb's FIND-PATH default ({config}, `ClimbSettings`) solves {row['solved']}/{row['runs']} "
            f"({_pct(row['rate'])}, 95 % CI {_pct(row['lo'])}-{_pct(row['hi'])}): by success rate it ranks "
            f"{by_rate} of {len(rows)}" + (f", its rate shared with {shared} other configuration(s)" if shared else "")
            + f" ({by_rate - 1} configuration(s) solve more); in the table's order (success, then the interval's "
            f"lower bound, then the median time of solved runs) it is number {rk}.")


def _figures(results: Sequence[dict[str, Any]], rows: Sequence[dict[str, Any]], out: Path, top: int) -> list[str]:
    """Write the page's PNG figures to ``out``; return their file names."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import numpy as np

    out.mkdir(parents=True, exist_ok=True)
    names = []
    groups: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for r in results:
        groups[config_of(r)].append(r)
    shown = [r["config"] for r in rows[:top]]
    budget = max((r.get("max_iterations") or 0 for r in results), default=0) or max(
        (r["states_sampled"] or 0 for r in results), default=1)
    tmax = max((r["time_limit"] for r in results), default=1.0)

    fig, axes = plt.subplots(1, 2, figsize=(11, 4.2))
    bs = np.linspace(0, budget, 200)
    ts = np.geomspace(0.01, tmax, 200)
    for i, cfg in enumerate(shown):
        rs = groups[cfg]
        ls = ("-", "--", ":")[i // 10 % 3]  # ten colours, then the next line style
        checks = np.array([r["states_sampled"] or 0 for r in rs if r["solved"]])
        times = np.array([r["time"] for r in rs if r["solved"]])
        axes[0].plot(bs, [(checks <= b).sum() / len(rs) for b in bs], ls, label=cfg)
        axes[1].plot(ts, [(times <= t).sum() / len(rs) for t in ts], ls, label=cfg)
    axes[0].set(xlabel="budget (validity checks)", ylabel="success rate", ylim=(0, 1.02),
                title="Success vs. validity-check budget")
    axes[1].set(xlabel="time limit (s, log)", xscale="log", ylim=(0, 1.02), title="Success vs. time")
    axes[1].legend(fontsize=6, loc="lower right")
    fig.tight_layout()
    fig.savefig(out / "success_vs_budget.png", dpi=100)
    plt.close(fig)
    names.append("success_vs_budget.png")

    fig, ax = plt.subplots(figsize=(max(6, 0.45 * len(shown)), 4))
    data = [[r["time"] for r in groups[c] if r["solved"]] or [np.nan] for c in shown]
    ax.boxplot(data)
    ax.set_yscale("log")
    ax.set_xticks(range(1, len(shown) + 1), shown, rotation=60, ha="right", fontsize=6)
    ax.set(ylabel="time of solved runs (s, log)", title="Time distribution (solved runs)")
    fig.tight_layout()
    fig.savefig(out / "times.png", dpi=100)
    plt.close(fig)
    names.append("times.png")

    planners = sorted({r["planner"] for r in results})
    spaces = sorted({r["space"] for r in results})
    succ = np.full((len(planners), len(spaces)), np.nan)
    for i, p in enumerate(planners):
        for j, s in enumerate(spaces):
            rs = [r for r in results if r["planner"] == p and r["space"] == s and r["sampler"] == "uniform"]
            if rs:
                succ[i, j] = sum(bool(r["solved"]) for r in rs) / len(rs)
    fig, ax = plt.subplots(figsize=(1.8 + 1.5 * len(spaces), 1.0 + 0.32 * len(planners)))
    cmap = matplotlib.colormaps["viridis"].with_extremes(bad="0.85")
    im = ax.imshow(np.ma.masked_invalid(succ), cmap=cmap, vmin=0, vmax=1, aspect="auto")
    for i in range(len(planners)):
        for j in range(len(spaces)):
            if not np.isnan(succ[i, j]):
                ax.text(j, i, f"{succ[i, j]:.0%}", ha="center", va="center", fontsize=7,
                        color="k" if succ[i, j] > 0.6 else "w")
    ax.set_xticks(range(len(spaces)), spaces)
    ax.set_yticks(range(len(planners)), planners, fontsize=7)
    fig.colorbar(im, ax=ax, label="success rate")
    ax.set_title("Planner x space (uniform sampling)")
    fig.tight_layout()
    fig.savefig(out / "heatmap.png", dpi=100)
    plt.close(fig)
    names.append("heatmap.png")

    eff = _sampler_effect(results)
    if eff:
        fig, ax = plt.subplots(figsize=(max(6, 0.4 * len(eff)), 3.6))
        x = np.arange(len(eff))
        ax.bar(x - 0.2, [e["uniform"] for e in eff], 0.4, label="uniform")
        ax.bar(x + 0.2, [e["custom"] for e in eff], 0.4, label="custom")
        ax.set_xticks(x, [e["planner"] for e in eff], rotation=60, ha="right", fontsize=7)
        ax.set(ylabel="success rate", ylim=(0, 1.02), title="Sampler effect on the projected space")
        ax.legend(fontsize=7)
        fig.tight_layout()
        fig.savefig(out / "sampler_effect.png", dpi=100)
        plt.close(fig)
        names.append("sampler_effect.png")
    return names


def mcnemar_exact(b: int, c: int) -> float:
    """Two-sided exact McNemar p-value of ``b`` vs ``c`` discordant pairs (a sign test: binomial, p = 1/2)."""
    n = b + c
    if n == 0:
        return 1.0
    tail = sum(math.comb(n, i) for i in range(min(b, c) + 1)) / 2.0 ** n
    return min(1.0, 2.0 * tail)


def paired(results: Sequence[dict[str, Any]], a: str, b: str) -> dict[str, Any]:
    """Configurations ``a`` and ``b`` (:func:`config_of` names) on the same (query, seed) pairs: how many pairs,
    solved by ``a`` only, by ``b`` only, and the exact McNemar p-value of that split."""
    by: dict[str, dict[tuple[int, int], bool]] = {a: {}, b: {}}
    for r in results:
        c = config_of(r)
        if c in by:
            by[c][(r["query"], r["seed"])] = bool(r["solved"])
    pairs = sorted(set(by[a]) & set(by[b]))
    only_a = sum(by[a][k] and not by[b][k] for k in pairs)
    only_b = sum(by[b][k] and not by[a][k] for k in pairs)
    return {"pairs": len(pairs), "only_a": only_a, "only_b": only_b, "p": mcnemar_exact(only_a, only_b)}


def per_set(results: Sequence[dict[str, Any]], configs: Sequence[str]) -> dict[str, dict[str, tuple[int, int]]]:
    """Per configuration of ``configs`` (:func:`config_of` names) and query set: ``(solved, runs)``."""
    out: dict[str, dict[str, list[int]]] = {c: defaultdict(lambda: [0, 0]) for c in configs}
    for r in results:
        c = config_of(r)
        if c in out:
            cell = out[c][r.get("query_set") or "?"]
            cell[0] += bool(r["solved"])
            cell[1] += 1
    return {c: {k: (v[0], v[1]) for k, v in sorted(sets.items())} for c, sets in out.items()}


def _sampler_effect(results: Sequence[dict[str, Any]]) -> list[dict[str, Any]]:
    """Per planner, projected space: success with uniform and with the custom sampler, and the runs paired by
    (query, seed): ``only_custom`` / ``only_uniform`` solved, with the exact McNemar p-value."""
    by: dict[tuple[str, str], dict[tuple[int, int], bool]] = defaultdict(dict)
    for r in results:
        if r["space"] == "projected":
            kind = "uniform" if r["sampler"] == "uniform" else "custom"
            by[(r["planner"], kind)][(r["query"], r["seed"])] = bool(r["solved"])
    out = []
    for p in sorted({k[0] for k in by}):
        u, c = by.get((p, "uniform")), by.get((p, "custom"))
        if u and c:
            pairs = sorted(set(u) & set(c))
            b = sum(c[k] and not u[k] for k in pairs)
            d = sum(u[k] and not c[k] for k in pairs)
            out.append({"planner": p, "uniform": sum(u.values()) / len(u), "custom": sum(c.values()) / len(c),
                        "n": len(u), "ku": sum(u.values()), "kc": sum(c.values()), "nc": len(c),
                        "pairs": len(pairs), "only_custom": b, "only_uniform": d, "p": mcnemar_exact(b, d)})
    return out


def _pooled_rows(results: Sequence[dict[str, Any]], title: str, pick: Any) -> list[str]:
    groups: dict[str, list[bool]] = defaultdict(list)
    for r in results:
        key = pick(r)
        if key is not None:
            groups[key].append(bool(r["solved"]))
    out = []
    for g in sorted(groups):
        k, m = sum(groups[g]), len(groups[g])
        lo, hi = wilson(k, m)
        out.append(f"| {title}: {g} | {m} | {_pct(k / m)} | {_pct(lo)}-{_pct(hi)} |")
    return out


def _grades() -> dict[int, dict[str, Any]]:
    """uid -> query (set, kind, hardness) of the bundled query sets."""
    from climb_ompl.bench._query_set import load_queries

    try:
        return {q["uid"]: q for q in load_queries()}
    except Exception:  # noqa: BLE001 - a page from a database of other queries still renders
        return {}


def experiment_info(db: str | Path) -> dict[str, Any] | None:
    """The first row of the database's ``experiments`` table (OMPL's layout: ``version``, ``date``,
    ``hostname``, ``cpuinfo``, ``totaltime`` ...); ``None`` when it has none."""
    import sqlite3

    con = sqlite3.connect(db)
    try:
        con.row_factory = sqlite3.Row
        row = con.execute("SELECT * FROM experiments ORDER BY id LIMIT 1").fetchone()
    except sqlite3.Error:
        return None
    finally:
        con.close()
    return dict(row) if row is not None else None


def _provenance(exp: dict[str, Any] | None) -> list[str]:
    """The set-up's line on what the database records of its making."""
    if not exp:
        return ["- The database has no `experiments` row: it records neither the code's version nor a date."]
    total = exp.get("totaltime")
    return [f"- The database records `{exp.get('version') or '?'}` and the start of its first run, "
            f"{exp.get('date') or '?'} UTC (`experiments` table; host `{exp.get('hostname') or '?'}`, "
            f"{exp.get('cpuinfo') or '?'}"
            + (f", `totaltime` {total / 60:.0f} min" if isinstance(total, (int, float)) else "") + ").  "
            "It records no commit, and a resumed comparison keeps the runs already in it (a run is keyed by "
            "planner, space, sampler, query, seed, budget and guard), so its runs may come from different states "
            "of the code; delete the database to run every run with the current code."]


def _guard_sentence(results: Sequence[dict[str, Any]], rows: Sequence[dict[str, Any]]) -> str:
    """The set-up's sentence on the runs the guard stopped (the budget is the same for every run only where
    the guard did not cut it short)."""
    g = sum(r["guard"] for r in rows)
    if not g:
        return "The guard stopped no run before its check budget: every run had the whole budget."
    u = sum(r["guard_unsolved"] for r in rows)
    hit = [r for r in rows if r["guard"]]
    by: dict[str, int] = defaultdict(int)
    for r in results:
        if r["solved"] and guard_stopped(r):
            by[r["planner"]] += 1
    solved = ", ".join(f"{p} {k}" for p, k in sorted(by.items(), key=lambda x: (-x[1], x[0])))
    return (f"The check budget was not the same in practice: the guard stopped {g} of the {len(results)} runs "
            f"({_pct(g / len(results))}) before they used it, {u} of them unsolved and {g - u} solved"
            + (f" (paths returned at the guard: {solved})" if solved else "")
            + f", in {len(hit)} of the {len(rows)} configurations.  How many checks "
            "such a run makes before the guard depends on the machine's load, so these configurations' success, "
            "checks and times depend on it too: a less loaded machine lets their runs go further and may solve "
            "more of them (see \"Runs the guard stopped\" below).")


def _guard_section(rows: Sequence[dict[str, Any]]) -> list[str]:
    """The configurations with unsolved runs the guard stopped, most first."""
    hit = sorted((r for r in rows if r["guard_unsolved"]), key=lambda r: (-r["guard_unsolved"], r["config"]))
    if not hit:
        return []
    L = ["## Runs the guard stopped", "",
         "A run the guard stopped (`time` at least the guard, fewer validity checks than the budget: "
         "`climb_ompl.bench._planners_report.guard_stopped`) ran out of wall-clock time, not of checks.  These "
         "configurations' unsolved runs include such runs, so their success rate is a figure of the machine's "
         "load as much as of the planner: on a less loaded machine the same runs make more checks before the "
         "guard and can solve.  The median checks at the guard shows how much of the budget those runs used: "
         "a run that made only a few checks before the guard spent its time outside the validity checks (in "
         "the planner, or in the constrained space's sampling and interpolation).", "",
         "| configuration | solved | guard-stopped | of them unsolved | median checks at the guard |",
         "|---|---|---|---|---|"]
    for r in hit:
        L.append(f"| {r['config']} | {r['solved']}/{r['runs']} | {r['guard']} | {r['guard_unsolved']} | "
                 f"{r['guard_checks']:.0f} |")
    walks = any(r["config"].split("/")[1:2] == ["projected"] and r["config"].split("/")[0] in WALKING
                and r["guard_checks"] <= 20 for r in hit)
    return L + ["", PROJECTED_WALKS, ""] if walks else L + [""]


#: The tree planners that extend towards uniform samples, whose few-check runs on the projected space
#: :data:`PROJECTED_WALKS` explains (it is printed when the guard stopped such a configuration's runs within 20
#: checks).
WALKING = ("RRT", "LazyRRT", "RRTstar", "TRRT", "RRTConnect")
#: Where the tree planners' time goes on the projected space (a profile of one run, written here: not read from
#: the database).
PROJECTED_WALKS = (
    "Where the few-check runs' time goes, profiled once (2026-12-04) for LazyRRT/projected/uniform on a "
    "lean55-80 query of the published comparison (1 check in 5.2 s): 4.3 s in 33,000 projections onto the "
    "stance manifold, every one from OMPL's `ConstrainedStateSpace::interpolate`.  To extend a tree towards a "
    "sample, OMPL 1.7 walks the manifold in steps of `delta` all the way to the sample, then keeps the first "
    "`range` of the walk; when the walk does not arrive, it returns the state it started from.  Most uniform "
    "samples lie off the manifold (OMPL's projected sampler clamps a projected sample into the joint bounds, "
    "and the projection ignores those bounds), so most walks crawl for 650-1750 projections and fail, and the "
    "tree grows by unchecked copies of its own vertices.  The tree planners that extend towards uniform "
    "samples (RRT, LazyRRT, RRTstar, TRRT, RRTConnect) suffer it; SBL and the KPIECE family sample near their "
    "trees.  Projections that keep the joints inside their bounds were tried on ten of these runs: 1.7 to 15 "
    "times the checks within the guard, and every run still unsolved; the cure is a walk that stops after "
    "`range`, inside OMPL.")


def render(results: Sequence[dict[str, Any]], *, db_name: str, fig_dir: str, figures: Sequence[str],
           grid_runs: int | None = None, full_runs: int = 1000, top: int = 12,
           experiment: dict[str, Any] | None = None) -> str:
    """The Markdown page (figures referenced as ``fig_dir/<name>``); ``experiment``: the database's
    :func:`experiment_info` (its version and date on the page)."""
    rows = table(results)
    cfgs = len(rows)
    dp, ds, dsa = climb_default()
    default_cfg = f"{dp}/{ds}/{'uniform' if dsa == 'uniform' else 'custom'}"
    L: list[str] = _intro(results, rows, db_name, grid_runs, full_runs, experiment)
    L += _recommendation(results, rows, default_cfg)
    L += _results_table(rows)
    L += _guard_section(rows)
    L += _figure_sections(set(figures), fig_dir, min(top, cfgs))
    L += _sampler_section(results, fig_dir)
    L += _pooled_section(results)
    L += _per_query_section(results)
    L += ["", "## Open the database in Planner Arena", "",
          "The database follows OMPL's benchmark layout (`docs/bench.md`):", "",
          "```", f"DATABASE={db_name if db_name.startswith('/') else '$PWD/' + db_name} plannerarena"
          "    # then open http://127.0.0.1:8888", "```", ""]
    return "\n".join(L)


def _intro(results: Sequence[dict[str, Any]], rows: list[dict[str, Any]], db_name: str, grid_runs: int | None,
           full_runs: int, experiment: dict[str, Any] | None) -> list[str]:
    """The page's title, where it comes from (a note when the run is small) and the set-up."""
    from climb_ompl.climb.onestep import RANGE_FRACTION

    n = len(results)
    cfgs = len(rows)
    queries = sorted({(r.get("query_set") or "?", r["query"]) for r in results})
    seeds = sorted({r["seed"] for r in results})
    budget = sorted({r.get("max_iterations") for r in results}, key=lambda x: (x is None, x))
    guard = sorted({r["time_limit"] for r in results})
    small = n < full_runs or (grid_runs is not None and n < grid_runs)
    L: list[str] = ["# Which OMPL planner for climbing", ""]
    L += ["Generated by `climb-ompl bench planners-doc` from the comparison database "
          f"(`{db_name}`, {n} runs); `make compare` runs the comparison (`climb-ompl bench compare`, resumable, "
          "Dask `LocalCluster` or `--scheduler tcp://HOST:PORT`) and regenerates this page and the executed "
          "notebooks `notebooks/02_one_step_planners.ipynb` and `notebooks/03_climb.ipynb`.", ""]
    if small:
        L += [f"**This page comes from a small run: {n} runs"
              + (f" of the {grid_runs}-run grid" if grid_runs else "")
              + f" ({n // max(cfgs, 1)} per configuration); the full comparison (`make compare`) regenerates it.  "
              "With so few runs per configuration the intervals below are wide and the ranking is provisional.**",
              ""]
    L += ["## Set-up", "",
          f"- {cfgs} configurations (planner / constrained space / sampler); `custom` is "
          "`joint-by-joint+straight-elbow+free-limb+lift` (projected space only: atlas and tangent-bundle "
          "spaces sample their own charts).",
          f"- {len(queries)} one-step queries from the versioned query sets (`climb_ompl/data/queries`, "
          "`climb-ompl bench queries`): {}; seeds {}.".format(
              ", ".join(f"`{s}`" for s in sorted({q for q, _ in queries})), ", ".join(map(str, seeds))),
          f"- Each run's budget: {', '.join(str(b) for b in budget)} validity checks or the wall-clock guard of "
          f"{', '.join(f'{g:g}' for g in guard)} s, whichever comes first; the planner alone answers "
          "(`find_path(direct=False)`).  " + _guard_sentence(results, rows),
          f"- Every planner that has a range (the longest motion one extension tries) gets {RANGE_FRACTION:g} of "
          "the ambient space's maximum extent (`climb_ompl.climb.onestep.RANGE_FRACTION`, `find_path`'s default; "
          "OMPL's is 0.2); the atlas and tangent-bundle spaces keep OMPL's chart radius.",
          "- Success rates carry Wilson 95 % score intervals (Wilson 1927); times were measured on a shared "
          "2-core machine: wall-clock figures are load-dependent, and so are the success and checks of a "
          "configuration whose runs the guard stopped (column `guard` below); success within the check budget "
          "is not."]
    return L + _provenance(experiment) + [""]


def _recommendation(results: Sequence[dict[str, Any]], rows: list[dict[str, Any]], default_cfg: str) -> list[str]:
    """The recommendation: the best configuration, how sure, against the climb's default ``default_cfg``, and the
    configurations at least as good as the default per query set."""
    rec = recommendation(rows)
    L = ["## Recommendation", ""]
    if rec["best"] is None:
        return L + ["No runs.", ""]
    best = rows[0]
    L += [f"**{best['config']}**: {best['solved']}/{best['runs']} solved "
          f"({_pct(best['rate'])}, 95 % CI {_pct(best['lo'])}-{_pct(best['hi'])})."]
    if rec["separated"]:
        L += ["Its interval lies above every other configuration's: the data supports it clearly."]
    else:
        tied = rec["tied"]
        L += [f"How sure: {len(tied)} other configuration(s) have intervals overlapping it "
              f"({', '.join(tied[:8])}{', ...' if len(tied) > 8 else ''}); at this sample size the data "
              "does not separate them, only the ones below."]
    d_row = next((r for r in rows if r["config"] == default_cfg), None)
    if d_row is not None and d_row is not best:
        L += _against_default(results, best, d_row, default_cfg, len(rows))
    L += ["", default_rank_sentence(rows, default_cfg), ""]
    above = [r["config"] for r in rows if r["rate"] >= (d_row["rate"] if d_row is not None else 2.0)]
    if d_row is not None and len(above) > 1:
        cells = per_set(results, above)
        sets = sorted({k for c in cells.values() for k in c})
        L += ["The configurations that solve as many runs as the default or more, per query set (solved/runs):",
              "", "| configuration | " + " | ".join(f"`{x}`" for x in sets) + " |",
              "|---|" + "---|" * len(sets)]
        for c in above:
            L.append(f"| {c} | " + " | ".join("{}/{}".format(*cells[c][x]) if x in cells[c] else "-"
                                              for x in sets) + " |")
        L += [""]
    return L


def _against_default(results: Sequence[dict[str, Any]], best: dict[str, Any], d_row: dict[str, Any],
                     default_cfg: str, cfgs: int) -> list[str]:
    """The best configuration against the climb's default: their intervals, and the paired runs (exact McNemar)."""
    sep = d_row["hi"] < best["lo"]
    pr = paired(results, best["config"], default_cfg)
    return ["", f"Against the climb's default ({default_cfg}: {d_row['solved']}/{d_row['runs']}, "
            f"{_pct(d_row['lo'])}-{_pct(d_row['hi'])}): "
            + ("the intervals do not overlap, the best configuration is better at this budget."
               if sep else "the intervals overlap.")
            + f"  Paired by query and seed ({pr['pairs']} pairs): solved by {best['config']} only "
            f"{pr['only_a']}, by the default only {pr['only_b']}, exact McNemar p = {pr['p']:.2g}"
            + (f": a difference at the 5 % level, though the best was picked after the fact among {cfgs} "
               "configurations, which makes this weaker evidence than it reads." if pr["p"] < 0.05 else
               ": the paired runs do not establish a difference either." if not sep else ".")]


def _results_table(rows: list[dict[str, Any]]) -> list[str]:
    """The table of every configuration: success with its interval, median time and checks, guard, crashes."""
    L = ["## Success rate (95 % Wilson interval), median time and checks of solved runs", "",
         "`guard`: runs the wall-clock guard stopped before their check budget (of them unsolved); these "
         "configurations' figures depend on the machine's load.  `killed`: runs the hard process timeout "
         "ended.", "",
         "| # | configuration | solved | success | 95 % CI | median s | median checks | guard (unsolved) | "
         "crashed | killed |",
         "|---|---|---|---|---|---|---|---|---|---|"]
    for i, r in enumerate(rows, 1):
        ms = f"{r['median_s']:.2f}" if r["median_s"] is not None else "-"
        mc = f"{r['median_checks']:.0f}" if r["median_checks"] is not None else "-"
        gd = f"{r['guard']} ({r['guard_unsolved']})" if r["guard"] else "0"
        L.append(f"| {i} | {r['config']} | {r['solved']}/{r['runs']} | {_pct(r['rate'])} | "
                 f"{_pct(r['lo'])}-{_pct(r['hi'])} | {ms} | {mc} | {gd} | {r['crashed']} | {r['timed_out']} |")
    return L + [""]


def _figure_sections(figs: set[str], fig_dir: str, shown: int) -> list[str]:
    """The sections of the figures written (``figs``): success against budget and time (the ``shown`` best
    configurations), time distributions, planner x space."""
    L: list[str] = []
    if "success_vs_budget.png" in figs:
        L += ["## Success against budget and time", "",
              f"The {shown} best configurations: the fraction of runs solved within b validity checks "
              "(the success a smaller budget would have had; a run's checks are counted at its end, the final "
              "path's checks included, so a few exceed the budget; a run the guard stopped counts as unsolved "
              "at every budget, though it had not used its checks) and within t seconds.  Asymptotically optimal "
              "planners (PRMstar, LazyPRMstar, RRTstar) use their whole budget or guard before returning.", "",
              f"![success vs budget]({fig_dir}/success_vs_budget.png)", ""]
    if "times.png" in figs:
        L += ["## Time distributions", "", f"![times]({fig_dir}/times.png)", ""]
    if "heatmap.png" in figs:
        L += ["## Planner x space", "", "Success rate with uniform sampling.", "",
              f"![heat map]({fig_dir}/heatmap.png)", ""]
    return L


def _sampler_section(results: Sequence[dict[str, Any]], fig_dir: str) -> list[str]:
    """The sampler's effect per planner on the projected space (paired runs, exact McNemar), if any."""
    eff = _sampler_effect(results)
    if not eff:
        return []
    L = ["## Sampler effect per planner (projected space)", "",
         "Runs paired by query and seed: solved by the custom sampler only / by uniform only, and the exact "
         "McNemar p-value of that split (small: the sampler makes a difference for this planner).", "",
         "| planner | uniform | custom | difference | pairs | custom only | uniform only | p |",
         "|---|---|---|---|---|---|---|---|"]
    for e in eff:
        L.append(f"| {e['planner']} | {e['ku']}/{e['n']} ({_pct(e['uniform'])}) | {e['kc']}/{e['nc']} "
                 f"({_pct(e['custom'])}) | {100 * (e['custom'] - e['uniform']):+.0f} points | {e['pairs']} | "
                 f"{e['only_custom']} | {e['only_uniform']} | {e['p']:.2g} |")
    return L + ["", f"![sampler effect]({fig_dir}/sampler_effect.png)", ""]


def _pooled_section(results: Sequence[dict[str, Any]]) -> list[str]:
    """Success pooled by space (uniform sampling), by sampler (projected space) and by query set."""
    L = ["## Pooled by space, by sampler and by query set", "",
         "Every planner's runs together (uniform sampling only for the spaces).", "",
         "| group | runs | success | 95 % CI |", "|---|---|---|---|"]
    for title, pick in (("space", lambda r: r["space"] if r["sampler"] == "uniform" else None),
                        ("sampler (projected)", lambda r: (config_of(r).rsplit("/", 1)[1]
                                                           if r["space"] == "projected" else None)),
                        ("query set", lambda r: r.get("query_set") or "?")):
        L += _pooled_rows(results, title, pick)
    return L


def _per_query_section(results: Sequence[dict[str, Any]]) -> list[str]:
    """Per query: every configuration's success against the reference planner's grade (the query file's
    ``hardness``)."""
    L = ["", "## Per query: the comparison's success against the reference planner's grade", "",
         "The reference grade is the query file's `hardness` (`climb_ompl/data/queries`).", "",
         "| query | set | kind | reference solved | runs | success (all configurations) |",
         "|---|---|---|---|---|---|"]
    grades = _grades()
    per_q: dict[int, list[bool]] = defaultdict(list)
    for r in results:
        per_q[r["query"]].append(bool(r["solved"]))
    for uid in sorted(per_q):
        g = grades.get(uid, {})
        h = g.get("hardness") or {}
        ref = f"{h['solved']}/{h['runs']}" if h else "-"
        k, m = sum(per_q[uid]), len(per_q[uid])
        L.append(f"| {uid} | {g.get('set', '?')} | {g.get('kind', '?')} | {ref} | {m} | {_pct(k / m)} |")
    return L


def write_page(db: str | Path, out: str | Path, *, fig_dir: str | Path | None = None,
               copy_db: str | Path | None = None, grid_runs: int | None = None) -> Path:
    """Write the page ``out`` (and its figures in ``fig_dir``, default ``<out stem>/``) from ``db``.

    ``copy_db``: also store a compacted copy of the database there (the one the page names).  ``grid_runs``
    (the full grid's size, named on a partial run's page) defaults to ``compare.json`` beside ``db``.

    Raises:
        InputError: the database is missing or holds no runs.
    """
    import sqlite3

    from climb_ompl._io import atomic_write
    from climb_ompl.bench._runs import load_results
    from climb_ompl.errors import InputError

    db, out = Path(db), Path(out)
    results = load_results(db)  # a missing file, a folder or no benchmark database: InputError
    if not results:
        raise InputError(db, "grid_runs", "the database holds no runs")
    summary = db.parent / "compare.json"
    if grid_runs is None and summary.is_file():  # written beside the database by `climb-ompl bench compare`
        import json

        grid_runs = json.loads(summary.read_text()).get("grid_runs")
    figs_path = Path(fig_dir) if fig_dir is not None else out.parent / out.stem
    figures = _figures(results, table(results), figs_path, top=12)
    shown_db = db
    if copy_db is not None:
        copy_db = Path(copy_db)
        tmp = copy_db.with_suffix(".tmp")
        tmp.unlink(missing_ok=True)
        src = sqlite3.connect(db)
        try:
            src.execute("VACUUM INTO ?", (str(tmp),))
        finally:
            src.close()
        tmp.replace(copy_db)
        shown_db = copy_db
    try:
        rel_figs = figs_path.resolve().relative_to(out.parent.resolve())
    except ValueError:
        rel_figs = figs_path.resolve()
    try:
        name = str(Path(shown_db).resolve().relative_to(Path.cwd()))
    except ValueError:
        name = str(shown_db)
    text = render(results, db_name=name, fig_dir=str(rel_figs), figures=figures, grid_runs=grid_runs,
                  experiment=experiment_info(db))
    return atomic_write(out, text)


__all__ = ["Z95", "wilson", "mcnemar_exact", "table", "recommendation", "render", "write_page", "climb_default",
           "config_of", "success_rank", "default_rank_sentence", "paired", "per_set", "guard_stopped",
           "experiment_info"]
