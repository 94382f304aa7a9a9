"""The 3D Winslow grid over all blocks of a dictionary at once (SPEC 15's ``elliptic``).

- **Unknowns.** Every node once (``placement``'s numbering). A node inside a block, inside
  a face two blocks share, or on an edge or vertex round which the blocks' cells close as
  eight octants has a full 3 x 3 x 3 neighbourhood: across a shared face it continues into
  the next block (the blocks' index directions carry on through it), on edges and vertices
  it is glued cell by cell from the cells round the node. Those nodes move as interior
  nodes: interfaces are solved, not drawn (SPEC 10's idea in 3D).
- **Boundary.** A node on a boundary face lying in a plane x, y or z = const slides within
  the plane: its normal coordinate is held and its neighbourhood is mirrored across the
  plane (a symmetry wall, so the grid lines meet it at right angles); on two such planes it
  slides along their line. Nodes on any other boundary face (curved, or a tilted plane),
  on curved boundary edges, and nodes whose cells do not close as eight octants (where
  three or five blocks meet round an edge) keep blockMesh's placement.
- **Gradings.** The logical coordinates are not the node indices but each block
  direction's graded fractions times its mean edge length: the Winslow map is harmonic in
  those, so a graded block with straight edges (blockMesh's own grid) is an exact solution
  and the gradings hold; second derivatives are the three-point non-uniform differences.
- **Solve.** Picard steps with the coefficients (cofactors of the metric) frozen, each
  coordinate's system solved inexactly by the AMG-preconditioned Krylov solver of the
  single hexahedral block (``hexa.inexact``).
"""

from __future__ import annotations

import itertools
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from pinn_engine.blas import one_blas_thread
from pinn_engine.blocks3d.placement import HEX_FACES, Placement, face_slice
from pinn_engine.hexa.inexact import InexactSolve

TOL = 1e-6  # converged when no node moves more than this share of the diagonal in a step
MAX_ITERATIONS = 60  # Picard steps at most
PLANE_TOL = 1e-9  # a boundary face is a coordinate plane when it spreads this share of the diagonal
OFFSETS = [o for o in itertools.product((-1, 0, 1), repeat=3) if np.count_nonzero(o) < 3]
CENTRE = (1, 1, 1)


@dataclass
class Stencils:
    """Neighbourhoods ``ids`` (m, 3, 3, 3) of the nodes ``ids[:, 1, 1, 1]`` solved for, and
    their logical spacings ``h`` (m, 3, 2): along each axis to the minus and plus side."""

    ids: np.ndarray
    h: np.ndarray


@dataclass
class Star:
    """A node whose cells do not close as eight octants (three or five blocks round an
    edge): its neighbours ``around`` and the least-squares weights ``fit`` (9, m) giving
    the first and second derivatives at it (``FIT_TERMS``) from their offsets."""

    node: int
    around: np.ndarray
    fit: np.ndarray
    slope: np.ndarray


# the derivatives of a quadratic fit, in the order of its design columns
FIT_TERMS = ((0,), (1,), (2,), (0, 0), (0, 1), (0, 2), (1, 1), (1, 2), (2, 2))


def _logical(place: Placement) -> list[list[np.ndarray]]:
    """Each block direction's node coordinates: graded fractions times the mean length of
    the direction's four edges."""
    out = []
    for ids, params in zip(place.ids, place.params):
        g = place.points[ids]
        coords = []
        for axis in range(3):
            steps = np.linalg.norm(np.diff(g, axis=axis), axis=-1).sum(axis=axis)
            corners = [steps[0, 0], steps[-1, 0], steps[0, -1], steps[-1, -1]]
            coords.append(params[axis] * float(np.mean(corners)))
        out.append(coords)
    return out


