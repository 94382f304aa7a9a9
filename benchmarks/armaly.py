"""Armaly's backward-facing step (Re 389, expansion ratio 1.94) in simpleFoam on pinn-mesh's
automatic blocking with a wall spacing and on blockMesh's three blocks of the same counts
and first cells: the reattachment length x_r / S against the 7.9-8.0 of the
two-dimensional solutions, as a Markdown table (docs/openfoam.md).

    nice .venv/bin/python benchmarks/armaly.py --out docs/openfoam.md   # minutes: one solve a row

Each row runs ``examples/openfoam_armaly/run.sh`` (MESHER=blockmesh for blockMesh's rows)
with N cells across the step in ``out/armaly_<mesher>_<N>`` and reads its logs; ``--out``
replaces the table between the two ARMALY markers of that file. Needs OpenFOAM
(simpleFoam, blockMesh, checkMesh).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "examples" / "openfoam_armaly"))

from armaly import counts  # noqa: E402
from dfg_openfoam import MESHERS, run  # noqa: E402
from multiblock import write_between  # noqa: E402

CELLS_ACROSS = (10, 20, 40)  # N, cells across the step: each about four times the last's grid
BAND = (7.9, 8.0)  # x_r / S of the two-dimensional solutions at Re 389
MARK = "<!-- ARMALY {} -->"  # the markers round the table in --out


def markdown(rows: list[tuple[str, int, dict]]) -> str:
    """The table: each run's grid, cells, checkMesh's non-orthogonality, the SIMPLE
    iterations, seconds (the whole run.sh, and simpleFoam's own) and x_r / S."""
    out = [
        "| mesh | N across the step | first cell | cells | max non-orthogonality | "
        "SIMPLE iterations | run.sh | simpleFoam | x_r / S | in 7.9-8.0 |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for mesher, n, r in rows:
        x = r["xr_S"]
        inside = "yes" if BAND[0] <= x <= BAND[1] else "no"
        out.append(
            f"| {mesher} | {n} | {counts(n)['first']:.4g} mm | {r['cells']} | "
            f"{r['non_orthogonality']:.2f} deg | {r['iterations'] or 'not converged'} | "
            f"{r['wall']:.0f} s | {r['seconds']:.0f} s | {x:.3f} | {inside} |"
        )
    return "\n".join(out) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="a Markdown file with the two ARMALY markers")
    parser.add_argument("--cells", type=int, nargs="+", default=CELLS_ACROSS)
    args = parser.parse_args()
    rows = []
    for n in args.cells:
        for mesher in MESHERS:
            start = time.perf_counter()
            case = ROOT / "out" / f"armaly_{mesher}_{n}"
            r = run(mesher, n, example="openfoam_armaly", case=case)
            rows.append((mesher, n, {**r, "wall": time.perf_counter() - start}))
            print(markdown(rows[-1:]).splitlines()[-1], flush=True)
    text = markdown(rows)
    print(text, end="")
    if args.out:
        write_between(args.out, MARK, text)


if __name__ == "__main__":
    main()
