"""The plan data model and the plan file (versioned JSON, ``schemas/plan.schema.json``).

A climb plan is the output of the multi-step planner (Bretl (2006), section 3.3, Fig. 16): a sequence of
*steps*, each one grab or one release (Bretl (2006), section 2.1: "it can take a step, releasing Hold 1 and
grabbing Hold 2"), preceded by the continuous motion on the current stance manifold that leads to the
transition where the contact changes (Bretl (2006), Fig. 13(c): transitions joined by paths).  It carries
what the robot's controller needs (Bretl (2006), section 5.1: "a list of joint-angle waypoints and
feedforward torques"): waypoints with their times, velocities and accelerations (each step timed within the
joint speed and acceleration limits, :mod:`climb_ompl.trajectory`), contact forces and feed-forward torques on a
thinned subset of waypoints, and the equilibrium margin.

The file embeds the robot spec, its URDF and the terrain (with SHA-256 content hashes) so that
:func:`climb_ompl.verification.climb.verify` checks a plan without the original files.  The ``kind`` field
(``climb`` | ``treebot`` | ``slope``) lets other planners share the format; only the ``climb`` kind is
modelled here, the others are validated by the common part of the schema and kept as plain dicts.

Determinism: everything in a plan is a function of the inputs and the seed except the ``timings``
object (wall-clock planning times), so two runs with the same seed give files that are byte-identical
once ``timings`` is removed (:func:`canonical_json`).
"""

from __future__ import annotations

import hashlib
import json
import math
import os
from dataclasses import dataclass, field
from functools import lru_cache
from importlib import resources
from pathlib import Path
from typing import Any, Literal

import numpy as np

from climb_ompl._io import atomic_write
from climb_ompl.errors import PlanFileError, RobotModelError

#: Version of the plan-file format written by this module; :func:`load_plan` reads this version only.
SCHEMA_VERSION = 1
PLAN_KINDS: tuple[str, ...] = ("climb", "treebot", "slope")
Action = Literal["grab", "release"]
StanceItems = tuple[tuple[str, str], ...]


def sha256_json(obj: Any) -> str:
    """SHA-256 of the canonical JSON (sorted keys, no spaces) of ``obj``."""
    return hashlib.sha256(json.dumps(obj, sort_keys=True, separators=(",", ":")).encode()).hexdigest()


def _motion_sha256(query: dict[str, Any], steps: list[dict[str, Any]], events: Any) -> str:
    """:meth:`Plan.motion_sha256` of a plan's query, steps (as dicts) and events."""
    return sha256_json({"query": query, "steps": steps, "events": list(events)})


def sha256_text(text: str) -> str:
    """SHA-256 of a text's UTF-8 bytes."""
    return hashlib.sha256(text.encode()).hexdigest()


def robot_record(robot: Any) -> dict[str, Any]:
    """The robot as a plan file embeds it: ``{"name", "spec", "spec_sha256", "urdf", "urdf_sha256"}`` (the spec as
    JSON reads it back, the URDF's text).  A climb plan writes it, ``verify --robot`` compares a robot with it."""
    spec = json.loads(json.dumps(robot.spec))
    urdf = getattr(robot, "urdf_text", None)
    if urdf is None:  # (a robot model that keeps only its path, such as the slope gait's)
        urdf = Path(robot.urdf_path).read_text()
    return {"name": robot.name, "spec": spec, "spec_sha256": sha256_json(spec), "urdf": urdf,
            "urdf_sha256": sha256_text(urdf)}


def _floats(v: Any) -> tuple[float, ...]:
    return tuple(float(x) for x in np.asarray(v, dtype=float).ravel())


def _stance_items(stance: Any) -> StanceItems:
    """A stance (mapping limb -> hold, or pairs) as pairs sorted by limb name."""
    items = stance.items() if hasattr(stance, "items") else stance
    return tuple(sorted((str(k), str(v)) for k, v in items))


