"""The ``pinn_mesh`` accessor registered on ``pyvista.PolyData``: one call for every domain
kind (the one a surface's ``FaceId`` array, a three-number ``size`` or ``blocks=`` names),
the networks it trained kept for the next call, and its last grid saved."""

from __future__ import annotations

from collections.abc import Sequence

import pyvista as pv

from pinn_engine.cache import MeshCache
from pinn_engine.errors import InputError
from pinn_engine.hexa.surface import FACE_ARRAY
from pinn_engine.hexamesh import HEXA_SIZE
from pinn_engine.routes.pyvista_accessor.four_sided import pinn_mesh
from pinn_engine.routes.pyvista_accessor.hexa import HEXA_OPTIONS, pinn_mesh_hexa
from pinn_engine.routes.pyvista_accessor.multiblock import pinn_mesh_blocks
from pinn_engine.routes.pyvista_accessor.save import save_mesh


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
        ``interfaces``, ``patches``, ``spacing``, ``orthogonal``, ``cells``; ``aux``:
        auxiliary lines inside blocks); returns a ``pyvista.MultiBlock``.

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
