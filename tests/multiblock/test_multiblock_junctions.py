"""Multi-block junctions and sliding ends (SPEC 10's free interfaces): junctions inside the
domain are solved as interior nodes, edge ends slide along straight boundary only."""

from __future__ import annotations

import numpy as np
import pytest

from pinn_engine.classical.elliptic import winslow_residual
from pinn_engine.multiblock.blocks import topology
from pinn_engine.multiblock.counts import cell_counts
from pinn_engine.multiblock.elliptic import stencils, winslow
from pinn_engine.multiblock.graph import linework
from pinn_engine.multiblock.junctions import Star, star_row
from pinn_engine.multiblock.layout import layout

ARC_POINTS = 41  # vertices of the arched top wall
CONVERGED = 1e-5  # a converged grid's Winslow residual against its TFI start's


def _solve(rings, edges, h):
    lines = linework(rings, edges, [f"edge {k}" for k in range(len(edges))], "test")
    topo = topology(lines)
    lay = layout(topo, cell_counts(topo, h))
    return topo, lay, winslow(topo, lay)[0]


@pytest.mark.parametrize("quadrants", [3, 5, 6])
def test_star_row_holds_on_an_affine_grid(quadrants):
    """Winslow's equation holds on any affine map of the logical Q-gon: the star's row is
    zero there, and its weights sum to zero (a translation leaves it zero)."""
    angles = 2 * np.pi * np.arange(quadrants) / quadrants
    sides = np.column_stack([np.cos(angles), np.sin(angles)])
    logical = np.vstack([[0.0, 0.0], sides, sides + np.roll(sides, -1, axis=0)])
    affine = np.array([[1.3, 0.4], [-0.2, 0.7]])
    points = logical @ affine.T + [5.0, -2.0]
    star = Star(0, np.arange(1, quadrants + 1), np.arange(quadrants + 1, 2 * quadrants + 1))
    ids, w = star_row(points, star)
    assert abs(w.sum()) < 1e-12 and abs(w[0]) > 0.1
    np.testing.assert_allclose(w @ points[ids], 0.0, atol=1e-12)


def test_junctions_move_and_satisfy_their_rows():
    """Around a cylinder the square's corners (five blocks meet) leave their drawn places and
    the converged grid satisfies their Winslow rows and, inside every block, the one-block
    Winslow equations."""
    cylinder = 0.5 * np.column_stack(
        [
            np.cos(np.linspace(0, 2 * np.pi, 48, endpoint=False)),
            np.sin(np.linspace(0, 2 * np.pi, 48, endpoint=False)),
        ]
    )
    channel = np.array([(-3, -2), (6, -2), (6, 2), (-3, 2)], dtype=float)
    square = [(1.0, -1.0), (1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0)]
    edges = [np.array([square[k - 1], square[k]]) for k in range(4)]
    edges += [np.array([(0.5 * x / np.sqrt(2), 0.5 * y / np.sqrt(2)), (x, y)]) for x, y in square]
    for x, y in ((-1, -2), (1, -2)):
        edges += [np.array([(x, y), (x, -1.0)]), np.array([(x, 1.0), (x, -y)])]
    for x, y in ((-3, -1), (-3, 1)):
        edges += [np.array([(x, y), (-1.0, y)]), np.array([(1.0, y), (6.0, y)])]
    topo, lay, points = _solve([channel, cylinder], edges, 0.2)
    start = max(np.abs(winslow_residual(lay.points[ids])).max() for ids in lay.ids)
    for ids in lay.ids:  # every block's interior is its own converged Winslow grid
        assert np.abs(winslow_residual(points[ids])).max() < CONVERGED * start
    _, stars = stencils(topo, lay, True)
    assert sorted(len(s.edges) for s in stars) == [5, 5, 5, 5]
    for star in stars:
        assert np.linalg.norm(points[star.node] - lay.points[star.node]) > 1e-3
        ids, w = star_row(points, star)
        assert np.linalg.norm(w @ points[ids]) < 1e-6 * np.abs(w).max()


def test_edge_end_slides_on_a_straight_wall_and_stays_on_a_curved_one():
    """An edge drawn askew from a straight floor to an arched roof (SPEC 10: ends slide
    only where the boundary is straight): the floor's end slides along it to where the
    edge's first grid line meets the floor at right angles; the roof's end stays where it
    was drawn, bit for bit."""
    x = np.linspace(2.0, 0.0, ARC_POINTS)
    arc = np.column_stack([x, 1.0 + 0.3 * np.sin(0.5 * np.pi * x)])  # (2, 1) over to (0, 1)
    ring = np.vstack([[(0.0, 0.0), (2.0, 0.0)], arc])
    drawn_top = arc[ARC_POINTS * 2 // 3]
    topo, lay, points = _solve([ring], [np.array([(1.2, 0.0), drawn_top])], 0.1)
    (edge,) = [ids for p, ids in zip(topo.pieces, lay.piece_ids) if p.interface]
    top, bottom = (edge[-1], edge[0]) if lay.points[edge[0], 1] == 0.0 else (edge[0], edge[-1])
    assert np.array_equal(points[top], lay.points[top])
    assert np.allclose(lay.points[top], drawn_top, rtol=0, atol=1e-12)
    inward = points[edge[1] if edge[0] == bottom else edge[-2]] - points[bottom]
    assert points[bottom, 1] == 0.0 and abs(points[bottom, 0] - 1.2) > 0.02
    assert abs(inward[0]) < np.sin(np.radians(1.0)) * np.linalg.norm(inward)