# ---- the data model --------------------------------------------------------------------------------
@dataclass(frozen=True)
class ForceSample:
    """Contact forces and feed-forward torques at one waypoint of a step.

    Attributes:
        waypoint: index of the waypoint within its step.
        forces: ``(limb, (fx, fy, fz))`` pairs sorted by limb: the force the hold exerts on the hand,
            newtons, world frame (Bretl (2006), appendix B, ``f_i``).
        torques: feed-forward joint torques ``tau = g(q) - sum_i J_i^T f_i`` (N m, one per
            configuration coordinate; zero on unactuated coordinates up to round-off).
        margin: equilibrium margin, metres: signed distance of the CoM to the boundary of the stance's
            support region (positive inside).
    """

    waypoint: int
    forces: tuple[tuple[str, tuple[float, float, float]], ...]
    torques: tuple[float, ...]
    margin: float

    def to_dict(self) -> dict[str, Any]:
        """The sample as a JSON-able dict."""
        return {"waypoint": self.waypoint, "forces": {k: list(v) for k, v in self.forces},
                "torques": list(self.torques), "margin": self.margin}

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "ForceSample":
        """Inverse of :meth:`to_dict`."""
        forces = tuple(sorted((str(k), tuple(float(x) for x in v)) for k, v in d["forces"].items()))
        return cls(int(d["waypoint"]), forces, _floats(d["torques"]), float(d["margin"]))  # type: ignore[arg-type]


@dataclass(frozen=True)
class Step:
    """One step of a climb: a motion on the stance manifold, then one grab or one release.

    Attributes:
        index: position in the plan, from 0.
        stance: ``(limb, hold)`` pairs (sorted by limb) that hold during the motion.
        action: ``"grab"`` (``limb`` takes ``hold``) or ``"release"`` (``limb`` lets go of ``hold``),
            done at the last waypoint, which is a transition between ``stance`` and
            :attr:`stance_after` (Bretl (2006), section 2.1).
        limb: the limb that grabs or releases.
        hold: the hold it grabs or releases.
        waypoints: configurations, one tuple of ``nq`` floats each (metres / radians); consecutive
            waypoints are joined by straight lines in configuration space.
        times: time of each waypoint from the start of the step, seconds: time-optimal within the joint speed and
            acceleration limits, at rest at the first and last waypoint (:mod:`climb_ompl.trajectory`), or, in a
            plan without :attr:`velocities`, each joint at most at its speed limit between waypoints.
        forces: contact forces/torques on a thinned subset of the waypoints (always the first and last).
        margin: smallest equilibrium margin over :attr:`forces`, metres.
        velocities: joint velocities at each waypoint (one tuple of ``nq`` floats each; m/s, rad/s), continuous
            along the step, zero at its ends (grasps and releases happen at rest); empty in a plan without timing.
        accelerations: joint accelerations from each waypoint towards the next (the last one's: arriving at it;
            m/s^2, rad/s^2); empty in a plan without timing.
    """

    index: int
    stance: StanceItems
    action: Action
    limb: str
    hold: str
    waypoints: tuple[tuple[float, ...], ...]
    times: tuple[float, ...]
    forces: tuple[ForceSample, ...] = ()
    margin: float = math.nan
    velocities: tuple[tuple[float, ...], ...] = ()
    accelerations: tuple[tuple[float, ...], ...] = ()

    @property
    def timed(self) -> bool:
        """Whether the step carries velocities and accelerations (a time-parameterised trajectory)."""
        return bool(self.velocities)

    @property
    def stance_after(self) -> StanceItems:
        """The stance after the grab/release."""
        d = dict(self.stance)
        if self.action == "grab":
            d[self.limb] = self.hold
        else:
            d.pop(self.limb, None)
        return _stance_items(d)

    @property
    def duration(self) -> float:
        """Execution time of the step's motion, seconds."""
        return self.times[-1] if self.times else 0.0

    @property
    def q(self) -> np.ndarray:
        """Waypoints as an ``(n, nq)`` array."""
        return np.array(self.waypoints, dtype=float)

    def to_dict(self) -> dict[str, Any]:
        """The step as a JSON-able dict."""
        timed = {"velocities": [list(w) for w in self.velocities],
                 "accelerations": [list(w) for w in self.accelerations]} if self.timed else {}
        return {"index": self.index, "stance": dict(self.stance), "action": self.action, "limb": self.limb,
                "hold": self.hold, "waypoints": [list(w) for w in self.waypoints], "times": list(self.times),
                "forces": [f.to_dict() for f in self.forces], "margin": self.margin, "duration": self.duration,
                **timed}

    @classmethod
    def from_dict(cls, d: dict[str, Any]) -> "Step":
        """Inverse of :meth:`to_dict` (``duration`` is derived, not read)."""
        return cls(int(d["index"]), _stance_items(d["stance"]), d["action"], str(d["limb"]), str(d["hold"]),
                   tuple(_floats(w) for w in d["waypoints"]), _floats(d["times"]),
                   tuple(ForceSample.from_dict(f) for f in d["forces"]), float(d["margin"]),
                   tuple(_floats(w) for w in d.get("velocities", ())),
                   tuple(_floats(w) for w in d.get("accelerations", ())))


