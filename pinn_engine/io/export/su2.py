"""SU2 native mesh (``.su2``), written by hand: a short, documented ASCII format.

2D only: quadrilaterals (VTK type 9) counter-clockwise, then one ``MARKER_TAG`` per patch
with its boundary lines (type 3) oriented with the domain on their left.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.io.export import bodies
from pinn_engine.io.export.block import Block
from pinn_engine.io.export.quadmesh import QuadMesh
from pinn_engine.io.export.text import write_rows
from pinn_engine.io.export.topology import quads, side_edges


def write_quadmesh(mesh: QuadMesh, path: Path, note: str) -> None:
    """An unstructured quad mesh (merged nodes), ``note`` saying what it is."""
    with open(path, "w") as f:
        f.write(f"% SU2 mesh written by pinn-mesh ({note})\nNDIME= 2\n")
        f.write(f"NELEM= {len(mesh.quads)}\n")
        rows = np.column_stack([mesh.quads, np.arange(len(mesh.quads))])
        write_rows(f, rows, "9 %d %d %d %d %d")
        xy = mesh.points[:, :2]
        f.write(f"NPOIN= {len(xy)}\n")
        write_rows(f, np.column_stack([xy, np.arange(len(xy))]), "%.17g %.17g %d")
        f.write(f"NMARK= {len(mesh.patches)}\n")
        for name, edges in mesh.patches.items():
            f.write(f"MARKER_TAG= {name}\nMARKER_ELEMS= {len(edges)}\n")
            write_rows(f, edges, "3 %d %d")


def write(block: Block, path: Path) -> None:
    ni, nj = block.ni, block.nj
    if block.topology:  # seam or cut nodes merged, quads counter-clockwise (bodies.py)
        write_quadmesh(bodies.quad_mesh(block), path, "O- or C-grid, seam or cut merged")
        return
    if block.normal[2] != 1.0:
        raise InputError(
            "SU2's 2D format needs a grid in a plane z = const; this one lies in "
            "a tilted plane (write .cgns, .msh, .xyz or OpenFOAM instead)",
            str(path),
        )
    cells = quads(ni, nj)
    with open(path, "w") as f:
        f.write("% SU2 mesh written by pinn-mesh\nNDIME= 2\n")
        f.write(f"NELEM= {len(cells)}\n")
        write_rows(f, np.column_stack([cells, np.arange(len(cells))]), "9 %d %d %d %d %d")
        f.write(f"NPOIN= {ni * nj}\n")
        xy = block.points.reshape(-1, 3)[:, :2]
        write_rows(f, np.column_stack([xy, np.arange(len(xy))]), "%.17g %.17g %d")
        patches = block.patches()
        f.write(f"NMARK= {len(patches)}\n")
        for name, sides in patches.items():
            edges = np.vstack([side_edges(ni, nj, s) for s in sides])
            f.write(f"MARKER_TAG= {name}\nMARKER_ELEMS= {len(edges)}\n")
            write_rows(f, edges, "3 %d %d")
