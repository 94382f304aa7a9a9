"""The ``pinn_mesh`` accessor registered on ``pyvista.PolyData``: one call for every domain
kind (the one a surface, a three-number ``size`` or ``blocks=`` names), its keywords explicit
and checked against that kind, the networks it trained kept for the next call, and its last
grid saved or read."""

from __future__ import annotations

import inspect
from collections.abc import Callable, Sequence

import pyvista as pv

from pinn_engine.errors import InputError
from pinn_engine.geometry.plane import Plane
from pinn_engine.routes.pyvista_accessor.four_sided import pinn_mesh
from pinn_engine.routes.pyvista_accessor.hexa import pinn_mesh_hexa
from pinn_engine.routes.pyvista_accessor.multiblock import pinn_mesh_blocks
from pinn_engine.routes.pyvista_accessor.report import report
from pinn_engine.routes.pyvista_accessor.running import node_counts, public
from pinn_engine.routes.pyvista_accessor.save import save_mesh
from pinn_engine.settings import HEXA_SIZE, setting_names


def _offered(kind: str, function: Callable) -> list[str]:
    """The keywords of ``function`` (this route's function of the domain ``kind``) that the
    kind takes (``job.OPTIONS``), in its signature's order, then, where it takes
    ``**settings``, the kind's other settings."""
    from pinn_engine.job import OPTIONS

    parameters = inspect.signature(function).parameters
    named = [name for name in parameters if name in OPTIONS[kind]]
    if any(p.kind is p.VAR_KEYWORD for p in parameters.values()):
        named += sorted(OPTIONS[kind] & setting_names() - set(named))
    return named


