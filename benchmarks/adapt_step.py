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
- ``twice``: the unadapted grid at H / sqrt 2 (about twice the cells).
The reference is the unadapted grid at ``--reference`` (about 16 times the cells of 0.07).
"""

from __future__ import annotations

import argparse
import math
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

from dfg_openfoam import run  # noqa: E402

OUT = ROOT / "out" / "adapt_step"
SIZES = (0.2, 0.1414, 0.1, 0.0707)  # cell sizes H, each about twice the cells of the last
REFERENCE = 0.0177  # the reference grid's cell size (53 000 cells)


def solve(name: str, h: float, extra: dict | None = None) -> dict:
    """One run of the step case in ``out/adapt_step/<name>``."""
    return run("pinn-mesh", h, example="openfoam_step", case=OUT / name, extra=extra)


def row(name: str, h: float, r: dict, reference: float) -> str:
    """A table row: the run's figures and its reattachment length's error."""
    x = r["reattachment"]
    return (
        f"| {name} | {h:g} | {r['cells']} | {r['non_orthogonality']:.1f} deg | "
        f"{r['iterations'] or 'not converged'} | {x:.4f} | {x - reference:+.4f} | "
        f"{100 * (x - reference) / reference:+.2f} % |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=float, nargs="+", default=SIZES)
    parser.add_argument("--array", default="U")
    parser.add_argument("--reference", type=float, default=REFERENCE)
    args = parser.parse_args()
    OUT.mkdir(parents=True, exist_ok=True)
    kept = OUT / "mesh_kept.sh"
    script = ROOT / "benchmarks" / "adapt_dfg.py"
    kept.write_text(f'#!/bin/sh\nexec "{sys.executable}" "{script}" --mesh-kept "$@"\n')
    kept.chmod(0o755)
    ref = solve(f"reference_{args.reference:g}", args.reference)["reattachment"]
    print(f"reference: x_r {ref:.4f} at cell size {args.reference:g}", flush=True)
    lines = [
        "| grid | cell size | cells | max non-orthogonality | SIMPLE iterations | x_r / S "
        "| error | error |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for h in args.sizes:
        plain = f"unadapted_{h:g}"
        field = {"ADAPT": f"{OUT / plain / 'case.foam'}:{args.array}"}
        for name, size, case, extra in (
            ("unadapted", h, plain, None),
            (f"adapted to {args.array} (the route)", h, f"route_{h:g}", field),
            (f"adapted to {args.array}, kept", h, f"kept_{h:g}", {**field, "PINN_MESH": str(kept)}),
            ("unadapted, twice the cells", h / math.sqrt(2), f"twice_{h:g}", None),
        ):
            lines.append(row(name, size, solve(case, size, extra), ref))
            print(lines[-1], flush=True)
    lines.append(f"| reference | {args.reference:g} | | | | {ref:.4f} | | |")
    print("\n".join(lines))


if __name__ == "__main__":
    main()
