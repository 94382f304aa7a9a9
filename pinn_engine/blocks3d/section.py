"""The least non-orthogonal grid of an extruded blocking (a section swept along an axis: a
straight pipe, a duct's bend, the DFG channel), under blockMesh's skewness (SPEC 15).

- **The section.** Where every block has one direction along a coordinate axis in which
  its nodes keep their two other coordinates (blockMesh's placement), the grid is a 2D
  section swept along that axis: every cell is a prism of a section quadrilateral, so its
  centre is the quadrilateral's area centroid and a side face's centre its edge's
  midpoint, and checkMesh's figures of the 3D grid are those of the section (faces
  between layers have no non-orthogonality or skewness).
- **The objective.** The section's free nodes (those the 3D rules free: inside the
  domain, or sliding on a coordinate plane) minimise a soft maximum of the faces'
  non-orthogonality (``SOFTNESS``) plus a quadratic penalty on every face's skewness over
  a bound (``PENALTY``): the grid with the least largest non-orthogonality whose every face
  is no more skewed than the bound (blockMesh's largest, so that neither figure is worse).
  Curved and tilted boundary nodes keep blockMesh's placement. A step that would fold a
  cell (a corner turning the wrong way) is refused by the line search.
- **The solve.** L-BFGS (``MEMORY`` pairs) from the grid given, with a backtracking line
  search, in NumPy: the section is small (hundreds to a few thousand cells), so SciPy's
  optimiser would cost more to import than to run.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pinn_engine.blocks3d import checks
from pinn_engine.blocks3d.placement import Placement, _merged
from pinn_engine.geometry.faces import topology

# a block direction is along an axis when its nodes keep their other two coordinates to
# this share of the domain's diagonal (blockMesh's placement of a swept section: round-off)
SWEPT = 1e-9
# the soft maximum's sharpness (per degree): log(faces) / SOFTNESS degrees above the largest
# angle at most, while faces a few degrees under it barely count
SOFTNESS = 1.0
# the penalty on a face's skewness over the bound, per unit squared, in degrees of the soft
# maximum: 0.01 over it costs as much as a degree, so the solve stays under the bound
PENALTY = 1e4
# the bound the solve aims at, this share under blockMesh's largest skewness, so that the
# penalty's last small excess still leaves the grid no more skewed than blockMesh's
MARGIN = 0.995
# a face whose share of the soft maximum is under this adds nothing the solve can see (its
# angle 28 degrees or more under the largest)
FAINT = 1e-12
MEMORY = 10  # L-BFGS pairs kept: the curvature of a few hundred coupled nodes
# of the objective at most, every trial step counted: at 80 the searches of the pipe and
# DFG variants still gained at their last steps, so that a start moved by the Winslow
# solve's tolerance changed their largest angle by up to 4 degrees (docs/blockmesh.md)
EVALUATIONS = 120
# the search stops once its best grid has gained less than STALL degrees (checkMesh's
# printed precision) in PATIENCE steps: 10 stopped DFG 3D's ring grading 1 on a plateau at
# 6.6 degrees that it leaves for 2.3
STALL = 0.01
PATIENCE = 20
FIRST = 0.01  # a first step's largest move, a share of the median edge: no fold to back off
BACKTRACKS = 8  # halvings of a step before the memory is dropped
ARMIJO = 1e-4  # the share of the slope's predicted fall a step must achieve
# a quadrilateral's next and previous corners counter-clockwise: np.roll's rows, without
# its cost per call (the section's evaluations are many and small)
NEXT, PREVIOUS = [1, 2, 3, 0], [3, 0, 1, 2]


@dataclass
class Section:
    """An extruded grid's section: the sweep ``axis`` and the two others (``plane``), each
    node's section node (``column``), the section nodes' 3D ids (``nodes``), the section's
    quadrilaterals counter-clockwise (``quads``, section numbering), interior edges
    (``inner``: p, q, owner, neighbour, p -> q counter-clockwise in the owner) and boundary
    edges (``outer``: p, q, owner), the free coordinates (``free``, section nodes x 2), and
    the blocks whose first layer gave the quadrilaterals (``blocks``) with each one's
    direction along the axis (``directions``)."""

    axis: int
    plane: list[int]
    column: np.ndarray
    nodes: np.ndarray
    quads: np.ndarray
    inner: np.ndarray
    outer: np.ndarray
    free: np.ndarray
    blocks: list[int]
    directions: list[int]


def sweep_axis(place: Placement) -> tuple[int, list[int]] | None:
    """The first axis every block is swept along and each block's direction along it, or
    None where the placement is no swept section."""
    diag = float(np.linalg.norm(np.ptp(place.points, axis=0)))
    # per block, per direction: the coordinates its nodes keep along it
    kept = [
        [np.ptp(place.points[ids], axis=k).max(axis=(0, 1)) <= SWEPT * diag for k in range(3)]
        for ids in place.ids
    ]
    for axis in range(3):
        others = [a for a in range(3) if a != axis]
        # along the direction the other two coordinates kept, across it the axis's (each
        # layer a plane normal to the axis, so that every cell is a prism)
        directions = [
            next(
                (
                    k
                    for k in range(3)
                    if b[k][others].all() and all(b[j][axis] for j in range(3) if j != k)
                ),
                None,
            )
            for b in kept
        ]
        if None not in directions:
            return axis, directions
    return None


def section(place: Placement, held: np.ndarray) -> Section | None:
    """The section of a swept placement (``held``: per node and coordinate whether the 3D
    rules hold it), or None where it is not swept."""
    swept = sweep_axis(place)
    if swept is None:
        return None
    axis, directions = swept
    plane = [a for a in range(3) if a != axis]
    pairs = [
        np.stack([ids.ravel(), np.broadcast_to(np.take(ids, [0], axis=k), ids.shape).ravel()], 1)
        for ids, k in zip(place.ids, directions)
    ]
    group = _merged(len(place.points), np.vstack(pairs))
    nodes = np.full(group.max() + 1, -1)
    nodes[group] = np.arange(len(place.points))
    quads, seen, blocks = [], set(), []
    for b, (ids, k) in enumerate(zip(place.ids, directions)):
        layer = group[np.take(ids, 0, axis=k)]
        key = (*np.sort(layer[[0, 0, -1, -1], [0, -1, 0, -1]]).tolist(), *layer.shape)
        if key in seen:  # a block further along the axis: the same quadrilaterals
            continue
        seen.add(key)
        blocks.append(b)
        q = np.stack([layer[:-1, :-1], layer[1:, :-1], layer[1:, 1:], layer[:-1, 1:]], -1)
        q = q.reshape(-1, 4)
        xy = place.points[nodes[q]][..., plane]
        if _areas(xy).sum() < 0:
            q = q[:, ::-1]
        quads.append(q)
    quads = np.vstack(quads)
    inner, outer = _edges(quads)
    free = np.ones((len(nodes), 2), dtype=bool)
    for c, a in enumerate(plane):
        np.logical_and.at(free[:, c], group, ~held[:, a])
    kept = [directions[b] for b in blocks]
    return Section(axis, plane, group, nodes, quads, inner, outer, free, blocks, kept)


def slab(place: Placement, sec: Section) -> Placement:
    """The section as a placement one cell thick along the axis (each block of ``blocks``
    cut to its first cell along it; node s and s + section nodes: the section node s at
    either face), its thickness the first block's first cell. Its Winslow grid is
    the swept grid's: a swept grid has no derivative along the axis, so the 3D equations
    over every layer are the section's, the same at each (``thin`` takes it back)."""
    n = len(sec.nodes)
    points = np.repeat(place.points[sec.nodes][None], 2, axis=0)
    ids, params, rises = [], [], []
    for b, k in zip(sec.blocks, sec.directions):
        first, second = np.moveaxis(place.ids[b], k, 0)[:2]  # its first layers along the axis
        rises.append(place.points[second.flat[0], sec.axis] - place.points[first.flat[0], sec.axis])
        layer = sec.column[first]
        ids.append(np.stack([layer, layer + n] if rises[-1] > 0 else [layer + n, layer], axis=k))
        params.append(
            [np.array([0.0, 1.0]) if a == k else u for a, u in enumerate(place.params[b])]
        )
    points[:, :, sec.axis] = [[0.0], [abs(rises[0])]]
    return Placement(points.reshape(-1, 3), ids, params, [], _shared_faces(ids))


