"""Junctions inside a multi-block domain (SPEC 10): points where three or more pieces meet
off the boundary (the O-ring's corners around a cylinder, a T-junction), solved as interior
nodes of the multi-block Winslow system.

Around a junction the blocks' corner cells form a closed fan of *quadrants*: a block that
has the junction as a corner gives one quadrant (its two side neighbours and its diagonal
node), a block that has it inside a side gives two. With four quadrants (a T-junction, four
blocks at a cross) the fan is an ordinary 3 x 3 neighbourhood and the junction takes the
usual Winslow stencil, exactly as inside a block. With Q != 4 quadrants no 3 x 3
neighbourhood exists; following Knupp's treatment of irregular nodes (Winslow smoothing on
unstructured meshes, 1999) the fan is mapped to a regular Q-gon in a local logical space:
side neighbours at unit distance in directions 2 pi i / Q, each diagonal node at the sum of
its two side neighbours' positions, as in a grid of rhombi. The first and second
derivatives of x(xi, eta) at the junction are the least-squares fit of a quadratic through
the 2Q neighbours (five coefficients; Q >= 3 gives at least six points, rank 5), and the
junction's row is Winslow's equation alpha x_xixi - 2 beta x_xieta + gamma x_etaeta = 0 in
them. The fit is invariant to rotating the logical Q-gon (full quadratics, unweighted), so
no block is preferred: every block round the junction enters alike, which is the point of
letting junctions move. The row is linear in the node positions for frozen alpha, beta,
gamma, so it joins the Picard steps of the other nodes unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cache

import numpy as np

from pinn_engine.multiblock.layout import Layout

REGULAR = 4  # quadrants round an ordinary grid node: its fan is a 3 x 3 neighbourhood


@dataclass
class Star:
    """A junction ``node`` with Q != 4 quadrants: its side neighbours ``edges`` (Q,) and
    diagonal neighbours ``diagonals`` (Q,) counter-clockwise, diagonal k between side
    neighbours k and k + 1."""

    node: int
    edges: np.ndarray
    diagonals: np.ndarray


def _quadrants(lay: Layout, node: int) -> list[tuple[int, int, int]]:
    """The (side, diagonal, side) neighbour triples of ``node``'s cells in every block, each
    counter-clockwise (the blocks' index directions are)."""
    out = []
    for ids in lay.ids:
        nj, ni = ids.shape
        for j, i in zip(*np.nonzero(ids == node)):
            for sj in (1, -1):
                for si in (1, -1):
                    if not (0 <= j + sj < nj and 0 <= i + si < ni):
                        continue
                    a, b = int(ids[j, i + si]), int(ids[j + sj, i])
                    d = int(ids[j + sj, i + si])
                    out.append((a, d, b) if si * sj > 0 else (b, d, a))
    return out


def _fan(quadrants: list[tuple[int, int, int]]) -> list[tuple[int, int, int]] | None:
    """The quadrants chained counter-clockwise (each one's last side neighbour the next
    one's first), or None when they do not close round the node (a node on the boundary)."""
    after = {q[0]: q for q in quadrants}
    if len(after) != len(quadrants):
        return None
    fan = [quadrants[0]]
    while len(fan) < len(quadrants):
        nxt = after.get(fan[-1][2])
        if nxt is None or nxt in fan:
            return None
        fan.append(nxt)
    return fan if fan[-1][2] == fan[0][0] else None


def junction_stencils(lay: Layout, nodes: list[int]) -> tuple[np.ndarray, list[Star]]:
    """For the interior ones of the junction ``nodes``: 3 x 3 neighbourhoods (n, 3, 3) of
    those with four quadrants (``[:, 1, 1]`` the junction), stars of the others."""
    grids, stars = [], []
    for node in nodes:
        fan = _fan(_quadrants(lay, node))
        if fan is None:
            continue
        edges = np.array([q[0] for q in fan])
        diagonals = np.array([q[1] for q in fan])
        if len(fan) == REGULAR:
            (e, n, w, s), (ne, nw, sw, se) = edges, diagonals
            grids.append(np.array([[sw, s, se], [w, node, e], [nw, n, ne]]))
        else:
            stars.append(Star(node, edges, diagonals))
    return np.array(grids, dtype=int).reshape(-1, 3, 3), stars


@cache
def _fit(quadrants: int) -> np.ndarray:
    """(5, 2Q) least-squares weights giving x_xi, x_eta, x_xixi, x_xieta, x_etaeta from the
    offsets of a Q-quadrant star's side then diagonal neighbours from its centre."""
    angles = 2 * np.pi * np.arange(quadrants) / quadrants
    sides = np.column_stack([np.cos(angles), np.sin(angles)])
    logical = np.vstack([sides, sides + np.roll(sides, -1, axis=0)])
    xi, eta = logical[:, 0], logical[:, 1]
    design = np.column_stack([xi, eta, 0.5 * xi**2, xi * eta, 0.5 * eta**2])
    return np.linalg.pinv(design)


def star_row(points: np.ndarray, star: Star) -> tuple[np.ndarray, np.ndarray]:
    """The frozen-coefficient Winslow row of a star at ``points``: node ids (centre first)
    and their weights (summing to zero)."""
    around = np.concatenate([star.edges, star.diagonals])
    fit = _fit(len(star.edges))
    x_xi, x_eta = fit[:2] @ (points[around] - points[star.node])
    alpha, beta, gamma = x_eta @ x_eta, x_xi @ x_eta, x_xi @ x_xi
    w = alpha * fit[2] - 2 * beta * fit[3] + gamma * fit[4]
    return np.concatenate([[star.node], around]), np.concatenate([[-w.sum()], w])
