"""The domains of ``benchmarks/autoblock.py`` (SPEC 13): each a boundary (outer ring and
holes) and a careful hand blocking of it, split into a tuning half and a report half.

The tuning half holds example_data's five multi-block examples (their drawn edges are the
hand blockings) and six more; the report half holds one variation of each kind the method
must handle (an L with a bump, a sharp step, a tee leaning the other way, a body near a
wall, an asymmetric Y) and kinds not tuned on (a cross, a U-bend, a rib, a tilted ellipse,
a jog, a four-sided diffuser). Channels are about 1 wide; lengths in the same units.
"""

from __future__ import annotations

import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "example_data"))
from make_multiblock import cylinder_channel, lshape, step, tee, ybranch  # noqa: E402

Domain = tuple[list[np.ndarray], list[np.ndarray]]  # rings, hand-drawn block edges
BODY_POINTS = 96  # points on a round body (a multiple of 8: a vertex at each diagonal)
BUMP_POINTS = 21  # points on the L's bump


def _a(*points) -> np.ndarray:
    return np.array(points, dtype=float)


def _arc(cx, cy, rx, ry, tilt=0.0, n=BODY_POINTS) -> np.ndarray:
    """An ellipse of half-axes rx, ry about (cx, cy), turned by ``tilt`` degrees."""
    t = 2 * np.pi * np.arange(n) / n
    c, s = np.cos(np.radians(tilt)), np.sin(np.radians(tilt))
    x, y = rx * np.cos(t), ry * np.sin(t)
    return np.column_stack([cx + c * x - s * y, cy + s * x + c * y])


def _box_blocks(hole: np.ndarray, box: tuple, walls: tuple) -> list[np.ndarray]:
    """A hand O-ring: the ``box`` (x0, y0, x1, y1) round ``hole``, cut along its diagonals
    from the hole's points nearest them, and its sides carried on to the channel's
    ``walls`` (x0, y0, x1, y1): 4 ring blocks in 8 outer blocks."""
    x0, y0, x1, y1 = box
    X0, Y0, X1, Y1 = walls
    corners = _a((x1, y0), (x1, y1), (x0, y1), (x0, y0))
    edges = [np.array([corners[k - 1], corners[k]]) for k in range(4)]
    centre = hole.mean(axis=0)
    for c in corners:
        d = (c - centre) / np.linalg.norm(c - centre)
        along = (hole - centre) @ d - np.abs((hole - centre) @ np.array([-d[1], d[0]]))
        edges.append(np.array([hole[int(np.argmax(along))], c]))
    for x in (x0, x1):
        edges += [_a((x, Y0), (x, y0)), _a((x, y1), (x, Y1))]
    for y in (y0, y1):
        edges += [_a((X0, y), (x0, y)), _a((x1, y), (X1, y))]
    return [e for e in edges if np.linalg.norm(e[1] - e[0]) > 0]  # none where walls are sides


def forward_step() -> Domain:
    """A forward-facing step: the channel's floor rises by 1 of its 2 at x = 0."""
    ring = _a((-2, 0), (0, 0), (0, 1), (6, 1), (6, 2), (-2, 2))
    return [ring], [_a((0, 1), (-2, 1)), _a((0, 1), (0, 2))]


def elbow() -> Domain:
    """A sharp 90-degree bend of a channel of width 1."""
    ring = _a((0, 0), (4, 0), (4, 4), (3, 4), (3, 1), (0, 1))
    return [ring], [_a((3, 1), (3, 0)), _a((3, 1), (4, 1))]


def straight_tee() -> Domain:
    """A channel [0, 6] x [0, 1] with an upright branch of width 1 at x in [2.5, 3.5]."""
    ring = _a((0, 0), (6, 0), (6, 1), (3.5, 1), (3.5, 3), (2.5, 3), (2.5, 1), (0, 1))
    return [ring], [_a((2.5, 1), (2.5, 0)), _a((3.5, 1), (3.5, 0)), _a((2.5, 1), (3.5, 1))]


def tandem_cylinders() -> Domain:
    """Two cylinders of diameter 1, 4 apart, in the channel [-3, 9] x [-2, 2]."""
    channel = _a((-3, -2), (9, -2), (9, 2), (-3, 2))
    first, second = _arc(0, 0, 0.5, 0.5), _arc(4, 0, 0.5, 0.5)
    edges = _box_blocks(first, (-1, -1, 1, 1), (-3, -2, 3, 2))
    edges += _box_blocks(second, (3, -1, 5, 1), (3, -2, 9, 2))
    return [channel, first, second], edges


def square_body() -> Domain:
    """A square body of side 1 (corners on the diagonals) in the channel [-3, 6] x [-2, 2]."""
    channel = _a((-3, -2), (6, -2), (6, 2), (-3, 2))
    body = _a((-0.5, -0.5), (0.5, -0.5), (0.5, 0.5), (-0.5, 0.5))
    return [channel, body], _box_blocks(body, (-1, -1, 1, 1), (-3, -2, 6, 2))


def curved_bend() -> Domain:
    """A quarter annulus (radii 1 and 2): four-sided, one block."""
    t = np.linspace(0, np.pi / 2, 33)
    outer = np.column_stack([2 * np.cos(t), 2 * np.sin(t)])
    inner = np.column_stack([np.cos(t), np.sin(t)])[::-1]
    return [np.vstack([outer, inner])], []


def bumped_l() -> Domain:
    """The L-shape of arm width 1 with a smooth bump 0.15 high on its bottom wall."""
    x = np.linspace(0.3, 1.7, BUMP_POINTS)
    bump = np.column_stack([x, 0.15 * np.sin(np.pi * (x - 0.3) / 1.4) ** 2])
    ring = np.vstack([_a((0, 0)), bump[1:-1], _a((2, 0), (2, 1), (1, 1), (1, 2), (0, 2))])
    return [ring], [_a((1, 1), (0, 1))]


