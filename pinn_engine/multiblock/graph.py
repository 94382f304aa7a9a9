"""The linework of a multi-block domain (SPEC 10): boundary rings and block edges, snapped
and checked, so that every junction is a vertex that the curves meeting there share exactly.

Faces are then found from these shared vertices alone (``blocks.py``); nothing is left to
floating-point intersection.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import shapely
from shapely.validation import explain_validity

from pinn_engine.errors import InputError

# Edge ends within this share of the domain's diagonal of the boundary, a hole or another
# edge are snapped onto it (SPEC 10)
SNAP = 1e-3


@dataclass
class Linework:
    """Closed ``rings`` ((n, 2), no repeated end point; ``rings[0]`` the outer boundary,
    counter-clockwise, the others holes) and open block ``edges`` ((n, 2)), ``names`` naming
    each edge for messages, and the domain's ``diagonal``."""

    rings: list[np.ndarray]
    edges: list[np.ndarray]
    names: list[str]
    diagonal: float


def _area(ring: np.ndarray) -> float:
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _inside(point: np.ndarray, ring: np.ndarray) -> bool:
    """Whether ``point`` lies inside the closed ``ring`` (even-odd rule)."""
    a, b = ring, np.roll(ring, -1, axis=0)
    crosses = (a[:, 1] > point[1]) != (b[:, 1] > point[1])
    with np.errstate(divide="ignore", invalid="ignore"):
        x = a[:, 0] + (point[1] - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return bool(np.count_nonzero(crosses & (point[0] < x)) % 2)


def order_rings(rings: list[np.ndarray], source: str) -> list[np.ndarray]:
    """The outer boundary first (the ring of largest area), then the holes in the order
    given (so ``hole1`` is the first hole drawn); the outer ring counter-clockwise, holes
    clockwise (the domain on the left of every ring)."""
    rings = [r[:-1] if np.array_equal(r[0], r[-1]) else r for r in rings]
    outer = max(range(len(rings)), key=lambda k: abs(_area(rings[k])))
    rings = [rings[outer], *rings[:outer], *rings[outer + 1 :]]
    out = []
    for k, ring in enumerate(rings):
        if k and not _inside(ring[0], rings[0]):
            raise InputError(
                f"closed curve {k} lies outside the outer boundary; holes must lie inside it",
                source,
            )
        ccw = _area(ring) > 0
        out.append(ring if ccw == (k == 0) else ring[::-1].copy())
    return out


def check_simple(rings: list[np.ndarray], source: str) -> None:
    """Refuse a ring that crosses or touches itself (its faces would not be found), naming
    the ring (``boundary``, ``hole1``, ...) and the place."""
    for k, ring in enumerate(rings):
        if shapely.LinearRing(ring).is_simple:
            continue
        why = explain_validity(shapely.Polygon(ring))  # e.g. "Self-intersection[x y]"
        x, y = (float(v) for v in why[why.index("[") + 1 : why.index("]")].split()[:2])
        name = f"hole{k}" if k else "the boundary"
        raise InputError(
            f"{name} crosses itself at ({x:.4g}, {y:.4g}); draw each closed curve without "
            "crossings",
            source,
        )


def _pieces(polyline: np.ndarray, closed: bool) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """A polyline's segments: their starts, their vectors and squared lengths (kept off 0)."""
    a = polyline if closed else polyline[:-1]
    d = (np.roll(polyline, -1, axis=0) if closed else polyline[1:]) - a
    return a, d, np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)


class _Curves:
    """Rings and edges as mutable point lists, with snapping of a point onto one of them."""

    def __init__(self, rings: list[np.ndarray], edges: list[np.ndarray], tol: float) -> None:
        self.curves = [list(map(tuple, r)) for r in rings] + [list(map(tuple, e)) for e in edges]
        self.closed = [True] * len(rings) + [False] * len(edges)
        self.tol = tol
        self._cache: dict[int, tuple] = {}  # each curve's points and segments, until it changes

    def points(self, c: int) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Curve ``c``'s points and :func:`_pieces` (built once for each state of the curve)."""
        if c not in self._cache:
            pts = np.array(self.curves[c])
            self._cache[c] = (pts, *_pieces(pts, self.closed[c]))
        return self._cache[c]

    def put(self, c: int, k: int, point: tuple) -> None:
        """Set point ``k`` of curve ``c``."""
        self.curves[c][k] = point
        self._cache.pop(c, None)

    def snap(self, p: np.ndarray, candidates: list[int]) -> tuple | None:
        """The point of the nearest curve among ``candidates`` within ``tol`` of ``p`` (the
        first of equals): one of its vertices if one is that close, else the foot of ``p``,
        inserted as a vertex."""
        if not candidates:
            return None
        parts = [self.points(c)[1:] for c in candidates]
        a, d, length2 = (np.concatenate(x) for x in zip(*parts))
        t = np.clip(np.einsum("ij,ij->i", p - a, d) / length2, 0.0, 1.0)
        dist = np.linalg.norm(a + t[:, None] * d - p, axis=1)
        k = int(np.argmin(dist))
        if dist[k] > self.tol:
            return None
        first = np.cumsum([0] + [len(x[0]) for x in parts])  # each curve's first segment
        which = int(np.searchsorted(first, k, side="right")) - 1
        c, seg = candidates[which], k - int(first[which])
        pts = self.points(c)[0]
        near = np.linalg.norm(pts - p, axis=1)
        if near.min() <= self.tol:
            return self.curves[c][int(np.argmin(near))]
        foot = tuple(a[k] + t[k] * d[k])
        self.curves[c].insert(seg + 1, foot)
        self._cache.pop(c, None)
        return foot


