"""Plots of a benchmark grid's results (matplotlib, PNG and SVG): see :mod:`climb_ompl.bench._runs`."""

from __future__ import annotations

from collections import defaultdict
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np


def _label(r: dict[str, Any]) -> str:
    return f"{r['planner']}/{r['space']}/{r['sampler']}"


def _save(fig: Any, out: Path, stem: str) -> list[Path]:
    paths = []
    for ext in ("png", "svg"):
        p = out / f"{stem}.{ext}"
        fig.savefig(p, dpi=110, bbox_inches="tight")
        paths.append(p)
    return paths


def report(results: Sequence[dict[str, Any]], out: str | Path) -> list[Path]:
    """Write the four standard plots of a grid to ``out`` and return their paths.

    * ``success_vs_time``: fraction of runs solved within t, for t up to the time limit (the empirical
      success rate a smaller time limit would have had).
    * ``times``: box plot of planning times of solved runs per configuration.
    * ``rejections``: stacked bars of rejected states by reason per configuration.
    * ``heatmap``: median time of solved runs (colour) and success rate (text) per planner x space.
    """
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    groups: dict[str, list[dict[str, Any]]] = defaultdict(list)
    for r in results:
        groups[_label(r)].append(r)
    labels = sorted(groups)
    paths: list[Path] = []

    fig, ax = plt.subplots(figsize=(7, 4))
    tmax = max((r["time_limit"] for r in results), default=1.0)
    ts = np.linspace(0, tmax, 200)
    for lab in labels:
        rs = groups[lab]
        times = np.array([r["time"] for r in rs if r["solved"]])
        ax.plot(ts, [(times <= t).sum() / len(rs) for t in ts], label=lab)
    ax.set(xlabel="time limit (s)", ylabel="success rate", ylim=(0, 1.05), title="Success rate vs. time limit")
    ax.legend(fontsize=7)
    paths += _save(fig, out, "success_vs_time")
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(max(6, len(labels) * 0.9), 4))
    data = [[r["time"] for r in groups[lab] if r["solved"]] or [np.nan] for lab in labels]
    ax.boxplot(data)
    ax.set_xticks(range(1, len(labels) + 1), labels, rotation=35, ha="right", fontsize=7)
    ax.set(ylabel="planning time of solved runs (s)", title="Time distribution")
    paths += _save(fig, out, "times")
    plt.close(fig)

    fig, ax = plt.subplots(figsize=(max(6, len(labels) * 0.9), 4))
    reasons = sorted({k for r in results for k in (r.get("rejections") or {})})
    bottom = np.zeros(len(labels))
    for reason in reasons:
        vals = np.array([np.mean([(r.get("rejections") or {}).get(reason, 0) for r in groups[lab]]) for lab in labels])
        ax.bar(range(len(labels)), vals, bottom=bottom, label=reason)
        bottom += vals
    ax.set_xticks(range(len(labels)), labels, rotation=35, ha="right", fontsize=7)
    ax.set(ylabel="rejected states per run (mean)", title="Rejections by reason")
    if reasons:
        ax.legend(fontsize=7)
    paths += _save(fig, out, "rejections")
    plt.close(fig)

    planners = sorted({r["planner"] for r in results})
    spaces = sorted({r["space"] for r in results})
    med = np.full((len(planners), len(spaces)), np.nan)
    succ = np.zeros_like(med)
    for i, p in enumerate(planners):
        for j, s in enumerate(spaces):
            rs = [r for r in results if r["planner"] == p and r["space"] == s]
            if rs:
                solved = [r["time"] for r in rs if r["solved"]]
                med[i, j] = np.median(solved) if solved else np.nan
                succ[i, j] = len(solved) / len(rs)
    fig, ax = plt.subplots(figsize=(1.8 + 1.6 * len(spaces), 1.2 + 0.45 * len(planners)))
    cmap = matplotlib.colormaps["viridis_r"].with_extremes(bad="0.85")  # nothing solved: grey
    im = ax.imshow(np.ma.masked_invalid(med), cmap=cmap, aspect="auto")
    for i in range(len(planners)):
        for j in range(len(spaces)):
            ax.text(j, i, f"{succ[i, j]:.0%}", ha="center", va="center", fontsize=8,
                    color="k" if np.isnan(med[i, j]) else "w")
    ax.set_xticks(range(len(spaces)), spaces)
    ax.set_yticks(range(len(planners)), planners)
    fig.colorbar(im, ax=ax, label="median time (s)")
    ax.set_title("Planner x space: median time, success rate")
    paths += _save(fig, out, "heatmap")
    plt.close(fig)
    return paths
