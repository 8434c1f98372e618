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
# # 04 - The papers' figures and numbers, reproduced next to theirs
#
# Regenerates the numbers and figures of `docs/papers.md`, paper by paper.  `NB_SCALE=paper` (the default,
# minutes on 2 cores) uses the page's parameters; `NB_SCALE=small` (the test suite) runs every cell with
# tiny ones, so its numbers are smoke values, not the page's.  Figures are written to `NB_OUT` (default:
# the current directory; `docs/` holds the page's copies).
#
# The papers' times come from C++ on 2003-2006 hardware and their own walls; ours are Python callbacks
# around OMPL on `demo-wall`: compare shapes and orders of magnitude, not digits.

# %% tags=["parameters"]
# ruff: noqa: E402, B018  (a notebook: imports follow the parameters cell; bare names display tables)
import os

SCALE = os.environ.get("NB_SCALE", "paper")  # "paper" (docs/papers.md) or "small" (the test suite)
SMALL = SCALE == "small"
OUT = os.environ.get("NB_OUT", ".")
SEED = int(os.environ.get("NB_SEED", "0"))
N_QUERIES = 2 if SMALL else 20  # one-step queries (Bretl et al. 2004, Fig. 6, T_max)
T_MAX = 1.0 if SMALL else 20.0  # one-step time limit, s (small: the planner-only queries run to it)
GAIN_DRAWS = 20 if SMALL else 300  # samples per sampler (Bretl 2006, sec. 4.3)
GAIN_STANCES = 2 if SMALL else None  # stances of the climb's query set for the same (None: all 49)
GAIN_CLIMB_DRAWS = 10 if SMALL else 60  # samples per sampler and stance there
STANCE_SAMPLES = 4 if SMALL else 300  # sampled stances per size (Bretl et al. 2004: > 20000 stances)
CLIMB_HEIGHT = 0.25 if SMALL else 2.0  # metres above the start (steps per 2 m, steps to the reach limit)
CLIMB_TIME_LIMIT = 60.0 if SMALL else 600.0
TREES = 1 if SMALL else 10  # generated trees (Lam et al., Fig. 13)
DOUBLE_LINK = not SMALL  # the double-link climb (Bretl 2006, Fig. 13; about 10 s, also in tests/test_multistep.py)

# %%
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import pandas as pd

from climb_ompl.bench import papers
from climb_ompl.bench.onestep import run as onestep_run
from climb_ompl import RobotModel

out = Path(OUT)
out.mkdir(parents=True, exist_ok=True)

# %% [markdown]
# ## Bretl, Latombe & Rock (2003)
# ### Fig. 4: the space Θ of the free limb's angles
# Curves of constant `δ = x_c/free - x_p` (Eq. 3) for δ = -0.9L, -0.5L, 0, 0.5L, 0.9L (Fig. 4a), and the
# feasible band between δ_min = -0.1L and δ_max = 0.7L (Fig. 4b).  δ is computed from the Pinocchio model of
# `planar-3limb` (the CoM of the whole robot with the free limb moved), not from Eq. 3.

# %%
robot3 = RobotModel.load("planar-3limb")
L = float(robot3.limbs[0].reach) / 2
free = robot3.limbs[2]
j1, j2 = free.joint_indices
q = np.asarray(robot3.nominal_q, float).copy()
q[list(robot3.base_indices)] = 0.0
th = np.linspace(-np.pi, np.pi, 181)
T1, T2 = np.meshgrid(th, th, indexing="ij")
com = np.empty(T1.shape)
for a in range(len(th)):
    for b in range(len(th)):
        q[j1], q[j2] = T1[a, b], T2[a, b]
        com[a, b] = robot3.com(q)[0]
q[j1], q[j2] = 0.0, 0.0  # free limb straight along +x: delta = L
delta = (3 * (com - robot3.com(q)[0]) + L) / L  # three limbs of equal mass, massless pelvis
fig, axs = plt.subplots(1, 2, figsize=(8, 3.6))
cs = axs[0].contour(T1, T2, delta, levels=[-0.9, -0.5, 0.0, 0.5, 0.9], colors="k")
axs[0].clabel(cs, fmt="%.1fL", fontsize=7)
axs[0].set(title="(a) curves of constant δ", xlabel="θ1 (rad)", ylabel="θ2 (rad)")
axs[1].contourf(T1, T2, (delta >= -0.1) & (delta <= 0.7), levels=[0.5, 1.5], colors=["0.75"])
axs[1].contour(T1, T2, delta, levels=[-0.1, 0.7], colors="k")
axs[1].set(title="(b) Θ_f for δ in [-0.1L, 0.7L]", xlabel="θ1 (rad)")
fig.tight_layout()
fig.savefig(out / "papers_theta_space.png", dpi=110)
print(f"delta range {delta.min():.3f}L .. {delta.max():.3f}L (Eq. 3: -L .. L); "
      f"Θ_f share of Θ in (b): {np.mean((delta >= -0.1) & (delta <= 0.7)):.2f}")