def _interior(place: Placement, logical) -> list[Stencils]:
    """The 3 x 3 x 3 windows of every block's interior nodes."""
    out = []
    for ids, u in zip(place.ids, logical):
        if min(ids.shape) < 3:
            continue
        win = np.lib.stride_tricks.sliding_window_view(ids, (3, 3, 3)).reshape(-1, 3, 3, 3)
        n = [len(c) - 2 for c in u]
        h = np.empty((*n, 3, 2))
        for axis in range(3):
            d = np.diff(u[axis])
            shape = [1, 1, 1]
            shape[axis] = -1
            h[..., axis, 0] = d[:-1].reshape(shape)
            h[..., axis, 1] = d[1:].reshape(shape)
        out.append(Stencils(win, h.reshape(-1, 3, 2)))
    return out


def _inward(axis: int, end: int, depth: int = 1) -> tuple:
    return tuple(((-1 - depth) if end else depth) if a == axis else slice(None) for a in range(3))


def _faces(place: Placement, logical, across: dict) -> list[Stencils]:
    """The windows of nodes inside block faces (not on their edges), each face once: a
    shared face's ghost layer is the next block's first layer in; a boundary face's is the
    block's own (a mirror; used where the face is a coordinate plane)."""
    out = []
    for b, ids in enumerate(place.ids):
        for axis, end in HEX_FACES:
            other = across.get((b, axis, end))
            if other is not None and other[0] < b:
                continue  # taken from the other block
            others = [a for a in range(3) if a != axis]
            if any(ids.shape[a] < 3 for a in others):
                continue
            face = ids[face_slice(axis, end)]
            if other is None:
                ghost, h_out = (
                    ids[_inward(axis, end)],
                    abs(float(np.diff(logical[b][axis])[-1 if end else 0])),
                )
            else:
                c, cx, ce = other
                their = np.full(len(place.points), -1)
                their[place.ids[c][face_slice(cx, ce)].ravel()] = place.ids[c][
                    _inward(cx, ce)
                ].ravel()
                ghost = their[face]
                h_out = abs(float(np.diff(logical[c][cx])[-1 if ce else 0]))
            layers = [ids[_inward(axis, end, 1)], face, ghost]
            if not end:
                layers = layers[::-1]
            block = np.stack(layers, axis=axis)  # 3 along axis, full along the others
            win = np.lib.stride_tricks.sliding_window_view(block, (3, 3, 3)).reshape(-1, 3, 3, 3)
            u = logical[b]
            h_in = abs(float(np.diff(u[axis])[-1 if end else 0]))
            n = [ids.shape[a] - 2 for a in others]
            h = np.empty((*n, 3, 2))
            for k, a in enumerate(others):
                d = np.diff(u[a])
                shape = [1, 1]
                shape[k] = -1
                h[..., a, 0] = d[:-1].reshape(shape)
                h[..., a, 1] = d[1:].reshape(shape)
            h[..., axis, 0] = h_out if not end else h_in
            h[..., axis, 1] = h_in if not end else h_out
            out.append(Stencils(win, h.reshape(-1, 3, 2)))
    return out


def _edge_nodes(place: Placement) -> dict[int, list]:
    """Nodes on block edges and vertices: each with its incident cells as (block, cell
    index (3,), node's corner in the cell (3,))."""
    out: dict[int, list] = {}
    for b, ids in enumerate(place.ids):
        n = np.array(ids.shape) - 1
        at_end = [np.isin(np.arange(m + 1), (0, m)) for m in n]
        mask = (
            at_end[0][:, None, None].astype(int)
            + at_end[1][None, :, None]
            + at_end[2][None, None, :]
        ) >= 2
        for i, j, k in zip(*np.nonzero(mask)):
            node = int(ids[i, j, k])
            for o in itertools.product((0, 1), repeat=3):
                c = np.array((i, j, k)) - np.array(o)
                if (c >= 0).all() and (c < n).all():
                    out.setdefault(node, []).append((b, c, np.array(o)))
    return out


