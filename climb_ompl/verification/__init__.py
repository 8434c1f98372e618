"""Independent re-checks of every plan kind (``climb-ompl verify``).

A ``climb`` plan goes to :func:`climb_ompl.verification.climb.verify`; a ``treebot`` plan to
:func:`climb_ompl.verification.tree.verify_tree` (Lam et al. (TreeBot)); a ``slope`` plan to
:func:`climb_ompl.verification.slope.verify_slope` (Kim, Kang & Choi (MRWALLSPECT III)).  All return the same
:class:`~climb_ompl.verification.report.VerifyReport` of :class:`~climb_ompl.verification.report.Violation` s.
Before a ``treebot`` or ``slope`` plan is checked, any NaN or infinity in it, or content its kind's schema
(``schemas/<kind>.schema.json``) rejects, is bad input: :class:`~climb_ompl.errors.PlanFileError` naming the
JSON path.

Nothing here imports the planner it checks (:mod:`climb_ompl.climb`, :mod:`climb_ompl.manifold`), so a planner bug
cannot hide behind a shared helper.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Any

from climb_ompl.verification.report import VerifyReport, Violation, check_input


def verify(plan: Any, **kwargs: Any) -> VerifyReport:
    """Re-check a plan of any kind, independently of the planner: a :class:`~climb_ompl.plan.file.Plan`, or the path
    of a plan file (keyword arguments go to that kind's verifier; see :func:`climb_ompl.verification.climb.verify`
    for a climb's).

    Raises:
        PlanFileError: ``plan`` is a path to an unreadable or schema-invalid file.
    """
    from climb_ompl.plan.file import Plan

    if isinstance(plan, Plan):
        from climb_ompl.verification.climb import verify as verify_climb

        return verify_climb(plan, **kwargs)
    return verify_file(plan, **kwargs)


def verify_plan_dict(d: dict[str, Any], source: str = "<plan>", **kwargs: Any) -> VerifyReport:
    """Verify a schema-valid plan dict of any kind (keyword arguments go to that kind's verifier).

    Raises:
        PlanFileError: bad input (see :func:`check_input`; a climb plan's own schema errors).
    """
    if d["kind"] == "climb":
        from climb_ompl.verification.climb import verify_dict

        return verify_dict(d, source, **kwargs)
    check_input(d, source)
    kwargs = {k: v for k, v in kwargs.items() if k == "max_per_check"}  # the other kinds' one shared option
    if d["kind"] == "treebot":
        from climb_ompl.verification.tree import verify_tree

        return verify_tree(d, source, **kwargs)
    from climb_ompl.verification.slope import verify_slope

    return verify_slope(d, source, **kwargs)


def verify_file(path: str | os.PathLike[str], **kwargs: Any) -> VerifyReport:
    """Read a plan file of any kind and verify it.

    Raises:
        PlanFileError: unreadable, not JSON, schema-invalid, non-finite numbers (naming the JSON path).
    """
    from climb_ompl.plan.file import read_plan_dict

    return verify_plan_dict(read_plan_dict(path), str(Path(path)), **kwargs)


__all__ = ["VerifyReport", "Violation", "verify", "verify_file", "verify_plan_dict"]
