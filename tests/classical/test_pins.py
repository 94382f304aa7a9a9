"""Sharp vertices inside a side as grid nodes (``classical.pins``): the assignment of
vertices to nodes, the reparametrized sides and the moved nodes of other distributions."""

from __future__ import annotations

import itertools

import numpy as np
import pytest

from pinn_engine.classical.pins import (
    assign,
    pin_sharp,
    pinned_boundary,
    pinned_lines,
    placed_on_boundary,
)
from pinn_engine.classical.spacing import param_grid
from pinn_engine.classical.tfi import tfi_at
from pinn_engine.geometry.auxlines import RawLine, map_lines
from pinn_engine.geometry.boundary import Boundary

# a 3 x 1.5 box whose bottom side climbs a trapezoidal bump: four vertices turning 45 degrees
BUMP = np.array(
    [[0, 0], [1.03, 0], [1.33, 0.3], [1.73, 0.3], [2.03, 0], [3, 0], [3, 1.5], [0, 1.5]],
    dtype=float,
)


def _least_move(nodes: np.ndarray, vertices: np.ndarray) -> float | None:
    """The least total move over every order-keeping assignment, by enumeration."""
    best = None
    for picks in itertools.combinations(range(1, len(nodes) - 1), len(vertices)):
        moved = nodes.copy()
        moved[list(picks)] = vertices
        if np.all(np.diff(moved) > 0):
            cost = float(np.abs(nodes[list(picks)] - vertices).sum())
            best = cost if best is None else min(best, cost)
    return best


def test_the_assignment_moves_least_and_keeps_the_order():
    rng = np.random.default_rng(3)
    for trial in range(400):
        n = int(rng.integers(3, 9))
        nodes = np.linspace(0, 1, n) if trial % 2 else np.r_[0, np.sort(rng.random(n - 2)), 1]
        vertices = np.sort(rng.random(int(rng.integers(1, 4))))
        if trial % 3 == 0:  # two vertices closer than any two nodes
            vertices = np.sort(np.r_[vertices, vertices[0] + 1e-3])
        picks, best = assign(nodes, vertices), _least_move(nodes, vertices)
        assert (picks is None) == (best is None)
        if picks is not None:
            assert np.abs(nodes[picks] - vertices).sum() == pytest.approx(best, abs=1e-12)


def test_the_reparametrized_side_puts_a_lattice_node_on_each_sharp_vertex():
    boundary = Boundary.from_points(BUMP)
    pinned = pinned_boundary(boundary, 21, 11)
    assert [side for side, _, _ in pinned.knots] == ["bottom"]
    nodes = pinned.side("bottom").at(np.linspace(0, 1, 21))
    for vertex in boundary.frame.to_unit(BUMP[1:5]):
        assert np.linalg.norm(nodes - vertex, axis=1).min() == 0.0
    # the other sides keep their arc-length parameter
    assert pinned.side("top").t.tolist() == boundary.side("top").t.tolist()


def test_nodes_of_another_distribution_move_onto_the_vertices_the_walls_keep_their_first_edge():
    boundary = pinned_boundary(Boundary.from_points(BUMP), 21, 11)
    params = param_grid(33, 17, {"left": np.full(17, 1e-3), "bottom": np.full(33, 1e-2)})
    moved = pin_sharp(boundary, params)
    nodes = boundary.side("bottom").at(moved[0, :, 0])
    for vertex in boundary.frame.to_unit(BUMP[1:5]):
        assert np.linalg.norm(nodes - vertex, axis=1).min() == 0.0
    assert np.all(np.diff(moved[..., 0], axis=1) > 0)
    # only the assigned nodes of the bottom row move; the left wall's first column stays
    assert np.count_nonzero(moved[0, :, 0] != params[0, :, 0]) == 4
    assert np.array_equal(moved[:, :2], params[:, :2])
    assert pin_sharp(boundary, moved) is moved  # nothing left to move


