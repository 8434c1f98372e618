"""Benchmark grids over planners x constrained spaces x samplers x queries x seeds.

Every run executes in a child process with a hard timeout (a hung or crashing C++ planner is recorded as
failed, its process replaced, and the grid goes on); a child executes many runs in turn (:class:`RunWorker`:
the interpreter, the compiled equilibrium code and the models load once per child, not once per run), and
each run seeds OMPL's and numpy's RNGs, so its result does not depend on what ran before it in the child.
Runs go to a local pool by default or to a Dask distributed cluster
(``scheduler="tcp://HOST:PORT"`` or a ``distributed.Client``).  Results go to a SQLite database that
follows OMPL's benchmark database layout (tables ``experiments``, ``plannerConfigs``, ``runs``,
``progress``, ``enums``, as OMPL's ``ompl_benchmark_statistics.py`` creates them, so Planner Arena style
tools read it) plus this project's ``grid_runs`` table keyed by the run's identity, which makes an
interrupted grid resumable, and to a tidy CSV for pandas.

A run is a plain dict (JSON-able)::

    {"planner": "LazyPRM", "space": "projected", "sampler": "uniform", "query": 3, "seed": 0,
     "time_limit": 5.0, "task": {...query description, see climb_ompl.bench.onestep...}}
"""

from __future__ import annotations

import csv
import itertools
import json
import os
import socket
import sqlite3
import subprocess
import sys
import time
from collections.abc import Callable, Iterable, Sequence
from concurrent.futures import ThreadPoolExecutor, as_completed
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from climb_ompl.errors import InputError

#: Columns of OMPL's ``runs`` table that a run fills, with their SQL types (OMPL's naming: spaces
#: become underscores; ``status`` is an enum).
RUN_COLUMNS: dict[str, str] = {
    "time": "REAL",
    "solved": "BOOLEAN",
    "status": "ENUM",
    "approximate_solution": "BOOLEAN",
    "solution_length": "REAL",
    "graph_states": "INTEGER",
    "states_sampled": "INTEGER",
    "memory": "REAL",
    "crashed": "BOOLEAN",
    "timed_out": "BOOLEAN",
}

#: OMPL's ``PlannerStatus`` enum, as written in the ``enums`` table.
STATUS_ENUM: tuple[str, ...] = (
    "unknown status", "invalid start", "invalid goal", "unrecognized goal type", "timeout",
    "approximate solution", "exact solution", "crash", "abort", "infeasible",
)

SCHEMA_SQL = """
CREATE TABLE IF NOT EXISTS experiments (
    id INTEGER PRIMARY KEY AUTOINCREMENT, name VARCHAR(512), totaltime REAL, timelimit REAL,
    memorylimit REAL, runcount INTEGER, version VARCHAR(128), hostname VARCHAR(1024), cpuinfo TEXT,
    date DATETIME, seed INTEGER, setup TEXT);
CREATE TABLE IF NOT EXISTS plannerConfigs (
    id INTEGER PRIMARY KEY AUTOINCREMENT, name VARCHAR(512) NOT NULL, settings TEXT);
CREATE TABLE IF NOT EXISTS enums (
    name VARCHAR(512), value INTEGER, description TEXT, PRIMARY KEY (name, value));
CREATE TABLE IF NOT EXISTS runs (
    id INTEGER PRIMARY KEY AUTOINCREMENT, experimentid INTEGER, plannerid INTEGER, {run_cols},
    FOREIGN KEY(experimentid) REFERENCES experiments(id) ON DELETE CASCADE,
    FOREIGN KEY(plannerid) REFERENCES plannerConfigs(id) ON DELETE CASCADE);
CREATE TABLE IF NOT EXISTS progress (
    runid INTEGER, time REAL, best_cost REAL, PRIMARY KEY (runid, time),
    FOREIGN KEY(runid) REFERENCES runs(id) ON DELETE CASCADE);
CREATE TABLE IF NOT EXISTS grid_runs (
    key TEXT PRIMARY KEY, runid INTEGER, planner TEXT, space TEXT, sampler TEXT, query INTEGER,
    seed INTEGER, result TEXT, FOREIGN KEY(runid) REFERENCES runs(id));
""".format(run_cols=", ".join(f"{k} {v if v != 'ENUM' else 'INTEGER'}" for k, v in RUN_COLUMNS.items()))

