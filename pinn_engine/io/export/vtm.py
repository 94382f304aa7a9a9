"""A multi-block grid as VTK data (SPEC 10): a ``vtkMultiBlockDataSet`` of structured
grids named ``block0``, ``block1``, ..., each with the arrays of SPEC 3, and its ``.vtm``
file (the blocks' ``.vts`` files in a folder beside it, as VTK's own writer lays them out)."""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from xml.sax.saxutils import quoteattr

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkStringArray
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet, vtkMultiBlockDataSet

from pinn_engine.errors import InputError
from pinn_engine.io.export.multiblock import PIECE_NAMES, PIECE_RANGES, PIECE_TYPES
from pinn_engine.io.export.patches import FIELD, TYPES_FIELD
from pinn_engine.io.fileio import write_text_atomic, write_vts
from pinn_engine.io.vtkgrid import structured_grid


def _add_pieces(grid, pieces: Sequence) -> None:
    """Put a block's boundary pieces (``multiblock.patches.PatchPiece``) on ``grid``."""
    fd = grid.GetFieldData()
    for key, values in (
        (PIECE_NAMES, [p.name for p in pieces]),
        (PIECE_TYPES, [p.kind for p in pieces]),
    ):
        arr = vtkStringArray()
        arr.SetName(key)
        for value in values:
            arr.InsertNextValue(value)
        fd.AddArray(arr)
    ranges = np.array([p.nodes for p in pieces], dtype=np.int32).reshape(-1, 4)
    arr = numpy_to_vtk(ranges, deep=True)
    arr.SetName(PIECE_RANGES)
    fd.AddArray(arr)


def multiblock_dataset(grids, cells, report: dict, patches=None) -> vtkMultiBlockDataSet:
    """The blocks of a multi-block result as one dataset; each block's field data holds the
    run's report with that block's own quality figures (``quality``) beside the whole
    grid's (``multiblock``), and its boundary pieces from ``patches`` (per block, as
    ``MultiBlockResult.patches``)."""
    out = vtkMultiBlockDataSet()
    out.SetNumberOfBlocks(len(grids))
    whole = {k: v for k, v in report.items() if k != "sizes"}
    for k, (points, arrays) in enumerate(zip(grids, cells)):
        figures = {
            "mean_max_angle": float(arrays["MaxIncludedAngle"].mean()),
            "worst_max_angle": float(arrays["MaxIncludedAngle"].max()),
            "worst_min_angle": float(arrays["MinIncludedAngle"].min()),
            "folded_cells": int(arrays["Folded"].sum()),
        }
        block = {"method": report["method"], "block": k, "quality": figures, "multiblock": whole}
        if "family" in report:  # a family model's run (SPEC 16): NetworkResult, FamilyModel
            block["training"] = {key: report["family"][key] for key in ("result", "model")}
        grid = structured_grid(points, block, cells=arrays)
        for name in (FIELD, TYPES_FIELD):  # a block's sides are no patches (SPEC 10's are)
            grid.GetFieldData().RemoveArray(name)
        if patches is not None:
            _add_pieces(grid, patches[k])
        out.SetBlock(k, grid)
        out.GetMetaData(k).Set(vtkCompositeDataSet.NAME(), f"block{k}")
    return out


def write_vtm(dataset: vtkMultiBlockDataSet, path: str | Path) -> Path:
    """Write ``OUT.vtm`` and its blocks as ``OUT/blockK.vts``; each file is written
    atomically and the ``.vtm`` last, so a ``.vtm`` on disk always has all its blocks."""
    path = Path(path)
    if path.suffix.lower() != ".vtm":
        raise InputError("a multi-block grid is written as a .vtm file", str(path))
    folder = path.with_suffix("")
    if folder.exists() and not folder.is_dir():
        raise InputError(f"{folder} is in the way of the blocks' folder", str(path))
    stale = folder.glob("block*.vts") if folder.is_dir() else []
    for old in stale:  # a previous, larger run's blocks would otherwise stay beside ours
        old.unlink()
    rows = []
    for k in range(dataset.GetNumberOfBlocks()):
        name = dataset.GetMetaData(k).Get(vtkCompositeDataSet.NAME())
        write_vts(dataset.GetBlock(k), folder / f"{name}.vts")
        rows.append(
            f'    <DataSet index="{k}" name={quoteattr(name)} '
            f"file={quoteattr(f'{folder.name}/{name}.vts')}/>"
        )
    text = "\n".join(
        [
            '<?xml version="1.0"?>',
            '<VTKFile type="vtkMultiBlockDataSet" version="1.0" byte_order="LittleEndian">',
            "  <vtkMultiBlockDataSet>",
            *rows,
            "  </vtkMultiBlockDataSet>",
            "</VTKFile>",
            "",
        ]
    )
    write_text_atomic(path, text)
    return path
