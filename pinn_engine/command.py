"""The ``pinn-mesh`` command: ``pinn-mesh batch MANIFEST ...`` (SPEC 12), ``pinn-mesh fit
MANIFEST ...`` (a family model, SPEC 16) or one run (SPEC 5).

Above both: the batch runs each case through the single-run command line, so the dispatch
between them lives here and neither imports the other's entry point."""

from __future__ import annotations

import gc
import os
import sys

# NumPy's OpenBLAS starts a worker thread per core when NumPy is imported, each spinning
# after every call; no product of a run is big enough to gain from them (``blas.py``), so
# the command's process keeps BLAS on one thread unless its caller says otherwise (measured
# on the blockMeshDict pipe: 0.95 -> 0.86 s CPU, 1.41 -> 1.26 s wall, 2 cores at load 4)
BLAS_THREADS = "1"


def main(argv: list[str] | None = None) -> int:
    """Run ``pinn-mesh`` with ``argv`` (default the process's: then this process is the
    command, and a single run's objects are frozen out of the garbage collector when it
    ends, since they die with the process: Python's exit would otherwise search them all
    for cycles, 0.06 s of CPU after the blockMeshDict pipe); returns its exit status."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", BLAS_THREADS)
    own = argv is None
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["batch"]:
        from pinn_engine.batch.cli import main as batch

        return batch(argv[1:])
    if argv[:1] == ["fit"]:
        from pinn_engine.batch.fit import main as fit

        return fit(argv[1:])
    from pinn_engine.routes.cli import main as single

    status = single(argv)
    if own:
        gc.freeze()
    return status


if __name__ == "__main__":  # python -m pinn_engine.command, as the pinn-mesh script
    sys.exit(main())
