"""The 3D Winslow grid over all blocks of a dictionary at once (SPEC 15's ``elliptic``).

- **Unknowns.** Every node once (``placement``'s numbering; a slab's back face, the
  mirror image of its front, moves with it and is not solved for). A node inside a block,
  inside a face two blocks share, or on an edge or vertex round which the blocks' cells
  close as eight octants has a full 3 x 3 x 3 neighbourhood: across a shared face it
  continues into the next block (the blocks' index directions carry on through it), on
  edges and vertices it is glued cell by cell from the cells round the node. Those nodes
  move as interior nodes: interfaces are solved, not drawn (SPEC 10's idea in 3D).
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
  coordinate's system solved inexactly by the Krylov solver of the single hexahedral block
  (``hexa.inexact``), preconditioned by a plain-aggregation multigrid: the steps' count is
  set by the Picard iteration, not the inner solves, so the cheapest hierarchy to build
  that meets the forcing wins. A slab's face, a 2D system, is preconditioned by its sparse
  LU instead. Coordinates free at the same nodes share their matrix and its
  preconditioner; a coordinate whose equations hold to round-off is not solved for.
"""

from __future__ import annotations

import functools
import itertools
from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

from pinn_engine.blas import one_thread
from pinn_engine.blocks3d.placement import HEX_FACES, Placement, face_slice
from pinn_engine.hexa.inexact import InexactSolve, direct, gmres, plain_aggregation
from pinn_engine.hexa.volume import cofactor_terms

# converged when no node moves more than this share of the diagonal in a step: on every
# solved dictionary of docs/blockmesh.md checkMesh's largest non-orthogonality is then
# within 0.02 degrees of the grid's at 1e-5 and its skewness within 0.002, the grid kept
# the same, in 1 to 5 Picard steps fewer
TOL = 1e-4
MAX_ITERATIONS = 60  # Picard steps at most
# each update's defect cut to this share by the plain-aggregation multigrid: its weaker
# V-cycles at the single block's 0.3 left the Picard steps stalling near 1e-4 of the diagonal
# (DFG 3D: 10 steps, 8 at 0.1; 0.05 takes as many steps with more V-cycles)
FORCING = 0.1
# a coordinate whose residuals are all below this share of the diagonal solves its equations
# already and is not solved for (a graded box's grid; the axial coordinate of an extruded
# blocking, straight in its logical coordinate: its residuals are round-off, 1e-16)
SOLVED = 1e-12
PLANE_TOL = 1e-9  # a boundary face is a coordinate plane when it spreads this share of the diagonal
OFFSETS = [o for o in itertools.product((-1, 0, 1), repeat=3) if np.count_nonzero(o) < 3]
CENTRE = (1, 1, 1)
# OFFSETS as places in a 3 x 3 x 3 frame flattened (i slowest)
FRAME_STENCIL = [9 * (i + 1) + 3 * (j + 1) + (k + 1) for i, j, k in OFFSETS]
# a flattened frame's first and last layer along each axis, in the same order
FRAME_SIDES = [
    tuple(
        [
            9 * p[0] + 3 * p[1] + p[2]
            for p in itertools.product(range(3), repeat=3)
            if p[axis] == end
        ]
        for end in (0, 2)
    )
    for axis in range(3)
]
REGULAR = 4  # cells round an edge of an ordinary grid node (Q != 4 makes a star)


@dataclass
class Stencils:
    """Neighbourhoods ``ids`` (m, 3, 3, 3) of the nodes ``ids[:, 1, 1, 1]`` solved for, and
    their logical spacings ``h`` (m, 3, 2): along each axis to the minus and plus side."""

    ids: np.ndarray
    h: np.ndarray

    @functools.cached_property
    def rows(self) -> RowGeometry:
        """What the Winslow rows take from the stencils alone, for every Picard step."""
        return RowGeometry(self)


class RowGeometry:
    """The parts of the stencils' Winslow rows that do not move with the nodes: the centre
    and its two neighbours per axis (``mirrored`` where they are one node), the spacings,
    and per offset of ``OFFSETS`` its cofactor and the factor and divisor of its weight."""

    def __init__(self, st: Stencils) -> None:
        ids, h = st.ids, st.h
        span = h[:, :, 0] + h[:, :, 1]
        self.centre = ids[:, 1, 1, 1]
        self.plus = [ids[:, 2, 1, 1], ids[:, 1, 2, 1], ids[:, 1, 1, 2]]
        self.minus = [ids[:, 0, 1, 1], ids[:, 1, 0, 1], ids[:, 1, 1, 0]]
        self.mirrored = [np.flatnonzero(p == m) for p, m in zip(self.plus, self.minus)]
        self.span = [span[:, a] for a in range(3)]
        self.ahead = [h[:, a, 1] for a in range(3)]
        self.centre_column = OFFSETS.index((0, 0, 0))
        self.terms: list = []
        for off in OFFSETS:
            axes = [a for a in range(3) if off[a]]
            if len(axes) == 1:
                a = axes[0]
                side = h[:, a, 1] if off[a] > 0 else h[:, a, 0]
                self.terms.append(((a, a), (2.0, side * span[:, a])))
            elif len(axes) == 2:
                a, b = axes
                self.terms.append(((a, b), (2.0 * off[a] * off[b], span[:, a] * span[:, b])))
            else:
                self.terms.append((None, None))


