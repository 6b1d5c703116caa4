# Two entry points for a fresh machine with Python 3.11 and make:
#   make reproduce   set up .venv, install, regenerate the paper's results into out/
#   make test        set up .venv, install, run the whole test suite
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: reproduce test bench clean

$(PY):
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip

$(STAMP): $(PY) pyproject.toml
	$(PY) -m pip install --quiet -e ".[test]"
	touch $(STAMP)

reproduce: $(STAMP)
	$(VENV)/bin/hosedrogue reproduce --out out/report

test: $(STAMP)
	$(PY) -m pytest -q

bench: $(STAMP)
	$(PY) benchmarks/realtime.py

clean:
	rm -rf out build dist src/*.egg-info .pytest_cache
