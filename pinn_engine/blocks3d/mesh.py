"""A blockMeshDict meshed (SPEC 15): blockMesh's placement, the Winslow grid over all
blocks, the choice between them, and the result as VTK blocks with SPEC 11's arrays.

The methods: ``tfi`` is blockMesh's placement; ``elliptic`` the 3D Winslow grid over all
blocks (``winslow.py``; refused where it folds); ``pinn`` (the default) the Winslow grid
where it meets SPEC 15's aims, checkMesh's largest non-orthogonality and skewness no worse
than blockMesh's, else the grid between the two nearest the Winslow grid that meets them and
is less non-orthogonal (a ``blend``), else blockMesh's placement (a placement orthogonal to
within ``ORTHOGONAL`` everywhere is kept unsolved: the solve could gain no figure that
matters); where the blocking is a swept section, the grid chosen is then ``optimised``: its
section's largest non-orthogonality minimised with no face more skewed (``section.py``), the
search run from it and from blockMesh's placement (unless the first reaches ``ORTHOGONAL``),
kept where at least ``ORTHOGONAL`` degrees less; the Winslow grid of a swept section is its
slab's (``winslow_grid``); the network would train on the Winslow
equations alone, which the elliptic grid already solves, so none is trained (the report's
``training.skipped`` says so, as for a hexahedral block without spacing or orthogonal
patches). The blocks are coupled through their interfaces, so the choice is made for the
grid as a whole.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.blocks3d.checks import Figures, figures, hexes
from pinn_engine.blocks3d.dictionary import BlockMeshDict
from pinn_engine.blocks3d.placement import Placement, place
from pinn_engine.errors import InputError
from pinn_engine.geometry.faces import FaceTopology, topology
from pinn_engine.hexa.quality import folded, included_angles, scaled_jacobian

if TYPE_CHECKING:  # VTK is imported where the dataset is built: a case written needs none
    from vtkmodules.vtkCommonDataModel import vtkMultiBlockDataSet

    from pinn_engine.blocks3d.section import Section

METHODS = ("pinn", "elliptic", "tfi")
# a figure within this many degrees (non-orthogonality) or this much (skewness) of
# blockMesh's counts as no worse: round-off of grids that are the same
SAME_ANGLE, SAME_SKEW = 1e-6, 1e-9
# a cyclic pair's nodes correspond where blockMesh places them this close (share of the
# diagonal) to one side translated
CONGRUENT = 1e-8
# blockMesh's placement no more non-orthogonal than this (degrees) anywhere is kept by the
# default without solving: the solve could gain at most this, where OpenFOAM's
# non-orthogonal correction (tan 1 deg < 0.02 of a face's flux) is already negligible
ORTHOGONAL = 1.0
# where the Winslow grid is worse than blockMesh's placement on one aim (its skewness, where
# graded cells meet a curved inner block), the grids between them, placement + t (Winslow -
# placement), are searched for the largest t meeting every aim by this many bisections (t
# within 1/32 of it: on a butterfly pipe with bulging centre edges, 0.02 degrees of
# non-orthogonality a step of 1/32)
BLEND_BISECTIONS = 5
UNSOLVED = f"blockMesh's placement is within {ORTHOGONAL:g} deg of orthogonal everywhere"
SKIPPED = "the network would train on the Winslow equations alone, which the elliptic grid solves"


@dataclass
class DictResult:
    """A meshed dictionary: the placement (ids, patches), the chosen ``points``, the
    ``method`` given and the grid ``kept`` (``elliptic`` or ``tfi``), each candidate's
    checkMesh figures, the cells' faces (each once), the report and each block's largest
    and smallest face angles."""

    place: Placement
    points: np.ndarray
    method: str
    kept: str
    candidates: dict[str, Figures]
    faces: FaceTopology
    blend: float | None = None  # a blend's share of the way to the Winslow grid
    start: str | None = None  # the grid the optimised section started from
    report: dict = field(default_factory=dict)
    angles: list[tuple[np.ndarray, np.ndarray]] = field(default_factory=list)

    @property
    def cells(self) -> np.ndarray:
        """Every block's hexahedra (OpenFOAM's corner order), block by block."""
        return np.vstack([hexes(ids) for ids in self.place.ids])

    def block_nodes(self) -> list[np.ndarray]:
        """Each block's nodes (ni+1, nj+1, nk+1, 3)."""
        return [self.points[ids] for ids in self.place.ids]


