# The two commands of the README, plus benchmarks. Each creates .venv when missing and
# (re)installs zmpkit into it whenever pyproject.toml changed.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
OUT    ?= out/demo
# Locally `make test` skips the slow simulation tests (its budget: 4 min on a fresh 2-core
# machine, install included); CI (CI=true) runs them too, as they fit its time, and then the
# fast tests again on the lowest dependency versions pyproject.toml allows (.ci/lowest).
PYTEST_MARK := $(if $(CI),,-m "not slow")
# One pytest worker a core (pytest-xdist); a test file stays on one worker, so its
# module-scoped fixtures (a balance run, a recorded walk) are made once. The slowest
# tests are listed at the end of each run.
PYTEST_ARGS := -n auto --dist loadfile --durations=15
COMMA := ,
TEST_EXTRAS := $(if $(CI),test$(COMMA)ray,test)
# Some machines set PYTHONDONTWRITEBYTECODE; the tests' subprocesses and pytest's rewritten
# test modules then compile from source every time. The project's own commands may cache.
unexport PYTHONDONTWRITEBYTECODE

.PHONY: demo test test-slow test-lowest bench lint format clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e .
	touch $@

# The tests install qibullet without its dependencies: a test reads NAO's URDF out of it
# (never imports it, so pybullet is not needed). CI also installs Ray (about 18 s here), so
# the cluster backend is exercised live on a local instance (locally those tests skip, saying
# so, unless Ray is installed), and PAL's TALOS (URDF and meshes, 131 MB: example-robot-data
# without its dependencies, none of which a test imports) for a slow test of an unseen robot.
$(VENV)/.installed-test: pyproject.toml | $(BIN)/python
	$(BIN)/python -m pip install --quiet -e '.[$(TEST_EXTRAS)]'
	$(BIN)/python -m pip install --quiet --no-deps 'qibullet==1.4.6'
	$(if $(CI),$(BIN)/python -m pip install --quiet --no-deps 'example-robot-data==6.0.0')
	touch $@ $(VENV)/.installed

demo: $(VENV)/.installed
	$(BIN)/zmpkit demo --out $(OUT)

test: $(VENV)/.installed-test
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/lint-imports
	$(BIN)/mypy
	$(BIN)/python -m pytest $(PYTEST_MARK) $(PYTEST_ARGS) -q
	$(if $(CI),.ci/lowest,@echo "dependency lower bounds: checked in CI (make test-lowest)")

test-slow: $(VENV)/.installed-test
	$(BIN)/python -m pytest -m slow $(PYTEST_ARGS) -q

# The dependency lower bounds are true: the lowest allowed versions pass the fast tests.
test-lowest:
	.ci/lowest

bench: $(VENV)/.installed-test
	@for b in benchmarks/bench_*.py; do echo "== $$b"; $(BIN)/python $$b || exit 1; done

lint: $(VENV)/.installed-test
	$(BIN)/ruff check .
	$(BIN)/lint-imports
	$(BIN)/mypy

format: $(VENV)/.installed-test
	$(BIN)/ruff format .

clean:
	rm -rf $(VENV) .venv-lowest out .pytest_cache .ruff_cache .hypothesis
