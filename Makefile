# The README's two commands: `make demo` (install + LEMUR climb with playback) and `make test`
# (install + the whole test suite).  Both create their own virtual environment in .venv and install
# the exact versions of requirements.lock (the lock that passed CI), then the package itself.
PYTHON ?= python3
VENV   ?= .venv
PY     := $(VENV)/bin/python
STAMP  := $(VENV)/.installed

.PHONY: demo test bench lint install chromium clean

$(STAMP): pyproject.toml requirements.lock
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install -q --upgrade pip
	$(PY) -m pip install -q -r requirements.lock
	$(PY) -m pip install -q --no-deps --no-build-isolation -e .
	touch $(STAMP)

install: $(STAMP)

# Debian's chromium for the playback browser tests (Playwright cannot download its own browser here).
chromium:
	@command -v chromium >/dev/null 2>&1 || { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq chromium >/dev/null; }

demo: $(STAMP)
	$(VENV)/bin/climb-ompl demo --out-dir out

test: $(STAMP) chromium
	$(VENV)/bin/ruff check climb_ompl tests
	$(VENV)/bin/python -m pytest -q -m "not slow"

bench: $(STAMP)
	$(VENV)/bin/python -m climb_ompl.benchmarks.all --out-dir out/bench

lint: $(STAMP)
	$(VENV)/bin/ruff check climb_ompl tests

clean:
	rm -rf $(VENV) out build dist