class SlabFigures:
    """checkMesh's figures of grids swept from ``sec`` (every node its column's section
    node's ``plane`` coordinates), each column ``layers`` cells, measured on the slab: the
    largest non-orthogonality and skewness are the slab's (faces between layers are neither
    non-orthogonal nor skewed, end faces not skewed), the mean cosine counts each side face
    ``layers`` times and each face between layers (cosine 1), and a folded quadrilateral
    folds its column's ``layers`` cells (a folded grid's other figures are the slab's: the
    choice refuses it whatever they are)."""

    def __init__(self, place: Placement, sec: Section, layers: int) -> None:
        self.sec, self.layers, self.slab = sec, layers, slab(place, sec)
        self.cells = np.vstack([checks.hexes(ids) for ids in self.slab.ids])
        self.faces = topology(self.cells)

    def __call__(self, points: np.ndarray) -> checks.Figures:
        n, plane = len(self.sec.nodes), self.sec.plane
        at = self.slab.points.copy()
        at[:n, plane] = at[n:, plane] = points[self.sec.nodes][:, plane]
        f = checks.figures(at, self.cells, self.faces)
        side = len(self.faces.neighbour) * self.layers
        between = len(self.cells) * (self.layers - 1)
        cos = (side * np.cos(np.radians(f.mean_non_orthogonality)) + between) / (side + between)
        mean = float(np.degrees(np.arccos(min(cos, 1.0))))
        return checks.Figures(f.max_non_orthogonality, mean, f.max_skewness, self.layers * f.folded)


