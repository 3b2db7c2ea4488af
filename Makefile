# Two commands do all the set-up on a fresh machine: `make run` and `make test`.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
STAMP := $(VENV)/.installed
# Rozum's official SDK pins urllib3==1.24.2, which clashes with the test tools; it lives in its own venv
# and the SDK tests run scripts there, as a user's script would run.
SDK_VENV := .venv-sdk
SDK_STAMP := $(SDK_VENV)/.installed

.PHONY: run test typecheck layers lint format bench models fleet clean

# --no-compile: Python compiles what is imported when it is first imported, not all of every package up front.
$(STAMP): pyproject.toml
	@test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	@$(BIN)/python -m pip install -q --disable-pip-version-check --no-compile -e '.[test]'
	@touch $(STAMP)

$(SDK_STAMP):
	@test -x $(SDK_VENV)/bin/python || $(PYTHON) -m venv $(SDK_VENV)
	@$(SDK_VENV)/bin/python -m pip install -q --disable-pip-version-check --no-compile "pulse-api==1.5.0" "pdhttp==1.5.0"
	@touch $(SDK_STAMP)

run: $(STAMP)
	@$(BIN)/pendant $(ARGS)

# Two workers (a 2-core machine) for every test but those marked `measures` (jog shares, stop times: what
# a user feels on a real clock), which run after, alone; each pass prints its count. Not `--dist loadgroup`:
# it keys tests by node id, and test_fuzz's 53 schemathesis cases share one, so it ran one of them.
test: $(STAMP) $(SDK_STAMP) layers typecheck
	@$(BIN)/pytest -q -n 2 -m "not measures" $(PYTEST_ARGS); a=$$?; [ $$a -eq 5 ] && a=0; \
	$(BIN)/pytest -q -m measures $(PYTEST_ARGS); b=$$?; [ $$b -eq 5 ] && b=0; \
	[ $$a -eq 0 ] && [ $$b -eq 0 ]

# N simulated pendants + Prometheus + Alertmanager on loopback with deploy/'s files; Ctrl-C stops all.
N ?= 3
fleet: $(STAMP)
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

models: $(STAMP)
	@$(BIN)/python scripts/build_models.py

clean:
	rm -rf $(VENV) $(SDK_VENV) build *.egg-info
