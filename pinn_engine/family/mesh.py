"""A member meshed by a family model: the model's grid, the guard, and the report.

The guard is section 4's: a grid with a folded cell, or whose worst cell is more than
``WORST_TOL`` degrees above the member's own start's, falls back to that start with a
warning. A body's grid is kept, without its own start (its elliptic grid) or its own run's
optimisation, where it has no fold and its worst angle is within ``WORST_TOL`` of its held
first layer's, which bounds its start's and its own run's grid from below
(:func:`held_worst`); else its start is solved and it is optimised as its own run is. A
four-sided member's start (the grid its own run starts from) costs what the default run
costs, so it is solved only where the model cannot vouch for its grid without it:

- a family of Winslow grids vouches for a grid that one more linearised Winslow step moves
  by at most ``DEFECT_TOL`` of the shortest edge at any node, and keeps that step (the steps
  contract towards the member's own Winslow grid, by a factor of about 0.2 a step measured
  on the channels of docs/family.md, so the step's cells' angles are within a fraction of a
  degree of it); up to ``DEFECT_STEPS`` steps are taken to get there;
- a family of node optima (the default's four-sided grids: the quality objective's best
  start, its nodes optimised) finishes the model's grid (:func:`polish_start`) by the
  member's own node optimisation (quality_start.sharpened: its own ranking, three of its
  stages, ``POLISH_SHARPENING``; from the model's grid or a blend towards it, the last
  alone after one that settled), each stage until it settles (``POLISH_SETTLE``; at most
  ``model.polish`` iterations), and
  vouches for a polished grid that ranks no worse than the grid the member's
  own optimisation starts from (the best of its elliptic, TFI and blended grids, which cost
  milliseconds once its elliptic grid, the model's base, is solved): what its own run would
  keep were its optimisation stopped there;
- another family's grid (no cheap certificate) is compared with the member's own start,
  solved: it is kept where it passes, and the member gains nothing in time;
- a multi-block member's grid is its own run's Winslow solve, choice and tolerance, started
  from the model's nodes (:class:`BlocksStart`), its sliding edge ends held where the model
  puts them on the wall (``multiblock.elliptic.winslow``): a model grid with a folded cell,
  or a solve from it that does not converge, gives way to its own run from its layout.
"""

from __future__ import annotations

import os
import time
from collections import OrderedDict
from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.family.members import Member, blocks_member, member_of, refuse_blocks_options
from pinn_engine.family.model import FamilyModel, load_family
from pinn_engine.geometry.boundary import Frame
from pinn_engine.geometry.plane import Plane
from pinn_engine.quality import (
    boundary_nodes,
    cell_quality,
    side_report,
    summary,
)
from pinn_engine.result import MeshResult
from pinn_engine.settings import Settings

if TYPE_CHECKING:
    from pinn_engine.starts.quality_start import Ranking

WORST_TOL = 2.0  # SPEC 16: degrees the worst cell may exceed the member's start's
# One more linearised step moves no node by more than this share of its shortest edge: a
# corner's angle then moves by at most about four times it in radians, 1.2 degrees
DEFECT_TOL = 0.005
DEFECT_STEPS = 6  # chord steps tried (0.3 ms each at 41 x 21; the default solve takes 15 ms)
# Each stage of a four-sided member's polish stops once 15 iterations lowered its best-ranked
# worst angle by under 0.05 degrees (or it is its held corners'), keeping the state of least
# mean within 0.25 of it (Settle): with the stages below, on 96 unseen channels of six draws
# it left each within 0.03 of its own worst and 0.39 of its mean at a median 87 evaluations
# (its own run: 173); a window of 10 left one 0.57 above (docs/family.md, "The polish")
POLISH_SETTLE = (15, 0.05, 0.25)
# The polish's stages (temperatures in QUALITY_TAU's), each a quarter of the one before and
# the last the own run's (its grids are that stage's end): 2 degrees moves the band of cells
# the model's grid misses together; from 1 degree the median was 103 evaluations, not 87.
# From a model's grid a stage that settled leaps to the last (median 69, within 0.19 of each
# own worst and mean); from the own start (all blends ranked below) every stage runs
POLISH_SHARPENING = (2.0, 1 / 2, 1 / 8)
KEPT_MODELS = 4  # family models kept loaded in a process (a batch worker meshes many members)
_LOADED: OrderedDict[tuple, FamilyModel] = OrderedDict()


