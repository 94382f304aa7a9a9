"""Run the paper's section 4 experiments; same as ``python -m pinn_engine.experiments``.

    .venv/bin/python scripts/run_experiments.py --mode full
"""

from __future__ import annotations

import sys

from pinn_engine.experiments import main

if __name__ == "__main__":
    sys.exit(main())
