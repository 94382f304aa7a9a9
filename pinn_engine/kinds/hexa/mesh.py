"""A hexahedral grid of a six-faced surface, from file to vtkStructuredGrid (SPEC 11): the
``hexa`` package's face grids and volume grids, or the hexahedral block kind for pinn (above
``blocks``, as ``kinds.body.mesh`` is for bodies); the solver formats write it through
:func:`pinn_engine.io.export.write`."""

from __future__ import annotations

import hashlib
import json
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from functools import cache, partial
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkPoints, vtkStringArray
from vtkmodules.vtkCommonDataModel import vtkPolyData, vtkStructuredGrid

from pinn_engine.errors import InputError, network_effect
from pinn_engine.hexa import quality, volume
from pinn_engine.hexa.block import cube_corners
from pinn_engine.hexa.facegrid import FaceMap
from pinn_engine.hexa.orthogonal import inner_angles, orthogonal_grid
from pinn_engine.hexa.spacing import (
    PATCH_AXIS,
    check_spacing,
    first_edges,
    fit_params,
    node_params,
    tfi_at,
)
from pinn_engine.hexa.surface import Surface, Topology, find_topology, surface_of
from pinn_engine.io import fileio
from pinn_engine.io.export.patches import BOX_SIDES, add_to_grid, named_patches, patch_specs
from pinn_engine.kinds.hexa.start import Start, better_start, winslow_start
from pinn_engine.patchnames import FACE_PREFIX
from pinn_engine.settings import Settings

if TYPE_CHECKING:
    from pinn_engine.kinds.hexa.problem import HexaModel
    from pinn_engine.kinds.hexa.untrained import VolumeStartModel
    from pinn_engine.neural.trainer import Progress

FACE_IDS = "FaceIds"  # field data: the input's FaceId of imin ... kmax


@dataclass
class HexResult:
    """The grid (ni, nj, nk, 3), its cell arrays, the run's seconds, the Winslow solve's
    Picard steps, for pinn its map (the trained HexaModel, or the untrained start's), the
    input face of each side, the sides' patch names and types and the seconds per stage."""

    grid: np.ndarray
    cells: dict[str, np.ndarray]
    seconds: float
    iterations: int
    walls: dict[str, tuple[float, float, float]] = field(default_factory=dict)
    model: HexaModel | VolumeStartModel | None = None
    faces: dict[str, int] = field(default_factory=dict)  # side -> the input's FaceId
    patches: tuple[tuple[str, ...], tuple[str, ...]] = patch_specs(None, sides=BOX_SIDES)
    timings: dict[str, float] = field(default_factory=dict)  # seconds per stage


def boundary_map(
    surface: Surface, topology: Topology, source: str
) -> tuple[Callable[[np.ndarray], np.ndarray], tuple[int, ...]]:
    """A function of node parameters (ni, nj, nk, 3) giving an array of that shape whose six
    faces hold the face grids at those parameters (interior zero; the face maps are built
    once), and the face index of each of imin ... kmax."""
    cube = cube_corners(surface, topology, source)
    faces = []
    for axis in range(3):
        a, b = (x for x in range(3) if x != axis)
        for value in (0, 1):

            def corner(ta: int, tb: int, a=a, b=b, axis=axis, value=value) -> int:
                c = [0, 0, 0]
                c[axis], c[a], c[b] = value, ta, tb
                return cube[tuple(c)]

            ring = {corner(0, 0), corner(1, 0), corner(0, 1), corner(1, 1)}
            face = next(f for f, cs in enumerate(topology.face_corners) if set(cs) == ring)
            sides = {
                "a0": topology.edges[(corner(0, 0), corner(1, 0))],
                "a1": topology.edges[(corner(0, 1), corner(1, 1))],
                "b0": topology.edges[(corner(0, 0), corner(0, 1))],
                "b1": topology.edges[(corner(1, 0), corner(1, 1))],
            }
            at = [slice(None)] * 3
            at[axis] = 0 if value == 0 else -1
            faces.append(
                (tuple(at), [a, b], FaceMap(surface, topology.face_triangles[face], sides), face)
            )

    last: list[np.ndarray] = []  # the last parameters and their grid: runs ask for them again

    def boundary(params: np.ndarray) -> np.ndarray:
        if last and last[0].shape == params.shape and np.array_equal(last[0], params):
            return last[1].copy()
        g = np.zeros(params.shape)
        for at, axes, face, _ in faces:
            g[at] = face.grid(params[at][..., axes])
        last[:] = [params.copy(), g.copy()]
        return g

    return boundary, tuple(face for *_, face in faces)


