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
# # 01 - Static equilibrium: support polygons, exact vs. linearised cones, margin maps
#
# A stance (which hand on which hold) fixes the set of centre-of-mass (CoM) positions in which the robot
# can hang in static equilibrium by friction alone: the **support region** (Bretl, Latombe & Rock (2003), eqs. (1), (6),
# (7); Bretl (2006), appendix B).  It depends on the stance only, so the planner computes it once per stance and
# tests configurations by a CoM-in-polygon check.  This notebook draws it for a few LEMUR stances on the
# bundled `demo-wall`, compares the exact second-order friction cones with their polyhedral
# (linearised) approximations, and maps the equilibrium margin over the wall.

# %% tags=["parameters"]
# ruff: noqa: E402, B018  (a notebook: imports follow the parameters cell; bare names display tables)
import os

TERRAIN = os.environ.get("NB_TERRAIN", "demo-wall")
N_STANCES = int(os.environ.get("NB_STANCES", "3"))  # stances drawn
GRID = int(os.environ.get("NB_GRID", "60"))  # margin-map resolution (points per axis)
CONE_EDGES = (4, 8)  # linearised cones compared with the exact one

# %%
import matplotlib.pyplot as plt
import numpy as np

from climb_ompl.equilibrium import Contact, contact_forces, support_region
from climb_ompl.climb.multistep import lowest_stance
from climb_ompl import RobotModel
from climb_ompl import Terrain

robot = RobotModel.load("lemur")
wall = Terrain.load(TERRAIN)
print(robot.name, robot.mass, "kg;", wall.name, len(wall.holds), "holds; gravity", wall.g)

# %% [markdown]
# ## A few stances
# Four-hold stances placed the way the climb planner places its start (the nominal hand layout at a few
# heights), and each one's three-hold sub-stances (one hand released), which are the stances a one-step
# move happens on.

# %%
stances = []
for k in range(N_STANCES):
    shifted = Terrain.from_dict({**wall.to_dict(), "holds": [
        h for h in wall.to_dict()["holds"] if h["position"][2] >= 0.45 * k]})
    st = lowest_stance(robot, shifted, 0.7)
    stances.append(st)
    print(k, st)


def contacts_of(stance):
    return [Contact.from_hold(wall.hold(h)) for h in stance.values()]


# %%
fig, axes = plt.subplots(1, N_STANCES, figsize=(4.2 * N_STANCES, 4.2), squeeze=False)
areas = []
for ax, st in zip(axes[0], stances, strict=True):
    C = contacts_of(st)
    for kk, style in zip(CONE_EDGES, (":", "--"), strict=False):
        reg = support_region(C, robot.mass, wall.g, cone_edges=kk)
        V = np.vstack([reg.vertices, reg.vertices[:1]])
        ax.plot(V[:, 0], V[:, 1], style, label=f"linearised {kk} edges")
    ex = support_region(C, robot.mass, wall.g, exact=True)
    V = np.vstack([ex.vertices, ex.vertices[:1]])
    ax.fill(V[:, 0], V[:, 1], alpha=0.25, color="C2", label="exact cones")
    P = np.array([c.position for c in C])
    ax.plot(P[:, 0], P[:, 1], "ks")
    ax.set(title=", ".join(f"{k}:{v}" for k, v in st.items()), xlabel="x (m)", ylabel="y stand-off (m)")
    ax.title.set_fontsize(8)
    ax.legend(fontsize=7)

    def area(v):
        x, y = v[:, 0], v[:, 1]
        return 0.5 * abs(np.dot(x, np.roll(y, 1)) - np.dot(y, np.roll(x, 1)))

    areas.append({"exact": area(ex.vertices),
                  **{f"lin{kk}": area(support_region(C, robot.mass, wall.g, cone_edges=kk).vertices)
                     for kk in CONE_EDGES}})
fig.suptitle("Support regions seen along gravity (a vertical wall: x along the wall, y away from it)")
fig.tight_layout()

# %% [markdown]
# On a vertical wall gravity is along -z, so the region lives in the horizontal x-y plane: it bounds how
# far the CoM may be along the wall and how far it may stand off the wall.  The inscribed polyhedral cones
# are conservative: their regions lie inside the exact one, and more edges close the gap.

