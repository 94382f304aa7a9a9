"""A four-sided domain or a body (SPEC 5 and 9): its geometry from files or VTK data, and its
run, one block by the block kind ``settings.topology`` names."""

from __future__ import annotations

import os
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field, replace
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.kinds.four_sided.cache import MeshCache
from pinn_engine.kinds.outcome import Outcome, network_trained
from pinn_engine.settings import DEFAULT_SIZE, Settings

if TYPE_CHECKING:
    from vtkmodules.vtkCommonDataModel import vtkPolyData

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
    ``body`` inside its far field ``far`` (SPEC 9); ``patches`` name the grid's sides (any
    form ``export.patch_names`` takes; None: bottom, right, top, left, or a body's wall,
    seam or outflow, far field)."""

    boundary: object | None = None  # geometry.boundary.Boundary
    aux: list = field(default_factory=list)  # geometry.auxlines.AuxLine
    body: object | None = None  # bodies.airfoil.Body
    far: object | None = None  # bodies.airfoil.FarField
    patches: object | None = None


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
    patches=None,
) -> Geometry:
    """The geometry of files: a boundary (``.vtp``, ``.vtk``, ``.csv``, ``.txt``) with
    auxiliary-line files, or (``settings.topology`` o or c) a body: an airfoil ``.dat``
    (with the far-field circle), a file of two closed polylines (body inside far field, or
    one body with the circle when ``farfield_given``), or ``settings.naca``; its sides named
    ``patches``."""
    found = _from_files(settings, boundary, aux, corners, farfield_given)
    return replace(found, patches=patches)


def _from_files(
    settings: Settings,
    boundary: str | os.PathLike | None,
    aux: Sequence[str | os.PathLike],
    corners: Sequence[int] | None,
    farfield_given: bool,
) -> Geometry:
    """:func:`geometry_from_files` without the patches."""
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


def topology_of(inputs: Sequence[vtkPolyData | None]) -> str:
    """The topology VTK inputs ask for when none is chosen: "o" for a body (one input
    holding an airfoil-like curve, as the Airfoil source and reader give, or two closed
    polylines, a body inside its far field), else "none" (a four-sided domain)."""
    from pinn_engine.io.fileio import polylines_of

    polys = [p for p in inputs if p is not None and p.GetNumberOfPoints()]
    if len(polys) != 1:
        return "none"
    try:
        lines = polylines_of(polys[0])
    except InputError:
        return "none"
    rings = len(lines) == 2 and all(closed for _, closed in lines)
    return "o" if rings or _looks_like_body(polys[0]) else "none"


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
    patches=None,
) -> Geometry:
    """The geometry of VTK inputs: the boundary is the one closed curve among ``inputs``, the
    open polylines there and ``aux`` are auxiliary lines; or (``settings.topology`` o or c)
    the body of the first non-empty input (or ``settings.naca``); its sides named
    ``patches``."""
    found = _from_polydata(settings, inputs, aux, corners, source)
    return replace(found, patches=patches)


def _from_polydata(
    settings: Settings,
    inputs: Sequence[vtkPolyData | None],
    aux: Sequence[vtkPolyData],
    corners: Sequence[int] | None,
    source: str,
) -> Geometry:
    """:func:`geometry_from_polydata` without the patches."""
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


def run_single(
    settings: Settings,
    geometry: Geometry,
    progress: Callable[[dict], bool | None] | None = None,
    cache: MeshCache | None = None,
    model: str | os.PathLike | None = None,
) -> Outcome:
    """Mesh ``geometry`` at ``settings.size`` nodes (default ``DEFAULT_SIZE``): a four-sided
    block through the fitted-network ``cache`` (or the saved model at ``model``, evaluated on
    this boundary), a body through its block kind."""
    from pinn_engine.io.export import patch_names
    from pinn_engine.io.export.patches import body_patch_names as body_patches
    from pinn_engine.io.pipeline import to_vtk
    from pinn_engine.kinds.body.mesh import mesh_body

    ni, nj = settings.size or DEFAULT_SIZE
    if settings.topology == "none":
        names = patch_names(geometry.patches)  # refused before meshing, not after
        trained = False
        if model is not None:
            # a four-sided run's: not a body's import
            from pinn_engine.kinds.four_sided.mesher import Mesher

            mesher, result = Mesher.load(model, geometry.boundary), None
        else:
            cache = cache if cache is not None else MeshCache(capacity=1)
            mesher, trained, result = _cached(cache, geometry, settings, ni, nj, progress)
        if result is None:
            result = mesher.predict(ni, nj)
        grid = to_vtk(result, names)
        return Outcome(
            "four-sided", grid, result.report, [result.points], result.history, trained, mesher
        )
    names = patch_names(geometry.patches, body_patches(settings.topology))
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
    grid = to_vtk(result, names)
    return Outcome(
        "body", grid, result.report, [result.points], result.history, network_trained(result.report)
    )


def _cached(
    cache: MeshCache,
    geometry: Geometry,
    settings: Settings,
    ni: int,
    nj: int,
    progress: Callable[[dict], bool | None] | None,
) -> tuple[object, bool, object]:
    """A four-sided run through ``cache``: (its mesher, whether a network was trained now,
    its grid where already made). A network trained at another size is evaluated at this one
    and kept where it passes this size's guard (kinds.four_sided.resize); else the mesher
    fitted for these settings, trained if new, with the failed guard in its report."""
    other = cache.trained_elsewhere(geometry.boundary, geometry.aux, settings)
    resize = None
    if other is not None:
        from pinn_engine.kinds.four_sided.resize import noted, resized

        result, resize = resized(other, geometry.aux, settings, ni, nj)
        if result is not None:
            return other, False, result
    mesher, trained = cache.fitted(geometry.boundary, geometry.aux, settings, progress)
    if resize is None:
        return mesher, trained, None
    result = mesher.predict(ni, nj)
    noted(result, resize)
    return mesher, trained, result
