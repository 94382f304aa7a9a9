"""O- and C-grids around a body as mesh results (SPEC 9): one entry point for every route.

``mesh_body(body, far, "o", "elliptic", 250, 100, wall_spacing=1e-5)`` returns a
:class:`MeshResult` like the four-sided mesher's, with the topology's figures in its report:
the seam's or the wake cut's largest node mismatch, the far field's largest radius error,
the first-layer heights on the wall (min, median, max) and the largest deviation from 90
degrees of the grid lines leaving the wall.
"""

from __future__ import annotations

import math
import time
from collections.abc import Callable

import numpy as np

from pinn_engine.bodies import bodygrid
from pinn_engine.bodies.airfoil import Body, FarField, inside_polygon
from pinn_engine.errors import InputError, network_effect
from pinn_engine.geometry.boundary import segment_distance
from pinn_engine.quality import angle_deviation, cell_quality, summary
from pinn_engine.result import MeshResult
from pinn_engine.settings import Settings, make_settings

METHODS = ("pinn", "tfi", "elliptic")
# The stages before training, reported as progress (phase "prepare"): seconds without a
# training step on fine grids (the elliptic sweeps, torch's first import)
STAGES = ("body layout", "elliptic grid", "network set-up")


def _stage(progress: Callable[[dict], object] | None, stage: str) -> None:
    """Report that ``stage`` of STAGES begins, so that a progress bar moves before training."""
    if progress is not None:
        step = STAGES.index(stage)
        progress({"phase": "prepare", "stage": stage, "step": step, "total": len(STAGES)})


# The search for a first layer whose first row lies outside the body tries round values (1, 2
# and 5 times a power of ten) over this many decades below the given one: 1e-12 of it is far below
# any wall's notch (no such value: the normals, not the notch, are at fault).
ROUND_STEPS, SEARCH_DECADES = (5, 2, 1), 12


def inside_out(grid: np.ndarray, lay: bodygrid.Layout) -> bool:
    """Whether nodes of the first row off the wall lie inside the body (the wall's nodes as
    a polygon): such a grid is never written (SPEC 9)."""
    return _row_inside(grid[0], grid[1], lay)


def _row_inside(wall_line: np.ndarray, row: np.ndarray, lay: bodygrid.Layout) -> bool:
    cols = lay.wall_columns()
    wall = wall_line[cols]
    ring = wall[:-1] if lay.topology == "o" else wall
    return bool(inside_polygon(row[cols], ring).any())


def outside_first_layer(lay: bodygrid.Layout) -> float | None:
    """The largest round first layer below the given one whose wall-normal first row (the
    one the elliptic and pinn grids hold) lies outside the body, or None."""
    top = math.floor(math.log10(lay.wall_spacing))
    for power in range(top, top - SEARCH_DECADES, -1):
        for step in ROUND_STEPS:
            h = step * 10.0**power
            row = bodygrid.first_row(lay.inner, lay.topology, h)
            if h < lay.wall_spacing and not _row_inside(lay.inner, row, lay):
                return h
    return None


def inside_out_error(method: str, lay: bodygrid.Layout, source: str | None) -> InputError:
    """The refusal of an inside-out grid, with the fix that keeps its first row outside:
    tfi's straight columns can enter the body (at a notch, a thin trailing edge) where the
    other methods' first rows leave along the wall's normals; theirs lie inside only where the
    first layer is wider than a notch of the wall, and a thinner one keeps them out."""
    if method == "tfi":
        fix = (
            "its straight columns enter the body; use {method:elliptic} or pinn, whose "
            "first rows leave the wall along its normals"
        )
    else:
        h = outside_first_layer(lay)
        fix = "its first rows lie inside the body"
        if h is not None:
            fix = (
                f"the first layer ({lay.wall_spacing:.3g}) is wider than a notch of the wall, "
                f"so its first rows lie inside the body; give one of at most {h:g} "
                f"({{spacing}} bottom={h:g})"
            )
    return InputError(f"the {method} grid is inside out: {fix}; nothing is written", source)


