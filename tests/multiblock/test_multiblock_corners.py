"""A block's corners where its outline gives fewer than four (SPEC 10): its junctions count
too, largest turn first, so a three-line junction drawn straight through (a Y-branch's
centre) is a corner of the block on its flat side."""

from __future__ import annotations

import numpy as np
import pytest

from pinn_engine.errors import InputError
from pinn_engine.multiblock.blocks import topology
from pinn_engine.multiblock.graph import linework
from pinn_engine.multiblock.mesh import mesh_blocks
from pinn_engine.settings import make_settings

MOUTH = 0.8  # distance of a Y arm's mouth from the centre
ARM = 2.0  # length of a Y arm


def ybranch(angles, widths, flat: int) -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
    """A Y of arms in directions ``angles`` (degrees, counter-clockwise) and ``widths``,
    its hexagonal centre cut into three blocks by one straight line through the centre O
    (from arm ``flat - 1``'s left mouth corner to arm ``flat``'s) and a line from O to the
    next arm's left mouth corner: the block holding arm ``flat``'s mouth has O on its flat
    side; the rings, the edges and O."""
    ring, mouths, lefts = [], [], []
    for angle, width in zip(angles, widths):
        a = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle))])
        n = np.array([-a[1], a[0]])
        right, left = MOUTH * a - 0.5 * width * n, MOUTH * a + 0.5 * width * n
        ring += [right, right + ARM * a, left + ARM * a, left]
        mouths.append(np.array([right, left]))
        lefts.append(left)
    a, b, c = lefts[flat - 1], lefts[flat], lefts[(flat + 1) % 3]
    centre = 0.5 * (a + b)
    return [np.array(ring)], [*mouths, np.array([a, centre, b]), np.array([centre, c])], centre


def split_triangle() -> tuple[list[np.ndarray], list[np.ndarray], np.ndarray]:
    """A triangle cut into three blocks: a line up from the base's middle to O, and one
    straight line through O between the two slanted sides (the top block is three-cornered
    but for O); the rings, the edges and O."""
    ring = np.array([(0.0, 0.0), (2.0, 0.0), (1.0, 2.0)])
    edges = [np.array([(1.0, 0.0), (1.0, 1.0)]), np.array([(0.5, 1), (1, 1), (1.5, 1)])]
    return [ring], edges, np.array([1.0, 1.0])


CASES = {
    "ybranch 50 degrees": ybranch((-50, 50, 180), (0.8, 0.8, 1.0), 0),
    "ybranch 50 degrees, upper arm flat": ybranch((-50, 50, 180), (0.8, 0.8, 1.0), 1),
    "ybranch, lopsided, trunk flat": ybranch((-60, 40, 180), (0.9, 0.7, 1.0), 2),
    "ybranch, bent trunk, upper arm flat": ybranch((-90, 30, 150), (1.0, 0.8, 1.0), 1),
    "ybranch, equal arms": ybranch((-60, 60, 180), (1.0, 1.0, 1.0), 0),
    "triangle in three": split_triangle(),
}


@pytest.mark.parametrize("name", sorted(CASES))
def test_a_junction_drawn_straight_through_is_a_corner(name):
    """Every block of each drawing has four corners, one of them the straight junction,
    and the elliptic grid has no folded cell."""
    rings, edges, centre = CASES[name]
    names = [f"line {k}" for k in range(len(edges))]
    topo = topology(linework(rings, edges, names, "boundary"))
    assert len(topo.blocks) == (3 if "triangle" in name else 6)
    flat = [b for b in topo.blocks if any(np.allclose(c, centre) for c in b.corners)]
    assert len(flat) == 3  # O is a corner of all three centre blocks, the flat one too
    result = mesh_blocks(rings, edges, names, make_settings("elliptic", cell_size=0.1))
    assert result.report["quality"]["folded_cells"] == 0


def test_only_as_many_junctions_as_needed_become_corners():
    """A block with four turning corners keeps them: a junction on its flat side stays
    inside the side (the left block of a T: three pieces on its right side)."""
    ring = np.array([(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)])
    edges = [np.array([(1.0, 0.0), (1.0, 2.0)]), np.array([(1.0, 1.0), (2.0, 1.0)])]
    topo = topology(linework([ring], edges, ["a", "b"], "boundary"))
    left = min(topo.blocks, key=lambda b: b.inside[0])
    assert sorted(map(tuple, left.corners)) == [(0, 0), (0, 2), (1, 0), (1, 2)]
    assert [len(side) for side in left.sides] == [1, 2, 1, 1]


def test_a_triangle_without_junctions_is_still_refused():
    """A diagonal cut makes two triangles whose only junctions are already corners: the
    count stays 3, named in one line."""
    ring = np.array([(0.0, 0.0), (2.0, 0.0), (2.0, 2.0), (0.0, 2.0)])
    with pytest.raises(InputError, match="has 3 corners"):
        topology(linework([ring], [np.array([(0.0, 0.0), (2.0, 2.0)])], ["a"], "boundary"))
