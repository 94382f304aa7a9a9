"""The guard's bound turned into a cap on the compression across a front (the shear cap),
and the draw-back that gives up a cell's move in proportion to its excess over the bound."""

from __future__ import annotations

import numpy as np

from pinn_engine.adapt.error import interpolation_error
from pinn_engine.adapt.guard import GUARD_DEGREES, _angles, _drawn_back, offending
from pinn_engine.adapt.monitor import SHEAR_FLOOR, shear_cap
from pinn_engine.adapt.nodes import node_graph
from pinn_engine.adapt.parametric import ParameterSpace
from pinn_engine.quality import cell_quality

LIMIT = 100.0  # a square grid's worst cell (90 degrees) plus the guard's 10


def square_front():
    x, y = np.meshgrid(np.linspace(0.0, 1.0, 21), np.linspace(0.0, 1.0, 21))
    graph = node_graph([np.stack([x, y], axis=-1)])

    def front(points: np.ndarray) -> np.ndarray:
        return np.tanh((0.8 * points[:, 0] + 0.6 * points[:, 1] - 0.7) / 0.03)

    return graph, front


def test_the_shear_cap_is_the_compression_that_reaches_the_bound():
    """A square compressed by half along its diagonal is a rhombus of 126.87 degrees; along
    a grid line it stays a rectangle whatever the compression; a cell already at the bound
    takes none."""
    e1, e2 = np.array([[1.0, 0.0]]), np.array([[0.0, 1.0]])
    diagonal = np.array([[1.0, 1.0]]) / np.sqrt(2.0)
    assert np.isclose(shear_cap(e1, e2, diagonal, 126.87), 2.0, rtol=1e-3)
    assert np.isclose(shear_cap(e1, e2, np.array([[1.0, 0.0]]), LIMIT), 1.0 / SHEAR_FLOOR)
    assert np.isclose(shear_cap(e1, e2, diagonal, 90.0), 1.0)


def test_the_capped_solve_keeps_an_oblique_front_within_the_bound():
    graph, front = square_front()
    space = ParameterSpace(graph, front, LIMIT)
    strength = np.full(len(graph.points), 20.0)
    free, capped = space.solve(strength), space.solve(strength, capped=True)
    assert offending(graph, free.points, LIMIT).sum() > 100
    assert not offending(graph, capped.points, LIMIT).any()
    before = interpolation_error(graph.points, graph.cells, front)
    assert interpolation_error(capped.points, graph.cells, front) < 0.85 * before


def test_a_cell_just_over_the_bound_gives_up_little_of_its_move():
    """The draw-back cuts a move in proportion to the cell's excess: with the bound a degree
    under the worst cell, every node keeps at least 90 % of its move, and none is over."""
    graph, front = square_front()
    solved = ParameterSpace(graph, front).solve(np.full(len(graph.points), 5.0))
    limit = _angles(graph, solved.points)[0].max() - 1.0
    out = _drawn_back(
        graph, solved, np.ones(len(graph.points)), limit, [], 1.0, lambda p: 0.0, np.inf
    )
    assert not offending(graph, out.solved.points, limit).any()
    assert 0.9 <= out.kept.min() < 1.0


def test_the_unadapted_grids_own_folded_cells_are_not_the_guards():
    """A cell the unadapted grid folds (its angle over any bound) offends neither the guard
    nor the draw-back: the grid may still be adapted round it."""
    x, y = np.meshgrid(np.linspace(0.0, 1.0, 11), np.linspace(0.0, 1.0, 11))
    grid = np.stack([x, y], axis=-1)
    grid[5, 5] += 0.15  # past its diagonal neighbour: its cells fold
    graph = node_graph([grid])
    q = cell_quality(grid)
    assert q["Folded"].any()
    limit = q["MaxIncludedAngle"][~q["Folded"]].max() + GUARD_DEGREES
    assert not offending(graph, graph.points, limit).any()