#: Tidy-table columns (one row per run).
TIDY_COLUMNS: tuple[str, ...] = (
    "planner", "space", "sampler", "query", "seed", "time_limit", "max_iterations", "solved", "status", "time",
    "path_length", "states_sampled", "samples", "roadmap_size", "peak_rss_mb", "crashed", "timed_out",
    "rejections", "error",
)


@dataclass
class Grid:
    """A benchmark grid.

    Attributes:
        name: experiment name (OMPL's ``experiments.name``).
        planners, spaces, samplers: names from the registries (``climb-ompl planners``).
        queries: one-step query descriptions (JSON-able dicts, as made by :func:`make_queries` or read from
            the query-set files of :mod:`climb_ompl.bench._query_set`).
        seeds: seeds; each (planner, space, sampler, query, seed) is one run (a custom sampler only with
            the projected space, the one space that calls it).  A query's ``uid`` (query-set files,
            :mod:`climb_ompl.bench._query_set`) is its number in the database, else its position in ``queries``.
        time_limit: per-run planning time limit, seconds (a wall-clock guard).
        max_iterations: per-run budget of validity checks (``find_path(max_iterations=...)``): runs that
            stop on it are reproducible whatever the machine load; ``None``: time limit only.
        hard_timeout: per-run process timeout, seconds (default ``3 * time_limit + 30``).
        extra: further keys copied into every run dict (test hooks, options of :func:`run_query`).
    """

    name: str
    planners: Sequence[str]
    spaces: Sequence[str]
    samplers: Sequence[str]
    queries: Sequence[dict[str, Any]]
    seeds: Sequence[int] = (0,)
    time_limit: float = 5.0
    max_iterations: int | None = None
    hard_timeout: float | None = None
    extra: dict[str, Any] = field(default_factory=dict)

    def runs(self) -> list[dict[str, Any]]:
        """The runs of the grid, in a fixed order."""
        out = []
        for planner, space, sampler, (qi, q), seed in itertools.product(
            self.planners, self.spaces, self.samplers, enumerate(self.queries), self.seeds
        ):
            if sampler != "uniform" and space != "projected":
                continue  # custom samplers need the projected space (find_path refuses them elsewhere)
            out.append({"planner": planner, "space": space, "sampler": sampler, "query": int(q.get("uid", qi)),
                        "seed": int(seed),
                        "time_limit": float(self.time_limit), "max_iterations": self.max_iterations, "task": q,
                        **self.extra})
        return out

    @property
    def timeout(self) -> float:
        """Hard per-run process timeout in seconds."""
        return self.hard_timeout if self.hard_timeout is not None else 3.0 * self.time_limit + 30.0


#: The keys that identify a run (what resuming matches on and what results carry back).
ID_KEYS: tuple[str, ...] = ("planner", "space", "sampler", "query", "seed", "time_limit", "max_iterations")

#: Test hooks understood by the run's child process in place of a planner name: ``__crash__`` aborts the
#: process (SIGABRT, like a C++ assertion in a planner), ``__hang__`` sleeps past any hard timeout.
CRASH_PLANNER, HANG_PLANNER = "__crash__", "__hang__"

#: One-step status (:data:`climb_ompl.climb.onestep.STATUSES`) -> OMPL ``PlannerStatus`` name (``enums`` table).
OMPL_STATUS: dict[str, str] = {"exact": "exact solution", "no-path": "timeout", "timeout": "timeout",
                               "torque-violation": "infeasible", "crash": "crash"}


def run_key(run: dict[str, Any]) -> str:
    """Identity of a run in the database (what resuming matches on); ``direct`` too when the run sets it."""
    key = {k: run.get(k) for k in ID_KEYS}
    if "direct" in run or "direct_first" in run:
        key["direct"] = run.get("direct", run.get("direct_first"))
    return json.dumps(key, sort_keys=True)


