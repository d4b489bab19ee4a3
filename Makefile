# slicelab: `make demo` and `make test` work on a fresh machine with Python 3.11+ and make.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
PIP    := $(BIN)/python -m pip install --disable-pip-version-check -q
PYTEST_ARGS ?=

.PHONY: demo test data data-large figures bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

# After installing, the compiled kernels are built once (numba's disk cache, about 20 s), as an
# install would: no later run, test worker or pool process compiles them again.
WARM := $(BIN)/python -c "from slicelab.geometry import kernels; kernels.warm()"

$(VENV)/.installed: pyproject.toml | $(BIN)/python
	$(PIP) -e .
	$(WARM)
	touch $@

$(VENV)/.installed-dev: pyproject.toml | $(BIN)/python
	$(PIP) -e '.[dev]'
	$(WARM)
	touch $@ $(VENV)/.installed

data: $(VENV)/.installed
	$(BIN)/python scripts/make_data.py

data-large: $(VENV)/.installed
	$(BIN)/python scripts/make_data.py --large

demo: data
	$(BIN)/python scripts/demo.py

test: $(VENV)/.installed-dev
	$(BIN)/python scripts/make_data.py
	$(BIN)/python -m pytest -n auto --nbmake tests notebooks slicelab $(PYTEST_ARGS)

figures: data
	$(BIN)/python scripts/figures.py

bench: data-large $(VENV)/.installed-dev
	for s in scripts/bench_*.py; do $(BIN)/python $$s || exit 1; done

clean:
	rm -rf $(VENV) results .pytest_cache
