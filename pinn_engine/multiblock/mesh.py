"""Mesh a multi-block domain (SPEC 10): linework, blocks, cell counts, nodes, then the
method (``tfi``: each block's TFI on the shared side nodes; ``elliptic``: Winslow on all
blocks at once; ``pinn``: the elliptic grid, then each block's PINN on its side nodes,
``kinds/blocks/problem.py``), with the quality figures of every block and of the interfaces."""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from pinn_engine.errors import InputError, network_effect
from pinn_engine.geometry.auxlines import RawLine, line_distances
from pinn_engine.multiblock.blocks import Topology, topology
from pinn_engine.multiblock.chains import (
    SideItem,
    from_corner,
    graded_ends,
    graded_minimum,
    graded_params,
    graded_sides,
    joint_ends,
    joint_minimum,
    nearest_piece,
    piece_chains,
    ratio_lines,
    ratio_params,
    side_first,
)
from pinn_engine.multiblock.counts import cell_counts, default_cell_size
from pinn_engine.multiblock.elliptic import MAX_ITERATIONS, Crossing, crossings, winslow
from pinn_engine.multiblock.grading import graded_asks, graded_lines, graded_report
from pinn_engine.multiblock.graph import linework
from pinn_engine.multiblock.layout import Layout, layout, side_lines
from pinn_engine.multiblock.orthogonal import boundary_neighbours, orthogonal
from pinn_engine.multiblock.patches import (
    PatchPiece,
    PatchPoint,
    PatchRing,
    block_patches,
    piece_patches,
)
from pinn_engine.multiblock.quadblock import block_boundary, block_lines
from pinn_engine.multiblock.spacing import (
    check_room,
    fitted_first_edges,
    held_pieces,
    on_drawn,
    requests,
    respace,
    spread,
    untangled_blocks,
    wall_nodes,
)
from pinn_engine.multiblock.walls import (
    Walls,
    check_names,
    wall_report,
    wall_sides,
    with_walls,
)
from pinn_engine.quality import cell_quality, ranks_above, summary
from pinn_engine.settings import MAX_NODES, MULTIBLOCK_METHODS, Settings

# Interface nodes this many positions or fewer from a block's corner are left out of the
# kink figures (the two nodes nearest each block corner): at a corner grid lines
# of three or more blocks meet and no line runs straight through
KINK_CORNER_NODES = 2

Progress = Callable[[dict], "bool | str | None"]  # trainer.Progress, without importing torch
# The pinn's training of the blocks' elliptic grids: kinds.blocks.problem.train_blocks, which the
# caller passes in (the block kinds are a layer above this package, and import torch)
TrainBlocks = Callable[..., tuple[list[np.ndarray], dict]]
# A block's grid (nj, ni, 2) with its folds undone and its sides held (starts.untangle, a
# layer above this package)
Untangle = Callable[[np.ndarray], np.ndarray]


class StartNodes(Protocol):
    """Where the Winslow solve starts (a family model's, SPEC 16, a layer above this
    package): called with the blocking and its layout, the unique nodes (N, 2) whose solved
    nodes start the solve, or None for the layout's own; ``note`` then adds what it did to
    the run's report (``solve_start`` says which start the grid was solved from)."""

    def __call__(self, topo: Topology, lay: Layout) -> np.ndarray | None: ...

    def note(self, report: dict) -> None: ...


@dataclass
class MultiBlockResult:
    """Each block's grid (nj, ni, 2), its per-cell quality arrays, the report, and each
    block's boundary pieces with their patches (``patches.py``)."""

    grids: list[np.ndarray]
    cells: list[dict[str, np.ndarray]]
    report: dict
    patches: list[list[PatchPiece]]


def _figures(cells: list[dict[str, np.ndarray]]) -> dict[str, float]:
    """SPEC 6's figures over the cells of all blocks (the boundary lies on the input)."""
    joined = {k: np.concatenate([c[k].ravel() for c in cells]) for k in cells[0]}
    figures = summary(joined, 0.0)
    figures.pop("boundary_deviation")
    return figures


def _tfi_ranks_better(
    lay: Layout, cross: list[Crossing], tfi: np.ndarray, elliptic: np.ndarray
) -> bool:
    """Whether the blocks' TFI grid (the interfaces as drawn) ranks above the elliptic grid
    (``quality.ranks_above``) with grid lines kinking no more across the interfaces (mean):
    the default's start then (a step's rectangles: TFI is orthogonal, where the solve with
    free interfaces shears the cells round the step's lip)."""
    t, e = (_figures([cell_quality(p[ids]) for ids in lay.ids]) for p in (tfi, elliptic))
    kinks = [interface_kinks(cross, lay, p) for p in (tfi, elliptic)]
    return ranks_above(t, e) and (kinks[0].mean() if kinks[0].size else 0.0) <= (
        kinks[1].mean() if kinks[1].size else 0.0
    )


