"""Index directions of a six-faced domain (SPEC 11): which input corner is each corner of
the unit cube, so that corner 0 has the smallest x + y + z (ties within ``TIE`` of the
diagonal: the smallest x, then y, then z), i leaves it nearest +x, and (i, j, k) is
right-handed."""

from __future__ import annotations

import itertools

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.hexa.surface import Surface, Topology

TIE = 1e-6  # coordinates within this fraction of the diagonal are equal (SPEC 11)


def _neighbours(topology: Topology, corner: int) -> set[int]:
    return {b for a, b in topology.edges if a == corner}


def _common(topology: Topology, a: int, b: int, other_than: int, source: str) -> int:
    """The one corner joined by edges to both ``a`` and ``b`` besides ``other_than``."""
    found = (_neighbours(topology, a) & _neighbours(topology, b)) - {other_than}
    if len(found) != 1:
        raise InputError("the faces do not meet as a cube's do", source)
    return found.pop()


def first_corner(points: np.ndarray, corners: list[int]) -> int:
    """Corner 0 of SPEC 11 among ``corners`` (point indices): the smallest x + y + z, ties
    within ``TIE`` of the diagonal broken by the smallest x, then y, then z (each again
    within ``TIE``), so that a symmetric shape's corner 0 does not hang on rounding."""
    xyz = points[corners]
    tol = TIE * float(np.linalg.norm(np.ptp(points, axis=0)))
    keys = np.column_stack([xyz.sum(axis=1), xyz])
    left = np.arange(len(corners))
    for column in keys.T:
        values = column[left]
        left = left[values <= values.min() + tol]
    return corners[int(left[0])]


def cube_corners(surface: Surface, topology: Topology, source: str) -> dict[tuple, int]:
    """Unit-cube corner (a, b, c) in {0, 1}^3 -> the input corner's point index."""
    pts = surface.points
    c0 = first_corner(pts, topology.corners)
    ends = sorted(_neighbours(topology, c0))
    if len(ends) != 3:
        raise InputError(f"corner 0 has {len(ends)} edges; a hexahedron's have 3", source)
    chord = {e: (pts[e] - pts[c0]) / np.linalg.norm(pts[e] - pts[c0]) for e in ends}
    i_end = max(ends, key=lambda e: float(chord[e][0]))
    j_end, k_end = (e for e in ends if e != i_end)
    if np.linalg.det(np.array([chord[i_end], chord[j_end], chord[k_end]])) < 0:
        j_end, k_end = k_end, j_end
    cube = {(0, 0, 0): c0, (1, 0, 0): i_end, (0, 1, 0): j_end, (0, 0, 1): k_end}
    for a, b in itertools.combinations(((1, 0, 0), (0, 1, 0), (0, 0, 1)), 2):
        both = tuple(x + y for x, y in zip(a, b, strict=True))
        cube[both] = _common(topology, cube[a], cube[b], c0, source)
    cube[(1, 1, 1)] = _common(topology, cube[(1, 1, 0)], cube[(1, 0, 1)], cube[(1, 0, 0)], source)
    if len(set(cube.values())) != 8:
        raise InputError("the faces do not meet as a cube's do", source)
    return cube