def no_worse(a: Figures, b: Figures) -> bool:
    """Whether ``a`` meets SPEC 15's aims against ``b``: no fold, largest non-orthogonality
    and skewness no worse."""
    return (
        a.folded == 0
        and a.max_non_orthogonality <= b.max_non_orthogonality + SAME_ANGLE
        and a.max_skewness <= b.max_skewness + SAME_SKEW
    )


def mesh_dictionary(
    d: BlockMeshDict,
    method: str = "pinn",
    free_interfaces: bool = True,
    progress: Callable[[str, float], object] | None = None,
) -> DictResult:
    """The grid of ``d`` by ``method`` (see the module); ``progress(stage, fraction)``
    hears the stages."""
    if method not in METHODS:
        raise InputError(f"--method {method}: a blockMeshDict takes {', '.join(METHODS)}")
    timings: dict[str, float] = {}
    began = time.perf_counter()

    def stage(name: str, fraction: float) -> None:
        if progress is not None:
            progress(name, fraction)

    stage("placing the blocks", 0.0)
    placed = place(d)
    cells = np.vstack([hexes(ids) for ids in placed.ids])
    timings["place"] = time.perf_counter() - began
    faces = topology(cells)
    candidates = {"tfi": figures(placed.points, cells, faces)}
    if candidates["tfi"].folded:
        raise InputError(
            f"blockMesh's placement folds {candidates['tfi'].folded} cells: check the "
            "vertex order of the blocks (each right-handed) and the curved edges",
            d.source,
        )
    points, kept, steps, share, start = placed.points, "tfi", 0, None, None
    orthogonal = candidates["tfi"].max_non_orthogonality <= ORTHOGONAL
    if method == "elliptic" or (method == "pinn" and not orthogonal):
        from pinn_engine.blocks3d.section import section
        from pinn_engine.blocks3d.winslow import boundary_held  # scipy: only where it solves

        stage("solving the Winslow equations over all blocks", 0.1)
        t0 = time.perf_counter()

        def step(k: int, moved: float) -> None:
            stage(f"Winslow step {k} (largest move {moved:.2e} of the diagonal)", 0.1)

        sec = section(placed, boundary_held(placed)[1])
        solved, steps = winslow_grid(placed, sec, free_interfaces, step)
        solved = _cyclic_congruent(d, placed, _through_empty(placed, solved))
        timings["solve"] = time.perf_counter() - t0
        measure = measure_of(placed, sec, free_interfaces, cells, faces)
        candidates["elliptic"] = measure(solved)
        if method == "elliptic":
            if candidates["elliptic"].folded:
                raise InputError(
                    f"the elliptic grid folds {candidates['elliptic'].folded} cells; "
                    "use --method tfi (blockMesh's placement)",
                    d.source,
                )
            points, kept = solved, "elliptic"
        elif no_worse(candidates["elliptic"], candidates["tfi"]):
            points, kept = solved, "elliptic"
        else:
            t, blend = _blend(placed.points, solved, measure, candidates["tfi"])
            if blend is not None:
                candidates["blend"], share = blend, t
                points, kept = placed.points + t * (solved - placed.points), "blend"
        if method == "pinn":
            stage("the least non-orthogonal section", 0.8)
            t0 = time.perf_counter()
            begins = {kept: points, "tfi": placed.points}
            better = _least_non_orthogonal(d, placed, sec, begins, measure, candidates[kept])
            timings["section"] = time.perf_counter() - t0
            if better is not None:
                points, candidates["optimised"], start = better
                kept = "optimised"
    timings["total"] = time.perf_counter() - began
    result = DictResult(placed, points, method, kept, candidates, faces, share, start)
    result.report = _report(d, result, steps, timings, free_interfaces)
    if method == "pinn" and orthogonal:
        result.report["unsolved"] = UNSOLVED
    stage("done", 1.0)
    return result


