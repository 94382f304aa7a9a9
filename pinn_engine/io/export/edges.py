"""Block edges as a file (SPEC 13's ``--save-blocks``): open polylines in a ``.vtp``, points
in double precision, so that meshing with the file as ``--blocks`` gives the same grid."""

from __future__ import annotations

import os
from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

from pinn_engine.errors import InputError
from pinn_engine.io.fileio import atomic_path, quiet_vtk


def edges_polydata(edges: list[np.ndarray]) -> vtkPolyData:
    """One open polyline per edge ((n, 2) or (n, 3) points; z = 0 where absent)."""
    poly, points, cells = vtkPolyData(), vtkPoints(), vtkCellArray()
    points.SetDataTypeToDouble()
    xyz = [np.column_stack([e[:, :2], e[:, 2:3] if e.shape[1] > 2 else 0 * e[:, :1]])
           for e in edges]  # fmt: skip
    if xyz:
        points.SetData(numpy_to_vtk(np.vstack(xyz).astype(np.float64), deep=True))
    start = 0
    for line in xyz:
        cells.InsertNextCell(len(line), list(range(start, start + len(line))))
        start += len(line)
    poly.SetPoints(points)
    poly.SetLines(cells)
    return poly


def edges_of(poly: vtkPolyData) -> list[np.ndarray]:
    """The open polylines of ``poly`` (as :func:`edges_polydata` makes them), (n, 3) each."""
    from pinn_engine.io.fileio import polylines_of

    if not poly.GetNumberOfLines():
        return []
    xyz = vtk_to_numpy(poly.GetPoints().GetData()).astype(np.float64)
    return [xyz[ids] for ids, _ in polylines_of(poly, "block edges")]


def write_edges(edges: list[np.ndarray], path: str | os.PathLike) -> Path:
    """Write ``edges`` as a ``.vtp`` of open polylines, atomically (complete or absent)."""
    path = Path(path)
    if path.suffix.lower() != ".vtp":
        raise InputError("block edges are saved as a .vtp file", str(path))
    with atomic_path(path, suffix=".vtp") as tmp:
        writer = vtkXMLPolyDataWriter()
        writer.SetFileName(str(tmp))
        writer.SetInputData(edges_polydata(edges))
        writer.SetDataModeToBinary()  # every bit kept: the edges read back are these points
        with quiet_vtk():
            ok = writer.Write() == 1
        if not ok:
            raise OSError(f"VTK could not write {path} (disk full or not writable?)")
    return path
