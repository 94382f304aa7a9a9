"""Batch meshing (SPEC 12): many cases of a manifest on a Dask cluster, each through the
single-run command's code path, with a ``summary.csv`` of one row a case.

``pinn-mesh batch MANIFEST -o OUTDIR`` on the command line (:mod:`.cli`), or
:func:`mesh_many` from Python.
"""

from pinn_engine.batch.api import mesh_many
from pinn_engine.batch.manifest import Case, ManifestError, read_manifest

__all__ = ["Case", "ManifestError", "mesh_many", "read_manifest"]
