"""Which domain kind a run's inputs are: the one rule every route follows."""

from __future__ import annotations

import os
from collections.abc import Sequence
from typing import TYPE_CHECKING

from pinn_engine.blocks3d.dictionary import is_blockmeshdict
from pinn_engine.hexa.surface import FACE_ARRAY, is_faced_surface
from pinn_engine.settings import HEXA_SIZE

if TYPE_CHECKING:
    from vtkmodules.vtkCommonDataModel import vtkPolyData


def _faced(boundary: str | os.PathLike | vtkPolyData | None) -> bool:
    """Whether ``boundary`` is a six-faced domain's surface: a file (an ``.stl``, or a
    ``.vtp``/``.vtk`` naming a FaceId array) or VTK data with a FaceId cell array."""
    if boundary is not None and not isinstance(boundary, str | os.PathLike):
        from vtkmodules.vtkCommonDataModel import vtkPolyData  # a VTK route's data

        if isinstance(boundary, vtkPolyData):
            return boundary.GetCellData().GetArray(FACE_ARRAY.decode()) is not None
    return boundary is not None and is_faced_surface(boundary)


def kind_of(
    boundary: str | os.PathLike | vtkPolyData | None,
    blocks: bool = False,
    size: Sequence[int] = (),
    body: bool = False,
) -> str:
    """The kind (``registry.KINDS``) of a run: ``dictionary`` for a blockMeshDict (SPEC 15),
    ``blocks`` when block edges are given (SPEC 10), ``hexa`` for a six-faced surface or
    three sizes (SPEC 11), ``body`` when a topology, a NACA section or an airfoil ``.dat``
    is given (SPEC 9), else ``four-sided`` (SPEC 5)."""
    if isinstance(boundary, str | os.PathLike) and is_blockmeshdict(boundary):
        return "dictionary"
    if blocks:
        return "blocks"
    if len(size) == len(HEXA_SIZE) or _faced(boundary):
        return "hexa"
    dat = isinstance(boundary, str | os.PathLike) and str(boundary).lower().endswith(".dat")
    return "body" if body or dat else "four-sided"
