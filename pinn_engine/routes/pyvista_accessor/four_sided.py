"""A four-sided domain's grid, or an O- or C-grid around a body: ``pinn_mesh``."""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import TYPE_CHECKING

import pyvista as pv
from vtkmodules.vtkCommonDataModel import vtkPolyData

from pinn_engine.errors import InputError, SettingsError
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.pyvista_accessor.body import body_input
from pinn_engine.routes.pyvista_accessor.inputs import as_polydata
from pinn_engine.routes.pyvista_accessor.report import report
from pinn_engine.routes.pyvista_accessor.running import (
    ROUTE,
    give_field,
    node_counts,
    public,
    run,
    warn_about,
)
from pinn_engine.settings import Settings, grid_size_problem, make_settings, setting_names

if TYPE_CHECKING:
    from pinn_engine.job import MeshCache


@public("pinn_mesh", also=setting_names())
def pinn_mesh(
    boundary,
    aux=None,
    size: Sequence[int] | None = None,
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
    progress_bar: bool = False,
    model=None,
    adapt=None,
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
    size : (int, int), optional
        Nodes along xi and eta (``ni``, ``nj``), default ``(41, 21)`` (with ``model``, the
        family's).
    method : {"pinn", "mgnet", "tfi", "elliptic"}
        The paper's PINN (default), its MGNet baseline, transfinite interpolation, or the
        elliptic (Winslow) method.
    preset : {"default", "paper"}
        ``"paper"`` reproduces the paper's section 4 settings.
    corners : four ints, optional
        Corner point indices of the boundary; default: the four sharpest turns.
    adam_epochs, lbfgs_iterations, hidden_layers, neurons, lambda2, seed : optional
        Training settings (``None``: the preset's value: by default 0 Adam epochs and 120
        L-BFGS iterations from the elliptic grid, 4 hidden layers of 30 neurons, lambda2
        30, seed 0; the paper preset 5000 Adam epochs and 500 L-BFGS iterations from TFI).
    boundary_mode : {"hard", "penalty"}, optional
        Exact boundary by construction (default) or the paper's penalty term.
    objective : {"best", "winslow", "quality"}, optional (a ``**settings`` field)
        ``method="pinn"``: the best grid (default: the quality objective's where no spacing
        or orthogonal side is asked), the Winslow equations alone, or with a cell-quality
        term that lowers the worst cell's largest angle (SPEC 7;
        ``docs/quality_objective.md``).
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
    cache : pinn_engine.job.MeshCache, optional
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
    progress_bar : bool, default: False
        Show a progress bar of the meshing, as pyvista's filters do.
    model : str, path or fitted family model, optional
        Mesh by a family model (SPEC 16: ``pinn-mesh fit``'s file, or
        ``pinn_engine.fit_family(...)``'s ``model_``) in a forward pass instead of the
        boundary's own run; field data ``NetworkResult`` ``family`` (``start`` where the
        guard kept the member's own start, with a warning) and ``FamilyModel``.
    adapt : (dataset, str), optional
        Adapt the grid to a solution (SPEC 14): a dataset (or a file pyvista reads, an
        OpenFOAM case's ``.foam`` too) and the name of its point or cell array (a vector by
        its magnitude). Nodes move to where the field changes fast; counts, corners and
        patches are kept, boundary nodes slide along their side, the sides given a
        ``spacing`` or ``orthogonal`` stay with their first row. ``adapt_strength=beta``
        (a ``**settings`` field, default 20) sets the monitor ``sqrt(1 + beta^2 |grad f|^2
        / max |grad f|^2)``. Point data ``Monitor``; the report's ``adaptation``.
    **settings
        Any other training setting by name (e.g. ``learning_rate=5e-4``); an unknown name
        raises ``pinn_engine.errors.KeywordError`` (a ``TypeError``) naming the nearest.

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
    ValueError
        Every bad input: a boundary, auxiliary line, size or setting, as
        ``pinn_engine.errors.InputError`` (a ``ValueError``); the message is one line.
    pinn_engine.errors.TrainingError
        Training failed or was cancelled.

    Examples
    --------
    >>> import pyvista as pv
    >>> from pinn_engine.routes.pyvista_accessor import pinn_mesh
    >>> square = pv.Rectangle([[0, 0, 0], [2, 0, 0], [2, 1, 0]])
    >>> grid = pinn_mesh(square, size=(21, 11), method="tfi")
    >>> grid.dimensions
    (21, 11, 1)
    """
    if size is None:
        size = _family_size(model) if model is not None else (41, 21)
    size = node_counts(size)
    if len(size) != 2:
        raise SettingsError(f"size={size}: give two node counts (ni, nj)")
    ni, nj = size
    problem = grid_size_problem(ni, nj)
    if problem:
        raise SettingsError(f"size=({ni}, {nj}): {problem}")
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
    from pinn_engine.job import MeshCache

    alg = PinnMeshAlgorithm(route=ROUTE, cache=cache or MeshCache(capacity=1), progress=progress)
    alg.SetMethod(method)
    alg.SetPreset(preset)
    for name, value in given.items():
        alg.SetSetting(name, value)
    alg.SetGridSize(ni, nj)
    alg.SetCorners(corners)
    if patches is not None:
        alg.SetPatchNames(patches)
    alg.SetModel(model)
    give_field(alg, adapt)
    grid = run(
        alg,
        lambda: _boundary_polydata(boundary, config, farfield is not None),
        aux,
        progress_bar=progress_bar,
    )
    warn_about(report(grid))
    return grid


def _family_size(model) -> tuple[int, int]:
    """The node counts of a family model (a fitted one, or its file)."""
    from pinn_engine import job

    return tuple(model.size) if hasattr(model, "size") else job.family_size(model)


def _boundary_polydata(boundary, settings: Settings, farfield_given: bool) -> vtkPolyData:
    """Port 0 of the algorithm from any of :func:`pinn_mesh`'s forms of ``boundary``: PolyData
    or points; for a body also a file path (``.dat``, or two closed polylines) or None with
    ``naca``."""
    if settings.topology != "none":
        return body_input(boundary, settings, farfield_given)
    if boundary is None:
        raise InputError("give a boundary (PolyData or an (n, 2) array of points)")
    return as_polydata(boundary, closed=True, what="boundary")
