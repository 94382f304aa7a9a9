"""The VTK formats: ``.vts`` (XML, through ``fileio.write_vts``) and ``.vtk`` (legacy).

VTK's writers and ``io.fileio`` (its readers too) are imported where a grid is written, so
that registering these formats (``--format``'s choices) costs no start-up."""

from __future__ import annotations

from pathlib import Path

from pinn_engine.io.atomic import atomic_path
from pinn_engine.io.export.registry import Format, register


def write_vts(grid, path: Path) -> Path:
    """Write ``grid`` as an XML ``.vts`` file atomically (``fileio.write_vts``)."""
    from pinn_engine.io import fileio

    return fileio.write_vts(grid, path)


def write_legacy(grid, path: Path) -> None:
    """Write ``grid`` as a binary legacy ``.vtk`` structured grid to ``path``."""
    from vtkmodules.vtkIOLegacy import vtkStructuredGridWriter

    from pinn_engine.io.fileio import quiet_vtk

    writer = vtkStructuredGridWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(grid)
    writer.SetFileTypeToBinary()
    with quiet_vtk():
        ok = writer.Write() == 1
    if not ok:
        raise OSError(f"VTK could not write {path} (disk full or not writable?)")


def write_vtk(grid, path: Path) -> None:
    """Write ``grid`` as a legacy ``.vtk`` file atomically."""
    with atomic_path(path, suffix=".vtk") as tmp:
        write_legacy(grid, tmp)


register(Format("vts", ".vts", "VTK XML structured grid", False, name="VTK XML", grid=write_vts))
register(Format("vtk", ".vtk", "VTK legacy structured grid", False, name="VTK", grid=write_vtk))


__all__ = ["write_legacy", "write_vtk", "write_vts"]
