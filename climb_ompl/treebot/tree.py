"""The tree model of TreeBot (Lam et al., sections III and IV): branches of rings of surface points.

A tree is a tree of branches; the trunk is a branch like any other, the single branch without a parent
(Lam et al. (TreeBot), Fig. 4).  Each branch is a sequence of *rings* from its base to its tip (Fig. 5); each ring is a
closed sequence of surface points with outward unit normals.  Some points are *unreachable* (obstacles,
``O = -inf`` in Eq. 4): the space above them is occupied (by another branch) or the surface there is
concave, so a gripper cannot hold (section III).

World frame: metres, ``z`` up against gravity (``gravity`` may be tilted).

File format (YAML)::

    name: three-branch
    gravity: [0, 0, -9.81]        # optional, m/s^2
    a0: 0.05                      # optional, weight of the pull-out term n in Eq. 4, metres
    robot:                        # optional; TreeBot's continuum body (Lam et al., section II)
      s_min: 0.12                 # contracted body length S_min, m (Eq. 18, 20)
      s_max: 0.45                 # longest body, m
      max_reach: 0.2              # longest step between consecutive gripping points, m (DP constraint)
      step: 0.22                  # path length between front-gripper targets, m (section V.A.1)
      max_bend: 2.0               # largest bending angle kappa * S of the body, rad
    branches:
      - name: trunk
        parent: null              # exactly one branch has no parent
        rings:
          - points: [[x, y, z], ...]        # >= 3 points, metres
            normals: [[nx, ny, nz], ...]    # one per point, non-zero, normalised on load
            obstacles: [3, 4]               # optional: indices of unreachable points
      - name: b2
        parent: trunk
        attach_ring: 17           # index of the parent's ring where this branch leaves it
        rings: [...]
"""

from __future__ import annotations

import hashlib
import json
import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
import yaml

from climb_ompl._io import load_yaml
from climb_ompl.errors import InputError
from climb_ompl.model.terrain import MAX_MAGNITUDE
from climb_ompl.resources import bundled, resolve

TREES_DIR = Path(__file__).resolve().parent / "trees"


class TreeError(InputError):
    """A malformed tree file or tree object (file, field, reason)."""


@dataclass(frozen=True)
class RobotParams:
    """TreeBot's body and stepping parameters.

    Attributes:
        s_min: body length in the contraction motion S_min, metres (Lam et al. (TreeBot), Eq. 18, 20).
        s_max: longest admissible body length, metres.
        max_reach: longest distance between consecutive gripping points of the path, metres; the DP's
            reachability constraint (an action farther than this has value -inf).
        step: path length between consecutive front-gripper targets, metres (Lam et al. (TreeBot), section V.A.1,
            "the distance between the target positions of the front gripper is set as constant").
        max_bend: largest bending angle ``kappa * S`` of the continuum body, radians (the turn of its tangent
            from one gripper to the other, Fig. 3).  The paper gives no value; 2 rad is an assumption.
    """

    s_min: float = 0.12
    s_max: float = 0.45
    max_reach: float = 0.2
    step: float = 0.22
    max_bend: float = 2.0

    def to_dict(self) -> dict[str, float]:
        """Plain-dict form (the YAML ``robot`` section)."""
        return {"s_min": self.s_min, "s_max": self.s_max, "max_reach": self.max_reach, "step": self.step,
                "max_bend": self.max_bend}


@dataclass(frozen=True, eq=False)
class Ring:
    """One ring of surface points (Lam et al. (TreeBot), Fig. 5).

    Attributes:
        points: ``(n, 3)`` surface points in the world frame, metres.
        normals: ``(n, 3)`` outward unit surface normals.
        obstacles: ``(n,)`` bool, True where a gripper cannot hold (``O = -inf``, Eq. 4).
    """

    points: np.ndarray
    normals: np.ndarray
    obstacles: np.ndarray

    @property
    def n(self) -> int:
        """Number of points."""
        return len(self.points)

    def to_dict(self, decimals: int | None = None) -> dict[str, Any]:
        """YAML form: ``points``, ``normals``, ``obstacles`` (point indices)."""

        def r(a: np.ndarray) -> list[list[float]]:
            return (np.round(a, decimals) if decimals is not None else a).tolist()

        return {"points": r(self.points), "normals": r(self.normals),
                "obstacles": [int(i) for i in np.flatnonzero(self.obstacles)]}


@dataclass(frozen=True, eq=False)
class Branch:
    """A branch: rings from base to tip; ``parent`` is ``None`` for the trunk.

    Attributes:
        name: unique name in the tree.
        parent: name of the parent branch, or ``None`` for the root (trunk).
        attach_ring: index of the parent's ring at which this branch leaves the parent.
        rings: the branch's rings, base first.
    """

    name: str
    parent: str | None
    attach_ring: int | None
    rings: tuple[Ring, ...]


