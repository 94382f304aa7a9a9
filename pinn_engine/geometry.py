"""Closed four-sided boundaries: validation, corners, sides, the working frame (SPEC 1)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .errors import InputError

SIDES = ("bottom", "right", "top", "left")

# A corner must turn by at least this much, and clearly more than any other vertex.
MIN_CORNER_TURN_DEG = 20.0
CORNER_MARGIN = 0.75  # the 5th-largest turn must be below this fraction of the 4th
# Points closer than this (relative to the bounding-box diagonal) are the same point.
DUPLICATE_TOL = 1e-12


class Polyline:
    """An open polyline parametrised by its arc-length fraction t in [0, 1]."""

    def __init__(self, points: np.ndarray) -> None:
        self.points = np.asarray(points, dtype=float)
        seg = np.linalg.norm(np.diff(self.points, axis=0), axis=1)
        self.length = float(seg.sum())
        self.t = np.concatenate([[0.0], np.cumsum(seg)]) / self.length
        self.t[-1] = 1.0

    def at(self, t: np.ndarray) -> np.ndarray:
        """Points at arc-length fractions ``t`` (exact linear interpolation)."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, 1.0)
        return np.stack(
            [np.interp(t, self.t, self.points[:, 0]), np.interp(t, self.t, self.points[:, 1])],
            axis=-1,
        )

    def project(self, p: np.ndarray) -> tuple[float, float]:
        """Arc-length fraction of the closest point to ``p`` and the distance to it."""
        a, b = self.points[:-1], self.points[1:]
        ab = b - a
        u = np.clip(np.einsum("ij,ij->i", p - a, ab) / np.maximum(np.einsum("ij,ij->i", ab, ab),
                                                                  1e-300), 0.0, 1.0)
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