def _model(path: str | os.PathLike | FamilyModel) -> FamilyModel:
    """The family model at ``path`` (or ``path`` itself, a fitted model), loaded once per
    process while the file is unchanged."""
    if isinstance(path, FamilyModel):
        return path
    p = Path(path)
    stat = p.stat() if p.is_file() else None
    key = (str(p.resolve()), stat.st_mtime_ns if stat else 0, stat.st_size if stat else 0)
    if key not in _LOADED:
        model = load_family(path)
        model.path = str(path)
        _LOADED[key] = model
        while len(_LOADED) > KEPT_MODELS:
            _LOADED.popitem(last=False)
    _LOADED.move_to_end(key)
    return _LOADED[key]


def family_size(path: str | os.PathLike) -> tuple[int, int]:
    """The node counts of the family model at ``path`` (a run that names none takes them)."""
    return tuple(_model(path).size)


def _start(member: Member, settings: Settings) -> np.ndarray:
    """The member's own start (family frame): a body's elliptic grid; a four-sided member's
    start under ``settings`` (``kinds.four_sided.untrained.StartModel``: the grid its own run starts
    from, and keeps where no network trains)."""
    if member.kind == "body":
        member.body_start()
        return member.elliptic
    from pinn_engine.kinds.four_sided.untrained import StartModel

    start = StartModel.of(member.boundary, (), settings, "the family model's grid failed")
    return start.grid(*member.size)


def mesh_member(
    path: str | os.PathLike | FamilyModel,
    settings: Settings,
    boundary=None,
    aux: Sequence = (),
    body=None,
    far=None,
) -> MeshResult:
    """The grid of a member (a four-sided ``boundary``, or a ``body`` in ``far``) by the
    family model at ``path`` (or a fitted model), under ``settings`` (which must be the
    family's)."""
    began = time.perf_counter()
    model = _model(path)
    member = member_of(settings, boundary, aux, body, far)
    model.check(member, settings)
    body = member.kind == "body"
    if body and not model.polish:  # no certificate without its start: the model corrects it
        member.body_start()
    placed = time.perf_counter()
    grid, info = model.predict(member)
    predicted = time.perf_counter()
    defect, steps = None, 0
    while model.winslow and steps < DEFECT_STEPS:
        grid, defect = model.frozen().step(grid)
        steps += 1
        if defect <= DEFECT_TOL:
            break
    reference, polished_from, points = None, None, None
    vouched = model.winslow and defect is not None and defect <= DEFECT_TOL
    if model.polish and body:  # the model's grid's arrays: its certificate's, kept with it
        points = member.frame.to_user(grid)
        cells = cell_quality(points)
        chosen, polished_from = _body_chosen(model, member, grid, _figures(cells))
        if chosen is not grid:
            grid, points = chosen, None
        vouched = True  # certified, or no worse than the member's elliptic start
    elif model.polish:
        grid, reference, vouched, polished_from = _polished(model, member, grid)
    if points is None:
        points = member.frame.to_user(grid)
        cells = cell_quality(points)
    figures = _figures(cells)
    start = None
    if not vouched:  # no certificate: the member's start decides
        start, start_points, start_cells = _start_grid(member, settings)
        reference = _figures(start_cells)
    elif body and member.start is not None:  # solved for its optimisation: measured
        reference = _figures(member.start.cells)
    passed = not figures["folded_cells"] and (
        vouched or figures["worst_max_angle"] <= reference["worst_max_angle"] + WORST_TOL
    )
    if not passed:
        if start is None:
            start, start_points, start_cells = _start_grid(member, settings)
            reference = _figures(start_cells)
        points, cells = start_points, start_cells
    guarded = time.perf_counter()
    kept = grid if passed else start
    move = 0.0 if start is None else float(np.abs(grid - start).max())
    training = {
        "result": "family" if passed else "start",
        "model": model.path or "(not saved)",
        "start": "elliptic",
        "largest_node_move": move * member.frame.scale / _diagonal(points),
        "adam_epochs": 0,
        "lbfgs_iterations": 0,
        "guard": {"family": figures, "start": reference, "in_range": info["in_range"]},
        "start_solved": start is not None or member.start is not None,
        "winslow_defect": defect,
        "winslow_steps": steps,
        "polish_iterations": model.polish,
        "polished_against": polished_from,
        "timings": {
            "place": placed - began,
            "predict": predicted - placed,
            "guard": guarded - predicted,
        },
    }
    if not passed:
        why = (
            "folded cells"
            if figures["folded_cells"]
            else (
                f"worst cell {figures['worst_max_angle']:.1f} degrees, above the start's "
                f"{reference['worst_max_angle']:.1f} + {WORST_TOL:g}"
            )
        )
        training["fallback"] = f"the family model's grid had {why}: the member's own start is kept"
    report = _report(member, model, settings, points, cells, kept)
    report["training"] = training
    report["mesh_seconds"] = time.perf_counter() - began
    report["timings"] = {**training["timings"], "quality": time.perf_counter() - guarded}
    plane = member.boundary.plane if member.boundary is not None else Plane.horizontal()
    return MeshResult(points=points, report=report, cells=cells, plane=plane)