def face_names(surface: Surface, faces: Sequence[int]) -> dict[str, int]:
    """Side (imin ... kmax) -> the input's FaceId of that face, from the face indices of
    :func:`boundary_map`."""
    return {side: int(surface.face_ids[f]) for side, f in zip(BOX_SIDES, faces, strict=True)}


def by_side(
    spacing: dict[str, float], orthogonal: tuple[str, ...], faces: dict[str, int]
) -> tuple[dict[str, float], tuple[str, ...]]:
    """``spacing`` and ``orthogonal`` with their ``faceN`` patches (the input face whose
    FaceId is N) named by the side that face became (``faces``: :func:`face_names`)."""
    side_of = {f"{FACE_PREFIX}{face}": side for side, face in faces.items()}
    listed = ", ".join(sorted(side_of, key=lambda name: int(name[len(FACE_PREFIX) :])))

    def side(name: str, flag: str) -> str:
        if name in BOX_SIDES:
            return name
        if name not in side_of:
            raise InputError(f"{flag} {name}: the surface has no {name} (its faces: {listed})")
        return side_of[name]

    out: dict[str, float] = {}
    for name, h in spacing.items():
        if out.setdefault(side(name, "{spacing}"), h) != h:
            raise InputError(
                f"{{spacing}} {name}={h:g}: patch {side(name, '')} is given two spacings"
            )
    walls = tuple(dict.fromkeys(side(name, "{orthogonal}") for name in orthogonal))
    return out, walls


def surface_key(surface: Surface) -> str:
    """A digest of the surface's points and triangles: a saved pinn model is evaluated only
    on the surface it was trained on."""
    digest = hashlib.sha256(np.ascontiguousarray(surface.points).tobytes())
    digest.update(np.ascontiguousarray(surface.triangles).tobytes())
    return digest.hexdigest()


def volume_grid(
    boundary: Callable[[np.ndarray], np.ndarray],
    method: str,
    spacing: dict[str, float],
    orthogonal: tuple[str, ...],
) -> Callable[[np.ndarray], np.ndarray]:
    """The method's grid as a function of node parameters: TFI of the face grids at them,
    or (elliptic) the Winslow grid with the distribution's control terms, each solve starting
    from the previous one's interior, its lines turned onto the ``orthogonal`` patches'
    normals (``orthogonal.orthogonal_grid``). ``evaluate.steps``: the last solve's Picard
    steps."""
    last: list = [None]

    def evaluate(params: np.ndarray) -> np.ndarray:
        g = tfi_at(boundary, params)
        if method != "elliptic":
            return g
        inner = (slice(1, -1),) * 3
        if last[0] is not None:
            g[inner] = last[0][inner]
        g, evaluate.steps = volume.winslow(g, params=params if spacing else None)
        last[0] = g
        if orthogonal:
            g = orthogonal_grid(g, orthogonal, params, spacing, bool(spacing))
        return g

    evaluate.steps = 0
    return evaluate


def _classical(
    boundary: Callable[[np.ndarray], np.ndarray],
    method: str,
    spacing: dict[str, float],
    orthogonal: tuple[str, ...],
    base: np.ndarray,
) -> tuple[np.ndarray, np.ndarray, int]:
    """The tfi or elliptic grid (:func:`volume_grid`) at uniform node parameters, or with a
    spacing at the parameters fitted to it (on the cheap TFI grids first: the Winslow grid
    then needs few rounds); ``base`` is the uniform TFI grid. Returns (params, grid, Picard
    steps)."""
    evaluate = volume_grid(boundary, method, spacing, orthogonal)
    uniform = node_params(base.shape[:3], {})
    if not spacing:
        return uniform, evaluate(uniform), evaluate.steps
    first_guess = None
    if method == "elliptic":
        first_guess = fit_params(volume_grid(boundary, "tfi", spacing, orthogonal), spacing, base)[
            2
        ]
    params, g, _ = fit_params(evaluate, spacing, base, first_guess)
    return params, g, evaluate.steps


