"""One meshing job, whichever route asks: the settings (the one spec), the geometry, the size.

Every route (the command line, the VTK algorithm, and through it pyvista and ParaView) builds
a :class:`~pinn_engine.settings.Settings`, turns its inputs into a :class:`Geometry` (from
files: :func:`geometry_from_files`; from VTK data: :func:`geometry_from_polydata`) and calls
:func:`run`, which picks the block kind from ``settings.topology`` and returns the result and
its ``vtkStructuredGrid``. What differs between routes is only how they read inputs and
present results, in their own words.
"""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from pathlib import Path

import numpy as np
from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet, vtkPolyData, vtkStructuredGrid

from pinn_engine.cache import MeshCache
from pinn_engine.errors import InputError
from pinn_engine.mesher import Mesher
from pinn_engine.result import MeshResult
from pinn_engine.settings import AUTO_BLOCKS, NEURAL, Settings

# A multi-block domain's curves must lie in one plane z = const: z may vary by this share
# of the domain's size (SPEC 10's grids are built in the x, y plane)
FLAT = 1e-6

# A curve that fails as a four-sided boundary is called a body (and the user pointed to the
# O- and C-grids) when its ends are at most this share of its size apart (a blunt trailing
# edge is about 0.3 % of the chord; a forgotten side of a four-sided domain is far more) ...
BODY_GAP = 0.02
# ... and it turns by more than this many degrees at no more than two points (an airfoil's
# trailing edge, a blunt base's two corners; a triangle or a four-sided domain has more)
BODY_TURN = 45.0


@dataclass
class Geometry:
    """A job's geometry: a four-sided ``boundary`` with auxiliary lines ``aux``, or a
    ``body`` inside its far field ``far`` (SPEC 9)."""

    boundary: object | None = None  # geometry.boundary.Boundary
    aux: list = field(default_factory=list)  # geometry.auxlines.AuxLine
    body: object | None = None  # bodies.airfoil.Body
    far: object | None = None  # bodies.airfoil.FarField


@dataclass
class Outcome:
    """What a job gives: the result, its VTK grid, whether a network was trained for it, and
    the fitted mesher of a four-sided block (to save it)."""

    result: MeshResult
    grid: vtkStructuredGrid
    trained: bool
    mesher: Mesher | None = None


def _naca_body(settings: Settings):
    from pinn_engine.bodies.airfoil import circle, load_body

    body = load_body(naca=settings.naca, te="blunt" if settings.topology == "o" else "sharp")
    return Geometry(body=body, far=circle(body, settings.farfield))


def geometry_from_files(
    settings: Settings,
    boundary: str | os.PathLike | None,
    aux: Sequence[str | os.PathLike] = (),
    corners: Sequence[int] | None = None,
    farfield_given: bool = False,
) -> Geometry:
    """The geometry of files: a boundary (``.vtp``, ``.vtk``, ``.csv``, ``.txt``) with
    auxiliary-line files, or (``settings.topology`` o or c) a body: an airfoil ``.dat``
    (with the far-field circle), a file of two closed polylines (body inside far field, or
    one body with the circle when ``farfield_given``), or ``settings.naca``."""
    if settings.topology == "none":
        from pinn_engine.io.pipeline import load_aux, load_boundary

        ring = load_boundary(boundary, corners)
        return Geometry(boundary=ring, aux=load_aux(list(aux), ring))
    if settings.naca:
        return _naca_body(settings)
    from pinn_engine.bodies.airfoil import circle, load_body
    from pinn_engine.io.pipeline import read_body_and_farfield

    if str(boundary).lower().endswith(".dat") or farfield_given:
        body = load_body(boundary)
        return Geometry(body=body, far=circle(body, settings.farfield))
    body, far = read_body_and_farfield(boundary)
    return Geometry(body=body, far=far)


