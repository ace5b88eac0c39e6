# softcath: the two set-up-free commands are `make demo` and `make test`.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
DOCS_STAMP := $(VENV)/.installed-docs
OUT ?= out/demo

.PHONY: demo test check bench lint docs clean

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/softcath demo --out $(OUT)

test: $(STAMP)
	$(PY) -m pytest -q --durations=25

check: $(STAMP)
	$(PY) -m pytest -q -m "not slow"

bench: $(STAMP)
	@for b in benchmarks/bench_*.py; do echo "== $$b"; $(PY) $$b || exit 1; done

lint: $(STAMP)
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .
	$(VENV)/bin/basedpyright
	$(PY) -m pytest -q tests/test_codebase_imports.py tests/test_codebase_size.py tests/test_codebase_api.py tests/test_codebase_signatures.py tests/test_codebase_cli.py

$(DOCS_STAMP): $(STAMP) pyproject.toml
	$(PY) -m pip install --quiet -e '.[dev,docs]'
	touch $(DOCS_STAMP)

# The Sphinx site in docs/_build/html; warnings are errors. The gallery runs examples/gallery/plot_*.py.
docs: $(DOCS_STAMP)
	MPLBACKEND=Agg $(VENV)/bin/sphinx-build -W --keep-going -b html docs docs/_build/html

clean:
	rm -rf $(VENV) out .pytest_cache docs/_build docs/auto_gallery docs/generated docs/sg_execution_times.rst
