"""Closed four-sided boundaries: validation, corners, sides, the working frame (SPEC 1)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.geometry.plane import Plane

SIDES = ("bottom", "right", "top", "left")

# A corner must turn by at least this much, and clearly more than any other vertex.
MIN_CORNER_TURN_DEG = 20.0
CORNER_MARGIN = 0.75  # the 5th-largest turn must be below this fraction of the 4th
# A vertex where the outline turns by this many degrees or more is a sharp corner, a grid
# node of any grid written (SPEC 10's rule for a block corner)
SHARP_TURN = 30.0
# Consecutive points closer than this (relative to the bounding-box diagonal) are one point:
# duplicates and CAD micro-segments are merged (a documented repair).
DUPLICATE_TOL = 1e-7
# A point the ring comes back to is one within a square of TOUCH_BIN duplicate tolerances of an
# earlier one (a coarse grid of squares: a touch is found whatever the points' spacing there),
# reached along the ring only after more than TOUCH_ARC such squares (a touch goes round; two
# close consecutive points do not)
TOUCH_BIN = 16
TOUCH_ARC = 2.0
# Coordinates must resolve the domain to at least this fraction of its size: a tiny domain far
# from the origin (1e-9 wide at 1e8) has too few significant digits left to mesh.
PRECISION_LIMIT = 1e-4
# Most boundary points accepted (reading, validation and meshing stay fast below this).
MAX_POINTS = 200_000
# Largest coordinate magnitude accepted (squares of lengths must not overflow).
MAX_COORDINATE = 1e100


def arc_lengths(points: np.ndarray) -> np.ndarray:
    """The length along a polyline (n, d) from its first point to each of its points, (n,)."""
    return np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(points, axis=0), axis=1))])


# arc-length fraction within which a knot of a reparametrized polyline is one of its points
# (a knot met by rounding beside a point would make a segment of zero length)
KNOT_MERGE = 1e-12


class Polyline:
    """An open polyline parametrised by its arc-length fraction t in [0, 1]."""

    def __init__(self, points: np.ndarray) -> None:
        self.points = np.asarray(points, dtype=float)
        self.length = float(np.linalg.norm(np.diff(self.points, axis=0), axis=1).sum())
        self.t = arc_lengths(self.points) / self.length
        self.t[-1] = 1.0

    def reparametrized(self, arc: np.ndarray, param: np.ndarray) -> Polyline:
        """The same polyline with its parameter the piecewise-linear map of the arc-length
        fraction through the knots (``arc``, ``param``), both increasing from 0 to 1; a knot
        inside a segment becomes a point of it, so that the knot's parameter is exactly there
        (one within ``KNOT_MERGE`` of a point is that point: no segment of zero length)."""
        near = np.abs(arc[:, None] - self.t[None, :]).min(axis=1) <= KNOT_MERGE
        t = np.union1d(self.t, arc[~near])
        line = Polyline.__new__(Polyline)
        line.points, line.length = self.at(t), self.length
        line.points[np.searchsorted(t, self.t)] = self.points  # its own points bit for bit
        line.t = np.interp(t, arc, param)
        return line

    def at(self, t: np.ndarray) -> np.ndarray:
        """Points at parameters ``t`` (the arc-length fractions unless reparametrized; exact
        linear interpolation)."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, 1.0)
        return np.stack(
            [np.interp(t, self.t, self.points[:, 0]), np.interp(t, self.t, self.points[:, 1])],
            axis=-1,
        )

    def project(self, p: np.ndarray) -> tuple[float, float]:
        """Arc-length fraction of the closest point to ``p`` and the distance to it."""
        a, b = self.points[:-1], self.points[1:]
        ab = b - a
        u = np.clip(
            np.einsum("ij,ij->i", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300),
            0.0,
            1.0,
        )
        d = np.linalg.norm(a + u[:, None] * ab - p, axis=1)
        k = int(np.argmin(d))
        return float(self.t[k] + u[k] * (self.t[k + 1] - self.t[k])), float(d[k])


