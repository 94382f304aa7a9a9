"""Chains of block sides (SPEC 10): ``--cells X,Y=N`` gives the chain through the block side
nearest (X, Y) N cells, and ``--spacing X,Y=H`` grades the blocks across that side, H at it
on both sides of an interface, growing smoothly along the chain.

A *chain* is what shares one cell count: a piece and, where a block's side is that one piece,
the piece of the opposite side, and so on through the blocks. A *graded* block side is one
from which a block's grid lines start with a first edge H: the blocks on both sides of the
named side, and, so that no block is graded on one side only, every block that shares a
whole side with a graded block's side along the grading (a column of blocks downstream of a
cylinder's box is graded as a column, as a blockMesh user grades it), and the block across a
graded interface where that grades no other block. ``grading.graded_lines`` places the
nodes of their lines.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from shapely.geometry import LineString, Point

from pinn_engine.classical.spacing import exact_stretch
from pinn_engine.errors import InputError
from pinn_engine.multiblock.blocks import Topology
from pinn_engine.multiblock.patches import FAR, TIE, point_of

MIN_SIDE_CELLS = 2  # SPEC 10: a chain has at least 2 cells
# Neighbouring cells along a graded chain differ by at most this factor (SPEC 10: 1.25), and
# the counts are raised until the straight line's stretching stays within GROWTH_AIM, a
# margin for the map's curved lines
MAX_GROWTH, GROWTH_AIM = 1.25, 1.2
# A graded chain's count is raised at most to this many times its count from the cell size
# before the grading is refused (H far from the cell size needs cells no count gives)
MAX_RAISE = 20


@dataclass(frozen=True)
class SideItem:
    """One ``X,Y=VALUE`` item of ``--cells`` (VALUE a count) or ``--spacing`` (a length)."""

    x: float
    y: float
    value: float
    flag: str  # "cells", "spacing" or "grading", for messages

    @property
    def where(self) -> str:
        return f"{self.flag} {self.x:g},{self.y:g}={self.value:g}"


def parse_cells(items: Sequence[str] | None) -> list[SideItem]:
    """``X,Y=N`` items (N a whole number of at least 2), checked (one line naming the item)."""
    out = []
    for item in items or ():
        where, sep, value = item.partition("=")
        point = point_of(where)
        try:
            n = int(value)
            if not (sep and point is not None and n >= MIN_SIDE_CELLS):
                raise ValueError
        except ValueError:
            raise InputError(
                f"cells {item!r}: {{with_blocks}}expected X,Y=N, N cells (at least 2) along "
                "the chain through the block side nearest the point (X, Y)"
            ) from None
        out.append(SideItem(*point, n, "cells"))
    return out


def parse_gradings(items: Sequence[str] | None) -> list[SideItem]:
    """``X,Y=R`` items (R a positive ratio), checked (one line naming the item)."""
    out = []
    for item in items or ():
        where, sep, value = item.partition("=")
        point = point_of(where)
        try:
            r = float(value)
            if not (sep and point is not None and np.isfinite(r) and r > 0):
                raise ValueError
        except ValueError:
            raise InputError(
                f"grading {item!r}: {{with_blocks}}expected X,Y=R, R > 0 the ratio of the "
                "last cell to the first along the chain through the block side nearest the "
                "point (X, Y), the first at the side's end nearest it"
            ) from None
        out.append(SideItem(*point, r, "grading"))
    return out


def _index_forward(side: int, backwards: bool) -> bool:
    """Whether a piece on a block's ``side`` (0-3, counter-clockwise from corner 0), walked
    ``backwards`` or not, runs along its block's index (i on sides 0 and 2, j on 1 and 3)."""
    return (side in (0, 1)) != backwards


def chain_senses(topo: Topology, piece: int) -> dict[int, bool]:
    """Every piece of ``piece``'s chain, and whether it runs the same way as ``piece`` (as
    the blocks' index runs across them)."""
    senses = {piece: True}
    queue = [piece]
    while queue:
        k = queue.pop()
        for block in topo.blocks:
            for a, b in ((0, 2), (1, 3)):
                if len(block.sides[a]) != 1 or len(block.sides[b]) != 1:
                    continue
                (pa, ba), (pb, bb) = block.sides[a][0], block.sides[b][0]
                same = _index_forward(a, ba) == _index_forward(b, bb)
                for this, other in ((pa, pb), (pb, pa)):
                    if this == k and other not in senses:
                        senses[other] = senses[k] == same
                        queue.append(other)
    return senses


