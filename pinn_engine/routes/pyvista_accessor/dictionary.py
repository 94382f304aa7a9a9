"""An OpenFOAM blockMeshDict's blocks, meshed (SPEC 15): ``read_blockmeshdict``."""

from __future__ import annotations

import os

import pyvista as pv

from pinn_engine.routes.dictionary_algorithm import PinnBlockMeshDictReader
from pinn_engine.routes.pyvista_accessor.running import ROUTE, public, pyvista_words, update


@public("read_blockmeshdict")
def read_blockmeshdict(
    path: str | os.PathLike,
    method: str | None = None,
    *,
    interfaces: str | None = None,
    progress_bar: bool = False,
) -> pv.MultiBlock:
    """The blocks of an OpenFOAM ``blockMeshDict``, meshed with the dictionary's blocks,
    counts, gradings and patches (SPEC 15).

    Parameters
    ----------
    path : str or os.PathLike
        The dictionary (``system/blockMeshDict``).
    method : str, optional
        ``"pinn"`` (default: the better of the 3D Winslow grid over all blocks and
        blockMesh's placement, by checkMesh's largest non-orthogonality and skewness),
        ``"elliptic"`` (the Winslow grid) or ``"tfi"`` (blockMesh's placement).
    interfaces : str, optional
        ``"free"`` (default: nodes on block faces between blocks solved like interior
        nodes) or ``"fixed"`` (blockMesh's placement of those faces kept).
    progress_bar : bool, default: False
        Show a progress bar of the meshing, as pyvista's filters do.

    Returns
    -------
    pyvista.MultiBlock
        One ``StructuredGrid`` a block, named ``block0``, ``block1``, ... in the
        dictionary's order, with cell arrays ``MaxIncludedAngle``, ``MinIncludedAngle``,
        ``ScaledJacobian``, ``Folded`` and field data ``Report`` (JSON: the grid kept,
        checkMesh's figures of each candidate, the patches, the timings).

    Raises ``pinn_engine.errors.InputError`` (a ``ValueError``, one line) for an entry the
    reader does not take (``geometry``, ``mergePatchPairs``, ``#include`` ...), naming it.

    >>> blocks = read_blockmeshdict("example_data/blockmesh/pipe/system/blockMeshDict")
    >>> blocks.keys()
    ['block0', 'block1', 'block2', 'block3', 'block4']
    """
    alg = PinnBlockMeshDictReader(route=ROUTE)
    with pyvista_words():
        for setter, value in ((alg.SetMethod, method), (alg.SetInterfaces, interfaces)):
            if value is not None:
                setter(value)
    alg.SetFileName(os.fspath(path))
    update(alg, progress_bar)
    return pv.wrap(alg.GetOutputDataObject(0))
