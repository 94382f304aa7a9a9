"""A six-faced 3D domain (SPEC 11): its geometry from a file or VTK data (a closed surface,
its faces tagged by FaceId or found at its sharp edges), and its run."""

from __future__ import annotations

import os
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING

from pinn_engine.errors import SettingsError
from pinn_engine.kinds.outcome import Outcome
from pinn_engine.settings import Settings, hexa_size_problem

if TYPE_CHECKING:
    from vtkmodules.vtkCommonDataModel import vtkPolyData

PERCENT = 100  # a stage's progress dict counts the share of the run done in per cent


@dataclass
class HexaGeometry:
    """A closed surface ``surface`` with a ``FaceId`` cell array, or (``sharp_edges``)
    faces found where it bends by more than ``settings.face_angle`` degrees; ``source``
    names it in messages; ``patches`` name its sides (imin ... kmax or ``faceN``)."""

    surface: vtkPolyData
    source: str
    sharp_edges: bool = False
    patches: object | None = None


def hexa_from_file(path: str | os.PathLike, patches=None) -> HexaGeometry:
    """The surface of a ``.vtp``/``.vtk`` file with ``FaceId``, or of an ``.stl`` (faces at
    its sharp edges)."""
    from pinn_engine.io.fileio import read_polydata

    stl = str(path).lower().endswith(".stl")
    return HexaGeometry(read_polydata(Path(path)), str(path), stl, patches)


def hexa_from_polydata(surface: vtkPolyData, source: str = "input", patches=None) -> HexaGeometry:
    """The surface of VTK data: faces by its ``FaceId`` cell array, else at its sharp
    edges."""
    from pinn_engine.hexa.surface import FACE_ARRAY

    faced = surface.GetCellData().GetArray(FACE_ARRAY.decode()) is not None
    return HexaGeometry(surface, source, not faced, patches)


def run_hexa(
    settings: Settings,
    geometry: HexaGeometry,
    progress: Callable[[dict], object] | None = None,
    model: str | os.PathLike | None = None,
) -> Outcome:
    """The hexahedral grid of ``geometry`` under ``settings`` (``kinds.hexa.mesh.mesh_polydata``);
    ``progress`` hears each stage (``{"phase": "prepare", "stage": ..., "step": k, "total":
    PERCENT}``, k the share of the run done) and the training; ``model``: a saved pinn to
    evaluate instead of training."""
    from pinn_engine.kinds.hexa.mesh import hexa_grid, mesh_polydata, report

    problem = hexa_size_problem(settings.size)
    if problem:
        raise SettingsError(f"size {settings.size}: {problem} (make_settings(..., size=...))")

    def stage(fraction: float, phase: str) -> None:
        if progress is not None:
            step = round(fraction * PERCENT)
            progress({"phase": "prepare", "stage": phase, "step": step, "total": PERCENT})

    result = mesh_polydata(
        geometry.surface,
        settings,
        geometry.source,
        stage,
        sharp_edges=geometry.sharp_edges,
        load_model=str(model) if model is not None else None,
        patches=geometry.patches,
        training=progress,
    )
    method = settings.method
    nodes = result.grid.transpose(2, 1, 0, 3)  # (ni, nj, nk, 3) as VTK orders them: i fastest
    history = result.model.history if result.model else {}
    trained = model is None and result.model is not None and not result.model.info.get("skipped")
    return Outcome(
        "hexa",
        hexa_grid(result, method),
        report(result, method),
        [nodes],
        history,
        trained,
        result.model,
    )