@dataclass(frozen=True, eq=False)
class Tree:
    """A tree of branches with its planning parameters.

    Attributes:
        name: tree name.
        branches: the branches; ``branches[0]`` need not be the root.
        gravity: gravity vector, m/s^2.
        a0: weight of the pull-out reward ``n`` in Lam et al. (TreeBot), Eq. 4, metres.
        robot: TreeBot's body parameters.
        source: file the tree came from (for error messages).
    """

    name: str
    branches: tuple[Branch, ...]
    gravity: tuple[float, float, float] = (0.0, 0.0, -9.81)
    a0: float = 0.05
    robot: RobotParams = field(default_factory=RobotParams)
    source: str = "<tree>"

    # -- structure ---------------------------------------------------------------------------------
    def branch(self, name: str) -> Branch:
        """The branch called ``name``.

        Raises:
            TreeError: no such branch; the message lists the branch names.
        """
        for b in self.branches:
            if b.name == name:
                return b
        names = ", ".join(b.name for b in self.branches)
        raise TreeError(self.source, "target", f"no branch {name!r}; branches: {names}")

    @property
    def root(self) -> Branch:
        """The trunk (the branch without a parent)."""
        return next(b for b in self.branches if b.parent is None)

    @property
    def up(self) -> np.ndarray:
        """Unit vector against gravity."""
        g = np.asarray(self.gravity, float)
        return -g / np.linalg.norm(g)

    def branch_chain(self, target: str) -> list[Branch]:
        """Branches from the trunk to ``target`` (backward search in the tree, Lam et al. (TreeBot), section III)."""
        chain = [self.branch(target)]
        while chain[-1].parent is not None:
            chain.append(self.branch(chain[-1].parent))
        return chain[::-1]

    def ring_sequence(self, target: str) -> list[tuple[str, int]]:
        """The rows of the DP state space (Lam et al. (TreeBot), Fig. 7): ``(branch, ring)`` from the trunk's first ring
        to the target branch's last ring, leaving each branch at the ring where the next one attaches."""
        chain = self.branch_chain(target)
        seq: list[tuple[str, int]] = []
        for b, nxt in zip(chain, chain[1:] + [None], strict=False):
            last = len(b.rings) - 1 if nxt is None else int(nxt.attach_ring)  # type: ignore[arg-type]
            seq.extend((b.name, r) for r in range(last + 1))
        return seq

    # -- serialisation ------------------------------------------------------------------------------
    def to_dict(self, decimals: int | None = None) -> dict[str, Any]:
        """The YAML content as a dict (round-trips through :meth:`from_dict`)."""
        return {
            "name": self.name,
            "gravity": [float(x) for x in self.gravity],
            "a0": float(self.a0),
            "robot": self.robot.to_dict(),
            "branches": [
                {"name": b.name, "parent": b.parent,
                 **({"attach_ring": int(b.attach_ring)} if b.parent is not None else {}),
                 "rings": [r.to_dict(decimals) for r in b.rings]}
                for b in self.branches
            ],
        }

    def content_hash(self) -> str:
        """sha256 of the canonical JSON of :meth:`to_dict`, coordinates rounded to 1e-10 (so re-normalising
        normals on load does not change it)."""
        text = json.dumps(self.to_dict(decimals=10), sort_keys=True, separators=(",", ":"))
        return hashlib.sha256(text.encode()).hexdigest()

    def to_yaml(self, decimals: int = 5) -> str:
        """YAML text; coordinates rounded to ``decimals``."""
        return yaml.safe_dump(self.to_dict(decimals), sort_keys=False, default_flow_style=None, width=200)

    @classmethod
    def from_dict(cls, data: Any, source: str = "<dict>") -> "Tree":
        """Validate and build a tree from its YAML content.

        Raises:
            TreeError: naming the source, the field and the reason.
        """
        return _parse(data, source)

    @classmethod
    def load(cls, name_or_path: str | Path) -> "Tree":
        """Load a bundled tree by name (``"three-branch"``) or a YAML file.

        Raises:
            TreeError: unknown name, unreadable file, invalid YAML or invalid content.
        """
        try:
            path = resolve(name_or_path, TREES_DIR, "tree")
        except InputError as exc:
            raise TreeError(str(name_or_path), "tree", exc.reason) from None
        return _parse(load_yaml(path, TreeError), str(path))


def bundled_trees() -> list[str]:
    """Names of the bundled trees."""
    return bundled(TREES_DIR)


# -- validation ---------------------------------------------------------------------------------------
def _num(v: Any, src: str, fld: str, positive: bool = True) -> float:
    if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
        raise TreeError(src, fld, f"expected a finite number, got {v!r}")
    if positive and v <= 0:
        raise TreeError(src, fld, f"must be > 0, got {v!r}")
    return float(v)


