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
# # 03 - A full climb: plan, statistics, independent check, 3-D playback
#
# The multi-step planner (`climb_ompl.climb.multistep.plan_climb`; Bretl (2006), section 3.3, Fig. 16) searches the
# stance graph (which hand goes on which hold next) and connects consecutive transitions with one-step
# OMPL paths.  Here LEMUR climbs the bundled `demo-wall`; the plan is then re-checked by `verify`, which
# trusts nothing the planner computed, and played back inline with meshcat (a self-contained HTML file).

# %% tags=["parameters"]
# ruff: noqa: E402, B018  (a notebook: imports follow the parameters cell; bare names display tables)
import os

ROBOT = os.environ.get("NB_ROBOT", "lemur")
TERRAIN = os.environ.get("NB_TERRAIN", "demo-wall")
GOAL = os.environ.get("NB_GOAL", "1.0")  # a height in metres, or LIMB=HOLD
PLANNER = os.environ.get("NB_PLANNER", "")  # FIND-PATH planner; "": the climb's default (ClimbSettings)
SPACE = os.environ.get("NB_SPACE", "")  # constrained space; "": the climb's default
TIME_LIMIT = float(os.environ.get("NB_TIME_LIMIT", "600"))  # whole query, s
STEP_TIME_LIMIT = float(os.environ.get("NB_STEP_TIME_LIMIT", "5"))  # one FIND-PATH call, s
SEED = int(os.environ.get("NB_SEED", "0"))
OUT = os.environ.get("NB_OUT", ".")  # where the playback HTML goes

# %%
import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from climb_ompl import default_start, plan_climb
from climb_ompl import RobotModel
from climb_ompl import ClimbSettings
from climb_ompl import Terrain

robot = RobotModel.load(ROBOT)
wall = Terrain.load(TERRAIN)
stance0, q0 = default_start(robot, wall, seed=SEED)
goal = float(GOAL) if GOAL.replace(".", "", 1).isdigit() else GOAL
print("start stance", stance0, "goal", goal)

# %%
t0 = time.perf_counter()
chosen = {k: v for k, v in (("planner", PLANNER), ("space", SPACE)) if v}  # else the ClimbSettings defaults
res = plan_climb(robot, wall, stance0, goal, time_limit=TIME_LIMIT, seed=SEED, q_start=q0,
                 step_time_limit=STEP_TIME_LIMIT, **chosen)
wall_s = time.perf_counter() - t0
d = ClimbSettings(**chosen)
print("found" if res.found else "no plan", f"in {wall_s:.1f} s", res.reason,
      f"| FIND-PATH: {d.planner} / {d.space} / {d.sampler}")
assert res.found, res.reason
plan = res.plan

# %% [markdown]
# ## Statistics

# %%
st = res.stats
print(f"steps: {st['steps']}  (grabs {sum(s.action == 'grab' for s in plan.steps)}, "
      f"releases {sum(s.action == 'release' for s in plan.steps)})")
print(f"stances explored: {st['stances_explored']}, candidate sequences: {st['candidates']}, "
      f"FIND-TRANSITION calls: {st['transition_calls']}, FIND-PATH calls: {st['path_calls']} "
      f"({st['path_failures']} failed)")
print(f"planning {st['total_s']:.1f} s; execution time of the motion {plan.execution_s:.1f} s")
print("rejections by reason (FIND-PATH):", st["rejections"])
hold_z = [max(wall.hold(h).p[2] for _, h in s.stance_after) for s in plan.steps]
print(f"highest hold: {hold_z[0]:.2f} m -> {hold_z[-1]:.2f} m")

# %%
fig, axes = plt.subplots(1, 3, figsize=(13, 3.6))
times = np.asarray(st["onestep_times_s"] + st["transition_times_s"], dtype=float)
if len(times):
    axes[0].hist(times, bins=min(20, max(3, len(times))))
axes[0].set(xlabel="FIND-PATH / FIND-TRANSITION time (s)", ylabel="calls", title="One-step planning times")
axes[1].plot(range(len(plan.steps)), hold_z, "o-")
axes[1].set(xlabel="step", ylabel="highest contact hold z (m)", title="Progress up the wall")
margins = [s.margin for s in plan.steps]
axes[2].bar(range(len(plan.steps)), [m * 100 for m in margins],
            color=["C0" if s.action == "grab" else "C1" for s in plan.steps])
axes[2].set(xlabel="step (blue grab, orange release)", ylabel="min margin (cm)", title="Equilibrium margin")
fig.tight_layout()

# %% [markdown]
# ## Independent check
# `verify` rebuilds robot and terrain from the plan file's embedded copies and re-checks every waypoint
# and the straight segments between them (hands on holds, equilibrium with exact cones where the LP says
# no, joint and torque limits, collisions).

# %%
from climb_ompl import verify

report = verify(plan)
print(report.summary())
print(report.by_check() or "no violations")

# %% [markdown]
# ## Playback
# A self-contained meshcat page (no server): time slider at the top right of the controls.

# %%
from IPython.display import IFrame, display

from climb_ompl import viz

out = Path(OUT)
out.mkdir(parents=True, exist_ok=True)
html = viz.play(plan.to_dict(), html=out / "03_climb_playback.html")
print(f"playback: {html} ({html.stat().st_size / 1e6:.1f} MB)")
try:
    display(IFrame(src=os.path.relpath(html), width=900, height=500))
except ValueError:  # another drive / no relative path: open the file directly
    print("open", html)
