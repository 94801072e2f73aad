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

# Mutation testing of the numeric core (docs/mutation.md); not part of `make test` or CI. In groups
# (MUTATE=core, view, sun, scene, daylight or glare; docs/mutation.md has each group's time; the whole
# set, MUTATE=all, takes several hours on 2 cores). A group's run keeps the other groups' results
# (mutants/); MUTATE=all starts afresh. CHANGED=1 mutates only the modules of the selection that
# changed since the commit of docs/mutation.md's table (scripts/mutation_report.py --changed), so a
# change to a numeric module comes with its row re-measured. pvlib (the independent SPA of
# tests/test_mutants_spa.py) comes with the test extra.
MUTATION_JOBS ?= $(shell nproc 2>/dev/null || echo 2)
MUTATE ?= all
MUTANTS_core := en17037cli.criteria.sunlight.solar_position.* en17037cli.criteria.sunlight.intervals.* \
  en17037cli.criteria.sunlight.visibility.* en17037cli.criteria.sunlight.point_p.* \
  en17037cli.criteria.sunlight.member_at_p.* en17037cli.standard.* en17037cli.bisection.* \
  en17037cli.criteria.view.sight_angle.* en17037cli.criteria.view.distance.* en17037cli.criteria.view.plan.* \
  en17037cli.criteria.view.wedge.*
MUTANTS_view := en17037cli.criteria.view.solid_angle.* en17037cli.criteria.view.decide.* \
  en17037cli.criteria.view.clip.* en17037cli.criteria.view.cells.* en17037cli.criteria.view.refine.* \
  en17037cli.criteria.view.edges.* en17037cli.criteria.view.sampler.* en17037cli.criteria.view.gnomonic.* \
  en17037cli.geometry.solid_angle.* en17037cli.geometry.planar.*
MUTANTS_sun := en17037cli.criteria.sunlight.exact.* en17037cli.criteria.sunlight.culling.*
MUTANTS_scene := en17037cli.scene.spaces.* en17037cli.scene.hosts.* en17037cli.scene.section.* \
  en17037cli.scene.rooms.* en17037cli.scene.auto_rooms.* en17037cli.scene.levels.* en17037cli.scene.openings.* \
  en17037cli.scene.quarantine.* en17037cli.io.ifc_glazing.* en17037cli.io.citygml.crs.*
MUTANTS_daylight := en17037cli.criteria.daylight.*
MUTANTS_glare := en17037cli.criteria.glare.*
mutation: $(STAMP)
	$(PY) -m pip install --quiet 'mutmut>=3.2,<4'
	@case "$(MUTATE)" in all|core|view|sun|scene|daylight|glare) ;; \
	  *) echo "MUTATE=$(MUTATE): one of all, core, view, sun, scene, daylight, glare"; exit 2;; esac
	$(if $(CHANGED),@true,$(if $(filter all,$(MUTATE)),rm -rf mutants,@true))
	@names="$(if $(CHANGED),$$($(PY) scripts/mutation_report.py --changed),$(if $(filter all,$(MUTATE)),,$(foreach m,$(MUTANTS_$(MUTATE)),'$(m)')))"; \
	  if [ -n "$(CHANGED)" ] && [ -z "$$names" ]; then echo "no module of the selection changed since the table's commit"; exit 0; fi; \
	  log=mutation-run-$(if $(CHANGED),changed,$(MUTATE)).log; start=$$(date +%s); \
	  echo "mutmut run --max-children $(MUTATION_JOBS) $$names"; \
	  eval "$(VENV)/bin/mutmut run --max-children $(MUTATION_JOBS) $$names" > $$log 2>&1; code=$$?; \
	  echo "mutmut run: exit $$code, $$(( ($$(date +%s) - start) / 60 )) min on $(MUTATION_JOBS) jobs (log: $$log)"
	$(PY) scripts/mutation_report.py --no-diff

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
