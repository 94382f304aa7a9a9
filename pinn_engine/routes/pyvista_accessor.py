"""pinn-mesh for pyvista: ``pinn_mesh(boundary, ...)`` and the ``PolyData.pinn_mesh`` accessor.

With pinn-mesh installed (pyvista 0.48+ finds the accessor through the ``pyvista.accessors``
entry point; no import needed)::

    import pyvista as pv

    boundary = pv.read("example_data/fig2.vtp")      # one closed polyline, four corners
    lines = pv.read("example_data/fig2_aux.vtp")     # optional auxiliary polylines
    grid = boundary.pinn_mesh(aux=lines, size=(41, 21))
    grid.plot(scalars="MaxIncludedAngle", show_edges=True, cpos="xy")

    finer = boundary.pinn_mesh(aux=lines, size=(161, 81))   # trains from the 161 x 81 elliptic grid
    again = boundary.pinn_mesh(aux=lines, size=(41, 21))    # the first network, no retraining

The accessor keeps the networks it trained for that boundary, so calling it again with
settings it has seen only re-evaluates the network. The default PINN starts from the
elliptic grid of ``size`` (``lattice``), so a new size trains anew; ``lattice=(41, 21)``
evaluates the network trained for 41 x 21 at any ``size``. ``boundary.pinn_mesh.trainings``
counts the trainings and ``boundary.pinn_mesh.clear()`` forgets them. ``pinn_mesh(boundary,
...)`` is the same as a plain function (no cache unless you pass one).

A grid with folded cells is still returned, with a ``pinn_engine.FoldedCellsWarning`` (a
``UserWarning``) that gives the count and a hint; ``warnings.simplefilter("error",
FoldedCellsWarning)`` turns it into an exception.

A multi-block domain (SPEC 10) is meshed by giving its block edges: ``blocks = boundary.
pinn_mesh(blocks=edges, cell_size=0.1)`` (or :func:`pinn_mesh_blocks`) returns a
``pyvista.MultiBlock`` of structured grids ``block0``, ``block1``, ...

A six-faced 3D domain (SPEC 11), a closed surface with a ``FaceId`` cell array, is meshed the
same way: ``grid = surface.pinn_mesh(size=(21, 21, 21))`` (or :func:`pinn_mesh_hexa`)
returns its hexahedral ``pyvista.StructuredGrid``.
"""

from __future__ import annotations

import json
import os
import sys
import warnings
from collections.abc import Callable, Sequence

import numpy as np
import pyvista as pv
from vtkmodules.vtkCommonDataModel import vtkPolyData

from pinn_engine.cache import MeshCache
from pinn_engine.errors import (
    FoldedCellsWarning,
    InputError,
    grid_warnings,
)
from pinn_engine.hexa.surface import FACE_ARRAY
from pinn_engine.hexamesh import HEXA_SIZE, size_problem
from pinn_engine.routes.airfoil_algorithm import body_polydata
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.filters import folded_warning
from pinn_engine.routes.hexa_algorithm import PinnHexaAlgorithm, refold_hint
from pinn_engine.routes.multiblock_algorithm import MOVE_EDGES, PinnMultiBlockAlgorithm
from pinn_engine.settings import Settings, grid_size_problem, make_settings

# pinn_mesh_hexa's keywords besides size and method, taken by the accessor on a surface
HEXA_OPTIONS = ("patches", "spacing", "orthogonal")

__all__ = [
    "FoldedCellsWarning",
    "PinnMeshAccessor",
    "pinn_mesh",
    "pinn_mesh_blocks",
    "pinn_mesh_hexa",
    "save_mesh",
]


def _ring_polydata(points, closed: bool) -> pv.PolyData:
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] not in (2, 3) or len(pts) < 2:
        raise InputError(f"expected an (n, 2) or (n, 3) array of points, got shape {pts.shape}")
    if pts.shape[1] == 2:
        pts = np.column_stack([pts, np.zeros(len(pts))])
    ids = list(range(len(pts))) + ([0] if closed else [])
    return pv.PolyData(pts, lines=[len(ids), *ids])


def _caller_level() -> int:
    """The ``stacklevel`` of the first caller outside this module, for ``warnings.warn``
    called from here."""
    frame, level = sys._getframe(1), 1
    while frame is not None and frame.f_code.co_filename == __file__:
        frame, level = frame.f_back, level + 1
    return level