def _glue(
    node: int, cells: list, place: Placement, logical
) -> tuple[np.ndarray, np.ndarray] | None:
    """The 3 x 3 x 3 frame of ``node`` glued from its cells (-1 where no cell reaches), and
    the spacings; None where the cells do not fit one frame (an irregular edge)."""
    frame = np.full((3, 3, 3), -1)
    h_sum, h_n = np.zeros((3, 2)), np.zeros((3, 2))
    placed = [False] * len(cells)
    maps: list = [None] * len(cells)
    maps[0] = (np.eye(3, dtype=int), None)
    where: dict[int, np.ndarray] = {node: np.array(CENTRE)}
    progress = True
    while progress:
        progress = False
        for q, (b, c, o) in enumerate(cells):
            if placed[q]:
                continue
            ids = place.ids[b]

            def corner(off, ids=ids, c=c) -> int:
                return int(ids[tuple(c + off)])

            if q == 0:
                rot = np.eye(3, dtype=int)
            else:
                cols = {}
                for a in range(3):
                    e = o.copy()
                    e[a] = 1 - o[a]
                    nb = corner(e)
                    if nb in where:
                        cols[a] = where[nb] - 1
                if len(cols) < 2:
                    continue
                rot = np.zeros((3, 3), dtype=int)
                for a, v in cols.items():
                    rot[:, a] = v * (1 if e_sign(o, a) > 0 else -1)
                if len(cols) == 2:
                    a0, a1 = sorted(cols)
                    a2 = 3 - a0 - a1
                    third = np.cross(rot[:, (a2 + 1) % 3], rot[:, (a2 + 2) % 3])
                    rot[:, a2] = third
                if round(np.linalg.det(rot)) != 1:
                    return None
            placed[q] = True
            progress = True
            for off in itertools.product((0, 1), repeat=3):
                off = np.array(off)
                pos = 1 + rot @ (off - o)
                nb = corner(off)
                if (pos < 0).any() or (pos > 2).any():
                    return None
                if frame[tuple(pos)] not in (-1, nb) or (
                    nb in where and not np.array_equal(where[nb], pos)
                ):
                    return None
                frame[tuple(pos)] = nb
                where[nb] = pos
            u = logical[b]
            for a in range(3):
                step = abs(float(u[a][c[a] + 1] - u[a][c[a]]))
                axis = int(np.flatnonzero(rot[:, a])[0])
                side = 1 if rot[axis, a] * (1 - 2 * o[a]) > 0 else 0
                h_sum[axis, side] += step
                h_n[axis, side] += 1
    if not all(placed):
        return None
    h = np.where(h_n > 0, h_sum / np.maximum(h_n, 1), 0.0)
    return frame, h


def e_sign(o: np.ndarray, a: int) -> int:
    """The direction (+1 or -1) in which a cell's local axis ``a`` leaves its corner ``o``."""
    return 1 - 2 * int(o[a])


def _mirror(frame: np.ndarray, h: np.ndarray) -> bool:
    """Fill the missing half of a boundary node's frame by mirroring it across the frame's
    axes whose one side is empty; whether the frame is then complete."""
    for axis in range(3):
        lo = np.take(frame, 0, axis=axis)
        hi = np.take(frame, 2, axis=axis)
        if (lo < 0).all() and (hi >= 0).any():
            idx = [slice(None)] * 3
            idx[axis] = 0
            frame[tuple(idx)] = hi
            h[axis, 0] = h[axis, 1]
        elif (hi < 0).all() and (lo >= 0).any():
            idx = [slice(None)] * 3
            idx[axis] = 2
            frame[tuple(idx)] = lo
            h[axis, 1] = h[axis, 0]
    used = np.array([frame[tuple(np.add(o, 1))] for o in OFFSETS])
    return bool((used >= 0).all())


