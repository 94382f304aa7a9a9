"""``python -m pinn_engine.routes.cli ARGS``: the command of one run, as ``pinn-mesh ARGS``."""

import sys

from pinn_engine.routes.cli.entry import main

sys.exit(main())