def _warn_about(report: dict) -> None:
    """A ``TrainingStoppedWarning``, ``FoldedCellsWarning`` and ``WallAngleWarning`` where
    they apply, attributed to the first caller outside this module."""
    level = _caller_level()
    for text, category in grid_warnings(report, "pyvista"):
        warnings.warn(text, category, stacklevel=level)


def _as_polydata(obj, closed: bool, what: str) -> vtkPolyData:
    if isinstance(obj, vtkPolyData):
        return obj
    if isinstance(obj, np.ndarray | list | tuple):
        return _ring_polydata(obj, closed)
    if hasattr(obj, "extract_surface"):  # another pyvista dataset holding lines
        return obj.extract_surface()
    raise InputError(
        f"{what}: expected a pyvista/VTK PolyData or an array of points, got {type(obj).__name__}"
    )


def _aux_list(aux) -> list[vtkPolyData]:
    if aux is None:
        return []
    if isinstance(aux, vtkPolyData):
        return [aux]
    if isinstance(aux, np.ndarray):  # one polyline as an (n, 2|3) array
        return [_ring_polydata(aux, closed=False)]
    if isinstance(aux, pv.MultiBlock):
        aux = [block for block in aux if block is not None]
    return [_as_polydata(a, closed=False, what="aux") for a in aux]