def _vectors(v: Any, src: str, fld: str) -> np.ndarray:
    if not isinstance(v, list) or not v:
        raise TreeError(src, fld, "expected a non-empty list of [x, y, z] triples")
    for i, row in enumerate(v):
        if (not isinstance(row, list) or len(row) != 3
                or not all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in row)):
            raise TreeError(src, f"{fld}[{i}]", f"expected [x, y, z] numbers, got {row!r}")
    try:
        a = np.asarray(v, dtype=float)
    except OverflowError:  # an integer no float holds
        raise TreeError(src, fld, "non-finite value") from None
    if not np.isfinite(a).all():
        raise TreeError(src, fld, "non-finite value")
    if float(np.abs(a).max()) > MAX_MAGNITUDE:
        raise TreeError(src, fld, f"a value beyond {MAX_MAGNITUDE:g} (metres; a normal's length does not matter, "
                        "but write it short)")
    return a


#: Smallest distance between the centres of consecutive rings, and smallest radius of a ring, metres.
RING_GAP_MIN = 1e-3


def _ring(r: Any, src: str, fld: str) -> Ring:
    if not isinstance(r, dict):
        raise TreeError(src, fld, "expected a mapping with points, normals[, obstacles]")
    unknown = sorted(set(r) - {"points", "normals", "obstacles"})
    if unknown:
        raise TreeError(src, f"{fld}.{unknown[0]}", "unknown field; known fields: normals, obstacles, points")
    for key in ("points", "normals"):
        if key not in r:
            raise TreeError(src, f"{fld}.{key}", "missing required field")
    pts = _vectors(r["points"], src, f"{fld}.points")
    nrm = _vectors(r["normals"], src, f"{fld}.normals")
    if len(pts) < 3:
        raise TreeError(src, f"{fld}.points", f"a ring needs at least 3 points, got {len(pts)}")
    spread = float(np.max(np.linalg.norm(pts - pts.mean(axis=0), axis=1)))
    if spread < RING_GAP_MIN:
        raise TreeError(src, f"{fld}.points", f"the points lie within {spread * 1000:.3g} mm of their centre: a ring "
                        "goes round the branch")
    if len(nrm) != len(pts):
        raise TreeError(src, f"{fld}.normals", f"expected {len(pts)} normals (one per point), got {len(nrm)}")
    lengths = np.linalg.norm(nrm, axis=1)
    bad = np.flatnonzero(lengths < 1e-9)
    if bad.size:
        raise TreeError(src, f"{fld}.normals[{bad[0]}]", "zero normal (a normal must have non-zero length)")
    obs = np.zeros(len(pts), bool)
    raw = r.get("obstacles", []) or []
    if not isinstance(raw, list):
        raise TreeError(src, f"{fld}.obstacles", "expected a list of point indices")
    for i, k in enumerate(raw):
        if isinstance(k, bool) or not isinstance(k, int) or not 0 <= k < len(pts):
            raise TreeError(src, f"{fld}.obstacles[{i}]", f"expected a point index in 0..{len(pts) - 1}, got {k!r}")
        obs[k] = True
    return Ring(pts, nrm / lengths[:, None], obs)


def _parse(data: Any, src: str) -> Tree:
    if not isinstance(data, dict):
        raise TreeError(src, "(top level)", "expected a mapping with name and branches")
    known = {"name", "gravity", "a0", "robot", "branches", "description"}
    extra = sorted(set(data) - known)
    if extra:
        raise TreeError(src, extra[0], f"unknown field; known fields: {', '.join(sorted(known))}")
    for key in ("name", "branches"):
        if key not in data:
            raise TreeError(src, key, "missing required field")
    name = data["name"]
    if not isinstance(name, str) or not name:
        raise TreeError(src, "name", "must be a non-empty string")
    g = data.get("gravity", [0.0, 0.0, -9.81])
    g = _vectors([g], src, "gravity")[0] if isinstance(g, list) else _vectors(g, src, "gravity")
    if np.linalg.norm(g) < 1e-9:
        raise TreeError(src, "gravity", "zero gravity vector")
    a0 = _num(data.get("a0", 0.05), src, "a0")
    robot = _robot_params(data, src)
    seen = _branch_entries(data["branches"], src)
    roots = [n for n, b in seen.items() if b.get("parent") is None]
    if len(roots) != 1:
        raise TreeError(src, "branches", f"exactly one branch (the trunk) must have parent: null, found {len(roots)}"
                        + (f" ({', '.join(roots)})" if roots else ""))
    branches = [_branch(i, bname, b, seen, roots[0], src) for i, (bname, b) in enumerate(seen.items())]
    return Tree(name, tuple(branches), tuple(float(x) for x in g), a0, robot, src)  # type: ignore[arg-type]


