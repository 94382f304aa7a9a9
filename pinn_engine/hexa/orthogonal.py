"""Grid lines that leave a patch along its normal (SPEC 7's ``--orthogonal`` on SPEC 11's
patches).

The first layer of nodes off each orthogonal patch is put on the patch's normals, at the
first edge's length (H where the patch has a spacing), and the 3D Winslow equations (with
the distribution's control terms) are solved for the nodes beyond those layers, which stay
fixed: the 3D form of the normal rows of 2D's orthogonal start (``starts.orthogonal``). The
normal at a patch node is the cross product of the chords through its neighbours along the
patch, the directions the grid itself has there (as 2D's ``chord_tangents``).
"""

from __future__ import annotations

import numpy as np

from pinn_engine.hexa import volume
from pinn_engine.hexa.spacing import PATCH_AXIS, leaving

# The two patch nodes nearest its rim (the rim's and the next) are left out of the wall
# angles (SPEC 7: "the two nodes nearest each corner excepted"; a rim node's line lies in
# the neighbouring face, and the next node's first cell leans on it)
RIM_NODES = 2


def normals(wall: np.ndarray, first: np.ndarray) -> np.ndarray:
    """Unit normals (na, nb, 3) of a patch's nodes ``wall``, towards the next layer
    ``first``: the cross product of the chords through each node's neighbours (one-sided at
    the rim)."""
    n = np.cross(np.gradient(wall, axis=0), np.gradient(wall, axis=1))
    n /= np.maximum(np.linalg.norm(n, axis=-1, keepdims=True), 1e-300)
    inward = np.einsum("abk,abk->ab", n, first - wall)
    return n * np.where(inward < 0, -1.0, 1.0)[..., None]


def wall_angles(g: np.ndarray, patch: str) -> np.ndarray:
    """Angle in degrees between the first grid edge leaving each node of ``patch`` and the
    patch's normal there, (na, nb)."""
    wall, first = leaving(g, patch)
    edge = first - wall
    cos = np.einsum("abk,abk->ab", normals(wall, first), edge) / np.maximum(
        np.linalg.norm(edge, axis=-1), 1e-300
    )
    return np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def inner_angles(g: np.ndarray, patch: str) -> np.ndarray:
    """:func:`wall_angles` without the ``RIM_NODES`` nodes nearest the patch's rim."""
    r = RIM_NODES
    return wall_angles(g, patch)[r:-r, r:-r]


def normal_layers(g: np.ndarray, patches: tuple[str, ...], heights: dict[str, float]) -> None:
    """Put the first layer's interior nodes off each of ``patches`` on the patch normals, at
    ``heights[patch]`` or else at the first edge's length (in place). A node in the first
    layers of two patches (along an edge where both meet) takes the mean of the two."""
    total = np.zeros_like(g)
    count = np.zeros(g.shape[:3])
    for patch in patches:
        wall, first = leaving(g, patch)
        height = heights.get(patch, np.linalg.norm(first - wall, axis=-1)[..., None])
        target = wall + height * normals(wall, first)
        axis, end = PATCH_AXIS[patch]
        layer = 1 if end == 0 else -2
        np.moveaxis(total, axis, 0)[layer][1:-1, 1:-1] += target[1:-1, 1:-1]
        np.moveaxis(count, axis, 0)[layer][1:-1, 1:-1] += 1.0
    set_ = count > 0
    g[set_] = total[set_] / count[set_][:, None]


def inside(shape: tuple[int, ...], patches: tuple[str, ...]) -> tuple[slice, slice, slice]:
    """The block of nodes whose faces are the domain's faces or the fixed first layers."""
    out = []
    for axis in range(3):
        low = any(PATCH_AXIS[p] == (axis, 0) for p in patches)
        high = any(PATCH_AXIS[p] == (axis, -1) for p in patches)
        out.append(slice(int(low), shape[axis] - int(high)))
    return tuple(out)


def solve_inside(
    g: np.ndarray, patches: tuple[str, ...], params: np.ndarray | None
) -> tuple[np.ndarray, int]:
    """The Winslow grid (with ``params``' control terms) of the nodes beyond the first
    layers off ``patches``, those layers fixed; returns the grid and the Picard steps."""
    block = inside(g.shape, patches)
    out = np.array(g, dtype=float)
    out[block], steps = volume.winslow(g[block], params=None if params is None else params[block])
    return out, steps
