# The README's commands: `make sim` (run the simulated observatory) and `make test` (set up + whole suite).
VENV ?= .venv
PY := $(VENV)/bin/python
STAMP := $(VENV)/.installed
# Debian packages of the real components the tests use (XMPP servers, plate solver, INDI simulators,
# browser, SSH and SMB servers; iproute2 for the private network namespaces of servers that listen on
# every interface and of the multi-host tests).
SYSTEM_PACKAGES := prosody ejabberd astrometry.net astrometry-data-tycho2 iproute2 indi-bin chromium \
	openssh-server samba nodejs
# Node for the generated JavaScript client's test; Debian ships npm apart from nodejs (NodeSource's
# nodejs includes it and conflicts with Debian's npm), so npm is asked for only when missing.
SYSTEM_PACKAGES += $(if $(shell command -v npm),,npm)
# The JavaScript client's npm packages, exactly as clients/js/package-lock.json pins them.
JS_STAMP := clients/js/node_modules/.installed

.PHONY: setup system-deps sky-deps js-deps catalogue lint test sim example bench bench-ekos clean

$(STAMP): pyproject.toml
	python3 -m venv $(VENV)
	$(PY) -m pip install --quiet --upgrade pip
	$(PY) -m pip install --quiet -e '.[dev]'
	touch $(STAMP)

setup: $(STAMP)

# PostgreSQL for the image archive's tests and bench (a private cluster: nightcrew.testing.postgres).
SYSTEM_PACKAGES += postgresql

# Real components the tests use (XMPP servers, plate solver); installs only what is missing.
system-deps:
	bash scripts/install-system-deps.sh $(SYSTEM_PACKAGES)

$(JS_STAMP): clients/js/package-lock.json clients/js/package.json
	cd clients/js && npm ci --no-audit --no-fund
	touch $(JS_STAMP)

js-deps: system-deps $(JS_STAMP)

# The catalogue and the JavaScript client generated from it (CI checks both are current).
catalogue: setup
	$(VENV)/bin/nightcrew catalogue --output docs/catalogue.json
	$(VENV)/bin/nightcrew catalogue --js clients/js/generated

lint: setup
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .
	$(VENV)/bin/mypy
	$(VENV)/bin/lint-imports

# The 25 slowest tests are listed at the end: the suite must stay under 30 minutes on 2 cores.
test: setup system-deps js-deps lint
	$(PY) -m pytest -q --durations=25

# What the simulated sky is made of besides the PyPI catalogs: the Tycho-2 stars of astrometry.net's
# index, and build-astrometry-index for the sky's own index files (nightcrew.sim.sky_index). Without
# them the sim stops with an error naming the package, never a thinner sky.
SKY_PACKAGES := astrometry.net astrometry-data-tycho2

sky-deps:
	bash scripts/install-system-deps.sh $(SKY_PACKAGES)

# The simulated observatory through a whole robotic night on virtual time (a minute or two); frames and
# report.html go to sim-output/. The first run also builds the sky's index files for the night's fields
# (about a minute, kept in ~/.cache/nightcrew/indexes).
sim: setup sky-deps
	$(VENV)/bin/nightcrew sim --out sim-output

example: setup
	$(VENV)/bin/nightcrew run examples/standalone.yaml

# Every benchmark that needs no options; bench/rpc.py starts its own Prosody (system-deps) and
# compares with pyobs-core only when given --pyobs-venv PATH; bench/console.py drives Debian's chromium
# (system-deps) for 0.5 min of events by default (--minutes 5 for the issue's run); bench/archive.py
# starts its own PostgreSQL (system-deps) and takes a few minutes (100,000 header rows per database).
bench: setup
	$(PY) bench/local_rpc.py
	$(PY) bench/render.py
	$(PY) bench/rpc.py
	$(PY) bench/console.py
	$(PY) bench/archive.py

# KStars/Ekos against nightcrew's IndiServer under Xvfb and a private D-Bus session (bench/ekos.py);
# these packages are the bench's only, not the test suite's (tests/indi/test_ekos_properties.py
# checks with indi-bin what Ekos asked for here).
EKOS_PACKAGES := kstars xvfb xauth dbus-daemon libglib2.0-bin
bench-ekos: setup
	bash scripts/install-system-deps.sh $(EKOS_PACKAGES)
	$(PY) bench/ekos.py

clean:
	rm -rf $(VENV) build src/*.egg-info .pytest_cache .mypy_cache .ruff_cache clients/js/node_modules
