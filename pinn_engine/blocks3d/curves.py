"""A blockMeshDict's edges as curves, and the node fractions of its gradings, as blockMesh
places them (SPEC 15).

- **Gradings.** An edge of n cells with sections (length share, cell share, ratio): each
  section gets its share of the cells (rounded, the largest section taking the remainder)
  and places them in geometric progression whose last cell is ``ratio`` times its first,
  over its share of the edge's parameter.
- **Curves.** ``position(t)`` for t in [0, 1]: a straight line; an arc (through a point, or
  about an origin: the circle through both ends and the point at mean radius halfway round)
  by angle; a polyLine by arc length; a spline (Catmull-Rom through the ends and its points,
  the ends' tangents by reflection) by the chord lengths of its points.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.blocks3d.dictionary import Edge

PARALLEL = 1e-12  # an arc whose three points are this close to collinear is refused


def divisions(sections: list[tuple[float, float, float]], n: int) -> np.ndarray:
    """The n + 1 node fractions (0 to 1) of an edge of ``n`` cells graded by ``sections``."""
    if n < len(sections):
        return np.linspace(0.0, 1.0, n + 1)
    shares = [s[1] for s in sections]
    cells = [int(share * n + 0.5) for share in shares]
    cells[int(np.argmax(shares))] += n - sum(cells)
    out, start = [0.0], 0.0
    for (length, _, ratio), k in zip(sections, cells):
        steps = np.arange(1, k + 1)
        if k == 0:
            continue
        if ratio == 1.0 or k == 1:
            local = steps / k
        else:
            grow = ratio ** (1.0 / (k - 1))
            local = (1.0 - grow**steps) / (1.0 - grow**k)
        out.extend(start + length * local)
        start = out[-1]
    arr = np.array(out)
    arr[-1] = 1.0
    return arr


class Curve:
    """A dictionary edge from point ``a`` to point ``b``."""

    def __init__(self, a: np.ndarray, b: np.ndarray, edge: Edge | None = None) -> None:
        self.a, self.b = np.asarray(a, float), np.asarray(b, float)
        self.kind = "line" if edge is None else edge.kind
        if self.kind in ("arc", "arc-origin"):
            self._arc(edge)
        elif self.kind in ("polyline", "spline"):
            self.knots = np.vstack([self.a, edge.points, self.b])
            chords = np.linalg.norm(np.diff(self.knots, axis=0), axis=1)
            self.params = np.concatenate([[0.0], np.cumsum(chords)]) / chords.sum()

    @property
    def straight(self) -> bool:
        return self.kind == "line"

    def _arc(self, edge: Edge) -> None:
        a, b = self.a, self.b
        if self.kind == "arc":
            m = edge.points[0]
        else:  # about an origin: the point halfway round at the ends' mean radius
            c = edge.points[0]
            ra, rb = a - c, b - c
            half = ra / np.linalg.norm(ra) + rb / np.linalg.norm(rb)
            m = c + 0.5 * (np.linalg.norm(ra) + np.linalg.norm(rb)) * half / np.linalg.norm(half)
        u, v = m - a, b - a
        normal = np.cross(u, v)
        nn = float(normal @ normal)
        if nn <= PARALLEL * float(u @ u) * float(v @ v):
            raise ValueError(f"arc from {a} to {b}: its points are on one line")
        # circumcentre of a, m, b
        centre = a + (np.cross(normal, u) * (v @ v) + np.cross(v, normal) * (u @ u)) / (2 * nn)
        self.centre = centre
        self.radius = float(np.linalg.norm(a - centre))
        e1 = (a - centre) / self.radius
        e2 = np.cross(normal / np.sqrt(nn), e1)
        self.frame = (e1, e2)
        angle = np.arctan2((b - centre) @ e2, (b - centre) @ e1)
        self.sweep = float(angle if angle > 0 else angle + 2 * np.pi)

    def position(self, t: np.ndarray) -> np.ndarray:
        """Points (len(t), 3) at parameters ``t`` in [0, 1], the ends exactly."""
        t = np.asarray(t, float)
        if self.kind == "line":
            out = self.a + t[:, None] * (self.b - self.a)
        elif self.kind in ("arc", "arc-origin"):
            e1, e2 = self.frame
            phi = self.sweep * t
            out = self.centre + self.radius * (
                np.cos(phi)[:, None] * e1 + np.sin(phi)[:, None] * e2
            )
        else:
            seg = np.clip(
                np.searchsorted(self.params, t, side="right") - 1, 0, len(self.params) - 2
            )
            local = (t - self.params[seg]) / (self.params[seg + 1] - self.params[seg])
            p0, p1 = self.knots[seg], self.knots[seg + 1]
            if self.kind == "polyline":
                out = p0 + local[:, None] * (p1 - p0)
            else:
                out = self._catmull_rom(seg, local)
        out[t <= 0.0] = self.a
        out[t >= 1.0] = self.b
        return out

    def _catmull_rom(self, seg: np.ndarray, s: np.ndarray) -> np.ndarray:
        k = self.knots
        last = len(k) - 2
        p0, p1 = k[seg], k[seg + 1]
        e0 = np.where((seg == 0)[:, None], 2 * p0 - p1, k[np.maximum(seg - 1, 0)])
        e1 = np.where((seg == last)[:, None], 2 * p1 - p0, k[np.minimum(seg + 2, last + 1)])
        s = s[:, None]
        return 0.5 * (
            2 * p0
            + s
            * ((p1 - e0) + s * ((2 * e0 - 5 * p0 + 4 * p1 - e1) + s * (3 * p0 - e0 - 3 * p1 + e1)))
        )


def curves(vertices: np.ndarray, edges: list[Edge]) -> dict[tuple[int, int], Curve]:
    """Each curved edge by its vertex pair in both directions' keys (the reversed one
    walks it backwards)."""
    out = {}
    for e in edges:
        c = Curve(vertices[e.start], vertices[e.end], e)
        out[(e.start, e.end)] = c
    return out


def edge_points(
    table: dict[tuple[int, int], Curve], vertices: np.ndarray, a: int, b: int, t: np.ndarray
) -> tuple[np.ndarray, bool]:
    """Points along the edge from vertex ``a`` to ``b`` at fractions ``t`` and whether it is
    curved."""
    if (a, b) in table:
        return table[(a, b)].position(t), True
    if (b, a) in table:
        return table[(b, a)].position(1.0 - t), True
    return Curve(vertices[a], vertices[b]).position(t), False
