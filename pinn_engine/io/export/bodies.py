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


__all__ = ["cells", "compact", "node_map", "patch_edges"]


def write_polymesh(block, mesh) -> None:
    """OpenFOAM polyMesh of an O- or C-grid extruded one cell in z (``block.thickness``):
    the seam or cut nodes merged, so its faces are internal faces like any other; patches
    wall, farfield (outflow) and ``frontAndBack`` (empty)."""
    from pinn_engine.io.export.openfoam import write_mesh_files
    from pinn_engine.io.export.patches import FRONT_AND_BACK, TYPES

    ni, nj, topo, nw = block.ni, block.nj, block.topology, block.n_wake
    kept, _ = compact(ni, nj, topo, nw)
    m = len(kept)
    xy = block.points.reshape(-1, 3)[kept]
    up = np.array([0.0, 0.0, abs(block.thickness)])
    points = np.vstack([xy, xy + up])
    q = cells(ni, nj, topo, nw)  # counter-clockwise seen from +z
    n_cells = len(q)
    a = q.ravel()
    b = np.roll(q, -1, axis=1).ravel()
    owner_of = np.repeat(np.arange(n_cells), 4)
    key = np.sort(np.column_stack([a, b]), axis=1)
    _, inverse, counts = np.unique(key, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    side = np.column_stack([a, b, b + m, a + m])  # normal out of the cell that owns the edge
    # internal faces: the lower cell owns the face, oriented as that cell's edge
    shared = counts[inverse] == 2
    order = np.lexsort((owner_of[shared], inverse[shared]))
    idx = np.flatnonzero(shared)[order].reshape(-1, 2)  # the two edge copies of each face
    first, second = idx[:, 0], idx[:, 1]
    swap = owner_of[first] > owner_of[second]
    own = np.where(swap, second, first)
    nei = np.where(swap, first, second)
    internal_faces, owner, neighbour = side[own], owner_of[own], owner_of[nei]
    sort = np.lexsort((neighbour, owner))
    internal_faces, owner, neighbour = internal_faces[sort], owner[sort], neighbour[sort]
    # boundary faces, patch by patch
    single = np.flatnonzero(counts[inverse] == 1)
    lookup = {tuple(key[k]): k for k in single}
    patches = []
    for name, edges in patch_edges(ni, nj, topo, nw, block.names).items():
        ks = np.array([lookup[tuple(sorted(e))] for e in edges])
        patches.append((name, TYPES[block.patch_type(name)][0], side[ks], owner_of[ks]))
    ids = np.arange(n_cells)
    patches.append(
        (FRONT_AND_BACK, "empty", np.vstack([q[:, ::-1], q + m]), np.concatenate([ids, ids]))
    )
    write_mesh_files(mesh, points, internal_faces, owner, neighbour, patches)