def _blend(
    placed: np.ndarray,
    solved: np.ndarray,
    measure: Callable[[np.ndarray], Figures],
    reference: Figures,
) -> tuple[float, Figures | None]:
    """The largest share t (bisected ``BLEND_BISECTIONS`` times) for which the grid
    ``placed + t (solved - placed)`` is no worse than ``reference`` and at least
    ``ORTHOGONAL`` degrees less non-orthogonal (a smaller gain matters to no solver), and its
    figures (None: no such grid). Boundary nodes stay on their planes (both grids hold them
    there) and curved faces (both keep blockMesh's nodes)."""
    low, high, found = 0.0, 1.0, None
    for _ in range(BLEND_BISECTIONS):
        t = 0.5 * (low + high)
        f = measure(placed + t * (solved - placed))
        good = no_worse(f, reference)
        if good and f.max_non_orthogonality <= reference.max_non_orthogonality - ORTHOGONAL:
            low, found = t, f
        else:
            high = t
    return low, found


def measure_of(
    placed: Placement, sec: Section | None, free: bool, cells: np.ndarray, faces: FaceTopology
) -> Callable[[np.ndarray], Figures]:
    """checkMesh's figures of the grids the solve and the search make: where every one is
    swept from ``sec`` (its interfaces ``free``, its slab the smaller, each column the same
    cells) measured on the slab (``section.SlabFigures``: pipe 0.03 s of CPU a grid less,
    DFG 3D 0.1 s), else on ``cells``."""
    from pinn_engine.blocks3d.section import SlabFigures

    if sec is not None and free and len(placed.points) > 2 * len(sec.nodes):
        count = np.bincount(sec.column)
        if (count == count[0]).all():
            return SlabFigures(placed, sec, int(count[0]) - 1)
    return lambda points: figures(points, cells, faces)


def winslow_grid(
    placed: Placement,
    sec: Section | None,
    free_interfaces: bool = True,
    progress: Callable[[int, float], object] | None = None,
) -> tuple[np.ndarray, int]:
    """The Winslow grid over all blocks and its Picard steps. A swept section ``sec``, its
    interfaces free, is solved as its slab one cell thick and swept along the axis: the
    same equations (a swept grid has no derivative along the axis), a layer's share of the
    work (DFG 3D: 0.27 s of CPU against 2.3 over its 28 layers); the slab's back face is
    its front's mirror image and moves with it, so one face is solved for (``twin``: DFG 3D
    0.19 -> 0.13 s, backwardFacingStep2D 1.5 -> 0.8 s)."""
    from pinn_engine.blocks3d.section import slab, swept, thin
    from pinn_engine.blocks3d.winslow import winslow

    if sec is None or not free_interfaces:
        return winslow(placed, free_interfaces=free_interfaces, progress=progress)
    twin = np.tile(np.arange(len(sec.nodes)), 2)  # the slab's back face mirrors its front
    points, steps = winslow(slab(placed, sec), progress=progress, twin=twin)
    return swept(placed.points, sec, thin(points, sec)), steps


def _least_non_orthogonal(
    d: BlockMeshDict,
    placed: Placement,
    sec: Section | None,
    begins: dict[str, np.ndarray],
    measure: Callable[[np.ndarray], Figures],
    start: Figures,
) -> tuple[np.ndarray, Figures, str] | None:
    """The grid of a swept blocking whose section is the least non-orthogonal under the
    skewness of ``start`` (the figures of the grid chosen so far), its figures and the name
    of the grid of ``begins`` (the grid chosen and blockMesh's placement) its search began
    from, the better of the searches from each (the second skipped where the first reaches
    ``ORTHOGONAL``): the Winslow grid's smooth cells can lie in a basin of their own (a
    butterfly pipe's centre square of 0.6 R: 13.6 degrees from it, 3.0 from the placement).
    None where ``sec`` (the blocking's swept section) is None, or no grid found is at least
    ``ORTHOGONAL`` degrees less non-orthogonal with no worse skewness and no fold."""
    from pinn_engine.blas import one_thread
    from pinn_engine.blocks3d.section import least_non_orthogonal, start_of, swept

    if sec is None:
        return None
    found = []
    for name, begin in begins.items():
        with one_thread():  # L-BFGS's vectors are far too small for BLAS threads
            xy = least_non_orthogonal(start_of(begin, sec), sec, start.max_skewness)
        out = _cyclic_congruent(d, placed, swept(begin, sec, xy))
        got = measure(out)
        if no_worse(got, start) and (
            got.max_non_orthogonality <= start.max_non_orthogonality - ORTHOGONAL
        ):
            found.append((got.max_non_orthogonality, len(found), out, got, name))
            if got.max_non_orthogonality <= ORTHOGONAL:
                break  # the next search could gain less than ORTHOGONAL: none that matters
    return min(found)[2:] if found else None


