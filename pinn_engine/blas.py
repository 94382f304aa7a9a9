"""One BLAS thread for SciPy's L-BFGS-B on small problems and the 3D Winslow solve."""

from __future__ import annotations

import contextlib


def one_blas_thread():
    """A context in which BLAS runs on one thread. L-BFGS-B's vectors (a few thousand
    numbers, tens of pairs) are far too small for threads: OpenBLAS's spinning workers made
    each iteration cost about 20 ms instead of 1.4 ms (measured on this 2-core machine with
    other work on it), and competed with the loss evaluations for the cores."""
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:
        return contextlib.nullcontext()
    return threadpool_limits(1, user_api="blas")
