"""A hexahedral grid of a six-faced surface, from file to vtkStructuredGrid (SPEC 11)."""

from __future__ import annotations

import hashlib
import time
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.errors import InputError, network_effect
from pinn_engine.hexa import quality, volume
from pinn_engine.hexa.block import cube_corners
from pinn_engine.hexa.facegrid import face_grid
from pinn_engine.hexa.surface import Surface, Topology, find_topology, read_surface

if TYPE_CHECKING:
    from pinn_engine.blocks.hexa import HexaModel

METHODS = ("pinn", "tfi", "elliptic")  # the methods of this build for six-faced domains
PATCHES = ("imin", "imax", "jmin", "jmax", "kmin", "kmax")  # SPEC 11's patch names
HEXA_METHOD = "pinn"  # SPEC 11's default (blocks/hexa.py; docs/hexa.md has its figures)
HEXA_SIZE = (21, 21, 21)  # SPEC 11's default nodes along i, j and k
MIN_NODES = 3  # fewer nodes along a direction leave no interior to solve for


@dataclass
class HexResult:
    """The grid (ni, nj, nk, 3), its cell arrays, the run's seconds, the Winslow solve's
    Picard steps and, for pinn, the trained model (blocks/hexa.py's HexaModel)."""

    grid: np.ndarray
    cells: dict[str, np.ndarray]
    seconds: float
    iterations: int
    model: HexaModel | None = None


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


def surface_key(surface: Surface) -> str:
    """A digest of the surface's points and triangles: a saved pinn model is evaluated only
    on the surface it was trained on."""
    digest = hashlib.sha256(np.ascontiguousarray(surface.points).tobytes())
    digest.update(np.ascontiguousarray(surface.triangles).tobytes())
    return digest.hexdigest()


def mesh_surface(
    path: str, size: tuple[int, int, int], method: str, load_model: str | None = None
) -> HexResult:
    """Read ``path``, check its topology, build the face grids and the volume grid; pinn
    trains its network, or evaluates the one saved at ``load_model``."""
    if method not in METHODS:
        raise InputError(
            f"--method {method}: six-faced 3D domains are meshed by {', '.join(METHODS)}"
        )
    if min(size) < MIN_NODES:
        raise InputError(f"--size {' '.join(map(str, size))}: each needs at least 3 nodes")
    start = time.perf_counter()
    surface = read_surface(path)
    topology = find_topology(surface, path)
    g = volume.tfi(boundary_grid(surface, topology, size, path))

    def tfi_of(shape: tuple[int, ...]) -> np.ndarray:
        """The TFI grid of ``shape`` nodes (the pinn's lattice)."""
        if tuple(shape) == tuple(size):
            return g
        return volume.tfi(boundary_grid(surface, topology, shape, path))

    iterations, model = 0, None
    if method == "elliptic":
        g, iterations = volume.winslow(g)
    elif method == "pinn":  # torch only for the network
        from pinn_engine.blocks.hexa import HexaModel, train

        key = surface_key(surface)
        model = HexaModel.load(load_model, key) if load_model else train(tfi_of, size, key)
        g = model.grid(g)
    cells = cell_arrays(g)
    return HexResult(g, cells, time.perf_counter() - start, iterations, model)


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


def write_vts(result: HexResult, out, method: str) -> None:
    """The grid with its cell arrays, method and patch names as a .vts file."""
    from pinn_engine.io.fileio import atomic_path

    grid = structured_grid(result.grid)
    for name, values in result.cells.items():
        grid.cell_data[name] = values
    grid.field_data["Method"] = [method]
    grid.field_data["Patches"] = list(PATCHES)
    if result.model:  # what the network did, as io/vtkgrid.py writes it for 2D
        grid.field_data["NetworkResult"] = [result.model.info["result"]]
        grid.field_data["LargestNodeMove"] = [result.model.info["largest_node_move"]]
    with atomic_path(out, suffix=".vts") as tmp:
        grid.save(str(tmp))


def summary(result: HexResult, method: str) -> str:
    """One line: cells, folds, min ScaledJacobian, mean/worst MaxIncludedAngle, time, and
    what the network did."""
    ni, nj, nk = result.grid.shape[:3]
    c = result.cells
    return (
        f"{method} {ni}x{nj}x{nk} hexahedral grid, {c['Folded'].size} cells in "
        f"{result.seconds:.2f} s: {int(c['Folded'].sum())} folded, min ScaledJacobian "
        f"{c['ScaledJacobian'].min():.3f}, mean MaxIncludedAngle "
        f"{c['MaxIncludedAngle'].mean():.2f} deg, worst {c['MaxIncludedAngle'].max():.2f} deg"
        + (f" ({result.iterations} Picard steps)" if result.iterations else "")
        + (f"; {network_effect({'training': result.model.info})}" if result.model else "")
    )
