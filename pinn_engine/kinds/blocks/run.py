"""A multi-block domain (SPEC 10): its geometry from files or VTK data (the rings, the block
edges drawn or proposed, the auxiliary lines, and the places the options name), and its
run."""

from __future__ import annotations

import os
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.errors import STOP, InputError
from pinn_engine.kinds.blocks.settings import BlocksSettings
from pinn_engine.kinds.outcome import Outcome
from pinn_engine.kinds.untrained import TFI_START, WINSLOW, cannot_win, start_or_train
from pinn_engine.settings import AUTO_BLOCKS, NO_TIME_LIMIT, Settings

if TYPE_CHECKING:
    from vtkmodules.vtkCommonDataModel import vtkPolyData

# A multi-block domain's curves must lie in one plane z = const: z may vary by this share
# of the domain's size (SPEC 10's grids are built in the x, y plane)
FLAT = 1e-6


@dataclass
class BlocksGeometry:
    """A multi-block domain: the outer boundary and holes ``rings`` and the block ``edges``
    (each (n, 2), the edges named ``names`` in messages), the auxiliary lines ``aux``
    (``geometry.auxlines.RawLine``), how the edges came (``blocking``: drawn, or proposed
    from the rings, SPEC 13), and what the options name on it: ``patches``
    (``multiblock.patches``' items), ``walls`` (spacing and orthogonality on patches or
    block sides) and ``cells`` (``--cells`` items); ``source`` names it in messages;
    ``start``: where its elliptic solve starts (``multiblock.mesh.StartNodes``: a family
    model's, SPEC 16; None: the layout's)."""

    rings: list[np.ndarray]
    edges: list[np.ndarray]
    names: list[str]
    source: str
    aux: list = field(default_factory=list)
    blocking: dict = field(default_factory=dict)
    patches: tuple = ()
    walls: object | None = None  # multiblock.walls.Walls
    cells: tuple = ()
    gradings: tuple = ()
    start: object | None = None  # multiblock.mesh.StartNodes


def flat_curves(curves: list[np.ndarray], source: str) -> list[np.ndarray]:
    """The curves' (x, y), refused unless every z is the same (within ``FLAT``)."""
    z = np.concatenate([c[:, 2] if c.shape[1] == 3 else np.zeros(len(c)) for c in curves])
    size = max(float(np.ptp(np.vstack([c[:, :2] for c in curves]), axis=0).max()), 1e-300)
    if np.ptp(z) > FLAT * size:
        raise InputError(
            f"z varies by {np.ptp(z):.3g}; a multi-block domain lies in a plane z = const in "
            "this build",
            source,
        )
    return [np.ascontiguousarray(c[:, :2]) for c in curves]


def _places(
    patches: Sequence[str],
    spacing: Sequence[str],
    orthogonal: Sequence[str],
    cells: Sequence[str],
    gradings: Sequence[str] = (),
) -> dict:
    """The options' items checked (before the inputs are read): patches, walls, cells,
    expansion ratios."""
    from pinn_engine.multiblock.chains import parse_cells, parse_gradings
    from pinn_engine.multiblock.patches import parse_patch_points
    from pinn_engine.multiblock.walls import parse_walls

    return {
        "patches": tuple(parse_patch_points(patches)),
        "walls": parse_walls(spacing, orthogonal),
        "cells": tuple(parse_cells(cells)),
        "gradings": tuple(parse_gradings(gradings)),
    }


def _laid_out(
    rings: list[np.ndarray],
    edges: list[np.ndarray],
    names: list[str],
    aux: list,
    automatic: bool,
    source: str,
    places: dict,
    cell_size: float = 0.0,
) -> BlocksGeometry:
    """The geometry of curves (n, 2 or 3) in one plane: the edges given, or proposed from
    the rings when ``automatic`` (layouts judged at the run's ``cell_size``, 0: the
    default)."""
    curves = flat_curves(rings + edges + [line.points for line in aux], source)
    flat = curves[len(rings) + len(edges) :]
    edges = curves[len(rings) : len(rings) + len(edges)]
    blocking = {"mode": "manual", "edges": len(edges)}
    if automatic:
        from pinn_engine.multiblock.autoblock import proposal

        walls, patches = places["walls"], places["patches"]
        proposed = proposal(curves[: len(rings)], source, cell_size, walls, patches)
        edges, names, blocking = proposed.edges, proposed.names, proposed.report
    lines = [replace(line, points=c) for line, c in zip(aux, flat)]
    return BlocksGeometry(curves[: len(rings)], edges, names, source, lines, blocking, **places)


