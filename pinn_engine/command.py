"""The ``pinn-mesh`` command: ``pinn-mesh batch MANIFEST ...`` (SPEC 12), ``pinn-mesh fit
MANIFEST ...`` (a family model, SPEC 16) or one run (SPEC 5).

Above both: the batch runs each case through the single-run command line, so the dispatch
between them lives here and neither imports the other's entry point."""

from __future__ import annotations

import sys


def main(argv: list[str] | None = None) -> int:
    """Run ``pinn-mesh`` with ``argv`` (default the process's); returns its exit status."""
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["batch"]:
        from pinn_engine.batch.cli import main as batch

        return batch(argv[1:])
    if argv[:1] == ["fit"]:
        from pinn_engine.batch.fit import main as fit

        return fit(argv[1:])
    from pinn_engine.routes.cli import main as single

    return single(argv)


if __name__ == "__main__":  # python -m pinn_engine.command, as the pinn-mesh script
    sys.exit(main())