def _turns(u: np.ndarray, v: np.ndarray) -> np.ndarray:
    """180 minus the angle in degrees between the edges ``u`` and ``v`` (n, 2) leaving a
    node: how far the grid line through it turns there."""
    cos = np.einsum("nk,nk->n", u, v) / (np.linalg.norm(u, axis=1) * np.linalg.norm(v, axis=1))
    return 180.0 - np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))


def interface_kinks(
    cross: list[Crossing], lay: Layout, points: np.ndarray, depth: int = 0
) -> np.ndarray:
    """At each node of the interfaces ``cross`` (:func:`elliptic.crossings`; those near a
    block corner aside), 180 minus the angle in degrees between the two blocks' grid edges
    leaving it: 0 where a grid line runs straight across the interface. With ``depth``
    d > 0, the turn of the same grid lines at their d-th node inside each block (both
    blocks' values): a smooth grid line turns about as much there as across the
    interface."""
    out = []
    for c in cross:
        keep = np.ones(len(c.nodes), dtype=bool)
        for b, (side, ks) in zip(c.blocks, c.places):
            n = lay.ids[b].shape[1 if side in ("bottom", "top") else 0]
            keep &= (ks > KINK_CORNER_NODES) & (ks < n - 1 - KINK_CORNER_NODES)
        if depth == 0:
            at = points[c.nodes[keep]]
            out.append(_turns(points[c.inward[0][keep]] - at, points[c.inward[1][keep]] - at))
            continue
        for b, (side, ks) in zip(c.blocks, c.places):
            lines = side_lines(lay.ids[b], side)[ks[keep]]
            at = points[lines[:, depth]]
            out.append(_turns(points[lines[:, depth - 1]] - at, points[lines[:, depth + 1]] - at))
    return np.concatenate(out) if out else np.zeros(0)


