"""A six-faced 3D domain's hexahedral grid (SPEC 11): ``pinn_mesh_hexa``."""

from __future__ import annotations

from collections.abc import Sequence

import pyvista as pv

from pinn_engine.errors import SettingsError
from pinn_engine.routes.hexa_algorithm import PinnHexaAlgorithm, refold_hint
from pinn_engine.routes.pyvista_accessor.inputs import as_polydata
from pinn_engine.routes.pyvista_accessor.report import report
from pinn_engine.routes.pyvista_accessor.running import (
    ROUTE,
    node_counts,
    public,
    run,
    warn_folded,
)
from pinn_engine.settings import FACE_ANGLE, HEXA_SIZE, hexa_size_problem


@public("pinn_mesh_hexa")
def pinn_mesh_hexa(
    surface,
    size: Sequence[int] = HEXA_SIZE,
    method: str | None = None,
    *,
    patches=None,
    spacing=None,
    orthogonal=None,
    face_angle: float = FACE_ANGLE,
    progress_bar: bool = False,
) -> pv.StructuredGrid:
    """Hexahedral structured grid (SPEC 11) of the 3D domain a closed surface bounds.

    Parameters
    ----------
    surface : pyvista.PolyData or vtkPolyData
        A closed triangulated (or polygonal) surface with a cell array ``FaceId`` of six
        values whose faces meet as a cube's do; without ``FaceId`` (an STL's surface) its
        faces are found where it bends by more than ``face_angle`` degrees.
    size : (int, int, int)
        Nodes along i, j and k, default ``(21, 21, 21)``.
    method : str, optional
        One of ``pinn_engine.settings.HEXA_METHODS`` (``"tfi"``: 3D transfinite interpolation;
        ``"elliptic"``: 3D Winslow), default ``pinn_engine.settings.HEXA_METHOD``.
    patches : dict, sequence of six names or str, optional
        Patch names of the six faces, e.g. ``{"imin": "inlet:inflow", "face4": "floor:wall"}``
        (a side imin ... kmax or ``faceN``, the input face whose ``FaceId`` is N; default
        imin ... kmax; equal names form one patch), each optionally typed as
        ``"NAME:TYPE"``; stored as field data ``PatchNames`` and ``PatchTypes`` and used by
        :func:`save_mesh`.
    spacing : dict or sequence of str, optional
        First grid edge leaving a face, ``{"kmin": 0.002}`` or ``["kmin=0.002"]`` (faces
        imin ... kmax; SPEC 7 on the patches, docs/hexa.md).
    orthogonal : str or sequence of str, optional
        Faces that grid lines leave along the normal, ``"kmin"`` or ``["kmin", "kmax"]``
        (elliptic and pinn).
    face_angle : float, optional
        Neighbouring triangles whose normals differ by more than this many degrees lie on
        two faces (a surface without ``FaceId``); default 40 (SPEC 11).
    progress_bar : bool, default: False
        Show a progress bar of the meshing, as pyvista's filters do.

    Returns
    -------
    pyvista.StructuredGrid
        Dimensions ``(ni, nj, nk)``, corner 0 the one with the smallest x + y + z, i leaving
        it nearest +x, (i, j, k) right-handed; cell data ``MaxIncludedAngle``,
        ``MinIncludedAngle``, ``ScaledJacobian``, ``Folded``; field data ``Method``,
        ``PatchNames``, ``PatchTypes``, ``Report`` (JSON) and the quality figures.

    Warns ``pinn_engine.FoldedCellsWarning`` when cells are folded; raises
    ``pinn_engine.errors.InputError`` (a ``ValueError``, one line) for a surface that is not
    six-faced or a bad setting, patch name, spacing or orthogonal face, before meshing.

    >>> surface = pv.read("example_data/hexa_bend.vtp")
    >>> grid = pinn_mesh_hexa(surface, size=(21, 11, 9), method="tfi")
    >>> grid.dimensions
    (21, 11, 9)
    """
    size = node_counts(size)
    problem = hexa_size_problem(size)
    if problem:
        raise SettingsError(f"size={size}: {problem}")
    alg = PinnHexaAlgorithm(route=ROUTE)
    if method is not None:
        alg.SetMethod(method)  # ValueError for an unknown method
    alg.SetGridSize(*size)
    alg.SetPatchNames(patches)
    alg.SetSpacing(spacing)
    alg.SetOrthogonal(orthogonal)
    alg.SetFaceAngle(face_angle)
    grid = run(
        alg, lambda: as_polydata(surface, closed=True, what="surface"), progress_bar=progress_bar
    )
    warn_folded(report(grid), refold_hint(ROUTE))
    return grid