def pinn_mesh(
    boundary,
    aux=None,
    size: Sequence[int] = (41, 21),
    method: str = "pinn",
    *,
    preset: str = "default",
    corners: Sequence[int] | None = None,
    adam_epochs: int | None = None,
    lbfgs_iterations: int | None = None,
    hidden_layers: int | None = None,
    neurons: int | None = None,
    lambda2: float | None = None,
    seed: int | None = None,
    boundary_mode: str | None = None,
    device: str | None = None,
    progress: Callable[[dict], bool | None] | None = None,
    cache: MeshCache | None = None,
    patches=None,
    topology: str | None = None,
    naca: str | None = None,
    farfield: float | None = None,
    spacing: dict | None = None,
    orthogonal=None,
    **settings,
) -> pv.StructuredGrid:
    """Structured quadrilateral grid of a four-sided 2D domain, or an O- or C-grid around a
    body (``topology="o"`` or ``"c"``, SPEC 9).

    Parameters
    ----------
    boundary : pyvista.PolyData, vtkPolyData or array_like
        The closed boundary: one closed polyline (or polygon) with four corners, or an
        ``(n, 2)``/``(n, 3)`` array of its points in order (closed automatically).
    aux : PolyData, vtkPolyData, array_like, or a list/MultiBlock of them, optional
        Auxiliary lines: open polylines from one side to the opposite side. One PolyData
        may hold several polylines. Used by ``method="pinn"`` only.
    size : (int, int)
        Nodes along xi and eta (``ni``, ``nj``), default ``(41, 21)``.
    method : {"pinn", "mgnet", "tfi", "elliptic"}
        The paper's PINN (default), its MGNet baseline, transfinite interpolation, or the
        elliptic (Winslow) method.
    preset : {"default", "paper"}
        ``"paper"`` reproduces the paper's section 4 settings.
    corners : four ints, optional
        Corner point indices of the boundary; default: the four sharpest turns.
    adam_epochs, lbfgs_iterations, hidden_layers, neurons, lambda2, seed : optional
        Training settings (``None``: the preset's value, e.g. 5000 Adam epochs and 500
        L-BFGS iterations). Short runs such as ``adam_epochs=300, lbfgs_iterations=50``
        are good for a first look.
    boundary_mode : {"hard", "penalty"}, optional
        Exact boundary by construction (default) or the paper's penalty term.
    objective : {"winslow", "quality"}, optional (a ``**settings`` field)
        ``method="pinn"``: the Winslow equations alone, or with a cell-quality term that
        lowers the worst cell's largest angle (SPEC 7; ``docs/quality_objective.md``).
    device : str, optional
        Torch device: ``"auto"`` (default), ``"cpu"``, ``"cuda"``.
    progress : callable, optional
        ``progress(info)`` during training, ``info`` a dict with ``phase`` ("adam" or
        "lbfgs"), ``step``, ``total``, ``loss`` and ``terms`` (before an O- or C-grid's
        training, ``phase`` "prepare" with ``stage``, ``step`` and ``total``); returning
        True cancels (``pinn_engine.errors.TrainingCancelled``), returning
        ``pinn_engine.errors.STOP`` ends the training with the grid of its best state so far
        and a ``TrainingStoppedWarning``.
    time_limit : float, optional (a ``**settings`` field)
        Seconds of training, then the same as a ``STOP`` answer (default: no limit).
    cache : pinn_engine.cache.MeshCache, optional
        Re-use networks trained earlier on the same inputs and training settings.
    patches : dict, sequence of four names or str, optional
        Boundary patch names, e.g. ``{"bottom": "wall", "top": "wall"}`` (default: bottom,
        right, top, left; equal names form one patch), each optionally typed as
        ``"NAME:TYPE"`` (wall, inflow, outflow, farfield, symmetry, patch; a patch named
        wall is a wall); stored as field data ``PatchNames`` and ``PatchTypes`` and used by
        :func:`save_mesh` (OpenFOAM and CGNS write the types).
    topology : {"o", "c"}, optional
        Mesh around a body instead: ``boundary`` is then the body (an airfoil curve as
        PolyData or points, or the path of a Selig/Lednicer ``.dat`` file or of a file with
        two closed polylines, body inside far field), or ``None`` with ``naca``. Methods
        pinn, tfi, elliptic. Index conventions and patches: SPEC 9 and docs/airfoils.md.
    naca : str, optional
        NACA 4-digit code, e.g. ``"0012"`` (chord 1; blunt trailing edge for the O-grid,
        closed for the C-grid).
    farfield : float, optional
        Far-field circle radius in chords about mid-chord (default 15).
    spacing : dict, optional
        First-edge length per side in the boundary's units, e.g. ``{"bottom": 1e-3}``
        (also ``"bottom=1e-3"`` or pairs): the first grid edge leaving every node of that
        side has this length, growing smoothly away from it (pinn, tfi, elliptic; SPEC 7,
        docs/boundary_layer.md). A body grid takes ``{"bottom": H}``: the first-layer
        height off the body wall.
    orthogonal : str or sequence, optional
        Sides that grid lines leave at 90 degrees, e.g. ``"bottom"`` or ``["bottom",
        "top"]`` (pinn: a loss term; elliptic: Hilgenstock control functions). A body grid
        takes ``"bottom"`` (elliptic and pinn body grids always leave the wall at 90).
    **settings
        Any other field of ``pinn_engine.settings.Settings`` (e.g. ``learning_rate``).

    Returns
    -------
    pyvista.StructuredGrid
        Dimensions ``(ni, nj, 1)``; cell data ``MaxIncludedAngle``, ``MinIncludedAngle``
        (degrees), ``ScaledJacobian``, ``Folded``; point data ``i``, ``j``; field data
        ``Method``, ``Report`` (JSON), quality figures, per side ``FirstEdge_<side>`` (min,
        median, max), ``WallAngleDeviation_<side>`` and ``GrowthRatio_<side>``,
        ``LossHistory`` (a row per evaluation, a component per term:
        ``grid.field_data["LossHistory"]``, or ``pinn_engine.io.vtkgrid.loss_history``) and
        ``PatchNames``.

    Warns
    -----
    pinn_engine.TrainingStoppedWarning
        The training ended early (``time_limit``, a ``STOP`` answer); the grid of its best
        state is returned.
    pinn_engine.FoldedCellsWarning
        Some cells of the grid are folded (the count and a hint of the fix); the grid is
        returned anyway.

    Raises
    ------
    pinn_engine.errors.PinnMeshError
        Bad boundary or auxiliary line (``InputError``), failed training
        (``TrainingError``); the message is one line.
    ValueError
        Invalid settings or size.

    Examples
    --------
    >>> import pyvista as pv
    >>> from pinn_engine.routes.pyvista_accessor import pinn_mesh
    >>> square = pv.Rectangle([[0, 0, 0], [2, 0, 0], [2, 1, 0]])
    >>> grid = pinn_mesh(square, size=(21, 11), method="tfi")
    >>> grid.dimensions
    (21, 11, 1)
    """
    ni, nj = (int(n) for n in size)
    problem = grid_size_problem(ni, nj)
    if problem:
        raise ValueError(f"size=({ni}, {nj}): {problem}")
    given = dict(
        adam_epochs=adam_epochs,
        lbfgs_iterations=lbfgs_iterations,
        hidden_layers=hidden_layers,
        neurons=neurons,
        lambda2=lambda2,
        seed=seed,
        boundary_mode=boundary_mode,
        device=device,
        spacing=spacing,
        orthogonal=orthogonal,
        topology=topology,
        naca=naca,
        farfield=farfield,
        **settings,
    )
    given = {k: v for k, v in given.items() if v is not None}
    config = make_settings(method, preset, **{"lattice": (ni, nj), **given})  # or ValueError
    alg = PinnMeshAlgorithm(
        route="pyvista", cache=cache or MeshCache(capacity=1), progress=progress
    )
    alg.SetMethod(method)
    alg.SetPreset(preset)
    for name, value in given.items():
        alg.SetSetting(name, value)
    alg.SetGridSize(ni, nj)
    alg.SetCorners(corners)
    if patches is not None:
        alg.SetPatchNames(patches)
    _run(alg, lambda: _boundary_polydata(boundary, config, farfield is not None), aux)
    grid = pv.wrap(alg.GetOutput())
    _warn_about(json.loads(grid.field_data["Report"][0]))
    return grid


