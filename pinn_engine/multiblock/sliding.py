"""Edge ends that slide along the boundary (SPEC 10's free interfaces): an edge ending on
the boundary or a hole between two boundary pieces that lie on one straight line moves
along them as the multi-block Winslow grid is solved (SPEC 10: "only where the boundary is
straight"; on a curved or cornered boundary the end stays where it was drawn).

Each step the end goes to the point of the boundary nearest the edge's next node, so that
the edge's first grid line meets the wall at right angles (on a straight wall this is a
symmetry wall's mirror condition), kept a margin from the current far ends of its two
boundary pieces (which may slide too), and those pieces' nodes are respaced at equal arc
length along the drawn boundary. An end where a grading starts (``--spacing X,Y=H``,
``chains.py``) stays where it was drawn, as the grading is asked there. Positions on a
boundary ring are arc lengths along it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pinn_engine.multiblock.blocks import Topology
from pinn_engine.multiblock.layout import Layout

SLIDE_MARGIN = 0.25  # a sliding end keeps this share of its shorter piece from its far ends
# the secant step of :func:`slide` is taken while the next node follows the end by at most
# this share (a larger one would multiply the move by more than 100: a wild step, not a fit)
MAX_FOLLOW = 0.99
# boundary pieces are straight when their drawn points lie this share of their extent or
# less off one line (float32 files round coordinates to about 6e-8 of their size)
STRAIGHT_TOL = 1e-6


class Ring:
    """A closed boundary polyline parametrised by arc length (any real, taken modulo the
    perimeter ``length``)."""

    def __init__(self, ring: np.ndarray) -> None:
        self.points = np.vstack([ring, ring[:1]])
        steps = np.linalg.norm(np.diff(self.points, axis=0), axis=1)
        self.arc = np.concatenate([[0.0], np.cumsum(steps)])
        self.length = float(self.arc[-1])
        self.vertex = {(float(x), float(y)): float(s) for (x, y), s in zip(ring, self.arc)}
        # the vertices' arc lengths over two laps, ascending
        self.inner = np.concatenate([self.arc[:-1], self.arc[:-1] + self.length])

    def at(self, s: np.ndarray) -> np.ndarray:
        """Points at arc lengths ``s``."""
        s = np.mod(s, self.length)
        return np.column_stack(
            [np.interp(s, self.arc, self.points[:, 0]), np.interp(s, self.arc, self.points[:, 1])]
        )

    def nearest(self, p: np.ndarray, lo: float, hi: float) -> float:
        """Arc length in [lo, hi] (hi - lo at most the perimeter) of the point of that
        stretch nearest ``p``."""
        inside = self.inner[
            np.searchsorted(self.inner, lo, "right") : np.searchsorted(self.inner, hi)
        ]
        s = np.concatenate([[lo], inside, [hi]])
        ends = self.at(s)
        a, b = ends[:-1], ends[1:]
        d = b - a
        t = np.einsum("nk,nk->n", p - a, d) / np.maximum(np.einsum("nk,nk->n", d, d), 1e-300)
        t = np.clip(t, 0.0, 1.0)
        k = int(np.argmin(np.linalg.norm(a + t[:, None] * d - p, axis=1)))
        return float(s[k] + t[k] * (s[k + 1] - s[k]))


@dataclass
class Slider:
    """An edge end ``node`` on ring ``ring``, its edge's next node ``next``, the far ends
    ``far`` of its two boundary pieces (before and after it along the ring) and those
    pieces' node ids ``pieces`` (far[0] to the end, the end to far[1])."""

    node: int
    next: int
    ring: int
    far: tuple[int, int]
    margin: float
    pieces: tuple[np.ndarray, np.ndarray]


def _toward(ids: np.ndarray, points: np.ndarray, e: int) -> tuple[np.ndarray, np.ndarray]:
    """A piece's node ids and drawn points oriented to end at its end ``e`` (0 or -1)."""
    return (ids[::-1], points[::-1]) if e == 0 else (ids, points)


def _even(params: np.ndarray) -> bool:
    """Whether a piece's node fractions are equal steps (not a grading's)."""
    return bool(np.allclose(params, np.linspace(0.0, 1.0, len(params))))


def straight(points: np.ndarray) -> bool:
    """Whether drawn ``points`` (n, 2) lie on one line, within STRAIGHT_TOL of their extent."""
    centred = points - points.mean(axis=0)
    extent = float(np.abs(centred).max())
    if extent == 0.0:
        return True
    # the smallest singular value: the points' spread off their best line, times sqrt(n)
    spread = np.linalg.svd(centred, compute_uv=False)[-1] / np.sqrt(len(points))
    return spread <= STRAIGHT_TOL * extent