@dataclass(frozen=True)
class Plan:
    """A climb plan (``kind == "climb"``).

    Attributes:
        robot: ``{"name", "spec", "spec_sha256", "urdf", "urdf_sha256"}``: the robot spec (the
            ``robots/<name>.yaml`` content as a dict) and the URDF text, with their hashes.
        terrain: ``{"name", "data", "sha256"}``: :meth:`Terrain.to_dict` and its content hash.
        query: ``{"start": {"stance": {...}, "q": [...]}, "goal": {"type": ..., ...}}``.
        seed: the seed the plan was made with.
        steps: the steps in order.
        settings: planner settings (planner, space, sampler, budgets, tolerance, ...).
        totals: deterministic totals (steps, execution time, one-step calls, stances explored, ...).
        versions: library versions used to make the plan.
        timings: wall-clock figures (planning time, per-step times); excluded from determinism checks.
        climb_ompl_version: the package version that wrote the plan.
        schema_version: plan-file format version.
        events: what happened to the plan after it was made, e.g. a re-plan after a hold failed
            (``{"type": "replan", "at_step", "resumed_at_step", "change", "terrain_sha256_before"}``,
            :mod:`climb_ompl.climb.replan`); empty for a plan made in one go.
        written_sha256: the ``steps_sha256`` of the file the plan was read from (:meth:`motion_sha256` when it was
            written), ``None`` for a plan made in this process or read from a file without one.
        source: the file the plan was read from (``"<dict>"`` otherwise): errors in its embedded robot, terrain
            or settings name it with the JSON path (``plan.json ($.terrain.data)``).
    """

    robot: dict[str, Any]
    terrain: dict[str, Any]
    query: dict[str, Any]
    seed: int
    steps: tuple[Step, ...]
    settings: dict[str, Any] = field(default_factory=dict)
    totals: dict[str, Any] = field(default_factory=dict)
    versions: dict[str, str] = field(default_factory=dict)
    timings: dict[str, Any] = field(default_factory=dict)
    climb_ompl_version: str = ""
    schema_version: int = SCHEMA_VERSION
    kind: str = "climb"
    events: tuple[dict[str, Any], ...] = ()
    written_sha256: str | None = field(default=None, compare=False)
    source: str = field(default="<dict>", compare=False)

    # ---- derived ------------------------------------------------------------------------------
    @property
    def start_stance(self) -> StanceItems:
        """The query's start stance as sorted ``(limb, hold)`` pairs."""
        return _stance_items(self.query["start"]["stance"])

    @property
    def final_stance(self) -> StanceItems:
        """The stance after the last step (the start stance for an empty plan)."""
        return self.steps[-1].stance_after if self.steps else self.start_stance

    def embedded_terrain(self) -> Any:
        """The terrain the plan embeds (``terrain.data``), its errors naming the plan file and that JSON path.

        Raises:
            TerrainError: the embedded terrain is malformed.
        """
        from climb_ompl.model.terrain import Terrain

        return Terrain.from_dict(self.terrain["data"], source=f"{self.source} ($.terrain.data)")

    def motion_sha256(self) -> str:
        """SHA-256 of the plan's query, steps and events (canonical JSON): written in the file as ``steps_sha256``,
        so that a reader can tell a plan as the planner wrote it from one edited since (:attr:`unchanged`)."""
        return _motion_sha256(self.query, [s.to_dict() for s in self.steps], self.events)

    @property
    def unchanged(self) -> bool:
        """Whether the plan's query, steps and events are those its file's ``steps_sha256`` was computed from
        (``False`` for a file without one, or edited since it was written)."""
        return self.written_sha256 is not None and self.written_sha256 == self.motion_sha256()

    @property
    def execution_s(self) -> float:
        """Total duration of the steps as timed (:attr:`Step.times`), seconds."""
        return float(sum(s.duration for s in self.steps))

    def path(self) -> np.ndarray:
        """All waypoints of all steps, in order, as an ``(n, nq)`` array (shared endpoints once)."""
        rows: list[tuple[float, ...]] = []
        for s in self.steps:
            for i, w in enumerate(s.waypoints):
                if rows and i == 0 and w == rows[-1]:
                    continue
                rows.append(w)
        return np.array(rows, dtype=float)

    # ---- (de)serialisation ---------------------------------------------------------------------
    def to_dict(self) -> dict[str, Any]:
        """The plan as a JSON-able dict in the plan-file format."""
        steps = [s.to_dict() for s in self.steps]
        return {"schema_version": self.schema_version, "kind": self.kind,
                "climb_ompl_version": self.climb_ompl_version, "seed": self.seed, "robot": self.robot,
                "terrain": self.terrain, "query": self.query, "settings": self.settings,
                "steps": steps, "totals": self.totals, "versions": self.versions,
                "timings": self.timings, **({"events": list(self.events)} if self.events else {}),
                "steps_sha256": _motion_sha256(self.query, steps, self.events)}

    @classmethod
    def from_dict(cls, d: dict[str, Any], source: str = "<dict>") -> "Plan":
        """Build a plan from a plan-file dict, validating it against the schema first.

        Raises:
            PlanFileError: the dict is not a valid climb plan (names the JSON path).
        """
        validate_plan_dict(d, source)
        return cls._from_valid(d, source)

    @classmethod
    def _from_valid(cls, d: dict[str, Any], source: str) -> "Plan":
        """:meth:`from_dict` for a dict :func:`read_plan_dict` has validated (walking the schema is most of the
        cost of reading a plan file: once is enough)."""
        if d["kind"] != "climb":
            raise PlanFileError(source, "$.kind", f"a {d['kind']!r} plan is not a climb plan")
        return cls(robot=d["robot"], terrain=d["terrain"], query=d["query"], seed=int(d["seed"]),
                   steps=tuple(Step.from_dict(s) for s in d["steps"]), settings=d["settings"],
                   totals=d["totals"], versions=d["versions"], timings=d.get("timings", {}),
                   climb_ompl_version=d["climb_ompl_version"], schema_version=int(d["schema_version"]),
                   kind=d["kind"], events=tuple(d.get("events", ())), written_sha256=d.get("steps_sha256"),
                   source=source)

    def to_json(self) -> str:
        """The plan file's text: indented, key-sorted JSON with a final newline."""
        return json.dumps(self.to_dict(), indent=1, sort_keys=True, allow_nan=False) + "\n"

    def save(self, path: str | os.PathLike[str]) -> Path:
        """Write the plan file atomically (no partial file on failure).

        Raises:
            InputError: the folder does not exist or is not writable.
        """
        return atomic_write(path, self.to_json())

    @classmethod
    def load(cls, path: str | os.PathLike[str]) -> "Plan":
        """Read and validate a climb plan file.

        Raises:
            PlanFileError: unreadable, not JSON, schema-invalid (naming the JSON path) or not a climb plan.
        """
        return cls._from_valid(read_plan_dict(path), str(path))