def wall_angle(g: np.ndarray, patches: tuple[str, ...]) -> float:
    """The largest angle in degrees of a grid line from the normal of an orthogonal patch
    (its rim's nodes aside, as :func:`wall_figures`)."""
    return max(float(inner_angles(g, patch).max(initial=0.0)) for patch in patches)


def spacing_error(g: np.ndarray, spacing: dict[str, float]) -> float:
    """The largest relative error of the first edges off the spaced patches (their four
    corners aside, as :func:`wall_figures`)."""
    worst = 0.0
    for patch, h in spacing.items():
        edges = first_edges(g, patch)
        edges[[0, 0, -1, -1], [0, -1, 0, -1]] = h
        worst = max(worst, float(np.abs(edges / h - 1.0).max()))
    return worst


def mesh_surface(path: str, settings: Settings) -> HexResult:
    """Read ``path`` (an ``.stl``'s faces are found at its sharp edges) and mesh it under
    ``settings`` (:func:`mesh_polydata`)."""
    data = fileio.read_polydata(Path(path))
    return mesh_polydata(data, settings, path, sharp_edges=str(path).lower().endswith(".stl"))


def mesh_polydata(
    data: vtkPolyData,
    settings: Settings,
    source: str,
    progress: Callable[[float, str], None] | None = None,
    *,
    sharp_edges: bool = False,
    load_model: str | None = None,
    patches: Mapping[str, str] | Sequence[str] | str | None = None,
    training: Progress | None = None,
) -> HexResult:
    """The hexahedral grid of a surface in memory (a polydata with a FaceId cell array, or
    with ``sharp_edges`` faces found at its edges sharper than ``settings.face_angle``
    degrees), ``source`` naming it in messages, by ``settings.method`` at ``settings.size``
    nodes, with ``settings.spacing`` (patch -> first edge H) and ``settings.orthogonal``
    (patches) as SPEC 7 on the patches; ``patches`` names them (:func:`named_patches`,
    checked before meshing); pinn trains its network (for at most ``settings.time_limit``
    seconds; ``training`` is the trainer's progress callback, whose ``errors.STOP`` ends it
    with the best grid so far), or evaluates the one saved at ``load_model``;
    ``progress(fraction, phase)`` is told each phase as it starts."""
    tell = progress or (lambda fraction, phase: None)
    method, size = settings.method, settings.size
    spacing, orthogonal = dict(settings.spacing), settings.orthogonal
    began = time.perf_counter()
    timings: dict[str, float] = {}

    def lap(stage: str) -> None:
        """Record the seconds since the last stage as ``stage``'s."""
        timings[stage] = time.perf_counter() - began - sum(timings.values())

    tell(0.0, "face grids")
    surface = surface_of(data, source, sharp_edges, settings.face_angle)
    topology = find_topology(surface, source)
    boundary, sides = boundary_map(surface, topology, source)
    faces = face_names(surface, sides)
    named = named_patches(patches, faces)
    spacing, orthogonal = by_side(spacing, orthogonal, faces)
    base = tfi_at(boundary, node_params(size, {}))
    check_spacing(spacing, base)
    lap("faces")
    model, elliptic = None, []  # the untrained start's grid: the elliptic run's
    if method == "pinn":  # the elliptic and tfi runs import no training modules
        from pinn_engine.kinds.hexa.untrained import VolumeStartModel
        from pinn_engine.kinds.untrained import TFI_START, WINSLOW, cannot_win, start_or_train

        @cache  # the start's lattice is often the grid's own size
        def tfi_of(shape: tuple[int, ...]) -> np.ndarray:
            """The TFI grid of ``shape`` nodes, its faces exactly the face grids."""
            return base if shape == tuple(size) else tfi_at(boundary, node_params(shape, {}))

        def kept(reason: str) -> tuple[VolumeStartModel, np.ndarray]:
            """The start's map (no network, no torch) and the TFI grid it corrects."""
            winslow = winslow_start(tfi_of, size)
            lap("start")
            elliptic.append(winslow.grid)
            start = better_start(winslow)
            reason = TFI_START if start.name == "tfi" and reason == WINSLOW else reason
            return VolumeStartModel.of(start, settings, key, reason, timings["start"]), base

        def trained() -> tuple[HexaModel, np.ndarray]:
            """The trained map and the TFI grid it corrects."""
            from pinn_engine.kinds.hexa.problem import train  # torch: imported only to train

            tfi = base
            if spacing or orthogonal:  # the elliptic grid with them, at the full size
                params, grid, _ = _classical(boundary, "elliptic", spacing, orthogonal, base)
                tfi = tfi_at(boundary, params)
                start = Start(
                    tfi,
                    grid,
                    params if spacing else None,
                    partial(spacing_error, spacing=spacing) if spacing else None,
                    tuple((PATCH_AXIS[p][0], float(PATCH_AXIS[p][1] != 0)) for p in orthogonal),
                    partial(wall_angle, patches=orthogonal) if orthogonal else None,
                )
            else:
                start = better_start(winslow_start(tfi_of, size))
            lap("start")
            return train(start, key, settings, training), tfi

        tell(0.2, "network")
        key = surface_key(surface)
        if load_model:  # a saved network evaluated
            from pinn_engine.kinds.hexa.problem import HexaModel  # torch: only for a saved network

            if spacing or orthogonal:
                raise InputError(
                    "--load-model with --spacing or --orthogonal: a saved map keeps the "
                    "spacing and walls it was trained with; drop them, or train anew"
                )
            model, tfi = HexaModel.load(load_model, key), base
            lap("start")
        else:
            model, tfi = start_or_train(cannot_win(settings), kept, trained)
        g, steps = model.grid(tfi), 0
        lap("training")
    else:
        if method == "elliptic":
            tell(0.3, "3D Winslow")
        _, g, steps = _classical(boundary, method, spacing, orthogonal, base)
        lap("volume")
    tell(0.9, "quality")
    cells = cell_arrays(g)
    if elliptic:  # an untrained start: the elliptic run's grid
        same = elliptic[0].shape == g.shape and np.array_equal(elliptic[0], g)
        model.info["guard"]["elliptic"] = figures(cells if same else cell_arrays(elliptic[0]))
    walls = wall_figures(g, spacing, orthogonal)
    lap("quality")
    seconds = time.perf_counter() - began
    return HexResult(g, cells, seconds, steps, walls, model, faces, named, timings)