def _run(alg, boundary: Callable[[], vtkPolyData], lines) -> None:
    """Give a filter the ``boundary`` (port 0) and the ``lines`` (port 1: auxiliary lines or
    block edges), run it and raise its error in pyvista's words."""
    try:
        alg.SetInputDataObject(0, boundary())
        for poly in _aux_list(lines):
            alg.AddInputDataObject(1, poly)
    except InputError as exc:
        raise exc.for_route("pyvista") from None
    alg.Update()
    error = alg.GetLastException()
    if error is not None:
        raise error.for_route("pyvista") if isinstance(error, InputError) else error


def pinn_mesh_blocks(
    boundary,
    blocks,
    *,
    cell_size: float | None = None,
    method: str | None = None,
    interfaces: str | None = None,
    patches=None,
    spacing=None,
    orthogonal=None,
    aux=None,
) -> pv.MultiBlock:
    """Multi-block structured grid (SPEC 10) of a domain cut into four-sided blocks.

    Parameters
    ----------
    boundary : pyvista.PolyData, vtkPolyData or array_like
        The outer boundary and its holes: closed polylines (one PolyData may hold several),
        or an ``(n, 2)``/``(n, 3)`` array of the outer boundary's points (closed
        automatically).
    blocks : PolyData, vtkPolyData, array_like, or a list/MultiBlock of them
        Block edges: open polylines from the boundary, a hole or another edge to the
        boundary, a hole or another edge.
    cell_size : float, optional
        Cell length in the boundary's units (default: the diagonal / 40).
    method : {"pinn", "elliptic", "tfi"}, optional
        Each block's PINN on the elliptic grid, kept where no worse (default); Winslow on
        all blocks at once; or each block's TFI.
    interfaces : {"free", "fixed"}, optional
        Interface nodes solved like interior nodes (default) or kept on the drawn edges.
    patches : dict or sequence of str, optional
        Names of boundary pieces (a stretch of the boundary or a hole between two block
        corners or junctions; default names ``boundary``, ``hole1``, ...): ``{(x, y):
        "NAME[:TYPE]"}`` or ``["X,Y=NAME[:TYPE]", ...]`` names the piece nearest (x, y);
        pieces of one name form one patch. Each block's field data ``PieceNames``,
        ``PieceTypes`` and ``PieceRanges`` carry them.
    spacing : dict or sequence of str, optional
        First grid edge leaving a patch, ``{"cylinder": 0.005}`` or ``["cylinder=0.005"]``
        (SPEC 7 on patches; docs/multiblock.md).
    orthogonal : str or sequence of str, optional
        Patches that grid lines leave along the normal, ``"cylinder"`` or ``["cylinder",
        "walls"]``.
    aux : PolyData, vtkPolyData, array_like, or a list/MultiBlock of them, optional
        Auxiliary lines inside blocks: open polylines, each from a side of the block holding
        its middle point to the opposite side (SPEC 2 in that block), fitted by the pinn;
        the report's ``aux_line_distance`` says how far the grid is from each.

    Returns
    -------
    pyvista.MultiBlock
        One ``StructuredGrid`` a block, named ``block0``, ``block1``, ..., each with the cell
        arrays ``MaxIncludedAngle``, ``MinIncludedAngle``, ``ScaledJacobian``, ``Folded`` and
        field data ``Report`` (JSON: the block's and the whole grid's figures). A node on a
        side shared by two blocks is the same point in both.

    Warns ``pinn_engine.FoldedCellsWarning`` when cells are folded; raises
    ``pinn_engine.errors.InputError`` (one line) for bad curves, ``ValueError`` for bad
    settings.

    >>> blocks = pinn_mesh_blocks(pv.read("example_data/lshape.vtp"),
    ...                           pv.read("example_data/lshape_blocks.vtp"), cell_size=0.1)
    >>> blocks.keys()
    ['block0', 'block1']
    """
    alg = PinnMultiBlockAlgorithm(route="pyvista")
    for setter, value in (
        (alg.SetMethod, method),
        (alg.SetCellSize, cell_size),
        (alg.SetInterfaces, interfaces),
        (alg.SetPatchNames, patches),
        (alg.SetSpacing, spacing),
        (alg.SetOrthogonal, orthogonal),
    ):
        if value is not None:
            setter(value)
    alg.GetSettings()  # ValueError for bad settings, before any input is read
    try:
        for poly in _aux_list(aux):
            alg.AddInputDataObject(2, poly)
    except InputError as exc:
        raise exc.for_route("pyvista") from None
    _run(alg, lambda: _as_polydata(boundary, closed=True, what="boundary"), blocks)
    out = pv.wrap(alg.GetOutput())
    report = json.loads(out[0].field_data["Report"][0])["multiblock"]
    warning = folded_warning(report, "pyvista", MOVE_EDGES)
    if warning:
        warnings.warn(warning, FoldedCellsWarning, stacklevel=_caller_level())
    return out