@dataclass(frozen=True)
class Frame:
    """Affine map between the user's coordinates and the unit-box working frame."""

    origin: np.ndarray
    scale: float

    @classmethod
    def around(cls, points: np.ndarray) -> Frame:
        lo, hi = points.min(axis=0), points.max(axis=0)
        return cls(origin=lo, scale=float((hi - lo).max()))

    def to_unit(self, p: np.ndarray) -> np.ndarray:
        return (np.asarray(p, dtype=float) - self.origin) / self.scale

    def to_user(self, q: np.ndarray) -> np.ndarray:
        return np.asarray(q, dtype=float) * self.scale + self.origin


def segment_feet(
    p: np.ndarray, a: np.ndarray, ab: np.ndarray, ab2: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """For each point of ``p`` (n, 2) and each segment from ``a`` (m, 2) along ``ab`` (m, 2),
    its squared length ``ab2`` (m, floored above 0): the fraction along the segment of its
    point nearest the point, and the distance there, (n, m) each.

    x and y are computed as separate (n, m) arrays: a (n, m, 2) array's products and norms
    reduce over its last axis of 2 one pair at a time, about 8x the CPU (124 boundary
    nodes against 360 segments: 3.4 ms), to the same bits (a sum of two products)."""
    px, py = p[:, :1], p[:, 1:2]
    ax, ay, abx, aby = a[:, 0], a[:, 1], ab[:, 0], ab[:, 1]
    u = np.clip(((px - ax) * abx + (py - ay) * aby) / ab2, 0.0, 1.0)
    dx = ax + u * abx - px
    dy = ay + u * aby - py
    return u, np.sqrt(dx * dx + dy * dy)


def segment_distance(p: np.ndarray, ring: np.ndarray, closed: bool = True) -> np.ndarray:
    """Distance of each point of ``p`` (n, 2) to the polyline ``ring`` (m, 2), closed unless
    ``closed`` is False."""
    a, b = (ring, np.roll(ring, -1, axis=0)) if closed else (ring[:-1], ring[1:])
    ab = b - a
    ab2 = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    out = np.empty(len(p))
    for start in range(0, len(p), 256):
        out[start : start + 256] = segment_feet(p[start : start + 256], a, ab, ab2)[1].min(axis=1)
    return out


def signed_area(ring: np.ndarray) -> float:
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def segments_cross(
    a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray, rel_tol: float = 1e-12
) -> np.ndarray:
    """Proper or touching intersection of segments ab and cd (broadcast).

    An orientation within ``rel_tol`` of zero (relative to the lengths involved) counts as
    collinear, and then the segments meet only if the point lies within the other segment's
    extent: rounding in nearly collinear, disjoint segments cannot fake a crossing.
    """

    def side(p, q, r):
        u, v = q - p, r - p
        o = u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]
        scale = np.hypot(u[..., 0], u[..., 1]) * np.hypot(v[..., 0], v[..., 1])
        return np.where(np.abs(o) <= rel_tol * scale, 0.0, np.sign(o))

    def within(p, q, r):
        out = np.ones(np.broadcast(p[..., 0], r[..., 0]).shape, dtype=bool)
        for k in (0, 1):
            lo, hi = np.minimum(p[..., k], q[..., k]), np.maximum(p[..., k], q[..., k])
            pad = rel_tol * (hi - lo + np.abs(r[..., k] - p[..., k]))
            out &= (r[..., k] >= lo - pad) & (r[..., k] <= hi + pad)
        return out

    s1, s2 = side(a, b, c), side(a, b, d)
    s3, s4 = side(c, d, a), side(c, d, b)
    proper = (s1 * s2 < 0) & (s3 * s4 < 0)
    touch = (
        ((s1 == 0) & within(a, b, c))
        | ((s2 == 0) & within(a, b, d))
        | ((s3 == 0) & within(c, d, a))
        | ((s4 == 0) & within(c, d, b))
    )
    return proper | touch


