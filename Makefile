# The README's two commands: `make demo` (install + LEMUR climb with playback) and `make test`
# (install + the whole test suite).  Both create their own virtual environment in .venv and install
# the exact versions of requirements.lock (the lock that passed CI), then the package itself
# (editable, without build isolation: hatchling comes from the lock, no network access at build time).
# On a fresh Debian machine the only system packages needed are python3-venv (for `python3 -m venv`)
# and chromium (browser tests); both are installed with apt-get when missing (as root, or with sudo).
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed
APT    := $(if $(filter 0,$(shell id -u)),,sudo )env DEBIAN_FRONTEND=noninteractive apt-get
PYTEST_ARGS ?=
# pytest-xdist processes for `make test` (the suite is sized for a 2-core machine).  --dist loadfile runs each
# test file on one process, so a module-scoped fixture (a grid, a plan, a browser page) is computed once.
# (Grouping by xdist_group marks, --dist loadgroup, does not work with pytest-xdist 3.8 under pytest 9.2.)
TEST_WORKERS ?= 2

.PHONY: demo test test-fast test-slow bench compare suite results papers lint install chromium clean

$(STAMP): pyproject.toml requirements.lock
	@$(PYTHON) -c 'import sys; sys.exit(sys.version_info < (3, 11))' || \
	  { echo "error: $(PYTHON) is older than Python 3.11 (set PYTHON=python3.11 or newer)" >&2; exit 2; }
	@$(PYTHON) -m venv $(VENV) 2>/dev/null || { \
	  echo "python venv/ensurepip missing: installing python3-venv with apt-get"; \
	  $(APT) update -qq && $(APT) install -y -qq python3-venv >/dev/null && $(PYTHON) -m venv $(VENV); }
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -r requirements.lock
	$(PY) -m pip install -q --no-deps --no-build-isolation -e .
	touch $(STAMP)

install: $(STAMP)

# Debian's chromium for the playback browser tests (Playwright cannot download its own browser here).
# Not fatal: without it the browser tests skip themselves.
chromium:
	@command -v chromium >/dev/null 2>&1 || { $(APT) update -qq && $(APT) install -y -qq chromium >/dev/null; } || \
	  echo "warning: could not install chromium; the browser tests will be skipped" >&2

demo: $(STAMP)
	$(VENV)/bin/climb-ompl demo --out-dir out

# Prints the ten slowest tests (--durations in pyproject.toml) and the suite's wall-clock time.
test: $(STAMP) chromium
	$(VENV)/bin/ruff check climb_ompl tests
	@start=$$(date +%s); \
	$(VENV)/bin/python -m pytest -q -m "not slow" -n $(TEST_WORKERS) --dist loadfile $(PYTEST_ARGS); rc=$$?; \
	echo "make test: test suite ran in $$(( $$(date +%s) - start )) s (pytest exit code $$rc)"; exit $$rc

# The fast tier (under a minute on the 2-core machine): every module's basics (the layers, the equilibrium oracles,
# terrain and robot loading, the one-step pieces, the command line's checks) without the tests marked slow, climb
# (a whole multi-step climb), browser or heavy (pyproject.toml).  `make test` runs these and the climb, browser and
# heavy ones.
FAST_MARKERS := not slow and not climb and not browser and not heavy
test-fast: $(STAMP)
	$(VENV)/bin/ruff check climb_ompl tests
	@start=$$(date +%s); \
	$(VENV)/bin/python -m pytest -q -m "$(FAST_MARKERS)" -n $(TEST_WORKERS) --dist loadfile $(PYTEST_ARGS); rc=$$?; \
	echo "make test-fast: test suite ran in $$(( $$(date +%s) - start )) s (pytest exit code $$rc)"; exit $$rc

# The long reproductions at paper scale (marked slow; LEMUR's full climb among them).
test-slow: $(STAMP) chromium
	$(VENV)/bin/python -m pytest -q -m slow -n $(TEST_WORKERS) --dist loadfile $(PYTEST_ARGS)

bench: $(STAMP)
	$(VENV)/bin/python -m climb_ompl.bench.all --out-dir out/bench

# Which OMPL planner for climbing (docs/planners.md): every planner x constrained space x sampler on the
# versioned query sets, each run in a child process (reused, replaced on a crash or a hard timeout), through a
# Dask LocalCluster of COMPARE_WORKERS processes
# (or a running scheduler: COMPARE_SCHEDULER=tcp://HOST:PORT).  Resumable: runs already in
# $(COMPARE_OUT)/grid.db are skipped.  Then the page, its figures and a compacted copy of the database, and
# notebooks 02 and 03 executed in place (committed with their outputs; the playback HTML goes to $(COMPARE_OUT)).
# COMPARE_ARGS passes options of `climb-ompl bench compare` (e.g. --sample 40 --per-set 2 --seed 1).
COMPARE_WORKERS ?= 2
COMPARE_OUT ?= out/compare
COMPARE_ARGS ?=
compare: $(STAMP)
	$(VENV)/bin/climb-ompl bench compare --out $(COMPARE_OUT) --workers $(COMPARE_WORKERS) \
	  $(if $(COMPARE_SCHEDULER),--scheduler $(COMPARE_SCHEDULER)) $(COMPARE_ARGS)
	$(VENV)/bin/climb-ompl bench planners-doc $(COMPARE_OUT)/grid.db --out docs/planners.md --copy-db docs/planners.db
	mkdir -p $(COMPARE_OUT)/notebooks
	NB_OUT=$(abspath $(COMPARE_OUT))/notebooks $(VENV)/bin/jupyter execute --inplace --timeout=3600 \
	  notebooks/02_one_step_planners.ipynb notebooks/03_climb.ipynb

# Robots x terrains (docs/bench.md, "Climb suite"): each cell a verified climb or a diagnosed infeasibility, 180 s per
# cell, SUITE_WORKERS cells at once, each in its own process.  Resumable: cells already in $(SUITE_OUT)/cells are
# skipped (SUITE_ARGS=--fresh runs them again).
SUITE_WORKERS ?= 2
SUITE_OUT ?= out/suite
SUITE_ARGS ?=
suite: $(STAMP)
	$(VENV)/bin/climb-ompl bench suite --out $(SUITE_OUT) --workers $(SUITE_WORKERS) $(SUITE_ARGS)

# docs/results.md, and the README's figures table copied from it, from the JSON files `make bench` writes into
# out/bench and `make suite` into $(SUITE_OUT): one headline figure per row with the command that produced it and the
# ratio to the baseline measured in the same run; a benchmark not run reads "not measured".
results: $(STAMP)
	$(VENV)/bin/climb-ompl bench results --bench-dir out/bench --suite-dir $(SUITE_OUT) --out docs/results.md \
	  --readme README.md

# docs/papers.md from its template (docs/papers.md.in) and the benchmarks' JSON in out/bench: papers.json and
# treebot.json (`make bench`) and fig16/CASE-SEED.json (`climb-ompl bench fig16 --case CASE --seed SEED --out
# out/bench/fig16/CASE-SEED.json`; LEMUR's five seeds take up to 10 minutes each), gathered into docs/papers.json.
papers: $(STAMP)
	$(VENV)/bin/climb-ompl bench papers-doc --bench-dir out/bench --evidence docs/papers.json --out docs/papers.md

lint: $(STAMP)
	$(VENV)/bin/ruff check climb_ompl tests

clean:
	rm -rf $(VENV) out build dist