# ---- one-step queries ----------------------------------------------------------------------------------
def make_queries(robot: str = "lemur", terrain: str = "demo-wall", n: int = 3, seed: int = 0,
                 max_steps: int | None = None, releases: bool = False) -> list[dict[str, Any]]:
    """One-step queries (Bretl et al. (2004), sec. 3): paths on a stance between two transitions.

    A greedy climb generates them: from :func:`climb_ompl.climb.multistep.default_start`, the lowest limb that can
    be released (FIND-TRANSITION to the stance without it) moves to the nearest reachable higher hold that
    has a transition; the query (``kind: grab``) is the path on the stance without that limb from the release
    configuration to the grab configuration, and the climb goes on from there.  With ``releases`` the path
    on the full stance from the climb's configuration to the release configuration is a query too
    (``kind: release``, ``moving: None``), when they differ.  Deterministic for a given ``seed``.

    Args:
        robot: bundled robot name (or spec path).
        terrain: bundled terrain name (or terrain file path).
        n: number of queries wanted.
        seed: seed of the start configuration and of every FIND-TRANSITION.
        max_steps: grab attempts before giving up (default ``10 * n``).
        releases: also emit the release queries.

    Returns:
        Up to ``n`` JSON-able dicts ``{robot, terrain, index, kind, stance, moving, from_hold, to_hold,
        q_start, q_goal}`` (fewer when the climb gets stuck).

    Raises:
        QueryError: no feasible start on this terrain.
    """
    import numpy as np

    from climb_ompl.climb.multistep import default_start, load_terrain
    from climb_ompl.climb.transition import TransitionFinder
    from climb_ompl.errors import QueryError
    from climb_ompl.manifold.feasibility import Feasibility
    from climb_ompl.manifold.stance import Stance
    from climb_ompl.model.reach import pair_reach
    from climb_ompl.model.robot import RobotModel

    r = RobotModel.load(robot)
    t = load_terrain(terrain)
    start = default_start(r, t, seed=seed)
    if start is None:
        raise QueryError(f"no feasible start stance for {robot!r} on {terrain!r}")
    stance, q = Stance(start[0]), np.asarray(start[1], dtype=float)
    feas = Feasibility.of(r, t)
    finder = TransitionFinder.of(feas)
    reach = pair_reach(r)
    P = t.positions
    up = P @ t.up  # heights along minus gravity
    out: list[dict[str, Any]] = []
    k = 0
    for _ in range(max_steps or 10 * n):
        if len(out) >= n:
            break
        moved = False
        for limb in sorted(stance.limbs, key=lambda lb: (t.height(stance[lb]), lb)):
            s3 = stance.without(limb)
            k += 1
            qa = q if feas.valid(s3, q) else finder.find(stance, s3, q, seed=seed + k)
            if qa is None:
                continue
            here = t.hold(stance[limb]).p
            contacts = [(lb, t.hold(h).p) for lb, h in s3.pairs]
            used = set(stance.hold_ids)
            cands = [i for i in np.argsort(np.linalg.norm(P - (here + 0.2 * t.up), axis=1), kind="stable")
                     if t.holds[i].id not in used and up[i] > t.height(here) + 0.03
                     and all(np.linalg.norm(P[i] - p) <= reach[(limb, lb)] for lb, p in contacts)][:6]
            for i in cands:
                hid = t.holds[int(i)].id
                k += 1
                qb = finder.find(s3, s3.with_hold(limb, hid), qa, seed=seed + k)
                if qb is None or float(np.max(np.abs(qb - qa))) < 1e-6:
                    continue
                if releases and float(np.max(np.abs(qa - q))) > 1e-6:
                    out.append({"robot": robot, "terrain": terrain, "index": len(out), "kind": "release",
                                "stance": stance.to_dict(), "moving": None, "from_hold": stance[limb],
                                "to_hold": None, "q_start": [float(x) for x in q], "q_goal": [float(x) for x in qa]})
                out.append({"robot": robot, "terrain": terrain, "index": len(out), "kind": "grab",
                            "stance": s3.to_dict(), "moving": limb, "from_hold": stance[limb], "to_hold": hid,
                            "q_start": [float(x) for x in qa], "q_goal": [float(x) for x in qb]})
                stance, q, moved = s3.with_hold(limb, hid), qb, True
                break
            if moved:
                break
        if not moved:
            break
    return out[:n]