def _through_empty(placed: Placement, points: np.ndarray) -> np.ndarray:
    """A 2D dictionary's grid with each node pair across its one cell, between its two
    ``empty`` patches, on one normal of those planes: the two planes are solved apart and
    meet each other only to the Picard tolerance, while OpenFOAM's 2D check wants the
    edges between them aligned with the normal to round-off."""
    empty = np.zeros(len(points), dtype=bool)
    for _, kind, faces in placed.patches:
        if kind == "empty":
            empty[faces.ravel()] = True
    out = points.copy()
    for ids in placed.ids:
        for axis in range(3):
            if ids.shape[axis] != 2:
                continue
            front, back = np.take(ids, 0, axis=axis).ravel(), np.take(ids, 1, axis=axis).ravel()
            if not (empty[front].all() and empty[back].all()):
                continue
            gap = points[back] - points[front]
            centred = points[front] - points[front].mean(axis=0)
            normal = np.linalg.svd(centred, full_matrices=False)[2][-1]  # the plane's normal
            slip = 0.5 * (gap - np.outer(gap @ normal, normal))
            out[front] = points[front] + slip
            out[back] = points[back] - slip
    return out


def _cyclic_congruent(d: BlockMeshDict, placed: Placement, points: np.ndarray) -> np.ndarray:
    """A grid with each translational cyclic pair's two sides congruent: the solve slides
    their nodes apart by up to its tolerance, while OpenFOAM matches the pair's faces to
    1e-4 of their size. The nodes are paired where blockMesh's placement has one side the
    other translated, and each pair keeps its placed offset."""
    faces = {name: f for name, _, f in placed.patches}
    diag = float(np.linalg.norm(np.ptp(placed.points, axis=0)))
    out = points.copy()
    for patch in d.patches:
        other = patch.extra.get("neighbourPatch")
        if patch.type != "cyclic" or other not in faces or str(other) <= patch.name:
            continue  # each pair once
        a, b = np.unique(faces[patch.name]), np.unique(faces[other])
        if len(a) != len(b):
            continue
        shift = placed.points[b].mean(axis=0) - placed.points[a].mean(axis=0)
        ia = a[np.lexsort(np.round((placed.points[a] + shift) / (CONGRUENT * diag)).T)]
        ib = b[np.lexsort(np.round(placed.points[b] / (CONGRUENT * diag)).T)]
        if np.abs(placed.points[ia] + shift - placed.points[ib]).max() > CONGRUENT * diag:
            continue  # not a translation (a rotational pair): left as solved
        # each side moved by half the pair's departure from its placed offset: a held
        # coordinate (the sides' planes) departs by nothing and stays as it is
        half = 0.5 * ((points[ib] - points[ia]) - (placed.points[ib] - placed.points[ia]))
        out[ia], out[ib] = points[ia] + half, points[ib] - half
    return out


