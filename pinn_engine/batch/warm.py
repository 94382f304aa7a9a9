"""Warm worker processes for a local batch: the forkserver that forks them imports, once,
what a case runs, and is started as soon as a batch knows it runs locally. Each worker then
starts with it loaded, where each imported it at its start (about 1.5 s), side by side on
the same cores.

Stdlib only, so that the batch command starts the server before it imports the engine or
Dask itself: the server's imports then overlap the command's own.
"""

from __future__ import annotations

import importlib.util
import multiprocessing
import os
from multiprocessing import forkserver

from pinn_engine.errors import MissingExtraError

# How local workers start: forked from a server process, and ended by os._exit, where a
# spawned process ends by a full interpreter shutdown (about 1 s a worker with torch and VTK
# loaded, paid at every batch's close)
START_METHOD = "forkserver"
# What the server imports before it forks the workers: what every four-sided or body case
# runs. Training's modules (torch, 1.5 s more) are left to the worker whose case trains: on
# the server they delayed every worker's start.
ENGINE = (
    "pinn_engine.routes.cli.dispatch",
    "pinn_engine.job",
    "pinn_engine.io.pipeline",
    "pinn_engine.io.export",
    "pinn_engine.io.export.registered",  # every format's writer (io.export imports them late)
    "pinn_engine.kinds.body.mesh",
    "pinn_engine.kinds.untrained",  # the decision and the start a case keeps untrained
    "pinn_engine.kinds.body.untrained",  # a body's decision and the grid it keeps
    "pinn_engine.kinds.four_sided.mesher",
    "pinn_engine.heap",
    "scipy.sparse.linalg",  # the elliptic solves' sparse LU, which their modules import late
    # VTK's polydata readers and stripper, which io.fileio imports where a file is read
    "vtkmodules.vtkIOGeometry",
    "vtkmodules.vtkIOLegacy",
    "vtkmodules.vtkFiltersCore",
)
DASK = ("distributed",)  # a Dask worker's own modules (0.5 s of CPU), for a Dask cluster
DASK_EXTRA = ("batch meshing (Dask)", "batch")  # what needs Dask, and the extra it comes with


def default_workers() -> int:
    """One worker process per core (SPEC 12)."""
    return os.cpu_count() or 1


def require_dask() -> None:
    """Raise :class:`MissingExtraError` where Dask is not installed (the batch extra), before
    anything starts; Dask itself is imported only where a batch runs on it."""
    if importlib.util.find_spec("distributed") is None:
        raise MissingExtraError(*DASK_EXTRA)


def start_method() -> str | None:
    """The start method of local workers: the forkserver where the platform has one."""
    return START_METHOD if START_METHOD in multiprocessing.get_all_start_methods() else None


def start(dask: bool) -> None:
    """Start the forkserver with :data:`ENGINE` (and with ``dask``, :data:`DASK`) now, where
    there is one (a no-op once it runs: a server started earlier in this process, with
    whatever it preloaded, is kept)."""
    if start_method() is None:
        return
    preload = [*DASK, *ENGINE] if dask else list(ENGINE)
    multiprocessing.get_context(START_METHOD).set_forkserver_preload(preload)
    forkserver.ensure_running()


def setup_worker() -> None:
    """Set a worker process up as the single-run command sets itself up, glibc's heap tuned,
    with one thread for torch and the BLAS: cases run in parallel across workers, not inside
    one. torch is not imported here: only a case that trains needs it, and it reads
    ``OMP_NUM_THREADS`` when it is imported."""
    import sys

    from threadpoolctl import threadpool_limits

    from pinn_engine import heap

    if "torch" in sys.modules:
        sys.modules["torch"].set_num_threads(1)
    os.environ["OMP_NUM_THREADS"] = "1"
    threadpool_limits(1)
    heap.tune_process()
    from pinn_engine.io import childread

    childread.serve()  # one reading child for the worker's cases, not one a case