@dataclass
class Star:
    """A node whose cells do not close as eight octants (three or five blocks round an
    edge): its neighbours ``around`` and the least-squares weights ``fit`` (9, m) giving
    the first and second derivatives at it (``FIT_TERMS``) from their offsets."""

    node: int
    around: np.ndarray
    fit: np.ndarray
    slope: np.ndarray


@dataclass
class Fan:
    """The cells round an irregular node as :func:`_fan` lays them out: the neighbours
    ``around`` at their logical offsets ``pos`` (m, 3), each found as a corner of one cell
    (``corners``: cell, corner), and its layers' signs and cells' axes along the edge
    (``heights``: the offsets' third components are their means of those cells' lengths)."""

    around: np.ndarray
    pos: np.ndarray
    corners: list[tuple[int, tuple[int, int, int]]]
    heights: list[tuple[float, list[tuple[int, int]]]]

    def along(self, cells: list, place: Placement, logical) -> Fan:
        """The fan of a node further along the same block edge (``cells``: its cells, as
        the first node's but for their index along the edge): the same neighbours a cell
        further, the same offsets across the edge (its cells' lengths across it are the
        same) and its own layers' heights."""
        around = np.array(
            [
                place.ids[cells[q][0]][tuple(c + k for c, k in zip(cells[q][1], e))]
                for q, e in self.corners
            ]
        )
        pos = self.pos.copy()
        for (sign, layer), first in zip(self.heights, (pos[:, 2] > 0, pos[:, 2] < 0)):
            lengths = [_lengths(logical[cells[q][0]], cells[q][1])[al] for q, al in layer]
            pos[first, 2] = sign * float(np.mean(lengths))
        return Fan(around, pos, self.corners, self.heights)


def _lengths(u: list[np.ndarray], c) -> list[float]:
    """A cell's logical edge lengths along its block's three directions (``u``: the block's
    logical coordinates, ``c``: the cell's index)."""
    return [abs(float(u[a][c[a] + 1] - u[a][c[a]])) for a in range(3)]


def _stars(
    nodes: list[int], edge: dict[int, list], place: Placement, logical, held: np.ndarray
) -> dict[int, Star | None]:
    """The stars of the irregular ``nodes`` (None where their cells form no fan or the node
    lies on two boundary planes): a fan laid out once an edge (:func:`_fan`), moved along it
    (:meth:`Fan.along`), and every star's least-squares fits found together."""
    groups: dict[tuple, list[int]] = {}
    for node in nodes:
        key = (_along_edge(edge[node], place), held[node].tobytes())
        groups.setdefault(key, []).append(node)
    fans: dict[int, tuple[Fan, int | None]] = {}
    for members in groups.values():
        normal = np.flatnonzero(held[members[0]])
        if len(normal) > 1:
            continue
        side = int(normal[0]) if len(normal) else None
        first = _fan(members[0], edge[members[0]], place, logical, side)
        for node in members:
            if first is None or node == members[0]:
                fan = first if node == members[0] else _fan(node, edge[node], place, logical, side)
            else:
                fan = first.along(edge[node], place, logical)
            if fan is not None:
                fans[node] = (fan, side)
    made = {}  # a star's neighbours, the offsets its fit is made at and its slope
    for members in _by_shape(fans, lambda node: fans[node][0].pos.shape):
        pos = np.stack([fans[n][0].pos for n in members])
        # the metric from the real cells alone (a mirror would make the normal derivative 0)
        slopes = np.linalg.pinv(_design(pos))[:, :3]
        for node, slope, at in zip(members, slopes, pos):
            around, side = fans[node][0].around, fans[node][1]
            if side is not None:  # the mirror layer: the same nodes across the plane
                around = np.concatenate([around, around])
                at = np.vstack([at, at * [1.0, 1.0, -1.0]])
                slope = np.hstack([slope, np.zeros_like(slope)])
            made[node] = (around, at, slope)
    out: dict[int, Star | None] = dict.fromkeys(nodes)
    for members in _by_shape(made, lambda node: made[node][1].shape):
        fits = np.linalg.pinv(_design(np.stack([made[n][1] for n in members])))
        for node, fit in zip(members, fits):
            out[node] = Star(node, made[node][0], fit, made[node][2])
    return out


