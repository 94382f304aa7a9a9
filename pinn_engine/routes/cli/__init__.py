"""The ``pinn-mesh`` command of one run (SPEC 5, 9, 10, 11).

``parser`` (the options), ``options`` (their values as settings), ``progress``, ``summary``
(the lines on stderr), ``outputs`` (the files written), one module per domain kind's run
(``four_sided``, ``hexa``, ``multiblock``), ``dispatch`` (which of them) and ``entry``
(``main``: the exit status)."""

from pinn_engine.routes.cli.dispatch import run
from pinn_engine.routes.cli.entry import EXIT_ERROR, EXIT_INTERRUPTED, main
from pinn_engine.routes.cli.parser import OneLineParser, build_parser

__all__ = [
    "EXIT_ERROR",
    "EXIT_INTERRUPTED",
    "OneLineParser",
    "build_parser",
    "main",
    "run",
]