def _polished(
    model: FamilyModel, member: Member, grid: np.ndarray
) -> tuple[np.ndarray, dict, bool, str]:
    """``grid`` after the member's own node optimisation has settled (``POLISH_SETTLE``, at
    most ``model.polish`` iterations) from :func:`polish_start`, the figures of the grid its
    own run optimises from (quality_start.best_candidate, with the member's ranking),
    whether the polished grid ranks no worse than that, and its name (and where the polish
    started, where not from ``grid``)."""
    from pinn_engine.blas import one_thread
    from pinn_engine.starts.quality_start import Ranking, Settle, best_candidate, sharpened

    elliptic = model.base(member)
    ranking = Ranking.of(elliptic, (), member.boundary.diagonal)
    (begin, name), ranking = best_candidate(elliptic, member.base, ranking)
    begun = ranking.quality(begin)
    grid, share = polish_start(ranking, begin, begun, grid)
    if share < 1:
        start = f"{share:.1f} of the way to the model's grid" if share else "itself"
        name = f"{name} (the model's grid ranked below it; polished from {start})"
    with one_thread():  # its L-BFGS, as the member's own run's
        settle = Settle(*POLISH_SETTLE)
        polished = sharpened(grid, ranking, model.polish, settle, POLISH_SHARPENING, leap=share > 0)
    ranks = ranking.key(ranking.quality(polished)) <= ranking.key(begun)
    return polished, {k: v for k, v in begun.items() if k in _FIGURES}, ranks, name


def polish_start(
    ranking: Ranking, begin: np.ndarray, begun: dict, grid: np.ndarray
) -> tuple[np.ndarray, float]:
    """Where a four-sided member's polish starts, and its share of the way from ``begin``
    (the grid its own run optimises from, its ``ranking``'s figures ``begun``) to the
    model's ``grid``: ``grid`` (1), or where that ranks below ``begin`` (folded, say) the
    best ranked of ``begin`` (0) and its blends towards ``grid`` at the own run's blends'
    weights (``quality_start.BLEND_WEIGHTS``), which keep what of the model's correction
    ranks well."""
    from pinn_engine.starts.quality_start import BLEND_WEIGHTS

    if ranking.key(ranking.quality(grid)) <= ranking.key(begun):
        return grid, 1.0
    blends = [(begin + w * (grid - begin), float(w)) for w in BLEND_WEIGHTS[::-1]]
    return min([*blends, (begin, 0.0)], key=lambda b: ranking.key(ranking.quality(b[0])))


