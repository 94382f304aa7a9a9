"""Build the output ``vtkStructuredGrid`` of SPEC 3 (VTK only, usable inside ParaView)."""

from __future__ import annotations

import json

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkPoints, vtkStringArray
from vtkmodules.vtkCommonDataModel import vtkStructuredGrid

from pinn_engine.io.export.patches import add_to_grid, patch_specs
from pinn_engine.quality import cell_quality


def _add_scalar(fd, name: str, values) -> None:
    arr = numpy_to_vtk(np.atleast_1d(np.asarray(values, dtype=float)), deep=True)
    arr.SetName(name)
    fd.AddArray(arr)


def _add_string(fd, name: str, text: str) -> None:
    arr = vtkStringArray()
    arr.SetName(name)
    arr.InsertNextValue(text)
    fd.AddArray(arr)


def _add_history(fd, history: dict[str, list[float]]) -> None:
    """The loss history as one array ``LossHistory``: a row per evaluation, a component per
    term, named after it; one entry in ParaView's Color By list instead of one per term."""
    terms = list(history)
    arr = numpy_to_vtk(np.column_stack([history[t] for t in terms]).astype(float), deep=True)
    arr.SetName("LossHistory")
    for k, term in enumerate(terms):
        arr.SetComponentName(k, term)
    fd.AddArray(arr)


def loss_history(grid) -> dict[str, np.ndarray]:
    """The loss history of a grid's field data (``LossHistory``): term -> values, e.g.
    ``loss_history(grid)["total"]``; empty for a method without training."""
    arr = grid.GetFieldData().GetArray("LossHistory")
    if arr is None:
        return {}
    values = vtk_to_numpy(arr).reshape(arr.GetNumberOfTuples(), -1)
    return {arr.GetComponentName(k): values[:, k].copy() for k in range(values.shape[1])}


def structured_grid(
    points: np.ndarray,
    report: dict | None = None,
    history: dict[str, list[float]] | None = None,
    cells: dict[str, np.ndarray] | None = None,
    patches=None,
    xyz: np.ndarray | None = None,
) -> vtkStructuredGrid:
    """A grid of dimensions (ni, nj, 1) from ``points`` (nj, ni, 2), with quality arrays;
    ``xyz`` (nj, ni, 3), when given, are the points in the user's 3D frame (default z = 0).

    Cell data: ``MaxIncludedAngle``, ``MinIncludedAngle`` (degrees, as vtkMeshQuality),
    ``ScaledJacobian`` and ``Folded`` (0/1), computed unless given as ``cells``. Field data:
    ``Method``, ``Report`` (JSON: settings, timings, quality summary), the summary figures as
    numbers, per side ``FirstEdge_<side>`` (min, median, max), ``WallAngleDeviation_<side>``
    (degrees) and ``GrowthRatio_<side>``, the loss history ``LossHistory`` (a component per
    term; :func:`loss_history` reads it), ``PatchNames``
    (``patches``: any form ``export.patch_names`` takes; default bottom, right, top, left),
    and for a trained network ``NetworkResult`` (``network``: its grid; ``start``: the guard
    kept the start) and ``LargestNodeMove`` (between start and result, of the diagonal).
    Point data: ``i``, ``j``.
    """
    nj, ni = points.shape[:2]
    grid = vtkStructuredGrid()
    grid.SetDimensions(ni, nj, 1)
    if xyz is None:
        xyz = np.column_stack([points.reshape(-1, 2), np.zeros(ni * nj)])
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(xyz, dtype=float).reshape(-1, 3), deep=True))
    grid.SetPoints(pts)
    cells = cell_quality(points) if cells is None else cells
    for name, values in cells.items():
        arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=float).ravel(), deep=True)
        arr.SetName(name)
        grid.GetCellData().AddArray(arr)
    grid.GetCellData().SetActiveScalars("MaxIncludedAngle")
    add_to_grid(grid, *patch_specs(patches))
    fd = grid.GetFieldData()
    report = report or {}
    _add_string(fd, "Method", str(report.get("method", "")))
    _add_string(fd, "Report", json.dumps(report, default=float))
    for key, value in report.get("quality", {}).items():
        _add_scalar(fd, key, value)
    for side, figures in report.get("sides", {}).items():  # SPEC 7, per side
        _add_scalar(
            fd,
            f"FirstEdge_{side}",
            [figures["first_edge_min"], figures["first_edge_median"], figures["first_edge_max"]],
        )
        _add_scalar(fd, f"WallAngleDeviation_{side}", figures["max_angle_deviation"])
        _add_scalar(fd, f"GrowthRatio_{side}", figures["max_growth_ratio"])
    for key in ("train_seconds", "mesh_seconds"):
        if key in report:
            _add_scalar(fd, key, report[key])
    training = report.get("training", {})
    if "result" in training:  # what the network did (the start kept, or its own grid)
        _add_string(fd, "NetworkResult", training["result"])
        if "model" in training:  # a family model's grid (SPEC 16): the model's file
            _add_string(fd, "FamilyModel", str(training["model"]))
        if training.get("largest_node_move") is not None:
            _add_scalar(fd, "LargestNodeMove", training["largest_node_move"])
    if history:
        _add_history(fd, history)
    topology = report.get("topology")
    if topology:  # an O- or C-grid (SPEC 9): what the writers need to join seam or cut
        _add_string(fd, "Topology", topology["kind"])
        _add_scalar(fd, "WakeNodes", topology.get("wake_nodes", 0))
    return grid