def run_query(task: dict[str, Any], planner: str = "LazyPRM", space: str = "projected", sampler: str = "uniform",
              time_limit: float = 5.0, seed: int = 0, max_iterations: int | None = None,
              direct: bool = True, range_: float | None = None, rho: float | None = None) -> dict[str, Any]:
    """Plan one query of :func:`make_queries` with :func:`climb_ompl.climb.onestep.find_path` and measure it.

    ``direct=False`` skips ``find_path``'s lift-move-place local path, so the planner alone answers.
    ``range_`` and ``rho``: the planner range and chart radius (default ``find_path``'s).

    Returns:
        ``{solved, status (one-step status), time (s), path_length (sum of joint-space distances between
        waypoints, None unless solved), states_sampled (states checked for validity), samples (drawn by a
        custom sampler, None for uniform), roadmap_size (planner graph vertices), rejections (by reason),
        direct_solved (the local path answered)}``.
    """
    import numpy as np

    from climb_ompl.bench._common import ONESTEP_OPTIONS
    from climb_ompl.climb.multistep import load_terrain
    from climb_ompl.climb.onestep import find_path
    from climb_ompl.model.robot import RobotModel

    r = RobotModel.load(task["robot"])
    t = load_terrain(task["terrain"])
    res = find_path(r, t, task["stance"], task["q_start"], task["q_goal"], seed=seed,
                    **{**ONESTEP_OPTIONS, "planner": planner, "space": space, "sampler": sampler,
                       "time_limit": time_limit, "max_iterations": max_iterations, "direct": direct,
                       "range_": range_, "rho": rho})
    length = None
    if res.found and len(res.path) > 1:
        qs = np.asarray(res.path)
        length = float(np.linalg.norm(np.diff(qs, axis=0), axis=1).sum())
    st = res.stats
    return {"solved": res.found, "status": res.status, "time": float(st["time_s"]), "path_length": length,
            "states_sampled": int(st["checks"]), "samples": st.get("samples"),
            "roadmap_size": int(st["roadmap_vertices"]), "rejections": dict(st.get("rejections", {})),
            "direct_solved": bool(st.get("direct"))}


# ---- one run, isolated -------------------------------------------------------------------------------
#: Runs a worker process executes before it is replaced by a fresh one (bounds what a leaking planner keeps).
WORKER_RUNS = 200

#: A worker process with no run for this long exits on its own (a Dask worker's idle child), s.
WORKER_IDLE_S = 900.0

#: Time a fresh worker process has to import its modules and say it is ready, s (not counted in a run's hard
#: timeout, which bounds the run alone, whatever the machine's load does to an interpreter's start).
WORKER_START_S = 300.0


class RunWorker:
    """A child process that executes runs one after another (``python -m climb_ompl.bench._runs --serve --ready``).

    The child reads one run dict per line on stdin and writes one result line on a private copy of its
    stdout (OMPL's and Python's own output go to stderr).  Every run seeds OMPL's and numpy's RNGs
    (:func:`climb_ompl.climb.onestep.find_path`), so a run gives the same result in a fresh or a reused process.
    A crash (the process dies, a signal) or a hang (no result within the hard timeout: the process is
    killed) costs the process: the next run starts a fresh one.  A Python exception in a run is reported
    for that run and the process goes on.  A fresh process imports the planning modules and reports ready
    (within :data:`WORKER_START_S`) before it is handed a run, so a run's hard timeout counts the run only.
    """

    def __init__(self, max_runs: int = WORKER_RUNS) -> None:
        self.max_runs = max_runs
        self.proc: subprocess.Popen | None = None
        self.runs = 0
        self.started = 0  # processes started (a measure of the per-process overhead paid)

    def _start(self) -> None:
        import queue
        import threading
        from collections import deque

        self.proc = subprocess.Popen([sys.executable, "-m", "climb_ompl.bench._runs", "--serve", "--ready"],
                                     stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
                                     bufsize=1)
        self.runs, self.started = 0, self.started + 1
        self._lines: queue.Queue[str | None] = queue.Queue()
        self._err: deque[str] = deque(maxlen=20)

        def pump(stream: Any, put: Callable[[Any], None], eof: bool) -> None:
            for line in stream:
                put(line)
            if eof:
                put(None)

        self._threads = [threading.Thread(target=pump, args=(self.proc.stdout, self._lines.put, True), daemon=True),
                         threading.Thread(target=pump, args=(self.proc.stderr, self._err.append, False), daemon=True)]
        for th in self._threads:
            th.start()
        try:
            ready = self._lines.get(timeout=WORKER_START_S)
        except queue.Empty:
            ready = None
        if ready is None or "__ready__" not in ready:
            tail = [ln.strip() for ln in self._err if ln.strip()][-1:]
            self.close()
            raise RuntimeError("the worker process did not start" + (f": {tail[0]}" if tail else ""))

    def close(self) -> None:
        """Kill the child process (if any) and reap it."""
        if self.proc is not None:
            if self.proc.poll() is None:
                self.proc.kill()
            self.proc.wait()
            for th in self._threads:
                th.join(timeout=5.0)
            for f in (self.proc.stdin, self.proc.stdout, self.proc.stderr):
                if f is not None:
                    f.close()
            self.proc = None

    def run(self, run: dict[str, Any], timeout: float) -> dict[str, Any]:
        """Execute ``run`` in the child with a hard timeout; never raises for planner failures (see
        :func:`run_isolated`)."""
        import queue

        if self.proc is not None and (self.proc.poll() is not None or self.runs >= self.max_runs):
            self.close()
        t0 = time.perf_counter()
        if self.proc is None:
            try:
                self._start()
            except RuntimeError as e:
                res = _failed(run, time.perf_counter() - t0, crashed=True)
                res["error"] = str(e)
                return res
        assert self.proc is not None and self.proc.stdin is not None
        self.runs += 1
        t0 = time.perf_counter()
        try:
            self.proc.stdin.write(json.dumps(run) + "\n")
            self.proc.stdin.flush()
            line = self._lines.get(timeout=timeout)
        except queue.Empty:
            self.close()
            res = _failed(run, time.perf_counter() - t0, timed_out=True)
            res["error"] = f"killed after the hard timeout of {timeout:g} s"
            return res
        except OSError:  # the child died before reading the run
            line = None
        if line is None:  # the child died during the run: its last words are on stderr
            code = self.proc.wait()
            self._threads[1].join(timeout=5.0)
            tail = [ln.strip() for ln in self._err if ln.strip()][-1:]
            self.close()
            res = _failed(run, time.perf_counter() - t0, crashed=True)
            res["error"] = tail[0] if tail else f"exit code {code}"
            return res
        out = json.loads(line)
        if "__error__" in out:  # a Python exception in the run
            res = _failed(run, time.perf_counter() - t0, crashed=True)
            res["error"] = out["__error__"]
            return res
        return out

    def __enter__(self) -> RunWorker:
        return self

    def __exit__(self, *exc: object) -> None:
        self.close()


