"""One BLAS thread inside blas.one_thread: every BLAS library loaded, those loaded by a later
import too, and each library's thread count set back as the host had it."""

from __future__ import annotations

import subprocess
import sys
import textwrap

# A child process that sets its BLAS libraries to 2 threads, enters one_thread before and
# after importing SciPy (which loads a BLAS of its own) and prints each library's count
# inside and after, and how many times the libraries were searched for
CHILD = textwrap.dedent(
    """
    import json, numpy
    from threadpoolctl import threadpool_info, threadpool_limits
    from pinn_engine import blas

    def counts():
        return {i["filepath"]: i["num_threads"] for i in threadpool_info()
                if i["user_api"] == "blas"}

    threadpool_limits(2, user_api="blas")
    seen = {}
    for step in ("numpy", "again", "scipy"):
        if step == "scipy":
            import scipy.linalg
            threadpool_limits(2, user_api="blas")
        with blas.one_thread():
            seen[step] = {"inside": counts()}
        seen[step]["after"] = counts()
        seen[step]["searches"] = blas._blas_pools.cache_info().misses
    print(json.dumps(seen))
    """
)


def test_one_thread_limits_every_blas_and_restores_the_hosts_counts():
    import json

    out = subprocess.run(
        [sys.executable, "-c", CHILD], check=True, capture_output=True, text=True
    ).stdout
    seen = json.loads(out)
    assert len(seen["scipy"]["inside"]) > len(seen["numpy"]["inside"])  # SciPy's own BLAS
    for step in seen.values():
        assert set(step["inside"].values()) == {1}
        assert set(step["after"].values()) == {2}
    # the libraries are searched for again only after an import
    assert seen["again"]["searches"] == seen["numpy"]["searches"]
    assert seen["scipy"]["searches"] == seen["numpy"]["searches"] + 1
