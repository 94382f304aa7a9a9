# The two commands of the README: `make demo` and `make test`. Both set everything up first.
# `make check` is the fast tier (lint and the tests not marked slow or paraview, stopping at
# the first failure; under 2 minutes on 2 cores); `make test` lints and runs every test.
VENV := .venv
STAMP := $(VENV)/.installed

.PHONY: setup demo lint check test
setup: $(STAMP)

$(STAMP): pyproject.toml setup.py pinn_engine/neural/jet/kernels.cpp pinn_engine/bodies/march.cpp \
		scripts/setup.sh
	bash scripts/setup.sh

demo: $(STAMP)
	$(VENV)/bin/pinn-mesh example_data/wavy.vtp --aux example_data/wavy_aux.vtp \
		-o out/wavy_pinn.vts --png out/wavy_pinn.png

# the whole repository; `ruff format` also checks the Python code blocks of the Markdown files
lint: $(STAMP)
	$(VENV)/bin/ruff check .
	$(VENV)/bin/ruff format --check .

# the tests run in two processes (pytest-xdist), one a core of the 2-core machines they are
# timed on; the ParaView GUI ones after them in one process (each drives a whole ParaView, and
# their bounds on how soon the GUI answers assume the cores are theirs)
JOBS := 2

check: lint
	$(VENV)/bin/python -m pytest -x -q -n $(JOBS) -m "not slow and not paraview"

test: lint
	$(VENV)/bin/python -m pytest -n $(JOBS) -m "not gui"
	$(VENV)/bin/python -m pytest -n $(JOBS) --dist loadfile -m gui; status=$$?; \
		[ $$status -eq 0 ] || [ $$status -eq 5 ]  # 5: no GUI test ran (no ParaView: they skip)
