"""Grid lines that leave a patch along its normal (SPEC 7's ``--orthogonal`` on SPEC 11's
patches), made from the Winslow grid as 2D's orthogonal start makes its two candidates
(``starts.orthogonal``, docs/boundary_layer.md):

1. *Sheared* (kept when it folds no cell and leaves every orthogonal patch within
   ``ANGLE_TOL``): each line leaving the patch is moved by its first node's offset from the
   patch normal (at the first edge's normal height, or H where the patch has a spacing) times
   ``w(s) / w(s_1)``, ``w(s) = s (1 - s/R)^2`` (s the line's parameter from the patch, R = 1,
   or 1/2 when the opposite patch is orthogonal too): the line leaves straight along the
   normal and bends back to the Winslow line a third of the way across, not within a cell.
2. *Normal layers*: the first layer of nodes off each patch put on its normals and the
   Winslow equations solved beyond those layers, which stay fixed (orthogonal by
   construction, with a turn of the lines one cell off the patch).

The normal at a patch node is the cross product of the chords through its neighbours along
the patch, the directions the grid itself has there (as 2D's ``chord_tangents``).
"""

from __future__ import annotations

import numpy as np

from pinn_engine.classical.shear import shear_weights
from pinn_engine.hexa import volume
from pinn_engine.hexa.quality import folded
from pinn_engine.hexa.spacing import PATCH_AXIS, first_edges, leaving

# The two patch nodes nearest its rim (the rim's and the next) are left out of the wall
# angles (SPEC 7: "the two nodes nearest each corner excepted"; a rim node's line lies in
# the neighbouring face, and the next node's first cell leans on it)
RIM_NODES = 2
ANGLE_TOL = 2.0  # SPEC 7: grid lines within 2 degrees of the normal
PROJECTIONS = 20  # alternating projections onto two patches' heights (converged well before)
SPACING_TOL = 0.1  # SPEC 7: first edges within 10 % of H


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


def _heights(
    wall: np.ndarray, first: np.ndarray, normal: np.ndarray, height: float | None
) -> np.ndarray:
    """The first layer's targets: the first edge's normal component, or ``height``."""
    if height is None:
        height = np.einsum("abk,abk->ab", first - wall, normal)[..., None]
    return wall + height * normal


def sheared(
    g: np.ndarray, patches: tuple[str, ...], params: np.ndarray, heights: dict[str, float]
) -> np.ndarray:
    """Candidate 1 of the module's docstring: ``g`` with the lines leaving each of
    ``patches`` sheared onto the normals (one patch after another)."""
    out = np.array(g, dtype=float)
    for patch in patches:
        axis, end = PATCH_AXIS[patch]
        opposite = next(p for p, v in PATCH_AXIS.items() if v == (axis, -1 - end))
        wall, first = leaving(out, patch)
        offset = _heights(wall, first, normals(wall, first), heights.get(patch)) - first
        s = np.moveaxis(params[..., axis], axis, 0)
        s = s if end == 0 else (1.0 - s)[::-1]
        shift = offset[None] * shear_weights(s, opposite in patches)[..., None]
        moved = np.moveaxis(out, axis, 0)
        moved = moved if end == 0 else moved[::-1]
        moved[1:-1, 1:-1, 1:-1] += shift[1:-1, 1:-1, 1:-1]
    return out


def normal_layers(g: np.ndarray, patches: tuple[str, ...], heights: dict[str, float]) -> None:
    """Put the first layer's interior nodes off each of ``patches`` on the patch normals, at
    ``heights[patch]`` or else at the first edge's normal height (in place). A node in the
    first layers of two patches (along an edge where both meet) is put at the asked height
    above both patches' nodes (alternating projections from the mean of the two targets,
    as 2D puts the node next to a corner between two orthogonal sides)."""
    total = np.zeros_like(g)
    count = np.zeros(g.shape[:3])
    planes = []
    for patch in patches:
        wall, first = leaving(g, patch)
        normal = normals(wall, first)
        target = _heights(wall, first, normal, heights.get(patch))
        axis, end = PATCH_AXIS[patch]
        layer = 1 if end == 0 else -2
        mask = np.zeros(g.shape[:3], dtype=bool)
        np.moveaxis(mask, axis, 0)[layer][1:-1, 1:-1] = True
        np.moveaxis(total, axis, 0)[layer][1:-1, 1:-1] += target[1:-1, 1:-1]
        np.moveaxis(count, axis, 0)[layer][1:-1, 1:-1] += 1.0
        height = np.einsum("abk,abk->ab", target - wall, normal)
        planes.append((mask, wall[1:-1, 1:-1], normal[1:-1, 1:-1], height[1:-1, 1:-1]))
    set_ = count > 0
    g[set_] = total[set_] / count[set_][:, None]
    shared = count > 1
    for _ in range(PROJECTIONS if shared.any() else 0):
        for mask, wall, normal, height in planes:
            p = g[mask].reshape(wall.shape)
            p += (height - np.einsum("abk,abk->ab", p - wall, normal))[..., None] * normal
            g[mask & shared] = p.reshape(-1, 3)[shared[mask]]


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


def orthogonal_grid(
    g: np.ndarray,
    patches: tuple[str, ...],
    params: np.ndarray,
    heights: dict[str, float],
    controls: bool,
) -> np.ndarray:
    """The sheared candidate of the Winslow grid ``g`` if it folds nothing, its lines leave
    every patch within ``ANGLE_TOL`` and the spaced ones' first edges stay within
    ``SPACING_TOL`` of H (another patch's shear can move them), else the normal layers'
    grid (its Winslow solve with the distribution's control terms where ``controls``)."""
    candidate = sheared(g, patches, params, heights)
    straight = all(inner_angles(candidate, p).max(initial=0.0) <= ANGLE_TOL for p in patches)
    spaced = all(
        np.abs(first_edges(candidate, p)[1:-1, 1:-1] / h - 1.0).max(initial=0.0) <= SPACING_TOL
        for p, h in heights.items()
        if p in patches
    )
    if straight and spaced and not folded(candidate).any():
        return candidate
    layered = np.array(g, dtype=float)
    normal_layers(layered, patches, heights)
    return solve_inside(layered, patches, params if controls else None)[0]
