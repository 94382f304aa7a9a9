"""The input surface of a six-faced domain: its faces, 12 edges and 8 corners (SPEC 11).

Reads a closed triangulated surface with a ``FaceId`` cell array (or an ``.stl``, its faces
found at its sharp edges) and checks that its faces meet as a cube's do; anything else is a
one-line :class:`InputError` saying what was found.
"""

from __future__ import annotations

from collections import defaultdict
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.hexa.sharp import faces_at_sharp_edges
from pinn_engine.settings import FACE_ANGLE

if TYPE_CHECKING:
    from vtkmodules.vtkCommonDataModel import vtkPolyData

FACES = 6  # a hexahedral block has six faces
CORNERS = 8  # ... eight corners
SIDES = 4  # ... and each face has four sides
FACE_ARRAY = b"FaceId"  # the cell array that tags the six faces (SPEC 11)
MERGE_DIGITS = 9  # points closer than 1e-9 of the surface's size are one (files repeat them)


@dataclass
class Surface:
    """A closed triangulated surface split into six faces."""

    points: np.ndarray  # (n, 3)
    triangles: np.ndarray  # (m, 3) point indices
    face_of: np.ndarray  # (m,) face index 0..5 of each triangle
    face_ids: np.ndarray  # (6,) the input's FaceId of each face index (an STL's: 0..5)


@dataclass
class Topology:
    """The faces' cube structure: corners, the edge polylines between them, face triangles."""

    corners: list[int]  # 8 point indices
    edges: dict[tuple[int, int], list[int]]  # (corner a, corner b) -> point path from a to b
    face_corners: list[list[int]]  # per face, its 4 corners in boundary order
    face_triangles: list[np.ndarray]  # per face, indices into Surface.triangles


def is_faced_surface(path: str) -> bool:
    """Whether ``path`` is a six-faced domain's surface: an ``.stl``, or a .vtp/.vtk file
    naming a FaceId array (a scan of its bytes, since VTK files write array names as text
    and a damaged file must not be parsed here: the 2D reader reports it)."""
    name = str(path).lower()
    if name.endswith(".stl"):
        return True
    if not name.endswith((".vtp", ".vtk")):
        return False
    try:
        with open(path, "rb") as f:
            return FACE_ARRAY in f.read()
    except OSError:
        return False


def surface_of(
    data: vtkPolyData, source: str, sharp_edges: bool = False, angle: float = FACE_ANGLE
) -> Surface:
    """The triangles of a polydata (polygons are triangulated) with coincident points merged,
    and their faces: the FaceId array, or with ``sharp_edges`` (an STL has no arrays) the
    regions between its edges sharper than ``angle`` degrees (:mod:`pinn_engine.hexa.sharp`),
    numbered in the order of their first triangle. Plain VTK, so that ParaView's Python (no
    pyvista) can use it."""
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkFiltersCore import vtkTriangleFilter

    if not sharp_edges and data.GetCellData().GetArray(FACE_ARRAY.decode()) is None:
        raise InputError("no FaceId cell array: tag each of the six faces", source)
    triangulate = vtkTriangleFilter()
    triangulate.SetInputData(data)
    triangulate.PassVertsOff()
    triangulate.PassLinesOff()
    triangulate.Update()
    data = triangulate.GetOutput()
    if data.GetNumberOfPolys() == 0:
        raise InputError("holds no triangles or polygons: a closed surface is needed", source)
    faces = vtk_to_numpy(data.GetPolys().GetConnectivityArray()).reshape(-1, 3)
    points = vtk_to_numpy(data.GetPoints().GetData()).astype(float)
    if not np.isfinite(points).all():
        raise InputError("holds a non-finite point", source)
    scale = float(np.ptp(points, axis=0).max()) or 1.0
    _, first, inverse = np.unique(
        np.round(points / scale, MERGE_DIGITS), axis=0, return_index=True, return_inverse=True
    )
    triangles = inverse.reshape(-1)[faces]
    keep = (
        (triangles[:, 0] != triangles[:, 1])
        & (triangles[:, 1] != triangles[:, 2])
        & (triangles[:, 0] != triangles[:, 2])
    )
    points, triangles = points[first], triangles[keep]
    if sharp_edges:
        count, face_of = faces_at_sharp_edges(points, triangles, angle)
        if count != FACES:
            raise InputError(
                f"found {count} faces at edges sharper than {angle:g} degrees; a "
                "six-faced domain needs 6 (try {face_angle})",
                source,
            )
        return Surface(points, triangles, face_of, np.arange(FACES))
    ids = vtk_to_numpy(data.GetCellData().GetArray(FACE_ARRAY.decode())).astype(int)
    values, face_of = np.unique(ids[keep], return_inverse=True)
    if len(values) != FACES:
        raise InputError(f"{len(values)} FaceId values found; a hexahedral block needs 6", source)
    return Surface(points, triangles, face_of.reshape(-1), values)