# %% [markdown]
# ## Bretl (2006)
# ### Sec. 4.3: joint-by-joint sampling (< 5 % of samples within joint limits -> over 75 %)

# %%
gain = papers.sampling_gain(n=GAIN_DRAWS, seed=SEED)
pd.DataFrame([{"stance": s["stance"], "uniform + projection, in limits": f"{s['uniform']['in_limits']}/"
               f"{s['uniform']['projected']} ({100 * s['uniform']['share_in_limits']:.1f} %)",
               "joint-by-joint, closed and in limits": f"{s['joint_by_joint']['in_limits']}/{GAIN_DRAWS} "
               f"({100 * s['joint_by_joint']['share_in_limits']:.1f} %)",
               "ms per draw (uniform / jbj)": f"{s['uniform']['ms_per_draw']:.2f} / "
               f"{s['joint_by_joint']['ms_per_draw']:.2f}"} for s in gain["stances"]])

# %% [markdown]
# The same on the stances of a climb (the `lemur-demo-wall` query set), with the joint-by-joint draws taken
# apart: why a draw fails, and the share when the base is drawn only among poses where every contact limb
# closes within its limits (the paper enforces the limits joint by joint, the base included).

# %%
gc = papers.sampling_gain_climb(n=GAIN_CLIMB_DRAWS, stances=GAIN_STANCES, seed=SEED)
pd.DataFrame([{"holds": k, "stances": v["stances"],
               "uniform + projection, in limits": f"{v['uniform_in_limits']}/{v['uniform_projected']} "
               f"({100 * v['uniform_share']:.1f} %)",
               "joint-by-joint": f"{100 * v['jbj_share']:.0f} %",
               "joint-by-joint, limit-exact base": f"{100 * v['exact_base_share']:.0f} %",
               **{f"fails: {c}": f"{100 * x:.0f} %" for c, x in sorted(v["jbj_failures"].items())}}
              for k, v in gc["by_size"].items()])

# %% [markdown]
# ### Sec. 5.3: about 80 steps to climb 2 m, 4-12 steps to the limit of reach
# A step is one grab or one release.  Steps to the reach limit: until a hand grabs a hold at or above the
# start's highest hold plus the limb reach (0.42 m).

# %%
climb = papers.climb_figures(height=CLIMB_HEIGHT, seed=SEED, time_limit=CLIMB_TIME_LIMIT)
if climb["found"]:
    per2m = climb["steps"] * 2.0 / climb["rise_m"] if climb["rise_m"] > 0 else float("nan")
    print(f"{climb['steps']} steps for {climb['rise_m']:.2f} m of mean hold height -> {per2m:.0f} steps per 2 m"
          f"{'' if climb['rise_m'] >= 1.95 else ' (extrapolated)'}; reach limit after "
          f"{climb['reach_limit']['steps']} steps   |   Bretl (2006): ~80 per 2 m, 4-12 to the reach limit")
    fig, ax = plt.subplots(figsize=(6, 3.5))
    z = np.array(climb["heights"])
    ax.plot(range(len(z)), z - z[0], "o-", ms=3, label="ours")
    ax.plot([0, 80], [0, 2], "C1--", label="80 steps / 2 m (Bretl 2006)")
    ax.plot([0, 88], [0, 2], "C1:", label="88 moves / 2 m (Bretl et al. 2004)")
    ax.set(xlabel="step", ylabel="mean hold height gained (m)", title="Steps vs. height")
    ax.legend(fontsize=7)
    fig.savefig(out / "papers_steps.png", dpi=110, bbox_inches="tight")
else:
    print("not found in this run:", climb["reason"])

# %% [markdown]
# ### Fig. 13: the double-link robot's stance sequence 1 -> 2 -> 3 -> 2 -> 4
# (Fig. 5's structure, the components of each stance manifold, is asserted by
# `tests/test_terrain_bundled.py::test_pegs_stance_manifolds_have_the_structure_of_fig_5`.)

