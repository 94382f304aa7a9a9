"""A multi-block domain's grid (SPEC 10): ``pinn_mesh_blocks``."""

from __future__ import annotations

from pathlib import Path

import pyvista as pv

from pinn_engine.io.export.edges import edges_of, write_edges
from pinn_engine.routes.multiblock_algorithm import BLOCKING, MOVE_EDGES, PinnMultiBlockAlgorithm
from pinn_engine.routes.pyvista_accessor.inputs import as_polydata, polydata_list
from pinn_engine.routes.pyvista_accessor.report import report
from pinn_engine.routes.pyvista_accessor.running import (
    ROUTE,
    give_field,
    public,
    pyvista_words,
    run,
    warn_folded,
)
from pinn_engine.settings import AUTO_BLOCKS, setting_names


@public("pinn_mesh_blocks", also=setting_names())
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
    save_blocks=None,
    progress_bar: bool = False,
    cells=None,
    grading=None,
    adapt=None,
    adapt_strength: float | None = None,
    model=None,
    **settings,
) -> pv.MultiBlock:
    """Multi-block structured grid (SPEC 10) of a domain cut into four-sided blocks.

    Parameters
    ----------
    boundary : pyvista.PolyData, vtkPolyData or array_like
        The outer boundary and its holes: closed polylines (one PolyData may hold several),
        or an ``(n, 2)``/``(n, 3)`` array of the outer boundary's points (closed
        automatically).
    blocks : PolyData, vtkPolyData, array_like, a list/MultiBlock of them, or "auto"
        Block edges: open polylines from the boundary, a hole or another edge to the
        boundary, a hole or another edge; ``"auto"``: proposed from the boundary and its
        holes alone (SPEC 13).
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
        "NAME[:TYPE]"}`` or ``["X,Y=NAME[:TYPE]", ...]`` names the piece nearest (x, y),
        ``{"hole1": "NAME[:TYPE]"}`` or ``["hole1=NAME[:TYPE]"]`` (or ``boundary``) every
        piece of that ring; pieces of one name form one patch. Each block's field data
        ``PieceNames``, ``PieceTypes`` and ``PieceRanges`` carry them.
    spacing : dict or sequence of str, optional
        First grid edge leaving a patch, ``{"cylinder": 0.005}`` or ``["cylinder=0.005"]``
        (SPEC 7 on patches; docs/multiblock.md), and at a block side, interior ones too,
        ``{(x, y): h}`` or ``["X,Y=H"]``: the cells on both sides of the side nearest (x, y)
        h across it, growing along the chain by at most 1.25 a cell.
    cells : dict or sequence of str, optional
        Cells along the chain through the block side nearest (x, y), ``{(x, y): n}`` or
        ``["X,Y=N"]`` (opposite sides of every block share a count).
    grading : dict or sequence of str, optional
        Cells growing geometrically along the chain through the block side nearest (x, y),
        the last r times the first (blockMesh's expansion ratio; the first at that side's
        end nearest the point), ``{(x, y): r}`` or ``["X,Y=R"]``.
    orthogonal : str or sequence of str, optional
        Patches that grid lines leave along the normal, ``"cylinder"`` or ``["cylinder",
        "walls"]``.
    aux : PolyData, vtkPolyData, array_like, or a list/MultiBlock of them, optional
        Auxiliary lines inside blocks: open polylines, each from a side of the block holding
        its middle point to the opposite side (SPEC 2 in that block), fitted by the pinn;
        the report's ``aux_line_distance`` says how far the grid is from each.
    save_blocks : str or os.PathLike, optional
        Also write the block edges meshed (the proposal of ``blocks="auto"``) to this
        ``.vtp``, open polylines: passed back as ``blocks=`` they give the same grid.
    progress_bar : bool, default: False
        Show a progress bar of the meshing, as pyvista's filters do.
    adapt : (dataset, str), optional
        Adapt the grid to a solution's array (SPEC 14; ``pinn_mesh``'s ``adapt``): block
        corners on the boundary stay, interfaces are solved, patches with a ``spacing`` or
        ``orthogonal`` stay with their first row. Point data ``Monitor``.
    adapt_strength : float, optional
        The monitor's strength beta (default 20).
    model : str, path or fitted family model, optional
        A multi-block family model (SPEC 16: ``pinn-mesh fit``'s file, or a fitted model)
        of this blocking: its nodes start the blocks' Winslow solve (docs/family.md). The
        blocks' field data ``NetworkResult`` (``family`` where the grid solved from them
        was kept, else ``start``) and ``FamilyModel`` say what was kept, as the report's
        ``family`` does; a member of another blocking is refused in one line.
    **settings
        The blocks' training settings by name, as ``pinn_mesh`` takes them (e.g.
        ``adam_epochs=500``, ``lbfgs_iterations=60``, ``hidden_layers=3``, ``preset="paper"``;
        the pinn trains a block with auxiliary lines); another setting raises
        ``pinn_engine.errors.SettingsError`` (a ``ValueError``) naming the nearest.

    Returns
    -------
    pyvista.MultiBlock
        One ``StructuredGrid`` a block, named ``block0``, ``block1``, ..., each with the cell
        arrays ``MaxIncludedAngle``, ``MinIncludedAngle``, ``ScaledJacobian``, ``Folded`` and
        field data ``Report`` (JSON: the block's and the whole grid's figures). A node on a
        side shared by two blocks is the same point in both.

    Warns ``pinn_engine.FoldedCellsWarning`` when cells are folded; raises
    ``pinn_engine.errors.InputError`` (a ``ValueError``, one line) for bad curves or
    settings.

    >>> blocks = pinn_mesh_blocks(pv.read("example_data/lshape.vtp"),
    ...                           pv.read("example_data/lshape_blocks.vtp"), cell_size=0.1)
    >>> blocks.keys()
    ['block0', 'block1']
    """
    alg = PinnMultiBlockAlgorithm(route=ROUTE)
    auto = isinstance(blocks, str) and blocks == AUTO_BLOCKS
    if save_blocks is not None and Path(save_blocks).suffix.lower() != ".vtp":
        raise ValueError(f"save_blocks={str(save_blocks)!r}: block edges are saved as .vtp")
    for setter, value in (
        (alg.SetBlocking, BLOCKING[1] if auto else None),
        (alg.SetMethod, method),
        (alg.SetCellSize, cell_size),
        (alg.SetInterfaces, interfaces),
        (alg.SetPatchNames, patches),
        (alg.SetSpacing, spacing),
        (alg.SetOrthogonal, orthogonal),
        (alg.SetCells, cells),
        (alg.SetGradings, grading),
        (alg.SetAdaptStrength, adapt_strength),
        (alg.SetModel, model),
    ):
        if value is not None:
            setter(value)
    for name, value in settings.items():
        alg.SetSetting(name, value)
    alg.GetSettings()  # ValueError for bad settings, before any input is read
    give_field(alg, adapt)
    with pyvista_words():
        for poly in polydata_list(aux, "aux"):
            alg.AddInputDataObject(2, poly)
    out = run(
        alg,
        lambda: as_polydata(boundary, closed=True, what="boundary"),
        None if auto else blocks,
        "blocks",
        progress_bar,
    )
    warn_folded(report(out), MOVE_EDGES)
    if save_blocks is not None:
        write_edges(edges_of(alg.GetBlockEdges()), save_blocks)
    return out
