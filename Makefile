# The two set-up commands the README promises (each creates .venv on first use):
#   make demo   the main job: theory vs 3D DEM on the default wall (a few minutes)
#   make test   the whole test suite (what .ci/run calls)
VENV ?= .venv
STAMP := $(VENV)/.wallsim-installed
export NUMBA_CACHE_DIR ?= $(CURDIR)/.numba_cache

$(STAMP): pyproject.toml scripts/make_venv.sh
	./scripts/make_venv.sh $(VENV)
	@touch $(STAMP)

demo: $(STAMP)
	$(VENV)/bin/wallsim compare nadukuru --mode T --wall rough --particles 3000

# the declared Python floor first (every tracked file compiles with it), then one pytest
# worker per core, a test file per worker at a time (module fixtures built once)
test: $(STAMP)
	./scripts/check_python_floor.sh
	$(VENV)/bin/python -m pytest -q -n auto --dist loadfile

.PHONY: demo test
