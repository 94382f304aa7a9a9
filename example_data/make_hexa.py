"""Writes the six-faced example surfaces of SPEC 11 (run from the repository root):
example_data/hexa_bump_box.vtp (a box with a bump in its floor) and example_data/hexa_bend.vtp
(a 90-degree bend of rectangular section). Each face is a triangulated patch tagged with its
FaceId; neighbouring faces share their edge points. The bend is also written untagged as
example_data/hexa_bend.stl (binary), whose faces the engine finds at its 90-degree edges."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyvista as pv

PATCH_NODES = 17  # points along each side of a face's patch (coarser or finer than grids)
BUMP_HEIGHT = 0.15  # the floor bump's height (the box is 2 x 1 x 0.6)
BUMP_WIDTH = 0.03  # the floor bump's Gaussian variance in (u, v)
MERGE_DIGITS = 9  # points of two faces closer than 1e-9 are one


def bump_box(u, v, w):
    """The unit cube onto a 2 x 1 x 0.6 box whose floor (w = 0) has a bump."""
    bump = BUMP_HEIGHT * np.exp(-((u - 0.5) ** 2 + (v - 0.5) ** 2) / BUMP_WIDTH)
    return np.stack([2.0 * u, v, 0.6 * w + bump * (1.0 - w)], axis=-1)


def bend(u, v, w):
    """The unit cube onto a quarter annulus (radii 1 to 2) 0.8 high: a 90-degree bend."""
    radius, angle = 1.0 + u, 0.5 * np.pi * v
    return np.stack([radius * np.cos(angle), radius * np.sin(angle), 0.8 * w], axis=-1)


def surface(shape) -> pv.PolyData:
    """The six faces of ``shape`` (a map of the unit cube) as tagged triangles; the
    diagonals alternate so that the triangles follow no grid direction."""
    s = np.linspace(0.0, 1.0, PATCH_NODES)
    a, b = np.meshgrid(s, s, indexing="ij")
    points, triangles, ids = [], [], []
    for face, (axis, value) in enumerate((ax, v) for ax in range(3) for v in (0.0, 1.0)):
        coords = [None, None, None]
        coords[axis] = np.full_like(a, value)
        coords[[x for x in range(3) if x != axis][0]] = a
        coords[[x for x in range(3) if x != axis][1]] = b
        p = shape(*coords).reshape(-1, 3)
        n = PATCH_NODES
        base = sum(len(q) for q in points)
        for i in range(n - 1):
            for j in range(n - 1):
                q = [i * n + j, (i + 1) * n + j, (i + 1) * n + j + 1, i * n + j + 1]
                pair = ((0, 1, 2), (0, 2, 3)) if (i + j) % 2 else ((0, 1, 3), (1, 2, 3))
                for t in pair:
                    triangles.append([base + q[x] for x in t])
                    ids.append(face)
        points.append(p)
    allp = np.concatenate(points)
    unique, inverse = np.unique(np.round(allp, MERGE_DIGITS), axis=0, return_inverse=True)
    tri = inverse.reshape(-1)[np.array(triangles)]
    mesh = pv.PolyData(unique, np.hstack([np.full((len(tri), 1), 3), tri]).ravel())
    mesh.cell_data["FaceId"] = np.array(ids, dtype=np.int32)
    return mesh


def main() -> None:
    here = Path(__file__).parent
    surface(bump_box).save(here / "hexa_bump_box.vtp")
    tagged_bend = surface(bend)
    tagged_bend.save(here / "hexa_bend.vtp")
    tagged_bend.save(here / "hexa_bend.stl")


if __name__ == "__main__":
    main()
