"""The ``pinn-mesh`` command of one run (SPEC 5, 9, 10, 11).

``parser`` (the options and exit statuses), ``options`` (their values as settings),
``progress``, ``summary`` (the lines on stderr), ``outputs`` (the files written), one module
per domain kind's run (``four_sided``, ``hexa``, ``multiblock``), ``dispatch`` (which of
them) and ``entry`` (``main``: the exit status). The names below are imported on first use,
so that ``pinn-mesh batch`` parses its manifest's options without importing the engine.
"""

from pinn_engine.lazy import lazy_names

# each public name and the module that defines it
_PUBLIC = {
    "EXIT_ERROR": ".parser",
    "EXIT_INTERRUPTED": ".parser",
    "OneLineParser": ".parser",
    "build_parser": ".parser",
    "main": ".entry",
    "run": ".dispatch",
}

__all__ = sorted(_PUBLIC)
__getattr__, __dir__ = lazy_names(__name__, _PUBLIC)
