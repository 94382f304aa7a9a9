"""A multi-block grid adapted with its blocks joined: the unadapted grid kept where the
field is flat, the operator's split Delaunay in the tensor's metric, a junction inside the
domain moved toward an oblique front with the corners on the boundary kept, and the slip
that turns the cells compressed across an oblique front along it instead of shearing them."""

from __future__ import annotations

import numpy as np

from pinn_engine.adapt.error import interpolation_error
from pinn_engine.adapt.guard import _angles, guarded
from pinn_engine.adapt.joined import _split, _stiffness
from pinn_engine.adapt.monitor import oriented, slipped
from pinn_engine.adapt.nodes import node_graph
from pinn_engine.adapt.parametric import ParameterSpace
from pinn_engine.quality import cell_quality


def four_blocks() -> list[np.ndarray]:
    """A square cut into four blocks of 13 x 13 nodes at its centre (a junction of four),
    the columns graded (a flat field must keep the grading)."""
    out = []
    for x0, y0 in ((0.0, 0.0), (0.5, 0.0), (0.0, 0.5), (0.5, 0.5)):
        t = np.linspace(0.0, 1.0, 13)
        x, y = np.meshgrid(x0 + 0.5 * t**1.2, np.linspace(y0, y0 + 0.5, 13))
        out.append(np.stack([x, y], axis=-1))
    return out


def oblique(points: np.ndarray) -> np.ndarray:
    """A front across the square's diagonal, beyond the junction (x + y = 1.3)."""
    return np.tanh((points[:, 0] + points[:, 1] - 1.3) / 0.05)


def test_a_flat_field_keeps_the_joined_grid_and_its_junction_exactly():
    graph = node_graph(four_blocks())
    assert np.allclose(graph.points[graph.junctions], [[0.5, 0.5]])
    space = ParameterSpace(graph, oblique)
    out = space.solve(np.zeros(len(graph.points)), joined=True)
    assert np.abs(out.points - graph.points).max() < 1e-12


def test_the_split_is_delaunay_in_the_tensors_metric():
    """A strongly anisotropic D across the square's diagonal: each sub-cell is cut along the
    diagonal whose finite-element weight is not negative (an edge weight is minus the
    operator's off-diagonal entry)."""
    x, y = np.meshgrid(np.linspace(0.0, 1.0, 5), np.linspace(0.0, 1.0, 5))
    points = np.column_stack([x.ravel(), y.ravel()])
    k = np.arange(25).reshape(5, 5)
    quads = np.stack([k[:-1, :-1], k[:-1, 1:], k[1:, 1:], k[1:, :-1]], -1).reshape(-1, 4)
    n = np.array([1.0, 1.0]) / np.sqrt(2.0)
    d = np.outer(n, n) / 20.0 + np.outer([-n[1], n[0]], [-n[1], n[0]])  # across 1/20
    tensor = np.tile([d[0, 0], d[0, 1], d[1, 1]], (25, 1))
    triangles = _split(points, quads, tensor)
    lap = _stiffness(points, triangles, tensor[triangles].mean(axis=1)).toarray()
    off = lap - np.diag(np.diag(lap))
    assert off.max() <= 1e-12
    inside = (points > 0.0).all(axis=1) & (points < 1.0).all(axis=1)
    assert np.abs((lap @ points)[inside]).max() < 1e-12  # a linear function is harmonic


def test_an_oblique_front_moves_the_junction_toward_it_within_the_guard():
    """The junction of four blocks moves toward the front (x + y = 1.3), as no block's own
    solve can move it; the boundary's corners and block corners stay, no cell folds, the
    worst cell keeps the guard's bound and the field is carried better."""
    graph = node_graph(four_blocks())
    limit = 100.0  # the unadapted grid's worst cell (90 degrees) and the guard's 10
    space = ParameterSpace(graph, oblique, limit)
    before = interpolation_error(graph.points, graph.cells, oblique)
    found = guarded(graph, space, 5.0, limit, bound=before, joined=True)
    points = found.solved.points
    junction = graph.junctions
    assert (points[junction] - graph.points[junction]).sum() > 0.01
    stays = graph.held & ~junction
    assert np.array_equal(points[stays], graph.points[stays])
    for grid in graph.grids(points):
        quality = cell_quality(grid)
        assert not quality["Folded"].any() and quality["MaxIncludedAngle"].max() <= limit
    assert found.error < before


def test_the_slip_keeps_a_compressed_square_a_rectangle():
    """A square at 37 degrees to a front compressed by c = 0.3 across it: the slip along the
    front that the slipped tensor's cross term gives, s = -c q / p, maps its edges to
    perpendicular ones, across the front compressed by c as before; a stretched cell (c > 1)
    keeps D."""
    n, t = np.array([0.8, 0.6]), np.array([-0.6, 0.8])
    e1, e2 = np.array([1.0, 0.0]), np.array([0.0, 1.0])
    d = oriented(n, np.array(0.05), np.array(1.0))
    for c in (0.3, 1.5):
        jacobian = np.eye(2) + (1.0 / c - 1.0) * np.outer(n, n)  # d xi / d x across the front
        out = slipped(d, n, jacobian, e1, e2)
        tensor = np.array([[out[0], out[1]], [out[1], out[2]]])
        p, q = n @ tensor @ n, n @ tensor @ t
        assert np.isclose(p, 0.05)
        if c > 1.0:
            assert np.allclose(out, d)
            continue
        slip = -c * q / p
        a = np.array([[c, 0.0], [-slip, 1.0]])  # in the frame (n, t)
        frame = np.stack([n, t])
        assert abs((a @ frame @ e1) @ (a @ frame @ e2)) < 1e-12
        assert np.linalg.eigvalsh(tensor).min() > 0.0


def test_the_slipped_solve_shears_the_cells_across_an_oblique_front_less():
    """The joined blocks adapted to a front at 37 degrees to their grid lines: solved again
    with the slip, the worst cell is more than 10 degrees nearer square."""
    graph = node_graph(four_blocks())

    def front(points: np.ndarray) -> np.ndarray:
        return np.tanh((0.8 * points[:, 0] + 0.6 * points[:, 1] - 0.7) / 0.05)

    space = ParameterSpace(graph, front)
    strength = np.full(len(graph.points), 2.0)
    free, slid = (space.solve(strength, joined=True, slip=slip) for slip in (False, True))
    assert _angles(graph, slid.points)[0].max() < _angles(graph, free.points)[0].max() - 10.0
    assert not _angles(graph, slid.points)[1].any()