def _edge_triangles(triangles: np.ndarray) -> dict[tuple[int, int], list[int]]:
    """Each undirected mesh edge and the triangles that hold it."""
    owners: dict[tuple[int, int], list[int]] = defaultdict(list)
    for t, (a, b, c) in enumerate(triangles.tolist()):
        for u, v in ((a, b), (b, c), (c, a)):
            owners[(min(u, v), max(u, v))].append(t)
    return owners


def _boundary_loop(triangles: np.ndarray, face: int, source: str) -> list[int]:
    """The one closed boundary loop of a face (the triangles' winding need not agree);
    errors if the face is not a disk (a pinch, several loops, Euler characteristic not 1)."""
    owners = _edge_triangles(triangles)
    around: dict[int, list[int]] = defaultdict(list)
    for (u, v), tris in owners.items():
        if len(tris) == 1:
            around[u].append(v)
            around[v].append(u)
    vertices = len(np.unique(triangles))
    euler = vertices - len(owners) + len(triangles)
    if not around or euler != 1:
        raise InputError(
            f"face {face} is not a disk (Euler characteristic {euler}, expected 1)", source
        )
    if any(len(v) != 2 for v in around.values()):
        raise InputError(f"face {face} is pinched at a point: not a disk", source)
    loop = [next(iter(around))]
    previous = None
    while True:
        a, b = around[loop[-1]]
        following = b if a == previous else a
        if following == loop[0]:
            break
        previous = loop[-1]
        loop.append(following)
    if len(loop) != len(around):
        raise InputError(f"face {face} has several boundary loops: not a disk", source)
    return loop


def find_topology(surface: Surface, source: str) -> Topology:
    """Corners, edges and face sides of ``surface``; checks closedness and cube topology."""
    owners = _edge_triangles(surface.triangles)
    counts = np.array([len(v) for v in owners.values()])
    if (counts != 2).any():
        open_edges, bad = int((counts == 1).sum()), int((counts > 2).sum())
        raise InputError(
            f"the surface is not closed: {open_edges} open edges, {bad} edges with more "
            "than two triangles",
            source,
        )
    face_triangles = [np.flatnonzero(surface.face_of == f) for f in range(FACES)]
    faces_at: dict[int, set[int]] = defaultdict(set)
    for f, tri in enumerate(face_triangles):
        for p in np.unique(surface.triangles[tri]).tolist():
            faces_at[p].add(f)
    corners = sorted(p for p, fs in faces_at.items() if len(fs) >= 3)
    if len(corners) != CORNERS:
        raise InputError(
            f"{len(corners)} corners found (points where three faces meet); a hexahedral "
            "block has 8",
            source,
        )
    corner_set = set(corners)
    edges: dict[tuple[int, int], list[int]] = {}
    face_corners = []
    for f, tri in enumerate(face_triangles):
        loop = _boundary_loop(surface.triangles[tri], f, source)
        at = [n for n, p in enumerate(loop) if p in corner_set]
        if len(at) != SIDES:
            raise InputError(f"face {f} has {len(at)} corners; each face needs 4 sides", source)
        face_corners.append([loop[n] for n in at])
        for s in range(SIDES):
            first, last = at[s], at[(s + 1) % SIDES]
            path = loop[first : last + 1] if last > first else loop[first:] + loop[: last + 1]
            edges.setdefault((path[0], path[-1]), path)
            edges.setdefault((path[-1], path[0]), path[::-1])
    if len(edges) != 2 * 12:  # 12 edges, each stored in both directions
        raise InputError(f"{len(edges) // 2} edges found; a hexahedral block has 12", source)
    return Topology(corners, edges, face_corners, face_triangles)