def pinn_mesh_hexa(
    surface,
    size: Sequence[int] = HEXA_SIZE,
    method: str | None = None,
    *,
    patches=None,
    spacing=None,
    orthogonal=None,
) -> pv.StructuredGrid:
    """Hexahedral structured grid (SPEC 11) of the 3D domain a closed surface bounds.

    Parameters
    ----------
    surface : pyvista.PolyData or vtkPolyData
        A closed triangulated (or polygonal) surface with a cell array ``FaceId`` of six
        values whose faces meet as a cube's do.
    size : (int, int, int)
        Nodes along i, j and k, default ``(21, 21, 21)``.
    method : str, optional
        One of ``pinn_engine.hexamesh.METHODS`` (``"tfi"``: 3D transfinite interpolation;
        ``"elliptic"``: 3D Winslow), default ``pinn_engine.hexamesh.HEXA_METHOD``.
    patches : dict, sequence of six names or str, optional
        Patch names of the six faces, e.g. ``{"imin": "inlet:inflow", "kmin": "floor:wall"}``
        (default imin ... kmax; equal names form one patch), each optionally typed as
        ``"NAME:TYPE"``; stored as field data ``PatchNames`` and ``PatchTypes`` and used by
        :func:`save_mesh`.
    spacing : dict or sequence of str, optional
        First grid edge leaving a face, ``{"kmin": 0.002}`` or ``["kmin=0.002"]`` (faces
        imin ... kmax; SPEC 7 on the patches, docs/hexa.md).
    orthogonal : str or sequence of str, optional
        Faces that grid lines leave along the normal, ``"kmin"`` or ``["kmin", "kmax"]``
        (elliptic and pinn).

    Returns
    -------
    pyvista.StructuredGrid
        Dimensions ``(ni, nj, nk)``, corner 0 the one with the smallest x + y + z, i leaving
        it nearest +x, (i, j, k) right-handed; cell data ``MaxIncludedAngle``,
        ``MinIncludedAngle``, ``ScaledJacobian``, ``Folded``; field data ``Method``,
        ``PatchNames``, ``PatchTypes``, ``Report`` (JSON) and the quality figures.

    Warns ``pinn_engine.FoldedCellsWarning`` when cells are folded; raises
    ``pinn_engine.errors.InputError`` (one line) for a surface that is not six-faced,
    ``ValueError`` for bad settings; a bad patch name, spacing or orthogonal face raises
    ``InputError`` (one line) before meshing.

    >>> surface = pv.read("example_data/hexa_bend.vtp")
    >>> grid = pinn_mesh_hexa(surface, size=(21, 11, 9), method="tfi")
    >>> grid.dimensions
    (21, 11, 9)
    """
    size = tuple(int(n) for n in size)
    problem = size_problem(size)
    if problem:
        raise ValueError(f"size={size}: {problem}")
    alg = PinnHexaAlgorithm(route="pyvista")
    if method is not None:
        alg.SetMethod(method)  # ValueError for an unknown method
    alg.SetGridSize(*size)
    alg.SetPatchNames(patches)
    alg.SetSpacing(spacing)
    alg.SetOrthogonal(orthogonal)
    _run(alg, lambda: _as_polydata(surface, closed=True, what="surface"), None)
    grid = pv.wrap(alg.GetOutput())
    warning = folded_warning(
        json.loads(grid.field_data["Report"][0]), "pyvista", refold_hint("pyvista")
    )
    if warning:
        warnings.warn(warning, FoldedCellsWarning, stacklevel=_caller_level())
    return grid