def ratio_params(
    topo: Topology, items: Sequence[SideItem], counts: np.ndarray, graded: set[int]
) -> dict[int, np.ndarray]:
    """The arc-length fractions of the nodes of every piece along each expansion ratio's
    chain (``--grading X,Y=R``: cells growing geometrically, the last R times the first,
    the first at the named side's end nearest the point, every piece of the chain the same
    way); refused on a chain that a spacing also grades (``graded``)."""
    out: dict[int, np.ndarray] = {}
    for item in items:
        named = nearest_piece(topo, item)
        points = topo.pieces[named].points
        at_start = np.hypot(*(points[0] - (item.x, item.y))) <= np.hypot(
            *(points[-1] - (item.x, item.y))
        )
        senses = chain_senses(topo, named)
        for block in topo.blocks:
            for a in range(4):
                side, opposite = block.sides[a], block.sides[(a + 2) % 4]
                if any(k in senses for k, _ in side) and (len(side) > 1 or len(opposite) > 1):
                    x, y = block.inside
                    raise InputError(
                        f"{item.where}: the block at ({x:.3g}, {y:.3g}) along the chain has a "
                        "side of several pieces there, whose grid lines one ratio cannot "
                        "grade; draw its block edges so that its sides along the chain are "
                        "one piece each, or grade with --spacing X,Y=H"
                    )
        for k, same in senses.items():
            if k in graded or k in out:
                raise InputError(
                    f"{item.where}: its chain is graded twice (by another --grading or a "
                    "--spacing X,Y=H); give one grading a chain"
                )
            n = int(counts[k])
            growth = item.value ** (1.0 / (n - 1)) if n > 1 else 1.0
            cells = growth ** np.arange(n)
            fractions = np.concatenate([[0.0], np.cumsum(cells)]) / cells.sum()
            out[k] = fractions if same == at_start else 1.0 - fractions[::-1]
    return out


def ratio_lines(
    topo: Topology, ids: list[np.ndarray], ratios: dict[int, np.ndarray], points: np.ndarray
) -> dict[tuple[int, ...], list]:
    """The grid lines of every block between two pieces of an expansion ratio's chain
    (``ratios``: :func:`ratio_params`' fractions), each asked its first and last edge so
    that its cells grow by the chain's ratio (``spacing.respace``'s requests): the method
    moves the nodes inside the blocks, and this puts the ratio back on every line."""
    from pinn_engine.multiblock.layout import side_lines

    out: dict[tuple[int, ...], list] = {}
    for block, block_ids in zip(topo.blocks, ids):
        for a, across in ((0, "left"), (1, "bottom")):
            (k, backwards), opposite = block.sides[a][0], block.sides[a + 2]
            if len(block.sides[a]) != 1 or len(opposite) != 1 or k not in ratios:
                continue
            f = np.diff(ratios[k])
            ratio = f[-1] / f[0]
            if _index_forward(a, backwards) is False:
                ratio = 1.0 / ratio  # the block's index runs against the piece
            for line in side_lines(block_ids, across):
                n = len(line) - 1
                length = float(np.linalg.norm(np.diff(points[line], axis=0), axis=1).sum())
                growth = ratio ** (1.0 / (n - 1)) if n > 1 else 1.0
                cells = growth ** np.arange(n)
                first, last = length * cells[0] / cells.sum(), length * cells[-1] / cells.sum()
                key = tuple(int(i) for i in line)
                out[key] = [first, last, "grading"]
    return out


def nearest_piece(topo: Topology, item: SideItem) -> int:
    """The piece (boundary or interface) nearest the item's point; refused when it is far
    from all or when two are about as near."""
    p = Point(item.x, item.y)
    dist = np.array([LineString(piece.points).distance(p) for piece in topo.pieces])
    order = np.argsort(dist)
    far, tie = FAR * topo.lines.diagonal, TIE * topo.lines.diagonal
    if dist[order[0]] > far:
        raise InputError(
            f"{item.where}: the point is {dist[order[0]]:.3g} from the nearest block side (at "
            f"most {far:.3g}); put it on the side"
        )
    if len(order) > 1 and dist[order[1]] - dist[order[0]] <= tie:
        raise InputError(
            f"{item.where}: the point is as near to two block sides (a corner or junction); "
            "put it inside the side"
        )
    return int(order[0])