@pv.register_dataset_accessor("pinn_mesh", pv.PolyData)
class PinnMeshAccessor:
    """``boundary.pinn_mesh(...)``: the structured grid of the domain this PolyData bounds.

    One closed polyline with four corners gives a four-sided grid; with ``topology`` an O-
    or C-grid around a body; with ``blocks=`` a multi-block grid; a closed surface (not in
    one plane, or with a ``FaceId`` cell array, or given a ``size`` of three numbers) a
    hexahedral grid.
    Its keywords are those of ``__call__`` (below); ``progress_bar=True`` shows a bar.

    Trained networks are kept per boundary: calling again with settings seen before (or with
    a change training does not depend on) re-evaluates the network instead of training.

    >>> grid = boundary.pinn_mesh(aux=lines, size=(41, 21))
    >>> fine = boundary.pinn_mesh(aux=lines, size=(161, 81), lattice=(41, 21))  # no retraining
    >>> boundary.pinn_mesh.trainings
    1
    >>> boundary.pinn_mesh.report["quality"]["worst_max_angle"]  # the last grid's report, a dict
    >>> boundary.pinn_mesh.save("out/fig2.su2")  # the last grid, for a CFD solver

    >>> lshape = pv.read("example_data/lshape.vtp")
    >>> blocks = lshape.pinn_mesh(blocks=pv.read("example_data/lshape_blocks.vtp"), cell_size=0.1)
    >>> duct = pv.read("example_data/hexa_twisted_duct.vtp")
    >>> grid = duct.pinn_mesh(size=(21, 21, 21))
    """

    def __init__(self, mesh: pv.PolyData) -> None:
        self._mesh = mesh
        from pinn_engine.job import MeshCache

        self._cache = MeshCache()
        self.last: pv.StructuredGrid | pv.MultiBlock | None = None  # the last grid made

    @public("pinn_mesh", also=setting_names())
    def __call__(
        self,
        aux=None,
        size: Sequence[int] | None = None,
        method: str | None = None,
        *,
        blocks=None,
        patches=None,
        spacing=None,
        orthogonal=None,
        preset: str | None = None,
        corners: Sequence[int] | None = None,
        objective: str | None = None,
        adam_epochs: int | None = None,
        lbfgs_iterations: int | None = None,
        hidden_layers: int | None = None,
        neurons: int | None = None,
        lambda2: float | None = None,
        seed: int | None = None,
        lattice: Sequence[int] | None = None,
        boundary_mode: str | None = None,
        time_limit: float | None = None,
        device: str | None = None,
        topology: str | None = None,
        naca: str | None = None,
        farfield: float | None = None,
        cell_size: float | None = None,
        interfaces: str | None = None,
        save_blocks: str | None = None,
        cells=None,
        grading=None,
        progress: Callable[[dict], bool | str | None] | None = None,
        progress_bar: bool = False,
        model=None,
        **settings,
    ) -> pv.StructuredGrid | pv.MultiBlock:
        """Mesh the domain this PolyData bounds; returns a ``pyvista.StructuredGrid`` (a
        ``pyvista.MultiBlock`` with ``blocks``).

        Parameters
        ----------
        aux : PolyData, array_like, or a list/MultiBlock of them, optional
            Auxiliary lines: open polylines from one side to the opposite side, which the
            grid lines follow (``method="pinn"``; with ``blocks``, lines inside blocks).
        size : (ni, nj) or (ni, nj, nk), optional
            Nodes along each direction: default ``(41, 21)``; three numbers for a six-faced
            surface (default ``(21, 21, 21)``).
        method : {"pinn", "mgnet", "tfi", "elliptic"}, optional
            The paper's PINN (default), its MGNet baseline, transfinite interpolation or the
            elliptic (Winslow) grid; blocks and surfaces take pinn, tfi and elliptic.
        blocks : PolyData, array_like, a list/MultiBlock of them, or "auto", optional
            Block edges: this PolyData's closed polylines are then the outer boundary and
            holes of a multi-block domain (SPEC 10, docs/multiblock.md); ``"auto"``: edges
            proposed from the boundary and holes alone (SPEC 13, docs/blocking.md).
        patches : dict, sequence of names or str, optional
            Boundary patch names, optionally typed ``"NAME:TYPE"``: ``{"bottom": "wall"}``
            by side (bottom right top left), ``{"imin": "inlet"}`` by face (imin ... kmax),
            or ``["X,Y=NAME"]`` for the block boundary piece nearest (X, Y), ``{"hole1":
            "NAME"}`` for every piece of a ring; stored as field data and used by
            :meth:`save`.
        spacing : dict or sequence of str, optional
            First grid edge leaving a side or patch, ``{"bottom": 1e-3}`` or
            ``["bottom=1e-3"]``, growing smoothly away from it (SPEC 7); with ``blocks``
            also ``{(x, y): h}``, the cells on both sides of the block side nearest (x, y).
        orthogonal : str or sequence of str, optional
            Sides or patches that grid lines leave at 90 degrees, ``"bottom"`` or
            ``["bottom", "top"]`` (pinn and elliptic).
        preset : {"default", "paper"}, optional
            ``"paper"`` reproduces the paper's section 4 training settings.
        corners : four ints, optional
            The boundary's corner point indices; default: its four sharpest turns.
        objective : {"best", "winslow", "quality"}, optional
            pinn: ``"best"`` (default) the grid of lowest worst cell among TFI, the
            elliptic grid, their blends and the quality-optimised grid, mean at most 0.5
            degrees above the elliptic grid's, lines followed (the Winslow equations under
            a spacing or orthogonal sides); ``"winslow"`` the Winslow equations alone;
            ``"quality"`` with a term that lowers the worst cell's largest angle
            (docs/quality_objective.md).
        adam_epochs, lbfgs_iterations : int, optional
            Training steps; default 0 Adam epochs and 120 L-BFGS iterations from the
            elliptic grid (the paper preset: 5000 and 500 from TFI).
        hidden_layers, neurons, lambda2, seed : optional
            The network (default 4 layers of 30), the boundary weight (30) and the seed (0).
        lattice : (int, int), optional
            The elliptic grid the pinn starts from (default: ``size``); a network trained
            on one lattice is re-evaluated at any ``size``.
        boundary_mode : {"hard", "penalty"}, optional
            The boundary exact by construction (default) or the paper's penalty term.
        time_limit : float, optional
            Seconds of training, then the grid of the best state so far is returned with a
            ``TrainingStoppedWarning`` (default: no limit).
        device : str, optional
            Torch device: ``"auto"`` (default), ``"cpu"``, ``"cuda"``.
        topology, naca, farfield : optional
            ``topology="o"`` or ``"c"``: an O- or C-grid around this PolyData as a body (an
            airfoil curve), ``naca="0012"`` for a NACA section instead, ``farfield`` the
            far field's radius in chords (default 15; docs/airfoils.md); with ``naca``
            the PolyData may be empty: ``pv.PolyData().pinn_mesh(naca="0012",
            topology="o")``.
        cell_size : float, optional
            With ``blocks``: the cells' length (default: the domain's diagonal / 40).
        interfaces : {"free", "fixed"}, optional
            With ``blocks``: interface nodes solved like interior ones (default) or kept on
            the drawn edges.
        save_blocks : str, optional
            With ``blocks``: also write the block edges meshed (``.vtp``; the proposal of
            ``blocks="auto"``), which passed back as ``blocks`` give the same grid.
        cells : dict or sequence of str, optional
            With ``blocks``: cells along the chain through the block side nearest (x, y),
            ``{(x, y): n}`` or ``["X,Y=N"]``.
        grading : dict or sequence of str, optional
            With ``blocks``: cells growing geometrically along the chain through the block
            side nearest (x, y), the last r times the first (blockMesh's expansion ratio),
            ``{(x, y): r}`` or ``["X,Y=R"]``.
        progress : callable, optional
            ``progress(info)`` during training (``info``: ``phase``, ``step``, ``total``,
            ``loss``); returning True cancels, ``pinn_engine.errors.STOP`` keeps the best
            state so far.
        progress_bar : bool, default: False
            Show a progress bar of the meshing, as pyvista's filters do.
        model : str, path or fitted family model, optional
            A family model (SPEC 16, ``pinn-mesh fit`` or ``pinn_engine.fit_family``) that
            meshes a four-sided domain or a body in a forward pass (default ``size``: the
            family's), or whose nodes start a multi-block domain's solve (with ``blocks``).
        **settings
            Any other training setting by name, e.g. ``learning_rate=5e-4``.

        Returns
        -------
        pyvista.StructuredGrid or pyvista.MultiBlock
            Cell data ``MaxIncludedAngle`` (active), ``MinIncludedAngle``,
            ``ScaledJacobian``, ``Folded``; field data ``Method``, ``PatchNames`` and the
            report (``pinn_engine.report(grid)`` reads it as a dict).

        Raises
        ------
        ValueError
            Every bad input or setting, as ``pinn_engine.errors.InputError`` (a
            ``ValueError``) with a one-line message.
        TypeError
            An unknown keyword, as ``pinn_engine.errors.KeywordError``: it names the nearest.

        Warns
        -----
        pinn_engine.FoldedCellsWarning, pinn_engine.TrainingStoppedWarning
            Folded cells, or a training ended early; the grid is returned anyway.
        """
        given = {
            name: value
            for name, value in dict(
                aux=aux,
                blocks=blocks,
                patches=patches,
                spacing=spacing,
                orthogonal=orthogonal,
                preset=preset,
                corners=corners,
                objective=objective,
                adam_epochs=adam_epochs,
                lbfgs_iterations=lbfgs_iterations,
                hidden_layers=hidden_layers,
                neurons=neurons,
                lambda2=lambda2,
                seed=seed,
                lattice=lattice,
                boundary_mode=boundary_mode,
                time_limit=time_limit,
                device=device,
                topology=topology,
                naca=naca,
                farfield=farfield,
                cell_size=cell_size,
                interfaces=interfaces,
                save_blocks=save_blocks,
                cells=cells,
                grading=grading,
                progress=progress,
                model=model,
                **settings,
            ).items()
            if value is not None
        }
        size = None if size is None else node_counts(size)
        from pinn_engine.job import OPTIONS, kind_of, only_for

        kind = kind_of(self._mesh, blocks is not None, size or ())
        if kind == "four-sided" and self._mesh.GetNumberOfPolys() and not _is_flat(self._mesh):
            kind = "hexa"  # a surface without FaceId: its size is checked as a 3D domain's
        if model is not None and "model" not in OPTIONS[kind]:
            raise InputError(
                "model= (a family model) meshes four-sided domains, O- and C-grids and "
                "multi-block domains (with blocks=) in this build, not six-faced domains; "
                "mesh without model="
            )
        if kind == "hexa":
            self.last = self._hexa(size, method, given, progress_bar)
        elif kind == "blocks":
            self.last = self._blocks(size, method, given, progress_bar)
        else:
            for name in only_for("blocks", "four-sided", "body"):
                if name in given:
                    raise InputError(f"{name}= applies to multi-block domains (with blocks=)")
            body = topology in ("o", "c") or naca is not None
            for name in only_for("four-sided", "body") if body else ():
                if name in given:
                    raise InputError(f"{name}= applies to four-sided domains, not to topology=")
            body_free = naca is not None and self._mesh.n_points == 0  # pv.PolyData()
            self.last = pinn_mesh(
                None if body_free else self._mesh,
                size=size,
                method=method or "pinn",
                cache=self._cache,
                progress_bar=progress_bar,
                **given,
            )
        return self.last

    mesh = __call__  # boundary.pinn_mesh.mesh(...) reads well too

    def _hexa(self, size, method, given: dict, progress_bar: bool) -> pv.StructuredGrid:
        """A six-faced surface's hexahedral grid, or the error of a 2D curve given three
        sizes or of keywords for 2D domains."""
        from pinn_engine.job import kind_of

        if kind_of(self._mesh) != "hexa" and _is_flat(self._mesh):
            raise InputError(
                f"size={tuple(size)}: three sizes need a six-faced surface (a closed surface "
                "with a FaceId cell array); this PolyData lies in a plane: give size=(ni, nj)"
            )
        offered = _offered("hexa", pinn_mesh_hexa)
        for name in given:
            if name not in offered:
                keywords = ", ".join(f"{n}=" for n in offered)
                raise InputError(
                    f"{name}= applies to 2D domains, not to a six-faced surface; give {keywords}"
                )
        return pinn_mesh_hexa(
            self._mesh, size or HEXA_SIZE, method, progress_bar=progress_bar, **given
        )

    def _blocks(self, size, method, given: dict, progress_bar: bool) -> pv.MultiBlock:
        """A multi-block domain's grid, or the error of keywords for other domains."""
        if size is not None:
            raise InputError("size= applies to four-sided domains, not to blocks=")
        from pinn_engine.job import OPTIONS

        offered = _offered("blocks", pinn_mesh_blocks)
        for name in given:
            if name not in offered:
                keywords = ", ".join(f"{n}=" for n in offered)
                where = (
                    "is not one of pinn_mesh_blocks' keywords in this build"
                    if name in OPTIONS["blocks"]
                    else "applies to four-sided domains, not to blocks="
                )
                raise InputError(f"{name}= {where}; give {keywords}")
        return pinn_mesh_blocks(self._mesh, method=method, progress_bar=progress_bar, **given)

    @public("boundary.pinn_mesh.save")
    def save(
        self,
        path,
        format: str | None = None,
        *,
        grid=None,
        patches=None,
        extrude: float | None = None,
    ):
        """Write ``grid`` (default: the last grid this accessor made) for a CFD solver, the
        format by the extension of ``path``: ``.vts``, ``.vtk``, ``.xyz`` (PLOT3D),
        ``.cgns``, ``.su2``, ``.msh`` (Gmsh), or ``format="openfoam"`` for a case folder;
        ``patches`` renames the boundary patches, ``extrude=T`` makes a 2D grid one cell of
        thickness T. A multi-block grid (``blocks=``) goes to ``.vtm``, ``.xyz``, ``.cgns``,
        ``.su2``, ``.msh`` or OpenFOAM. Returns the path written (``pinn_engine.save`` does
        the same for any grid).

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
    def report(self) -> dict:
        """The last grid's report as a dict (sizes, quality figures, training, settings);
        ``pinn_engine.report(grid)`` reads any grid's."""
        if self.last is None:
            raise InputError("no grid made yet; call boundary.pinn_mesh(...) first")
        return report(self.last)

    @property
    def trainings(self) -> int:
        """Networks trained for this boundary so far."""
        return self._cache.trainings

    def clear(self) -> None:
        """Forget the trained networks: the next call trains again."""
        self._cache.clear()


def _is_flat(mesh: pv.PolyData) -> bool:
    """Whether ``mesh`` lies in one plane (a 2D domain's curve, not a closed surface)."""
    try:
        Plane.fit(mesh.points)
    except InputError:
        return False
    return True
