"""Boundary patches of a multi-block domain (SPEC 10): each boundary piece (a stretch of the
boundary or of a hole between two junctions or block corners) is a patch, named ``boundary``
(the outer boundary) or ``hole1``, ``hole2``, ... by default; ``--patch X,Y=NAME[:TYPE]``
names the piece nearest the point (X, Y), ``--patch hole1=NAME[:TYPE]`` (or ``boundary=``)
every piece of that ring. Pieces of one name form one patch.
"""

from __future__ import annotations

import re
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from shapely.geometry import LineString, Point

from pinn_engine.errors import InputError
from pinn_engine.multiblock.blocks import Topology
from pinn_engine.multiblock.layout import Layout
from pinn_engine.patchnames import checked_name, default_type, split_type

OUTER = "boundary"  # SPEC 10: the default name of the outer boundary's pieces
HOLE = "hole"  # SPEC 10: hole k's pieces are named hole1, hole2, ...
PIECES = "{pieces}"  # the route token an error about a piece's name or type points to
# A --patch point farther than this share of the domain's diagonal from every boundary
# piece is refused: a point meant for a piece lies on or near it; one this far is a typo
FAR = 0.05
# A --patch point whose two nearest pieces are within this share of the diagonal of each
# other's distance lies where they meet: it names both where they continue one straight side
# (a block corner on it, as automatic blocking places them), and is refused as ambiguous at
# a corner of the boundary
TIE = 1e-3
# two pieces continue one straight side where their directions at the end they share differ
# by less than this many degrees (a drawn corner turns by more: SPEC 1's sharp corners)
STRAIGHT = 1.0


@dataclass(frozen=True)
class PatchPiece:
    """A boundary piece on one block: its patch ``name`` and ``kind`` (``patchnames.TYPES``),
    and its 0-based node range ``(i0, j0, i1, j1)`` along one side of the block (i0 <= i1,
    j0 <= j1)."""

    name: str
    kind: str
    nodes: tuple[int, int, int, int]


RING = re.compile(rf"^({OUTER}|{HOLE}[1-9][0-9]*)$")  # a ring's default name, as items give it


@dataclass(frozen=True)
class PatchPoint:
    """One ``--patch X,Y=NAME[:TYPE]`` item: the point, the name, the type or None."""

    x: float
    y: float
    name: str
    kind: str | None


@dataclass(frozen=True)
class PatchRing:
    """One ``--patch RING=NAME[:TYPE]`` item: the ring (``boundary``, ``hole1``, ...), the
    name, the type or None."""

    ring: str
    name: str
    kind: str | None


def point_of(where: str) -> tuple[float, float] | None:
    """``X,Y`` as two finite numbers, else None (the left side of a ``--patch``,
    ``--spacing`` or ``--cells`` item that names a place)."""
    parts = where.split(",")
    try:
        x, y = (float(p) for p in parts)
    except ValueError:
        return None
    return (x, y) if np.isfinite(x) and np.isfinite(y) else None


def parse_patch_points(items: Sequence[str] | None) -> list[PatchPoint | PatchRing]:
    """``X,Y=NAME[:TYPE]`` and ``RING=NAME[:TYPE]`` items, checked (one line naming the bad
    item)."""
    out: list[PatchPoint | PatchRing] = []
    for item in items or ():
        where, sep, named = item.partition("=")
        point = point_of(where)
        if not sep or (point is None and not RING.match(where.strip())):
            raise InputError(
                f"patch {item!r}: {{with_blocks}}expected X,Y=NAME[:TYPE] naming the boundary "
                f"piece nearest the point (X, Y), or {OUTER}=NAME[:TYPE] or {HOLE}K=NAME[:TYPE] "
                "naming every piece of the outer boundary or of hole K"
            )
        name, kind = split_type(named.strip(), PIECES)
        name = checked_name(name, PIECES)
        out.append(
            PatchRing(where.strip(), name, kind)
            if point is None
            else PatchPoint(*point, name, kind)
        )
    return out


def _default_names(topo: Topology) -> list[str | None]:
    """Each piece's default patch name: ``boundary`` or ``holeK`` on the rings, None for
    interfaces."""
    ring_of = {(float(x), float(y)): k for k, ring in enumerate(topo.lines.rings) for x, y in ring}
    out: list[str | None] = []
    for piece in topo.pieces:
        if piece.interface:
            out.append(None)
            continue
        k = ring_of[(float(piece.points[0, 0]), float(piece.points[0, 1]))]
        out.append(OUTER if k == 0 else f"{HOLE}{k}")
    return out


