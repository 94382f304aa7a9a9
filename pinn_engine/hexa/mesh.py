"""A hexahedral grid of a six-faced surface, from file to vtkStructuredGrid (SPEC 11); the
solver formats write it through :func:`pinn_engine.io.export.write`."""

from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.hexa import quality, volume
from pinn_engine.hexa.block import cube_corners
from pinn_engine.hexa.facegrid import face_grid
from pinn_engine.hexa.surface import Surface, Topology, find_topology, read_surface

METHODS = ("tfi", "elliptic")  # the methods of this build for six-faced domains
HEXA_METHOD = "elliptic"  # the default while 3D has no pinn: the converged Winslow grid
HEXA_SIZE = (21, 21, 21)  # SPEC 11's default nodes along i, j and k
MIN_NODES = 3  # fewer nodes along a direction leave no interior to solve for


@dataclass
class HexResult:
    """The grid (ni, nj, nk, 3), its cell arrays and the run's seconds."""

    grid: np.ndarray
    cells: dict[str, np.ndarray]
    seconds: float
    iterations: int


def boundary_grid(
    surface: Surface, topology: Topology, size: tuple[int, int, int], source: str
) -> np.ndarray:
    """An (ni, nj, nk, 3) array whose six faces hold the face grids (interior zero)."""
    cube = cube_corners(surface, topology, source)
    g = np.zeros((*size, 3))
    for axis in range(3):
        a, b = (x for x in range(3) if x != axis)
        for value in (0, 1):

            def corner(ta: int, tb: int, a=a, b=b, axis=axis, value=value) -> int:
                c = [0, 0, 0]
                c[axis], c[a], c[b] = value, ta, tb
                return cube[tuple(c)]

            ring = {corner(0, 0), corner(1, 0), corner(0, 1), corner(1, 1)}
            face = next(f for f, cs in enumerate(topology.face_corners) if set(cs) == ring)
            sides = {
                "a0": topology.edges[(corner(0, 0), corner(1, 0))],
                "a1": topology.edges[(corner(0, 1), corner(1, 1))],
                "b0": topology.edges[(corner(0, 0), corner(0, 1))],
                "b1": topology.edges[(corner(1, 0), corner(1, 1))],
            }
            at = [slice(None)] * 3
            at[axis] = 0 if value == 0 else -1
            g[tuple(at)] = face_grid(
                surface, topology.face_triangles[face], sides, (size[a], size[b])
            )
    return g


def mesh_surface(path: str, size: tuple[int, int, int], method: str) -> HexResult:
    """Read ``path``, check its topology, build the face grids and the volume grid."""
    if method not in METHODS:
        raise InputError(
            f"--method {method}: six-faced 3D domains are meshed by {' or '.join(METHODS)} "
            "in this build"
        )
    if min(size) < MIN_NODES:
        raise InputError(f"--size {' '.join(map(str, size))}: each needs at least 3 nodes")
    start = time.perf_counter()
    surface = read_surface(path)
    topology = find_topology(surface, path)
    g = volume.tfi(boundary_grid(surface, topology, size, path))
    iterations = 0
    if method == "elliptic":
        g, iterations = volume.winslow(g)
    cells = cell_arrays(g)
    return HexResult(g, cells, time.perf_counter() - start, iterations)


def structured_grid(g: np.ndarray):
    """A pyvista StructuredGrid of the (ni, nj, nk, 3) array (i fastest, as VTK's)."""
    import pyvista as pv

    return pv.StructuredGrid(g[..., 0], g[..., 1], g[..., 2])


def cell_arrays(g: np.ndarray) -> dict[str, np.ndarray]:
    """SPEC 11's cell arrays of a grid."""
    largest, smallest = quality.included_angles(g)
    return {
        "MaxIncludedAngle": largest,
        "MinIncludedAngle": smallest,
        "ScaledJacobian": quality.scaled_jacobian(structured_grid(g)),
        "Folded": quality.folded(g),
    }


def result_grid(result: HexResult, method: str):
    """The grid with its cell arrays and method (the writers add the patch names)."""
    grid = structured_grid(result.grid)
    for name, values in result.cells.items():
        grid.cell_data[name] = values
    grid.field_data["Method"] = [method]
    return grid


def summary(result: HexResult, method: str) -> str:
    """One line: cells, folds, min ScaledJacobian, mean/worst MaxIncludedAngle, time."""
    ni, nj, nk = result.grid.shape[:3]
    c = result.cells
    return (
        f"{method} {ni}x{nj}x{nk} hexahedral grid, {c['Folded'].size} cells in "
        f"{result.seconds:.2f} s: {int(c['Folded'].sum())} folded, min ScaledJacobian "
        f"{c['ScaledJacobian'].min():.3f}, mean MaxIncludedAngle "
        f"{c['MaxIncludedAngle'].mean():.2f} deg, worst {c['MaxIncludedAngle'].max():.2f} deg"
        + (f" ({result.iterations} Picard steps)" if result.iterations else "")
    )