def piece_chains(topo: Topology) -> np.ndarray:
    """Each piece's chain (an id shared by the pieces that must have one count): opposite
    sides of a block that are one piece each are joined."""
    root = list(range(len(topo.pieces)))

    def find(a: int) -> int:
        while root[a] != a:
            root[a] = root[root[a]]
            a = root[a]
        return a

    for block in topo.blocks:
        for a, b in ((0, 2), (1, 3)):
            if len(block.sides[a]) == 1 and len(block.sides[b]) == 1:
                root[find(block.sides[a][0][0])] = find(block.sides[b][0][0])
    return np.array([find(k) for k in range(len(topo.pieces))])


def _corner_key(xy) -> tuple[float, float]:
    return (float(xy[0]), float(xy[1]))


def graded_sides(topo: Topology, piece: int) -> dict[tuple[int, int], int]:
    """The (block, side) pairs whose grid lines start at the side with the first edge H of a
    grading at ``piece``, each with the side of the piece it lies on (+1 or -1): each block
    holding the piece, from its side holding it, then through every side along the grading
    that a neighbour shares whole, the neighbour from its side at the same end; and where a
    graded side is an interface that the block across has whole as a side and that block's
    sides along the grading lie on the boundary, that block from that side too (a grading
    carried to an interface grades the block across as well, where that grades no other)."""
    pieces_of = {}
    for b, block in enumerate(topo.blocks):
        for s, side in enumerate(block.sides):
            pieces_of[(b, s)] = sorted(p for p, _ in side)
    whole: dict[tuple, list[tuple[int, int]]] = {}
    for key, pieces in pieces_of.items():
        whole.setdefault(tuple(pieces), []).append(key)

    def on_boundary(b: int, s: int) -> bool:
        return not any(topo.pieces[p].interface for p in pieces_of[(b, s)])

    start = [(b, s) for (b, s), pieces in pieces_of.items() if piece in pieces]
    seen = {key: 1 - 2 * k for k, key in enumerate(start)}
    todo = list(start)
    while todo:
        b, s = todo.pop()
        for b2, t in whole[tuple(pieces_of[(b, s)])]:
            alone = on_boundary(b2, (t + 1) % 4) and on_boundary(b2, (t - 1) % 4)
            if (b2, t) not in seen and alone:
                seen[(b2, t)] = -seen[(b, s)]
        corners = topo.blocks[b].corners
        # the sides along the grading: s + 1 leaves corner s + 1, s - 1 ends at corner s
        for along, end in (((s + 1) % 4, (s + 1) % 4), ((s - 1) % 4, s)):
            at = _corner_key(corners[end])
            for b2, t in whole[tuple(pieces_of[(b, along)])]:
                if b2 == b:
                    continue
                c2 = topo.blocks[b2].corners
                nxt = (t - 1) % 4 if _corner_key(c2[t]) == at else (t + 1) % 4
                if (b2, nxt) not in seen:
                    seen[(b2, nxt)] = seen[(b, s)]
                    todo.append((b2, nxt))
    return seen


def _side_length(topo: Topology, b: int, s: int) -> float:
    return sum(topo.pieces[p].length for p, _ in topo.blocks[b].sides[s])


def max_growth(n: int, first: float, last: float | None = None) -> float:
    """The largest ratio of neighbouring cells of the stretching of ``n`` cells whose first
    cell is ``first`` (a share of the line) and whose last is ``last`` (None: free, the
    one-sided stretching a grading gives an end nobody asks)."""
    cells = np.diff(exact_stretch(n + 1, first, last)[0])
    ratio = cells[1:] / cells[:-1]
    return float(max(ratio.max(), (1.0 / ratio).max()))


def _least_count(n: int, top: int, first: float, last: float | None) -> int | None:
    """The least count from ``n`` to ``top`` whose stretching (``max_growth``) stays within
    GROWTH_AIM, or None."""
    while max_growth(n, first, last) > GROWTH_AIM:
        n += 1
        if n > top:
            return None
    return n