def test_a_grid_near_the_boundary_is_placed_on_it_with_every_sharp_vertex_a_node():
    boundary = pinned_boundary(Boundary.from_points(BUMP), 21, 11)
    exact = tfi_at(boundary)(param_grid(21, 11, {}))
    rng = np.random.default_rng(0)
    near = exact + rng.normal(scale=2e-3, size=exact.shape)  # a soft boundary's network
    placed = placed_on_boundary(near, boundary)
    edge = np.concatenate([placed[0], placed[-1], placed[:, 0], placed[:, -1]])
    assert boundary.deviation(edge).max() < 1e-12
    # the interior moved as TFI spreads the sides' moves (two sides' and a corner's at most)
    move = np.linalg.norm(placed - near, axis=-1)
    edge = np.concatenate([move[0], move[-1], move[:, 0], move[:, -1]])
    assert 0.0 < move[1:-1, 1:-1].max() <= 3.0 * edge.max()
    assert np.array_equal(
        placed[[0, 0, -1, -1], [0, -1, 0, -1]], boundary.corner_points()[[0, 1, 3, 2]]
    )
    for vertex in boundary.frame.to_unit(BUMP[1:5]):
        assert np.linalg.norm(placed[0] - vertex, axis=1).min() == 0.0
    assert np.all(np.diff(placed[0, :, 0]) > 0)


def _round_bump(n: int = 200) -> np.ndarray:
    """A 3 x 1.5 box whose bottom side is a smooth bump (no sharp vertex), counter-clockwise."""
    x = np.linspace(0.0, 3.0, n)
    bottom = np.column_stack([x, 0.4 * np.exp(-(((x - 1.5) / 0.4) ** 2))])
    return np.vstack([bottom, [[3.0, 1.5], [0.0, 1.5]]])


def test_a_drawn_lines_end_is_a_lattice_node_where_it_meets_a_curved_side():
    boundary = Boundary.from_points(_round_bump())
    x0 = 1.3  # on the bump's flank
    drawn = np.array([[x0, 0.4 * np.exp(-(((x0 - 1.5) / 0.4) ** 2))], [1.8, 1.5]])
    start = boundary.side("bottom").project(boundary.frame.to_unit(drawn[:1]))[0]
    line = map_lines([RawLine(drawn, None, "drawn")], boundary)
    pinned = pinned_boundary(boundary, 9, 5, line)  # its chord misses the end by 8e-3
    assert [side for side, _, _ in pinned.knots] == ["bottom"]  # the top is straight
    (on,) = pinned_lines(line, pinned)
    assert on.xi_eta[0, 0] * 8 == pytest.approx(round(on.xi_eta[0, 0] * 8), abs=1e-12)
    nodes = pinned.side("bottom").at(np.linspace(0, 1, 9))
    assert np.linalg.norm(nodes - on.xy[0], axis=1).min() < 1e-12  # the end is a node
    assert on.xy[0] == pytest.approx(boundary.side("bottom").at(np.array([start]))[0])
    # without the line the smooth side keeps its arc-length parameter
    assert pinned_boundary(boundary, 9, 5) is boundary


def test_line_ends_on_straight_stretches_leave_the_sides_as_they_were():
    boundary = Boundary.from_points(BUMP)
    # twelve lines beside the bump: each end on a straight stretch, which no cell edge misses
    x = np.r_[np.linspace(0.1, 0.95, 6), np.linspace(2.1, 2.9, 6)]
    lines = map_lines(
        [RawLine(np.array([[u, 0.0], [u, 1.5]]), None, f"l{k}") for k, u in enumerate(x)],
        boundary,
    )
    with_lines, alone = (pinned_boundary(boundary, 9, 5, ends) for ends in (lines, ()))
    assert [side for side, _, _ in with_lines.knots] == ["bottom"]
    for (_, *knots), (_, *expected) in zip(with_lines.knots, alone.knots, strict=True):
        assert all(np.array_equal(a, b) for a, b in zip(knots, expected, strict=True))