_THREAD_WORKER = None  # threading.local holding a RunWorker per thread of this process (Dask tasks)


def _thread_worker() -> RunWorker:
    """This thread's long-lived worker (a Dask worker thread keeps its child between tasks)."""
    global _THREAD_WORKER
    import atexit
    import threading

    if _THREAD_WORKER is None:
        _THREAD_WORKER = threading.local()
    w = getattr(_THREAD_WORKER, "worker", None)
    if w is None:
        w = _THREAD_WORKER.worker = RunWorker()
        atexit.register(w.close)
    return w


def run_isolated(run: dict[str, Any], timeout: float, worker: RunWorker | None = None) -> dict[str, Any]:
    """Execute one run in a child process with a hard timeout; never raises for planner failures.

    The child is ``worker`` (default: this thread's long-lived :class:`RunWorker`), reused from run to run;
    a crash or a timeout replaces it.  Returns the run's result dict (see :data:`TIDY_COLUMNS`); a crash
    (the child dies or the run raises) or a timeout (the child is killed) gives ``solved=False`` with
    ``crashed``/``timed_out`` set and the child's last stderr line (or the exception) in ``error``.
    """
    return (worker or _thread_worker()).run(run, timeout)


def _ids(run: dict[str, Any]) -> dict[str, Any]:
    """The run's identity, plus the name of the query set its query comes from (when it has one)."""
    out = {k: run.get(k) for k in ID_KEYS}
    if "direct" in run:
        out["direct_first"] = run["direct"]
    qset = (run.get("task") or {}).get("set")
    if qset is not None:
        out["query_set"] = qset
    return out


def _failed(run: dict[str, Any], elapsed: float, crashed: bool = False, timed_out: bool = False) -> dict[str, Any]:
    return {**_ids(run), "solved": False, "status": "crash" if crashed else "timeout", "time": elapsed,
            "path_length": None, "states_sampled": None, "samples": None, "roadmap_size": None,
            "peak_rss_mb": None, "crashed": crashed, "timed_out": timed_out, "rejections": {}}


def _peak_rss_reset() -> bool:
    """Reset this process's peak resident set size (Linux ``/proc/self/clear_refs``), so the next reading
    is the peak of one run in a reused process; ``False`` where the kernel does not allow it."""
    try:
        with open("/proc/self/clear_refs", "w") as f:
            f.write("5")
        return True
    except OSError:
        return False


