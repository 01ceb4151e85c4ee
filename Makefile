# `make run` (whole workflow on config/config.yaml, then the report and the archive),
# `make test` (ruff, snakefmt, pytest: the documentation site's strict build too), `make
# test-fast` (the unit tests only) and `make docs` (the site into site/). Each creates .venv with
# the system python3 and installs pinned deps.
# Snakemake loads the default workflow profile profiles/default/ by itself (all cores,
# keep-going, rerun-incomplete): `make run` passes no options. CORES=2 limits the cores.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
CORES ?=
SNAKEMAKE := $(BIN)/snakemake $(if $(CORES),--cores $(CORES))
# The documentation site (mkdocs.yml) into site/; --strict: any warning, a broken internal link
# or anchor included, fails the build; the build executes the tutorials (docs/tutorials/*.ipynb,
# about a minute; CRAQUELURE_DOCS_EXECUTE=0 skips that while editing pages). pytest's
# tests/test_docs.py runs the same build in `make test`. NO_MKDOCS_2_WARNING silences the
# theme's banner.
MKDOCS := NO_MKDOCS_2_WARNING=1 $(BIN)/mkdocs build --strict --quiet

.PHONY: install run test test-fast test-slurm lint bench docs reference clean-results publish \
	republish

$(BIN)/.installed: pyproject.toml requirements.lock
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -c requirements.lock -e '.[test]'
	touch $@

install: $(BIN)/.installed

run: install
	$(SNAKEMAKE)
	$(SNAKEMAKE) --report results/report.html
	$(SNAKEMAKE) archive

test: install
	$(BIN)/ruff check src tests workflow benchmarks docs
	$(BIN)/snakefmt --check Snakefile workflow/rules
	$(BIN)/pytest -q -m "not slurm"

docs: install
	$(MKDOCS)

# The unit tests, for a developer between edits: no end-to-end workflow (tests/workflow), no
# hard cases (tests/hard_cases), nothing marked slow (the long physics runs, the killed and
# signalled CLI runs, the documentation site's build: docs/performance.md lists them).
# `make test` stays the whole suite, slow tests included.
test-fast: install
	$(BIN)/pytest -q -m "not slow and not slurm" --ignore=tests/workflow --ignore=tests/hard_cases

# The CI config through the SLURM profile on a one-node cluster started on this machine
# (needs root: installs and starts Debian's slurmctld, slurmd and munge).
test-slurm: install
	.ci/slurm-cluster start
	$(BIN)/pytest -q -m slurm tests/workflow/test_slurm.py

lint: install
	$(BIN)/ruff check src tests workflow benchmarks docs
	$(BIN)/snakefmt --check Snakefile workflow/rules
	$(BIN)/snakemake --lint --configfile config/ci.yaml

bench: install
	$(BIN)/python benchmarks/neighbours.py

# The CI reference (tests/reference/ci/) that `make test` compares the CI run's summary.json
# files and verdicts with: regenerated from a fresh CI-profile run (several minutes) or from a
# finished one (RESULTS=workflow folder or its archive, e.g. the one `make test` leaves in
# results/archive/), with the CHANGELOG.md line saying why. Commit both with the change.
reference: install
	@test -n "$(REASON)" || { echo "usage: make reference REASON='why the numbers moved'" \
		"[RESULTS=<CI run folder or results/archive/craquelure-ci-<date>.tar.gz>]"; exit 2; }
	$(BIN)/python -m tests.reference.regenerate --reason "$(REASON)" \
		$(if $(RESULTS),--from $(RESULTS))

# Install a finished drying ensemble's archived result in results/published/$(NAME)/ (the
# compact tables, then the figures, summary and validation rows rebuilt from them, and the
# SHA-256 manifest `craquelure verify` checks); commit the folder. For the Table I ensemble:
#   make publish NAME=drying-table1 SCENE=table1_trace \
#       CONFIG="config/faithful.yaml config/table1_ensemble.yaml"
# and for its companions (any drying scene; a criterion run's folder, e.g. paper_speed_Ctrace):
#   make publish NAME=drying-l5-trace SCENE=paper_speed_Ctrace \
#       CONFIG="config/faithful.yaml config/l5_trace_ensemble.yaml"
PUBLISH := $(BIN)/python -c 'import sys; from craquelure.drying.published import publish; \
	publish(*[None if a == "-" else a for a in sys.argv[1:]])'
publish: install
	@test -n "$(NAME)" -a -n "$(SCENE)" -a -n "$(CONFIG)" || { echo "usage: make publish" \
		"NAME=drying-table1 SCENE=<drying scene> CONFIG='<config files>'"; exit 2; }
	$(SNAKEMAKE) results/drying/$(SCENE)/published --configfile $(CONFIG)
	$(PUBLISH) results/drying/$(SCENE)/published - results/published/$(NAME)
	$(SNAKEMAKE) published --forcerun drying_published
	$(PUBLISH) results/drying/$(SCENE)/published results/drying_published/$(NAME) \
		results/published/$(NAME)
	$(BIN)/craquelure verify results/published/$(NAME)

# Refresh an archived ensemble's rebuilt files (figures, summary, validation rows, manifest)
# from its committed tables, e.g. once a companion its provenance names is archived (the
# companions' overlays: config/table1_source_ensemble.yaml, l5_source_ensemble.yaml,
# l5_trace_ensemble.yaml): make republish NAME=drying-table1
republish: install
	@test -n "$(NAME)" || { echo "usage: make republish NAME=<archived ensemble>"; exit 2; }
	$(SNAKEMAKE) published --forcerun drying_published
	$(PUBLISH) results/published/$(NAME) results/drying_published/$(NAME) \
		results/published/$(NAME)
	$(BIN)/craquelure verify results/published/$(NAME)

clean-results:
	find results -mindepth 1 ! -name README.md ! -path 'results/published' ! -path 'results/published/*' -delete
	rm -rf .snakemake logs benchmarks/results
