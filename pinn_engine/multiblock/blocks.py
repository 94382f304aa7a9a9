"""Blocks of a multi-block domain (SPEC 10): the faces of the linework, their four corners,
and their sides as chains of pieces, each piece shared by the one or two blocks it bounds.

shapely's ``polygonize`` finds the faces: the linework is given as its segments, which
share their end points exactly (``graph.py``), so the faces are found without any
intersection arithmetic.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import shapely
from shapely.geometry import Point, Polygon
from shapely.geometry.polygon import orient

from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import turning_angles
from pinn_engine.multiblock.graph import Linework

# A block's corner is a point of its outline that turns by at least this many degrees
# (SPEC 10: edge ends, edge junctions, sharp boundary vertices)
CORNER_TURN = 30.0
CORNERS = 4  # every block has four corners (SPEC 10)


@dataclass
class Piece:
    """A stretch of linework between two junctions: ``points`` (m, 2) in its own direction,
    the ``blocks`` it bounds (one: on the boundary or a hole; two: an interface)."""

    points: np.ndarray
    blocks: list[int] = field(default_factory=list)

    @property
    def interface(self) -> bool:
        return len(self.blocks) == 2

    @property
    def length(self) -> float:
        return float(np.linalg.norm(np.diff(self.points, axis=0), axis=1).sum())


@dataclass
class Block:
    """A four-cornered face: ``corners`` (4, 2), corner 0 the one with the smallest x + y,
    then counter-clockwise; ``sides[s]`` the pieces from corner s to corner s + 1 as
    (piece index, walked backwards) in walking order; ``inside`` a point inside it."""

    corners: np.ndarray
    sides: list[list[tuple[int, bool]]]
    inside: tuple[float, float]


@dataclass
class Topology:
    """The blocks and pieces of a domain, and its linework."""

    blocks: list[Block]
    pieces: list[Piece]
    lines: Linework


def _key(p) -> tuple[float, float]:
    return (float(p[0]), float(p[1]))


def polygon_faces(lines: Linework) -> list[Polygon]:
    """The faces of the linework inside the domain, each oriented counter-clockwise;
    refused: a face with a hole or loop inside it, and one outside the boundary."""
    pairs = []
    for k, curve in enumerate(lines.rings + lines.edges):
        closed = k < len(lines.rings)
        nxt = np.roll(curve, -1, axis=0) if closed else curve[1:]
        start = curve if closed else curve[:-1]
        pairs.append(np.stack([start, nxt], axis=1)[(start != nxt).any(axis=1)])
    segs = shapely.linestrings(np.concatenate(pairs))
    holes = [Polygon(r) for r in lines.rings[1:]]
    outer = Polygon(lines.rings[0])
    faces = []
    for face in shapely.get_parts(shapely.polygonize(segs)):
        inside = face.representative_point()
        if any(h.contains(inside) for h in holes):
            continue
        where = f"({inside.x:.4g}, {inside.y:.4g})"
        if not outer.contains(inside):
            raise InputError(f"block edges enclose a face outside the boundary at {where}")
        if face.interiors:
            raise InputError(
                f"the block at {where} has a hole or a loop inside it; join it to the "
                "boundary with block edges"
            )
        faces.append(orient(face, 1.0))
    return faces


def _corners(ring: np.ndarray, inside: Point, junctions: set) -> np.ndarray:
    """Indices of the four corners of a face's ring, starting at the corner of smallest
    x + y (ties: smallest y): the points turning by CORNER_TURN or more, then, while fewer
    than four, the ``junctions`` on the ring, largest turn first (a three-line junction
    drawn straight through is a corner of the block on its flat side); refused with the
    count when there are not four."""
    turns = np.abs(turning_angles(ring))
    found = list(np.flatnonzero(turns >= CORNER_TURN))
    if len(found) < CORNERS:
        more = [k for k in range(len(ring)) if _key(ring[k]) in junctions and k not in found]
        more.sort(key=lambda k: -turns[k])
        found = sorted(found + more[: CORNERS - len(found)])
    if len(found) != CORNERS:
        raise InputError(
            f"the block at ({inside.x:.4g}, {inside.y:.4g}) has {len(found)} corners (points "
            f"where its outline turns by {CORNER_TURN:g} degrees or more, and junctions "
            "where it has fewer); every block needs exactly 4: add or move block edges"
        )
    found = np.array(found)
    first = min(range(CORNERS), key=lambda k: (ring[found[k]].sum(), ring[found[k], 1]))
    return np.roll(found, -first)


def topology(lines: Linework) -> Topology:
    """Blocks and pieces of checked linework: each face a block with four corners, its sides
    cut into pieces at every junction (a point where three or more curves meet, or any
    block's corner), a piece shared by the blocks on both sides of it."""
    faces = polygon_faces(lines)
    rings = [np.asarray(f.exterior.coords)[:-1] for f in faces]
    degree: dict[tuple, int] = {}
    for k, curve in enumerate(lines.rings + lines.edges):
        closed = k < len(lines.rings)
        for i, p in enumerate(curve):
            inner = closed or 0 < i < len(curve) - 1
            degree[_key(p)] = degree.get(_key(p), 0) + (2 if inner else 1)
    junctions = {k for k, d in degree.items() if d != 2}
    cuts = [_corners(r, f.representative_point(), junctions) for r, f in zip(rings, faces)]
    junctions |= {_key(r[c]) for r, cs in zip(rings, cuts) for c in cs}
    pieces: list[Piece] = []
    index: dict[bytes, int] = {}
    blocks = []
    for b, (ring, corners, face) in enumerate(zip(rings, cuts, faces)):
        sides = []
        for s in range(4):
            a, z = corners[s], corners[(s + 1) % 4]
            walk = np.concatenate([ring[a:], ring[:z]]) if z <= a else ring[a:z]
            walk = np.vstack([walk, ring[z]])
            sides.append(_pieces_of(walk, junctions, pieces, index, b))
        inside = face.representative_point()
        blocks.append(Block(ring[corners], sides, (inside.x, inside.y)))
    return Topology(blocks, pieces, lines)


def _pieces_of(
    walk: np.ndarray,
    junctions: set,
    pieces: list[Piece],
    index: dict[bytes, int],
    block: int,
) -> list[tuple[int, bool]]:
    """A side (points from corner to corner) as pieces cut at ``junctions``; a piece seen
    before (from the block on its other side) is shared, else added."""
    cut = [0] + [i for i in range(1, len(walk) - 1) if _key(walk[i]) in junctions]
    cut.append(len(walk) - 1)
    out = []
    for a, z in zip(cut[:-1], cut[1:]):
        pts = walk[a : z + 1]
        backwards = _key(pts[0]) > _key(pts[-1]) or (
            _key(pts[0]) == _key(pts[-1]) and _key(pts[1]) > _key(pts[-2])
        )
        canon = pts[::-1] if backwards else pts
        key = np.ascontiguousarray(canon).tobytes()
        if key not in index:
            index[key] = len(pieces)
            pieces.append(Piece(np.array(canon)))
        pieces[index[key]].blocks.append(block)
        out.append((index[key], bool(backwards)))
    return out
