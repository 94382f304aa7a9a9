"""A backward-facing step in simpleFoam on a grid adapted to its own first solution (SPEC
14): the reattachment length before and after adapting, beside the unadapted grid with
twice the cells, against a fine grid's (docs/adaptation.md).

    .venv/bin/python benchmarks/adapt_step.py [--sizes 0.2 0.1414 0.1 0.0707] [--array U]
                                              [--reference 0.0177]          # minutes

For each cell size H, rows of ``examples/openfoam_step/run.sh`` in ``out/adapt_step/``:
- ``unadapted``: the grid at H, solved; its result is the field;
- ``adapted to ARRAY``: the same command with ``--adapt <unadapted>/case.foam:ARRAY`` (the
  route as a user runs it: the grid is kept unadapted where no strength lowers the field's
  interpolation error, which the unadapted grid, where the field was solved, always wins);
- ``adapted, kept``: the best adapted try kept whatever its interpolation error
  (``adapt_dfg.py --mesh-kept``): what the adapted grid gives in the solver;
- ``curvature, kept``: the same with the literature's interpolation-error monitor in place
  of SPEC 14's (``--mesh-curvature``): ``M = (1 + (beta / 20) ||H|| / alpha)^(1/3)``, H the
  field's Hessian (the gradient of its node gradients, smoothed as SPEC 14's gradient is),
  alpha its area mean on the unadapted grid (Huang and Russell's L2 monitor for d = 2,
  about half the nodes left in the bulk);
- ``twice``: the unadapted grid at H / sqrt 2 (about twice the cells).
The reference is the unadapted grid at ``--reference`` (about 16 times the cells of 0.07);
``--reference-x X`` takes its x_r from an earlier run, ``--rows`` runs only some rows,
``--reuse`` reads the cases an earlier run solved to convergence instead of solving again.
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "examples" / "openfoam_step"))

from adapt_dfg import mesh_kept  # noqa: E402
from dfg_openfoam import logged, run  # noqa: E402
from step import reattachment  # noqa: E402

OUT = ROOT / "out" / "adapt_step"
SIZES = (0.2, 0.1414, 0.1, 0.0707)  # cell sizes H, each about twice the cells of the last
REFERENCE = 0.0177  # the reference grid's cell size (53 000 cells)
ROWS = ("unadapted", "route", "kept", "curvature", "twice")
POWER = 1.0 / 3.0  # Huang and Russell's L2 interpolation monitor's power, 2 / (d + 4), d = 2


def mesh_curvature(args: list[str]) -> int:
    """``mesh_kept`` with the curvature monitor in place of SPEC 14's."""
    import numpy as np

    import pinn_engine.adapt.grids as grids
    import pinn_engine.adapt.monitor as monitors
    import pinn_engine.adapt.parametric as parametric
    from pinn_engine.adapt.monitor import (
        SMOOTHING_PASSES,
        cell_areas,
        cell_gradient_vectors,
        to_nodes,
    )

    scale = {}

    def curvature(points, cells, f, passes=SMOOTHING_PASSES):
        n = len(points)
        g = cell_gradient_vectors(points, cells, f)
        hx = cell_gradient_vectors(points, cells, to_nodes(cells, g[:, 0], n))
        hy = cell_gradient_vectors(points, cells, to_nodes(cells, g[:, 1], n))
        cross = 0.5 * (hx[:, 1] + hy[:, 0])
        h = to_nodes(cells, np.sqrt(hx[:, 0] ** 2 + hy[:, 1] ** 2 + 2 * cross**2), n)
        for _ in range(passes):
            h = to_nodes(cells, h[cells].mean(axis=1), n)
        if "alpha" not in scale:  # the first call is on the unadapted grid
            area = to_nodes(cells, cell_areas(points, cells), n)
            scale["alpha"] = float((h * area).sum() / area.sum())
        return h

    def monitor(h, strength, largest):
        return (1.0 + np.asarray(strength) / grids.DEFAULT_STRENGTH * h / scale["alpha"]) ** POWER

    for module in (grids, parametric, monitors):  # monitors: the diffusion tensor calls its own
        module.gradient_size, module.monitor_values = curvature, monitor
    return mesh_kept(args)


def solve(name: str, h: float, extra: dict | None = None, reuse: bool = False) -> dict:
    """One run of the step case in ``out/adapt_step/<name>`` (``reuse``: read a case already
    solved there instead)."""
    case = OUT / name
    log = case / "log.simpleFoam"
    if reuse and log.exists() and "SIMPLE solution converged" in log.read_text():
        return {**logged(case), "reattachment": reattachment(case)}
    return run("pinn-mesh", h, example="openfoam_step", case=case, extra=extra)


def row(name: str, h: float, r: dict, reference: float) -> str:
    """A table row: the run's figures and its reattachment length's error."""
    x = r["reattachment"]
    return (
        f"| {name} | {h:g} | {r['cells']} | {r['non_orthogonality']:.1f} deg | "
        f"{r['iterations'] or 'not converged'} | {x:.4f} | {x - reference:+.4f} | "
        f"{100 * (x - reference) / reference:+.2f} % |"
    )


def main() -> None:
    if len(sys.argv) > 1 and sys.argv[1] == "--mesh-curvature":
        sys.exit(mesh_curvature(sys.argv[2:]))
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=SIZES)
    parser.add_argument("--array", default="U")
    parser.add_argument("--reference", type=float, default=REFERENCE)
    parser.add_argument("--reference-x", type=float)
    parser.add_argument("--rows", nargs="+", choices=ROWS, default=ROWS)
    parser.add_argument("--reuse", action="store_true")
    args = parser.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    kept, curved = OUT / "mesh_kept.sh", OUT / "mesh_curvature.sh"
    kept.write_text(
        f'#!/bin/sh\nexec "{sys.executable}" "{ROOT / "benchmarks" / "adapt_dfg.py"}" '
        '--mesh-kept "$@"\n'
    )
    curved.write_text(
        f'#!/bin/sh\nexec "{sys.executable}" "{Path(__file__)}" --mesh-curvature "$@"\n'
    )
    for script in (kept, curved):
        script.chmod(0o755)
    ref = args.reference_x
    if ref is None:
        ref = solve(f"reference_{args.reference:g}", args.reference, reuse=args.reuse)
        ref = ref["reattachment"]
    print(f"reference: x_r {ref:.4f} at cell size {args.reference:g}", flush=True)
    lines = [
        "| grid | cell size | cells | max non-orthogonality | SIMPLE iterations | x_r / S "
        "| error | error |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for h in args.sizes:
        plain = f"unadapted_{h:g}"
        field = {"ADAPT": f"{OUT / plain / 'case.foam'}:{args.array}"}
        adapted = {**field, "PINN_MESH": str(kept)}
        for key, name, size, case, extra in (
            ("unadapted", "unadapted", h, plain, None),
            ("route", f"adapted to {args.array} (the route)", h, f"route_{h:g}", field),
            ("kept", f"adapted to {args.array}, kept", h, f"kept_{h:g}", adapted),
            (
                "curvature",
                f"adapted to {args.array}'s curvature, kept",
                h,
                f"curvature_{h:g}",
                {**field, "PINN_MESH": str(curved)},
            ),
            ("twice", "unadapted, twice the cells", h / math.sqrt(2), f"twice_{h:g}", None),
        ):
            if key in args.rows:
                lines.append(row(name, size, solve(case, size, extra, args.reuse), ref))
                print(lines[-1], flush=True)
    lines.append(f"| reference | {args.reference:g} | | | | {ref:.4f} | | |")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