# %%
if DOUBLE_LINK:
    from climb_ompl import plan_climb

    dl = plan_climb("double-link", "pegs", {"a": "1"}, "a=4", time_limit=120, seed=SEED,
                    q_start=[1.70, 0.90, 0.5 - 2 * np.pi, 1.0], heuristic_weight=1.0, step_time_limit=0.5)
    seq = ["1"] + [s.hold for s in dl.plan.steps if s.action == "grab"] if dl.found else []
    print("ours:", " -> ".join(seq) if dl.found else dl.reason, "  |   Bretl (2006), Fig. 13: 1 -> 2 -> 3 -> 2 -> 4")

# %% [markdown]
# ## Bretl et al. (2004)
# ### Fig. 6 and T_max: one-step times 0.09-17.3 s, mean 1.02 s, over 75 % quicker than the mean;
# ### T_max = 2 s would lose about 15 % of the moves, T_max = 20 s none
# `bench onestep`'s queries (a limb moves to a neighbouring hold), planner only (`direct=False`: the
# lift-move-place local plan is skipped, as the paper's planner has none) and with it; and the step-motion
# times along our climb above.

# %%
rows = {}
for direct in (False, True):
    r = onestep_run(queries=N_QUERIES, seed=SEED, time_limit=T_MAX, torque_compare=False, baseline=False,
                    direct=direct)
    m = r["runs"][r["sampler"]]
    rows["with local plan" if direct else "planner only"] = papers.onestep_times(m["times_s"], m["solved"])
    if not direct:
        t_planner = np.array([t for t, ok in zip(m["times_s"], m["solved"], strict=True) if ok])
if climb["found"]:
    rows["step motions along the climb"] = climb["step_motion_times"]
rows["Bretl et al. (2004)"] = {"queries": 88, "solved": 88, "min_s": 0.09, "max_s": 17.3, "mean_s": 1.02,
                               "share_below_mean": 0.75, "share_above_2s": 0.15}
pd.DataFrame(rows).T

# %%
fig, ax = plt.subplots(figsize=(6, 3.5))
bins = np.logspace(np.log10(0.01), np.log10(30), 25)
ax.hist(t_planner, bins=bins, label=f"ours, planner only (n={len(t_planner)})")
ax.axvspan(0.09, 17.3, color="C1", alpha=0.12, label="Bretl et al. (2004): 0.09-17.3 s")
ax.axvline(1.02, color="C1", label="their mean 1.02 s")
if len(t_planner):
    ax.axvline(t_planner.mean(), color="C0", ls="--", label=f"our mean {t_planner.mean():.2f} s")
ax.axvline(2.0, color="k", ls=":", label="T_max = 2 s")
ax.set(xscale="log", xlabel="one-step planning time (s)", ylabel="queries", title="One-step planning time")
ax.legend(fontsize=7)
fig.savefig(out / "papers_onestep_times.png", dpi=110, bbox_inches="tight")

# %% [markdown]
# ### Over 20000 feasible stances on a 2 m wall

# %%
sc = papers.stance_count(samples=STANCE_SAMPLES, seed=SEED)
pd.DataFrame([{"holds in the lowest 2 m": sc["holds"], "stance size": k, "sampled": v["samples"],
               "feasible": v["feasible"], "estimated feasible stances": f"{v['estimate']:.3g} ± {v['stderr']:.2g}",
               "pass the reach test": f"{v['reach_stances']:.3g}"} for k, v in sc["by_size"].items()])

# %% [markdown]
# ## Kim, Kang & Choi (MRWALLSPECT III): the 35 deg hill, up and down as one sequence
# Four transitions: floor to up slope (concave), up slope to top (convex, first plane tilted 35 deg), top to
# the down slope (convex) and down slope to floor (concave, first plane tilted -35 deg), with 1 m of slope,
# top and slope between the edges.  Each transition starts in the posture the previous one ended in and
# crawls along the plane to its own edge (`climb_ompl.mrwallspect.chain`); each plan is checked by
# `climb-ompl verify` (the verifier re-derives the trajectory from the paper's equations).

# %%
from climb_ompl.mrwallspect.chain import hill, next_start, plan_chain
from climb_ompl.verification import verify_plan_dict

