"""Warm worker processes for a local cluster: the forkserver that forks them imports, once,
what a case runs, and is started as soon as a batch knows it runs locally. Each worker then
starts with it loaded, where each imported it at its start (about 1.5 s), side by side on
the same cores.

Stdlib only, so that the batch command starts the server before it imports Dask itself: the
server's imports (Dask, VTK, SciPy, the engine) then overlap the command's own.
"""

from __future__ import annotations

import multiprocessing
from multiprocessing import forkserver

# How a local cluster starts its worker processes: forked from a server process, and ended
# by os._exit, where a spawned process ends by a full interpreter shutdown (about 1 s a
# worker with torch and VTK loaded, paid at every batch's close)
START_METHOD = "forkserver"
# What the server imports before it forks the workers: Dask's worker and what every
# four-sided or body case runs. Training's modules (torch, 1.5 s more) are left to the
# worker whose case trains: on the server they delayed every worker's start.
PRELOAD = (
    "distributed",
    "pinn_engine.batch.task",
    "pinn_engine.job",
    "pinn_engine.io.pipeline",
    "pinn_engine.io.export",
    "pinn_engine.bodymesh",
)


def start_method() -> str | None:
    """The start method of local workers: the forkserver where the platform has one."""
    return START_METHOD if START_METHOD in multiprocessing.get_all_start_methods() else None


def start() -> None:
    """Start the forkserver with :data:`PRELOAD` now, where there is one (a no-op once it
    runs: a server started earlier in this process, with whatever it preloaded, is kept)."""
    if start_method() is None:
        return
    multiprocessing.get_context(START_METHOD).set_forkserver_preload(list(PRELOAD))
    forkserver.ensure_running()
