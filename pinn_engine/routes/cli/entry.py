"""``main``: one run of the command, its failures as one line and an exit status (SPEC 5)."""

from __future__ import annotations

import os
import signal
import sys
import warnings
from pathlib import Path

from pinn_engine import heap
from pinn_engine.errors import JetKernelsWarning, PinnMeshError
from pinn_engine.routes.cli.dispatch import run
from pinn_engine.routes.cli.parser import EXIT_ERROR, EXIT_INTERNAL, EXIT_INTERRUPTED, build_parser


def _raise_interrupt(signum, frame):  # noqa: ARG001
    raise KeyboardInterrupt


def _one_line_warning(message, category, filename, lineno, file=None, line=None):  # noqa: ARG001
    """A Python warning on the command line: its one line (it names pinn-mesh), on stderr."""
    text = str(message)
    print(text if text.startswith("pinn-mesh") else f"pinn-mesh: warning: {text}", file=sys.stderr)


def main(argv: list[str] | None = None) -> int:
    """Run the command; returns 0, 2 (error, one line on stderr) or 130 (interrupted).

    An unexpected internal failure prints one line and returns 3; set ``PINN_MESH_DEBUG=1``
    to see its traceback instead.
    """
    argv = sys.argv[1:] if argv is None else argv
    args = build_parser().parse_args(argv)
    heap.tune_process()  # this process is ours: glibc's heap tuned for training and meshing
    previous = signal.signal(signal.SIGTERM, _raise_interrupt)
    written: list[Path] = []
    try:
        with warnings.catch_warnings():
            warnings.showwarning = _one_line_warning
            if args.quiet:
                warnings.simplefilter("ignore", JetKernelsWarning)
            run(args, written)
    except PinnMeshError as exc:
        print(f"pinn-mesh: error: {exc}", file=sys.stderr)
        return EXIT_ERROR
    except KeyboardInterrupt:
        done = (
            f"; already written: {', '.join(map(str, written))}"
            if written
            else "; no output written"
        )
        print(f"pinn-mesh: interrupted{done}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except OSError as exc:
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        print(f"pinn-mesh: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return EXIT_ERROR
    except MemoryError:
        print("pinn-mesh: error: out of memory; try a smaller --size", file=sys.stderr)
        return EXIT_ERROR
    except Exception as exc:  # a bug: one line, not a traceback, unless debugging
        if os.environ.get("PINN_MESH_DEBUG"):
            raise
        print(
            f"pinn-mesh: internal error: {type(exc).__name__}: {exc} (please report it; "
            "PINN_MESH_DEBUG=1 shows the traceback)",
            file=sys.stderr,
        )
        return EXIT_INTERNAL
    finally:
        signal.signal(signal.SIGTERM, previous)
    return 0
