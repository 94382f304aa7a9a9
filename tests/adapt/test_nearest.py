"""The grid nearest an adapted one within the guard's bound: the corner angles' gradient, and
a grid that keeps more of a front's compression than drawing it back does."""

from __future__ import annotations

import numpy as np
import pytest

from pinn_engine.adapt.error import interpolation_error
from pinn_engine.adapt.guard import _drawn_back, offending
from pinn_engine.adapt.nearest import Slide, angle_gradient, corner_angles, nearest_within
from pinn_engine.adapt.nodes import lattice_quads, node_graph
from pinn_engine.adapt.parametric import ParameterSpace
from pinn_engine.adapt.pieces import Piece
from pinn_engine.quality import cell_quality

LIMIT = 100.0  # a square grid's worst cell (90 degrees) plus the guard's 10


@pytest.mark.parametrize("turn", [1.0, -1.0])
def test_the_angles_are_cell_qualitys_and_their_gradient_their_derivative(turn):
    rng = np.random.default_rng(0)
    x, y = np.meshgrid(np.linspace(0.0, turn, 6), np.linspace(0.0, 1.0, 5))
    grid = np.stack([x, y], axis=-1) + 0.03 * rng.standard_normal((5, 6, 2))
    points, quads = grid.reshape(-1, 2), lattice_quads([np.arange(30).reshape(5, 6)])
    turns = np.full(len(quads), turn)
    theta, parts = corner_angles(points, quads, turns)
    assert np.allclose(
        np.rad2deg(theta.max(axis=1)), cell_quality(grid)["MaxIncludedAngle"].ravel()
    )
    weights = rng.standard_normal(theta.shape)
    gradient = angle_gradient(weights, quads, turns, parts, len(points))
    step, numeric = 1e-6, np.zeros_like(points)
    for k in np.ndindex(points.shape):
        up, down = points.copy(), points.copy()
        up[k] += step
        down[k] -= step
        numeric[k] = (
            (corner_angles(up, quads, turns)[0] - corner_angles(down, quads, turns)[0]) * weights
        ).sum() / (2 * step)
    assert np.abs(numeric - gradient).max() < 1e-6


def test_the_nearest_grid_keeps_the_bound_and_more_of_the_front_than_drawing_back():
    """An oblique front's adapted square grid over the bound: drawn back toward the
    unadapted grid it keeps a fifth of its error's cut, moved to the nearest grid within the
    bound more."""
    x, y = np.meshgrid(np.linspace(0.0, 1.0, 21), np.linspace(0.0, 1.0, 21))
    graph = node_graph([np.stack([x, y], axis=-1)])

    def front(points: np.ndarray) -> np.ndarray:
        return np.tanh((0.8 * points[:, 0] + 0.6 * points[:, 1] - 0.7) / 0.03)

    def error(points: np.ndarray) -> float:
        return interpolation_error(points, graph.cells, front)

    solved = ParameterSpace(graph, front, LIMIT).solve(np.full(len(graph.points), 2.0))
    assert offending(graph, solved.points, LIMIT).any()
    ones = np.ones(len(graph.points))
    drawn = _drawn_back(graph, solved, ones, LIMIT, [], 1.0, error, np.inf)
    quads, turn, folded = graph.lattice_cells
    free = ~graph.held
    for piece in graph.pieces:
        free[piece] = False
    near, _ = nearest_within(solved.points, quads, turn, free, LIMIT, ~folded)
    assert not offending(graph, near, LIMIT).any()
    assert np.allclose(near[~free], solved.points[~free])
    assert error(near) < 0.95 * drawn.error


def test_a_boundary_node_slides_along_its_piece_to_the_bound():
    """A bottom-side node pushed along its side shears its two cells past the bound; with
    every interior node held and the side's ends kept, it slides back along the side (y
    stays 0) until they keep it."""
    x, y = np.meshgrid(np.linspace(0.0, 1.0, 5), np.linspace(0.0, 1.0, 5))
    grid = np.stack([x, y], axis=-1)
    graph = node_graph([grid])
    bottom = graph.pieces[[k for k, p in enumerate(graph.pieces) if 2 in p][0]]
    piece = Piece(bottom, graph.points)
    arcs = piece.s.copy()
    node = int(np.flatnonzero(bottom == 2)[0])
    arcs[node] += 0.15  # of a side 1 long, cells 0.25 wide
    points = graph.points.copy()
    points[bottom] = piece.curve(arcs)
    quads, turn, folded = graph.lattice_cells
    assert offending(graph, points, LIMIT).any()
    free = np.zeros(len(points), dtype=bool)
    moved, (slid,) = nearest_within(
        points, quads, turn, free, LIMIT, ~folded, [Slide(bottom[1:-1], arcs[1:-1], piece.curve)]
    )
    assert not offending(graph, moved, LIMIT).any()
    assert np.allclose(moved[bottom, 1], 0.0) and 0.0 < slid[node - 1] - piece.s[node] < 0.15