def _peak_rss_mb() -> float:
    """Peak resident set size of this process since start or the last :func:`_peak_rss_reset`, MB."""
    try:
        with open("/proc/self/status") as f:
            for line in f:
                if line.startswith("VmHWM:"):
                    return int(line.split()[1]) / 1024.0
    except OSError:
        pass
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0  # kilobytes on Linux


def _child(run: dict[str, Any]) -> dict[str, Any]:
    """Body of the child process for one run: plan the run's one-step query and measure it."""
    if run["planner"] == CRASH_PLANNER:
        os.abort()
    if run["planner"] == HANG_PLANNER:
        time.sleep(1e6)
    _peak_rss_reset()
    stats = run_query(run["task"], planner=run["planner"], space=run["space"], sampler=run["sampler"],
                      time_limit=run["time_limit"], seed=run["seed"], max_iterations=run.get("max_iterations"),
                      direct=run.get("direct", True))
    return {**_ids(run), **stats, "peak_rss_mb": _peak_rss_mb(), "crashed": False, "timed_out": False}


def _serve(idle: float = WORKER_IDLE_S, ready: bool = False) -> None:
    """The :class:`RunWorker` child: one run dict per stdin line, one result line on the private channel.

    The channel is a copy of the original stdout; stdout itself then points at stderr, so whatever OMPL,
    a C++ library or ``print`` writes cannot mix with the result lines.  Exits at end of input or after
    ``idle`` seconds without a run.  ``ready``: say so on the channel once the modules are loaded.
    """
    import select
    import traceback

    channel = os.fdopen(os.dup(1), "w", buffering=1)
    sys.stdout.flush()
    os.dup2(2, 1)
    from climb_ompl.climb import onestep  # noqa: F401 - the planning modules, loaded before the first run's clock starts
    from climb_ompl.equilibrium._simplex import _kernels

    _kernels()
    if ready:
        channel.write(json.dumps({"__ready__": os.getpid()}) + "\n")
    while True:
        ready, _, _ = select.select([sys.stdin], [], [], idle)
        line = sys.stdin.readline() if ready else ""
        if not line:
            return
        run = json.loads(line)
        try:
            out = _child(run)
        except Exception as e:  # noqa: BLE001 - reported as this run's crash; the process goes on
            out = {"__error__": traceback.format_exception_only(e)[-1].strip()}
        channel.write(json.dumps(out, sort_keys=True, default=float) + "\n")


def _collect(futs: dict[Any, int], completed: Callable[[Any], Any], results: list[Any],
             on_result: Callable[[dict[str, Any]], None] | None) -> None:
    """Store each future's result at its run's index as it completes (``completed``: the executor's
    ``as_completed``), calling ``on_result`` with it."""
    for fut in completed(futs):
        i = futs[fut]
        results[i] = fut.result()
        if on_result:
            on_result(results[i])


# ---- executors -------------------------------------------------------------------------------------
def execute_runs(runs: Sequence[dict[str, Any]], timeout: float, *, workers: int | None = None,
            scheduler: Any = None, on_result: Callable[[dict[str, Any]], None] | None = None,
            worker_runs: int = WORKER_RUNS) -> list[dict[str, Any]]:
    """Execute ``runs`` (each in a child process, isolated from this one); results in the order of ``runs``.

    Args:
        runs: run dicts (see module docstring).
        timeout: hard per-run timeout, seconds.
        workers: local pool size (default: CPU count); 1 runs serially.  Each pool thread drives one
            :class:`RunWorker`, reused for up to ``worker_runs`` runs (1: a fresh process per run).
        scheduler: ``None`` for the local pool, a ``"tcp://HOST:PORT"`` address or a
            ``distributed.Client`` to run on a Dask cluster (each Dask worker thread drives its own
            long-lived :class:`RunWorker`, since Dask cannot kill a hung C++ planner thread).
        on_result: called with each result as it arrives (progress, incremental saving).
    """
    results: list[dict[str, Any] | None] = [None] * len(runs)
    if scheduler is not None:
        from distributed import Client
        from distributed import as_completed as dask_completed

        client = scheduler if isinstance(scheduler, Client) else Client(scheduler)
        try:
            _collect({client.submit(run_isolated, r, timeout, pure=False): i for i, r in enumerate(runs)},
                     dask_completed, results, on_result)
        finally:
            if client is not scheduler:
                client.close()
        return results  # type: ignore[return-value]
    import queue

    n = workers or os.cpu_count() or 1
    idle: queue.SimpleQueue[RunWorker] = queue.SimpleQueue()
    pool_workers = [RunWorker(max_runs=worker_runs) for _ in range(n)]
    for w in pool_workers:
        idle.put(w)

    def one(run: dict[str, Any]) -> dict[str, Any]:
        w = idle.get()  # at most n runs at once, so a worker is always free here
        try:
            return w.run(run, timeout)
        finally:
            idle.put(w)

    try:
        with ThreadPoolExecutor(max_workers=n) as pool:  # threads only wait on child processes
            _collect({pool.submit(one, r): i for i, r in enumerate(runs)}, as_completed, results, on_result)
    finally:
        for w in pool_workers:
            w.close()
    return results  # type: ignore[return-value]


