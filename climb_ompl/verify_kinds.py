"""What ``climb-ompl verify`` shares across plan kinds: dispatch on ``kind``, bad-input checks, the recorder.

A ``climb`` plan goes to :func:`climb_ompl.verify_climb.verify`; a ``treebot`` plan to
:func:`climb_ompl.verify_tree.verify_tree` (Lam et al. (TreeBot)); a ``slope`` plan to
:func:`climb_ompl.verify_slope.verify_slope` (Kim, Kang & Choi (MRWALLSPECT III)).  All return the same
:class:`~climb_ompl.verify.VerifyReport` of :class:`~climb_ompl.verify.Violation` s.  Before a ``treebot`` or
``slope`` plan is checked, any NaN or infinity in it, or content its kind's schema
(``schemas/<kind>.schema.json``) rejects, is bad input: :class:`~climb_ompl.errors.PlanFileError` naming the
JSON path.
"""

from __future__ import annotations

import json
import math
import os
from collections import Counter
from functools import lru_cache
from importlib import resources
from pathlib import Path
from typing import Any

from .errors import PlanFileError
from .verify_climb import VerifyReport, Violation


def first_non_finite(obj: Any, path: str = "$") -> str | None:
    """JSON path of the first NaN or infinity in ``obj`` (dicts, lists, numbers), or ``None``."""
    if isinstance(obj, float):
        return None if math.isfinite(obj) else path
    if isinstance(obj, dict):
        for k in sorted(obj):
            hit = first_non_finite(obj[k], f"{path}.{k}")
            if hit:
                return hit
    elif isinstance(obj, list):
        for i, v in enumerate(obj):
            hit = first_non_finite(v, f"{path}[{i}]")
            if hit:
                return hit
    return None


@lru_cache(maxsize=4)
def kind_schema(kind: str) -> dict[str, Any]:
    """The JSON schema of a plan kind's content (``climb_ompl/schemas/<kind>.schema.json``)."""
    return json.loads(resources.files("climb_ompl").joinpath("schemas", f"{kind}.schema.json").read_text())


def check_input(d: dict[str, Any], source: str) -> None:
    """Bad input of a ``treebot`` or ``slope`` plan dict: a non-finite number, or content its schema rejects.

    Raises:
        PlanFileError: naming the JSON path (e.g. ``$.motion.frames[3].S``) and the reason.
    """
    import jsonschema

    where = first_non_finite(d)
    if where:
        raise PlanFileError(source, where, "non-finite number (NaN or infinity)")
    errs = []
    for e in jsonschema.Draft202012Validator(kind_schema(d["kind"])).iter_errors(d):
        path = "$" + "".join(f"[{p}]" if isinstance(p, int) else f".{p}" for p in e.absolute_path)
        errs.append((path, e.message))
    if errs:
        where, msg = sorted(errs)[0]
        raise PlanFileError(source, where, msg + (f" (and {len(errs) - 1} more)" if len(errs) > 1 else ""))


class Recorder:
    """Collects violations, at most ``cap`` listed per check (the counts stay exact)."""

    def __init__(self, cap: int = 50):
        self.cap = cap
        self.out: list[Violation] = []
        self.counts: Counter[str] = Counter()
        self.states = 0
        self.lp = self.socp = 0

    def add(self, check: str, step: int | None, instant: float | None, msg: str) -> None:
        """Record a failed ``check`` at ``step`` and ``instant`` (a frame index, fractional between frames)."""
        self.counts[check] += 1
        if self.counts[check] <= self.cap:
            self.out.append(Violation(check, step, instant, msg))

    def report(self, steps: int) -> VerifyReport:
        """The :class:`VerifyReport` of what was recorded."""
        return VerifyReport(tuple(self.out), self.states, steps, self.lp, self.socp, dict(sorted(self.counts.items())))


def verify_plan_dict(d: dict[str, Any], source: str = "<plan>", **kwargs: Any) -> VerifyReport:
    """Verify a schema-valid plan dict of any kind (keyword arguments go to that kind's verifier).

    Raises:
        PlanFileError: bad input (see :func:`check_input`; a climb plan's own schema errors).
    """
    if d["kind"] == "climb":
        from .plan import Plan
        from .verify_climb import verify

        return verify(Plan.from_dict(d, source), **kwargs)
    check_input(d, source)
    if d["kind"] == "treebot":
        from .verify_tree import verify_tree

        return verify_tree(d, source, **kwargs)
    from .verify_slope import verify_slope

    return verify_slope(d, source, **kwargs)


def verify_file(path: str | os.PathLike[str], **kwargs: Any) -> VerifyReport:
    """Read a plan file of any kind and verify it.

    Raises:
        PlanFileError: unreadable, not JSON, schema-invalid, non-finite numbers (naming the JSON path).
    """
    from .plan import read_plan_dict

    return verify_plan_dict(read_plan_dict(path), str(Path(path)), **kwargs)
