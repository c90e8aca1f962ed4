# catwalk: the two commands are `make demo` and `make test`; both install what they need.
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
CATWALK := $(VENV)/bin/catwalk
STAMP := $(VENV)/.installed
NODE_STAMP := tools/node/node_modules/.installed
FS_STAMP := garments/freesewing/node_modules/.installed
PYTEST_ARGS ?=
DEMO_GARMENT ?= dress

.PHONY: install demo test lint bodies clean services

install: $(STAMP) $(NODE_STAMP) $(FS_STAMP)
	$(CATWALK) assets

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip==26.3
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $@

$(NODE_STAMP): tools/node/package.json tools/node/package-lock.json
	cd tools/node && npm ci --no-audit --no-fund --loglevel=error
	touch $@

$(FS_STAMP): garments/freesewing/package.json garments/freesewing/package-lock.json
	cd garments/freesewing && npm ci --no-audit --no-fund --loglevel=error
	touch $@

demo: install
	$(CATWALK) demo --garment $(DEMO_GARMENT) --size M --seconds 4 --out-dir demo

lint: $(STAMP)
	$(VENV)/bin/ruff check backend tests

services:
	tools/services/ensure.sh

test: install lint services
	$(VENV)/bin/pytest -q $(PYTEST_ARGS)

bodies: install
	$(CATWALK) bodies build

clean:
	rm -rf $(VENV) tools/node/node_modules garments/freesewing/node_modules demo