def _star(node: int, cells: list, place: Placement, logical, normal: int | None) -> Star | None:
    """The star of a node on an edge round which Q != 4 blocks meet (Knupp's irregular
    node, as ``multiblock.junctions`` in 2D): the cells' fan across the edge mapped to a
    regular Q-gon in a logical plane, the edge along the third logical axis, each cell's
    nodes at those logical offsets; a node on a boundary plane (``normal``: its axis) has
    its one layer mirrored across it. None where the cells form no such fan."""
    axes = []
    for b, c, o in cells:
        index = np.array(c) + np.array(o)
        inner = [a for a in range(3) if 0 < index[a] < place.ids[b].shape[a] - 1]
        if len(inner) == 1:
            axes.append(inner[0])
        elif not inner and normal is not None:
            ids = place.ids[b]
            step = []
            for a in range(3):
                e = np.array(o)
                e[a] = 1 - e[a]
                nb = ids[tuple(c + e)]
                step.append(abs(place.points[nb, normal] - place.points[node, normal]))
            axes.append(int(np.argmax(step)))
        else:
            return None
    layers: dict[int, list] = {}
    for (b, c, o), along in zip(cells, axes):
        ids = place.ids[b]

        def at(flip, c=c, o=o, ids=ids):
            e = np.array(o)
            for a in flip:
                e[a] = 1 - e[a]
            return int(ids[tuple(c + e)])

        plane = [a for a in range(3) if a != along]
        u = logical[b]
        lengths = [abs(float(u[a][c[a] + 1] - u[a][c[a]])) for a in range(3)]
        layers.setdefault(at([along]), []).append((at, along, plane, lengths))
    if len(layers) > 2 or (len(layers) == 1) != (normal is not None):
        return None
    # the fan: side neighbours in the edge's normal plane, chained round the node
    first = next(iter(layers.values()))
    links: dict[int, list[int]] = {}
    for at, _, plane, _ in first:
        s, t = at([plane[0]]), at([plane[1]])
        links.setdefault(s, []).append(t)
        links.setdefault(t, []).append(s)
    if any(len(v) != 2 for v in links.values()):
        return None
    ring = [next(iter(links))]
    while len(ring) < len(links):
        nxt = [v for v in links[ring[-1]] if v not in ring[-2:]]
        ring.append(nxt[0])
    q = len(ring)
    if q == 4 or links[ring[-1]].count(ring[0]) == 0:
        return None
    radius = float(
        np.mean([ln[a] for layer in layers.values() for _, _, pl, ln in layer for a in pl])
    )
    angle = 2 * np.pi * np.arange(q) / q
    side = {n: radius * np.array([np.cos(t), np.sin(t), 0.0]) for n, t in zip(ring, angle)}
    offsets: dict[int, np.ndarray] = dict(side)
    for sign, layer in zip((1.0, -1.0), layers.values()):
        height = sign * float(np.mean([ln[al] for _, al, _, ln in layer]))
        for at, along, plane, _ in layer:
            s, t = at([plane[0]]), at([plane[1]])
            if s not in side or t not in side:
                return None
            found = {
                at(plane): side[s] + side[t],
                at([along]): np.array([0.0, 0.0, height]),
                at([along, plane[0]]): side[s] + [0.0, 0.0, height],
                at([along, plane[1]]): side[t] + [0.0, 0.0, height],
                at([along, *plane]): side[s] + side[t] + [0.0, 0.0, height],
            }
            for n, pos in found.items():
                if n in offsets and not np.allclose(offsets[n], pos):
                    return None
                offsets[n] = pos
    around = np.array(list(offsets))
    logical_pos = np.array([offsets[n] for n in around])
    # the metric from the real cells alone (a mirror would make the normal derivative 0)
    slope = np.linalg.pinv(_design(logical_pos))[:3]
    if normal is not None:  # the mirror layer: the same nodes across the plane
        around = np.concatenate([around, around])
        logical_pos = np.vstack([logical_pos, logical_pos * [1.0, 1.0, -1.0]])
        slope = np.hstack([slope, np.zeros_like(slope)])
    return Star(node, around, np.linalg.pinv(_design(logical_pos)), slope)


def _design(pos: np.ndarray) -> np.ndarray:
    """The quadratic fit's design matrix at logical offsets ``pos`` (m, 3)."""
    xi, eta, zeta = pos.T
    return np.column_stack(
        [xi, eta, zeta, 0.5 * xi**2, xi * eta, xi * zeta, 0.5 * eta**2, eta * zeta, 0.5 * zeta**2]
    )


