"""``python -m pinn_engine.experiments``: see :mod:`pinn_engine.experiments`."""

from pinn_engine.experiments import main

raise SystemExit(main())
