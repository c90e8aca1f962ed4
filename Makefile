# catwalk: the two commands are `make demo` and `make test`; both install what they need.
SHELL := /bin/bash
PYTHON ?= python3
VENV := .venv
PY := $(VENV)/bin/python
CATWALK := $(VENV)/bin/catwalk
STAMP := $(VENV)/.installed
NODE_STAMP := tools/node/node_modules/.installed
PYTEST_ARGS ?=

.PHONY: install demo test lint bodies clean

install: $(STAMP) $(NODE_STAMP)
	$(CATWALK) assets

$(STAMP): pyproject.toml
	test -x $(PY) || $(PYTHON) -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip==26.3
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $@

$(NODE_STAMP): tools/node/package.json tools/node/package-lock.json
	cd tools/node && npm ci --no-audit --no-fund --loglevel=error
	touch $@

demo: install
	mkdir -p demo
	$(CATWALK) body make --sex female --height 1.68 --bust 0.90 --waist 0.72 --hips 0.98 -o demo/body.glb
	$(CATWALK) walk --body demo/body.glb --seconds 4 --style catwalk -o demo/walk.glb
	$(CATWALK) render demo/walk.glb --time 0.6 --view front -o demo/walk_front.png
	$(CATWALK) render demo/walk.glb --time 0.6 --view side -o demo/walk_side.png
	@echo "demo: wrote demo/walk.glb, demo/walk_front.png, demo/walk_side.png"

lint: $(STAMP)
	$(VENV)/bin/ruff check backend tests

test: install lint
	$(VENV)/bin/pytest -q $(PYTEST_ARGS)

bodies: install
	$(CATWALK) bodies build

clean:
	rm -rf $(VENV) tools/node/node_modules demo
