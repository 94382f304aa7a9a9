"""One thread for SciPy's L-BFGS-B on small problems, the 3D Winslow solve and the torch
terms evaluated inside them."""

from __future__ import annotations

import contextlib
import functools
import sys
from collections.abc import Iterator


@functools.lru_cache(maxsize=1)
def _blas_pools(modules: int):
    """threadpoolctl's controller of the BLAS libraries loaded, found when ``modules``
    modules were imported: finding them reads ``/proc/self/maps``, 3-9 ms CPU in a batch
    worker with torch and VTK loaded, so it is redone only when the number of imported
    modules changes (a library is loaded by an import, the rule of threadpoolctl's own
    ``get_cached_controller``)."""
    from threadpoolctl import ThreadpoolController

    return ThreadpoolController().select(user_api="blas")


@contextlib.contextmanager
def one_thread() -> Iterator[None]:
    """A context in which BLAS, and torch where it is already imported, run on one thread,
    both restored afterwards (the host process is left as it was found: each library's
    thread count is read on entry and set back on exit).

    L-BFGS-B's vectors (a few thousand numbers, tens of pairs) are far too small for threads:
    OpenBLAS's spinning workers made each iteration cost about 20 ms instead of 1.4 ms, and
    torch's two intra-op threads made the orthogonal repair's barrier terms (a 41 x 21 grid)
    3.2x slower in CPU time (both measured on this 2-core machine with other work on it)."""
    torch = sys.modules.get("torch")
    threads = torch.get_num_threads() if torch is not None else None
    try:
        pools = _blas_pools(len(sys.modules))
    except ImportError:
        limits = contextlib.nullcontext()
    else:
        limits = pools.limit(limits=1)
    with limits:
        if threads is not None:
            torch.set_num_threads(1)
        try:
            yield
        finally:
            if threads is not None:
                torch.set_num_threads(threads)