def sliders(topo: Topology, lay: Layout) -> tuple[list[Slider], list[Ring], dict[int, float]]:
    """The edge ends that slide (junctions of two boundary pieces and one interface piece
    where both boundary pieces lie on one straight line), the boundary rings, and the arc
    length on its ring of every boundary junction node."""
    rings = [Ring(r) for r in topo.lines.rings]
    ends: dict[int, list[tuple[int, int]]] = {}
    for k, nodes in enumerate(lay.piece_ids):
        ends.setdefault(int(nodes[0]), []).append((k, 0))
        ends.setdefault(int(nodes[-1]), []).append((k, -1))
    where: dict[int, tuple[int, float]] = {}
    for node in ends:
        key = (float(lay.points[node, 0]), float(lay.points[node, 1]))
        for r, ring in enumerate(rings):
            if key in ring.vertex:
                where[node] = (r, ring.vertex[key])
    out = []
    for node, meeting in ends.items():
        walls = [(k, e) for k, e in meeting if not topo.pieces[k].interface]
        edges = [(k, e) for k, e in meeting if topo.pieces[k].interface]
        if len(meeting) != 3 or len(walls) != 2 or len(edges) != 1 or node not in where:
            continue
        r, s = where[node]
        ring = rings[r]
        runs = [_toward(lay.piece_ids[k], topo.pieces[k].points, e) for k, e in walls]
        # the piece before the end along the ring has its last drawn step forwards
        behind = [
            np.mod(s - ring.vertex[(float(p[-2, 0]), float(p[-2, 1]))], ring.length)
            for _, p in runs
        ]
        if behind[0] > behind[1]:
            runs.reverse()
        (first, before), (second, after) = runs
        if not straight(np.vstack([before, after])):
            continue  # a curved or cornered boundary (the L's inner corner): the end stays
        if not all(_even(lay.piece_params[k]) for k, _ in walls):
            continue  # a grading starts at the end: it stays where the grading is asked
        k, e = edges[0]
        nxt = int(lay.piece_ids[k][1 if e == 0 else -2])
        margin = SLIDE_MARGIN * min(topo.pieces[k].length for k, _ in walls)
        far = (int(first[0]), int(second[0]))
        out.append(Slider(node, nxt, r, far, margin, (first, second[::-1])))
    return out, rings, {n: s for n, (_, s) in where.items()}


def slide(
    points: np.ndarray,
    slider: Slider,
    ring: Ring,
    at: dict[int, float],
    last: dict[int, tuple[float, float]],
) -> None:
    """Move a slider toward the point of its stretch (between its far ends' current arc
    lengths ``at``, less the margin) nearest its edge's next node, record its arc length in
    ``at`` and respace its two boundary pieces at equal arc length.

    The next node follows the end part of the way (it is solved with the end held), so
    going to the nearest point each step converges slowly (the cylinder's ends needed 160
    Picard steps, the interior alone 19): the move is a secant step on (nearest point -
    position) = 0 over this slider's previous step, kept in ``last`` (position, target),
    where the two steps say the next node follows by a share between 0 and
    ``MAX_FOLLOW``, else the plain move."""
    lo, hi = _stretch(slider, ring, at)
    now = lo + np.mod(at[slider.node] - lo, ring.length)
    target = ring.nearest(points[slider.next], lo + slider.margin, hi - slider.margin)
    s = target
    if slider.node in last:
        before, aimed = last[slider.node]
        moved = now - before
        if abs(moved) > 0:
            follow = (target - aimed) / moved  # how far the target moved per unit of the end
            if 0.0 <= follow <= MAX_FOLLOW:
                s = now + (target - now) / (1.0 - follow)
        s = float(np.clip(s, lo + slider.margin, hi - slider.margin))
    last[slider.node] = (now, target)
    _put(points, slider, ring, at, s)


def place(points: np.ndarray, slider: Slider, ring: Ring, at: dict[int, float]) -> None:
    """Put a slider at the point of its stretch (as :func:`slide`'s) nearest its node's
    position in ``points`` (a family model's, SPEC 16), record its arc length in ``at`` and
    respace its two boundary pieces at equal arc length: exactly on the boundary, where the
    model put it."""
    lo, hi = _stretch(slider, ring, at)
    s = ring.nearest(points[slider.node], lo + slider.margin, hi - slider.margin)
    _put(points, slider, ring, at, s)


def _stretch(slider: Slider, ring: Ring, at: dict[int, float]) -> tuple[float, float]:
    """The arc lengths of a slider's far ends (``at``), the second past the first."""
    lo = at[slider.far[0]]
    return lo, lo + (np.mod(at[slider.far[1]] - lo, ring.length) or ring.length)


def _put(points: np.ndarray, slider: Slider, ring: Ring, at: dict[int, float], s: float) -> None:
    """A slider at arc length ``s`` (within its stretch, recorded in ``at``), its two
    pieces respaced evenly."""
    lo, hi = _stretch(slider, ring, at)
    at[slider.node] = float(np.mod(s, ring.length))
    first, second = slider.pieces
    arcs = [np.linspace(lo, s, len(first))[1:], np.linspace(s, hi, len(second))[1:-1]]
    placed = ring.at(np.concatenate(arcs))
    points[first[1:]] = placed[: len(arcs[0])]
    points[second[1:-1]] = placed[len(arcs[0]) :]
