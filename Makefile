# Two entry points for a fresh machine with Python 3.11 and make:
#   make reproduce   set up .venv, install, regenerate the paper's results into out/
#   make test        set up .venv, install, run the whole test suite
# and, with the same set-up:
#   make docs        the documentation (Sphinx, warnings as errors) into out/docs/index.html
#   make wheel-check build the wheel, install it in a clean virtual environment, run it there
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
DOCS_STAMP := $(VENV)/.installed-docs

.PHONY: reproduce test test-quick bench docs wheel-check clean

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

$(STAMP): $(PY) pyproject.toml
	$(PY) -m pip install --quiet -e ".[test]"
	touch $(STAMP)

$(DOCS_STAMP): $(PY) pyproject.toml
	$(PY) -m pip install --quiet -e ".[docs]"
	touch $(DOCS_STAMP)

reproduce: $(STAMP)
	$(VENV)/bin/hosedrogue reproduce --out out/report

# -n auto: one pytest worker per core (pytest-xdist); they share numba's disk cache, and a function
# one worker is compiling the other waits for and loads (hosedrogue.jit.CompileOnceCache)
test: $(STAMP)
	$(PY) -m pytest -q -n auto

# the daily loop: everything but what is slow for reasons other than physics (docs/develop.md, "Tests")
test-quick: $(STAMP)
	$(PY) -m pytest -q -n auto -m "not e2e and not dask and not browser and not packaging and not fmu and not subprocess"

bench: $(STAMP)
	$(PY) benchmarks/realtime.py

# -W: a warning is an error; the API pages are generated into docs/api/ (not kept in git)
docs: $(DOCS_STAMP)
	rm -rf docs/api out/docs
	$(PY) -m sphinx -W --keep-going -q -b html -d out/docs-doctrees docs out/docs
	@echo "wrote out/docs/index.html"

# The wheel in a clean virtual environment (dependencies from pip's cache or the index, ~700 MB,
# a couple of minutes): the shipped scenarios and presets must come with it.
WHEEL_DIR := out/wheel-check
wheel-check: $(STAMP)
	rm -rf $(WHEEL_DIR)
	$(PY) -m build --wheel --outdir $(WHEEL_DIR)/dist .
	$(PYTHON) -m venv $(WHEEL_DIR)/venv
	$(WHEEL_DIR)/venv/bin/python -m pip install --quiet $(WHEEL_DIR)/dist/hosedrogue-*.whl
	cd $(WHEEL_DIR) && venv/bin/hosedrogue steady
	cd $(WHEEL_DIR) && venv/bin/hosedrogue simulate swing-release --out simulate
	cd $(WHEEL_DIR) && venv/bin/python -c "from importlib.resources import files; \
	    names = sorted(p.name for d in ('scenarios', 'spec/presets') if files('hosedrogue').joinpath(d).is_dir() \
	                   for p in files('hosedrogue').joinpath(d).iterdir() if p.name.endswith('.toml')); \
	    print('package data:', ', '.join(names))"
	@echo "wheel-check passed"

clean:
	rm -rf out build dist src/*.egg-info .pytest_cache docs/api