def _continued(topo: Topology, a: int, b: int) -> bool:
    """Whether pieces ``a`` and ``b`` share an end where they continue one straight side."""
    pa, pb = topo.pieces[a].points, topo.pieces[b].points
    for ea, eb in ((0, 0), (0, -1), (-1, 0), (-1, -1)):
        if np.allclose(pa[ea], pb[eb]):
            da = pa[1 if ea == 0 else -2] - pa[ea]  # each leaving the shared end
            db = pb[1 if eb == 0 else -2] - pb[eb]
            cos = -np.dot(da, db) / (np.linalg.norm(da) * np.linalg.norm(db))
            return cos >= np.cos(np.radians(STRAIGHT))
    return False


def _nearest(topo: Topology, point: PatchPoint, candidates: list[int]) -> list[int]:
    """The boundary piece nearest ``point``, or the two it lies between where they continue
    one straight side; refused when it is far from all or between two at a corner."""
    p = Point(point.x, point.y)
    dist = np.array([LineString(topo.pieces[k].points).distance(p) for k in candidates])
    order = np.argsort(dist)
    where = f"({point.x:g}, {point.y:g})"
    diagonal = topo.lines.diagonal
    if dist[order[0]] > FAR * diagonal:
        raise InputError(
            f"patch {where}={point.name}: the point is {dist[order[0]]:.3g} from the nearest "
            f"boundary piece (at most {FAR * diagonal:.3g}); put it on the piece to name"
        )
    if len(order) > 1 and dist[order[1]] - dist[order[0]] <= TIE * diagonal:
        pair = [candidates[order[0]], candidates[order[1]]]
        if len(order) > 2 and dist[order[2]] - dist[order[0]] <= TIE * diagonal:
            pair = []  # three pieces meet there: no one side to name
        if not pair or not _continued(topo, *pair):
            raise InputError(
                f"patch {where}={point.name}: the point is as near to two boundary pieces (a "
                "corner of the boundary); put it inside the piece to name"
            )
        return pair
    return [candidates[order[0]]]


def _ring_pieces(topo: Topology, defaults: list[str | None], item: PatchRing) -> list[int]:
    """The pieces of the ring an item names; refused when the domain has no such ring."""
    found = [k for k, n in enumerate(defaults) if n == item.ring]
    if not found:
        holes = len(topo.lines.rings) - 1
        known = ", ".join([OUTER] + [f"{HOLE}{k}" for k in range(1, holes + 1)])
        raise InputError(
            f"patch {item.ring}={item.name}: the domain has no ring {item.ring} (its rings: "
            f"{known})"
        )
    return found


def piece_patches(
    topo: Topology, items: Sequence[PatchPoint | PatchRing]
) -> list[tuple[str, str] | None]:
    """Each piece's (patch name, type), None for interfaces: defaults, then the ring items,
    then the point items (a point names one piece of a ring named as a whole, or the two it
    lies between on one straight side). Pieces of
    one name must agree on its type; a name without a type gets the type given to it
    elsewhere, else ``default_type``."""
    defaults = _default_names(topo)
    names = list(defaults)
    boundary = [k for k, n in enumerate(names) if n is not None]
    given: dict[str, str] = {}
    named: dict[int, str] = {}
    rings = [item for item in items if isinstance(item, PatchRing)]
    points = [item for item in items if isinstance(item, PatchPoint)]
    for item in rings + points:
        if isinstance(item, PatchRing):
            where = item.ring
            for k in _ring_pieces(topo, defaults, item):
                names[k] = item.name
        else:
            where = f"({item.x:g}, {item.y:g})"
            for k in _nearest(topo, item, boundary):
                if named.setdefault(k, item.name) != item.name:
                    raise InputError(
                        f"patch {where}={item.name}: that piece is already named {named[k]}"
                    )
                names[k] = item.name
        if item.kind is not None and given.setdefault(item.name, item.kind) != item.kind:
            raise InputError(
                f"patch {item.name!r} is given two types, {given[item.name]} and {item.kind} "
                f"(at {where})"
            )
    return [None if n is None else (n, given.get(n, default_type(n))) for n in names]


def _range(ids: np.ndarray, nodes: np.ndarray) -> tuple[int, int, int, int]:
    """The (i0, j0, i1, j1) of a piece's ``nodes`` on a side of a block of node ``ids``."""
    for side in (ids[0], ids[:, -1], ids[-1], ids[:, 0]):
        if np.isin(nodes, side).all():
            jj, ii = np.nonzero(np.isin(ids, nodes))
            return int(ii.min()), int(jj.min()), int(ii.max()), int(jj.max())
    raise AssertionError("a boundary piece lies on no side of its block")


def block_patches(
    topo: Topology, lay: Layout, points: Sequence[PatchPoint | PatchRing] = ()
) -> list[list[PatchPiece]]:
    """Per block, its boundary pieces with their patch names, types and node ranges."""
    out: list[list[PatchPiece]] = [[] for _ in topo.blocks]
    for piece, spec, nodes in zip(topo.pieces, piece_patches(topo, points), lay.piece_ids):
        if spec is None:
            continue
        b = piece.blocks[0]
        out[b].append(PatchPiece(*spec, _range(lay.ids[b], nodes)))
    return out
