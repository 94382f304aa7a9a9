"""Batch meshing (SPEC 12): many cases of a manifest on a Dask cluster, each through the
single-run command's code path, with a ``summary.csv`` of one row a case.

``pinn-mesh batch MANIFEST -o OUTDIR`` on the command line (:mod:`.cli`), or
:func:`mesh_many` from Python. The names below are imported on first use, so that the batch
command starts its local workers' server (:mod:`.warm`) before it imports the engine.
"""

from importlib import import_module

# each public name and the module that defines it
_PUBLIC = {
    "Case": "manifest",
    "ManifestError": "manifest",
    "mesh_many": "api",
    "read_manifest": "manifest",
}

__all__ = sorted(_PUBLIC)


def __getattr__(name: str):
    if name in _PUBLIC:
        return getattr(import_module(f"{__name__}.{_PUBLIC[name]}"), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def __dir__() -> list[str]:
    return sorted({*globals(), *_PUBLIC})
