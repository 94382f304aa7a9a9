"""Regenerate the multi-block examples (SPEC 10): a boundary file and a block-edge file each.

Run ``.venv/bin/python example_data/make_multiblock.py``; it rewrites, beside it,
``lshape.vtp``/``lshape_blocks.vtp`` (two blocks; the edge drawn askew, to be solved
straight; ``lshape_aux.vtp`` an auxiliary line inside the bottom block),
``step.vtp``/``step_blocks.vtp`` (a backward-facing step: four blocks, an edge ending on
another edge) and ``cylinder_channel.vtp``/``cylinder_channel_blocks.vtp`` (a
cylinder of diameter 1 in a channel: an O-ring of 4 blocks inside 8 outer blocks),
``tee.vtp``/``tee_blocks.vtp`` (a tee whose branch leans downstream: four blocks) and
``ybranch.vtp``/``ybranch_blocks.vtp`` (a bifurcation: three arms and a centre of three
blocks meeting at one point) and ``dfg.vtp``/``dfg_blocks.vtp`` (the DFG 2D-1 benchmark's
cylinder in a channel, Schaefer and Turek 1996: 12 blocks, docs/dfg.md).
"""

from __future__ import annotations

import numpy as np
from make_examples import polydata, write

CYLINDER_POINTS = 96  # points on the cylinder (a multiple of 8: a vertex at each diagonal)
BRANCH_TILT = 30.0  # degrees the tee's branch leans from the vertical (downstream)
Y_ARMS = (-50.0, 50.0, 180.0)  # directions of the Y's daughters and trunk, counter-clockwise
Y_WIDTHS = (0.8, 0.8, 1.0)  # the arms' widths (daughters narrower than the trunk)
Y_MOUTH = 0.8  # distance of each arm's mouth from the Y's centre
ARM_LENGTH = 3.0  # length of the Y's arms
# DFG 2D-1 (Schaefer and Turek 1996): the channel [0, 2.2] x [0, 0.41], a cylinder of
# diameter 0.1 centred at (0.2, 0.2); the O-ring's square reaches half way to the walls
DFG_LENGTH, DFG_HEIGHT = 2.2, 0.41
DFG_CENTRE, DFG_RADIUS = (0.2, 0.2), 0.05
DFG_BOX = 0.1  # half the side of the square around the cylinder


def lshape() -> tuple[list[np.ndarray], list[np.ndarray]]:
    """An L of arm width 1; one edge from the inner corner to the left wall, drawn askew."""
    ring = np.array([(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)], dtype=float)
    return [ring], [np.array([(1.0, 1.0), (0.0, 1.25)])]


def lshape_aux() -> list[np.ndarray]:
    """A grid line drawn inside the L's bottom block, from its bottom side to its top side,
    leaning and gently bent (for the pinn's auxiliary lines inside blocks)."""
    return [np.array([(1.3, 0.0), (1.42, 0.5), (1.6, 1.0)])]


def step() -> tuple[list[np.ndarray], list[np.ndarray]]:
    """A backward-facing step of height 1 in a channel of height 2: the step's edge runs to
    the outlet, one edge closes the inlet block (drawn leaning), one edge below the step's
    edge ends on it."""
    ring = np.array([(-2, 1), (0, 1), (0, 0), (6, 0), (6, 2), (-2, 2)], dtype=float)
    edges = [
        np.array([(0.0, 1.0), (3.0, 1.0), (6.0, 1.0)]),
        np.array([(0.0, 1.0), (0.25, 2.0)]),
        np.array([(2.5, 0.0), (3.0, 1.0)]),
    ]
    return [ring], edges


def cylinder_channel() -> tuple[list[np.ndarray], list[np.ndarray]]:
    """A cylinder of diameter 1 at the origin in the channel [-3, 6] x [-2, 2]; a square
    [-1, 1]^2 around it cut along its diagonals (the O-ring) and its sides carried on to
    the channel's walls (8 outer blocks)."""
    channel = np.array([(-3, -2), (6, -2), (6, 2), (-3, 2)], dtype=float)
    a = 2 * np.pi * np.arange(CYLINDER_POINTS) / CYLINDER_POINTS
    cylinder = 0.5 * np.column_stack([np.cos(a), np.sin(a)])
    square = [(1.0, -1.0), (1.0, 1.0), (-1.0, 1.0), (-1.0, -1.0)]
    edges = [np.array([square[k - 1], square[k]]) for k in range(4)]
    for x, y in square:
        edges.append(np.array([(0.5 * x / np.sqrt(2), 0.5 * y / np.sqrt(2)), (x, y)]))
    for x, y in ((-1, -2), (1, -2)):  # the square's sides carried on to the walls
        edges += [np.array([(x, y), (x, -1.0)]), np.array([(x, 1.0), (x, -y)])]
    for x, y in ((-3, -1), (-3, 1)):
        edges += [np.array([(x, y), (-1.0, y)]), np.array([(1.0, y), (6.0, y)])]
    return [channel, cylinder], edges


