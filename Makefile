# The two set-up commands the README promises (each creates .venv on first use):
#   make demo   the main job: theory vs DEM on the default case
#   make test   the whole test suite (what .ci/run calls)
VENV ?= .venv
STAMP := $(VENV)/.wallsim-installed
export NUMBA_CACHE_DIR ?= $(CURDIR)/.numba_cache

$(STAMP): pyproject.toml scripts/make_venv.sh
	./scripts/make_venv.sh $(VENV)
	@touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/wallsim theory --phi 34 --delta 24.7 --H 3.1 --gamma 16.7

test: $(STAMP)
	$(VENV)/bin/python -m pytest -q

.PHONY: demo test
