# The two set-up commands of the README: `make demo` and `make test`.
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed

.PHONY: demo test lint bench goals profile install samples clean mutation bim-corpus

$(STAMP): pyproject.toml
	$(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[test]'
	touch $(STAMP)

install: $(STAMP)

samples: $(STAMP)
	$(PY) scripts/make_synthetic_project.py sample_projects/synthetic-street
	$(PY) scripts/make_synthetic_weather.py sample_projects/seed-office/weather/delft-synthetic.epw --lat 52.0116 --lon 4.3571

demo: $(STAMP) samples
	$(VENV)/bin/en17037 check sample_projects/seed-office/project.yaml --out out/seed-office; \
	  code=$$?; echo "report: $(CURDIR)/out/seed-office/report.html (beside it report.md, report.json, the CSVs and figures/), exit code $$code"; \
	  test $$code -le 1

lint: $(STAMP)
	$(VENV)/bin/ruff check en17037cli tests scripts benchmarks
	$(VENV)/bin/mypy

test: lint
	$(PY) -m pytest

# Mutation testing of the numeric core (docs/mutation.md); not part of `make test` or CI. About
# an hour on 2 cores. pvlib (the independent SPA of tests/test_mutants_spa.py) comes with the test extra.
MUTATION_JOBS ?= $(shell nproc 2>/dev/null || echo 2)
mutation: $(STAMP)
	$(PY) -m pip install --quiet 'mutmut>=3.2,<4'
	rm -rf mutants
	@start=$$(date +%s); \
	  $(VENV)/bin/mutmut run --max-children $(MUTATION_JOBS) > mutation-run.log 2>&1; code=$$?; \
	  echo "mutmut run: exit $$code, $$(( ($$(date +%s) - start) / 60 )) min on $(MUTATION_JOBS) jobs (log: mutation-run.log)"
	$(PY) scripts/mutation_report.py

# The README's table of real exports (docs/bim.md): every IFC, gbXML, CityGML and CityJSON file of
# ../shared/data/real-models checked as a user would; BIM_CORPUS=<files or folders> for others.
BIM_CORPUS ?= ../shared/data/real-models
bim-corpus: $(STAMP)
	$(PY) scripts/bim_corpus.py $(BIM_CORPUS) --out out/bim-corpus

bench: $(STAMP) samples
	$(PY) benchmarks/bench.py --out bench.json

# The speed goals of issue 38 alone (part of `make bench`): docs/performance.md.
goals: $(STAMP)
	$(PY) benchmarks/goals.py

# The top functions (cProfile, CPU clock, one ray-tracing thread) of the seed office's check
# without its daylight section and of the paper's grid: docs/performance.md.
profile: $(STAMP)
	$(PY) benchmarks/profiling.py

clean:
	rm -rf $(VENV) out .pytest_cache .hypothesis .mypy_cache .ruff_cache mutants mutation-run.log
