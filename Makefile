# Two commands do all the set-up on a fresh machine: `make run` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
# Two stamps: `make run` installs only what the pendant needs; `make test` (and the tools) add the test extras.
RUN_STAMP := $(VENV)/.installed-run
STAMP := $(VENV)/.installed
# Rozum's official SDK pins urllib3==1.24.2, which clashes with the test tools; it lives in its own venv
# and the SDK tests run scripts there, as a user's script would run.
SDK_VENV := .venv-sdk
SDK_STAMP := $(SDK_VENV)/.installed
# Python keeps the bytecode of what it imports (the venvs install with --no-compile): the suite starts a
# hundred Python processes, each of which would otherwise compile its imports again (2.7x the import time).
unexport PYTHONDONTWRITEBYTECODE

.PHONY: run test typecheck layers lint format bench models fleet clean

# --no-compile: Python compiles what is imported when it is first imported, not all of every package up front.
$(RUN_STAMP): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	@$(BIN)/python -m pip install -q --disable-pip-version-check --no-compile -e .
	@touch $(RUN_STAMP)

# The test extras include everything `make run` needs, so its stamp is touched too.
$(STAMP): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	@$(BIN)/python -m pip install -q --disable-pip-version-check --no-compile -e '.[test]'
	@touch $(STAMP) $(RUN_STAMP)

$(SDK_STAMP):
	@test -x $(SDK_VENV)/bin/python || $(PYTHON) -m venv $(SDK_VENV)
	@$(SDK_VENV)/bin/python -m pip install -q --disable-pip-version-check --no-compile "pulse-api==1.5.0" "pdhttp==1.5.0"
	@touch $(SDK_STAMP)

# `make run FOXGLOVE=8765`: also the live view for Foxglove on that port (the banner prints its URL).
run: $(RUN_STAMP)
	@$(BIN)/pendant $(if $(FOXGLOVE),--foxglove-port $(FOXGLOVE)) $(ARGS)

# The suite (scripts/test_passes.sh says why), in two phases: the tests that time what a user feels on a
# real clock (`measures`: jog shares, stop times) and the `alone` ones, one at a time at normal priority,
# with every test outside tests/browser on three workers (--dist worksteal), ruff, the import layers and
# mypy beside them in the idle scheduling class (they get only the CPU the timed tests leave); then the other
# browser tests on two workers, a module per worker (it shares a Chromium and its pendants,
# tests/browser/conftest.py).
# A browser test that fails is run once more (pytest-rerunfailures; R in the output): some fail now and then
# in a full run and pass alone (docs/development.md lists them).
test: $(STAMP) $(SDK_STAMP)
	@BIN=$(BIN) PYTEST_ARGS="$(PYTEST_ARGS)" bash scripts/test_passes.sh

# N simulated pendants + Prometheus + Alertmanager on loopback with deploy/'s files; Ctrl-C stops all.
N ?= 3
fleet: $(RUN_STAMP)
	@$(BIN)/python -m pendant.monitoring.fleet --pendants $(N)

# The import layers and the no-circle rule (pyproject.toml's [tool.importlinter]), then the types.
layers: $(STAMP)
	@$(BIN)/lint-imports

typecheck: $(STAMP)
	@$(BIN)/mypy

lint: $(STAMP)
	@$(BIN)/ruff check . && $(BIN)/ruff format --check .

format: $(STAMP)
	@$(BIN)/ruff format . && $(BIN)/ruff check --fix .

bench: $(STAMP)
	@for b in benchmarks/*.py; do echo "== $$b"; $(BIN)/python $$b || exit 1; done

models: $(RUN_STAMP)
	@$(BIN)/python scripts/build_models.py

clean:
	rm -rf $(VENV) $(SDK_VENV) build *.egg-info
