# Two commands: `make run` (whole workflow on config/config.yaml) and `make test`.
# Both create .venv with the system python3 and install pinned dependencies themselves.
PYTHON ?= python3
VENV := .venv
BIN := $(VENV)/bin
CORES ?= all

.PHONY: install run test lint bench clean-results

$(BIN)/.installed: pyproject.toml requirements.lock
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install -q --upgrade pip
	$(BIN)/python -m pip install -q -c requirements.lock -e '.[test]'
	touch $@

install: $(BIN)/.installed

run: install
	$(BIN)/snakemake --cores $(CORES)
	$(BIN)/snakemake --cores 1 --report results/report.html

test: install
	$(BIN)/ruff check src tests workflow benchmarks
	$(BIN)/pytest -q

lint: install
	$(BIN)/ruff check src tests workflow benchmarks
	$(BIN)/snakemake --lint --configfile config/ci.yaml

bench: install
	$(BIN)/python benchmarks/neighbours.py

clean-results:
	rm -rf results/* .snakemake