chain = plan_chain(*hill(35.0, 1.0, 1.0, 1.0), seed=SEED)
rows = []
names = ["floor -> up slope", "up slope -> top", "top -> down slope", "down slope -> floor"]
for i, r in enumerate(chain.results):
    rep = verify_plan_dict(r.plan, "<hill>", resolution=0.2 if SMALL else 0.02) if r.found else None
    nxt = chain.results[i + 1] if i + 1 < len(chain.results) else None
    cont = (float(np.max(np.abs(np.asarray(nxt.plan["frames"][0]["q"]) - next_start(r.plan, chain.lengths[i]))))
            if nxt is not None and nxt.found else None)
    rows.append({"transition": names[i], "status": r.status, "d (m)": r.stats.get("d"),
                 "body steps": r.stats.get("steps"), "duration (s)": r.stats.get("duration_s"),
                 "plan time (s)": round(r.stats["plan_time_s"], 2), "verified": None if rep is None else rep.ok,
                 "max |q_next start - q end|": cont})
print("chained:", chain.found, chain.reason)
pd.DataFrame(rows)

# %%
fig, ax = plt.subplots(figsize=(7, 2.6))
for (R, c), r in zip(chain.world_frames(), chain.results, strict=False):
    o = np.array([c + R @ np.asarray(f["body"]["origin"]) for f in r.plan["frames"]])
    ax.plot(o[:, 0], o[:, 2], lw=1.5, label=r.plan["query"]["kind"])
    for pl in r.plan["planes"]:
        p, t = np.asarray(pl["point"]), np.asarray(pl["direction"])
        e = np.array([c + R @ (p + s * pl["extent"][0] / 2 * t) for s in (-1, 1)])
        ax.plot(e[:, 0], e[:, 2], color="0.4", lw=3, alpha=0.5)
ax.set(aspect="equal", xlabel="x (m)", ylabel="z (m)", title="35 deg hill: body origin along the chained gait")
ax.legend(fontsize=7)
fig.savefig(out / "papers_hill.png", dpi=110, bbox_inches="tight")

# %% [markdown]
# ## Lam et al. (TreeBot)
# ### Fig. 12: reward of the state space (trunk and branch 2 of the three-branch tree), planned path

# %%
from climb_ompl.treebot import DPPlanner, Tree
from climb_ompl.treebot.dp import rewards

tree = Tree.load("three-branch")
dp = DPPlanner.for_tree(tree, "b2")
R = np.array([rewards(r, tree.up, 1.0) for r in dp.rings])  # n_ij - 1 (a0 = 1), -inf at obstacles
path = dp.solve()
fig, ax = plt.subplots(figsize=(4, 5))
im = ax.imshow(np.where(np.isfinite(R), R + 1.0, np.nan), origin="lower", aspect="auto", cmap="viridis")
ax.plot([p.point for p in path.path], [p.row for p in path.path], "-o", color="0.6", ms=3)
ax.set(xlabel="point j on the ring", ylabel="ring i (trunk, then branch 2)", title="reward n_ij; blank: obstacles")
fig.colorbar(im, ax=ax, fraction=0.05)
fig.savefig(out / "papers_treebot_fig12.png", dpi=110, bbox_inches="tight")
print(f"{len(dp.rings)} rings x {dp.rings[0].n} points, {int(np.sum(~np.isfinite(R)))} obstacle points, "
      f"path cost {path.cost:.3f}")

# %% [markdown]
# ### Fig. 13: proposed vs. simple motion: ring density, arc fit, path smoothing
# Mean following error (body at the end of each extension to the path) and segment error (the segment
# being climbed to the body), mm, over generated trees.

# %%
rows = [{**r, "tree": "three-branch, b2"} for r in papers.treebot_fig13_three_branch()]
rows += [{**r, "tree": f"{r['trees']} generated"} for r in papers.treebot_fig13_factors(
    trees=TREES, points=(16,) if SMALL else (16, 32, 64), smooth=(0, 2), fits=("geometric", "algebraic"))]
pd.DataFrame([{"tree": r["tree"], "points/ring": r["points"], "arc fit": r["fit"], "smoothing (±k points)": r["smooth"],
               "following: proposed / simple": f"{r['proposed']['following_mm']:.1f} / "
               f"{r['simple']['following_mm']:.1f}",
               "segment: proposed / simple": f"{r['proposed']['segment_mm']:.1f} / {r['simple']['segment_mm']:.1f}"}
              for r in rows])