def blocks_from_files(
    boundary: str | os.PathLike,
    edges: Sequence[str | os.PathLike],
    aux: Sequence[str | os.PathLike] = (),
    patches: Sequence[str] = (),
    spacing: Sequence[str] = (),
    orthogonal: Sequence[str] = (),
    cells: Sequence[str] = (),
    gradings: Sequence[str] = (),
    cell_size: float = 0.0,
) -> BlocksGeometry:
    """The multi-block domain of files: ``boundary`` (outer boundary and holes), the
    block-edge files ``edges`` (``[AUTO_BLOCKS]``: edges proposed from the boundary alone,
    SPEC 13) and auxiliary-line files ``aux`` (each line inside one block); ``patches``:
    ``X,Y=NAME[:TYPE]`` items naming boundary pieces; ``spacing``: ``NAME=H`` or ``X,Y=H``
    items, ``orthogonal``: ``NAME[,NAME...]`` items; ``cells``: ``X,Y=N`` items, N cells
    along the chain through the block side nearest (X, Y); ``gradings``: ``X,Y=R`` items,
    an expansion ratio R along that chain; ``cell_size``: the run's (0: the default), the
    size automatic blocking judges its layouts at."""
    from pinn_engine.io.fileio import read_aux_lines, read_rings

    places = _places(patches, spacing, orthogonal, cells, gradings)  # refused before reading
    rings = read_rings(boundary)
    automatic = [str(e) for e in edges] == [AUTO_BLOCKS]
    raws = [] if automatic else [line for path in edges for line in read_block_edges(path)]
    lines = [line for path in aux for line in read_aux_lines(path)]
    names = [r.name for r in raws]
    curves = [r.points for r in raws]
    return _laid_out(rings, curves, names, lines, automatic, str(boundary), places, cell_size)


def read_block_edges(path: str | os.PathLike) -> list:
    """The open polylines of a block-edge file (``.vtp``, ``.vtk``, or a ``.csv``/``.txt``
    table, one polyline a group of rows that blank lines separate, as the boundary's
    tables); none from a file that holds no line (a four-sided domain's saved proposal,
    SPEC 13)."""
    from pinn_engine.io.fileio import (
        AUX_FORMATS,
        aux_lines_of,
        check_file,
        read_polydata,
        table_aux_lines,
    )

    source = check_file(Path(path), AUX_FORMATS)
    if Path(path).suffix.lower() in (".csv", ".txt"):
        return table_aux_lines(Path(path), source)
    poly = read_polydata(Path(path))
    if not poly.GetNumberOfLines():
        return []
    return aux_lines_of(poly, source)


def _name(what: str, k: int, count: int) -> str:
    """An input's name in messages: ``what``, numbered from 1 when its port has several."""
    return what if count == 1 else f"{what} {k + 1}"


def curves_of(
    boundary_inputs: list[vtkPolyData],
    edge_inputs: list[vtkPolyData],
    automatic: bool | None = False,
) -> tuple[list[np.ndarray], list[np.ndarray], list[str]]:
    """The rings (closed curves: outer boundary and holes), the block edges (open curves)
    and the edges' names of the two ports' inputs, each curve's points (n, 3); with
    ``automatic`` blocking there must be no edges, without it some (None: either)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from pinn_engine.io.fileio import polylines_of

    rings, edges, names = [], [], []
    ports = (("input", boundary_inputs), ("block edges input", edge_inputs))
    for what, polys in ports:
        polys = [p for p in polys if p is not None and p.GetNumberOfPoints()]
        for k, poly in enumerate(polys):
            source = _name(what, k, len(polys))
            xyz = vtk_to_numpy(poly.GetPoints().GetData()).astype(float)
            for j, (ids, closed) in enumerate(polylines_of(poly, source)):
                points = xyz[ids]
                if not np.all(np.isfinite(points)):
                    raise InputError(f"line {j} has a non-finite point", source)
                if closed:
                    rings.append(points[:-1] if ids[0] == ids[-1] else points)
                else:
                    edges.append(points)
                    names.append(f"{source} line {j}")
    if not rings:
        raise InputError(
            "no closed polyline among the inputs: the outer boundary and its holes are closed "
            "polylines; {close}",
            "input",
        )
    if automatic and edges:
        raise InputError(
            "Blocking Automatic proposes every block edge: leave Block Edges empty and give "
            "the boundary alone (or set Blocking Manual)",
            names[0],
        )
    if not edges and automatic is False:
        raise InputError("no block edges (open polylines) among the inputs; {blocks}", "input")
    return rings, edges, names


def blocks_from_polydata(
    boundary_inputs: list[vtkPolyData],
    edge_inputs: list[vtkPolyData],
    aux_inputs: list[vtkPolyData] = (),
    automatic: bool | None = False,
    patches: Sequence[str] = (),
    spacing: Sequence[str] = (),
    orthogonal: Sequence[str] = (),
    cells: Sequence[str] = (),
    gradings: Sequence[str] = (),
    cell_size: float = 0.0,
) -> BlocksGeometry:
    """The multi-block domain of VTK inputs (:func:`curves_of`: the rings and edges of the
    boundary and block-edge ports; the auxiliary lines of ``aux_inputs``), the edges proposed
    when ``automatic`` (None: when no edge is given); the items as :func:`blocks_from_files`'."""
    from pinn_engine.io.fileio import aux_lines_of

    places = _places(patches, spacing, orthogonal, cells, gradings)  # refused before meshing
    rings, edges, names = curves_of(boundary_inputs, edge_inputs, automatic)
    automatic = not edges if automatic is None else automatic
    polys = [p for p in aux_inputs if p is not None and p.GetNumberOfPoints()]
    aux = [
        line
        for k, poly in enumerate(polys)
        for line in aux_lines_of(poly, _name("auxiliary lines input", k, len(polys)))
    ]
    return _laid_out(rings, edges, names, aux, automatic, "input", places, cell_size)


