# Two commands do all the set-up on a fresh machine: `make demo` and `make test`.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
# Timings mean something only with one BLAS thread (2-core machines).
export OPENBLAS_NUM_THREADS ?= 1
export OMP_NUM_THREADS ?= 1
export MKL_NUM_THREADS ?= 1

.PHONY: demo test test-all docs stress bench wheel clean

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e ".[all]"
	touch $(STAMP)

demo: $(STAMP)
	$(BIN)/qpcontact demo
	$(BIN)/qpcontact simulate examples/scenes/drum.toml --out out/scenes/drum.h5
	$(BIN)/qpcontact plot out/scenes/drum.h5 --out out/scenes/drum
	$(BIN)/qpcontact compare --quick --out out/compare

test: $(STAMP)
	$(BIN)/python -m pytest -q -n 2

test-all: $(STAMP)
	$(BIN)/python -m pytest -q -n 2 -m ""

# The API reference from the docstrings (docs/api), warnings as errors; -E: a
# fresh read, so a page added under docs/ is listed.  `make test` builds it too.
docs: $(STAMP)
	$(BIN)/python -m sphinx -b html -W --keep-going -E -q docs/api out/docs/html
	@echo "API reference: out/docs/html/index.html"

# The full hard-case suite (docs/testing.md): about 10 000 problems, ~1 h on 2 cores.
stress: $(STAMP)
	$(BIN)/qpcontact stress --out out/stress

bench: $(STAMP)
	$(BIN)/python -m pip install --quiet -e ".[benchmark]"
	$(BIN)/python benchmarks/backends.py
	$(BIN)/python benchmarks/pivoting.py --plot docs/figures/pivoting.png
	$(BIN)/python benchmarks/drum.py
	$(BIN)/python benchmarks/penalty_mu.py --plot docs/figures/penalty_mu.png
	$(BIN)/python benchmarks/bvp.py --plot docs/figures/elastica.png
	$(BIN)/python benchmarks/multibody.py --plot docs/figures/multibody.png
	$(BIN)/python benchmarks/far_contact.py --problems 200
	$(BIN)/python benchmarks/frames.py
	$(BIN)/python benchmarks/scale.py --quick
	$(BIN)/python benchmarks/friction.py --skip-large
	$(BIN)/python benchmarks/backend_limits.py

# The wheel and sdist (dist/), built as a user would and installed into a fresh
# virtual environment with their dependencies from the index; the README's first
# example and a scene then run from it (tests/package/test_wheel.py).
wheel: $(STAMP)
	rm -rf dist
	$(BIN)/python -m build --outdir dist
	QPCONTACT_WHEEL_DIST=dist QPCONTACT_WHEEL_VENV=fresh $(BIN)/python -m pytest -q -m slow tests/package/test_wheel.py

clean:
	rm -rf $(VENV) build dist *.egg-info .pytest_cache