def _looks_like_body(poly: vtkPolyData | None) -> bool:
    """Whether a curve that is no four-sided boundary is a body: one polyline, closed or
    open by at most ``BODY_GAP`` of its size (a blunt trailing edge), that turns by more
    than ``BODY_TURN`` degrees at no more than two points (a trailing edge's corner or a
    blunt base's two), and that is a valid body (SPEC 9)."""
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from pinn_engine.bodies.airfoil import body_from_points
    from pinn_engine.geometry.boundary import turning_angles
    from pinn_engine.io.fileio import polylines_of

    try:
        lines = polylines_of(poly) if poly is not None and poly.GetNumberOfPoints() else []
        if len(lines) != 1:
            return False
        pts = vtk_to_numpy(poly.GetPoints().GetData())[lines[0][0], :2].astype(float)
        size = float(np.ptp(pts, axis=0).max())
        if np.linalg.norm(pts[0] - pts[-1]) > BODY_GAP * size:
            return False
        body = body_from_points(pts, "body")
    except InputError:
        return False
    ring = body.surface[:-1] if body.sharp else body.surface
    return int((np.abs(turning_angles(ring)) > BODY_TURN).sum()) <= 2


def geometry_from_polydata(
    settings: Settings,
    inputs: Sequence[vtkPolyData | None],
    aux: Sequence[vtkPolyData] = (),
    corners: Sequence[int] | None = None,
    source: str = "boundary input",
) -> Geometry:
    """The geometry of VTK inputs: the boundary is the one closed curve among ``inputs``, the
    open polylines there and ``aux`` are auxiliary lines; or (``settings.topology`` o or c)
    the body of the first non-empty input (or ``settings.naca``)."""
    from pinn_engine.io.pipeline import (
        aux_from_polydata,
        body_from_polydata,
        boundary_from_polydata,
        split_inputs,
    )

    if settings.topology == "none":
        boundary_poly, aux_polys = split_inputs(list(inputs))
        try:
            ring = boundary_from_polydata(boundary_poly, corners, source=source)
        except InputError as exc:
            if corners is None and _looks_like_body(boundary_poly):
                raise InputError(
                    "looks like an airfoil or another body, not a four-sided domain: "
                    "choose {topologies} to mesh around it, or name four point indices "
                    "({corners}) to mesh inside it",
                    source,
                ) from exc
            raise
        return Geometry(boundary=ring, aux=aux_from_polydata(aux_polys + list(aux), ring))
    if settings.naca:
        return _naca_body(settings)
    polys = [p for p in inputs if p is not None and p.GetNumberOfPoints()]
    if not polys:
        raise InputError("is empty; connect an airfoil (the Airfoil source or a .dat file)", source)
    body, far = body_from_polydata(polys[0], settings.farfield, source)
    return Geometry(body=body, far=far)


def run(
    settings: Settings,
    size: tuple[int, int],
    geometry: Geometry,
    patches=None,
    progress: Callable[[dict], bool | None] | None = None,
    cache: MeshCache | None = None,
    mesher: Mesher | None = None,
) -> Outcome:
    """Mesh ``geometry`` at ``size`` nodes under ``settings``: a four-sided block through the
    fitted-network ``cache`` (or a given fitted ``mesher``, e.g. a loaded model), a body
    through its block kind; ``patches`` (any form ``export.patch_names`` takes) name the
    grid's sides (default: bottom, right, top, left; a body's wall, seam or outflow, far
    field)."""
    from pinn_engine.bodymesh import mesh_body
    from pinn_engine.io.export import patch_names
    from pinn_engine.io.export.patches import body_patch_names as body_patches
    from pinn_engine.io.pipeline import to_vtk

    ni, nj = size
    if settings.topology == "none":
        names = patch_names(patches)  # refused before meshing, not after
        trained = False
        if mesher is None:
            cache = cache if cache is not None else MeshCache(capacity=1)
            mesher, trained = cache.fitted(geometry.boundary, geometry.aux, settings, progress)
        result = mesher.predict(ni, nj)
        return Outcome(result, to_vtk(result, names), trained, mesher)
    names = patch_names(patches, body_patches(settings.topology))
    result = mesh_body(
        geometry.body,
        geometry.far,
        settings.topology,
        settings.method,
        ni,
        nj,
        settings,
        settings.wall_spacing,
        progress,
    )
    return Outcome(result, to_vtk(result, names), settings.method in NEURAL)


@dataclass
class BlocksOutcome:
    """What a multi-block job gives: the result and its ``vtkMultiBlockDataSet``."""

    result: object  # multiblock.mesh.MultiBlockResult
    dataset: vtkMultiBlockDataSet
    edges: list[np.ndarray] = field(default_factory=list)  # the block edges meshed, (x, y)


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