def wall_metrics(grid: np.ndarray, topology: str, n_wake: int, sharp: bool) -> dict:
    """First-layer heights and wall angles on the body part of j = 0."""
    ni = grid.shape[1]
    idx = np.arange(ni - 1) if topology == "o" else np.arange(n_wake, ni - n_wake)
    e = grid[1] - grid[0]
    h = np.linalg.norm(e, axis=1)
    dev = angle_deviation(bodygrid.row_chords(grid[0], topology), e)
    keep = idx
    if sharp:  # the corner at a sharp trailing edge has no tangent
        te = [0, ni - 1] if topology == "o" else [n_wake, ni - 1 - n_wake]
        keep = np.setdiff1d(idx, te)
    return {
        "first_layer": {
            "min": float(h[idx].min()),
            "median": float(np.median(h[idx])),
            "max": float(h[idx].max()),
        },
        "wall_angle_deviation": float(dev[keep].max()),
    }


def topology_metrics(
    grid: np.ndarray, topology: str, n_wake: int, far: FarField, sharp: bool
) -> dict:
    """Seam or cut mismatch, far-field radius error and the wall figures."""
    if topology == "o":
        gap = float(np.abs(grid[:, 0] - grid[:, -1]).max())
    else:
        gap = float(np.abs(grid[0, : n_wake + 1] - grid[0, ::-1][: n_wake + 1]).max())
    out = {
        "kind": topology,
        "wake_nodes": n_wake,
        ("seam_gap" if topology == "o" else "cut_gap"): gap,
    }
    if far.radius is not None:
        r = np.linalg.norm(grid[-1] - far.center, axis=1)
        front = slice(None) if topology == "o" else grid[-1][:, 0] <= far.center[0] + 1e-12
        out["far_field_radius"] = far.radius
        out["far_field_radius_error"] = float(np.abs(r[front] - far.radius).max())
    out.update(wall_metrics(grid, topology, n_wake, sharp))
    return out


def _check_wall_spacing(wall_spacing: float | None) -> None:
    if wall_spacing is not None and not (np.isfinite(wall_spacing) and wall_spacing > 0):
        raise InputError(f"wall spacing {wall_spacing}: must be a number > 0 (--spacing bottom=H)")


def body_layout(
    body: Body,
    far: FarField,
    topology: str,
    method: str,
    ni: int,
    nj: int,
    wall_spacing: float | None = None,
) -> bodygrid.Layout:
    """The layout of a ``method`` grid around ``body`` (its wall, first row and far field, and
    the reference grid marched between them), refused where its first row, which every grid
    but tfi's holds, lies inside the body (as :func:`mesh_body` refuses the grid)."""
    _check_wall_spacing(wall_spacing)
    lay = bodygrid.layout(body, far, topology, ni, nj, wall_spacing=wall_spacing)
    if inside_out(lay.reference, lay):
        raise inside_out_error(method, lay, body.source)
    return lay


def layout_report(
    grid: np.ndarray, lay: bodygrid.Layout, body: Body, far: FarField
) -> tuple[float, dict]:
    """A body grid's wall deviation from the drawn body (a share of the grid's extent) and
    its report's topology figures (:func:`topology_metrics`, the wall spacing, a cut or a
    closing segment that continues)."""
    wall = grid[0][lay.wall_columns()]
    scale = float(np.linalg.norm(np.ptp(grid.reshape(-1, 2), axis=0)))
    deviation = float(segment_distance(wall, body.ring()[:-1]).max()) / scale
    figures = topology_metrics(grid, lay.topology, lay.n_wake, far, body.sharp)
    figures["wall_spacing"] = lay.wall_spacing
    if body.cut is not None:  # crossing surfaces cut at the crossing (SPEC 9)
        figures["cut"] = list(body.cut)
    if body.continued is not None:  # a closing segment that is no base (SPEC 9)
        figures["closing_segment_continues"] = body.continued
    return deviation, figures


