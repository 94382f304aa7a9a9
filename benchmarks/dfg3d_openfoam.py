"""DFG 3D-1Z with simpleFoam on pinn-mesh's grid of the channel's blockMeshDict and on
blockMesh's of the same dictionary, at several sizes: drag, lift and pressure difference
against the published intervals (Schaefer and Turek 1996) and the later accurate values,
as a Markdown table (docs/dfg3d.md).

    .venv/bin/python benchmarks/dfg3d_openfoam.py --out docs/dfg3d.md   # minutes a row

Each row runs ``examples/openfoam_dfg3d/run.sh`` (MESHER=blockmesh for blockMesh's rows) in
``out/dfg3d_<mesher>_<size>`` and reads its logs; ``--out`` replaces the table between the
two DFG3D markers of that file. Needs OpenFOAM (simpleFoam, blockMesh, checkMesh).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "examples" / "openfoam_dfg3d"))

from dfg3d import PUBLISHED, REFERENCE  # noqa: E402
from dfg_openfoam import MESHERS, run  # noqa: E402
from multiblock import write_between  # noqa: E402

SIZES = (0.5, 1.0)  # the dictionary's cell counts as shares of the default's (run.sh's SIZE)
MARK = "<!-- DFG3D {} -->"  # the markers round the table in --out


def markdown(rows: list[tuple[str, float, dict]]) -> str:
    """The table: each run's figures, whether each lies in the published interval, and its
    error against the accurate value."""
    out = [
        "| mesh | size | cells | max non-orthogonality | SIMPLE iterations | "
        "Cd | error | Cl | error | dp | error |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for mesher, size, r in rows:
        cells = [f"| {mesher} | {size:g} | {r['cells']} | {r['non_orthogonality']:.1f} deg | "
                 f"{r['iterations'] or 'not converged'} |"]  # fmt: skip
        for key, digits in (("Cd", 4), ("Cl", 6), ("dp", 5)):
            lo, hi = PUBLISHED[key]
            inside = "" if lo <= r[key] <= hi else " (outside)"
            error = 100 * (r[key] - REFERENCE[key]) / REFERENCE[key]
            cells.append(f" {r[key]:.{digits}f}{inside} | {error:+.2f} % |")
        out.append("".join(cells))
    out.append(
        "| published interval | | | | | "
        + " | | ".join(f"{PUBLISHED[k][0]} - {PUBLISHED[k][1]}" for k in ("Cd", "Cl", "dp"))
        + " | |"
    )
    out.append(
        "| accurate value | | | | | "
        + " | | ".join(f"{REFERENCE[k]}" for k in ("Cd", "Cl", "dp"))
        + " | |"
    )
    return "\n".join(out) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="a Markdown file with the two DFG3D markers")
    parser.add_argument("--sizes", type=float, nargs="+", default=SIZES)
    args = parser.parse_args()
    rows = [
        (m, s, run(m, s, example="openfoam_dfg3d", name="dfg3d"))
        for s in args.sizes
        for m in MESHERS
    ]
    text = markdown(rows)
    print(text, end="")
    if args.out:
        write_between(args.out, MARK, text)


if __name__ == "__main__":
    main()
