"""Face nodes on the input triangles (hexa/facegrid.py): the search among the triangles whose
bounding box holds a node finds the same triangle and point as a search among all of them,
inside the mapped square and just off it; the closest point on the triangles; and a polar
bend's face and volume grids kept polar (TFI where it ranks better)."""

from __future__ import annotations

import numpy as np
from helpers import EXAMPLES

from pinn_engine.hexa.facegrid import carry_back, closest_points
from pinn_engine.kinds.hexa.mesh import mesh_surface
from pinn_engine.settings import make_settings

CELLS = 12  # the mapped square's triangulation: CELLS x CELLS squares, each cut in two
JITTER = 0.3  # interior vertices moved by up to this share of a cell: uneven triangles
ARC_SAG = 2.5e-3  # the bend's arcs drawn as 16 chords over 90 degrees sag 2.4e-3 at radius 2


def _square() -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A jittered triangulation of the unit square (uv), its triangles and a curved surface's
    points over it."""
    rng = np.random.default_rng(3)
    t = np.linspace(0.0, 1.0, CELLS + 1)
    uv = np.stack(np.meshgrid(t, t, indexing="ij"), axis=-1).reshape(-1, 2)
    inner = (uv > 0).all(axis=1) & (uv < 1).all(axis=1)
    uv[inner] += JITTER / CELLS * rng.uniform(-1, 1, (inner.sum(), 2))
    k = np.arange(CELLS)
    a = (k[:, None] * (CELLS + 1) + k[None, :]).ravel()
    b, c, d = a + CELLS + 1, a + CELLS + 2, a + 1
    tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)])
    points = np.column_stack([uv, np.sin(3 * uv[:, 0]) * uv[:, 1]])
    return uv, tris, points


def _everywhere(uv, tris, points, queries) -> np.ndarray:
    """The same carrying back, each query tested against every triangle."""
    p0 = uv[tris[:, 0]]
    e1, e2 = uv[tris[:, 1]] - p0, uv[tris[:, 2]] - p0
    det = e1[:, 0] * e2[:, 1] - e1[:, 1] * e2[:, 0]
    q = queries[:, None, :] - p0[None]
    l1 = (q[..., 0] * e2[:, 1] - q[..., 1] * e2[:, 0]) / det
    l2 = (e1[:, 0] * q[..., 1] - e1[:, 1] * q[..., 0]) / det
    best = np.minimum(np.minimum(l1, l2), 1.0 - l1 - l2).argmax(axis=1)
    rows = np.arange(len(queries))
    lam = np.stack([1 - l1[rows, best] - l2[rows, best], l1[rows, best], l2[rows, best]], 1)
    lam = np.clip(lam, 0.0, None)
    lam /= lam.sum(axis=1, keepdims=True)
    return np.einsum("qc,qcd->qd", lam, points[tris[best]])


def test_the_bucketed_search_finds_what_a_search_of_every_triangle_finds():
    uv, tris, points = _square()
    rng = np.random.default_rng(4)
    inside = rng.uniform(0.0, 1.0, (500, 2))
    off = np.array([[-1e-9, 0.5], [1.0 + 1e-9, 0.25], [0.5, -1e-9]])  # off by round-off
    queries = np.vstack([inside, off, uv])  # the vertices too: on several triangles at once
    np.testing.assert_allclose(
        carry_back(uv, tris, points, queries), _everywhere(uv, tris, points, queries), atol=1e-14
    )
    assert np.ptp(carry_back(uv, tris, points, inside)[:, 2]) > 0.1  # a curved surface


def test_the_closest_point_on_the_triangles_is_no_farther_than_any_point_on_them():
    uv, tris, points = _square()
    rng = np.random.default_rng(5)
    queries = np.column_stack([rng.uniform(0.1, 0.9, (300, 2)), rng.uniform(-0.2, 0.6, 300)])
    closest = closest_points(points, tris, queries)
    dense = carry_back(uv, tris, points, rng.uniform(0.0, 1.0, (20000, 2)))  # on the surface
    gap = np.linalg.norm(queries - closest, axis=1)
    nearest_dense = np.linalg.norm(queries[:, None] - dense[None], axis=2).min(axis=1)
    assert np.all(gap <= nearest_dense + 1e-12)
    # each closest point lies on the surface: its own closest point is itself
    np.testing.assert_allclose(closest_points(points, tris, closest), closest, atol=1e-12)
    # a sliver (three points on a line) among the triangles answers by its edges, not its
    # plane: the query stays off it
    sliver = np.array([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [2.0, 0.0, 0.0]])
    found = closest_points(sliver, np.array([[0, 1, 2]]), np.array([[0.5, 1.0, 0.0]]))
    np.testing.assert_allclose(found, [[0.5, 0.0, 0.0]], atol=1e-15)


def test_a_polar_bend_keeps_its_grid_polar():
    """The 90-degree bend of rectangular section (radii 1 to 2): the square map's face grid
    bends its arcs toward the inner wall, the TFI of the face sides keeps them on circles,
    and the default keeps the TFI volume grid over the Winslow grid, which bends them too."""
    result = mesh_surface(str(EXAMPLES / "hexa_bend.vtp"), make_settings("pinn", size=(21, 21, 21)))
    g = result.grid
    radius, angle = np.hypot(g[..., 0], g[..., 1]), np.degrees(np.arctan2(g[..., 1], g[..., 0]))
    # i runs along the arcs, j across them, k up: radial lines, on circles but for the sag of
    # the input's arcs (16 chords over 90 degrees: 2.4e-3 at radius 2)
    assert np.ptp(angle, axis=1).max() < 1e-6 and np.ptp(angle, axis=2).max() < 1e-6
    assert np.ptp(radius, axis=0).max() < ARC_SAG and np.ptp(radius, axis=2).max() < 1e-12
    assert result.model.info["start"] == "tfi"
    assert result.cells["MaxIncludedAngle"].max() < 93.0
