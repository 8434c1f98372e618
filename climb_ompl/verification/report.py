"""What every verifier shares: the report and its violations, the recorder that fills it, and the checks of bad input
(a non-finite number, content the plan kind's schema rejects) made before a plan is verified."""

from __future__ import annotations

import json
import math
from collections import Counter
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources
from typing import Any

from climb_ompl.errors import PlanFileError


@dataclass(frozen=True)
class Violation:
    """One failed check.

    Attributes:
        check: the check's name (one of :data:`CHECKS`).
        step: step index, or ``None`` for plan-level checks.
        waypoint: waypoint index within the step (fractional between waypoints), or ``None``.
        message: what is wrong, with the numbers.
    """

    check: str
    step: int | None
    waypoint: float | None
    message: str

    def __str__(self) -> str:
        where = "plan" if self.step is None else f"step {self.step}"
        if self.waypoint is not None:
            wp = self.waypoint
            where += f" waypoint {int(wp)}" if float(wp).is_integer() else f" waypoint {wp:.3f}"
        return f"{where}: {self.check}: {self.message}"


@dataclass(frozen=True)
class VerifyReport:
    """The result of a verifier (:func:`climb_ompl.verification.verify`).

    Attributes:
        violations: every violation found, in plan order.
        states_checked: number of configurations checked (waypoints and interpolated states).
        steps_checked: number of steps checked.
        lp_solves, socp_solves: equilibrium programs solved (the SOCP only where the LP said no).
    """

    violations: tuple[Violation, ...]
    states_checked: int = 0
    steps_checked: int = 0
    lp_solves: int = 0
    socp_solves: int = 0
    counts: dict[str, int] = field(default_factory=dict)

    @property
    def ok(self) -> bool:
        """``True`` when no check failed."""
        return not self.violations

    def by_check(self) -> dict[str, int]:
        """Number of violations per check name."""
        return dict(sorted(Counter(v.check for v in self.violations).items()))

    def summary(self) -> str:
        """One line: valid, or the number of violations by check."""
        head = f"{self.steps_checked} steps, {self.states_checked} states checked"
        if self.ok:
            return f"valid ({head})"
        parts = ", ".join(f"{k}: {n}" for k, n in self.by_check().items())
        return f"{len(self.violations)} violations ({parts}; {head})"


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


__all__ = ["Recorder", "VerifyReport", "Violation", "check_input", "first_non_finite", "kind_schema"]