def _boundary_polydata(boundary, settings: Settings, farfield_given: bool) -> vtkPolyData:
    """Port 0 of the algorithm from any of :func:`pinn_mesh`'s forms of ``boundary``: PolyData
    or points; for a body also a file path (``.dat``, or two closed polylines) or None with
    ``naca``."""
    if settings.topology == "none":
        if boundary is None:
            raise InputError("give a boundary (PolyData or an (n, 2) array of points)")
        return _as_polydata(boundary, closed=True, what="boundary")
    if settings.naca:
        if boundary is not None:
            raise InputError("give either a body or naca=, not both")
        return vtkPolyData()  # the algorithm makes the section itself
    if boundary is None:
        raise InputError("give a body (PolyData, points or a .dat path) or naca=")
    if isinstance(boundary, str | os.PathLike):
        from pinn_engine.job import geometry_from_files

        geometry = geometry_from_files(settings, boundary, farfield_given=farfield_given)
        return body_polydata(geometry.body.surface, geometry.body.sharp, geometry.far.polyline)
    if isinstance(boundary, np.ndarray | list | tuple):
        return _ring_polydata(boundary, closed=False)
    return _as_polydata(boundary, closed=False, what="body")


def save_mesh(grid, path, format: str | None = None, *, patches=None, extrude: float | None = None):
    """Write a grid from :func:`pinn_mesh` for a CFD solver; returns the path written.

    The format follows the extension of ``path``: ``.vts``, ``.vtk``, ``.xyz`` (PLOT3D),
    ``.cgns``, ``.su2``, ``.msh`` (Gmsh 4.1); ``format="openfoam"`` writes the case folder
    ``path`` (``constant/polyMesh``). ``patches`` renames the boundary patches (default: the
    grid's ``PatchNames``); ``extrude=T`` makes PLOT3D, CGNS and Gmsh outputs one cell of
    thickness T in z (OpenFOAM always is). Atomic: on failure nothing is left behind.
    Raises ``pinn_engine.errors.InputError`` (one line) for bad arguments.

    >>> grid = pinn_mesh(square, size=(21, 11), method="tfi", patches={"bottom": "wall"})
    >>> save_mesh(grid, "out/square.cgns")
    >>> save_mesh(grid, "out/square_case", format="openfoam", extrude=0.1)
    """
    from pinn_engine.io.export import write

    try:
        return write(grid, path, format, patches=patches, extrude=extrude)
    except InputError as exc:
        raise exc.for_route("pyvista") from None