def mesh_blocks(
    rings: list[np.ndarray],
    edges: list[np.ndarray],
    names: list[str],
    settings: Settings,
    source: str = "boundary",
    patch_points: Sequence[PatchPoint | PatchRing] = (),
    walls: Walls | None = None,
    progress: Progress | None = None,
    aux: Sequence[RawLine] = (),
    train: TrainBlocks | None = None,
    cells: Sequence[SideItem] = (),
    untangle: Untangle | None = None,
    gradings: Sequence[SideItem] = (),
    start: StartNodes | None = None,
) -> MultiBlockResult:
    """The multi-block grid of a boundary's ``rings`` (outer and holes) and block
    ``edges`` (named ``names`` in messages) by ``settings.method`` (tfi, elliptic or pinn),
    cells about ``settings.cell_size`` long (0: the diagonal over 40), interfaces free or
    fixed; ``patch_points`` name boundary pieces (``patches.py``); ``walls``: spacing and
    orthogonality on patches (``spacing.py``, ``orthogonal.py``), after the method;
    ``train`` trains the pinn's blocks and ``progress`` hears it, block by block;
    ``aux``: auxiliary lines (user (x, y)) inside blocks, each in the block holding it
    (``quadblock.block_lines``), fitted by the pinn; every method reports how far its grid
    is from them; ``cells``: ``--cells X,Y=N`` items (``chains.py``); ``untangle``: undoes a
    block's folds after gradings and patch spacings move its nodes
    (``starts.untangle.untangle``, passed in by the caller); ``gradings``: ``--grading
    X,Y=R`` items, expansion ratios along chains (``chains.ratio_params``); ``start``: where
    the elliptic solve starts, asked once the layout is known (a family model's nodes)."""
    if settings.method not in MULTIBLOCK_METHODS:
        raise InputError(
            f"method {settings.method}: multi-block domains are meshed by "
            f"{', '.join(MULTIBLOCK_METHODS[:-1])} or {MULTIBLOCK_METHODS[-1]} in this build",
            source,
        )
    if settings.method == "pinn" and train is None:
        raise ValueError("method pinn: pass train=kinds.blocks.problem.train_blocks")
    began = time.perf_counter()
    lines = linework(rings, edges, names, source)
    topo = topology(lines)
    h = settings.cell_size or default_cell_size(lines.diagonal)
    walls = with_walls(walls or Walls(), piece_patches(topo, patch_points))
    fixed = {nearest_piece(topo, item): item for item in cells}
    counts = cell_counts(topo, h, fixed)
    sized = _cells(topo, counts)  # the cells of the cell size alone, before any grading
    grades = [(item, graded_sides(topo, nearest_piece(topo, item))) for item in walls.sides]
    if grades:
        spaced = {
            k: walls.spacing[spec[0]]
            for k, spec in enumerate(piece_patches(topo, patch_points))
            if spec is not None and spec[0] in walls.spacing
        }
        minimum: dict[int, tuple[int, SideItem]] = {}
        for item, graded in grades:
            for piece, n in graded_minimum(topo, graded, h, counts, item, spaced).items():
                if n > minimum.get(piece, (0, item))[0]:
                    minimum[piece] = (n, item)
    ends: dict[tuple[int, int], float] = {}
    for item, graded in grades:
        for end, first in graded_ends(topo, graded, item.value).items():
            ends[end] = min(first, ends.get(end, first))
    if grades:
        alone, ends = ends, joint_ends(topo, ends, spaced)
        chain = piece_chains(topo)
        held_chains = {chain[p] for p in fixed}  # --cells counts stay as given
        finer = {
            end: first
            for end, first in ends.items()
            if first < alone.get(end, np.inf) and chain[end[0]] not in held_chains
        }
        for piece, n in joint_minimum(topo, finer, ends, counts, h).items():
            if n > minimum.get(piece, (0, None))[0]:
                minimum[piece] = (n, grades[0][0])
        counts = cell_counts(topo, h, fixed, minimum)
    params = graded_params(topo, ends, counts)
    ratios = ratio_params(topo, gradings, counts, set(params))
    params.update(ratios)
    lay = layout_checked(topo, counts, h, params)
    patches = block_patches(topo, lay, patch_points)  # refused before the solve, not after
    check_names(walls, patches)
    sides = wall_sides(lay.ids, patches, walls.names)
    ends_of_pieces = {int(nodes[e]) for nodes in lay.piece_ids for e in (0, -1)}
    boundary_nodes = np.zeros(len(lay.points), dtype=bool)
    for piece, nodes in zip(topo.pieces, lay.piece_ids):
        boundary_nodes[nodes] |= not piece.interface
    pieces, asked = held_pieces(
        spread(requests(sides, walls.spacing), lay.ids, lay.points, ends_of_pieces, boundary_nodes),
        ends_of_pieces,
        wall_nodes(sides, walls.spacing),
        lay.ids,
    )
    asked = pieces | asked
    check_room(lay.points, asked)
    steps = 0
    points = lay.points
    timings = {"layout": time.perf_counter() - began}
    first = start(topo, lay) if start is not None else None
    solve_start = "layout" if first is None else "given"
    if settings.method in ("elliptic", "pinn"):
        held_sides = frozenset(
            k for item, _ in grades if from_corner(topo, k := nearest_piece(topo, item))
        )
        free = settings.interfaces == "free"
        points, steps = winslow(topo, lay, free, held=held_sides, start=first)
        if first is not None and steps >= MAX_ITERATIONS:  # not converged: the layout's
            points, steps = winslow(topo, lay, free, held=held_sides)
            solve_start = "layout (the given start did not converge)"
    timings["solve"] = time.perf_counter() - began - timings["layout"]
    lines = block_lines(aux, [points[ids] for ids in lay.ids])  # the method's block sides
    cross = crossings(topo, lay)  # the interfaces' nodes, for every kink figure below
    frames = [block_boundary(points[ids]) for ids in lay.ids]
    training = None
    elliptic = points
    if settings.method == "pinn":
        chosen = "tfi" if _tfi_ranks_better(lay, cross, lay.points, points) else "elliptic"
        points = lay.points if chosen == "tfi" else points

        def kinks(grids: list[np.ndarray]) -> np.ndarray:
            return interface_kinks(cross, lay, _assembled(points, lay, grids))

        starts = [points[ids] for ids in lay.ids]
        grids, training = train(starts, settings, progress, lines, kinks)
        training["start"] = chosen
        points = _assembled(points, lay, grids)
        timings["training"] = training["seconds"]

    graded = [
        (item, side, sign, min(item.value, side_first(topo, *side, ends) or item.value))
        for item, g in grades
        for side, sign in g.items()
    ]
    graded_ask = graded_asks(lay.ids, graded, boundary_nodes, asked)

    def finished(points: np.ndarray) -> np.ndarray:
        """Gradings along chains, first edges of patches, blocks these fold untangled, and
        orthogonality on patches, last: no solve or training moves them after."""
        points, rest = graded_lines(points, lay.ids, graded, boundary_nodes, asked)
        points = respace(points, ratio_lines(topo, lay.ids, ratios, points))
        points = respace(points, {key: ask for key, ask in rest.items() if key in pieces})
        points = respace(points, {key: ask for key, ask in rest.items() if key not in pieces})
        if grades or asked or ratios:
            points = on_drawn(points, boundary_nodes, rings)
        if (grades or asked) and untangle is not None:
            points = untangled_blocks(points, lay.ids, untangle)
        if asked or graded:
            inner = {k: ask for k, ask in graded_ask.items() if not boundary_nodes[list(k)].all()}
            points = fitted_first_edges(points, sides, walls.spacing, inner)
        if walls.orthogonal:
            points = orthogonal(
                points, sides, walls.orthogonal, boundary_neighbours(topo, lay), lay.ids
            )
        return points

    points = finished(points)
    grids = [points[ids] for ids in lay.ids]
    cells = [cell_quality(g) for g in grids]
    if training is not None:  # the elliptic run's figures, for what the pinn chose
        changed = (
            training["network_blocks"]
            or any("untangled" in b for b in training["blocks"])
            or training["start"] != "elliptic"
        )
        done = finished(elliptic) if changed else points
        training["guard"] = {"elliptic": _figures([cell_quality(done[ids]) for ids in lay.ids])}
    kinks = interface_kinks(cross, lay, points)
    inside = interface_kinks(cross, lay, points, depth=1)
    report = {
        "method": settings.method,
        "interfaces": settings.interfaces,
        "cell_size": h,
        "blocks": len(grids),
        "cells": int(sum(c["Folded"].size for c in cells)),
        "sizes": [list(g.shape[1::-1]) for g in grids],
        "quality": _figures(cells),
        "interface_kink": {
            "mean": float(kinks.mean()) if kinks.size else 0.0,
            "max": float(kinks.max()) if kinks.size else 0.0,
            "nodes": int(kinks.size),
            "inside_mean": float(inside.mean()) if inside.size else 0.0,
        },
        "graded_cells": {"from": sized, "to": _cells(topo, counts)},
        "iterations": steps,
        "walls": wall_report(points, sides, walls.spacing),
        "gradings": graded_report(
            points,
            lay.ids,
            graded,
            graded_ask,
            wall_nodes(sides, walls.spacing),
        ),
        "aux_lines": [line.name for block in lines for line in block],
        "aux_line_distance": {
            name: d
            for grid, frame, mine in zip(grids, frames, lines)
            for name, d in line_distances(frame.frame.to_unit(grid), mine, frame.diagonal).items()
        },
        "mesh_seconds": time.perf_counter() - began,
    }
    timings["walls_and_quality"] = report["mesh_seconds"] - sum(timings.values())
    report["timings"] = timings
    if training is not None:
        report["training"] = training
        report["choice"] = network_effect(report)
    if start is not None:
        report["solve_start"] = solve_start
        start.note(report)
    return MultiBlockResult(grids, cells, report, patches)


