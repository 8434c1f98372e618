"""``climb-ompl bench papers-doc``: docs/papers.md rendered from its template and the evidence JSON (``make papers``).

The page's measured figures are not typed in: the template (``docs/papers.md.in``) names each one by its place in
the evidence (``{{papers.climb.steps}}``, ``{{papers.sampling_gain_climb.by_size.4.jbj_share|pct}}``), and this
module fills them in.  The evidence is one JSON object (``docs/papers.json``) gathered from the benchmarks' files:
``papers`` is ``climb-ompl bench papers``' result, ``treebot`` ``climb-ompl bench treebot``'s, ``fig16`` the
``climb-ompl bench fig16`` runs by case and seed (``fig16.lemur.0``).  ``tests/test_papers_doc.py`` renders the
template from the committed evidence and fails when the page differs, or when a row rated *reproduced* names no
command.

Placeholders: ``{{path}}`` or ``{{path|format}}``, ``path`` dotted keys (list items by index), ``format`` a Python
format spec (``.2f``), ``pct`` (a share as a whole percentage), ``pct1`` (one decimal), ``int`` or ``opt3`` (three
decimals, a dash for ``null``).
"""

from __future__ import annotations

import json
import re
from pathlib import Path
from typing import Any

import typer

from climb_ompl.errors import InputError

#: The benchmarks' files the evidence takes whole (``<name>.json`` of the benchmark folder, under ``name``).
EVIDENCE_FILES: tuple[str, ...] = ("papers", "treebot")

#: A placeholder of the template.
PLACEHOLDER = re.compile(r"\{\{\s*([^|}]+?)\s*(?:\|\s*([^}]*?)\s*)?\}\}")


def lookup(evidence: Any, path: str, source: str = "evidence") -> Any:
    """The value at the dotted ``path`` of ``evidence`` (dict keys, or list indices).

    Raises:
        InputError: no such key, naming the path.
    """
    node = evidence
    for part in path.split("."):
        if isinstance(node, dict) and part in node:
            node = node[part]
        elif isinstance(node, list) and part.lstrip("-").isdigit() and -len(node) <= int(part) < len(node):
            node = node[int(part)]
        else:
            raise InputError(source, path, f"no such value in the evidence (no {part!r} there)")
    return node


def fmt(value: Any, spec: str | None) -> str:
    """``value`` written with ``spec`` (see the module docstring)."""
    if spec in (None, ""):
        if isinstance(value, float):
            return f"{value:.3g}"
        return str(value)
    if spec == "pct":
        return f"{100.0 * float(value):.0f} %"
    if spec == "pct1":
        return f"{100.0 * float(value):.1f} %"
    if spec == "opt3":  # a number to the millimetre, or a dash for none
        return "-" if value is None else f"{float(value):.3f}"
    if spec == "int":
        return str(int(round(float(value))))
    return format(value, spec)


def render(template: str, evidence: dict[str, Any], source: str = "evidence") -> str:
    """The page: every placeholder of ``template`` replaced by its value in ``evidence`` (``source``: its file, for
    the message).

    Raises:
        InputError: a placeholder whose path is not in the evidence.
    """
    return PLACEHOLDER.sub(lambda m: fmt(lookup(evidence, m.group(1), source), m.group(2)), template)


def gather(bench_dir: Path) -> dict[str, Any]:
    """The evidence from a benchmark folder: ``papers.json`` as ``papers`` (and the other :data:`EVIDENCE_FILES`),
    ``fig16/<case>-<seed>.json`` as
    ``fig16.<case>.<seed>`` with, per case, ``found`` (the seeds found and verified) and ``seeds`` (run)."""
    out: dict[str, Any] = {}
    for name in EVIDENCE_FILES:
        p = bench_dir / f"{name}.json"
        if p.exists():
            out[name] = json.loads(p.read_text())
    runs: dict[str, dict[str, Any]] = {}
    for f in sorted((bench_dir / "fig16").glob("*.json")) if (bench_dir / "fig16").is_dir() else []:
        r = json.loads(f.read_text())
        r["steps_text"] = str(r["steps"]) if r["found"] else "-"
        r["found"] = "yes" if r["found"] and r.get("verified") else "no"
        runs.setdefault(r["case"] + ("" if not r.get("changes") else "+" + _changes_name(r["changes"])),
                        {})[str(r["seed"])] = r
    for case in runs.values():
        seeds = [case[k] for k in sorted(case, key=int)]
        case["seeds"] = len(seeds)
        case["found"] = sum(1 for r in seeds if r["found"] == "yes")
        case["steps"] = ", ".join(str(r["steps"]) for r in seeds if r["found"] == "yes") or "none"
        case["cpu_s"] = ", ".join(f"{r['cpu_s']:.0f}" for r in seeds)
    out["fig16"] = runs
    return out


def _changes_name(changes: dict[str, Any]) -> str:
    """A run's changed settings as a key: ``name=value`` joined by ``+``."""
    return "+".join(f"{k}={v}" for k, v in sorted(changes.items()))


def command(
    template: Path = typer.Option(Path("docs/papers.md.in"), "--template", help="The page's template."),
    evidence: Path = typer.Option(Path("docs/papers.json"), "--evidence", help="The evidence JSON."),
    bench_dir: Path = typer.Option(None, "--bench-dir", help="Gather the evidence from this benchmark folder "
                                   "(papers.json, fig16/*.json) and write it to --evidence first."),
    out: Path = typer.Option(Path("docs/papers.md"), "--out", help="The page to write."),
) -> None:
    """docs/papers.md from its template and the benchmarks' evidence (``make papers``)."""
    from climb_ompl._io import atomic_write, atomic_write_json
    from climb_ompl._options import error

    try:
        if bench_dir is not None:
            atomic_write_json(evidence, gather(bench_dir))
        page = render(template.read_text(), json.loads(evidence.read_text()), str(evidence))
    except InputError as exc:
        raise error(str(exc)) from None
    except (OSError, ValueError) as exc:
        raise error(f"papers-doc: {exc}") from None
    atomic_write(out, page)
    print(f"[papers-doc] {out} from {template} and {evidence}")
