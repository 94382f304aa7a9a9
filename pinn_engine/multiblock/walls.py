"""Walls of a multi-block grid (SPEC 10 with SPEC 7): the patches named by ``--spacing
NAME=H`` and ``--orthogonal NAME``, the grid lines that leave their pieces, and the report of
first edges and wall angles there.

A block side holding a piece of a patch is a *wall side*; the block's grid lines across it
(its columns for the bottom and top sides, its rows for left and right) leave the wall, each
given here from its wall node outward.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from pinn_engine.errors import InputError
from pinn_engine.multiblock.chains import SideItem
from pinn_engine.multiblock.layout import side_lines
from pinn_engine.multiblock.patches import PIECES, RING, PatchPiece, point_of
from pinn_engine.patchnames import checked_name

# Wall nodes this many positions or fewer from a block's corner are left out of the wall
# angle figures (SPEC 7: "the two nodes nearest each corner excepted")
ANGLE_CORNER_NODES = 1
# SPEC 7: a spaced patch's first edges are H within this share (each block side's corners
# aside, as the report's figures)
FIRST_EDGE_TOL = 0.1
# ``--spacing walls=H`` and ``--orthogonal walls``, where no patch has this name: every patch
# of type wall, else the boundary the user did not name (its default names, boundary and
# holeK), as a CFD user means "the walls" beside the inlet and outlet they named
WALLS = "walls"


@dataclass(frozen=True)
class Walls:
    """``spacing``: patch name -> first edge H (user units); ``orthogonal``: patch names;
    ``sides``: ``--spacing X,Y=H`` items, a first edge H at the block side nearest (X, Y)."""

    spacing: dict[str, float] = field(default_factory=dict)
    orthogonal: tuple[str, ...] = ()
    sides: tuple[SideItem, ...] = ()

    @property
    def names(self) -> set[str]:
        return set(self.spacing) | set(self.orthogonal)


def parse_walls(spacing: Sequence[str] = (), orthogonal: Sequence[str] = ()) -> Walls:
    """``NAME=H`` and ``X,Y=H`` items and ``NAME[,NAME...]`` items, checked (one line naming
    the item)."""
    out: dict[str, float] = {}
    sides = []
    for item in spacing:
        name, sep, value = item.partition("=")
        try:
            h = float(value)
            if not (sep and np.isfinite(h) and h > 0):
                raise ValueError
        except ValueError:
            raise InputError(
                f"spacing {item!r}: {{with_blocks}}expected NAME=H, a patch name and a first "
                "edge H > 0 (e.g. cylinder=0.005), or X,Y=H, the first edge across the block "
                "side nearest (X, Y)"
            ) from None
        point = point_of(name)
        if point is not None:
            sides.append(SideItem(*point, h, "spacing"))
            continue
        name = checked_name(name.strip(), PIECES)
        if out.setdefault(name, h) != h:
            raise InputError(f"spacing {item!r}: patch {name} is given two spacings")
    names = tuple(
        dict.fromkeys(
            checked_name(n.strip(), PIECES) for item in orthogonal for n in item.split(",")
        )
    )
    return Walls(out, names, tuple(sides))


def with_walls(walls: Walls, specs: Sequence[tuple[str, str] | None]) -> Walls:
    """``walls`` with the name ``WALLS`` (where no patch has it) read as the patches it
    means, given each piece's (name, type) ``specs`` (None: an interface): those of type
    wall, else those of the default names; a name also given on its own keeps its own
    spacing."""
    names = {spec[0]: spec[1] for spec in specs if spec is not None}
    if WALLS not in walls.names or WALLS in names:
        return walls
    meant = sorted(n for n, kind in names.items() if kind == "wall") or sorted(
        n for n, kind in names.items() if kind == "patch" and RING.match(n)
    )
    if not meant:
        raise InputError(
            f"{WALLS}: no patch of type wall and none left unnamed; the patches are "
            f"{', '.join(sorted(names))} (give the walls' type with {{pieces}})"
        )
    spacing = {n: h for n, h in walls.spacing.items() if n != WALLS}
    if WALLS in walls.spacing:
        for name in meant:
            spacing.setdefault(name, walls.spacing[WALLS])
    orthogonal = [n for n in walls.orthogonal if n != WALLS]
    if WALLS in walls.orthogonal:
        orthogonal += [n for n in meant if n not in orthogonal]
    return Walls(spacing, tuple(orthogonal), walls.sides)


def check_names(walls: Walls, patches: list[list[PatchPiece]]) -> None:
    """Refuse a spacing or orthogonal name that no boundary piece carries."""
    known = sorted({p.name for block in patches for p in block})
    for name in sorted(walls.names - set(known)):
        flag = f"spacing {name}=" if name in walls.spacing else f"orthogonal {name}"
        raise InputError(
            f"{flag}: no patch named {name!r}; the patches are {', '.join(known)} (name "
            "boundary pieces with {pieces})"
        )


@dataclass(frozen=True)
class WallSide:
    """A block side holding pieces of patch ``name``: the block's grid lines leaving it
    (``lines`` (m, n) node ids, row k from the side's node k to the opposite side) and which
    of the m side nodes lie on the patch's pieces (``on``)."""

    block: int
    side: str
    name: str
    lines: np.ndarray
    on: np.ndarray


def _side_of(piece: PatchPiece) -> tuple[str, int, int]:
    """The side a piece's node range lies on and its first and last position along it."""
    i0, j0, i1, j1 = piece.nodes
    if j0 == j1 and i0 != i1:
        return ("bottom" if j0 == 0 else "top"), i0, i1
    return ("left" if i0 == 0 else "right"), j0, j1


def wall_sides(ids: list[np.ndarray], patches: list[list[PatchPiece]], names) -> list[WallSide]:
    """Every block side holding pieces of the patches ``names``, one per side and patch."""
    found: dict[tuple[int, str, str], WallSide] = {}
    for b, pieces in enumerate(patches):
        for piece in pieces:
            if piece.name not in names:
                continue
            side, first, last = _side_of(piece)
            lines = side_lines(ids[b], side)
            key = (b, side, piece.name)
            if key not in found:
                found[key] = WallSide(b, side, piece.name, lines, np.zeros(len(lines), bool))
            found[key].on[first : last + 1] = True
    return list(found.values())


def _wall_angles(points: np.ndarray, wall: WallSide) -> np.ndarray:
    """Degrees off 90 of each line's first edge against the side's chord tangent (the
    neighbours' chord, as SPEC 6's wall angle), at the side's nodes 1..m-2."""
    side = points[wall.lines[:, 0]]
    tangent = side[2:] - side[:-2]
    leave = points[wall.lines[1:-1, 1]] - side[1:-1]
    cos = np.einsum("nk,nk->n", tangent, leave) / (
        np.linalg.norm(tangent, axis=1) * np.linalg.norm(leave, axis=1)
    )
    return np.abs(90.0 - np.degrees(np.arccos(np.clip(cos, -1.0, 1.0))))


def wall_report(
    points: np.ndarray, sides: list[WallSide], spacing: dict[str, float]
) -> dict[str, dict]:
    """Per patch: its first edges (min, median, max over its nodes, block corners aside)
    and the largest wall angle off 90 degrees (the two nodes nearest each corner aside);
    where ``spacing`` asks H of it, H and the node whose first edge is farthest from it
    (``first_edge_off``: the relative error there, and where)."""
    edges: dict[str, list[np.ndarray]] = {}
    angles: dict[str, list[np.ndarray]] = {}
    nodes: dict[str, list[np.ndarray]] = {}
    for wall in sides:
        inner = wall.on.copy()
        inner[[0, -1]] = False
        first = points[wall.lines[:, 1]] - points[wall.lines[:, 0]]
        edges.setdefault(wall.name, []).append(np.linalg.norm(first, axis=1)[inner])
        nodes.setdefault(wall.name, []).append(points[wall.lines[inner, 0]])
        keep = inner[1:-1].copy()
        keep[:ANGLE_CORNER_NODES] = keep[len(keep) - ANGLE_CORNER_NODES :] = False
        angles.setdefault(wall.name, []).append(_wall_angles(points, wall)[keep])
    out = {}
    for name in edges:
        e, a = np.concatenate(edges[name]), np.concatenate(angles[name])
        out[name] = {
            "first_edge": {
                "min": float(e.min()),
                "median": float(np.median(e)),
                "max": float(e.max()),
            },
            "max_angle_deviation": float(a.max(initial=0.0)),
        }
        h = spacing.get(name)
        if h is not None:
            off = np.abs(e / h - 1.0)
            worst = int(off.argmax())
            at = np.concatenate(nodes[name])[worst]
            out[name]["spacing"] = h
            out[name]["first_edge_off"] = {"share": float(off[worst]), "at": at.tolist()}
    return out


def first_edges_refusal(report: dict) -> str | None:
    """Why a multi-block grid whose ``report`` has the figures ``walls``
    (:func:`wall_report`) and ``gradings`` (``grading.graded_report``) breaks SPEC 7 (a
    spaced patch or a grading along a chain with a first edge off H by more than
    ``FIRST_EDGE_TOL``), a phrase, or None where every first edge keeps it."""
    figures = {**report["walls"], **report.get("gradings", {})}
    for name, patch in figures.items():
        off = patch.get("first_edge_off")
        if off is None or off["share"] <= FIRST_EDGE_TOL:
            continue
        edge, (x, y) = patch["first_edge"], off["at"]
        return (
            f"its first edges on {name} are {edge['min']:.3g} to {edge['max']:.3g}, "
            f"{patch['spacing']:g} asked (within {FIRST_EDGE_TOL:.0%}), "
            f"{off['share']:.0%} off at ({x:.4g}, {y:.4g})"
        )
    return None