def _by_shape(nodes, shape) -> list[list[int]]:
    """``nodes`` in groups of one ``shape(node)``: their fits are found together."""
    groups: dict[tuple, list[int]] = {}
    for node in nodes:
        groups.setdefault(shape(node), []).append(node)
    return list(groups.values())


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
    index, node's corner in the cell), each a tuple of three."""
    out: dict[int, list] = {}
    corners = list(itertools.product((0, 1), repeat=3))
    octants = np.array(corners)
    for b, ids in enumerate(place.ids):
        n = np.array(ids.shape) - 1
        at_end = [np.isin(np.arange(m + 1), (0, m)) for m in n]
        mask = (
            at_end[0][:, None, None].astype(int)
            + at_end[1][None, :, None]
            + at_end[2][None, None, :]
        ) >= 2
        index = np.argwhere(mask)
        cells = index[:, None, :] - octants[None]  # (nodes, 8, 3)
        inside = ((cells >= 0) & (cells < n)).all(axis=2)
        nodes = ids[tuple(index.T)].tolist()
        for node, cs, ok in zip(nodes, cells.tolist(), inside.tolist()):
            for c, o, good in zip(cs, corners, ok):
                if good:
                    out.setdefault(node, []).append((b, tuple(c), o))
    return out


@functools.cache
def _spots(perm: tuple, sign: tuple, o: tuple) -> tuple | None:
    """Where a cell's corners (i, j, k) fall in the frame of its corner ``o``, its local
    axis a along the frame's ``perm[a]`` with ``sign[a]``; None where one falls outside."""
    out = []
    for off in itertools.product((0, 1), repeat=3):
        pos = [1, 1, 1]
        for a in range(3):
            pos[perm[a]] += sign[a] * (off[a] - o[a])
        if min(pos) < 0 or max(pos) > 2:
            return None
        out.append((off, tuple(pos)))
    return tuple(out)


def _glued(edge: dict[int, list], place: Placement, steps: list) -> dict[int, tuple | None]:
    """Each node's (``edge``: nodes on block edges and vertices with their cells) 3 x 3 x 3
    frame glued from its cells (27 ids, -1 where no cell reaches) and its spacings (3 x 2;
    ``steps``: each block direction's logical cell lengths), or None where the cells do not
    fit one frame (an irregular edge). The nodes along one block edge (the same blocks,
    corners and places at the blocks' ends) share their cells' axis maps (:func:`_maps`):
    found once, and their frames gathered together."""
    groups: dict[tuple, list[int]] = {}
    for node, cells in edge.items():
        groups.setdefault(_along_edge(cells, place), []).append(node)
    out: dict[int, tuple | None] = {}
    for nodes in groups.values():
        maps = _maps(nodes[0], _corners(edge[nodes[0]], place))
        if maps is None:  # an irregular edge: its cells fit no frame at any of its nodes
            out.update(dict.fromkeys(nodes))
            continue
        for node, one in zip(nodes, _frames(nodes, edge, maps, place, steps)):
            if one is None:  # not as the edge's first node: glued on its own
                own = _maps(node, _corners(edge[node], place))
                one = _frames([node], edge, own, place, steps)[0] if own else None
            out[node] = one
    return out


def _along_edge(cells: list, place: Placement) -> tuple:
    """What the nodes along one block edge share (their cells' blocks, the node's corners in
    them and the cells' places at the blocks' ends): nodes with the same key have cells
    that differ only in their index along the edge."""
    return tuple(
        (b, o, tuple((c[a] == 0, c[a] == place.ids[b].shape[a] - 2) for a in range(3)))
        for b, c, o in cells
    )


def _corners(cells: list, place: Placement) -> list:
    """Each cell's node ids (2, 2, 2) as lists, and the node's corner in it."""
    return [
        (place.ids[b][c[0] : c[0] + 2, c[1] : c[1] + 2, c[2] : c[2] + 2].tolist(), o)
        for b, c, o in cells
    ]


