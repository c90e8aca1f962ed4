# catwalk: the two commands are `make demo` and `make test`; both install what they need.
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
CATWALK := $(VENV)/bin/catwalk
STAMP := $(VENV)/.installed
NODE_STAMP := tools/node/node_modules/.installed
FS_STAMP := garments/freesewing/node_modules/.installed
FRONT_STAMP := frontend/node_modules/.installed
FRONT_DIST := frontend/dist/index.html
FRONT_SRC := $(shell find frontend -path frontend/node_modules -prune -o -path frontend/dist -prune -o -type f -print)
PYTEST_ARGS ?=
DEMO_GARMENT ?= dress

.PHONY: install demo test lint bodies clean services browser fuzz

install: $(STAMP) $(NODE_STAMP) $(FS_STAMP) $(FRONT_DIST)
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

$(FRONT_STAMP): frontend/package.json frontend/package-lock.json
	cd frontend && npm ci --no-audit --no-fund --loglevel=error
	touch $@

# the pages `catwalk serve` serves at /
$(FRONT_DIST): $(FRONT_STAMP) $(FRONT_SRC)
	cd frontend && npm run build --silent

demo: install
	$(CATWALK) demo --garment $(DEMO_GARMENT) --size M --seconds 4 --out-dir demo

lint: $(STAMP)
	$(VENV)/bin/ruff check backend tests tools
	$(VENV)/bin/lint-imports --no-cache

services:
	tools/services/ensure.sh

browser:
	tools/services/browser.sh

test: install lint services browser
	cd frontend && npm test --silent
	$(VENV)/bin/pytest -q $(PYTEST_ARGS)

# the fuzzers deeper than `make test` runs them: FUZZ_EXAMPLES inputs per file reader
# (tests/fuzz), FUZZ_API_EXAMPLES examples per API operation (schemathesis,
# tests/service/test_schema_fuzz.py; each a request to the running service)
FUZZ_EXAMPLES ?= 10000
FUZZ_API_EXAMPLES ?= 1000
fuzz: install services
	CATWALK_FUZZ_EXAMPLES=$(FUZZ_EXAMPLES) CATWALK_FUZZ_API_EXAMPLES=$(FUZZ_API_EXAMPLES) \
		$(VENV)/bin/pytest -q -s tests/fuzz tests/service/test_schema_fuzz.py

bodies: install
	$(CATWALK) bodies build

clean:
	rm -rf $(VENV) tools/node/node_modules garments/freesewing/node_modules demo \
		frontend/node_modules frontend/dist
