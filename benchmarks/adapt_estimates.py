"""Which estimate of a solved field's error pays in the solver (SPEC 14, docs/adaptation.md):
the step's reattachment length and DFG 2D-1's drag, lift and pressure difference on grids
adapted to the first solution's velocity, with the route's judge (the field's
interpolation error, which the grid the field was solved on always wins) replaced by an
estimate it does not win by construction, and on grids of one form and strength.

    .venv/bin/python benchmarks/adapt_estimates.py [--sizes 0.2 0.1414] [--rows ...] [--sweep]

Rows, each one ``run.sh`` of ``examples/openfoam_step`` at each cell size (in
``out/adapt_step/``, beside ``adapt_step.py``'s) and of ``examples/openfoam_dfg`` at 0.01
(in ``out/adapt_dfg/``), adapted to the unadapted grid's solution there (solved first; the
step's read where ``adapt_step.py`` solved it):
- ``recovery``: the judge is the recovered-gradient (Zienkiewicz-Zhu) estimate of the H1
  seminorm error, ``(sum over cells of the integral of |G - grad f_h|^2 / area)^(1/2)``,
  ``grad f_h`` the bilinear cells' gradient of the node values and G its recovery (the cells'
  centre gradients averaged to the nodes by area, bilinear in between), at 2 x 2 Gauss points;
- ``recovery monitor``: the same judge, and the gradient forms' monitor the H1-optimal
  density of that estimate, ``M = 1 + (beta / 20) |H| / alpha`` with ``|H|`` the estimate's
  RMS gradient error over the cell's size (smoothed as SPEC 14's gradient), alpha its area
  mean on the unadapted grid;
- ``cell mean``: the judge is the L2 error of the field's cell means (a cell-centred finite
  volume's own representation of it, whose optimal density is the gradient's, SPEC 14's);
- ``truncation``: the judge is the tau-estimate of the truncation error of a cell-centred
  finite-volume Laplacian (faces' over-relaxed two-point gradients, a boundary face's value
  at its middle) of the field's C1 reconstruction (Clough-Tocher's cubic through its point
  values, on the image the field is sampled on): the operator on the grid minus its mean on
  the grid's cells split in four, L2 over the cells (the local source of a solver's error);
- ``--sweep``: each gradient form (``grids.FORMS`` 0, the anisotropic tensor, joined on
  multi-block grids, and 1, the isotropic) alone at strengths 1.25 to 20, kept whatever its
  interpolation error.
Each row names the form and strength kept, the unadapted grid's judged error and the
lowest of the tries'. ``--mesh ARGS`` is the pinn-mesh command of a row
(run.sh's PINN_MESH; the row from the environment's ESTIMATE, the form kept written to the
file ADAPTATION names).
"""

from __future__ import annotations

import argparse
import math
import os
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

import adapt_step  # noqa: E402
from dfg_openfoam import markdown, run  # noqa: E402

DFG = ROOT / "out" / "adapt_dfg"
DFG_SIZE = 0.01  # DFG 2D-1's coarsest documented cell size (4533 cells)
SIZES = (0.2, 0.1414)  # the step's two coarsest sizes
REFERENCE_X = 2.9148  # the step's x_r on the 0.0177 grid (adapt_step.py's reference row)
ROWS = ("recovery", "recovery monitor", "cell mean", "truncation")
SWEEP = (1.25, 2.5, 5.0, 20.0)  # strengths of --sweep: the route's from 20 down to a sixteenth
GAUSS = (0.5 - 0.5 / math.sqrt(3.0), 0.5 + 0.5 / math.sqrt(3.0))  # 2-point Gauss on [0, 1]
QUAD = 3  # the cell-mean judge's sample points a cell side, as the interpolation error's


