"""Face nodes carried back to the input triangles (hexa/facegrid.py): the search among the
triangles whose bounding box holds a node finds the same triangle and point as a search
among all of them, inside the mapped square and just off it."""

from __future__ import annotations

import numpy as np

from pinn_engine.hexa.facegrid import carry_back

CELLS = 12  # the mapped square's triangulation: CELLS x CELLS squares, each cut in two
JITTER = 0.3  # interior vertices moved by up to this share of a cell: uneven triangles


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