# ---- database ----------------------------------------------------------------------------------------
#: Why :func:`open_db` and :func:`load_results` refuse a file that SQLite cannot read as their database.
NOT_A_DATABASE = "not a benchmark database written by climb-ompl bench"


def open_db(path: str | Path) -> sqlite3.Connection:
    """Open (creating if needed) a benchmark database with OMPL's tables and ``grid_runs``."""
    path = Path(path)
    if path.parent and not path.parent.is_dir():
        raise InputError(path, "database", f"folder {str(path.parent)!r} does not exist")
    con = sqlite3.connect(path)
    try:
        con.execute("PRAGMA foreign_keys = ON")
        con.executescript(SCHEMA_SQL)
    except sqlite3.DatabaseError as exc:  # an existing file that is no SQLite database
        con.close()
        raise InputError(path, "database", f"{NOT_A_DATABASE} ({exc})") from None
    con.executemany("INSERT OR IGNORE INTO enums VALUES ('status', ?, ?)", list(enumerate(STATUS_ENUM)))
    con.commit()
    return con


def finished_keys(con: sqlite3.Connection) -> set[str]:
    """Keys of the runs already in the database."""
    return {row[0] for row in con.execute("SELECT key FROM grid_runs")}


def _experiment(con: sqlite3.Connection, grid: Grid) -> int:
    from climb_ompl._version import __version__

    row = con.execute("SELECT id FROM experiments WHERE name = ?", (grid.name,)).fetchone()
    if row:
        return int(row[0])
    cur = con.execute(
        "INSERT INTO experiments (name, totaltime, timelimit, memorylimit, runcount, version, hostname, cpuinfo,"
        " date, seed, setup) VALUES (?, 0, ?, 0, ?, ?, ?, ?, datetime('now'), ?, ?)",
        (grid.name, grid.time_limit, len(grid.runs()), f"climb_ompl {__version__}", socket.gethostname(),
         f"{os.cpu_count()} cpus", int(grid.seeds[0]) if grid.seeds else 0,
         json.dumps({"planners": list(grid.planners), "spaces": list(grid.spaces), "samplers": list(grid.samplers),
                     "queries": len(grid.queries), "seeds": list(grid.seeds)})))
    return int(cur.lastrowid)  # type: ignore[arg-type]


def _planner_config(con: sqlite3.Connection, res: dict[str, Any]) -> int:
    name = f"geometric_{res['planner']}"
    settings = json.dumps({"space": res["space"], "sampler": res["sampler"]}, sort_keys=True)
    row = con.execute("SELECT id FROM plannerConfigs WHERE name = ? AND settings = ?", (name, settings)).fetchone()
    if row:
        return int(row[0])
    return int(con.execute("INSERT INTO plannerConfigs (name, settings) VALUES (?, ?)", (name, settings)).lastrowid)  # type: ignore[arg-type]


def store(con: sqlite3.Connection, exp_id: int, run: dict[str, Any], res: dict[str, Any]) -> None:
    """Insert one run's result into ``runs`` and ``grid_runs`` (one transaction)."""
    status = OMPL_STATUS.get(res.get("status") or "", "unknown status")
    code = STATUS_ENUM.index(status)
    cur = con.execute(
        "INSERT INTO runs (experimentid, plannerid, time, solved, status, approximate_solution, solution_length,"
        " graph_states, states_sampled, memory, crashed, timed_out) VALUES (?,?,?,?,?,?,?,?,?,?,?,?)",
        (exp_id, _planner_config(con, res), res["time"], int(res["solved"]), code, 0, res.get("path_length"),
         res.get("roadmap_size"), res.get("states_sampled"), res.get("peak_rss_mb"), int(res["crashed"]),
         int(res["timed_out"])))
    con.execute("INSERT OR REPLACE INTO grid_runs VALUES (?,?,?,?,?,?,?,?)",
                (run_key(run), cur.lastrowid, res["planner"], res["space"], res["sampler"], res["query"],
                 res["seed"], json.dumps(res, sort_keys=True)))
    con.commit()


