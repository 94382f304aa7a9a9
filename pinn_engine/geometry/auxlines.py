"""Auxiliary lines (paper section 3.1, SPEC 2): physical points with known (xi, eta)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import Boundary, Polyline, segment_distance, segments_cross

END_TOL = 1e-2  # an end lies on a side within this fraction of the bounding-box diagonal
# Where two auxiliary lines cross, the (xi, eta) that each gives the crossing point may differ
# by at most this much (max-norm, computational units): the SPEC 2 arc-length rule is only
# approximately consistent (the example lines differ by up to 0.15), a larger mismatch means
# lines drawn in an order the map cannot follow without folding.
CROSS_TOL = 0.25
SAMPLES_PER_LINE = 101
OPPOSITE = {"bottom": "top", "top": "bottom", "left": "right", "right": "left"}


@dataclass(frozen=True)
class RawLine:
    """A polyline as read: points (n, 2) or (n, 3) and optional per-point (xi, eta) overrides."""

    points: np.ndarray
    xi_eta: np.ndarray | None
    name: str


@dataclass(frozen=True)
class AuxLine:
    """Samples of one auxiliary line: working-frame points and their (xi, eta)."""

    name: str
    xy: np.ndarray
    xi_eta: np.ndarray
    sides: tuple[str, str] | None = None


def inside(points: np.ndarray, ring: np.ndarray) -> np.ndarray:
    """Even-odd point-in-polygon test."""
    x, y = points[:, 0:1], points[:, 1:2]
    a, b = ring, np.roll(ring, -1, axis=0)
    straddle = (a[:, 1] > y) != (b[:, 1] > y)
    with np.errstate(divide="ignore", invalid="ignore"):
        x_cross = a[:, 0] + (y - a[:, 1]) * (b[:, 0] - a[:, 0]) / (b[:, 1] - a[:, 1])
    return (straddle & (x < x_cross)).sum(axis=1) % 2 == 1


def _end_sides(p: np.ndarray, boundary: Boundary, tol: float) -> dict[str, tuple[float, float]]:
    """Sides within ``tol`` of point ``p``: side -> (arc-length fraction, distance)."""
    near = {}
    for side in ("bottom", "right", "top", "left"):
        t, d = boundary.side(side).project(p[None, :])
        if d <= tol:
            near[side] = (t, d)
    return near


def _check_inside(line: Polyline, boundary: Boundary, name: str) -> None:
    """The line between its ends must stay strictly inside the domain."""
    eps = 1e-3
    inner = Polyline(
        line.at(np.concatenate([[eps], line.t[(line.t > eps) & (line.t < 1 - eps)], [1 - eps]]))
    )
    a, b = boundary.ring, np.roll(boundary.ring, -1, axis=0)
    p, q = inner.points[:-1], inner.points[1:]
    cross = segments_cross(p[:, None], q[:, None], a[None], b[None])
    if cross.any():
        raise InputError("crosses the boundary", name)
    if not inside(inner.at(np.array([0.5])), boundary.ring)[0]:
        raise InputError("lies outside the domain", name)


def map_line(raw: RawLine, boundary: Boundary, end_tol: float = END_TOL) -> AuxLine:
    """Computational coordinates of an auxiliary line by the rule of SPEC 2."""
    pts = boundary.frame.to_unit(boundary.plane.to_plane(raw.points, raw.name))
    if raw.xi_eta is not None:
        xe = np.asarray(raw.xi_eta, dtype=float)
        if not np.all(np.isfinite(xe)) or xe.min() < 0 or xe.max() > 1:
            raise InputError("xi/eta point data must be finite and within [0, 1]", raw.name)
        return AuxLine(raw.name, pts, xe)
    step = np.linalg.norm(np.diff(pts, axis=0), axis=1)
    pts = pts[np.concatenate([[True], step > 1e-12])]
    if len(pts) < 2:
        raise InputError("has zero length", raw.name)
    tol = end_tol * boundary.diagonal
    first, last = (_end_sides(p, boundary, tol) for p in (pts[0], pts[-1]))
    pairs = [(s, OPPOSITE[s]) for s in first if OPPOSITE[s] in last]
    if not pairs:
        where = lambda ends: "/".join(ends) or "no side"  # noqa: E731
        raise InputError(
            f"does not end on two opposite sides (start near {where(first)}, end near "
            f"{where(last)}; tolerance {end_tol:g} of the diagonal)",
            raw.name,
        )
    s0, s1 = min(pairs, key=lambda p: first[p[0]][1] + last[p[1]][1])
    t0, t1 = first[s0][0], last[s1][0]
    if s0 in ("top", "right"):  # orient from bottom to top, or from left to right
        pts, (s0, s1), (t0, t1) = pts[::-1], (s1, s0), (t1, t0)
    pts = pts.copy()
    pts[0] = boundary.side(s0).at(np.array([t0]))[0]
    pts[-1] = boundary.side(s1).at(np.array([t1]))[0]
    line = Polyline(pts)
    _check_inside(line, boundary, raw.name)
    t = np.linspace(0.0, 1.0, SAMPLES_PER_LINE)
    across = t0 + t * (t1 - t0)
    xi_eta = np.column_stack([across, t] if s0 == "bottom" else [t, across])
    return AuxLine(raw.name, line.at(t), xi_eta, (s0, s1))


def _crossings(a: AuxLine, b: AuxLine) -> list[tuple[np.ndarray, np.ndarray, np.ndarray]]:
    """Points where lines ``a`` and ``b`` meet: (point, (xi, eta) by a, (xi, eta) by b)."""
    p, r = a.xy[:-1, None], np.diff(a.xy, axis=0)[:, None]
    q, s = b.xy[None, :-1], np.diff(b.xy, axis=0)[None]

    def cross(u, v):
        return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

    den, qp = cross(r, s), q - p
    scale = np.linalg.norm(r, axis=-1) * np.linalg.norm(s, axis=-1)
    parallel = np.abs(den) <= 1e-12 * scale
    with np.errstate(divide="ignore", invalid="ignore"):
        u = np.where(parallel, 0.0, cross(qp, s) / den)
        v = np.where(parallel, 0.0, cross(qp, r) / den)
    hit = ~parallel & (u >= 0) & (u <= 1) & (v >= 0) & (v <= 1)
    if np.any(parallel):  # collinear overlaps: use a's segment start projected onto b
        on = parallel & (np.abs(cross(qp, r)) <= 1e-12 * np.maximum(scale, 1e-300))
        with np.errstate(divide="ignore", invalid="ignore"):
            v_par = np.einsum("ijk,ijk->ij", p - q, np.broadcast_to(s, qp.shape)) / np.maximum(
                np.einsum(
                    "ijk,ijk->ij", np.broadcast_to(s, qp.shape), np.broadcast_to(s, qp.shape)
                ),
                1e-300,
            )
        on &= (v_par >= 0) & (v_par <= 1)
        v = np.where(on, v_par, v)
        hit |= on
    out = []
    for i, j in zip(*np.nonzero(hit)):
        ui, vj = float(u[i, j]), float(v[i, j])
        point = a.xy[i] + ui * (a.xy[i + 1] - a.xy[i])
        xa = a.xi_eta[i] + ui * (a.xi_eta[i + 1] - a.xi_eta[i])
        xb = b.xi_eta[j] + vj * (b.xi_eta[j + 1] - b.xi_eta[j])
        out.append((point, xa, xb))
    return out


def check_crossings(lines: list[AuxLine], boundary: Boundary, tol: float = CROSS_TOL) -> None:
    """Refuse two lines that cross where they disagree about the crossing's (xi, eta).

    Every crossing point of two auxiliary lines gets a computational position from each line;
    if the two differ by more than ``tol`` (e.g. two bottom-to-top lines in one order at the
    bottom and the other order at the top that cross far from where their computational
    images cross, or a bottom-top and a left-right line that cross more than once), no
    unfolded map can honour both lines, and :class:`InputError` names both.
    """
    for k, a in enumerate(lines):
        lo_a, hi_a = a.xy.min(axis=0), a.xy.max(axis=0)
        for b in lines[k + 1 :]:
            if np.any(b.xy.min(axis=0) > hi_a) or np.any(b.xy.max(axis=0) < lo_a):
                continue
            for point, xa, xb in _crossings(a, b):
                if np.abs(xa - xb).max() > tol:
                    user = boundary.frame.to_user(point)
                    raise InputError(
                        f"auxiliary lines {a.name!r} and {b.name!r} cross inconsistently: at "
                        f"({user[0]:.6g}, {user[1]:.6g}) the first gives (xi, eta) = "
                        f"({xa[0]:.3f}, {xa[1]:.3f}) and the second ({xb[0]:.3f}, "
                        f"{xb[1]:.3f}), more than {tol:g} apart; redraw or drop one of them"
                    )


def map_lines(raws: list[RawLine], boundary: Boundary, end_tol: float = END_TOL) -> list[AuxLine]:
    """Map every auxiliary line and check that they cross consistently.

    Raises :class:`InputError` naming the first bad line, or both lines of a bad crossing.
    """
    lines = [map_line(r, boundary, end_tol) for r in raws]
    check_crossings(lines, boundary)
    return lines


def line_distances(grid: np.ndarray, lines: list[AuxLine], diagonal: float) -> dict[str, float]:
    """How far the grid follows each auxiliary line: the largest distance from the drawn line
    of the grid's curve through the line's (xi, eta) (bilinear in the grid's cells), relative
    to the boundary's diagonal. ``grid`` (nj, ni, 2) and the lines share one frame."""
    return {
        line.name: float(
            segment_distance(bilinear(grid, line.xi_eta), line.xy, closed=False).max() / diagonal
        )
        for line in lines
    }


def bilinear(grid: np.ndarray, xi_eta: np.ndarray) -> np.ndarray:
    """The points (m, 2) of ``grid`` (nj, ni, 2), bilinear in its cells, at ``xi_eta`` (m, 2)
    in the unit square (its nodes uniform in xi and eta)."""
    nj, ni = grid.shape[:2]
    u = np.clip(xi_eta[:, 0], 0.0, 1.0) * (ni - 1)
    v = np.clip(xi_eta[:, 1], 0.0, 1.0) * (nj - 1)
    i = np.minimum(u.astype(int), ni - 2)
    j = np.minimum(v.astype(int), nj - 2)
    a, b = (u - i)[:, None], (v - j)[:, None]
    low = (1 - a) * grid[j, i] + a * grid[j, i + 1]
    high = (1 - a) * grid[j + 1, i] + a * grid[j + 1, i + 1]
    return (1 - b) * low + b * high


def crossing_nodes(shape: tuple[int, ...], line: AuxLine) -> np.ndarray:
    """Where the grid lines of the other family cross ``line`` (rows for a line from bottom
    to top, columns for one from left to right): for each interior one its node nearest the
    line's (xi, eta) with the nodes before and after it, as flat indices (3, n) into a grid of
    ``shape`` (nj, ni, ...) reshaped to (nj ni, ...)."""
    nj, ni = shape[:2]
    vertical = line.sides is None or line.sides[0] == "bottom"
    count, along = (nj, ni) if vertical else (ni, nj)
    across = line.xi_eta[:, 0] if vertical else line.xi_eta[:, 1]
    param = line.xi_eta[:, 1] if vertical else line.xi_eta[:, 0]
    k = np.arange(1, count - 1)
    order = np.argsort(param)
    at = np.interp(k / (count - 1), param[order], across[order]) * (along - 1)
    node = np.clip(np.rint(at).astype(int), 1, along - 2)
    nodes = np.stack([node - 1, node, node + 1])
    return k * ni + nodes if vertical else nodes * ni + k


def crossing_turns(grid: np.ndarray, lines: list[AuxLine]) -> dict[str, float]:
    """How smoothly the grid lines cross each auxiliary line: the mean, over the grid lines of
    the other family (:func:`crossing_nodes`), of the angle in degrees by which each turns at
    its node nearest the line's (xi, eta). A grid line that does not bend there turns 0; a
    split-block grid whose interface is the line kinks there. ``grid`` (nj, ni, 2)."""
    flat = grid.reshape(-1, 2)
    turns = {}
    for line in lines:
        before, at, after = flat[crossing_nodes(grid.shape, line)]
        a, b = at - before, after - at
        cos = (a * b).sum(-1) / (np.linalg.norm(a, axis=-1) * np.linalg.norm(b, axis=-1))
        turns[line.name] = float(np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))).mean())
    return turns