def graded_minimum(
    topo: Topology,
    graded: dict[tuple[int, int], int],
    h: float,
    counts: np.ndarray,
    item: SideItem,
    walls: dict[int, float],
) -> dict[int, int]:
    """Cells the pieces along a grading need so that neighbouring cells stay within
    GROWTH_AIM of each other (the first edge ``item.value`` with the other end free, or
    against the first edge of a spaced patch on the opposite side, ``walls``: piece -> H,
    where the lines are stretched to both; where no count does that, a wall too near the
    graded side, with the other end free as without the wall): per piece along,
    the least such count of its side (one piece a side; a side of several pieces keeps its
    counts)."""
    out: dict[int, int] = {}
    for b, s in graded:
        along = topo.blocks[b].sides[(s + 1) % 4]
        if len(along) != 1:
            continue
        piece = along[0][0]
        length = _side_length(topo, b, (s + 1) % 4)
        opposite = [walls.get(k) for k, _ in topo.blocks[b].sides[(s + 2) % 4]]
        first, n = item.value / length, int(counts[piece])
        top = max(n, int(np.ceil(length / h))) * MAX_RAISE
        least = None if None in opposite else _least_count(n, top, first, min(opposite) / length)
        least = least or _least_count(n, top, first, None)
        if least is None:
            raise InputError(
                f"{item.where}: no cell count keeps neighbouring cells within "
                f"{MAX_GROWTH:g} of each other from a first edge of {item.value:g} along a "
                f"side {length:.4g} long; choose H nearer the cell size ({h:.4g})"
            )
        out[piece] = max(out.get(piece, 0), least)
    return out


def graded_ends(
    topo: Topology, graded: dict[tuple[int, int], int], h: float
) -> dict[tuple[int, int], float]:
    """The ends of the pieces along a grading (the sides leaving each graded side, one
    piece each) where it asks the first edge ``h``: (piece, 0) at the piece's first point,
    (piece, 1) at its last."""
    out: dict[tuple[int, int], float] = {}
    for b, s in graded:
        block = topo.blocks[b]
        for along, end in (((s + 1) % 4, (s + 1) % 4), ((s - 1) % 4, s)):
            if len(block.sides[along]) != 1:
                continue
            k = block.sides[along][0][0]
            forward = _corner_key(topo.pieces[k].points[0]) == _corner_key(block.corners[end])
            out[(k, 0 if forward else 1)] = h
    return out


def graded_params(
    topo: Topology, ends: dict[tuple[int, int], float], counts: np.ndarray
) -> dict[int, np.ndarray]:
    """The arc-length fractions of the nodes of the pieces along gradings, from every
    grading's ``ends`` (:func:`graded_ends`, merged, the finer first edge where two ask
    one end): the first edges asked at either end or both, an end none asks free (a
    one-sided stretching: the cells grow monotonically from the asked end, SPEC 7, where
    the uniform cell asked there made them bulge above it in between), so that the solve
    starts from, and its sliding ends keep, the gradings."""
    out: dict[int, np.ndarray] = {}
    for k in sorted({k for k, _ in ends}):
        length, n = topo.pieces[k].length, int(counts[k])
        first, last = (ends[(k, e)] / length if (k, e) in ends else None for e in (0, 1))
        out[k] = exact_stretch(n + 1, first, last)[0]
    return out


def _leaving(topo: Topology, k: int, e: int) -> np.ndarray:
    """The unit direction in which piece ``k`` leaves its end ``e`` (0: first point)."""
    p = topo.pieces[k].points
    d = p[1] - p[0] if e == 0 else p[-2] - p[-1]
    return d / max(float(np.linalg.norm(d)), 1e-300)