def _robot_params(data: dict[str, Any], src: str) -> RobotParams:
    """The tree file's ``robot`` section over the defaults of :class:`RobotParams`."""
    rob = data.get("robot", {}) or {}
    if not isinstance(rob, dict):
        raise TreeError(src, "robot", "expected a mapping")
    defaults = RobotParams().to_dict()
    unknown = sorted(set(rob) - set(defaults))
    if unknown:
        raise TreeError(src, f"robot.{unknown[0]}", f"unknown field; known fields: {', '.join(sorted(defaults))}")
    robot = RobotParams(**{k: _num(rob.get(k, v), src, f"robot.{k}") for k, v in defaults.items()})
    if robot.s_min >= robot.s_max:
        raise TreeError(src, "robot.s_max", f"must exceed s_min ({robot.s_min}), got {robot.s_max}")
    return robot


def _branch_entries(raw: Any, src: str) -> dict[str, dict[str, Any]]:
    """The file's ``branches`` by name, each entry's fields checked (parents are resolved by :func:`_branch`)."""
    if not isinstance(raw, list) or not raw:
        raise TreeError(src, "branches", "expected a non-empty list of branches")
    seen: dict[str, dict[str, Any]] = {}
    for i, b in enumerate(raw):
        f = f"branches[{i}]"
        if not isinstance(b, dict):
            raise TreeError(src, f, "expected a mapping with name, parent, rings")
        unknown = sorted(set(b) - {"name", "parent", "attach_ring", "rings"})
        if unknown:
            raise TreeError(src, f"{f}.{unknown[0]}", "unknown field; known fields: attach_ring, name, parent, rings")
        bname = b.get("name")
        if not isinstance(bname, str) or not bname:
            raise TreeError(src, f"{f}.name", "missing or empty (a non-empty string is required)")
        if bname in seen:
            raise TreeError(src, f"{f}.name", f"duplicate branch name {bname!r}")
        if "rings" not in b or not isinstance(b["rings"], list) or not b["rings"]:
            raise TreeError(src, f"{f}.rings", f"branch {bname!r} has no rings (a non-empty list is required)")
        if len(b["rings"]) < 2:
            raise TreeError(src, f"{f}.rings", f"branch {bname!r} has one ring: a branch runs from its base ring to "
                            "its tip ring (at least 2)")
        par = b.get("parent")
        if par is not None and not isinstance(par, str):
            raise TreeError(src, f"{f}.parent", f"expected the name of a branch, or null for the trunk, got {par!r}")
        seen[bname] = b
    return seen


def _branch(i: int, bname: str, b: dict[str, Any], seen: dict[str, dict[str, Any]], trunk: str, src: str) -> Branch:
    """Branch ``i`` of the file: its parent and attachment ring checked (no loop of parents), its rings read."""
    f = f"branches[{i}]"
    parent = b.get("parent")
    attach: int | None = None
    if parent is not None:
        if parent not in seen:
            raise TreeError(src, f"{f}.parent", f"branch {bname!r} is attached to {parent!r}, which is not a "
                            f"branch of this tree; branches: {', '.join(seen)}")
        attach = b.get("attach_ring")
        n_par = len(seen[parent]["rings"])
        if isinstance(attach, bool) or not isinstance(attach, int) or not 0 <= attach < n_par:
            raise TreeError(src, f"{f}.attach_ring", f"expected a ring index of {parent!r} in 0..{n_par - 1}, "
                            f"got {attach!r}")
        # A loop of parents never reaches the trunk.
        walk, hops = parent, 0
        while walk is not None and hops <= len(seen):
            walk, hops = seen[walk].get("parent"), hops + 1
        if walk is not None:
            raise TreeError(src, f"{f}.parent", f"branch {bname!r} is in a cycle of parents (never reaches "
                            f"the trunk {trunk!r})")
    elif b.get("attach_ring") is not None:  # (written null, as a listing of every field may have it: fine)
        raise TreeError(src, f"{f}.attach_ring", "the trunk (parent: null) attaches to nothing")
    rings = tuple(_ring(r, src, f"{f}.rings[{k}]") for k, r in enumerate(b["rings"]))
    for k in range(1, len(rings)):  # a segment of no length has no surface to climb
        gap = float(np.linalg.norm(rings[k].points.mean(axis=0) - rings[k - 1].points.mean(axis=0)))
        if gap < RING_GAP_MIN:
            raise TreeError(src, f"{f}.rings[{k}]", f"centred {gap * 1000:.3g} mm from ring {k - 1}: consecutive "
                            f"rings must lie at least {RING_GAP_MIN * 1000:g} mm apart along the branch")
    return Branch(bname, parent, attach, rings)
