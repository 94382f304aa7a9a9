"""An unstructured quadrilateral mesh with patches: the form in which the unstructured
writers (SU2, Gmsh, OpenFOAM) take a grid whose coincident nodes are merged (an O- or
C-grid's seam or cut, ``bodies.py``; the blocks of a multi-block grid, ``multiblock.py``)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class QuadMesh:
    """``points`` (n, 3) in a plane z = const, each written once; ``quads`` (m, 4) node ids
    counter-clockwise in x-y; ``patches`` patch name -> (edges, 2) node ids with the domain
    on each edge's left; ``types`` patch name -> its type (``patchnames.TYPES``)."""

    points: np.ndarray
    quads: np.ndarray
    patches: dict[str, np.ndarray]
    types: dict[str, str]
