# ---
# jupyter:
#   jupytext:
#     formats: ipynb,py:percent
#     text_representation:
#       extension: .py
#       format_name: percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # 02 - One-step planners on LEMUR: planners, constrained spaces, samplers
#
# A *one-step* query (Bretl et al. (2004), sec. 3; Bretl (2006), Fig. 17, FIND-PATH) moves LEMUR on a three-hold stance
# from the configuration where it released a hand to the one where it grabs the next hold.  The queries
# come from a greedy climb on the bundled `demo-wall` (`climb_ompl.bench._runs.make_queries`).  Every run is
# planned in its own process by the benchmark harness (`climb_ompl.bench._runs`, the same code as
# `climb-ompl bench grid`), with a reproducible budget of validity checks and a wall-clock guard.  The
# planner alone answers (`find_path(direct=False)`): the climb's lift-move-place local path, tried first in a
# climb, solves these queries before any planner runs, and would give every planner the same answer.
#
# Three experiments: (1) every registered OMPL planner on the atlas space; (2) the three constrained
# spaces (`projected`, `atlas`, `tangent_bundle`) for two planners; (3) samplers (uniform vs. the
# straight-elbow sampler of Bretl (2006), sec. 4.2.2, and the free-limb samples nearest the equilibrium
# boundary of Bretl et al. (2004), sec. 3) on the projected space, the only one where custom samplers are used.
# The prose conclusions below are computed from the data.

# %% tags=["parameters"]
# ruff: noqa: E402, B018  (a notebook: imports follow the parameters cell; bare names display tables)
import os

N_QUERIES = int(os.environ.get("NB_QUERIES", "5"))
PLANNERS = os.environ.get("NB_PLANNERS", "all")  # "all" or comma-separated names
TIME_LIMIT = float(os.environ.get("NB_TIME_LIMIT", "5"))  # wall-clock guard per run, s
MAX_ITERATIONS = int(os.environ.get("NB_MAX_ITERATIONS", "5000"))  # validity-check budget per run
WORKERS = int(os.environ.get("NB_WORKERS", "0")) or None  # local process pool (default: CPU count)
SEEDS = [int(s) for s in os.environ.get("NB_SEEDS", "0").split(",")]

# %%
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from climb_ompl import PLANNER_NAMES
from climb_ompl.bench._runs import Grid, make_queries, run_grid

planners = list(PLANNER_NAMES) if PLANNERS == "all" else [p.strip() for p in PLANNERS.split(",")]
queries = make_queries("lemur", "demo-wall", N_QUERIES, seed=0)
work = Path(tempfile.mkdtemp(prefix="nb02-"))
print(len(queries), "queries:", [f"{q['moving']} {q['from_hold']}->{q['to_hold']}" for q in queries])


def grid(name, planners, spaces, samplers):
    g = Grid(name=name, planners=planners, spaces=spaces, samplers=samplers, queries=queries, seeds=SEEDS,
             time_limit=TIME_LIMIT, max_iterations=MAX_ITERATIONS,
             extra={"direct": False})  # the planner alone answers (see above)
    return pd.DataFrame(run_grid(g, work / f"{name}.db", workers=WORKERS))


def medians(df, by):
    out = df.groupby(by).apply(lambda d: pd.Series({
        "runs": len(d), "success": d["solved"].mean(),
        "median_s": d.loc[d["solved"], "time"].median(),
        "median_checks": d.loc[d["solved"], "states_sampled"].median(),
        "median_path": d.loc[d["solved"], "path_length"].median(),
        "crashed": int(d["crashed"].sum())}), include_groups=False)
    return out.sort_values(["success", "median_s"], ascending=[False, True])


# %% [markdown]
# ## 1. Every planner (atlas space, uniform sampling)

# %%
df1 = grid("planners", planners, ["atlas"], ["uniform"])
t1 = medians(df1, "planner")
t1

# %%
fig, ax = plt.subplots(figsize=(max(6, 0.45 * len(t1)), 3.8))
order = list(t1.index)
data = [df1.loc[(df1.planner == p) & df1.solved, "time"].to_numpy() for p in order]
ax.boxplot([d if len(d) else [np.nan] for d in data])
ax.set_xticks(range(1, len(order) + 1), order, rotation=45, ha="right")
ax.set(ylabel="time of solved runs (s)", yscale="log", title="One-step planning time by planner (atlas)")
for i, p in enumerate(order, start=1):
    ax.text(i, ax.get_ylim()[1], f"{t1.loc[p, 'success']:.0%}", ha="center", va="bottom", fontsize=7)

# %%
best = t1.index[0]
solved_all = t1[t1.success == t1.success.max()]
print(f"Conclusion 1: {len(t1)} planners on {len(queries)} queries x {len(SEEDS)} seed(s). "
      f"Best success rate {t1.success.max():.0%} ({', '.join(solved_all.index[:6])}"
      f"{'...' if len(solved_all) > 6 else ''}); fastest among them {best} "
      f"(median {t1.loc[best, 'median_s']:.2f} s). "
      f"Planners that solved nothing: {', '.join(t1.index[t1.success == 0]) or 'none'}; "
      f"crashed runs: {int(t1.crashed.sum())}.")

# %% [markdown]
# ## 2. Constrained spaces

# %%
sp_planners = [p for p in ("LazyPRM", "RRTConnect") if p in planners] or planners[:2]
df2 = grid("spaces", sp_planners, ["projected", "atlas", "tangent_bundle"], ["uniform"])
t2 = medians(df2, ["space", "planner"])
t2

# %%
by_space = df2.groupby("space")["solved"].mean().sort_values(ascending=False)
slow = df2.groupby("space")["time"].median()
print("Conclusion 2: success rate by space: " + ", ".join(f"{s} {v:.0%}" for s, v in by_space.items())
      + "; median run time (all runs): " + ", ".join(f"{s} {slow[s]:.2f} s" for s in by_space.index) + ". "
      + (f"The {by_space.index[0]} space is the one to use for these stances."
         if by_space.iloc[0] > by_space.iloc[-1] else "The spaces do equally well here."))

# %% [markdown]
# ## 3. Samplers (projected space)
# Straight-elbow sampling (Bretl (2006), sec. 4.2.2; the "straight-limb" samples of Bretl et al. (2004),
# sec. 3) and free-limb samples nearest the equilibrium boundary (Bretl et al. (2004), sec. 3) against uniform
# sampling of the ambient space followed by projection.

# %%
sa_planners = [p for p in ("PRM", "LazyPRM") if p in planners] or planners[:1]
df3 = grid("samplers", sa_planners, ["projected"], ["uniform", "straight-elbow", "free-limb"])
t3 = medians(df3, ["sampler", "planner"])
t3

# %%
by_sampler = df3.groupby("sampler").agg(success=("solved", "mean"), median_s=("time", "median"))
base = by_sampler.loc["uniform"]
lines = []
for s, row in by_sampler.iterrows():
    if s == "uniform":
        continue
    lines.append(f"{s}: success {row.success:.0%} vs uniform {base.success:.0%}, "
                 f"median run time {row.median_s:.2f} s vs {base.median_s:.2f} s")
print("Conclusion 3: " + "; ".join(lines) + ".")

# %% [markdown]
# **Caveat.** These are small grids (a handful of queries, one seed unless `NB_SEEDS` says otherwise): the
# conclusions printed above are what *this* data says; run `climb-ompl bench grid --preset planners` /
# `--preset samplers` with more queries and seeds (on a Dask cluster with `--scheduler`) before trusting
# a ranking.  Runs that stop on the validity-check budget repeat exactly; runs that hit the wall-clock
# guard depend on the machine's load.
