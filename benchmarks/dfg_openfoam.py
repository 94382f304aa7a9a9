"""DFG 2D-1 with simpleFoam on pinn-mesh's grid and on blockMesh's of the same blocks and
counts, at several cell sizes: drag, lift and pressure difference against the published
values (Schaefer and Turek 1996), as a Markdown table (docs/dfg.md).

    .venv/bin/python benchmarks/dfg_openfoam.py --out docs/dfg.md        # minutes: one solve a row

Each row runs ``examples/openfoam_dfg/run.sh`` (MESHER=blockmesh for blockMesh's rows) in
``out/dfg_<mesher>_<cell size>`` and reads its logs; ``--out`` replaces the table between
the two DFG markers of that file. Needs OpenFOAM (simpleFoam, blockMesh, checkMesh).
"""

from __future__ import annotations

import argparse
import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
sys.path.insert(0, str(ROOT / "examples" / "openfoam_dfg"))

from dfg import REFERENCE  # noqa: E402
from multiblock import write_between  # noqa: E402

SIZES = (0.01, 0.005, 0.0025)  # cell sizes H of the rows (the run's --cell-size)
MESHERS = ("pinn-mesh", "blockmesh")
MARK = "<!-- DFG {} -->"  # the markers round the table in --out


def run(
    mesher: str,
    h: float,
    example: str = "openfoam_dfg",
    name: str = "dfg",
    case: Path | None = None,
    extra: dict | None = None,
) -> dict:
    """One case of ``examples/<example>/run.sh`` (in ``case``, default
    ``out/<name>_<mesher>_<h>``; ``extra``: more of run.sh's variables, e.g. ADAPT): its
    cells, checkMesh's largest non-orthogonality, the SIMPLE iterations, seconds of
    simpleFoam, and Cd, Cl, dp."""
    case = case or ROOT / "out" / f"{name}_{mesher}_{h:g}"
    env = {**os.environ, "MESHER": mesher, **(extra or {})}
    proc = subprocess.run(
        ["bash", str(ROOT / "examples" / example / "run.sh"), str(case), str(h)],
        capture_output=True,
        text=True,
        env=env,
        check=True,
    )
    found = dict(zip(*[iter(proc.stdout.split("\n")[-2].split())] * 2))
    return {**logged(case), **{k: float(v) for k, v in found.items()}}


def logged(case: Path) -> dict:
    """A solved case's cells, checkMesh's largest non-orthogonality, the SIMPLE iterations
    (None: not converged) and seconds of simpleFoam, from its logs."""
    check = (case / "log.checkMesh").read_text()
    log = (case / "log.simpleFoam").read_text()
    times = re.findall(r"ExecutionTime = ([0-9.]+) s", log)
    done = re.search(r"SIMPLE solution converged in (\d+) iterations", log)
    return {
        "cells": int(re.search(r"cells:\s+(\d+)", check)[1]),
        "non_orthogonality": float(re.search(r"non-orthogonality Max: ([0-9.]+)", check)[1]),
        "iterations": int(done[1]) if done else None,
        "seconds": float(times[-1]) if times else float("nan"),
    }


def markdown(rows: list[tuple[str, float, dict]]) -> str:
    """The table: each run's figures and its errors against the published values."""
    out = [
        "| mesh | cell size | cells | max non-orthogonality | SIMPLE iterations | "
        "Cd | error | Cl | error | dp | error |",
        "|---|---|---|---|---|---|---|---|---|---|---|",
    ]
    for mesher, h, r in rows:
        errors = {k: 100 * (r[k] - v) / v for k, v in REFERENCE.items()}
        out.append(
            f"| {mesher} | {h:g} | {r['cells']} | {r['non_orthogonality']:.1f} deg | "
            f"{r['iterations'] or 'not converged'} | {r['Cd']:.5f} | {errors['Cd']:+.2f} % | "
            f"{r['Cl']:.6f} | {errors['Cl']:+.1f} % | {r['dp']:.5f} | {errors['dp']:+.2f} % |"
        )
    ref = REFERENCE
    out.append(f"| published | | | | | {ref['Cd']} | | {ref['Cl']} | | {ref['dp']} | |")
    return "\n".join(out) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="a Markdown file with the two DFG markers")
    parser.add_argument("--sizes", type=float, nargs="+", default=SIZES)
    args = parser.parse_args()
    rows = [(m, h, run(m, h)) for h in args.sizes for m in MESHERS]
    text = markdown(rows)
    print(text, end="")
    if args.out:
        write_between(args.out, MARK, text)


if __name__ == "__main__":
    main()