def wall_figures(
    g: np.ndarray, spacing: dict[str, float], orthogonal: tuple[str, ...]
) -> dict[str, tuple[float, float, float]]:
    """Per patch with a spacing or orthogonality: the first edges' min and max (the patch's
    corners aside) and the largest angle of a grid line from the normal (its rim's two
    nodes aside)."""
    out = {}
    for patch in BOX_SIDES:
        if patch in spacing or patch in orthogonal:
            edges = first_edges(g, patch)
            edges[[0, 0, -1, -1], [0, -1, 0, -1]] = np.nan
            angle = inner_angles(g, patch)
            out[patch] = (
                float(np.nanmin(edges)),
                float(np.nanmax(edges)),
                float(angle.max(initial=0.0)),
            )
    return out


def structured_grid(g: np.ndarray) -> vtkStructuredGrid:
    """A vtkStructuredGrid of the (ni, nj, nk, 3) array (i fastest, as VTK's); plain VTK,
    for ParaView's Python."""
    grid = vtkStructuredGrid()
    grid.SetDimensions(*g.shape[:3])
    points = vtkPoints()
    xyz = np.ascontiguousarray(g.transpose(2, 1, 0, 3).reshape(-1, 3), dtype=float)
    points.SetData(numpy_to_vtk(xyz, deep=True))
    grid.SetPoints(points)
    return grid