def train_blocks(
    grids: list[np.ndarray],
    settings: Settings,
    progress: Callable[[dict], bool | str | None] | None = None,
    aux: Sequence[Sequence] | None = None,
    kinks: Callable[[list[np.ndarray]], np.ndarray] | None = None,
) -> tuple[list[np.ndarray], dict]:
    """The multi-block pinn's training (``blocks.multiblock.train_blocks``), imported only
    when some block's network can win (``blocks.untrained.cannot_win``; else every block
    keeps its start, ``untrained.untrained_blocks``): the elliptic and tfi runs, and a pinn
    whose networks cannot win, never import torch."""
    from pinn_engine.blocks.untrained import cannot_win, untrained_blocks

    reasons = [cannot_win(settings, lines) for lines in (aux or [()] * len(grids))]
    if all(reasons):
        return untrained_blocks(grids, reasons[0])
    from pinn_engine.blocks.multiblock import train_blocks as train

    return train(grids, settings, progress, aux, kinks)


def run_blocks(
    settings: Settings,
    boundary: str | os.PathLike,
    edges: Sequence[str | os.PathLike],
    patches: Sequence[str] = (),
    spacing: Sequence[str] = (),
    orthogonal: Sequence[str] = (),
    progress: Callable[[dict], bool | str | None] | None = None,
    aux: Sequence[str | os.PathLike] = (),
    cells: Sequence[str] = (),
) -> BlocksOutcome:
    """Mesh a multi-block domain (SPEC 10) from files: ``boundary`` (outer boundary and
    holes) and the block-edge files ``edges`` (``[AUTO_BLOCKS]``: edges proposed from the
    boundary alone, SPEC 13), by ``settings.method`` (tfi, elliptic or pinn); ``patches``:
    ``X,Y=NAME[:TYPE]`` items naming boundary pieces; ``spacing``: ``NAME=H`` items,
    ``orthogonal``: ``NAME[,NAME...]`` items, on those patches; ``progress`` hears the
    pinn's training block by block; ``aux``: auxiliary-line files, each line inside one
    block (the pinn fits it there); ``cells``: ``X,Y=N`` items, N cells along the chain
    through the block side nearest (X, Y)."""
    from pinn_engine.io.export.vtm import multiblock_dataset
    from pinn_engine.io.fileio import read_aux_lines, read_rings
    from pinn_engine.multiblock.autoblock import proposal
    from pinn_engine.multiblock.chains import parse_cells
    from pinn_engine.multiblock.mesh import mesh_blocks
    from pinn_engine.multiblock.patches import parse_patch_points
    from pinn_engine.multiblock.walls import parse_walls

    points = parse_patch_points(patches)  # refused before reading, not after
    walls = parse_walls(spacing, orthogonal)
    chains = parse_cells(cells)
    source = str(boundary)
    rings = read_rings(boundary)
    auto = [str(e) for e in edges] == [AUTO_BLOCKS]
    raws = [] if auto else [line for path in edges for line in read_block_edges(path)]
    lines = [line for path in aux for line in read_aux_lines(path)]
    curves = flat_curves(rings + [r.points for r in raws + lines], source)
    names = [r.name for r in raws]
    edge_curves = curves[len(rings) : len(rings) + len(raws)]
    blocking = {"mode": "manual", "edges": len(edge_curves)}
    if auto:
        proposed = proposal(curves[: len(rings)], source)
        edge_curves, names, blocking = proposed.edges, proposed.names, proposed.report
    flat = [replace(r, points=c) for r, c in zip(lines, curves[len(rings) + len(raws) :])]
    result = mesh_blocks(
        curves[: len(rings)],
        edge_curves,
        names,
        settings,
        source,
        points,
        walls,
        progress,
        flat,
        train_blocks,
        chains,
    )
    result.report["blocking"] = blocking
    dataset = multiblock_dataset(result.grids, result.cells, result.report, result.patches)
    return BlocksOutcome(result, dataset, edge_curves)


def read_block_edges(path: str | os.PathLike) -> list:
    """The open polylines of a block-edge file; none from a file that holds no line (a
    four-sided domain's saved proposal, SPEC 13)."""
    from pinn_engine.io.fileio import AUX_FORMATS, _check_file, aux_lines_of, read_polydata

    source = _check_file(Path(path), AUX_FORMATS)
    poly = read_polydata(Path(path))
    if not poly.GetNumberOfLines():
        return []
    return aux_lines_of(poly, source)
