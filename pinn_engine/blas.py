"""One thread for SciPy's L-BFGS-B on small problems, the 3D Winslow solve and the torch
terms evaluated inside them."""

from __future__ import annotations

import contextlib
import sys
from collections.abc import Iterator


@contextlib.contextmanager
def one_thread() -> Iterator[None]:
    """A context in which BLAS, and torch where it is already imported, run on one thread,
    both restored afterwards (the host process is left as it was found).

    L-BFGS-B's vectors (a few thousand numbers, tens of pairs) are far too small for threads:
    OpenBLAS's spinning workers made each iteration cost about 20 ms instead of 1.4 ms, and
    torch's two intra-op threads made the orthogonal repair's barrier terms (a 41 x 21 grid)
    3.2x slower in CPU time (both measured on this 2-core machine with other work on it)."""
    torch = sys.modules.get("torch")
    threads = torch.get_num_threads() if torch is not None else None
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        limits = contextlib.nullcontext()
    else:
        limits = threadpool_limits(1, user_api="blas")
    with limits:
        if threads is not None:
            torch.set_num_threads(1)
        try:
            yield
        finally:
            if threads is not None:
                torch.set_num_threads(threads)