def recovery_cells(points: np.ndarray, cells: np.ndarray, f: np.ndarray) -> np.ndarray:
    """Each cell's integral of ``|G - grad f_h|^2`` (the recovered-gradient estimate)."""
    from pinn_engine.adapt.monitor import cell_areas, cell_gradient_vectors

    area, centre = cell_areas(points, cells), cell_gradient_vectors(points, cells, f)
    weight = np.bincount(cells.ravel(), np.repeat(area, 4), minlength=len(points))
    recovered = np.stack(
        [
            np.bincount(cells.ravel(), np.repeat(area * centre[:, k], 4), len(points)) / weight
            for k in (0, 1)
        ],
        axis=1,
    )[cells]
    p, v, total = points[cells], f[cells], np.zeros(len(cells))
    for a in GAUSS:
        for b in GAUSS:
            x_u = (1 - b) * (p[:, 1] - p[:, 0]) + b * (p[:, 2] - p[:, 3])
            x_v = (1 - a) * (p[:, 3] - p[:, 0]) + a * (p[:, 2] - p[:, 1])
            f_u = (1 - b) * (v[:, 1] - v[:, 0]) + b * (v[:, 2] - v[:, 3])
            f_v = (1 - a) * (v[:, 3] - v[:, 0]) + a * (v[:, 2] - v[:, 1])
            jac = x_u[:, 0] * x_v[:, 1] - x_u[:, 1] * x_v[:, 0]
            jac = np.where(np.abs(jac) > 1e-300, jac, 1e-300)
            g = np.column_stack(
                [f_u * x_v[:, 1] - f_v * x_u[:, 1], f_v * x_u[:, 0] - f_u * x_v[:, 0]]
            )
            shape = np.array([(1 - a) * (1 - b), a * (1 - b), a * b, (1 - a) * b])
            gap = np.einsum("k,mkd->md", shape, recovered) - g / jac[:, None]
            total += (gap**2).sum(axis=1) * np.abs(jac) / 4.0
    return total


def recovery_error(points: np.ndarray, cells: np.ndarray, sample) -> float:
    """The recovered-gradient estimate of the field's H1 seminorm error on the grid."""
    from pinn_engine.adapt.monitor import cell_areas

    total = recovery_cells(points, cells, sample(points)).sum()
    return float(np.sqrt(total / cell_areas(points, cells).sum()))


def cell_mean_error(points: np.ndarray, cells: np.ndarray, sample) -> float:
    """The L2 error of the field's cell means (``QUAD`` x ``QUAD`` points a cell)."""
    from pinn_engine.adapt.monitor import cell_areas

    u = (np.arange(QUAD) + 0.5) / QUAD
    uu, vv = (a.ravel() for a in np.meshgrid(u, u))
    weights = np.stack([(1 - uu) * (1 - vv), uu * (1 - vv), uu * vv, (1 - uu) * vv])
    inside = np.einsum("kq,mkd->mqd", weights, points[cells]).reshape(-1, 2)
    f = sample(inside).reshape(len(cells), -1)
    area = cell_areas(points, cells)
    gap = ((f - f.mean(axis=1, keepdims=True)) ** 2).mean(axis=1)
    return float(np.sqrt((area * gap).sum() / area.sum()))