def star_row(points: np.ndarray, star: Star) -> tuple[np.ndarray, np.ndarray]:
    """A star's frozen-coefficient Winslow row: node ids (the node first) and weights,
    normalised so that the node's is -1."""
    offsets = points[star.around] - points[star.node]
    d = star.slope @ offsets
    m = d @ d.T
    c = _cofactor_terms([[m[a, b] for b in range(3)] for a in range(3)])
    w = sum(
        (1.0 if len(t) == 1 or t[0] == t[1] else 2.0) * c[t] * star.fit[k]
        for k, t in enumerate(FIT_TERMS)
        if len(t) == 2
    )
    centre = -w.sum()
    return np.concatenate([[star.node], star.around]), np.concatenate([[centre], w]) / -centre


def _cofactor_terms(m) -> dict[tuple[int, int], np.ndarray]:
    """Cofactors of the metric tensor m (3 x 3 of arrays or numbers), by (a, b), a <= b."""
    return {
        (0, 0): m[1][1] * m[2][2] - m[1][2] ** 2,
        (1, 1): m[0][0] * m[2][2] - m[0][2] ** 2,
        (2, 2): m[0][0] * m[1][1] - m[0][1] ** 2,
        (0, 1): m[0][2] * m[1][2] - m[0][1] * m[2][2],
        (0, 2): m[0][1] * m[1][2] - m[0][2] * m[1][1],
        (1, 2): m[0][1] * m[0][2] - m[0][0] * m[1][2],
    }


def stencils(place: Placement) -> tuple[Stencils, list[Star], np.ndarray]:
    """Every node's neighbourhood that can be built, and per node and coordinate whether it
    is held (the boundary's rules of the module)."""
    logical = _logical(place)
    across = {}
    faces_of = {}
    for b, _ in enumerate(place.ids):
        for axis, end in HEX_FACES:
            if (b, axis, end) in place.interfaces:
                key = frozenset(
                    place.ids[b][face_slice(axis, end)][[0, 0, -1, -1], [0, -1, 0, -1]].tolist()
                )
                faces_of.setdefault(key, []).append((b, axis, end))
    for owners in faces_of.values():
        if len(owners) == 2:
            across[owners[0]], across[owners[1]] = owners[1], owners[0]
    held = np.zeros((len(place.points), 3), dtype=bool)
    diag = float(np.linalg.norm(np.ptp(place.points, axis=0)))
    for b, ids in enumerate(place.ids):
        for axis, end in HEX_FACES:
            if (b, axis, end) in across:
                continue
            nodes = ids[face_slice(axis, end)]
            spread = np.ptp(place.points[nodes].reshape(-1, 3), axis=0)
            flat = np.flatnonzero(spread <= PLANE_TOL * diag)
            if len(flat):
                held[nodes.ravel(), flat[0]] = True
            else:
                held[nodes.ravel()] = True
    parts = _interior(place, logical) + _faces(place, logical, across)
    glued_ids, glued_h, stars = [], [], []
    for node, cells in _edge_nodes(place).items():
        if held[node].all():
            continue
        got = _glue(node, cells, place, logical)
        if got is not None and _mirror(*got) and (got[1] > 0).all():
            glued_ids.append(got[0])
            glued_h.append(got[1])
            continue
        normal = np.flatnonzero(held[node])
        star = _star(node, cells, place, logical, int(normal[0]) if len(normal) == 1 else None)
        if star is None or len(normal) > 1:
            held[node] = True
        else:
            stars.append(star)
    if glued_ids:
        parts.append(Stencils(np.array(glued_ids), np.array(glued_h)))
    ids = np.concatenate([p.ids for p in parts])
    h = np.concatenate([p.h for p in parts])
    solved = ~held[ids[:, 1, 1, 1]].all(axis=1)
    return Stencils(ids[solved], h[solved]), stars, held


