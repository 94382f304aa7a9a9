"""The VTK formats: ``.vts`` (XML, through ``fileio.write_vts``) and ``.vtk`` (legacy)."""

from __future__ import annotations

from pathlib import Path

from vtkmodules.vtkIOLegacy import vtkStructuredGridWriter

from pinn_engine.io.fileio import _quiet_vtk, write_vts


def write_legacy(grid, path: Path) -> None:
    """Write ``grid`` as a binary legacy ``.vtk`` structured grid to ``path``."""
    writer = vtkStructuredGridWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(grid)
    writer.SetFileTypeToBinary()
    with _quiet_vtk():
        ok = writer.Write() == 1
    if not ok:
        raise OSError(f"VTK could not write {path} (disk full or not writable?)")


__all__ = ["write_legacy", "write_vts"]
