"""blockMesh's placement of a dictionary's nodes (the ``tfi`` method of SPEC 15), one
numbering over all blocks, and the patches' faces.

- **A block's nodes.** Each of its 12 edges is divided by its grading (``curves.divisions``)
  and its points placed on the curve at those fractions. A node inside the block is the
  weighted mean of the points at its fractions on the straight lines between the corners,
  the weights of each direction's four edges the products of the other directions' edge
  fractions, plus, where edges are curved, each edge's offset from its straight line with
  the same weights: blockMesh's edge-weighted transfinite interpolation. So block faces'
  curved edges are kept exactly and a graded box with straight edges gets blockMesh's nodes.
- **Shared nodes.** Blocks share a face where they share its four vertices (blockMesh's
  rule); the face's nodes are matched by position and merged, so every node is one id.
- **Patches.** A patch face is a block face with the same four vertices; faces of one
  block that no patch names and no other block shares go to the default patch (the
  dictionary's patch of that name, if it lists one).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pinn_engine.blocks3d.curves import curves, divisions, edge_points
from pinn_engine.blocks3d.dictionary import BlockMeshDict
from pinn_engine.errors import InputError

# blockMesh's edge numbering: vertex pairs along i, j, k
HEX_EDGES = (
    (0, 1), (3, 2), (7, 6), (4, 5),
    (0, 3), (1, 2), (5, 6), (4, 7),
    (0, 4), (1, 5), (2, 6), (3, 7),
)  # fmt: skip
# a block's faces by their corner vertices (hex-local ids) and as (axis, end)
HEX_FACES = {
    (0, 0): (0, 4, 7, 3),
    (0, 1): (1, 2, 6, 5),
    (1, 0): (0, 1, 5, 4),
    (1, 1): (3, 7, 6, 2),
    (2, 0): (0, 3, 2, 1),
    (2, 1): (4, 5, 6, 7),
}
# shared face nodes match within this share of the smallest cell edge next to them
MATCH = 1e-3


@dataclass
class Placement:
    """Node positions ``points`` (N, 3); per block its node ids ``ids`` (ni+1, nj+1, nk+1)
    and each direction's node fractions ``params`` (the mean of its four edges'); the
    patches as (name, type, faces (m, 4) of node ids, normals outward); ``interfaces``
    (block, axis, end) faces shared with another block."""

    points: np.ndarray
    ids: list[np.ndarray]
    params: list[list[np.ndarray]]
    patches: list[tuple[str, str, np.ndarray]]
    interfaces: set[tuple[int, int, int]]


def block_nodes(d: BlockMeshDict, b: int, table) -> tuple[np.ndarray, list[np.ndarray]]:
    """Block ``b``'s nodes (ni+1, nj+1, nk+1, 3) by blockMesh's edge-weighted interpolation,
    and its 12 edges' node fractions."""
    block = d.blocks[b]
    v = d.vertices[block.vertices]
    w, p, curved = [], [], []
    for e, (s, t) in enumerate(HEX_EDGES):
        frac = divisions(block.grading[e], block.counts[e // 4])
        pts, bent = edge_points(table, d.vertices, block.vertices[s], block.vertices[t], frac)
        w.append(frac)
        p.append(pts)
        if bent:
            curved.append(e)
    ni, nj, nk = block.counts
    wi = [x[:, None, None] for x in w[0:4]]
    wj = [x[None, :, None] for x in w[4:8]]
    wk = [x[None, None, :] for x in w[8:12]]
    w0, w1, w2, w3 = wi
    w4, w5, w6, w7 = wj
    w8, w9, w10, w11 = wk
    wx = [
        (1 - w0) * (1 - w4) * (1 - w8) + w0 * (1 - w5) * (1 - w9),
        (1 - w1) * w4 * (1 - w11) + w1 * w5 * (1 - w10),
        (1 - w2) * w7 * w11 + w2 * w6 * w10,
        (1 - w3) * (1 - w7) * w8 + w3 * (1 - w6) * w9,
    ]
    wy = [
        (1 - w4) * (1 - w0) * (1 - w8) + w4 * (1 - w1) * (1 - w11),
        (1 - w5) * w0 * (1 - w9) + w5 * w1 * (1 - w10),
        (1 - w6) * w3 * w9 + w6 * w2 * w10,
        (1 - w7) * (1 - w3) * w8 + w7 * (1 - w2) * w11,
    ]
    wz = [
        (1 - w8) * (1 - w0) * (1 - w4) + w8 * (1 - w3) * (1 - w7),
        (1 - w9) * w0 * (1 - w5) + w9 * w3 * (1 - w6),
        (1 - w10) * w1 * w5 + w10 * w2 * w6,
        (1 - w11) * (1 - w1) * w4 + w11 * (1 - w2) * w7,
    ]
    out = np.zeros((ni + 1, nj + 1, nk + 1, 3))
    groups = ((wx, 0, (slice(None), None, None)), (wy, 4, (None, slice(None), None)))
    groups += ((wz, 8, (None, None, slice(None))),)
    for weights, first, index in groups:
        total = sum(np.broadcast_to(x, (ni + 1, nj + 1, nk + 1)) for x in weights)
        for m in range(4):
            e = first + m
            s, t = HEX_EDGES[e]
            frac = w[e][index][..., None]
            straight = v[s] + frac * (v[t] - v[s])
            weight = (weights[m] / total)[..., None]
            out += weight * straight / 3.0
            if e in curved:
                out += weight * (p[e][index] - straight)
    for e in range(12):  # edges exactly (their points, not the blend)
        s, t = HEX_EDGES[e]
        line = _edge_slice(e)
        out[line] = p[e]
    return out, w


def _edge_slice(e: int) -> tuple:
    """The index of block edge ``e``'s nodes in a block's (ni+1, nj+1, nk+1) array."""
    # each direction's four edges sit at the other two indices (0,0), (n,0), (n,n), (0,n)
    a, b = ((0, 0), (-1, 0), (-1, -1), (0, -1))[e % 4]
    return {0: (slice(None), a, b), 1: (a, slice(None), b), 2: (a, b, slice(None))}[e // 4]


def face_slice(axis: int, end: int) -> tuple:
    """The index of a block face's nodes in its (ni+1, nj+1, nk+1) array."""
    return tuple((-1 if end else 0) if a == axis else slice(None) for a in range(3))


def place(d: BlockMeshDict) -> Placement:
    """Every block's nodes, merged over shared faces, and the patches (see the module)."""
    table = curves(d.vertices, d.edges)
    grids, params = [], []
    for b in range(len(d.blocks)):
        try:
            g, w = block_nodes(d, b, table)
        except ValueError as exc:
            raise InputError(f"block {b}: {exc}", d.source) from None
        grids.append(g)
        params.append([np.mean(w[4 * a : 4 * a + 4], axis=0) for a in range(3)])
    starts = np.cumsum([0] + [g[..., 0].size for g in grids])
    local = [
        starts[b] + np.arange(g[..., 0].size).reshape(g.shape[:3]) for b, g in enumerate(grids)
    ]
    xyz = np.concatenate([g.reshape(-1, 3) for g in grids])
    pairs = []
    faces: dict[frozenset, list[tuple[int, int, int]]] = {}
    for b, block in enumerate(d.blocks):
        for (axis, end), corners in HEX_FACES.items():
            key = frozenset(block.vertices[c] for c in corners)
            faces.setdefault(key, []).append((b, axis, end))
    interfaces = set()
    for key, owners in faces.items():
        if len(owners) > 2:
            raise InputError(
                f"a face with vertices {sorted(key)} belongs to more than two blocks", d.source
            )
        if len(owners) < 2:
            continue
        (a, ax, ea), (b, bx, eb) = owners
        ida, idb = local[a][face_slice(ax, ea)], local[b][face_slice(bx, eb)]
        if ida.size != idb.size:
            raise InputError(
                f"blocks {a} and {b} share a face but not its cell counts; give both the same",
                d.source,
            )
        cell = min(_smallest_edge(grids[a]), _smallest_edge(grids[b]))
        dist, near = _matched(xyz, ida, idb)
        if dist > MATCH * cell:
            raise InputError(
                f"blocks {a} and {b} share a face whose nodes do not match (its gradings or "
                "curved edges differ between them)",
                d.source,
            )
        pairs.append(np.column_stack([near, idb.ravel()]))
        interfaces |= {(a, ax, ea), (b, bx, eb)}
    pairs = np.vstack(pairs) if pairs else np.zeros((0, 2), int)
    index = _merged(len(xyz), pairs)
    count = int(index.max(initial=-1)) + 1
    points = np.zeros((count, 3))
    np.add.at(points, index, xyz)
    points /= np.bincount(index, minlength=count)[:, None]
    ids = [index[lo] for lo in local]
    patches = _patches(d, ids, faces)
    return Placement(points, ids, params, patches, interfaces)


def _merged(n: int, pairs: np.ndarray) -> np.ndarray:
    """The merged id of each of ``n`` nodes joined by ``pairs`` (k, 2): the groups of nodes
    joined directly or through others, numbered by their lowest node in node order
    (scipy's ``connected_components`` numbering, without importing scipy)."""
    low = np.arange(n)
    while True:
        least = np.minimum(low[pairs[:, 0]], low[pairs[:, 1]])
        before = low.copy()
        np.minimum.at(low, pairs[:, 0], least)
        np.minimum.at(low, pairs[:, 1], least)
        low = low[low]  # each node to its group's lowest node found so far
        if np.array_equal(low, before):
            return np.unique(low, return_inverse=True)[1]


def _matched(xyz: np.ndarray, ida: np.ndarray, idb: np.ndarray) -> tuple[float, np.ndarray]:
    """The node of face ``ida`` (a 2D array of ids) at each node of face ``idb``: of the
    face grid's eight orientations (flips and the transpose) the one whose largest distance
    between matched nodes is smallest, and that distance."""
    best, near = np.inf, ida.ravel()
    for grid in (ida, ida.T):
        for flipped in (grid, grid[::-1], grid[:, ::-1], grid[::-1, ::-1]):
            if flipped.shape != idb.shape:
                continue
            dist = float(np.linalg.norm(xyz[flipped] - xyz[idb], axis=-1).max())
            if dist < best:
                best, near = dist, flipped.ravel()
    return best, near


def _smallest_edge(g: np.ndarray) -> float:
    out = np.inf
    for axis in range(3):
        d = np.linalg.norm(np.diff(g, axis=axis), axis=-1)
        if d.size:
            out = min(out, float(d.min()))
    return out


def block_faces(ids: np.ndarray, axis: int, end: int) -> np.ndarray:
    """The cell faces (m, 4) of node ids of one block face, each ordered so that its normal
    points out of the block (blockMesh's orientation)."""
    face = ids[face_slice(axis, end)]  # 2D over the other two axes, in order
    a, b = face[:-1, :-1], face[1:, :-1]
    c, e = face[1:, 1:], face[:-1, 1:]
    quads = np.stack([a, b, c, e], axis=-1).reshape(-1, 4)
    # (a, b, c, e) turns from the first other axis to the second: its normal is that
    # cross product, which is +axis for axis 0 and 2 and -axis for axis 1
    outward_positive = axis != 1
    if outward_positive != bool(end):
        quads = quads[:, ::-1]
    return quads


def _patches(d: BlockMeshDict, ids, faces) -> list[tuple[str, str, np.ndarray]]:
    """The patches' faces in the dictionary's order (a patch's faces as it lists them, as
    blockMesh orders them: a cyclic pair's faces then correspond one to one), the faces no
    patch lists in the default patch (the listed patch of its name, if any)."""
    collected: dict[tuple[str, str], list[np.ndarray]] = {}
    listed: set[frozenset] = set()
    for p in d.patches:
        got = collected.setdefault((p.name, p.type), [])
        for f in p.faces:
            key = frozenset(f)
            if key not in faces:
                raise InputError(f"patch '{p.name}': face {list(f)} is no block's face", d.source)
            if len(faces[key]) == 2:
                raise InputError(
                    f"patch '{p.name}': face {list(f)} lies between two blocks (baffles are "
                    "not supported)",
                    d.source,
                )
            b, axis, end = faces[key][0]
            got.append(block_faces(ids[b], axis, end))
            listed.add(key)
    order = list(collected)
    default = [k for k in order if k[0] == d.default_patch[0]]  # named: it takes the rest
    rest = collected.setdefault(default[0] if default else d.default_patch, [])
    for key, owners in faces.items():
        if len(owners) == 1 and key not in listed:
            b, axis, end = owners[0]
            rest.append(block_faces(ids[b], axis, end))
    # a patch the dictionary names is kept even with no faces (blockMesh keeps it)
    return [
        (name, kind, np.vstack(q) if q else np.zeros((0, 4), dtype=int))
        for (name, kind), q in collected.items()
        if q or (name, kind) in order
    ]