def _body_chosen(
    model: FamilyModel, member: Member, grid: np.ndarray, q: dict
) -> tuple[np.ndarray, str]:
    """A body's grid and its name: the model's ``grid`` (its figures ``q``), kept without the
    member's own start or optimisation where its worst angle is certified; else
    :func:`_body_polished`.

    The certificate: every grid the member's own run can return (its elliptic grid, or that
    grid optimised) holds its wall row and first layer (``BODY_HELD_ROWS``), which the
    model's grid holds too, so its worst angle is at least those cells' worst; a model grid
    with no fold and a worst angle within ``WORST_TOL`` of theirs is within SPEC 16's bound
    of the member's own grid and of its start. Its mean is the model's fit of its own grid,
    measured in docs/family.md, not bounded here."""
    if not q["folded_cells"] and q["worst_max_angle"] <= held_worst(member.base) + WORST_TOL:
        return grid, "family (not optimised: certified)"
    return _body_polished(model, member)


def held_worst(grid: np.ndarray) -> float:
    """The worst angle of the cells that every grid of a body's own run keeps as they are in
    its reference ``grid`` (or its elliptic grid): those between its held rows (the wall and
    the first layer, ``kinds.body.untrained.BODY_HELD_ROWS``, the least it holds), a lower
    bound of its own grid's worst angle."""
    from pinn_engine.kinds.body import untrained

    return untrained.held_worst(grid)


def _body_polished(model: FamilyModel, member: Member) -> tuple[np.ndarray, str]:
    """A body's grid as its own run chooses it (quality_start.body_quality_start: its
    elliptic grid, or that optimised where it ranks better), its elliptic grid solved and
    the optimisation started from the model's grid on it (the elliptic grid plus the
    model's correction) where that ranks no worse than the elliptic grid (else from the
    elliptic grid, as the member's own run: a NACA-like C-grid's model grid ranked below
    it, and optimised from there its worst non-orthogonality was 30.5 degrees against the
    elliptic grid's 20.1, so the elliptic grid was kept, 10.6 degrees above its own run's),
    and the name of the grid chosen. A C-grid whose optimisation from the model's grid
    fails the choice (its elliptic grid returned) is decided by its own run's choice from
    its elliptic grid: on the naca_c family of docs/family.md 4 of 8 unseen members'
    optimisations from the model's grid left their wake less orthogonal than their elliptic
    grids, whose own optimised grids were 7-12 degrees lower in worst angle; an O-grid's
    own run mostly keeps its elliptic grid, and would pay its optimisation twice."""
    from pinn_engine.blas import one_thread
    from pinn_engine.kinds.body.untrained import held_rows
    from pinn_engine.starts.quality_start import Ranking, body_quality_start

    elliptic = model.base(member)
    grid = model.predict(member)[0]
    ranking = Ranking.of(elliptic, [], 1.0)
    better = ranking.key(ranking.quality(grid)) <= ranking.key(ranking.quality(elliptic))
    seam = member.topology == "o"
    with one_thread():  # its L-BFGS, as the member's own run's
        held = held_rows(elliptic)
        found = body_quality_start(elliptic, seam, held, begin=grid if better else None)
        if better and not seam and found[1] == "elliptic":
            found = body_quality_start(elliptic, seam, held)
    return found


def _start_grid(member: Member, settings: Settings) -> tuple[np.ndarray, np.ndarray, dict]:
    """The member's own start (:func:`_start`; family frame), in the user's coordinates and
    its cell arrays."""
    start = _start(member, settings)
    if member.kind == "body":
        return start, member.start.points, member.start.cells
    points = member.frame.to_user(start)
    return start, points, cell_quality(points)


