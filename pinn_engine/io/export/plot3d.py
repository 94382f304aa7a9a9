"""PLOT3D grid (``.xyz``): multi-grid, whole, double precision, Fortran unformatted.

Written by hand (numpy): three Fortran records with 4-byte length markers (number of
blocks; ni nj nk; all x, then all y, then all z), native byte order, no iblank, the layout
VTK's ``vtkMultiBlockPLOT3DReader`` detects by itself. A 2D grid is written with nk = 1.
PLOT3D has no boundary conditions: the patch names are not stored.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pinn_engine.io.export.block import Block


def _record(f, data: np.ndarray) -> None:
    marker = np.array([data.nbytes], dtype=np.int32)
    f.write(marker.tobytes())
    f.write(np.ascontiguousarray(data).tobytes())
    f.write(marker.tobytes())


def write(block: Block, path: Path) -> None:
    xyz = block.layers()  # (nk, nj, ni, 3): x(i, j, k) in Fortran order is i fastest
    nk, nj, ni = xyz.shape[:3]
    with open(path, "wb") as f:
        _record(f, np.array([1], dtype=np.int32))
        _record(f, np.array([ni, nj, nk], dtype=np.int32))
        _record(f, np.moveaxis(xyz, -1, 0).astype(np.float64))