def _weights(points: np.ndarray, st: Stencils) -> np.ndarray:
    """(m, 19) weights of each node's frozen-coefficient Winslow row over ``OFFSETS``,
    normalised so that the centre's is -1."""
    ids, h = st.ids, st.h
    span = h[:, :, 0] + h[:, :, 1]
    x0 = points[ids[:, 1, 1, 1]]
    d = []
    for a in range(3):
        plus, minus = [1, 1, 1], [1, 1, 1]
        plus[a], minus[a] = 2, 0
        ip, im = ids[:, plus[0], plus[1], plus[2]], ids[:, minus[0], minus[1], minus[2]]
        central = (points[ip] - points[im]) / span[:, a, None]
        # across a mirror plane the ghost is the neighbour itself: one-sided there
        one_sided = (points[ip] - x0) / h[:, a, 1, None]
        d.append(np.where((ip == im)[:, None], one_sided, central))
    c = _cofactor_terms([[np.einsum("nk,nk->n", d[a], d[b]) for b in range(3)] for a in range(3)])
    w = np.zeros((len(ids), len(OFFSETS)))
    centre = OFFSETS.index((0, 0, 0))
    for k, off in enumerate(OFFSETS):
        axes = [a for a in range(3) if off[a]]
        if len(axes) == 1:
            a = axes[0]
            side = h[:, a, 1] if off[a] > 0 else h[:, a, 0]
            w[:, k] = c[(a, a)] * 2.0 / (side * span[:, a])
            w[:, centre] -= w[:, k]
        elif len(axes) == 2:
            a, b = axes
            w[:, k] = 2.0 * off[a] * off[b] * c[(a, b)] / (span[:, a] * span[:, b])
    scale = -w[:, centre]
    return w / scale[:, None]


def _columns(st: Stencils) -> np.ndarray:
    """(m, 19) node ids of each row's entries, in ``OFFSETS``' order."""
    return np.stack([st.ids[:, 1 + o[0], 1 + o[1], 1 + o[2]] for o in OFFSETS], axis=1)


def winslow(
    place: Placement,
    max_iterations: int = MAX_ITERATIONS,
    free_interfaces: bool = True,
    progress=None,
) -> tuple[np.ndarray, int]:
    """The nodes of the Winslow grid over all blocks from blockMesh's placement, and the
    Picard steps taken. ``free_interfaces=False`` keeps every node on a block face, edge
    or vertex where blockMesh puts it (each block's interior solved)."""
    st, stars, held = stencils(place)
    points = place.points.copy()
    if not free_interfaces:
        inner = np.zeros(len(points), dtype=bool)
        for ids in place.ids:
            inner[ids[1:-1, 1:-1, 1:-1].ravel()] = True
        held[~inner] = True
    centre = st.ids[:, 1, 1, 1]
    cols = _columns(st)
    owners = np.concatenate([centre, [star.node for star in stars]]).astype(int)
    systems = []
    for comp in range(3):
        index = np.full(len(points), -1)
        free = owners[~held[owners, comp]]
        index[free] = np.arange(len(free))
        systems.append((index, len(free), InexactSolve()))
    rows = np.repeat(centre, cols.shape[1])
    diag = float(np.linalg.norm(np.ptp(points, axis=0)))
    steps = 0
    with one_blas_thread():
        for steps in range(1, max_iterations + 1):
            r, c, v = [rows], [cols.ravel()], [_weights(points, st).ravel()]
            for star in stars:
                ids, w = star_row(points, star)
                r.append(np.full(len(ids), star.node))
                c.append(ids)
                v.append(w)
            r, c, v = np.concatenate(r), np.concatenate(c), np.concatenate(v)
            moved = 0.0
            update = np.zeros_like(points)
            for comp, (index, n, solver) in enumerate(systems):
                if not n:
                    continue
                ri, ci = index[r], index[c]
                mine = ri >= 0
                residual = np.bincount(ri[mine], v[mine] * points[c[mine], comp], minlength=n)
                inside = mine & (ci >= 0)
                mat = sp.csr_matrix((-v[inside], (ri[inside], ci[inside])), shape=(n, n))
                delta = solver.solve(mat, residual[:, None])[:, 0]
                free = np.flatnonzero(index >= 0)
                update[free, comp] = delta[index[free]]
                moved = max(moved, float(np.abs(delta).max()))
            points += update
            if progress is not None:
                progress(steps, moved / diag)
            if moved <= TOL * diag:
                break
    return points, steps