def canonical_json(plan: Plan | dict[str, Any]) -> str:
    """The plan's JSON without the wall-clock ``timings``: equal for equal seeds and inputs."""
    d = dict(plan.to_dict() if isinstance(plan, Plan) else plan)
    d.pop("timings", None)
    return json.dumps(d, indent=1, sort_keys=True)


def library_versions() -> dict[str, str]:
    """Versions of the libraries that shape a plan (recorded in the plan file)."""
    from importlib import metadata

    out = {}
    for dist in ("climb_ompl", "ompl", "pin", "coal", "cvxpy", "numpy", "scipy", "highspy"):
        try:
            out[dist] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            out[dist] = "not installed"
    import platform

    out["python"] = platform.python_version()
    return out


# ---- schema ---------------------------------------------------------------------------------------
@lru_cache(maxsize=1)
def plan_schema() -> dict[str, Any]:
    """The plan-file JSON schema shipped with the package (``climb_ompl/schemas/plan.schema.json``)."""
    text = resources.files("climb_ompl").joinpath("schemas", "plan.schema.json").read_text()
    return json.loads(text)


def _json_path(parts: Any) -> str:
    out = "$"
    for p in parts:
        out += f"[{p}]" if isinstance(p, int) else f".{p}"
    return out


def schema_errors(d: Any) -> list[tuple[str, str]]:
    """All schema violations of a plan-file dict as ``(json_path, message)``, sorted by path."""
    import jsonschema

    validator = jsonschema.Draft202012Validator(plan_schema())
    errs = []
    for e in validator.iter_errors(d):
        # descend into the most specific error of an if/then or anyOf branch
        leaf = e
        while leaf.context:
            leaf = min(leaf.context, key=lambda c: (-len(c.absolute_path), str(c.message)))
        errs.append((_json_path(leaf.absolute_path), leaf.message))
    return sorted(set(errs))