_FIGURES = ("mean_max_angle", "worst_max_angle", "folded_cells")


def _figures(cells: dict) -> dict:
    """:func:`quality.guard_figures` of a grid from its cell arrays."""
    q = summary(cells, 0.0)
    return {k: q[k] for k in _FIGURES}


def _diagonal(points: np.ndarray) -> float:
    return max(float(np.linalg.norm(np.ptp(points.reshape(-1, 2), axis=0))), 1e-300)


def _report(
    member: Member,
    model: FamilyModel,
    settings: Settings,
    points: np.ndarray,
    cells: dict,
    unit: np.ndarray,
) -> dict:
    """The run's report as its kind's pipeline words it (SPEC 3 and 9)."""
    ni, nj = member.size
    report = {
        "method": settings.method,
        "size": [ni, nj],
        "settings": settings.to_dict(),
        "train_seconds": 0.0,
        "source": member.source,
        "aux_lines": [],
        "aux_line_distance": {},
    }
    if member.kind == "body":
        from pinn_engine.kinds.body.mesh import layout_report

        deviation, report["topology"] = layout_report(
            points, member.layout, member.body, member.far
        )
    else:
        deviation = float(member.boundary.deviation(boundary_nodes(unit)).max())
        report["sides"] = side_report(unit, member.frame.scale)
    report["quality"] = summary(cells, deviation)
    return report


class BlocksStart:
    """A multi-block member's start by the family model at ``path`` (or a fitted model), for
    its own run under ``settings`` (``multiblock.mesh.StartNodes``): the model's nodes of
    the member's blocking, a blocking of another topology refused in one line; where they
    fold a cell, the layout's (the member's own start). ``geometry``: the member's
    (``kinds.blocks.run.BlocksGeometry``), options that place nodes otherwise refused."""

    def __init__(self, path: str | os.PathLike | FamilyModel, settings: Settings, geometry) -> None:
        g = geometry
        refuse_blocks_options(g.aux, g.walls, g.gradings, g.source)
        self.model, self.settings, self.source = _model(path), settings, g.source
        self.info: dict = {}

    def __call__(self, topo, lay) -> np.ndarray | None:
        began = time.perf_counter()
        frame = Frame.around(topo.lines.rings[0])
        member = blocks_member(self.settings, lay, self.source, frame, self.model.corners)
        self.model.check(member, self.settings)
        grid, info = self.model.predict(member)
        points = member.frame.to_user(member.unique(grid))
        folded = int(sum(cell_quality(points[ids])["Folded"].sum() for ids in lay.ids))
        self.info = {
            "in_range": info["in_range"],
            "model_folded_cells": folded,
            "predict_seconds": time.perf_counter() - began,
        }
        return None if folded else points

    def note(self, report: dict) -> None:
        """The family's part of the run's ``report`` (``family``): ``result`` ``family``
        where the grid was solved from the model's nodes and kept, else ``start`` and why
        (the run's own choice keeps its start, the blocks' TFI grid, where that ranks above
        the solved grid: section 4's guard, as the member's own run applies it)."""
        solved = report["solve_start"] == "given"
        tfi = report.get("training", {}).get("start") == "tfi"
        family = {
            "result": "family" if solved and not tfi else "start",
            "model": self.model.path or "(not saved)",
            "solve_steps": report["iterations"],
            **self.info,
        }
        if tfi:
            family["fallback"] = "the member's start (its blocks' TFI grid) ranked above"
        elif not solved:
            why = (
                f"{self.info['model_folded_cells']} folded cells"
                if self.info.get("model_folded_cells")
                else "a solve that did not converge"
            )
            family["fallback"] = (
                f"the family model's grid had {why}: solved from the member's own start"
            )
        report["family"] = family
