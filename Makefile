# The two commands of the README: `make demo` and `make test`. Both set everything up first.
VENV := .venv
STAMP := $(VENV)/.installed

.PHONY: setup demo test lint
setup: $(STAMP)

$(STAMP): pyproject.toml scripts/setup.sh
	bash scripts/setup.sh

demo: $(STAMP)
	$(VENV)/bin/pinn-mesh example_data/wavy.vtp --aux example_data/wavy_aux.vtp \
		-o out/wavy_pinn.vts --png out/wavy_pinn.png

test: $(STAMP)
	$(VENV)/bin/ruff check pinn_engine plugin tests examples benchmarks experiments scripts example_data
	$(VENV)/bin/ruff format --check pinn_engine plugin tests examples benchmarks experiments scripts example_data
	$(VENV)/bin/python -m pytest
