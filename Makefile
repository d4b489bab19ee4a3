# slicelab: `make demo` and `make test` work on a fresh machine with Python 3.11+ and make.
PYTHON ?= python3
VENV   := .venv
BIN    := $(VENV)/bin
PIP    := $(BIN)/python -m pip install --disable-pip-version-check -q
PYTEST_ARGS ?=

.PHONY: demo test data data-large figures bench clean

$(BIN)/python:
	$(PYTHON) -m venv $(VENV)

# After installing, and again whenever their sources change, the compiled kernels are built
# (about 40 s): ahead of time into an extension module where a C compiler is at hand, and into
# numba's disk cache in the user's cache folder, the fallback (slicelab.geometry.compiled). No
# run compiles them again. The install is editable, which builds no kernels (setup.py builds
# them into a wheel: `pip install .`).
PACKAGING := pyproject.toml setup.py build_support/backend.py
EXT     := _aot_kernels
KERNELS := slicelab/geometry/compiled.py $(shell grep -rl --include='*.py' "import njit" slicelab)
BUILD   := $(BIN)/python -c "from slicelab.geometry import compiled; print(compiled.build())"

$(VENV)/.installed: $(PACKAGING) | $(BIN)/python
	$(PIP) -e .
	touch $@

$(VENV)/.installed-dev: $(PACKAGING) | $(BIN)/python
	$(PIP) -e '.[dev]'
	touch $@ $(VENV)/.installed

$(VENV)/.kernels: $(KERNELS) $(VENV)/.installed
	$(BUILD)
	touch $@

data: $(VENV)/.installed $(VENV)/.kernels
	$(BIN)/python scripts/make_data.py

data-large: $(VENV)/.installed
	$(BIN)/python scripts/make_data.py --large

demo: data
	$(BIN)/python scripts/demo.py

test: $(VENV)/.installed-dev $(VENV)/.kernels
	$(BIN)/python scripts/make_data.py
	$(BIN)/python -m pytest -n auto --nbmake tests notebooks slicelab $(PYTEST_ARGS)

figures: data
	$(BIN)/python scripts/figures.py

# The documentation site: API pages from the docstrings, the guides, the notebooks executed by
# myst-nb, warnings as errors (docs/conf.py). Output in docs/_build/html; nothing else is written
# outside git-ignored paths.
.PHONY: docs

$(VENV)/.installed-docs: $(PACKAGING) | $(BIN)/python
	$(PIP) -e '.[docs]'
	touch $@ $(VENV)/.installed

docs: $(VENV)/.installed-docs $(VENV)/.kernels
	$(BIN)/python -m sphinx -W --keep-going -j auto -b html docs docs/_build/html

bench: data-large $(VENV)/.installed-dev $(VENV)/.kernels
	for s in scripts/bench_*.py; do $(BIN)/python $$s || exit 1; done

clean:
	rm -rf $(VENV) build results .pytest_cache slicelab/geometry/$(EXT)*
