"""O- and C-grids (SPEC 9) for the writers: the seam or the wake cut as an internal joint.

- O-grid: column ni - 1 repeats column 0 (the seam); its cells are clockwise in (i, j)
  (i runs counter-clockwise around the body, j outward), so unstructured writers reverse
  them, and extrusions go along -z (so that (i, j, k) is right-handed).
- C-grid: node (i, 0) coincides with node (ni - 1 - i, 0) for i <= n_wake (the cut).

Unstructured writers (SU2, Gmsh) merge the coincident nodes: each node is written once, the
seam or cut has no boundary edges, and the patches are ``wall`` (the body's edges of
j = 0), ``farfield`` (j = nj - 1) and, for the C-grid, ``outflow`` (columns 0 and ni - 1),
named by the grid's PatchNames for the bottom, top and right/left sides.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.io.export.quadmesh import QuadMesh
from pinn_engine.io.export.topology import quads


def node_map(ni: int, nj: int, topology: str, n_wake: int) -> np.ndarray:
    """For each structured node ``i + ni * j``, the index of the node it is merged into."""
    idx = np.arange(ni * nj).reshape(nj, ni)
    if topology == "o":
        idx[:, -1] = idx[:, 0]
    else:
        i = np.arange(ni - 1 - n_wake, ni)
        idx[0, i] = idx[0, ni - 1 - i]
    return idx.ravel()


def compact(ni: int, nj: int, topology: str, n_wake: int) -> tuple[np.ndarray, np.ndarray]:
    """(kept, new_id): the structured indices of the nodes written, and for every
    structured node its 0-based id among them."""
    rep = node_map(ni, nj, topology, n_wake)
    kept = np.unique(rep)
    new = np.full(ni * nj, -1)
    new[kept] = np.arange(len(kept))
    return kept, new[rep]


def cells(ni: int, nj: int, topology: str, n_wake: int) -> np.ndarray:
    """(cells, 4) counter-clockwise quads in merged node ids."""
    q = quads(ni, nj)
    if topology == "o":
        q = q[:, ::-1]
    return compact(ni, nj, topology, n_wake)[1][q]


def patch_edges(
    ni: int, nj: int, topology: str, n_wake: int, names: tuple[str, ...]
) -> dict[str, np.ndarray]:
    """Patch name -> (edges, 2) merged node ids, the domain on each edge's left."""
    new = compact(ni, nj, topology, n_wake)[1]
    i = np.arange(ni - 1)
    bottom, right, top, left = names
    out: dict[str, list[np.ndarray]] = {}
    if topology == "o":
        wall = np.column_stack([i + 1, i])  # i runs with the domain on its right
        far = np.column_stack([i, i + 1]) + ni * (nj - 1)
        parts = [(bottom, wall), (top, far)]
    else:
        body = np.arange(n_wake, ni - 1 - n_wake)
        wall = np.column_stack([body, body + 1])
        far = (np.column_stack([i + 1, i]) + ni * (nj - 1))[::-1]
        j = np.arange(nj - 1)
        out_right = np.column_stack([ni - 1 + ni * j, ni - 1 + ni * (j + 1)])
        out_left = np.column_stack([ni * (j + 1), ni * j])[::-1]
        parts = [(bottom, wall), (right, out_right), (top, far), (left, out_left)]
    for name, edges in parts:
        out.setdefault(name, []).append(new[edges])
    return {name: np.vstack(e) for name, e in out.items()}


def quad_mesh(block) -> QuadMesh:
    """An O- or C-grid (a ``block.Block``) with its seam or cut nodes merged."""
    ni, nj, topo, nw = block.ni, block.nj, block.topology, block.n_wake
    kept, _ = compact(ni, nj, topo, nw)
    patches = patch_edges(ni, nj, topo, nw, block.names)
    return QuadMesh(
        block.points.reshape(-1, 3)[kept],
        cells(ni, nj, topo, nw),
        patches,
        {name: block.patch_type(name) for name in patches},
    )


__all__ = ["cells", "compact", "node_map", "patch_edges", "quad_mesh"]
