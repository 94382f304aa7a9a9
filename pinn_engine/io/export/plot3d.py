"""PLOT3D grid (``.xyz``): multi-grid, whole, double precision, Fortran unformatted.

Written by hand (numpy): Fortran records with 4-byte length markers (the number of
grids; ni nj nk of each; then per grid all x, then all y, then all z), native byte order,
no iblank, the layout VTK's ``vtkMultiBlockPLOT3DReader`` detects by itself. A 2D grid is
written with nk = 1, a hexahedral grid (SPEC 11) as the one 3D grid of the file. PLOT3D
has no boundary conditions: the patch names are not stored.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pinn_engine.io.export.block import Block, Box
from pinn_engine.io.export.multiblock import Z_UP, Blocks
from pinn_engine.io.export.registry import Format, register
from pinn_engine.io.export.topology import layers


def _record(f, data: np.ndarray) -> None:
    marker = np.array([data.nbytes], dtype=np.int32)
    f.write(marker.tobytes())
    f.write(np.ascontiguousarray(data).tobytes())
    f.write(marker.tobytes())


def write_grids(grids: list[np.ndarray], path: Path) -> None:
    """Several grids, each (nk, nj, ni, 3), as one multi-grid file."""
    with open(path, "wb") as f:
        _record(f, np.array([len(grids)], dtype=np.int32))
        _record(f, np.array([g.shape[2::-1] for g in grids], dtype=np.int32))  # ni nj nk each
        for xyz in grids:  # x(i, j, k) in Fortran order is i fastest
            _record(f, np.moveaxis(xyz, -1, 0).astype(np.float64))


def write(block: Block, path: Path) -> None:
    write_grids([block.layers()], path)


def write_box(box: Box, path: Path) -> None:
    write_grids([box.xyz], path)


def write_blocks(blocks: Blocks, path: Path, extrude: float | None) -> None:
    """A multi-block grid (SPEC 10): a grid a block."""
    write_grids([layers(p, extrude, Z_UP) for p in blocks.points], path)


register(
    Format(
        "xyz",
        ".xyz",
        "PLOT3D grid (multi-grid, whole, double)",
        True,
        name="PLOT3D",
        block=write,
        box=write_box,
        blocks=write_blocks,
        blocks_extrude=True,
        paraview=("xyz", "PINNMeshPLOT3DWriter", "PINN Mesh PLOT3D"),
    )
)