def segment_distance(p: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Distance of each point of ``p`` (n, 2) to the closed polyline ``ring`` (m, 2)."""
    a = ring
    b = np.roll(ring, -1, axis=0)
    ab = b - a
    ab2 = np.maximum(np.einsum("ij,ij->i", ab, ab), 1e-300)
    out = np.empty(len(p))
    for start in range(0, len(p), 256):
        q = p[start:start + 256, None, :]
        u = np.clip(np.einsum("pmj,mj->pm", q - a, ab) / ab2, 0.0, 1.0)
        out[start:start + 256] = np.linalg.norm(a + u[..., None] * ab - q, axis=2).min(axis=1)
    return out


def signed_area(ring: np.ndarray) -> float:
    x, y = ring[:, 0], ring[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def _segments_cross(a: np.ndarray, b: np.ndarray, c: np.ndarray, d: np.ndarray) -> np.ndarray:
    """Proper or touching intersection of segments ab and cd (broadcast)."""

    def orient(p, q, r):
        return (q[..., 0] - p[..., 0]) * (r[..., 1] - p[..., 1]) - (q[..., 1] - p[..., 1]) * (
            r[..., 0] - p[..., 0])

    o1, o2 = orient(a, b, c), orient(a, b, d)
    o3, o4 = orient(c, d, a), orient(c, d, b)
    collinear = (o1 == 0) & (o2 == 0)
    boxes = np.ones(np.broadcast(o1, o3).shape, dtype=bool)
    for k in (0, 1):  # collinear segments meet only if their extents overlap
        boxes &= (np.maximum(np.minimum(a[..., k], b[..., k]), np.minimum(c[..., k], d[..., k]))
                  <= np.minimum(np.maximum(a[..., k], b[..., k]), np.maximum(c[..., k], d[..., k])))
    return (o1 * o2 <= 0) & (o3 * o4 <= 0) & (~collinear | boxes)


def self_intersections(ring: np.ndarray) -> list[tuple[int, int]]:
    """Pairs of non-adjacent edges of the closed ring that touch or cross."""
    n = len(ring)
    a, b = ring, np.roll(ring, -1, axis=0)
    hits: list[tuple[int, int]] = []
    for i in range(n):
        j = np.arange(i + 2, n)
        if i == 0:
            j = j[j != n - 1]
        if len(j) == 0:
            continue
        cross = _segments_cross(a[i], b[i], a[j], b[j])
        hits.extend((i, int(k)) for k in j[cross])
        if hits:
            break
    return hits


def turning_angles(ring: np.ndarray) -> np.ndarray:
    """Signed turning angle (degrees) at each vertex of a counter-clockwise ring."""
    e_in = ring - np.roll(ring, 1, axis=0)
    e_out = np.roll(ring, -1, axis=0) - ring
    cross = e_in[:, 0] * e_out[:, 1] - e_in[:, 1] * e_out[:, 0]
    dot = np.einsum("ij,ij->i", e_in, e_out)
    return np.degrees(np.arctan2(cross, dot))


def clean_ring(points: np.ndarray, source: str | None) -> tuple[np.ndarray, np.ndarray]:
    """Validate a closed ring of (x, y) points; return the kept points and the kept mask.

    Consecutive duplicates are dropped (a documented repair); any other problem raises
    :class:`InputError`.
    """
    pts = np.asarray(points, dtype=float)
    if pts.ndim != 2 or pts.shape[1] != 2:
        raise InputError("boundary must be a list of (x, y) points", source)
    if not np.all(np.isfinite(pts)):
        bad = int(np.flatnonzero(~np.isfinite(pts).all(axis=1))[0])
        raise InputError(f"boundary point {bad} is not finite (NaN or infinity)", source)
    if len(pts) < 4:
        raise InputError(f"boundary has {len(pts)} points; a four-sided domain needs at "
                         "least 4", source)
    diag = float(np.linalg.norm(pts.max(axis=0) - pts.min(axis=0)))
    if diag == 0.0:
        raise InputError("boundary points all coincide", source)
    tol = DUPLICATE_TOL * diag
    keep = np.linalg.norm(np.diff(pts, axis=0, append=pts[:1]), axis=1) > tol
    pts = pts[keep]
    if len(pts) < 4:
        raise InputError("boundary has fewer than 4 distinct points", source)
    rounded = np.round((pts - pts.min(axis=0)) / (tol * 16)).astype(np.int64)
    _, first, counts = np.unique(rounded, axis=0, return_index=True, return_counts=True)
    if np.any(counts > 1):
        k = int(first[np.argmax(counts > 1)])
        raise InputError(f"boundary point {k} is repeated further along the ring "
                         "(the boundary touches itself)", source)
    hits = self_intersections(pts)
    if hits:
        i, j = hits[0]
        raise InputError(f"boundary is self-intersecting (edges {i} and {j} cross)", source)
    if abs(signed_area(pts)) < 1e-9 * diag * diag:
        raise InputError("boundary encloses no area", source)
    return pts, keep


def detect_corners(ring: np.ndarray, source: str | None = None) -> np.ndarray:
    """Indices of the four vertices with the largest turning angle of a CCW ring."""
    turn = turning_angles(ring)
    order = np.argsort(-turn, kind="stable")
    fourth = turn[order[3]]
    fifth = turn[order[4]] if len(ring) > 4 else -180.0
    if fourth < MIN_CORNER_TURN_DEG or fifth > CORNER_MARGIN * fourth:
        top = ", ".join(f"{turn[k]:.1f}" for k in order[:5])
        raise InputError(
            f"fewer than four clear corners (largest turning angles {top} degrees); "
            "name them with four point indices (--corners)", source)
    return np.sort(order[:4])


@dataclass(frozen=True)
class Boundary:
    """A validated four-sided boundary in the working frame.

    ``ring`` is counter-clockwise and starts at corner 0 (SPEC 1); ``corners`` index it.
    """

    ring: np.ndarray
    corners: tuple[int, int, int, int]
    frame: Frame
    source: str | None = None

    @classmethod
    def from_points(cls, points: np.ndarray, corners: tuple[int, ...] | None = None,
                    source: str | None = None) -> Boundary:
        """Validate user points, find the corners and apply the side convention of SPEC 1.

        ``corners`` are indices into ``points`` as given (closing point excluded).
        """
        raw = np.asarray(points, dtype=float)
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
        ring, keep = clean_ring(raw, source)
        frame = Frame.around(ring)
        unit = frame.to_unit(ring)
        flags = marked[keep] if marked is not None else None
        if flags is not None and flags.sum() != 4:
            raise InputError("a named corner is a duplicate point", source)
        if signed_area(unit) < 0:
            unit = unit[::-1]
            flags = flags[::-1] if flags is not None else None
        idx = np.flatnonzero(flags) if flags is not None else detect_corners(unit, source)
        c = unit[idx]
        key = np.lexsort((c[:, 1], c[:, 0] + c[:, 1]))
        start = int(idx[key[0]])
        unit = np.roll(unit, -start, axis=0)
        idx = np.sort((idx - start) % len(unit))
        return cls(ring=unit, corners=tuple(int(i) for i in idx), frame=frame, source=source)

    @property
    def diagonal(self) -> float:
        """Bounding-box diagonal in the working frame."""
        return float(np.linalg.norm(self.ring.max(axis=0) - self.ring.min(axis=0)))

    def side(self, name: str) -> Polyline:
        """Side polyline oriented along increasing xi (bottom, top) or eta (left, right)."""
        c0, c1, c2, c3 = self.corners
        closed = np.vstack([self.ring, self.ring[:1]])
        if name == "bottom":
            return Polyline(closed[c0:c1 + 1])
        if name == "right":
            return Polyline(closed[c1:c2 + 1])
        if name == "top":
            return Polyline(closed[c2:c3 + 1][::-1])
        if name == "left":
            return Polyline(closed[c3:][::-1])
        raise ValueError(f"unknown side {name!r}")

    def corner_points(self) -> np.ndarray:
        """Corners 0..3 in the working frame: (0,0), (1,0), (1,1), (0,1) in (xi, eta)."""
        return self.ring[list(self.corners)]

    def deviation(self, points_unit: np.ndarray) -> np.ndarray:
        """Distance of points (working frame) from the boundary, relative to the diagonal."""
        return segment_distance(points_unit, self.ring) / self.diagonal