def _cells(topo: Topology, counts: np.ndarray) -> int:
    """The cells of all blocks for the pieces' cell ``counts``."""
    return int(
        sum(
            sum(counts[p] for p, _ in block.sides[0]) * sum(counts[p] for p, _ in block.sides[1])
            for block in topo.blocks
        )
    )


def _assembled(points: np.ndarray, lay: Layout, grids: list[np.ndarray]) -> np.ndarray:
    """The unique nodes ``points`` with each block's nodes set from its grid (shared nodes
    are equal in every block)."""
    out = points.copy()
    for ids, grid in zip(lay.ids, grids):
        out[ids] = grid
    return out


def layout_checked(
    topo: Topology, counts: np.ndarray, h: float, graded: dict[int, np.ndarray] | None = None
) -> Layout:
    """:func:`layout`, refused before it is built when the grid would exceed MAX_NODES."""
    nodes = 0
    for block in topo.blocks:
        ni = sum(counts[p] for p, _ in block.sides[0]) + 1
        nj = sum(counts[p] for p, _ in block.sides[1]) + 1
        nodes += ni * nj
    if nodes > MAX_NODES:
        raise InputError(
            f"a cell size of {h:g} gives {nodes:,} nodes; at most {MAX_NODES:,}: choose a "
            "larger cell size"
        )
    return layout(topo, counts, graded)