def _frames(nodes: list[int], edge: dict[int, list], maps: list, place: Placement, steps: list):
    """The frames and spacings (as :func:`_glued`) of ``nodes``, whose cells share the axis
    maps ``maps``; None for a node whose cells then place two ids at one spot or one id at
    two."""
    cells = edge[nodes[0]]
    c = np.array([[cell[1] for cell in edge[node]] for node in nodes])  # (nodes, cells, 3)
    frame = np.full((len(nodes), 27), -1)
    frame[:, 13] = nodes
    ok = np.ones(len(nodes), dtype=bool)
    h = np.zeros((len(nodes), 3, 2))
    count = np.zeros((3, 2), dtype=int)
    for q, ((b, _, o), (perm, sign)) in enumerate(zip(cells, maps)):
        off, slots = _spot_arrays(perm, sign, o)
        nb = place.ids[b][tuple((c[:, q, :, None] + off).transpose(1, 0, 2))]  # (nodes, 8)
        there = frame[:, slots]
        ok &= ((there == -1) | (there == nb)).all(axis=1)
        frame[:, slots] = nb
        for a in range(3):
            side = 1 if sign[a] * (1 - 2 * int(o[a])) > 0 else 0
            h[:, perm[a], side] += steps[b][a][c[:, q, a]]
            count[perm[a], side] += 1
    h = np.where(count > 0, h / np.maximum(count, 1), 0.0)
    ordered = np.sort(frame, axis=1)
    ok &= ~((ordered[:, 1:] == ordered[:, :-1]) & (ordered[:, 1:] >= 0)).any(axis=1)
    return [(f, s) if good else None for f, s, good in zip(frame.tolist(), h.tolist(), ok.tolist())]


@functools.cache
def _spot_arrays(perm: tuple, sign: tuple, o: tuple) -> tuple[np.ndarray, np.ndarray]:
    """:func:`_spots` as arrays: the cell's corners (3, 8) and their places in a flattened
    frame (8,)."""
    spots = _spots(perm, sign, o)
    off = np.array([corner for corner, _ in spots]).T
    return off, np.array([9 * i + 3 * j + k for _, (i, j, k) in spots])


def _maps(node: int, corners: list) -> list | None:
    """Each cell's map of its local axes to the frame's (``perm``, ``sign``; ``corners``:
    each cell's node ids (2, 2, 2) and the node's corner in it), or None where the cells do
    not fit one frame.

    A cell's local axis a maps to the frame axis ``perm[a]`` with a sign: read from two of
    its edge neighbours of the node already placed, the third by right-handedness (every
    block is right-handed)."""
    where: dict[int, tuple[int, int, int]] = {node: CENTRE}
    maps: list = [None] * len(corners)
    maps[0] = ((0, 1, 2), (1, 1, 1))
    placed = [False] * len(corners)
    progress = True
    while progress:
        progress = False
        for q, (box, o) in enumerate(corners):
            if placed[q]:
                continue
            if maps[q] is None:
                perm, sign = [-1, -1, -1], [0, 0, 0]
                for a in range(3):
                    e = list(o)
                    e[a] = 1 - o[a]
                    pos = where.get(box[e[0]][e[1]][e[2]])
                    if pos is None:
                        continue
                    moved = [pos[k] - 1 for k in range(3)]
                    if sum(map(abs, moved)) != 1:
                        return None
                    axis = next(k for k in range(3) if moved[k])
                    perm[a], sign[a] = axis, moved[axis] * (1 - 2 * o[a])
                if perm.count(-1) > 1:
                    continue
                if perm.count(-1) == 1:
                    a2 = perm.index(-1)
                    a0, a1 = (a2 + 1) % 3, (a2 + 2) % 3
                    if perm[a0] == perm[a1]:
                        return None
                    perm[a2] = 3 - perm[a0] - perm[a1]
                    # the column of a2 is the cross product of those of a0 and a1
                    parity = 1 if (perm[a1] - perm[a0]) % 3 == 1 else -1
                    sign[a2] = sign[a0] * sign[a1] * parity
                if sorted(perm) != [0, 1, 2] or _det(perm, sign) != 1:
                    return None
                maps[q] = (tuple(perm), tuple(sign))
            spots = _spots(*maps[q], o)
            if spots is None:
                return None
            for (i, j, k), pos in spots:
                nb = box[i][j][k]
                if where.get(nb, pos) != pos:
                    return None
                where[nb] = pos
            placed[q] = progress = True
    return maps if all(placed) else None


def _det(perm, sign) -> int:
    """The determinant of the signed permutation taking local axis a to ``perm[a]``."""
    inversions = sum(perm[i] > perm[j] for i in range(3) for j in range(i + 1, 3))
    return (-1) ** inversions * sign[0] * sign[1] * sign[2]