def mesh_body(
    body: Body,
    far: FarField,
    topology: str,
    method: str,
    ni: int,
    nj: int,
    settings: Settings | None = None,
    wall_spacing: float | None = None,
    progress: Callable[[dict], bool | None] | None = None,
    layout: bodygrid.Layout | None = None,
) -> MeshResult:
    """The O- or C-grid of ``ni`` x ``nj`` nodes around ``body`` (see bodygrid.py), on
    ``layout`` where given (``body_layout``'s of these arguments)."""
    if method not in METHODS:
        raise InputError(
            f"method {method}: O- and C-grids are made by "
            f"{', '.join(METHODS)} (mgnet meshes four-sided domains only)"
        )
    settings = settings or make_settings(method, lattice=(ni, nj))
    _check_wall_spacing(wall_spacing)
    start = time.perf_counter()
    _stage(progress, "body layout")
    lay = layout or bodygrid.layout(body, far, topology, ni, nj, wall_spacing=wall_spacing)
    timings = {"layout": time.perf_counter() - start}
    history: dict[str, list[float]] = {}
    training: dict | None = None
    train_seconds = 0.0
    if method == "tfi":
        grid = bodygrid.tfi(lay, nj)
        timings["tfi"] = time.perf_counter() - start - timings["layout"]
    else:
        sweeps = settings.elliptic_iterations or bodygrid.ELLIPTIC_SWEEPS
        _stage(progress, "elliptic grid")
        grid, controls = bodygrid.elliptic(lay, sweeps)
        timings["elliptic"] = time.perf_counter() - start - timings["layout"]
    if method == "pinn":
        began = time.perf_counter()
        from pinn_engine.kinds.body.untrained import body_cannot_win, body_start
        from pinn_engine.kinds.untrained import start_or_train

        def kept(reason: str) -> tuple[np.ndarray, dict, dict, float]:
            """The elliptic start (under the default objective: its nodes beyond the first
            layer and any boundary layer optimised where that ranks better), its report, no
            history and no training seconds."""
            optimize = settings.objective != "winslow"  # the default or quality objective
            chosen, training = body_start(grid, reason, optimize, topology == "o")
            return chosen, {}, training, 0.0

        def trained() -> tuple[np.ndarray, dict, dict, float]:
            """The trained grid, its history and report, and the training's seconds."""
            _stage(progress, "network set-up")
            from pinn_engine.kinds.body.problem import train_body  # torch: imported only to train

            t0 = time.perf_counter()
            out = train_body(lay, grid, controls, settings, progress)
            return (*out, time.perf_counter() - t0)

        grid, history, training, train_seconds = start_or_train(
            body_cannot_win(settings, lay.wall_aspect()), kept, trained
        )
        timings["start"] = time.perf_counter() - began - train_seconds  # chosen, optimised
        timings["training"] = train_seconds
    mesh_seconds = time.perf_counter() - start - train_seconds
    if not np.isfinite(grid).all():
        raise InputError(
            f"the {method} grid has non-finite nodes; try another {{size}}", body.source
        )
    if inside_out(grid, lay):
        raise inside_out_error(method, lay, body.source)
    quality_began = time.perf_counter()
    cells = cell_quality(grid)
    folded = int(np.count_nonzero(cells["Folded"]))
    if topology == "c" and folded:  # the O-grid follows any section without a cut
        raise InputError(
            f"the {method} C-grid folds {folded} cells (a trailing edge too thick or "
            "blunt for a wake cut); an O-grid ({topology}) is the natural topology for "
            "this section",
            body.source,
        )
    deviation, layout_figures = layout_report(grid, lay, body, far)
    report = {
        "method": method,
        "size": [ni, nj],
        "settings": settings.to_dict(),
        "train_seconds": train_seconds,
        "mesh_seconds": mesh_seconds,
        "quality": summary(cells, deviation),
        "source": body.source,
        "aux_lines": [],
        "aux_line_distance": {},
        "topology": layout_figures,
    }
    if method != "tfi":
        report["topology"]["elliptic_sweeps"] = lay.sweeps_kept
    if training is not None:
        report["training"] = training
    report["timings"] = {**timings, "quality": time.perf_counter() - quality_began}
    choice = network_effect(report)
    if choice:  # the summary's line, in the report for the routes without one (pyvista)
        report["choice"] = choice
    return MeshResult(points=grid, report=report, history=history, cells=cells)


__all__ = [
    "METHODS",
    "body_layout",
    "layout_report",
    "mesh_body",
    "topology_metrics",
    "wall_metrics",
]