def train_blocks(
    grids: list[np.ndarray],
    settings: Settings,
    progress: Callable[[dict], bool | str | None] | None = None,
    aux: Sequence[Sequence] | None = None,
    kinks: Callable[[list[np.ndarray]], np.ndarray] | None = None,
) -> tuple[list[np.ndarray], dict]:
    """The multi-block pinn's training (``kinds.blocks.problem.train_blocks``), imported only
    when some block's network can win (``kinds.untrained.cannot_win``; else every block
    keeps its start, ``blocks.untrained.untrained_blocks``): the elliptic and tfi runs, and a pinn
    whose networks cannot win, never import torch."""
    from pinn_engine.kinds.blocks.untrained import untrained_blocks

    def trained() -> tuple[list[np.ndarray], dict]:
        from pinn_engine.kinds.blocks.problem import train_blocks as train  # torch: only to train

        return train(grids, settings, progress, aux, kinks)

    reasons = [cannot_win(settings, lines) for lines in (aux or [()] * len(grids))]
    return start_or_train(
        reasons[0] if all(reasons) else None,
        lambda reason: untrained_blocks(grids, reason),
        trained,
    )


class Clock:
    """The multi-block pinn's progress callback: ``progress`` told, and ``errors.STOP``
    answered once ``time_limit`` seconds (all blocks together, from the run's start; 0: no
    limit) have passed or ``progress`` answered it, the block in training keeping its best
    grid so far and the blocks after it their elliptic grids; ``stopped`` says why (the
    report's ``training.stopped``)."""

    def __init__(self, time_limit: float, progress: Callable[[dict], object] | None) -> None:
        self.time_limit, self.progress = time_limit, progress
        self.began = time.perf_counter()
        self.stopped: dict | None = None

    def __call__(self, info: dict) -> object:
        answer = self.progress(info) if self.progress is not None else None
        seconds = time.perf_counter() - self.began
        late = 0 < self.time_limit < seconds
        if self.stopped is None and (late or answer == STOP):
            self.stopped = {
                "reason": "time limit" if late else "request",
                "phase": info["phase"],
                "step": info.get("step", 0),
                "seconds": round(seconds, 2),
                "time_limit": self.time_limit,
            }
        return STOP if self.stopped is not None else answer


def run_blocks(
    settings: Settings,
    geometry: BlocksGeometry,
    progress: Callable[[dict], bool | str | None] | None = None,
) -> Outcome:
    """Mesh a multi-block domain by ``settings.method`` (tfi, elliptic or pinn); ``progress``
    hears the pinn's training block by block (:class:`Clock`: ``settings.time_limit`` bounds
    all blocks' training together)."""
    from pinn_engine.io.export.vtm import multiblock_dataset
    from pinn_engine.multiblock.mesh import mesh_blocks
    from pinn_engine.starts.untangle import untangle

    g, settings = geometry, BlocksSettings.adopt(settings)  # a route's core settings
    if settings.objective == "best":  # the quality objective's start is a four-sided block's
        settings = replace(settings, objective="winslow")
    clock = Clock(settings.time_limit, progress)
    result = mesh_blocks(
        g.rings,
        g.edges,
        g.names,
        replace(settings, time_limit=NO_TIME_LIMIT),
        g.source,
        g.patches,
        g.walls,
        clock,
        g.aux,
        train_blocks,
        g.cells,
        untangle,
        g.gradings,
        g.start,
    )
    result.report["blocking"] = g.blocking
    training = result.report.get("training", {})
    if training.get("start") == "tfi":  # the networks train toward the elliptic grid
        for block in training["blocks"]:
            if block.get("skipped") == WINSLOW:
                block["skipped"] = TFI_START
    if clock.stopped is not None:
        result.report.setdefault("training", {})["stopped"] = clock.stopped
    dataset = multiblock_dataset(result.grids, result.cells, result.report, result.patches)
    trained = any(
        not block.get("skipped") for block in result.report.get("training", {}).get("blocks", [])
    )
    return Outcome("blocks", dataset, result.report, result.grids, {}, trained, None, g.edges)