def tee() -> tuple[list[np.ndarray], list[np.ndarray]]:
    """A channel [0, 6] x [0, 1] with a branch of width 1 and length 2 leaving its top wall
    at x in [2.5, 3.5], leaning BRANCH_TILT degrees downstream; the crossing is one block."""
    tilt = np.radians(BRANCH_TILT)
    up = 2.0 * np.array([np.sin(tilt), np.cos(tilt)])
    left, right = np.array([2.5, 1.0]), np.array([3.5, 1.0])
    ring = np.array([(0, 0), (6, 0), (6, 1), right, right + up, left + up, left, (0, 1)])
    edges = [np.array([left, (2.5, 0.0)]), np.array([right, (3.5, 0.0)]), np.array([left, right])]
    return [ring], edges


def ybranch() -> tuple[list[np.ndarray], list[np.ndarray]]:
    """A bifurcation: arms in the directions Y_ARMS leave a hexagonal centre, which edges
    from its middle to one mouth corner of each arm cut into three blocks."""
    ring, edges = [], []
    for angle, width in zip(Y_ARMS, Y_WIDTHS):
        a = np.array([np.cos(np.radians(angle)), np.sin(np.radians(angle))])
        n = np.array([-a[1], a[0]])
        right = Y_MOUTH * a - 0.5 * width * n
        left = Y_MOUTH * a + 0.5 * width * n
        ring += [right, right + ARM_LENGTH * a, left + ARM_LENGTH * a, left]
        edges += [np.array([right, left]), np.array([(0.0, 0.0), left])]
    return [np.array(ring)], edges


def dfg(
    centre: tuple[float, float] = DFG_CENTRE, radius: float = DFG_RADIUS
) -> tuple[list[np.ndarray], list[np.ndarray]]:
    """The DFG 2D-1 channel and cylinder (or one of ``radius`` at ``centre``: the family of
    make_families.py); a square of half side DFG_BOX around the cylinder cut along its
    diagonals (the O-ring) and its sides carried on to the walls, the inlet and the outlet
    (8 outer blocks)."""
    channel = np.array([(0, 0), (DFG_LENGTH, 0), (DFG_LENGTH, DFG_HEIGHT), (0, DFG_HEIGHT)])
    a = 2 * np.pi * np.arange(CYLINDER_POINTS) / CYLINDER_POINTS
    cx, cy = centre
    cylinder = np.column_stack([cx + radius * np.cos(a), cy + radius * np.sin(a)])
    x0, x1, y0, y1 = cx - DFG_BOX, cx + DFG_BOX, cy - DFG_BOX, cy + DFG_BOX
    square = [(x1, y0), (x1, y1), (x0, y1), (x0, y0)]
    edges = [np.array([square[k - 1], square[k]]) for k in range(4)]
    for x, y in square:
        d = np.array([x - cx, y - cy]) / np.hypot(x - cx, y - cy)
        edges.append(np.array([(cx + radius * d[0], cy + radius * d[1]), (x, y)]))
    for x in (x0, x1):
        edges += [np.array([(x, 0.0), (x, y0)]), np.array([(x, y1), (x, DFG_HEIGHT)])]
    for y in (y0, y1):
        edges += [np.array([(0.0, y), (x0, y)]), np.array([(x1, y), (DFG_LENGTH, y)])]
    return [channel.astype(float), cylinder], edges


def main() -> None:
    for name, make in (
        ("lshape", lshape),
        ("step", step),
        ("cylinder_channel", cylinder_channel),
        ("tee", tee),
        ("ybranch", ybranch),
        ("dfg", dfg),
    ):
        rings, edges = make()
        write(polydata(rings, closed=True), f"{name}.vtp")
        write(polydata(edges, closed=False), f"{name}_blocks.vtp")
    write(polydata(lshape_aux(), closed=False), "lshape_aux.vtp")


if __name__ == "__main__":
    main()
