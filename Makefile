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
DEMO_GARMENT ?= garments/dress.json

.PHONY: install demo test lint bodies clean

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
	mkdir -p demo
	$(CATWALK) body make --sex female --height 1.68 --bust 0.90 --waist 0.72 --hips 0.98 -o demo/body.glb
	$(CATWALK) tryon --body demo/body.glb --garment $(DEMO_GARMENT) --size M --seconds 4 \
		-o demo/tryon.glb --metrics demo/metrics.json
	$(CATWALK) render demo/tryon.glb --time 0.5 1.4 2.3 3.2 --view front side --size 360x540 \
		-o demo/tryon.png
	@echo "demo: wrote demo/tryon.glb (open it in any glTF viewer), demo/metrics.json and the preview demo/tryon.png"

lint: $(STAMP)
	$(VENV)/bin/ruff check backend tests

test: install lint
	$(VENV)/bin/pytest -q $(PYTEST_ARGS)

bodies: install
	$(CATWALK) bodies build

clean:
	rm -rf $(VENV) tools/node/node_modules garments/freesewing/node_modules demo