def _brute_force_intersections(a: np.ndarray, b: np.ndarray) -> list[tuple[int, int]]:
    """First edge (in ring order) that meets a non-adjacent edge; O(n^2), stops at a hit."""
    n = len(a)
    for i in range(n):
        j = np.arange(i + 2, n)
        if i == 0:
            j = j[j != n - 1]
        if len(j) == 0:
            continue
        cross = segments_cross(a[i], b[i], a[j], b[j])
        if cross.any():
            return [(i, int(k)) for k in j[cross]]
    return []


def _candidate_pairs(a: np.ndarray, b: np.ndarray, budget: int) -> np.ndarray | None:
    """Edge pairs whose bounding boxes share a cell of a uniform grid; None if over budget."""
    n = len(a)
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    origin = lo.min(axis=0)
    extent = float((hi.max(axis=0) - origin).max()) or 1.0
    length = np.linalg.norm(b - a, axis=1)
    cells = int(np.clip(extent / max(float(np.median(length)), 1e-300), 1, 8192))
    cell_lo = np.clip(((lo - origin) / extent * cells).astype(np.int64), 0, cells - 1)
    cell_hi = np.clip(((hi - origin) / extent * cells).astype(np.int64), 0, cells - 1)
    width = cell_hi[:, 0] - cell_lo[:, 0] + 1
    count = width * (cell_hi[:, 1] - cell_lo[:, 1] + 1)
    total = int(count.sum())
    if total > budget:
        return None
    seg = np.repeat(np.arange(n), count)
    k = np.arange(total) - np.repeat(np.cumsum(count) - count, count)
    cx = cell_lo[seg, 0] + k % width[seg]
    cy = cell_lo[seg, 1] + k // width[seg]
    order = np.argsort(cy * cells + cx, kind="stable")
    key, seg = (cy * cells + cx)[order], seg[order]
    # pair every entry with the later entries of its cell
    end = np.searchsorted(key, key, side="right")
    pos = np.arange(total)
    later = end - pos - 1
    n_pairs = int(later.sum())
    if n_pairs > budget:
        return None
    first = np.repeat(pos, later)
    second = first + 1 + (np.arange(n_pairs) - np.repeat(np.cumsum(later) - later, later))
    i, j = seg[first], seg[second]
    i, j = np.minimum(i, j), np.maximum(i, j)
    far = (j - i > 1) & ~((i == 0) & (j == n - 1))
    pairs = np.unique(i[far] * n + j[far])
    return np.column_stack([pairs // n, pairs % n])


def self_intersections(ring: np.ndarray, budget: int = 4_000_000) -> list[tuple[int, int]]:
    """Pairs of non-adjacent edges of the closed ring that touch or cross.

    Edges are bucketed in a uniform grid, so a valid ring of many points is checked in about
    linear time; only rings whose edges are very long and many (random clutter, which crosses
    itself early) fall back to the quadratic scan.
    """
    n = len(ring)
    a, b = ring, np.roll(ring, -1, axis=0)
    if n < 4:
        return []
    pairs = _candidate_pairs(a, b, budget) if n > 64 else None
    if pairs is None:
        return _brute_force_intersections(a, b)
    hits: list[tuple[int, int]] = []
    for s in range(0, len(pairs), 1 << 20):
        i, j = pairs[s : s + (1 << 20), 0], pairs[s : s + (1 << 20), 1]
        cross = segments_cross(a[i], b[i], a[j], b[j])
        hits.extend((int(p), int(q)) for p, q in zip(i[cross], j[cross]))
    return sorted(hits)


def turning_angles(ring: np.ndarray) -> np.ndarray:
    """Signed turning angle (degrees) at each vertex of a counter-clockwise ring."""
    e_in = ring - np.roll(ring, 1, axis=0)
    e_out = np.roll(ring, -1, axis=0) - ring
    cross = e_in[:, 0] * e_out[:, 1] - e_in[:, 1] * e_out[:, 0]
    dot = np.einsum("ij,ij->i", e_in, e_out)
    return np.degrees(np.arctan2(cross, dot))


def _merge_close(
    unit: np.ndarray, tol: float, marked: np.ndarray | None, source: str | None
) -> np.ndarray:
    """Keep-mask that drops each point lying within ``tol`` of the next one (ring order).

    Named corners (``marked``) are always kept: the neighbour is dropped instead.
    """
    n = len(unit)
    keep = np.linalg.norm(np.diff(unit, axis=0, append=unit[:1]), axis=1) > tol
    if marked is not None:
        for i in np.flatnonzero(marked & ~keep):  # i lies within tol of its successor
            nxt = (i + 1) % n
            if marked[nxt]:
                raise InputError(f"named corners {i} and {nxt} are the same point", source)
            keep[i], keep[nxt] = True, False
    return keep


def _touching(unit: np.ndarray, size: float) -> int | None:
    """The first point of a ring (n, 2) that shares a square of side ``size`` with a point
    further along it: one the ring reaches again only after more than ``TOUCH_ARC`` squares
    of its length (consecutive points a few ``size`` apart lie along the ring, not on a
    touch); None where there is none."""
    rounded = np.round(unit / size).astype(np.int64)
    _, inverse, counts = np.unique(rounded, axis=0, return_inverse=True, return_counts=True)
    inverse = inverse.ravel()
    steps = np.linalg.norm(np.diff(unit, axis=0, append=unit[:1]), axis=1)
    arc = np.concatenate([[0.0], np.cumsum(steps[:-1])])
    perimeter = float(steps.sum())
    found = []
    for group in np.flatnonzero(counts > 1):
        members = np.flatnonzero(inverse == group)
        apart = np.abs(arc[members][:, None] - arc[members][None, :])
        along = np.minimum(apart, perimeter - apart)
        if along.max() > TOUCH_ARC * size:
            found.append(int(members[0]))
    return min(found) if found else None


def clean_ring(
    points: np.ndarray, source: str | None, marked: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Validate a closed ring of (x, y) points; return the kept points and the kept mask.

    Consecutive points closer than ``DUPLICATE_TOL`` times the bounding-box diagonal are merged
    (a documented repair; ``marked`` points, the named corners, are the ones kept). Every other
    problem raises :class:`InputError`. The checks run in the normalised frame, so they do not
    depend on the units, the offset or the scale of the coordinates.
    """
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InputError("boundary must be a list of (x, y) points", source)
    if not np.all(np.isfinite(pts)):
        bad = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise InputError(f"boundary point {bad} is not finite (NaN or infinity)", source)
    if len(pts) > 1 and np.all(pts == pts[0]):
        raise InputError("boundary points all coincide", source)
    if len(pts) < 4:
        raise InputError(
            f"boundary has {len(pts)} points; a four-sided domain needs at least 4", source
        )
    if np.abs(pts).max() > MAX_COORDINATE:
        raise InputError(
            f"boundary coordinates beyond +-{MAX_COORDINATE:g} are not accepted", source
        )
    if len(pts) > MAX_POINTS:
        raise InputError(
            f"boundary has {len(pts)} points; at most {MAX_POINTS} are accepted (resample it)",
            source,
        )
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    size = float((hi - lo).max())
    ulp = float(np.spacing(np.abs(pts).max()))
    if ulp > PRECISION_LIMIT * size:
        raise InputError(
            f"coordinates carry too few significant digits for a domain this "
            f"small ({size:.3g} wide at {np.abs(pts).max():.3g} from the origin); "
            "shift it nearer the origin",
            source,
        )
    unit = (pts - lo) / size
    diag = float(np.linalg.norm(unit.max(axis=0) - unit.min(axis=0)))
    tol = max(DUPLICATE_TOL * diag, 4.0 * ulp / size)
    keep = _merge_close(unit, tol, marked, source)
    unit = unit[keep]
    if len(unit) < 4:
        raise InputError("boundary has fewer than 4 distinct points", source)
    kept = np.flatnonzero(keep)
    touching = _touching(unit, tol * TOUCH_BIN)
    if touching is not None:
        raise InputError(
            f"boundary point {int(kept[touching])} is repeated further along the ring (the "
            "boundary touches itself)",
            source,
        )
    e_in = unit - np.roll(unit, 1, axis=0)
    e_out = np.roll(unit, -1, axis=0) - unit
    cross = e_in[:, 0] * e_out[:, 1] - e_in[:, 1] * e_out[:, 0]
    dot = np.einsum("ij,ij->i", e_in, e_out)
    back = (dot < 0) & (
        np.abs(cross) <= 1e-9 * np.linalg.norm(e_in, axis=1) * np.linalg.norm(e_out, axis=1)
    )
    if back.any():
        k = int(kept[np.argmax(back)])
        raise InputError(
            f"boundary doubles back on itself at point {k} (a zero-width spike)", source
        )
    hits = self_intersections(unit)
    if hits:
        i, j = hits[0]
        x, y = lo + size * _crossing(unit, i, j)
        raise InputError(
            f"boundary is self-intersecting: the edges after points {kept[i]} and {kept[j]} "
            f"cross at ({x:.6g}, {y:.6g}); move those points so that the boundary runs once "
            "around the domain without crossing itself (its points in order along it)",
            source,
        )
    if abs(signed_area(unit)) < 1e-9 * diag * diag:
        raise InputError("boundary encloses no area", source)
    return pts[keep], keep


def _crossing(ring: np.ndarray, i: int, j: int) -> np.ndarray:
    """Where the edge after point ``i`` of ``ring`` meets the edge after point ``j`` (the
    middle of their overlap's ends when they are parallel)."""
    n = len(ring)
    a, b, c, d = ring[i], ring[(i + 1) % n], ring[j], ring[(j + 1) % n]
    r, s = b - a, d - c
    denom = r[0] * s[1] - r[1] * s[0]
    if abs(denom) <= 1e-12 * float(np.linalg.norm(r) * np.linalg.norm(s)):
        return 0.5 * (b + c)  # touching or overlapping collinear edges
    q = c - a
    return a + (q[0] * s[1] - q[1] * s[0]) / denom * r


def detect_corners(
    ring: np.ndarray, source: str | None = None, labels: np.ndarray | None = None
) -> np.ndarray:
    """Indices of the four vertices with the largest turning angle of a CCW ring.

    A corner turns by at least ``MIN_CORNER_TURN_DEG`` (an interior angle of at most 160
    degrees), and the fifth-largest turn is below ``CORNER_MARGIN`` times the fourth;
    otherwise the corners are ambiguous and the error lists the candidates by ``labels``
    (the user's point numbers) so that they can be named (``--corners`` on the command line).
    """
    turn = turning_angles(ring)
    order = np.argsort(-turn, kind="stable")
    fourth = turn[order[3]]
    fifth = turn[order[4]] if len(ring) > 4 else -180.0
    if fourth < MIN_CORNER_TURN_DEG or fifth > CORNER_MARGIN * fourth:
        names = labels if labels is not None else np.arange(len(ring))
        top = ", ".join(f"{turn[k]:.1f} at point {names[k]}" for k in order[:5])
        why = (
            f"the 4th-largest turn is below {MIN_CORNER_TURN_DEG:g}"
            if fourth < MIN_CORNER_TURN_DEG
            else "the 5th-largest turn is close to the 4th"
        )
        raise InputError(
            f"fewer than four clear corners ({why}; largest turning angles {top} degrees); "
            "name them with four point indices ({corners})",
            source,
        )
    return np.sort(order[:4])


@dataclass(frozen=True)
class Boundary:
    """A validated four-sided boundary in the working frame.

    ``ring`` is counter-clockwise and starts at corner 0 (SPEC 1); ``corners`` index it.
    """

    ring: np.ndarray
    corners: tuple[int, int, int, int]
    frame: Frame  # user's in-plane (u, v) <-> working frame
    source: str | None = None
    plane: Plane = field(default_factory=Plane.horizontal)  # user's 3D <-> in-plane (u, v)
    # sides parametrized other than by their arc-length fraction: (side, arc-length
    # fractions, parameters), knots of a piecewise-linear map (a grid node on each sharp
    # vertex inside a side, pins.pinned_boundary)
    knots: tuple[tuple[str, np.ndarray, np.ndarray], ...] = ()

    @classmethod
    def from_points(
        cls, points: np.ndarray, corners: tuple[int, ...] | None = None, source: str | None = None
    ) -> Boundary:
        """Validate user points, find the corners and apply the side convention of SPEC 1.

        ``corners`` are indices into ``points`` as given (closing point excluded). Points
        (n, 3) may lie in any plane: the ring is meshed in the plane's own (u, v).
        """
        raw = np.asarray(points, dtype=float)
        plane = Plane.horizontal()
        if raw.ndim == 2 and raw.shape[1] == 3:
            if np.isfinite(raw).all():  # (non-finite points are refused below, by index)
                plane = Plane.fit(raw, source)
                raw = plane.to_plane(raw, source)
            else:
                raw = raw[:, :2]
        if raw.ndim == 2 and len(raw) > 1 and np.array_equal(raw[0], raw[-1]):
            raw = raw[:-1]
        marked = None
        if corners is not None:
            if len(corners) != 4 or len(set(corners)) != 4:
                raise InputError("corners must be four different point indices", source)
            if min(corners) < 0 or max(corners) >= len(raw):
                raise InputError(f"corner index out of range 0..{len(raw) - 1}", source)
            marked = np.zeros(len(raw), dtype=bool)
            marked[list(corners)] = True
        ring, keep = clean_ring(raw, source, marked)
        frame = Frame.around(ring)
        unit = frame.to_unit(ring)
        flags = marked[keep] if marked is not None else None
        labels = np.flatnonzero(keep)
        if flags is not None and flags.sum() != 4:
            raise InputError("a named corner is a duplicate point", source)
        if signed_area(unit) < 0:
            unit, labels = unit[::-1], labels[::-1]
            flags = flags[::-1] if flags is not None else None
        idx = np.flatnonzero(flags) if flags is not None else detect_corners(unit, source, labels)
        c = unit[idx]
        key = np.lexsort((c[:, 1], c[:, 0] + c[:, 1]))
        start = int(idx[key[0]])
        unit = np.roll(unit, -start, axis=0)
        idx = np.sort((idx - start) % len(unit))
        return cls(
            ring=unit, corners=tuple(int(i) for i in idx), frame=frame, source=source, plane=plane
        )

    @property
    def diagonal(self) -> float:
        """Bounding-box diagonal in the working frame."""
        return float(np.linalg.norm(self.ring.max(axis=0) - self.ring.min(axis=0)))

    def side(self, name: str) -> Polyline:
        """Side polyline oriented along increasing xi (bottom, top) or eta (left, right),
        parametrized by its ``knots`` where it has them."""
        line = self.arc_side(name)
        for side, arc, param in self.knots:
            if side == name:
                return line.reparametrized(arc, param)
        return line

    def arc_side(self, name: str) -> Polyline:
        """Side polyline as :meth:`side`, parametrized by its arc-length fraction."""
        c0, c1, c2, c3 = self.corners
        closed = np.vstack([self.ring, self.ring[:1]])
        if name == "bottom":
            return Polyline(closed[c0 : c1 + 1])
        if name == "right":
            return Polyline(closed[c1 : c2 + 1])
        if name == "top":
            return Polyline(closed[c2 : c3 + 1][::-1])
        if name == "left":
            return Polyline(closed[c3:][::-1])
        raise ValueError(f"unknown side {name!r}")

    def corner_points(self) -> np.ndarray:
        """Corners 0..3 in the working frame: (0,0), (1,0), (1,1), (0,1) in (xi, eta)."""
        return self.ring[list(self.corners)]

    def deviation(self, points_unit: np.ndarray) -> np.ndarray:
        """Distance of points (working frame) from the boundary, relative to the diagonal."""
        return segment_distance(points_unit, self.ring) / self.diagonal