# %%
for st, a in zip(stances, areas, strict=True):
    ratios = {k: a[k] / a["exact"] for k in a if k != "exact"}
    print(f"{list(st.values())}: exact area {a['exact'] * 1e4:.1f} cm^2; linearised/exact:",
          {k: round(float(v), 3) for k, v in ratios.items()})
assert all(a[f"lin{k}"] <= a["exact"] * (1 + 1e-6) for a in areas for k in CONE_EDGES)

# %% [markdown]
# ## Release one hand: the three-hold stances of a one-step move
# Releasing a hand shrinks the region; when the CoM of the current configuration is outside the smaller
# region, the robot must first shift its body (a one-step path) before it can let go.

# %%
st = stances[0]
C4 = contacts_of(st)
reg4 = support_region(C4, robot.mass, wall.g, exact=True)
fig, ax = plt.subplots(figsize=(5, 4))
V = np.vstack([reg4.vertices, reg4.vertices[:1]])
ax.fill(V[:, 0], V[:, 1], alpha=0.15, color="k", label="4 holds")
for i, limb in enumerate(st):
    sub = {k: v for k, v in st.items() if k != limb}
    reg = support_region(contacts_of(sub), robot.mass, wall.g, exact=True)
    if reg.is_empty:
        print("release", limb, ": empty region")
        continue
    V = np.vstack([reg.vertices, reg.vertices[:1]])
    ax.plot(V[:, 0], V[:, 1], color=f"C{i}", label=f"release {limb}")
ax.set(xlabel="x (m)", ylabel="y (m)", title="Support regions after one release")
ax.legend(fontsize=7)

# %% [markdown]
# ## Margin map over the wall
# For every point of a grid in front of the wall (x along the wall, y the stand-off; on a vertical wall the
# height z does not matter since gravity is along z), the equilibrium margin of the stance: the distance
# to the region's boundary (positive inside).  `SupportRegion.margin` is vectorised, so the whole map is
# one call.  The most robust contact forces (`contact_forces`, exact cones through cvxpy) confirm the sign
# at a few points.

# %%
reg = reg4
zc = float(np.mean([wall.hold(h).p[2] for h in st.values()]))
xs = np.linspace(reg.vertices[:, 0].min() - 0.3, reg.vertices[:, 0].max() + 0.3, GRID)
ys = np.linspace(0.0, max(0.4, reg.vertices[:, 1].max() + 0.1), GRID)
X, Y = np.meshgrid(xs, ys)
pts = np.stack([X.ravel(), Y.ravel(), np.full(X.size, zc)], axis=1)
M = np.asarray(reg.margin(pts), dtype=float).reshape(X.shape)
fig, ax = plt.subplots(figsize=(6, 4.5))
lim = float(np.nanmax(np.abs(M[np.isfinite(M)])))
im = ax.pcolormesh(X, Y, M, cmap="RdBu", vmin=-lim, vmax=lim, shading="auto")
fig.colorbar(im, ax=ax, label="margin (m)")
ax.contour(X, Y, M, levels=[0.0], colors="k", linewidths=1)
H = np.array([wall.hold(h).p for h in st.values()])
ax.plot(H[:, 0], H[:, 1], "ks")
ax.set(xlabel="x along the wall (m)", ylabel="y stand-off (m)", title="Equilibrium margin of the 4-hold stance")
ax.set_aspect("equal")

# %%
rng = np.random.default_rng(0)
checks = []
for i in rng.choice(len(pts), size=8, replace=False):
    m = float(np.asarray(reg.margin(pts[i]), dtype=float).reshape(-1)[0])
    if abs(m) < 1e-3:
        continue
    f = contact_forces(C4, robot.mass, wall.g, pts[i])
    checks.append((m > 0, f is not None))
print("(inside by margin, forces found) at sampled points:", checks)
assert all(a == b for a, b in checks)

# %% [markdown]
# **Reading the map.** The region is bounded along the wall by the outermost holds and off the wall by
# friction: the further the CoM stands off, the more the upper holds must pull outwards, and the narrower
# the band of x that stays in equilibrium.  The exact-cone region is what `verify` uses; the planner's
# inner loop uses the cached polygon with linearised cones, which is slightly smaller, i.e. conservative.