def cell_arrays(g: np.ndarray) -> dict[str, np.ndarray]:
    """SPEC 11's cell arrays of a grid."""
    largest, smallest = quality.included_angles(g)
    return {
        "MaxIncludedAngle": largest,
        "MinIncludedAngle": smallest,
        "ScaledJacobian": quality.scaled_jacobian(structured_grid(g)),
        "Folded": quality.folded(g),
    }


def figures(cells: dict[str, np.ndarray]) -> dict[str, float]:
    """The grid's summary figures: folded cells, min ScaledJacobian, mean and worst
    MaxIncludedAngle, worst MinIncludedAngle."""
    return {
        "folded_cells": int(cells["Folded"].sum()),
        "min_scaled_jacobian": float(cells["ScaledJacobian"].min()),
        "mean_max_angle": float(cells["MaxIncludedAngle"].mean()),
        "worst_max_angle": float(cells["MaxIncludedAngle"].max()),
        "worst_min_angle": float(cells["MinIncludedAngle"].min()),
    }


def report(result: HexResult, method: str) -> dict:
    """What the grid's field data ``Report`` holds: method, size, the input's FaceId of each
    of imin ... kmax (``faces``), cells, seconds (and per stage, ``timings``), Picard steps,
    :func:`figures` as ``quality``, per patch with a spacing or orthogonality its
    ``walls`` figures (:func:`wall_figures`, in the multi-block report's keys) and the
    pinn's ``training`` (the trainer's info)."""
    walls = {
        patch: {"first_edge": {"min": low, "max": high}, "max_angle_deviation": angle}
        for patch, (low, high, angle) in result.walls.items()
    }
    out = {
        "method": method,
        "size": list(result.grid.shape[:3]),
        "faces": dict(result.faces),
        "cells": int(result.cells["Folded"].size),
        "seconds": result.seconds,
        "timings": dict(result.timings),
        "iterations": result.iterations,
        "quality": figures(result.cells),
        **({"walls": walls} if walls else {}),
        **({"training": result.model.info} if result.model else {}),
    }
    choice = network_effect(out)
    return {**out, **({"choice": choice} if choice else {})}


def hexa_grid(result: HexResult, method: str) -> vtkStructuredGrid:
    """The grid with SPEC 11's cell arrays (active scalars MaxIncludedAngle) and field
    data: ``Method``, ``Report`` (JSON, :func:`report`), each figure of its ``quality`` as
    a number, ``FaceIds`` (the input's FaceId of imin ... kmax) and SPEC 8's
    ``PatchNames``, ``PatchTypes`` (the result's ``patches``). What every route hands
    over."""
    grid = structured_grid(result.grid)
    for name, values in result.cells.items():
        array = numpy_to_vtk(np.ascontiguousarray(values), deep=True)
        array.SetName(name)
        grid.GetCellData().AddArray(array)
    grid.GetCellData().SetActiveScalars("MaxIncludedAngle")
    fd = grid.GetFieldData()
    run = report(result, method)
    add_to_grid(grid, *result.patches)
    if result.faces:
        ids = numpy_to_vtk(np.array([result.faces[s] for s in BOX_SIDES]), deep=True)
        ids.SetName(FACE_IDS)
        fd.AddArray(ids)
    for name, texts in (("Method", [method]), ("Report", [json.dumps(run, default=float)])):
        array = vtkStringArray()
        array.SetName(name)
        for text in texts:
            array.InsertNextValue(text)
        fd.AddArray(array)
    if result.model:  # what the network did, as io/vtkgrid.py writes it for 2D
        training = result.model.info
        numbers = {"LargestNodeMove": training["largest_node_move"] or 0.0}
        texts = vtkStringArray()
        texts.SetName("NetworkResult")
        texts.InsertNextValue(training["result"])
        fd.AddArray(texts)
    else:
        numbers = {}
    for name, value in {**run["quality"], **numbers}.items():
        array = numpy_to_vtk(np.array([value], dtype=float), deep=True)
        array.SetName(name)
        fd.AddArray(array)
    return grid