def snap_edges(rings: list[np.ndarray], edges: list[np.ndarray], tol: float) -> list[list]:
    """Rings and edges (as point lists) with every edge end moved onto what it ends on: ends
    near each other meet at their mean, then go onto a ring, else onto another edge (the
    point inserted as that curve's vertex). Returns the curves, rings first, and the ends
    that found nothing as (edge, 0 or -1)."""
    n_r = len(rings)
    curves = _Curves(rings, edges, tol)
    ends = [(e, k) for e in range(len(edges)) for k in (0, -1)]
    xy = np.array([edges[e][k] for e, k in ends], dtype=float)
    group = list(range(len(ends)))  # ends within tol of each other, joined (union-find)

    def root(a: int) -> int:
        while group[a] != a:
            group[a] = group[group[a]]
            a = group[a]
        return a

    apart = np.linalg.norm(xy[:, None] - xy[None, :], axis=-1)
    for a, b in np.argwhere(np.triu(apart <= tol, 1)):  # each close pair, a < b, in order
        group[root(int(a))] = root(int(b))
    clusters: dict[int, list[int]] = {}
    for a in range(len(ends)):
        clusters.setdefault(root(a), []).append(a)
    loose = []
    for members in clusters.values():
        p = xy[members].mean(axis=0)
        target = curves.snap(p, list(range(n_r)))
        if target is None:
            own = {ends[a][0] for a in members}
            others = [n_r + e for e in range(len(edges)) if e not in own]
            target = curves.snap(p, others)
        if target is None:
            target = tuple(p)
            if len(members) == 1:
                loose.append(ends[members[0]])
        for a in members:
            e, k = ends[a]
            curves.put(n_r + e, k, target)
    return curves.curves, loose


def _segments(curve: np.ndarray, closed: bool) -> np.ndarray:
    b = np.roll(curve, -1, axis=0) if closed else curve[1:]
    return np.stack([curve if closed else curve[:-1], b], axis=1)


def _crosses(s: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Whether segments ``s[i]``, ``t[j]`` ((n, 2, 2)) cross properly (each one's ends
    strictly on both sides of the other), sharing no end point, for every (i, j)."""

    def side(a, b, p):
        ab, ap = b - a, p - a
        return np.sign(ab[..., 0] * ap[..., 1] - ab[..., 1] * ap[..., 0])

    a, b = s[:, None, 0], s[:, None, 1]
    c, d = t[None, :, 0], t[None, :, 1]
    return (side(a, b, c) * side(a, b, d) < 0) & (side(c, d, a) * side(c, d, b) < 0)


def _crossing(s: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Pairs (i, j) of segments ``s[i]``, ``t[j]`` that cross (:func:`_crosses`)."""
    return np.argwhere(_crosses(s, t))


def _where(s: np.ndarray, t: np.ndarray) -> str:
    """The crossing point of two segments, written for a message."""
    a, b, c, d = s[0], s[1], t[0], t[1]
    m = np.column_stack([b - a, c - d])
    u = np.linalg.solve(m, c - a)[0]
    x, y = a + u * (b - a)
    return f"({x:.4g}, {y:.4g})"


def check_crossings(rings: list[np.ndarray], edges: list[np.ndarray], names: list[str]) -> None:
    """Refuse an edge that crosses another edge or a ring, naming the place."""
    ring_segs = np.concatenate([_segments(r, True) for r in rings])
    edge_segs = [_segments(e, False) for e in edges]
    every = np.concatenate(edge_segs)
    owner = np.repeat(np.arange(len(edges)), [len(segs) for segs in edge_segs])
    # every pair at once: each edge against the rings and against each later edge; the
    # loop below only runs to name the first crossing
    later = owner[:, None] < owner[None, :]
    if not _crosses(every, ring_segs).any() and not (_crosses(every, every) & later).any():
        return
    for k, segs in enumerate(edge_segs):
        hit = _crossing(segs, ring_segs)
        if len(hit):
            i, j = hit[0]
            raise InputError(
                f"crosses the boundary at {_where(segs[i], ring_segs[j])}; a block edge runs "
                "inside the domain and ends on the boundary, a hole or another edge",
                names[k],
            )
        for m in range(k + 1, len(edge_segs)):
            hit = _crossing(segs, edge_segs[m])
            if len(hit):
                i, j = hit[0]
                where = _where(segs[i], edge_segs[m][j])
                raise InputError(
                    f"crosses the block edge {names[m]} at {where}; block edges may only meet "
                    "at an end (end one edge on the other)",
                    names[k],
                )


def linework(
    rings: list[np.ndarray], edges: list[np.ndarray], names: list[str], source: str
) -> Linework:
    """The checked linework of a boundary's ``rings`` (any order and orientation) and the
    block ``edges``: ends snapped (:func:`snap_edges`), then refused if an end lies on
    nothing (naming the edge and the point), a ring crosses itself or edges cross (naming
    the place)."""
    rings = order_rings([np.asarray(r, dtype=float)[:, :2] for r in rings], source)
    check_simple(rings, source)
    edges = [np.asarray(e, dtype=float)[:, :2] for e in edges]
    diagonal = float(np.linalg.norm(np.ptp(rings[0], axis=0)))
    curves, loose = snap_edges(rings, edges, SNAP * diagonal)
    if loose:
        e, k = loose[0]
        x, y = edges[e][k]
        raise InputError(
            f"ends nowhere at ({x:.4g}, {y:.4g}): each end must lie on the boundary, a hole or "
            f"another block edge (within {SNAP:g} of the diagonal)",
            names[e],
        )
    n_r = len(rings)
    rings = [np.array(c) for c in curves[:n_r]]
    edges = [np.array(c) for c in curves[n_r:]]
    if edges:
        check_crossings(rings, edges, names)
    return Linework(rings, edges, list(names), diagonal)
