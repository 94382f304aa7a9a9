"""A job's grid adapted to a field (SPEC 14): the finished grid of any 2D kind handed to
``adapt``, with the walls whose first edge or angle was asked held, and the result put back
into the run's VTK data (new points, quality arrays, the point array ``Monitor``, the
report's ``adaptation``)."""

from __future__ import annotations

import json

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkStringArray
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet, vtkStructuredGrid

from pinn_engine.adapt import Field
from pinn_engine.adapt.grids import Adapted, adapt_grids
from pinn_engine.errors import InputError
from pinn_engine.kinds.outcome import Outcome
from pinn_engine.quality import cell_quality, summary
from pinn_engine.settings import Settings

# the rows next to a side that stay when its first edge or wall angle was asked: the wall's
# nodes and the first row off it (their distance and direction are what was asked)
WALL_ROWS = 2


def _side_mask(shape: tuple[int, int], side: str) -> np.ndarray:
    """A block's nodes on ``side`` and the row next to it."""
    mask = np.zeros(shape, dtype=bool)
    rows = {
        "bottom": (slice(0, WALL_ROWS), slice(None)),
        "top": (slice(-WALL_ROWS, None), slice(None)),
        "left": (slice(None), slice(0, WALL_ROWS)),
        "right": (slice(None), slice(-WALL_ROWS, None)),
    }
    mask[rows[side]] = True
    return mask


def _held_four_sided(grid: np.ndarray, settings: Settings) -> np.ndarray:
    """The sides with a spacing or ``--orthogonal``, and their first rows."""
    mask = np.zeros(grid.shape[:2], dtype=bool)
    for side in {s for s, _ in settings.spacing} | set(settings.orthogonal):
        mask |= _side_mask(grid.shape[:2], side)
    return mask


def _held_body(grid: np.ndarray, report: dict) -> np.ndarray:
    """The body's wall and its first row (the marched first layer and wall angle of SPEC
    9); a C-grid's wake cut moves."""
    mask = np.zeros(grid.shape[:2], dtype=bool)
    wake = int(report.get("topology", {}).get("wake_nodes", 0) or 0)
    ni = grid.shape[1]
    mask[:WALL_ROWS, wake : ni - wake] = True
    return mask


def _held_blocks(data: vtkMultiBlockDataSet, grids: list[np.ndarray], walls) -> list[np.ndarray]:
    """Each block's pieces of the patches with a spacing or ``--orthogonal``, and their
    first rows."""
    from pinn_engine.io.export.multiblock import PIECE_NAMES, PIECE_RANGES

    names = walls.names if walls is not None else set()
    out = []
    for k, grid in enumerate(grids):
        mask = np.zeros(grid.shape[:2], dtype=bool)
        fd = data.GetBlock(k).GetFieldData()
        pieces, ranges = fd.GetAbstractArray(PIECE_NAMES), fd.GetArray(PIECE_RANGES)
        if names and pieces is not None and ranges is not None:
            rows = vtk_to_numpy(ranges).reshape(-1, 4)
            nj, ni = grid.shape[:2]
            for p, (i0, j0, i1, j1) in enumerate(rows):
                if pieces.GetValue(p) not in names:
                    continue
                if j0 == j1:  # along i: the bottom or top side
                    rows_j = slice(0, WALL_ROWS) if j0 == 0 else slice(nj - WALL_ROWS, nj)
                    mask[rows_j, i0 : i1 + 1] = True
                else:
                    cols = slice(0, WALL_ROWS) if i0 == 0 else slice(ni - WALL_ROWS, ni)
                    mask[j0 : j1 + 1, cols] = True
        out.append(mask)
    return out


def _placed(grid: vtkStructuredGrid, old: np.ndarray, new: np.ndarray) -> np.ndarray:
    """The grid's 3D points for in-plane nodes ``new``: the affine map that takes the old
    in-plane nodes ``old`` to the grid's 3D points (a plane z = const, or any plane)."""
    xyz = vtk_to_numpy(grid.GetPoints().GetData()).astype(float)
    old, new = old.reshape(-1, 2), new.reshape(-1, 2)
    if np.array_equal(xyz[:, :2], old):  # the plane z = const: only x and y change
        return np.column_stack([new, xyz[:, 2]])
    a = np.column_stack([old, np.ones(len(old))])
    affine, *_ = np.linalg.lstsq(a, xyz, rcond=None)
    out = np.column_stack([new, np.ones(len(new))]) @ affine
    still = (new == old).all(axis=1)  # a node that did not move keeps its point exactly
    out[still] = xyz[still]
    return out


