"""Writes the six-faced example surfaces of SPEC 11 (run from the repository root) into
example_data/: hexa_bump_box.vtp (a box with a bump in its floor), hexa_bend.vtp (a 90-degree
bend of rectangular section), hexa_twisted_duct.vtp (a square duct twisted by 90 degrees),
hexa_nozzle.vtp (a contracting nozzle) and hexa_sheared_wavy.vtp (a sheared hexahedron with a
wavy top face). Each face is a triangulated patch tagged with its FaceId; neighbouring faces
share their edge points. The bend is also written untagged as hexa_bend.stl (binary), whose
faces the engine finds at its 90-degree edges."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pyvista as pv

PATCH_NODES = 17  # points along each side of a face's patch (coarser or finer than grids)
FINE_PATCH_NODES = 33  # ... for the twisted, contracting and wavy faces: smooth at 41 nodes
BUMP_HEIGHT = 0.15  # the floor bump's height (the box is 2 x 1 x 0.6)
BUMP_WIDTH = 0.03  # the floor bump's Gaussian variance in (u, v)
TWIST = 0.5 * np.pi  # the duct's twist from inlet to outlet (its section is 1 x 1, length 3)
INLET_HALF, THROAT_HALF = 0.5, 0.25  # the nozzle's half-widths: area ratio 4 over length 2
SHEAR = 0.4  # the hexahedron's top is shifted this far in x (its base is 1.5 x 1, height 0.8)
WAVE = 0.05  # the wavy top face's amplitude (two waves along x, one along y)
MERGE_DIGITS = 9  # points of two faces closer than 1e-9 are one


def bump_box(u, v, w):
    """The unit cube onto a 2 x 1 x 0.6 box whose floor (w = 0) has a bump."""
    bump = BUMP_HEIGHT * np.exp(-((u - 0.5) ** 2 + (v - 0.5) ** 2) / BUMP_WIDTH)
    return np.stack([2.0 * u, v, 0.6 * w + bump * (1.0 - w)], axis=-1)


def bend(u, v, w):
    """The unit cube onto a quarter annulus (radii 1 to 2) 0.8 high: a 90-degree bend."""
    radius, angle = 1.0 + u, 0.5 * np.pi * v
    return np.stack([radius * np.cos(angle), radius * np.sin(angle), 0.8 * w], axis=-1)


def twisted_duct(u, v, w):
    """The unit cube onto a 1 x 1 square duct of length 3 along x whose section turns by
    ``TWIST`` about the axis, evenly along it."""
    angle = TWIST * u
    a, b = v - 0.5, w - 0.5
    return np.stack(
        [3.0 * u, a * np.cos(angle) - b * np.sin(angle), a * np.sin(angle) + b * np.cos(angle)],
        axis=-1,
    )


def nozzle(u, v, w):
    """The unit cube onto a square nozzle of length 2 along x whose half-width falls from
    ``INLET_HALF`` to ``THROAT_HALF`` along a half cosine (smooth at both ends)."""
    half = INLET_HALF + (THROAT_HALF - INLET_HALF) * 0.5 * (1.0 - np.cos(np.pi * u))
    return np.stack([2.0 * u, half * (2.0 * v - 1.0), half * (2.0 * w - 1.0)], axis=-1)


def sheared_wavy(u, v, w):
    """The unit cube onto a parallelepiped sheared by ``SHEAR`` in x whose top face (w = 1)
    waves with amplitude ``WAVE``; the wave fades linearly to the flat base."""
    wave = WAVE * np.sin(4.0 * np.pi * u) * np.sin(np.pi * v)
    return np.stack([1.5 * u + SHEAR * w, v, (0.8 + wave) * w], axis=-1)


def surface(shape, nodes: int = PATCH_NODES) -> pv.PolyData:
    """The six faces of ``shape`` (a map of the unit cube) as tagged triangles; the
    diagonals alternate so that the triangles follow no grid direction."""
    s = np.linspace(0.0, 1.0, nodes)
    a, b = np.meshgrid(s, s, indexing="ij")
    points, triangles, ids = [], [], []
    for face, (axis, value) in enumerate((ax, v) for ax in range(3) for v in (0.0, 1.0)):
        coords = [None, None, None]
        coords[axis] = np.full_like(a, value)
        coords[[x for x in range(3) if x != axis][0]] = a
        coords[[x for x in range(3) if x != axis][1]] = b
        p = shape(*coords).reshape(-1, 3)
        n = nodes
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
    surface(twisted_duct, FINE_PATCH_NODES).save(here / "hexa_twisted_duct.vtp")
    surface(nozzle, FINE_PATCH_NODES).save(here / "hexa_nozzle.vtp")
    surface(sheared_wavy, FINE_PATCH_NODES).save(here / "hexa_sheared_wavy.vtp")


if __name__ == "__main__":
    main()
