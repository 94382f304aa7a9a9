"""Batch meshing (SPEC 12): many cases of a manifest on a Dask cluster, each through the
single-run command's code path, with a ``summary.csv`` of one row a case.

``pinn-mesh batch MANIFEST -o OUTDIR`` on the command line (:mod:`.cli`), or
:func:`mesh_many` from Python. The names below are imported on first use, so that the batch
command starts its local workers' server (:mod:`.warm`) before it imports the engine.
"""

from pinn_engine.lazy import lazy_names

# each public name and the module that defines it
_PUBLIC = {
    "Case": ".manifest",
    "ManifestError": ".manifest",
    "mesh_many": ".api",
    "read_manifest": ".manifest",
}

__all__ = sorted(_PUBLIC)
__getattr__, __dir__ = lazy_names(__name__, _PUBLIC)
