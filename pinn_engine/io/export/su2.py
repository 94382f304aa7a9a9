"""SU2 native mesh (``.su2``), written by hand: a short, documented ASCII format.

2D: quadrilaterals (VTK type 9) counter-clockwise, then one ``MARKER_TAG`` per patch with
its boundary lines (type 3) oriented with the domain on their left. A hexahedral grid (SPEC
11): hexahedra (type 12, VTK's node order), each marker's quadrilaterals facing out.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.io.export import bodies
from pinn_engine.io.export.block import Block, Box
from pinn_engine.io.export.multiblock import Blocks, merged
from pinn_engine.io.export.quadmesh import QuadMesh
from pinn_engine.io.export.registry import Format, register
from pinn_engine.io.export.text import write_rows
from pinn_engine.io.export.topology import box_faces, hexahedra, quads, side_edges

# VTK cell type numbers, which SU2 uses for its elements
LINE, QUAD, HEXAHEDRON = 3, 9, 12


def _write(
    path: Path, note: str, points: np.ndarray, cells: np.ndarray, markers: dict[str, np.ndarray]
) -> None:
    """Nodes ``points`` (n, dim), ``cells`` (quads in 2D, hexahedra in 3D) and the boundary
    elements of each marker (lines in 2D, quads in 3D)."""
    dim = points.shape[1]
    cell_type, face_type = (QUAD, LINE) if dim == 2 else (HEXAHEDRON, QUAD)
    with open(path, "w") as f:
        f.write(f"% SU2 mesh written by pinn-mesh{note}\nNDIME= {dim}\n")
        f.write(f"NELEM= {len(cells)}\n")
        rows = np.column_stack([cells, np.arange(len(cells))])
        write_rows(f, rows, " ".join([str(cell_type)] + ["%d"] * rows.shape[1]))
        f.write(f"NPOIN= {len(points)}\n")
        rows = np.column_stack([points, np.arange(len(points))])
        write_rows(f, rows, " ".join(["%.17g"] * dim + ["%d"]))
        f.write(f"NMARK= {len(markers)}\n")
        for name, faces in markers.items():
            f.write(f"MARKER_TAG= {name}\nMARKER_ELEMS= {len(faces)}\n")
            write_rows(f, faces, " ".join([str(face_type)] + ["%d"] * faces.shape[1]))


def write_quadmesh(mesh: QuadMesh, path: Path, note: str) -> None:
    """An unstructured quad mesh (merged nodes), ``note`` saying what it is."""
    _write(path, f" ({note})", mesh.points[:, :2], mesh.quads, mesh.patches)


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
    markers = {
        name: np.vstack([side_edges(ni, nj, s) for s in sides])
        for name, sides in block.patches().items()
    }
    _write(path, "", block.points.reshape(-1, 3)[:, :2], quads(ni, nj), markers)


def write_box(box: Box, path: Path) -> None:
    """A hexahedral grid (SPEC 11): hexahedra and a marker per patch."""
    shape = box.shape
    markers = {
        name: np.vstack([box_faces(*shape, s) for s in sides])
        for name, sides in box.patches().items()
    }
    _write(path, " (hexahedral grid)", box.xyz.reshape(-1, 3), hexahedra(*shape), markers)


def write_hexes(
    points: np.ndarray, cells: np.ndarray, markers: dict[str, np.ndarray], path: Path, note: str
) -> None:
    """An unstructured hexahedral mesh (merged nodes; cells in VTK's node order), a marker
    per patch of quads facing out, ``note`` saying what it is."""
    _write(path, f" ({note})", points, cells, markers)


def write_blocks(blocks: Blocks, path: Path, extrude: None) -> None:
    """A multi-block grid (SPEC 10): one mesh, each shared node once."""
    write_quadmesh(merged(blocks), path, f"{len(blocks.points)} blocks merged")


register(
    Format(
        "su2",
        ".su2",
        "SU2 mesh with markers",
        False,
        name="SU2",
        block=write,
        box=write_box,
        blocks=write_blocks,
        paraview=("su2", "PINNMeshSU2Writer", "PINN Mesh SU2"),
    )
)
