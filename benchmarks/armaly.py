"""Armaly's backward-facing step (Re 389, expansion ratio 1.94) in simpleFoam on pinn-mesh's
automatic blocking with a wall spacing and on blockMesh's three blocks of the same counts
and first cells: the reattachment length x_r / S against the 7.9-8.0 of the
two-dimensional solutions, as a Markdown table (docs/openfoam.md).

    nice .venv/bin/python benchmarks/armaly.py --out docs/openfoam.md   # minutes: one solve a row

Each row runs ``examples/openfoam_armaly/run.sh`` (MESHER=blockmesh for blockMesh's rows)
with N cells across the step in ``out/armaly_<mesher>_<N>`` and reads its logs; ``--out``
replaces the table between the two ARMALY markers of that file; ``--reuse`` reads the cases
an earlier run solved to convergence instead of solving again. Needs OpenFOAM (simpleFoam,
blockMesh, checkMesh).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "examples" / "openfoam_armaly"))

from armaly import counts, reattachment  # noqa: E402
from dfg_openfoam import MESHERS, logged, run  # noqa: E402
from multiblock import write_between  # noqa: E402

CELLS_ACROSS = (10, 20, 30, 40)  # N, cells across the step (even): N^2 x 22 cells or so
BAND = (7.9, 8.0)  # x_r / S of the two-dimensional solutions at Re 389
MARK = "<!-- ARMALY {} -->"  # the markers round the table in --out


def solve(mesher: str, n: int, reuse: bool = False) -> dict:
    """One run of the case in ``out/armaly_<mesher>_<n>`` (``reuse``: read a case already
    solved there instead)."""
    case = ROOT / "out" / f"armaly_{mesher}_{n}"
    log = case / "log.simpleFoam"
    if reuse and log.exists() and "SIMPLE solution converged" in log.read_text():
        return {**logged(case), "xr_S": reattachment(case)}
    return run(mesher, n, example="openfoam_armaly", case=case)


def markdown(rows: list[tuple[str, int, dict]]) -> str:
    """The table: each run's grid, cells, checkMesh's non-orthogonality, the SIMPLE
    iterations, simpleFoam's seconds and x_r / S."""
    out = [
        "| mesh | N across the step | first cell | cells | max non-orthogonality | "
        "SIMPLE iterations | simpleFoam | x_r / S | in 7.9-8.0 |",
        "|---|---|---|---|---|---|---|---|---|",
    ]
    for mesher, n, r in rows:
        x = r["xr_S"]
        inside = "yes" if BAND[0] <= round(x, 2) <= BAND[1] else "no"  # to the band's digits
        out.append(
            f"| {mesher} | {n} | {counts(n)['first']:.4g} mm | {r['cells']} | "
            f"{r['non_orthogonality']:.2f} deg | {r['iterations'] or 'not converged'} | "
            f"{r['seconds']:.0f} s | {x:.3f} | {inside} |"
        )
    return "\n".join(out) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="a Markdown file with the two ARMALY markers")
    parser.add_argument("--cells", type=int, nargs="+", default=CELLS_ACROSS)
    parser.add_argument("--reuse", action="store_true")
    args = parser.parse_args()
    rows = []
    for n in args.cells:
        for mesher in MESHERS:
            rows.append((mesher, n, solve(mesher, n, args.reuse)))
            print(markdown(rows[-1:]).splitlines()[-1], flush=True)
    text = markdown(rows)
    print(text, end="")
    if args.out:
        write_between(args.out, MARK, text)


if __name__ == "__main__":
    main()