def validate_plan_dict(d: Any, source: str = "<dict>") -> None:
    """Validate a plan-file dict against the schema.

    Raises:
        PlanFileError: ``field`` is the JSON path of the first violation (e.g. ``$.steps[3].waypoints``).
    """
    bad = _nonfinite(d)
    if bad is not None:
        raise PlanFileError(source, bad, "not a finite number (NaN or infinity)")
    errs = schema_errors(d)
    if errs:
        where, msg = errs[0]
        more = f" (and {len(errs) - 1} more)" if len(errs) > 1 else ""
        raise PlanFileError(source, where, f"{msg}{more}")


def _other_file(d: Any) -> str | None:
    """What a file read as ``d`` (its JSON or YAML) is when it is no plan: ``"a terrain file (with holds)"`` or
    ``"a robot spec (with limbs and a URDF)"``, else ``None``."""
    if not isinstance(d, dict) or "steps" in d:
        return None
    if "holds" in d:
        return "a terrain file (with holds)"
    if "limbs" in d and "urdf" in d:
        return "a robot spec (with limbs and a URDF)"
    return None


def _yaml_file(text: str) -> Any:
    """``text`` read as YAML (libyaml's loader when present), or ``None``; not tried for text that starts as JSON
    does (a truncated plan of megabytes would take seconds)."""
    import yaml

    if text.lstrip().startswith(("{", "[")):
        return None
    try:
        return yaml.load(text, Loader=getattr(yaml, "CSafeLoader", yaml.SafeLoader))
    except yaml.YAMLError:
        return None