def _report(d, result: DictResult, steps: int, timings: dict, free: bool) -> dict:
    chosen = result.candidates[result.kept]
    angles = result.angles = [included_angles(g) for g in result.block_nodes()]
    biggest = np.concatenate([a[0] for a in angles])
    spec6 = {  # SPEC 6's figures, over every cell
        "mean_max_angle": float(biggest.mean()),
        "worst_max_angle": float(biggest.max()),
        "worst_min_angle": float(min(a[1].min() for a in angles)),
    }
    report = {
        "method": result.method,
        "kept": result.kept,
        "blend": result.blend,
        "start": result.start,
        "source": d.source,
        "blocks": len(d.blocks),
        "cells": int(len(result.cells)),
        "points": int(len(result.points)),
        "interfaces": "free" if free else "fixed",
        "patches": {
            name: {"type": kind, "faces": len(f)} for name, kind, f in result.place.patches
        },
        "candidates": {k: v.as_dict() for k, v in result.candidates.items()},
        "quality": {**chosen.as_dict(), **spec6},
        "winslow_steps": steps,
        "timings": timings,
    }
    if result.method == "pinn":  # the kept start moved no node: no network was trained
        report["training"] = {
            "skipped": SKIPPED,
            "result": "start",
            "start": result.kept,
            "largest_node_move": 0.0,
        }
    return report


def _string(fd, name: str, value: str) -> None:
    from vtkmodules.vtkCommonCore import vtkStringArray

    arr = vtkStringArray()
    arr.SetName(name)
    arr.InsertNextValue(value)
    fd.AddArray(arr)


def _own_figures(biggest: np.ndarray, smallest: np.ndarray, folds: np.ndarray) -> dict:
    """SPEC 6's figures of one block's own cells."""
    return {
        "mean_max_angle": float(biggest.mean()),
        "worst_max_angle": float(biggest.max()),
        "worst_min_angle": float(smallest.min()),
        "folded_cells": int(folds.sum()),
    }


def dataset(result: DictResult) -> vtkMultiBlockDataSet:
    """The blocks as a ``vtkMultiBlockDataSet`` of ``vtkStructuredGrid`` (``block0``, ...)
    with SPEC 11's cell arrays, the structured indices ``i``, ``j``, ``k`` as point arrays,
    the method asked as ``Method``, the figures of each block's own cells as field data, and
    the whole run's report (the grid kept, checkMesh's figures) as ``Report``."""
    import json

    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import (
        vtkCompositeDataSet,
        vtkMultiBlockDataSet,
        vtkStructuredGrid,
    )

    out = vtkMultiBlockDataSet()
    blocks = result.block_nodes()
    out.SetNumberOfBlocks(len(blocks))
    for k, (g, (biggest, smallest)) in enumerate(zip(blocks, result.angles)):
        grid = vtkStructuredGrid()
        grid.SetDimensions(*g.shape[:3])
        pts = vtkPoints()
        flat = np.ascontiguousarray(g.transpose(2, 1, 0, 3).reshape(-1, 3))
        pts.SetData(numpy_to_vtk(flat, deep=True))
        grid.SetPoints(pts)
        folds = folded(g).astype(float)
        arrays = {
            "MaxIncludedAngle": biggest,
            "MinIncludedAngle": smallest,
            "ScaledJacobian": scaled_jacobian(grid),
            "Folded": folds,
        }
        for name, values in arrays.items():
            arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=float), deep=True)
            arr.SetName(name)
            grid.GetCellData().AddArray(arr)
        grid.GetCellData().SetActiveScalars("MaxIncludedAngle")
        kk, jj, ii = np.indices(g.shape[2::-1])  # i fastest, as the points
        for name, values in (("i", ii), ("j", jj), ("k", kk)):
            arr = numpy_to_vtk(np.ascontiguousarray(values.ravel(), dtype=np.int32), deep=True)
            arr.SetName(name)
            grid.GetPointData().AddArray(arr)
        fd = grid.GetFieldData()
        _string(fd, "Method", result.method)
        _string(fd, "Report", json.dumps({**result.report, "block": k}, default=float))
        for name, value in _own_figures(biggest, smallest, folds).items():
            arr = numpy_to_vtk(np.array([value], dtype=float), deep=True)
            arr.SetName(name)
            fd.AddArray(arr)
        out.SetBlock(k, grid)
        out.GetMetaData(k).Set(vtkCompositeDataSet.NAME(), f"block{k}")
    return out