def _split(points: np.ndarray, cells: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The grid with each cell split in four at its edges' middles and its centre (each
    cell's four children in a row of the cells returned)."""
    n, m = len(points), len(cells)
    a, b, c, d = cells.T
    sides = np.stack([np.sort(np.stack(pair), axis=0) for pair in ((a, b), (b, c), (c, d), (d, a))])
    keys, middle = np.unique((sides[:, 0] * n + sides[:, 1]).ravel(), return_inverse=True)
    ab, bc, cd, da = middle.reshape(4, m) + n
    centre = np.arange(m) + n + len(keys)
    halves = 0.5 * (points[keys // n] + points[keys % n])
    out = np.concatenate([points, halves, points[cells].mean(axis=1)])
    children = np.stack(
        [(a, ab, centre, da), (ab, b, bc, centre), (centre, bc, c, cd), (da, centre, cd, d)]
    )  # (4 children, 4 corners, m)
    return out, children.transpose(2, 0, 1).reshape(-1, 4)


def laplacian(points: np.ndarray, cells: np.ndarray, sample) -> tuple[np.ndarray, np.ndarray]:
    """The cell-centred finite-volume Laplacian of the field at each cell (cells (m, 4)
    counter-clockwise) and the cells' areas."""
    from pinn_engine.adapt.monitor import cell_areas

    n, m = len(points), len(cells)
    centres, area = points[cells].mean(axis=1), cell_areas(points, cells)
    f = sample(centres)
    first, second = cells.ravel(), np.roll(cells, -1, axis=1).ravel()
    edge = points[second] - points[first]
    normal = np.column_stack([edge[:, 1], -edge[:, 0]])  # outward of a counter-clockwise cell
    owner = np.repeat(np.arange(m), 4)
    keys = np.minimum(first, second) * n + np.maximum(first, second)
    order = np.argsort(keys, kind="stable")
    pair = np.flatnonzero(keys[order][1:] == keys[order][:-1])
    near, far = order[pair], order[pair + 1]
    lone = np.setdiff1d(np.arange(4 * m), np.concatenate([near, far]))
    flux = np.zeros(m)
    for face, gap, value in (
        (near, centres[owner[far]] - centres[owner[near]], f[owner[far]]),
        (lone, 0.5 * (points[first[lone]] + points[second[lone]]) - centres[owner[lone]], None),
    ):
        s = normal[face]
        if value is None:
            value = sample(0.5 * (points[first[face]] + points[second[face]]))
        g = (s * s).sum(axis=1) / np.abs((s * gap).sum(axis=1)) * (value - f[owner[face]])
        np.add.at(flux, owner[face], g)
        if face is near:
            np.add.at(flux, owner[far], -g)
    return flux / area, area


def truncation_error(points: np.ndarray, cells: np.ndarray, sample) -> float:
    """The tau-estimate of the finite-volume Laplacian's truncation error on the grid: the
    operator on its cells minus its area mean on their four children, L2 over the cells."""
    coarse, area = laplacian(points, cells, sample)
    fine, halves = laplacian(*_split(points, cells), sample)
    fine = (fine * halves).reshape(-1, 4).sum(axis=1) / halves.reshape(-1, 4).sum(axis=1)
    return float(np.sqrt((area * (coarse - fine) ** 2).sum() / area.sum()))


def c1_image(imaged):
    """``Field._imaged`` with the values inside the field's cells from the C1 (Clough-Tocher)
    cubic through its point values (coinciding points, a 2D case's two planes, averaged)."""
    from scipy.interpolate import CloughTocher2DInterpolator, RegularGridInterpolator
    from vtkmodules.util.numpy_support import vtk_to_numpy

    from pinn_engine.adapt.nodes import MERGE_TOL

    def smooth(field):
        image = imaged(field)
        y, x = image.grid
        xx, yy = np.meshgrid(x, y)
        at = np.column_stack([xx.ravel(), yy.ravel()])
        inside = field.probe(at)[1]
        plane = field._all_points()[:, :2]
        key = np.round((plane - plane.min(axis=0)) / (MERGE_TOL * field.diagonal))
        _, first, which = np.unique(key, axis=0, return_index=True, return_inverse=True)
        values = vtk_to_numpy(field.data.GetPointData().GetArray("f")).astype(float)
        mean = np.bincount(which.ravel(), values) / np.bincount(which.ravel())
        cubic = CloughTocher2DInterpolator(plane[first], mean)(at[inside])
        flat = image.values.ravel().copy()
        flat[inside] = np.where(np.isnan(cubic), flat[inside], cubic)
        values = flat.reshape(image.values.shape)
        return RegularGridInterpolator((y, x), values, bounds_error=False, fill_value=None)

    return smooth


def mesh(row: str, args: list[str]) -> int:
    """pinn-mesh with ``args``, its judge (and monitor, or forms and strength) as ``row``."""
    import torch

    import pinn_engine.adapt.grids as grids
    import pinn_engine.adapt.guard as guard
    import pinn_engine.adapt.monitor as monitors
    import pinn_engine.adapt.parametric as parametric
    import pinn_engine.job.adapted as job
    from pinn_engine.command import main

    torch.set_num_threads(1)
    if row.startswith("form"):  # "form K beta B": one form at one strength, kept
        _, form, _, beta = row.split()
        grids.FORMS, grids.STRENGTHS = (grids.FORMS[int(form)],), 1
        measured, calls, adapt = grids.interpolation_error, [], job.adapt_grids

        def unadapted_worst(points, cells, sample):
            calls.append(1)
            return math.inf if len(calls) == 1 else measured(points, cells, sample)

        def fixed(blocks, field, strength, held=None):
            return adapt(blocks, field, float(beta), held)

        grids.interpolation_error, job.adapt_grids = unadapted_worst, fixed
    else:
        judge = {"cell mean": cell_mean_error, "truncation": truncation_error}
        judge = judge.get(row, recovery_error)
        grids.interpolation_error = guard.interpolation_error = judge
    if row == "truncation":
        from pinn_engine.adapt.field import Field

        Field._imaged = c1_image(Field._imaged)
    if row == "recovery monitor":
        from pinn_engine.adapt.monitor import cell_areas, smoothed_at_nodes, to_nodes

        scale = {}

        def estimated(points, cells, f, passes=monitors.SMOOTHING_PASSES):
            area = cell_areas(points, cells)
            hessian = np.sqrt(recovery_cells(points, cells, f)) / area
            out = smoothed_at_nodes(cells, hessian, len(points), passes)
            if "alpha" not in scale:  # the first call is on the unadapted grid
                weight = to_nodes(cells, area, len(points))
                scale["alpha"] = float((out * weight).sum() / weight.sum())
            return out

        def monitor(h, strength, largest):
            return 1.0 + np.asarray(strength) / grids.DEFAULT_STRENGTH * h / scale["alpha"]

        for module in (grids, parametric, monitors):  # monitors: the tensor calls its own
            module.gradient_size, module.monitor_values = estimated, monitor
    adapted = job.adapt_grids

    def reported(*given, **named):
        result = adapted(*given, **named)
        report = result.report
        best = min(t["error"] for t in report["tries"])
        Path(os.environ["ADAPTATION"]).write_text(
            f"{report['form']} {report['strength_used']:g}; the grid judged "
            f"{report['interpolation_error']['before']:.3g}, the best try {best:.3g}"
        )
        return result

    job.adapt_grids = reported
    sys.argv = ["pinn-mesh", *args]
    return main()


def dfg(name: str, extra: dict | None = None) -> dict:
    """DFG 2D-1 at ``DFG_SIZE`` in ``out/adapt_dfg/<name>``."""
    return run("pinn-mesh", DFG_SIZE, case=DFG / name, extra=extra)


def _extra(name: str, field: str, command: Path, case: Path) -> dict:
    """run.sh's variables for a row adapted to ``field`` in ``case``."""
    return {
        "ADAPT": field,
        "PINN_MESH": str(command),
        "ESTIMATE": name,
        "ADAPTATION": str(case / "adaptation.txt"),
    }


def _kept(name: str, extra: dict) -> str:
    """A row's name and the form and strength kept."""
    return f"{name} ({Path(extra['ADAPTATION']).read_text()})"


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--mesh":
        sys.exit(mesh(os.environ["ESTIMATE"], sys.argv[2:]))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=SIZES)
    parser.add_argument("--sweep", action="store_true")
    parser.add_argument("--rows", nargs="+", choices=ROWS, default=ROWS)
    args = parser.parse_args()
    rows = [f"form {k} beta {b:g}" for k in (0, 1) for b in SWEEP] if args.sweep else args.rows
    adapt_step.OUT.mkdir(parents=True, exist_ok=True)
    DFG.mkdir(parents=True, exist_ok=True)
    command = adapt_step.OUT / "mesh_estimates.sh"
    command.write_text(f'#!/bin/sh\nexec "{sys.executable}" "{Path(__file__)}" --mesh "$@"\n')
    command.chmod(0o755)
    for h in args.sizes:
        plain = f"unadapted_{h:g}"
        print(adapt_step.row("unadapted", h, adapt_step.solve(plain, h, reuse=True), REFERENCE_X))
        field = f"{adapt_step.OUT / plain / 'case.foam'}:U"
        for name in rows:
            case = f"{name.replace(' ', '_')}_{h:g}"
            extra = _extra(name, field, command, adapt_step.OUT / case)
            found = adapt_step.solve(case, h, extra)
            print(adapt_step.row(_kept(name, extra), h, found, REFERENCE_X), flush=True)
    found = [("unadapted", DFG_SIZE, dfg("plain"))]
    field = f"{DFG / 'plain' / 'case.foam'}:U"
    for name in rows:
        extra = _extra(name, field, command, DFG / name.replace(" ", "_"))
        found.append((name, DFG_SIZE, dfg(name.replace(" ", "_"), extra)))
        found[-1] = (_kept(name, extra), *found[-1][1:])
        print(markdown(found[-1:]).splitlines()[-2], flush=True)
    print(markdown(found), end="")


if __name__ == "__main__":
    main()