def read_plan_dict(path: str | os.PathLike[str]) -> dict[str, Any]:
    """Read a plan file of any kind and validate it against the schema.

    Raises:
        PlanFileError: unreadable, not JSON or schema-invalid.
    """
    p = Path(path)
    try:
        text = p.read_text()
    except (OSError, UnicodeDecodeError) as exc:
        raise PlanFileError(p, "file", f"cannot read ({getattr(exc, 'strerror', None) or exc})") from None
    if not text.strip():
        raise PlanFileError(p, "file", "empty (a plan file is the JSON that climb-ompl plan writes)")
    bad: json.JSONDecodeError | None = None
    try:
        d = json.loads(text)
    except json.JSONDecodeError as exc:  # a YAML terrain or spec given here is said to be one, below
        d, bad = _yaml_file(text), exc
    except RecursionError:
        raise PlanFileError(p, "file", "invalid JSON (arrays or objects nested too deep to read)") from None
    kind = _other_file(d)
    if kind:
        raise PlanFileError(p, "file", f"{kind}, not a plan file (the JSON that climb-ompl plan writes)")
    if bad is not None:
        at = "" if bad.msg.endswith(" at") else " at"  # "Unterminated string starting at": the column follows
        raise PlanFileError(p, f"line {bad.lineno}", f"invalid JSON ({bad.msg}{at} column {bad.colno})")
    validate_plan_dict(d, str(p))
    return d


def robot_from_plan(plan: Plan | dict[str, Any], folder: str | os.PathLike[str] | None = None,
                    source: str = "<plan>") -> Any:
    """The plan's robot, rebuilt from the spec and URDF embedded in it (not from the installed files).

    The embedded URDF is written to ``folder`` (default: a temporary folder, deleted once the model is built:
    the model keeps the URDF's text, :attr:`~climb_ompl.model.robot.RobotModel.urdf_text`, and builds its visual
    geometry from it) and the spec's ``urdf`` field pointed at it.  A plan dict without an embedded robot (a
    hand-written playback file) falls back to the bundled robot of that name.

    Raises:
        PlanFileError: no robot in the plan, or an embedded URDF that cannot be read.  RobotModelError: a bad spec.
    """
    import tempfile

    from climb_ompl.model.robot import RobotModel

    if folder is None:
        with tempfile.TemporaryDirectory(prefix="climb-plan-robot-") as tmp:
            return robot_from_plan(plan, tmp, source)

    where = plan.source if isinstance(plan, Plan) and source == "<plan>" else source
    entry = plan.robot if isinstance(plan, Plan) else plan.get("robot")
    name = entry if isinstance(entry, str) else entry.get("name") if isinstance(entry, dict) else None
    if not isinstance(name, str) or not name:
        raise PlanFileError(where, "$.robot.name", "missing robot name")
    if not (isinstance(entry, dict) and isinstance(entry.get("spec"), dict) and isinstance(entry.get("urdf"), str)):
        return RobotModel.load(name)
    spec = json.loads(json.dumps(entry["spec"]))
    base = Path(folder)
    rel = Path(str(spec.get("urdf") or "embedded.urdf"))
    if rel.is_absolute() or ".." in rel.parts:
        rel = Path(rel.name)
    spec["urdf"] = rel.as_posix()  # unchanged for a spec next to its URDF: the replayed plan embeds the same spec
    (base / rel).parent.mkdir(parents=True, exist_ok=True)
    (base / rel).write_text(entry["urdf"])
    try:
        return RobotModel.from_spec(spec, base_dir=base, source=f"{where} ($.robot.spec)")
    except RobotModelError as exc:
        if Path(str(exc.path)) == base / rel:  # the URDF written from the plan: name the plan's field
            raise PlanFileError(where, f"$.robot.urdf ({exc.field})", exc.reason) from None
        raise


def _nonfinite(d: Any, path: str = "$") -> str | None:
    """JSON path of the first NaN or infinite number in ``d``, or ``None``."""
    if isinstance(d, float):
        return None if math.isfinite(d) else path
    if isinstance(d, dict):
        for k, v in d.items():
            if (p := _nonfinite(v, f"{path}.{k}")) is not None:
                return p
    elif isinstance(d, list):
        for i, v in enumerate(d):
            if (p := _nonfinite(v, f"{path}[{i}]")) is not None:
                return p
    return None


__all__ = ["SCHEMA_VERSION", "PLAN_KINDS", "ForceSample", "Step", "Plan", "canonical_json", "library_versions",
           "robot_record",
           "plan_schema", "schema_errors", "validate_plan_dict", "read_plan_dict", "sha256_json", "sha256_text",
           "robot_from_plan"]