def sharp_step() -> Domain:
    """A backward-facing step of height 2 in a channel 3 high (expansion ratio 3)."""
    ring = _a((-2, 2), (0, 2), (0, 0), (8, 0), (8, 3), (-2, 3))
    return [ring], [_a((0, 2), (8, 2)), _a((0, 2), (0, 3))]


def tee_upstream() -> Domain:
    """A channel [0, 6] x [0, 1] with a branch of width 1 leaning 45 degrees upstream."""
    up = 2.0 * _a(-np.sin(np.pi / 4), np.cos(np.pi / 4))
    left, right = _a(2.5, 1.0), _a(3.5, 1.0)
    ring = np.array([(0, 0), (6, 0), (6, 1), right, right + up, left + up, left, (0, 1)])
    return [ring], [_a(left, (2.5, 0)), _a(right, (3.5, 0)), np.array([left, right])]


def cylinder_near_wall() -> Domain:
    """A cylinder of diameter 1 whose bottom is 0.3 above the channel's floor."""
    channel = _a((-3, -2), (6, -2), (6, 2), (-3, 2))
    body = _arc(0, -1.2, 0.5, 0.5)
    return [channel, body], _box_blocks(body, (-1, -1.85, 1, -0.2), (-3, -2, 6, 2))


def y_branch(arms, widths, mouth=0.8, length=3.0) -> Domain:
    """A bifurcation as example_data's: arms in the directions ``arms`` (degrees) of
    ``widths`` leave a centre cut into three blocks from its middle."""
    ring, edges = [], []
    for angle, width in zip(arms, widths):
        a = _a(np.cos(np.radians(angle)), np.sin(np.radians(angle)))
        n = _a(-a[1], a[0])
        right, left = mouth * a - 0.5 * width * n, mouth * a + 0.5 * width * n
        ring += [right, right + length * a, left + length * a, left]
        edges += [np.array([right, left]), np.array([(0.0, 0.0), left])]
    return [np.array(ring)], edges


def cross() -> Domain:
    """A cross of four arms of width 1 and length 2 round the square [-0.5, 0.5]^2."""
    ring, edges = [], []
    for k in range(4):
        c, s = np.cos(k * np.pi / 2), np.sin(k * np.pi / 2)
        turn = np.array([[c, -s], [s, c]])
        ring += [turn @ p for p in _a((0.5, -0.5), (2.5, -0.5), (2.5, 0.5))]
        edges.append(np.array([turn @ _a(0.5, -0.5), turn @ _a(0.5, 0.5)]))
    return [np.array(ring)], edges


def u_bend() -> Domain:
    """A channel of width 1 turning back on itself through two sharp bends."""
    ring = _a((0, 0), (4, 0), (4, 3), (0, 3), (0, 2), (3, 2), (3, 1), (0, 1))
    edges = [_a((3, 1), (3, 0)), _a((3, 1), (4, 1)), _a((3, 2), (4, 2)), _a((3, 2), (3, 3))]
    return [ring], edges


def rib() -> Domain:
    """A rib 1 wide and 0.8 high on the floor of the channel [0, 8] x [0, 2]."""
    ring = _a((0, 0), (3, 0), (3, 0.8), (4, 0.8), (4, 0), (8, 0), (8, 2), (0, 2))
    return [ring], [_a((3, 0.8), (3, 2)), _a((4, 0.8), (4, 2))]


def tilted_ellipse() -> Domain:
    """An ellipse of half-axes 0.8 and 0.3 turned 20 degrees in the channel [-3, 6] x [-2, 2]."""
    channel = _a((-3, -2), (6, -2), (6, 2), (-3, 2))
    body = _arc(0, 0, 0.8, 0.3, tilt=20.0)
    return [channel, body], _box_blocks(body, (-1.3, -1, 1.3, 1), (-3, -2, 6, 2))


def jog() -> Domain:
    """A channel of width 1 that steps down by 1 between x = 3 and x = 4."""
    ring = _a((0, 1), (3, 1), (3, 0), (8, 0), (8, 1), (4, 1), (4, 2), (0, 2))
    return [ring], [_a((3, 1), (3, 2)), _a((4, 1), (4, 0))]


def diffuser() -> Domain:
    """A four-sided diffuser whose upper wall opens smoothly from 1 to 2: one block."""
    x = np.linspace(0, 6, 31)
    top = 1 + 0.5 * (1 - np.cos(np.pi * x / 6))
    ring = np.vstack([np.column_stack([x, 0 * x]), np.column_stack([x, top])[::-1]])
    return [ring], []


TUNING: dict[str, Callable[[], Domain]] = {
    "L-shape": lshape,
    "backward step": step,
    "tee, branch leaning 30 downstream": tee,
    "cylinder in channel": cylinder_channel,
    "Y-branch": ybranch,
    "forward step": forward_step,
    "elbow": elbow,
    "tee, upright branch": straight_tee,
    "two cylinders in tandem": tandem_cylinders,
    "square body in channel": square_body,
    "curved bend (four-sided)": curved_bend,
}
REPORT: dict[str, Callable[[], Domain]] = {
    "L with a bump": bumped_l,
    "sharp backward step": sharp_step,
    "tee, branch leaning 45 upstream": tee_upstream,
    "cylinder near a wall": cylinder_near_wall,
    "Y-branch, asymmetric": lambda: y_branch((-30.0, 70.0, 180.0), (0.8, 0.6, 1.0)),
    "cross": cross,
    "U-bend": u_bend,
    "rib on the floor": rib,
    "tilted ellipse in channel": tilted_ellipse,
    "jog": jog,
    "diffuser (four-sided)": diffuser,
}