def joint_ends(
    topo: Topology, ends: dict[tuple[int, int], float], walls: dict[int, float]
) -> dict[tuple[int, int], float]:
    """The gradings' ``ends`` (:func:`graded_ends`, merged) solved jointly with the spaced
    patches ``walls`` (boundary piece -> H): each piece end takes the smallest first edge
    asked of it, where a first edge is asked of an end

    - by a spaced wall that the piece leaves there (meets at a block corner, not as its
      continuation: the wall's first edge runs along the piece),
    - by any piece of its chain at the same end (every block side of a chain is graded
      alike, as blockMesh grades a chain),
    - by the piece that continues it through the node (turning by less than CORNER_TURN),
      so the cells on both sides of a node match (a step's lip: the inlet wall's cells
      meet the step line's cells),

    until no end changes (each change only lowers a first edge, so it ends). So two
    gradings meeting at one chain's end give it the finer one, on every side of the
    chain, instead of one at each side and a shear between them."""
    from pinn_engine.multiblock.blocks import CORNER_TURN

    out = dict(ends)
    at: dict[tuple[float, float], list[tuple[int, int]]] = {}
    for k, piece in enumerate(topo.pieces):
        for e in (0, 1):
            at.setdefault(_corner_key(piece.points[-e]), []).append((k, e))
    straight = float(np.cos(np.radians(CORNER_TURN)))
    senses = {}

    def ask(k: int, e: int, h: float) -> bool:
        if h < out.get((k, e), np.inf):
            out[(k, e)] = h
            return True
        return False

    changed = True
    while changed:
        changed = False
        for k, e in list(out):
            if senses.get(k) is None:
                senses[k] = chain_senses(topo, k)
            for k2, same in senses[k].items():
                changed |= ask(k2, e if same else 1 - e, out[(k, e)])
            for e in (0, 1):
                for k2, e2 in at[_corner_key(topo.pieces[k].points[-e])]:
                    if k2 != k and k2 in walls and not topo.pieces[k].interface:
                        cos = float(_leaving(topo, k, e) @ _leaving(topo, k2, e2))
                        if cos >= -straight:
                            changed |= ask(k, e, walls[k2])
    return out


def joint_minimum(
    topo: Topology,
    finer: dict[tuple[int, int], float],
    ends: dict[tuple[int, int], float],
    counts: np.ndarray,
    h: float,
) -> dict[int, int]:
    """Cells each piece with an end made ``finer`` by :func:`joint_ends` (than its
    gradings alone asked; ``ends``: all of them) needs so that its stretching's
    neighbouring cells stay within GROWTH_AIM of each other: from both first edges, else
    (an end too near, whose stretching no count bounds) from the finer one with the other
    end free, as :func:`graded_minimum` counts; a piece that neither bounds keeps its
    count (its gradings' own minimum has refused what they cannot do)."""
    out: dict[int, int] = {}
    for k in sorted({k for k, _ in finer}):
        length, n = topo.pieces[k].length, int(counts[k])
        asked = sorted(ends[(k, e)] / length for e in (0, 1) if (k, e) in ends)
        top = max(n, int(np.ceil(length / h))) * MAX_RAISE
        least = _least_count(n, top, *asked) if len(asked) == 2 else None
        least = least or _least_count(n, top, asked[0], None)
        if least is not None:
            out[k] = least
    return out


def side_first(topo: Topology, b: int, s: int, ends: dict[tuple[int, int], float]) -> float | None:
    """The smallest first edge ``ends`` asks of block ``b``'s sides along the grading at
    its side ``s`` (None: none asks)."""
    block, found = topo.blocks[b], []
    for along, end in (((s + 1) % 4, (s + 1) % 4), ((s - 1) % 4, s)):
        if len(block.sides[along]) != 1:
            continue
        k = block.sides[along][0][0]
        forward = _corner_key(topo.pieces[k].points[0]) == _corner_key(block.corners[end])
        if (k, 0 if forward else 1) in ends:
            found.append(ends[(k, 0 if forward else 1)])
    return min(found) if found else None


def from_corner(topo: Topology, k: int) -> bool:
    """Whether piece ``k`` is an interface with an end at a sharp corner of the boundary
    (two boundary pieces meeting there turn by CORNER_TURN or more): a line drawn from a
    step's lip or a blunt base, where a grading places a shear layer, which the solve
    keeps where it is drawn (free, the Winslow map draws it off the corner into the
    larger angle and the graded cells with it)."""
    from pinn_engine.multiblock.blocks import CORNER_TURN

    if not topo.pieces[k].interface:
        return False
    straight = float(np.cos(np.radians(CORNER_TURN)))
    for e in (0, 1):
        node = _corner_key(topo.pieces[k].points[-e])
        walls = [
            _leaving(topo, k2, e2)
            for k2, piece in enumerate(topo.pieces)
            if not piece.interface
            for e2 in (0, 1)
            if _corner_key(piece.points[-e2]) == node
        ]
        if len(walls) == 2 and float(walls[0] @ walls[1]) > -straight:
            return True
    return False