def _mirror(frame: list[int], h: list[list[float]]) -> bool:
    """Fill the missing half of a boundary node's frame (27 ids, -1 where none) by mirroring
    it across the frame's axes whose one side is empty; whether the frame is then complete."""
    for axis, (first, last) in enumerate(FRAME_SIDES):
        lo, hi = [frame[i] for i in first], [frame[i] for i in last]
        if all(n < 0 for n in lo) and any(n >= 0 for n in hi):
            for i, n in zip(first, hi):
                frame[i] = n
            h[axis][0] = h[axis][1]
        elif all(n < 0 for n in hi) and any(n >= 0 for n in lo):
            for i, n in zip(last, lo):
                frame[i] = n
            h[axis][1] = h[axis][0]
    return all(frame[i] >= 0 for i in FRAME_STENCIL)


def _fan(node: int, cells: list, place: Placement, logical, normal: int | None) -> Fan | None:
    """The fan of a node on an edge round which Q != 4 blocks meet (Knupp's irregular
    node, as ``multiblock.junctions`` in 2D): the cells' fan across the edge mapped to a
    Q-gon in a logical plane (equal angles, each side neighbour at its logical distance),
    the edge along the third logical axis, each cell's nodes at those logical offsets; a
    node on a boundary plane (``normal``: its axis) has its one layer mirrored across it
    (by :func:`_stars`). None where the cells form no such fan."""

    def neighbour(b, c, o, a) -> int:
        e = list(o)
        e[a] = 1 - e[a]
        return int(place.ids[b][c[0] + e[0], c[1] + e[1], c[2] + e[2]])

    # a block vertex inside the domain: the edge runs to the neighbours that the cells of
    # one layer share (Q each), the fan's side neighbours are shared by four cells
    shared: dict[int, int] = {}
    for b, c, o in cells:
        for a in range(3):
            n = neighbour(b, c, o, a)
            shared[n] = shared.get(n, 0) + 1
    axes = []
    for b, c, o in cells:
        index = np.array(c) + np.array(o)
        inner = [a for a in range(3) if 0 < index[a] < place.ids[b].shape[a] - 1]
        counts = [shared[neighbour(b, c, o, a)] for a in range(3)]
        if len(inner) == 1:
            axes.append(inner[0])
        elif not inner and normal is None:
            along = [a for a in range(3) if counts[a] == len(cells) // 2 != REGULAR]
            if len(along) != 1 or sorted(counts) != sorted([REGULAR, REGULAR, counts[along[0]]]):
                return None
            axes.append(along[0])
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
    for q, ((b, c, o), along) in enumerate(zip(cells, axes)):
        ids = place.ids[b]

        def at(flip, c=c, o=o, ids=ids):
            e = list(o)
            for a in flip:
                e[a] = 1 - e[a]
            return int(ids[c[0] + e[0], c[1] + e[1], c[2] + e[2]])

        plane = [a for a in range(3) if a != along]
        lengths = _lengths(logical[b], c)
        layers.setdefault(at([along]), []).append((at, along, plane, lengths, q))
    if len(layers) > 2 or (len(layers) == 1) != (normal is not None):
        return None
    # the fan: side neighbours in the edge's normal plane, chained round the node
    first = next(iter(layers.values()))
    links: dict[int, list[int]] = {}
    for at, _, plane, _, _ in first:
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
    # each side neighbour at its cells' logical edge length from the node
    reach: dict[int, list[float]] = {}
    for layer in layers.values():
        for at, _, plane, lengths, _ in layer:
            for a in plane:
                reach.setdefault(at([a]), []).append(lengths[a])
    angle = 2 * np.pi * np.arange(q) / q
    side = {
        n: float(np.mean(reach[n])) * np.array([np.cos(t), np.sin(t), 0.0])
        for n, t in zip(ring, angle)
    }
    offsets: dict[int, np.ndarray] = dict(side)
    heights = []
    for sign, layer in zip((1.0, -1.0), layers.values()):
        heights.append((sign, [(q, al) for _, al, _, _, q in layer]))
        height = sign * float(np.mean([ln[al] for _, al, _, ln, _ in layer]))
        for at, along, plane, _, _ in layer:
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
                if n in offsets and not _close(offsets[n], pos):
                    return None
                offsets[n] = pos
    around = np.array(list(offsets))
    corners = {}  # a node of the cells as (cell, corner), for the nodes further along the edge
    for q, (b, c, _) in enumerate(cells):
        box = place.ids[b][c[0] : c[0] + 2, c[1] : c[1] + 2, c[2] : c[2] + 2]
        for e in itertools.product((0, 1), repeat=3):
            corners.setdefault(int(box[e]), (q, e))
    return Fan(
        around, np.array([offsets[n] for n in around]), [corners[n] for n in around], heights
    )


def _close(a: np.ndarray, b: np.ndarray) -> bool:
    """``np.allclose(a, b)`` of two 3-vectors, without its overhead (called per star node)."""
    return all(abs(x - y) <= 1e-8 + 1e-5 * abs(y) for x, y in zip(a.tolist(), b.tolist()))


def _design(pos: np.ndarray) -> np.ndarray:
    """The quadratic fit's design matrices at logical offsets ``pos`` (..., m, 3)."""
    xi, eta, zeta = pos[..., 0], pos[..., 1], pos[..., 2]
    return np.stack(
        [xi, eta, zeta, 0.5 * xi**2, xi * eta, xi * zeta, 0.5 * eta**2, eta * zeta, 0.5 * zeta**2],
        axis=-1,
    )


class StarRows:
    """The stars' frozen-coefficient Winslow rows, computed together for the stars of one
    fan size: per star its node ids (the node first) and weights, normalised so that the
    node's is -1."""

    def __init__(self, stars: list[Star]) -> None:
        sizes: dict[int, list[int]] = {}
        for k, star in enumerate(stars):
            sizes.setdefault(len(star.around), []).append(k)
        self.count = len(stars)
        self.groups = [
            (
                np.array(ks),
                np.array([stars[k].node for k in ks]),
                np.stack([stars[k].around for k in ks]),
                np.stack([stars[k].slope for k in ks]),
                np.stack([stars[k].fit for k in ks]),
            )
            for ks in sizes.values()
        ]
        self.ids = [np.concatenate([[s.node], s.around]) for s in stars]

    def weights(self, points: np.ndarray) -> list[np.ndarray]:
        """Each star's row weights at the nodes ``points``, in the stars' order."""
        out: list[np.ndarray] = [np.empty(0)] * self.count
        for ks, node, around, slope, fit in self.groups:
            offsets = points[around] - points[node][:, None]
            d = slope @ offsets
            m = d @ d.transpose(0, 2, 1)
            c = cofactor_terms([[m[:, a, b] for b in range(3)] for a in range(3)])
            w = sum(
                (1.0 if len(t) == 1 or t[0] == t[1] else 2.0) * c[t][:, None] * fit[:, k]
                for k, t in enumerate(FIT_TERMS)
                if len(t) == 2
            )
            centre = -w.sum(axis=1)
            rows = np.concatenate([centre[:, None], w], axis=1) / -centre[:, None]
            for k, row in zip(ks.tolist(), rows):
                out[k] = row
        return out


def boundary_held(place: Placement) -> tuple[dict, np.ndarray]:
    """Each shared block face's face across (block, axis, end both), and per node and
    coordinate whether the boundary's rules of the module hold it: a node on a boundary
    face in a coordinate plane holds that coordinate, on any other boundary face all three."""
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
    return across, held


def stencils(
    place: Placement, twin: np.ndarray | None = None
) -> tuple[Stencils, list[Star], np.ndarray]:
    """Every node's neighbourhood that can be built (none for a node whose ``twin`` is
    another: it moves with it), and per node and coordinate whether it is held (the
    boundary's rules of the module)."""
    twin = np.arange(len(place.points)) if twin is None else twin
    logical = _logical(place)
    across, held = boundary_held(place)
    parts = _interior(place, logical) + _faces(place, logical, across)
    steps = [[np.abs(np.diff(u)) for u in block] for block in logical]
    glued_ids, glued_h, stars = [], [], []
    edge = {
        node: cells
        for node, cells in _edge_nodes(place).items()
        if not held[node].all() and twin[node] == node
    }
    glued = _glued(edge, place, steps)
    irregular = []
    for node in edge:
        got = glued[node]
        if got is not None and _mirror(*got) and all(x > 0 for side in got[1] for x in side):
            glued_ids.append(got[0])
            glued_h.append(got[1])
        else:
            irregular.append(node)
    for node, star in _stars(irregular, edge, place, logical, held).items():
        if star is None:
            held[node] = True
        else:
            stars.append(star)
    if glued_ids:
        parts.append(Stencils(np.array(glued_ids).reshape(-1, 3, 3, 3), np.array(glued_h)))
    ids = np.concatenate([p.ids for p in parts])
    h = np.concatenate([p.h for p in parts])
    centre = ids[:, 1, 1, 1]
    solved = ~held[centre].all(axis=1) & (twin[centre] == centre)
    return Stencils(ids[solved], h[solved]), stars, held


def _weights(points: np.ndarray, st: Stencils) -> np.ndarray:
    """(m, 19) weights of each node's frozen-coefficient Winslow row over ``OFFSETS``,
    normalised so that the centre's is -1."""
    g = st.rows
    x0 = np.take(points, g.centre, axis=0)  # np.take: several times faster than [ids]
    d = []
    for a in range(3):
        ahead = np.take(points, g.plus[a], axis=0)
        slope = (ahead - np.take(points, g.minus[a], axis=0)) / g.span[a][:, None]
        # across a mirror plane the ghost is the neighbour itself: one-sided there
        at = g.mirrored[a]
        slope[at] = (ahead[at] - x0[at]) / g.ahead[a][at][:, None]
        d.append(slope)
    upper = {(a, b): np.einsum("nk,nk->n", d[a], d[b]) for a in range(3) for b in range(a, 3)}
    c = cofactor_terms([[upper[min(a, b), max(a, b)] for b in range(3)] for a in range(3)])
    # an offset's weights as a row (19, m), each written and read whole, then turned
    w = np.empty((len(OFFSETS), len(x0)))
    centre = np.zeros(len(x0))
    for k, (terms, scale) in enumerate(g.terms):
        if terms is None:
            continue
        w[k] = c[terms] * scale[0] / scale[1]
        if terms[0] == terms[1]:
            centre -= w[k]
    w[g.centre_column] = centre
    w /= -centre
    return w.T


def _columns(st: Stencils) -> np.ndarray:
    """(m, 19) node ids of each row's entries, in ``OFFSETS``' order."""
    return np.stack([st.ids[:, 1 + o[0], 1 + o[1], 1 + o[2]] for o in OFFSETS], axis=1)


class _Systems:
    """The three coordinates' Picard systems over one sparsity pattern, laid out once: the
    rows of the ``nodes`` free in some coordinate over every node, each row's entries as the
    stencil gives them (``cols``, ``counts`` a row). A column that a mirror repeats stays
    twice, summed by every product and smoothing sweep as one entry of their sum (the
    diagonal is never repeated): merging them would sort 1.7 million entries and touch
    170 MB on DFG 3D for nothing the solve needs. A coordinate's matrix is the rows and
    columns of its free nodes (``free``); coordinates free at the same nodes (the
    cross-section's two of a pipe) have the same matrix, so one inexact solver, its
    hierarchy built once, solves their columns together. A node whose ``twin`` is another
    (a slab's back face, the mirror image of its front) has no row: its column is its twin's,
    and where that is the row's own node its weight joins the diagonal (Gauss-Seidel reads
    one diagonal entry a row)."""

    def __init__(
        self,
        owners: np.ndarray,
        held: np.ndarray,
        cols: np.ndarray,
        counts: np.ndarray,
        twin: np.ndarray,
    ) -> None:
        n = len(held)
        solved = ~held[owners].all(axis=1) & (twin[owners] == owners)
        self.twin = twin
        self.nodes = owners[solved]
        self.free = ~held[self.nodes]
        self.mine = np.repeat(solved, counts)
        self.counts = counts[solved]
        indptr = np.zeros(len(self.counts) + 1, dtype=np.int64)
        np.cumsum(self.counts, out=indptr[1:])
        self.pattern = (cols[self.mine].astype(np.int32), indptr, (len(self.nodes), n))
        self.rows = [np.flatnonzero(self.free[:, comp]) for comp in range(3)]
        self.groups: dict[bytes, list[int]] = {}
        for comp in range(3):
            self.groups.setdefault(np.packbits(self.free[:, comp]).tobytes(), []).append(comp)
        self.parts: dict[bytes, tuple] = {}  # a group's matrix layout, at its first solve
        # a slab's face (its back face the twin) is a 2D system: its sparse LU costs less
        # than the multigrid's V-cycles there, and pyamg is not imported
        face = bool((twin != np.arange(n)).any())
        build = direct if face else plain_aggregation
        self.solvers = {key: InexactSolve(build, FORCING, gmres) for key in self.groups}

    def _part(self, free: np.ndarray) -> tuple:
        """The entries (a mask), column indices and row pointers of the matrix of the rows
        and columns ``free`` among the pattern's rows, and the entries that join their
        row's diagonal (a twin of the row's node: a mask) with the places of those
        diagonals among the entries kept."""
        cols, starts, (_, n) = self.pattern
        rows = np.flatnonzero(free)
        local = np.full(n, -1, dtype=np.int32)  # a node's place among the free rows
        local[self.nodes[rows]] = np.arange(len(rows), dtype=np.int32)
        local = local[self.twin]  # a twin's column is its node's
        inner = local[cols]
        row = np.repeat(np.arange(len(self.nodes)), self.counts)  # each entry's row
        owner = self.nodes[row]
        keep = np.repeat(free, self.counts) & (inner >= 0)
        own = keep & (cols == owner)  # each kept row's diagonal
        echo = keep & ~own & (inner == local[owner])
        keep &= ~echo
        kept = np.zeros(len(keep) + 1, dtype=np.int64)  # entries kept before each
        np.cumsum(keep, out=kept[1:])
        diagonal = np.zeros(len(self.nodes), dtype=np.int64)
        diagonal[row[own]] = kept[:-1][own]
        into = diagonal[row[echo]]
        return keep, inner[keep], np.append(kept[starts[rows]], kept[-1]), echo, into

    def residuals(self, v: np.ndarray, points: np.ndarray) -> np.ndarray:
        """(m, 3) Winslow residuals of the rows' nodes under the entries' weights ``v``
        (rows normalised: a length), and keeps the weights for :meth:`updates`."""
        indices, indptr, shape = self.pattern
        self.data = v[self.mine]
        return sp.csr_matrix((self.data, indices, indptr), shape=shape) @ points

    def updates(self, residual: np.ndarray, solved: float) -> list[np.ndarray | None]:
        """Per coordinate, the update of its free nodes (``rows``) toward the frozen
        system's solution (``residual``: :meth:`residuals`), or None where no residual
        exceeds ``solved``."""
        out: list[np.ndarray | None] = [None] * 3
        for key, comps in self.groups.items():
            rows = self.rows[comps[0]]
            rhs = np.take(residual, rows, axis=0)[:, comps]
            live = [k for k in range(len(comps)) if np.abs(rhs[:, k]).max(initial=0.0) > solved]
            if not live:
                continue
            if key not in self.parts:
                self.parts[key] = self._part(self.free[:, comps[0]])
            keep, indices, indptr, echo, into = self.parts[key]
            values = -self.data[keep]
            if len(into):
                values -= np.bincount(into, weights=self.data[echo], minlength=len(values))
            mat = sp.csr_matrix((values, indices, indptr), shape=(len(rows),) * 2)
            got = self.solvers[key].solve(mat, np.ascontiguousarray(rhs[:, live]))
            for k, column in zip(live, got.T):
                out[comps[k]] = column
        return out


def winslow(
    place: Placement,
    max_iterations: int = MAX_ITERATIONS,
    free_interfaces: bool = True,
    progress=None,
    twin: np.ndarray | None = None,
) -> tuple[np.ndarray, int]:
    """The nodes of the Winslow grid over all blocks from blockMesh's placement, and the
    Picard steps taken. ``free_interfaces=False`` keeps every node on a block face, edge
    or vertex where blockMesh puts it (each block's interior solved). ``twin``: each
    node's mirror image where the placement and its equations are symmetric (a slab's two
    faces, section.slab; the identity by default): only one of each pair is solved for,
    the other moves with it (half the unknowns)."""
    twin = np.arange(len(place.points)) if twin is None else twin
    st, stars, held = stencils(place, twin)
    points = place.points.copy()
    if not free_interfaces:
        inner = np.zeros(len(points), dtype=bool)
        for ids in place.ids:
            inner[ids[1:-1, 1:-1, 1:-1].ravel()] = True
        held[~inner] = True
    centre = st.ids[:, 1, 1, 1]
    cols = _columns(st)
    owners = np.concatenate([centre, [star.node for star in stars]]).astype(int)
    counts = np.array([cols.shape[1]] * len(cols) + [len(s.around) + 1 for s in stars])
    star_rows = StarRows(stars)
    entries = np.concatenate([cols.ravel()] + star_rows.ids)
    systems = _Systems(owners, held, entries, counts, twin)
    diag = float(np.linalg.norm(np.ptp(points, axis=0)))
    v = np.empty(len(entries))  # the entries' weights, written in place each step
    regular = v[: cols.size].reshape(cols.shape)  # the stencils' rows; the stars' follow
    steps = 0
    with one_thread():
        for steps in range(1, max_iterations + 1):
            np.copyto(regular, _weights(points, st))
            if stars:
                np.concatenate(star_rows.weights(points), out=v[cols.size :])
            residual = systems.residuals(v, points)
            updates = systems.updates(residual, SOLVED * diag)
            if all(delta is None for delta in updates):
                return points, steps - 1  # the grid solves the equations already
            moved = 0.0
            for comp, delta in enumerate(updates):
                if delta is not None:
                    step = np.zeros(len(points))
                    step[systems.nodes[systems.rows[comp]]] = delta
                    points[:, comp] += step[twin]  # a twin moves as its node
                    moved = max(moved, float(np.abs(delta).max(initial=0.0)))
            if progress is not None:
                progress(steps, moved / diag)
            if moved <= TOL * diag:
                break
    return points, steps
