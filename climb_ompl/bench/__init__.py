"""Benchmarks behind ``climb-ompl bench NAME`` (and ``make bench``).

Convention (one per module ``climb_ompl/bench/<name>.py``):

* ``run(**params) -> dict``: does the measurement and returns JSON-able figures; ratios are taken
  against a baseline measured in the same run, never against a fixed time.
* ``summary(result) -> str``: the one-line summary printed after the run.
* ``command``: a typer command function (``climb-ompl bench <name> ...``) that calls
  :func:`climb_ompl.bench._common.execute`, which runs ``run`` in its own subprocess with a
  timeout (a hung C++ planner cannot stall the caller), writes the JSON atomically and prints the
  summary.
"""