def _set_string(fd, name: str, text: str) -> None:
    fd.RemoveArray(name)
    arr = vtkStringArray()
    arr.SetName(name)
    arr.InsertNextValue(text)
    fd.AddArray(arr)


def _set_scalar(fd, name: str, value: float) -> None:
    fd.RemoveArray(name)
    arr = numpy_to_vtk(np.atleast_1d(np.asarray(value, dtype=float)), deep=True)
    arr.SetName(name)
    fd.AddArray(arr)


def _update(
    grid: vtkStructuredGrid, old: np.ndarray, new: np.ndarray, monitor: np.ndarray, report: dict
) -> dict[str, np.ndarray]:
    """Put adapted nodes into ``grid``: points, quality arrays, ``Monitor``, field data
    (``Report`` and the summary figures of ``report``); the new cells' quality."""
    from vtkmodules.vtkCommonCore import vtkPoints

    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(_placed(grid, old, new)), deep=True))
    grid.SetPoints(pts)
    cells = cell_quality(new)
    for name, values in cells.items():
        arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=float).ravel(), deep=True)
        arr.SetName(name)
        grid.GetCellData().RemoveArray(name)
        grid.GetCellData().AddArray(arr)
    grid.GetCellData().SetActiveScalars("MaxIncludedAngle")
    arr = numpy_to_vtk(np.ascontiguousarray(monitor, dtype=float).ravel(), deep=True)
    arr.SetName("Monitor")
    grid.GetPointData().AddArray(arr)
    fd = grid.GetFieldData()
    _set_string(fd, "Report", json.dumps(report, default=float))
    for key, value in report.get("quality", {}).items():
        _set_scalar(fd, key, value)
    adaptation = report.get("adaptation") or report.get("multiblock", {}).get("adaptation", {})
    for key, value in (
        ("AdaptStrength", adaptation.get("strength_used", 0.0)),
        ("EquidistributionBefore", adaptation.get("equidistribution_cv", {}).get("before", 0.0)),
        ("EquidistributionAfter", adaptation.get("equidistribution_cv", {}).get("after", 0.0)),
        ("LargestAdaptMove", adaptation.get("largest_node_move", 0.0)),
    ):
        _set_scalar(fd, key, value)
    return cells


def adapted(outcome: Outcome, settings: Settings, field: Field, walls=None) -> Outcome:
    """``outcome``'s grid adapted to ``field`` at ``settings.adapt_strength``; ``walls``:
    a multi-block run's ``multiblock.walls.Walls`` (their patches are held)."""
    if outcome.kind not in ("four-sided", "body", "blocks"):
        raise InputError("adapting to a field applies to 2D grids (SPEC 14), not to this one")
    grids = outcome.grids
    if outcome.kind == "four-sided":
        held = [_held_four_sided(grids[0], settings)]
    elif outcome.kind == "body":
        held = [_held_body(grids[0], outcome.report)]
    else:
        held = _held_blocks(outcome.data, grids, walls)
    result: Adapted = adapt_grids(grids, field, settings.adapt_strength, held)
    report = dict(outcome.report)
    report["adaptation"] = result.report
    if outcome.kind == "blocks":
        cells = [cell_quality(g) for g in result.grids]
        joined = {k: np.concatenate([c[k].ravel() for c in cells]) for k in cells[0]}
        figures = summary(joined, 0.0)
        figures.pop("boundary_deviation")
        report["quality"] = figures
        whole = {k: v for k, v in report.items() if k != "sizes"}
        for k, (old, new, m) in enumerate(zip(grids, result.grids, result.monitor)):
            block = outcome.data.GetBlock(k)
            own = json.loads(block.GetFieldData().GetAbstractArray("Report").GetValue(0))
            q = cell_quality(new)
            own["quality"] = {
                "mean_max_angle": float(q["MaxIncludedAngle"].mean()),
                "worst_max_angle": float(q["MaxIncludedAngle"].max()),
                "worst_min_angle": float(q["MinIncludedAngle"].min()),
                "folded_cells": int(q["Folded"].sum()),
            }
            own["multiblock"] = whole
            _update(block, old, new, m, own)
    else:
        cells = cell_quality(result.grids[0])
        deviation = report["quality"].get("boundary_deviation", 0.0)
        report["quality"] = summary(cells, deviation)
        _update(outcome.data, grids[0], result.grids[0], result.monitor[0], report)
    return Outcome(
        outcome.kind,
        outcome.data,
        report,
        result.grids,
        outcome.history,
        outcome.trained,
        outcome.model,
        outcome.edges,
    )