def load_results(db: str | Path) -> list[dict[str, Any]]:
    """All run results stored in ``db`` (ordered by planner, space, sampler, query, seed).

    Raises:
        InputError: no such file, or not a database of this module (:func:`open_db`).
    """
    if not Path(db).is_file():
        raise InputError(db, "database", "a folder, not a database file" if Path(db).is_dir() else "no such file")
    con = sqlite3.connect(db)
    try:
        rows = con.execute("SELECT result FROM grid_runs ORDER BY planner, space, sampler, query, seed").fetchall()
    except sqlite3.DatabaseError as exc:  # not SQLite, or SQLite without the grid's table
        raise InputError(db, "database", f"{NOT_A_DATABASE} ({exc})") from None
    finally:
        con.close()
    return [json.loads(r[0]) for r in rows]


def summary_table(results: Iterable[dict[str, Any]]) -> dict[str, dict[str, Any]]:
    """Per ``planner/space/sampler``: runs, success rate, median time and path length of solved runs."""
    import numpy as np

    groups: dict[str, list[dict[str, Any]]] = {}
    for r in results:
        groups.setdefault(f"{r['planner']}/{r['space']}/{r['sampler']}", []).append(r)
    out = {}
    for key in sorted(groups):
        rs = groups[key]
        ok = [r for r in rs if r["solved"]]
        out[key] = {"runs": len(rs), "success_rate": len(ok) / len(rs),
                    "median_s": float(np.median([r["time"] for r in ok])) if ok else None,
                    "median_path_length": float(np.median([r["path_length"] for r in ok])) if ok else None}
    return out


def write_tidy(results: Iterable[dict[str, Any]], path: str | Path) -> Path:
    """Write the tidy one-row-per-run CSV (rejections as JSON) atomically."""
    import io

    from climb_ompl._io import atomic_write

    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(TIDY_COLUMNS), extrasaction="ignore")
    w.writeheader()
    for r in results:
        w.writerow({**r, "rejections": json.dumps(r.get("rejections", {}), sort_keys=True)})
    return atomic_write(path, buf.getvalue())


def run_grid(grid: Grid, db: str | Path, *, workers: int | None = None, scheduler: Any = None,
             resume: bool = True, progress: Callable[[int, int], None] | None = None,
             runs: Sequence[dict[str, Any]] | None = None, worker_runs: int = WORKER_RUNS) -> list[dict[str, Any]]:
    """Run (or resume) ``grid``, storing each result in ``db`` as it arrives; returns all results in ``db``.

    Runs whose key is already in ``db`` are skipped when ``resume`` is true.  ``runs``: run only these
    (a subset of ``grid.runs()``, e.g. a sample to estimate the grid's time).  ``worker_runs``: runs per
    child process of the local pool (:func:`execute_runs`).
    """
    con = open_db(db)
    try:
        exp_id = _experiment(con, grid)
        done = finished_keys(con) if resume else set()
        todo = [r for r in (grid.runs() if runs is None else runs) if run_key(r) not in done]
        by_key = {run_key(r): r for r in todo}
        count = [0]
        t0 = time.perf_counter()

        def on_result(res: dict[str, Any]) -> None:
            store(con, exp_id, by_key[run_key(res)], res)
            count[0] += 1
            if progress:
                progress(count[0], len(todo))

        execute_runs(todo, grid.timeout, workers=workers, scheduler=scheduler, on_result=on_result,
                     worker_runs=worker_runs)
        con.execute("UPDATE experiments SET totaltime = totaltime + ? WHERE id = ?", (time.perf_counter() - t0, exp_id))
        con.commit()
    finally:
        con.close()
    return load_results(db)


if __name__ == "__main__":
    if sys.argv[1:2] == ["--serve"]:
        _serve(ready="--ready" in sys.argv[2:])
    else:  # one run given as JSON on the command line
        print(json.dumps(_child(json.loads(sys.argv[1])), sort_keys=True, default=float))