@pv.register_dataset_accessor("pinn_mesh", pv.PolyData)
class PinnMeshAccessor:
    """``boundary.pinn_mesh(aux=None, size=(41, 21), method="pinn", **settings)``.

    Meshes the four-sided domain bounded by this PolyData (one closed polyline) and returns
    a ``pyvista.StructuredGrid`` (active cell scalars ``MaxIncludedAngle``). The arguments
    are those of :func:`pinn_engine.routes.pyvista_accessor.pinn_mesh`; ``help(pinn_mesh)``
    describes them.

    Trained networks are kept per boundary: calling again with settings seen before (or with
    a change training does not depend on) re-evaluates the network instead of training.

    >>> grid = boundary.pinn_mesh(aux=lines, size=(41, 21))
    >>> fine = boundary.pinn_mesh(aux=lines, size=(161, 81), lattice=(41, 21))  # no retraining
    >>> boundary.pinn_mesh.trainings
    1

    With ``blocks=`` (block edges) it meshes a multi-block domain (SPEC 10) instead and
    returns a ``pyvista.MultiBlock``; see :func:`pinn_mesh_blocks`. A closed surface with a
    ``FaceId`` cell array (or a ``size`` of three numbers) gives a hexahedral grid (SPEC 11);
    see :func:`pinn_mesh_hexa`.

    >>> lshape = pv.read("example_data/lshape.vtp")
    >>> blocks = lshape.pinn_mesh(blocks=pv.read("example_data/lshape_blocks.vtp"), cell_size=0.1)
    >>> duct = pv.read("example_data/hexa_twisted_duct.vtp")
    >>> grid = duct.pinn_mesh(size=(21, 21, 21))
    """

    def __init__(self, mesh: pv.PolyData) -> None:
        self._mesh = mesh
        self._cache = MeshCache()
        self.last: pv.StructuredGrid | pv.MultiBlock | None = None  # the last grid made

    def __call__(
        self,
        aux=None,
        size: Sequence[int] | None = None,
        method: str | None = None,
        *,
        blocks=None,
        **options,
    ) -> pv.StructuredGrid | pv.MultiBlock:
        """Mesh the domain bounded by this PolyData (or, with ``topology``, around this body);
        the keyword ``options`` are those of :func:`pinn_mesh` (``help(pinn_mesh)``), with
        this accessor's networks re-used.

        ``aux``: auxiliary polylines (PolyData or a list); ``size``: ``(ni, nj)`` nodes
        (default 41 x 21); ``method``: pinn (default), mgnet, tfi or elliptic. Returns a
        ``pyvista.StructuredGrid`` with MaxIncludedAngle/MinIncludedAngle cells.

        ``blocks``: block edges (PolyData or a list): this PolyData's closed polylines are
        then the outer boundary and holes of a multi-block domain, and the keywords those of
        :func:`pinn_mesh_blocks` (``cell_size``, ``method``: pinn, elliptic or tfi,
        ``interfaces``, ``patches``, ``spacing``, ``orthogonal``; ``aux``: auxiliary lines
        inside blocks); returns a ``pyvista.MultiBlock``.

        A surface with a ``FaceId`` cell array, or ``size=(ni, nj, nk)``: the hexahedral grid
        of :func:`pinn_mesh_hexa` (``size``, ``method``, ``patches``, ``spacing``,
        ``orthogonal``); returns a ``pyvista.StructuredGrid``.
        """
        faced = FACE_ARRAY.decode() in self._mesh.cell_data
        if faced or (size is not None and len(size) == len(HEXA_SIZE)):
            given = {"aux": aux, "blocks": blocks, **options}
            for name, value in given.items():
                if value is not None and name not in HEXA_OPTIONS:
                    keywords = ", ".join(f"{n}=" for n in ("size", "method", *HEXA_OPTIONS))
                    raise InputError(
                        f"{name}= applies to 2D domains, not to a six-faced surface; give "
                        f"{keywords}"
                    )
            hexa = {k: v for k, v in options.items() if k in HEXA_OPTIONS}
            self.last = pinn_mesh_hexa(self._mesh, size or HEXA_SIZE, method, **hexa)
            return self.last
        if blocks is not None:
            if size is not None:
                raise InputError("size= applies to four-sided domains, not to blocks=")
            self.last = pinn_mesh_blocks(self._mesh, blocks, method=method, aux=aux, **options)
            return self.last
        if size is not None:
            options["size"] = size
        self.last = pinn_mesh(
            self._mesh, aux, method=method or "pinn", cache=self._cache, **options
        )
        return self.last

    mesh = __call__  # boundary.pinn_mesh.mesh(...) reads well too

    def save(
        self,
        path,
        format: str | None = None,
        *,
        grid=None,
        patches=None,
        extrude: float | None = None,
    ):
        """Write ``grid`` (default: the last grid this accessor made) for a CFD solver;
        the arguments are those of :func:`save_mesh`.

        >>> boundary.pinn_mesh(size=(41, 21), patches={"bottom": "wall", "top": "wall"})
        >>> boundary.pinn_mesh.save("out/channel.su2")
        """
        grid = grid if grid is not None else self.last
        if grid is None:
            raise InputError(
                "no grid to save yet; call boundary.pinn_mesh(...) first or pass grid="
            )
        return save_mesh(grid, path, format, patches=patches, extrude=extrude)

    @property
    def trainings(self) -> int:
        """Networks trained for this boundary so far."""
        return self._cache.trainings

    def clear(self) -> None:
        """Forget the trained networks: the next call trains again."""
        self._cache.clear()