def thin(points: np.ndarray, sec: Section) -> np.ndarray:
    """The section's nodes (section nodes x 2) of a grid of :func:`slab`: its two faces'
    mean."""
    n = len(sec.nodes)
    return 0.5 * (points[:n, sec.plane] + points[n:, sec.plane])


def _shared_faces(ids: list[np.ndarray]) -> set[tuple[int, int, int]]:
    """The (block, axis, end) faces whose four corners another block's face has too."""
    owners: dict[frozenset, list[tuple[int, int, int]]] = {}
    for b, g in enumerate(ids):
        for axis in range(3):
            for end in (0, 1):
                face = np.take(g, -end, axis=axis)
                key = frozenset(face[[0, 0, -1, -1], [0, -1, 0, -1]].tolist())
                owners.setdefault(key, []).append((b, axis, end))
    return {f for faces in owners.values() if len(faces) == 2 for f in faces}


def _areas(xy: np.ndarray) -> np.ndarray:
    """Signed areas of quadrilaterals (m, 4, 2)."""
    x, y = xy[..., 0], xy[..., 1]
    return 0.5 * (x * np.roll(y, -1, axis=1) - np.roll(x, -1, axis=1) * y).sum(axis=1)


def _edges(quads: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Interior edges (p, q, owner, neighbour) and boundary edges (p, q, owner) of
    counter-clockwise quadrilaterals, p -> q counter-clockwise in the owner."""
    p = quads.ravel()
    q = np.roll(quads, -1, axis=1).ravel()
    cell = np.repeat(np.arange(len(quads)), 4)
    key = np.minimum(p, q) * (quads.max() + 1) + np.maximum(p, q)
    order = np.argsort(key, kind="stable")
    key, p, q, cell = key[order], p[order], q[order], cell[order]
    twin = np.flatnonzero(key[1:] == key[:-1])
    first = np.zeros(len(key), dtype=bool)
    first[twin] = True
    paired = first.copy()
    paired[twin + 1] = True
    inner = np.stack([p[twin], q[twin], cell[twin], cell[twin + 1]], axis=1)
    outer = np.stack([p[~paired], q[~paired], cell[~paired]], axis=1)
    return inner, outer


def _rot(v: np.ndarray) -> np.ndarray:
    """Each vector (m, 2) turned a quarter clockwise: an edge's outward normal."""
    return np.stack([v[:, 1], -v[:, 0]], axis=1)


def _unrot(g: np.ndarray) -> np.ndarray:
    """The gradient with respect to v of a function of ``_rot(v)`` (``g``: with respect to
    the turned vector)."""
    return np.stack([-g[:, 1], g[:, 0]], axis=1)


def _dot(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Each row's dot product (m, 2)."""
    return a[:, 0] * b[:, 0] + a[:, 1] * b[:, 1]


def _unit_back(g: np.ndarray, u: np.ndarray, length: np.ndarray) -> np.ndarray:
    """The gradient with respect to v of a function of u = v / |v|."""
    return (g - _dot(g, u)[:, None] * u) / length[:, None]


def figures(xy: np.ndarray, sec: Section) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Each interior face's non-orthogonality (degrees), each face's skewness (interior,
    then boundary) and each quadrilateral's smallest corner cross product (a fold where
    it is not positive), as checkMesh gives them on the swept grid."""
    parts = _forward(xy, sec)
    return parts["angle"], np.concatenate([parts["skew"], parts["bskew"]]), parts["turn"]


def _forward(xy: np.ndarray, sec: Section) -> dict:
    # each quadrilateral's corners (4, m) and the next corners, counter-clockwise
    x, y = xy[sec.quads.T, 0], xy[sec.quads.T, 1]
    x1, y1 = x[NEXT], y[NEXT]
    w = x * y1 - x1 * y
    area = 0.5 * w.sum(axis=0)
    moment = np.stack([((x + x1) * w).sum(axis=0), ((y + y1) * w).sum(axis=0)], axis=1)
    centre = moment / (6 * area[:, None])
    x0, y0 = x[PREVIOUS], y[PREVIOUS]
    turn = ((x - x0) * (y1 - y) - (y - y0) * (x1 - x)).min(axis=0)
    p, q, a, b = sec.inner.T
    # np.take: several times faster than [ids] on these (m, 2) rows
    xp, xq, ca = np.take(xy, p, axis=0), np.take(xy, q, axis=0), np.take(centre, a, axis=0)
    e = xq - xp
    n = _rot(e)
    length = _length(e)
    d = np.take(centre, b, axis=0) - ca
    dist = _length(d)
    nd = _dot(n, d)
    cos = nd / (length * dist)
    angle = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    u = e / length[:, None]
    cpf = 0.5 * (xp + xq) - ca
    alpha, beta, gamma = _dot(u, cpf), _dot(n, cpf), _dot(u, d)
    r = alpha - beta * gamma / nd
    wide = 0.2 * dist >= 0.5 * length
    reach = np.where(wide, 0.2 * dist, 0.5 * length)
    skew = np.abs(r) / reach
    bp, bq, ba = sec.outer.T
    bxp, bxq = np.take(xy, bp, axis=0), np.take(xy, bq, axis=0)
    be = bxq - bxp
    blength = _length(be)
    bu = be / blength[:, None]
    bcpf = 0.5 * (bxp + bxq) - np.take(centre, ba, axis=0)
    along = _dot(bu, bcpf)
    normal = _dot(_rot(bu), bcpf)
    bwide = 0.4 * np.abs(normal) >= 0.5 * blength
    breach = np.where(bwide, 0.4 * np.abs(normal), 0.5 * blength)
    bskew = np.abs(along) / breach
    return locals()


def objective(xy: np.ndarray, sec: Section, bound: float) -> tuple[float, np.ndarray, float, float]:
    """The soft maximum of the non-orthogonality plus the skewness penalty over ``bound``,
    its gradient (section nodes x 2), the largest angle and skewness; inf where a cell
    folds."""
    f = _forward(xy, sec)
    if f["turn"].min() <= 0 or not np.isfinite(f["angle"]).all():
        return np.inf, np.zeros_like(xy), np.inf, np.inf
    angle = f["angle"]
    top = angle.max()
    weight = np.exp(SOFTNESS * (angle - top))
    total = weight.sum()
    over = np.maximum(f["skew"] - bound, 0.0)
    bover = np.maximum(f["bskew"] - bound, 0.0)
    value = top + np.log(total) / SOFTNESS + PENALTY * (over @ over + bover @ bover)
    # the gradient over the faces that count: near the largest angle or over the bound (a
    # slice where every face counts, as under a largest angle below 28 degrees: no copies)
    counts = (weight > FAINT * total) | (over > 0)
    live = slice(None) if counts.all() else np.flatnonzero(counts)
    n, d, length, dist, cos, r, reach, nd, beta, gamma, u, cpf, wide = (
        f[k][live]
        for k in ("n", "d", "length", "dist", "cos", "r", "reach", "nd", "beta", "gamma")
        + ("u", "cpf", "wide")
    )
    # the angles' part: d angle / d cos, each face's share of the soft maximum
    sin = np.sqrt(np.maximum(1.0 - np.clip(cos, -1.0, 1.0) ** 2, 1e-24))
    g_cos = -(weight[live] / total) * np.degrees(1.0) / sin
    g_d = g_cos[:, None] * (n / (length * dist)[:, None] - (cos / dist**2)[:, None] * d)
    g_n = g_cos[:, None] * (d / (length * dist)[:, None] - (cos / length**2)[:, None] * n)
    # the skewness's part, |r| / reach, on the faces over the bound (zero on the others)
    sk = np.flatnonzero(over[live] > 0)
    g_cpf = np.zeros_like(n)
    g_e = _unrot(g_n)
    if len(sk):
        n, d, length, dist, r, reach, nd, beta, gamma, u, cpf, wide = (
            v[sk] for v in (n, d, length, dist, r, reach, nd, beta, gamma, u, cpf, wide)
        )
        g_s = 2 * PENALTY * over[live][sk]
        g_r = g_s * np.sign(r) / reach
        g_reach = -g_s * np.abs(r) / reach**2
        g_cpf[sk] = g_r[:, None] * (u - (gamma / nd)[:, None] * n)
        g_d[sk] += g_r[:, None] * (-(beta / nd)[:, None] * u + (beta * gamma / nd**2)[:, None] * n)
        g_u = g_r[:, None] * (cpf - (beta / nd)[:, None] * d)
        turned = g_r[:, None] * (-(gamma / nd)[:, None] * cpf + (beta * gamma / nd**2)[:, None] * d)
        g_d[sk] += np.where(wide, g_reach * 0.2 / dist, 0.0)[:, None] * d
        g_e[sk] = _unrot(g_n[sk] + turned) + _unit_back(g_u, u, length)
        g_e[sk] += np.where(wide, 0.0, g_reach * 0.5)[:, None] * u
    grad = np.zeros_like(xy)
    g_centre = np.zeros((len(sec.quads), 2))
    p, q, a, b = sec.inner[live].T
    _add(grad, q, (g_e + 0.5 * g_cpf).T)
    _add(grad, p, (-g_e + 0.5 * g_cpf).T)
    _add(g_centre, b, g_d.T)
    _add(g_centre, a, (-g_d - g_cpf).T)
    # the boundary faces' skewness: |along| / breach
    blive = np.flatnonzero(bover > 0)
    g_b = 2 * PENALTY * bover[blive]
    along, normal, breach, bwide, bu, bcpf, blength = (
        f[k][blive] for k in ("along", "normal", "breach", "bwide", "bu", "bcpf", "blength")
    )
    g_along = g_b * np.sign(along) / breach
    g_breach = -g_b * np.abs(along) / breach**2
    g_normal = np.where(bwide, g_breach * 0.4 * np.sign(normal), 0.0)
    g_bcpf = g_along[:, None] * bu + g_normal[:, None] * _rot(bu)
    g_bu = g_along[:, None] * bcpf + _unrot(g_normal[:, None] * bcpf)
    g_be = _unit_back(g_bu, bu, blength) + np.where(bwide, 0.0, g_breach * 0.5)[:, None] * bu
    bp, bq, ba = sec.outer[blive].T
    _add(grad, bq, (g_be + 0.5 * g_bcpf).T)
    _add(grad, bp, (-g_be + 0.5 * g_bcpf).T)
    _add(g_centre, ba, -g_bcpf.T)
    # the centroids: moment / (6 area), through each corner's share of the moment and area
    x, y, x1, y1, w, area, centre = (f[k] for k in ("x", "y", "x1", "y1", "w", "area", "centre"))
    g_mx, g_my = (g_centre / (6 * area)[:, None]).T
    g_area = -_dot(g_centre, centre) / area
    g_w = g_mx * (x + x1) + g_my * (y + y1) + 0.5 * g_area
    g_x = g_mx * w + g_w * y1 + (g_mx * w - g_w * y)[PREVIOUS]
    g_y = g_my * w - g_w * x1 + (g_my * w + g_w * x)[PREVIOUS]
    _add(grad, sec.quads.T.ravel(), (g_x.ravel(), g_y.ravel()))
    skew = max(f["skew"].max(initial=0.0), f["bskew"].max(initial=0.0))
    return float(value), grad, float(top), float(skew)


def _add(out: np.ndarray, at: np.ndarray, columns: np.ndarray | tuple[np.ndarray, ...]) -> None:
    """``out[at, c] += columns[c]`` with repeated indices summed (a bincount per coordinate;
    ``columns``: a sequence of 1-D arrays, or a 2-D array's transpose)."""
    for c, column in enumerate(columns):
        out[:, c] += np.bincount(at, weights=column, minlength=len(out))


def _length(v: np.ndarray) -> np.ndarray:
    """Each row's length (m, 2): ``np.linalg.norm(v, axis=1)``'s sums, without its reduction
    along rows of two (several times slower)."""
    return np.sqrt(v[:, 0] * v[:, 0] + v[:, 1] * v[:, 1])


def least_non_orthogonal(xy: np.ndarray, sec: Section, bound: float) -> np.ndarray:
    """The section's nodes (section nodes x 2) from ``xy`` by L-BFGS on :func:`objective`
    (the skewness bound ``MARGIN`` under ``bound``) over the free coordinates: of the grids
    met, the least non-orthogonal with no face more skewed than ``bound`` (``xy`` itself
    where none is less), the search stopped once that grid has gained less than ``STALL``
    degrees in ``PATIENCE`` steps or after ``EVALUATIONS``."""
    free = sec.free
    x = xy[free]
    target = MARGIN * bound

    def evaluate(values: np.ndarray) -> tuple[float, np.ndarray, float, float]:
        full = xy.copy()
        full[free] = values
        value, grad, largest, skew = objective(full, sec, target)
        return value, grad[free], largest, skew

    value, grad, best, _ = evaluate(x)
    if not np.isfinite(value):
        return xy
    kept, since, spent = x, 0, 1
    edge = float(np.median(np.linalg.norm(xy[sec.inner[:, 1]] - xy[sec.inner[:, 0]], axis=1)))
    steps: list[tuple[np.ndarray, np.ndarray]] = []
    while spent < EVALUATIONS and since < PATIENCE:
        direction = -_two_loop(grad, steps)
        slope = float(direction @ grad)
        if slope >= 0:
            direction, slope, steps = -grad, -float(grad @ grad), []
        # a first step (or one after a reset) moves no node more than FIRST of an edge
        t = 1.0 if steps else FIRST * edge / max(float(np.abs(direction).max()), 1e-300)
        for _ in range(BACKTRACKS):
            trial, trial_grad, largest, skew = evaluate(x + t * direction)
            spent += 1
            if skew <= bound and largest < best:  # the best grid met, as checkMesh judges
                since = -1 if largest < best - STALL else since
                kept, best = x + t * direction, largest
            if trial <= value + ARMIJO * t * slope:
                break
            t *= 0.5
        else:
            if not steps:
                break  # no fall even along the gradient
            steps = []
            continue
        s, y = t * direction, trial_grad - grad
        if s @ y > 0:
            steps.append((s, y))
            steps = steps[-MEMORY:]
        x, value, grad, since = x + s, trial, trial_grad, since + 1
    out = xy.copy()
    out[free] = kept
    return out


def _two_loop(grad: np.ndarray, steps: list[tuple[np.ndarray, np.ndarray]]) -> np.ndarray:
    """L-BFGS's product of the inverse Hessian estimate with ``grad``."""
    q = grad.copy()
    alphas = []
    for s, y in reversed(steps):
        rho = 1.0 / (y @ s)
        alpha = rho * (s @ q)
        q -= alpha * y
        alphas.append((rho, alpha, s, y))
    if steps:
        s, y = steps[-1]
        q *= (s @ y) / (y @ y)
    for rho, alpha, s, y in reversed(alphas):
        q += (alpha - rho * (y @ q)) * s
    return q


def swept(points: np.ndarray, sec: Section, xy: np.ndarray) -> np.ndarray:
    """The 3D nodes with every column's in-plane coordinates the section node's ``xy``."""
    out = points.copy()
    out[:, sec.plane] = xy[sec.column]
    return out


def start_of(points: np.ndarray, sec: Section) -> np.ndarray:
    """The section's nodes (section nodes x 2) of a 3D grid: each column's mean in-plane
    coordinates (a solved grid's layers agree to the solve's tolerance)."""
    total = np.zeros((len(sec.nodes), 2))
    _add(total, sec.column, points[:, sec.plane].T)
    count = np.bincount(sec.column, minlength=len(sec.nodes))
    return total / count[:, None]
