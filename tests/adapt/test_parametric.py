"""The adaptive equations solved in the unadapted grid's parameter space: the unadapted grid
kept exactly where the monitor is flat, thin rows moved as one, the inversion of the
computational coordinates, and a C-grid whose error is halved within the guard."""

from __future__ import annotations

import numpy as np
import pytest

from pinn_engine.adapt.nodes import node_graph
from pinn_engine.adapt.parametric import ParameterSpace, _inverted, bilinear, own_diffusion
from pinn_engine.quality import cell_quality


def graded(ni: int = 17, nj: int = 13) -> np.ndarray:
    """A channel whose rows are 1e-3 thick at the bottom wall, growing by 1.5, and whose
    columns are graded too: cells up to a hundred times longer than thick."""
    rows = np.concatenate([[0.0], np.cumsum(1e-3 * 1.5 ** np.arange(nj - 1))])
    cols = np.linspace(0.0, 1.0, ni) ** 1.3
    x, y = np.meshgrid(cols, rows / rows[-1] * 0.5)
    return np.stack([x, y + 0.05 * np.sin(np.pi * x) * y], axis=-1)


def front(points: np.ndarray) -> np.ndarray:
    return np.tanh((points[:, 0] - 0.55 + 0.3 * points[:, 1]) / 0.02)


def test_a_flat_monitor_keeps_the_unadapted_grid_exactly():
    """xi = u, eta = v solve the equations with M constant, gradings and thin rows included."""
    grid = graded()
    graph = node_graph([grid])
    space = ParameterSpace(graph, front)
    out = space.solve(np.zeros(len(graph.points)))
    assert np.abs(out.points - graph.points).max() < 1e-12


def test_the_diffusion_is_the_physical_anisotropy_and_keeps_the_lattice_harmonic():
    """On a product grid T_22 / T_11 = (L / h)^2 in every cell of the xi equation, and xi's
    factor along i is one value a row (so xi = u is discrete-harmonic)."""
    cols = np.array([0.0, 0.1, 0.3, 0.7])
    rows = np.array([0.0, 0.001, 0.003, 0.01])
    x, y = np.meshgrid(cols, rows)
    grid = np.stack([x, y], axis=-1)
    (xi_i, xi_j), (eta_i, eta_j) = own_diffusion(grid)
    assert np.allclose(np.ptp(xi_i, axis=1), 0.0) and np.allclose(np.ptp(eta_j, axis=0), 0.0)
    q = np.log(np.diff(cols)[None, :] / np.diff(rows)[:, None])  # log(L / h), cell by cell
    assert np.allclose(xi_j / xi_i, np.exp(2 * q)) and np.allclose(eta_i / eta_j, np.exp(-2 * q))
    assert np.allclose(xi_i[:, 0], np.exp(-q.mean(axis=1)))
    assert np.allclose(eta_j[0, :], np.exp(q.mean(axis=0)))


def test_the_inversion_recovers_an_affine_map():
    rows, cols = 9, 13
    v, u = np.meshgrid(np.arange(rows) / 2.0, np.arange(cols) / 2.0, indexing="ij")
    xi, eta = 1.5 * u + 0.2 * v, 0.1 * u + 0.8 * v  # a map onto a parallelogram
    ti, tj = np.array([1, 2, 3]), np.array([1, 1, 2])
    uv = _inverted(xi, eta, u, v, ti, tj)
    back = np.column_stack([1.5 * uv[:, 0] + 0.2 * uv[:, 1], 0.1 * uv[:, 0] + 0.8 * uv[:, 1]])
    assert np.allclose(back, np.column_stack([ti, tj]))


def test_thin_rows_beside_a_node_that_stays_keep_the_guard():
    """A front across a graded channel (wall cells a hundred times longer than thick), a
    wall node in the middle held: the adapted grid has no fold, its worst cell within the
    guard's 10 degrees, the node held in place, and the field's error lower."""
    from pinn_engine.adapt.error import interpolation_error
    from pinn_engine.adapt.grids import GUARD_DEGREES, adapt_grids

    class Front:
        source, array = "front", "f"

        def check_covers(self, points):
            pass

        def sample(self, points):
            return front(points)

    grid = graded()
    held = np.zeros(grid.shape[:2], dtype=bool)
    held[0, 8] = True
    out = adapt_grids([grid], Front(), 20.0, [held])
    new = out.grids[0]
    q0, q1 = cell_quality(grid), cell_quality(new)
    assert not q1["Folded"].any()
    assert q1["MaxIncludedAngle"].max() <= q0["MaxIncludedAngle"].max() + GUARD_DEGREES + 1e-9
    assert np.array_equal(new[0, 8], grid[0, 8])
    g0, g1 = node_graph([grid]), node_graph([new])
    assert interpolation_error(g1.points, g1.cells, front) < interpolation_error(
        g0.points, g0.cells, front
    )


def test_bilinear_is_the_grid_at_its_nodes():
    grid = graded(5, 4)
    j, i = np.meshgrid(np.arange(4), np.arange(5), indexing="ij")
    assert np.array_equal(bilinear(grid, i.astype(float), j.astype(float)), grid)


@pytest.mark.slow
def test_a_c_grid_halves_a_boundary_layer_error_within_the_guard():
    """The NACA 0012 C-grid of the benchmark (161 x 41, wall spacing 1e-3) adapted to a
    layer along its lowest far field, through the whole adaptation (strengths and guard)."""
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonDataModel import vtkImageData

    from pinn_engine.adapt import Field
    from pinn_engine.adapt.grids import adapt_grids
    from pinn_engine.bodies.airfoil import circle, load_body
    from pinn_engine.kinds.body.mesh import mesh_body
    from pinn_engine.settings import make_settings

    settings = make_settings("elliptic", topology="c", farfield=5.0)
    body = load_body(naca="0012", te="sharp")
    grid = mesh_body(body, circle(body, 5.0), "c", "elliptic", 161, 41, settings, 1e-3, None)
    grid = grid.points
    lo, hi = grid.reshape(-1, 2).min(axis=0), grid.reshape(-1, 2).max(axis=0)

    def layer(x, y):
        return 1.0 - np.exp(-(y - lo[1]) / (0.03 * (hi[0] - lo[0])))

    im, n = vtkImageData(), 401
    im.SetDimensions(n, n, 1)
    im.SetOrigin(lo[0] - 0.1, lo[1] - 0.1, 0.0)
    step = (hi - lo + 0.2) / (n - 1)
    im.SetSpacing(step[0], step[1], 1.0)
    x, y = np.meshgrid(lo[0] - 0.1 + step[0] * np.arange(n), lo[1] - 0.1 + step[1] * np.arange(n))
    values = numpy_to_vtk(np.ascontiguousarray(layer(x.ravel(), y.ravel())), deep=True)
    values.SetName("p")
    im.GetPointData().AddArray(values)
    out = adapt_grids([grid], Field(im, "p"))
    report = out.report
    assert report["interpolation_error"]["after"] <= 0.5 * report["interpolation_error"]["before"]
    assert report["folded_cells"]["after"] == 0
    assert report["worst_max_angle"]["after"] <= report["worst_max_angle"]["before"] + 10
