"""Gradings that combine on a multi-block step, run on the command line as a user types them
and read back: each case writes the OpenFOAM case and the ``.vtm``; checkMesh's verdict,
its largest non-orthogonality, skewness and aspect ratio, and from the ``.vtm`` the worst
neighbour ratio along any grid line, the lines whose cells bulge (an interior cell larger
than both its neighbours), and the cell heights on both sides of the step's line y = S (the
first edges of a grading there: their range, and their largest ratio across the line).

Run ``.venv/bin/python benchmarks/combined_gradings.py`` (OpenFOAM's checkMesh on the PATH,
else the checkMesh columns read "missing"). The step is ``example_data/step.vtp`` (S = 1,
the lip at (0, 1)); its block edges are drawn in a ``.csv`` (the lip's two lines) or
proposed (``--blocks auto``).
"""

from __future__ import annotations

import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pyvista as pv

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))

from helpers import foam_env  # noqa: E402

STEP = ROOT / "example_data" / "step.vtp"
LIP_LINES = "0 1\n0 2\n\n0 1\n6 1\n"  # the lip's two lines, one polyline a row group
PATCHES = ["--patch=boundary=walls:wall", "--patch=-2,1.5=inlet:inflow"]
PATCHES += ["--patch=6,0.5=outlet:outflow", "--patch=6,1.5=outlet"]
WALL, LINE = 5e-5, 1e-4  # the first edges: the walls and the step's line
BULGE = 1.01  # an interior cell over this times both neighbours is a bulge

# (name, block edges: "lines" or "auto", options)
CASES: list[tuple[str, str, list[str]]] = [
    ("walls + step line", "lines", [f"--spacing=walls={WALL}", f"--spacing=3,1={LINE}"]),
    ("walls + step line", "auto", [f"--spacing=walls={WALL}", f"--spacing=3,1={LINE}"]),
    ("step line finer than walls", "lines", [f"--spacing=walls={LINE}", f"--spacing=3,1={WALL}"]),
    ("walls", "auto", [f"--spacing=walls={WALL}"]),
    ("step line", "auto", [f"--spacing=3,1={LINE}"]),
    ("ratio 10 from the lip", "lines", ["--grading=0.5,0=10"]),
    ("walls + ratio on the outlet", "lines", [f"--spacing=walls={WALL}", "--grading=3,2=0.5"]),
]


def check_mesh(case: Path) -> dict[str, str]:
    """checkMesh's verdict and figures (the aspect ratio apart: over 1000 it fails a mesh
    whose first cells resolve a wall, by design, docs/openfoam.md)."""
    if shutil.which("checkMesh") is None:
        return {"verdict": "missing"}
    proc = subprocess.run(
        ["checkMesh", "-case", str(case)], capture_output=True, text=True, env=foam_env()
    )
    text = proc.stdout + proc.stderr
    failed = re.search(r"Failed (\d+) mesh checks", text)
    aspect = re.search(r"Max aspect ratio *[:=] *([\d.e+-]+)", text)
    others = int(failed.group(1)) - ("High aspect ratio" in text) if failed else 0
    skew = float(re.search(r"Max skewness = ([\d.e+-]+)", text).group(1))
    return {
        "verdict": "Mesh OK" if "Mesh OK." in text else f"failed {failed.group(1)}",
        "other failures": str(others),
        "non-orth": re.search(r"non-orthogonality Max: ([\d.e+-]+)", text).group(1)[:5],
        "skewness": f"{skew:.2g}",
        "aspect": f"{float(aspect.group(1)):.0f}" if aspect else "?",
    }


def lines_figures(path: Path) -> dict[str, str]:
    """The worst neighbour ratio along any grid line, the lines with a bulge, and the cell
    heights just below and above y = 1 over x > 0 (the step's line)."""
    worst, bulged, total = 1.0, 0, 0
    below: dict[float, float] = {}  # x of a node on the step's line -> the cell height there
    above: dict[float, float] = {}
    for block in pv.read(path):
        ni, nj, _ = block.dimensions
        xy = np.asarray(block.points[:, :2], dtype=float).reshape(nj, ni, 2)
        for lines in (xy, xy.transpose(1, 0, 2)):
            d = np.linalg.norm(np.diff(lines, axis=1), axis=2)
            r = d[:, 1:] / d[:, :-1]
            worst = max(worst, float(np.maximum(r, 1 / r).max()))
            bump = (d[:, 1:-1] > BULGE * d[:, :-2]) & (d[:, 1:-1] > BULGE * d[:, 2:])
            bulged += int(bump.any(axis=1).sum())
            total += len(d)
        for side, inner in ((xy[0], xy[1]), (xy[-1], xy[-2]), (xy[:, 0], xy[:, 1]),
                            (xy[:, -1], xy[:, -2])):  # fmt: skip
            on = np.isclose(side[:, 1], 1.0) & (side[:, 0] > 1e-6) & (side[:, 0] < 6 - 1e-6)
            if on.sum() > 2:  # the side lies on the step's line
                found = below if inner[on, 1].mean() < 1.0 else above
                found.update(zip(np.round(side[on, 0], 6), np.abs(inner[on, 1] - side[on, 1])))
    common = sorted(set(below) & set(above))
    heights = [*below.values(), *above.values()]
    first = f"{min(heights):.3g}..{max(heights):.3g}" if heights else "-"
    jump = "-"
    if common:
        b, a = np.array([below[x] for x in common]), np.array([above[x] for x in common])
        jump = f"{float(np.max(np.maximum(a / b, b / a))):.2f}"
    return {
        "worst ratio": f"{worst:.3f}",
        "bulged lines": f"{bulged}/{total}",
        "y=S first": first,
        "y=S jump": jump,
    }


def run(name: str, edges: str, options: list[str], folder: Path) -> list[str]:
    blocks = folder / "lines.csv"
    blocks.write_text(LIP_LINES)
    argv = [str(STEP), "--blocks", "auto" if edges == "auto" else str(blocks), *PATCHES]
    argv += ["--cell-size", "0.1", *options, "-q"]
    exe = str(ROOT / ".venv" / "bin" / "pinn-mesh")
    vtm = folder / "g.vtm"
    proc = subprocess.run([exe, *argv, "-o", str(vtm)], capture_output=True, text=True)
    if proc.returncode:
        return [name, edges, " ".join(options), "refused: " + proc.stderr.strip()[:160]]
    case = folder / "case"
    subprocess.run(
        [exe, *argv, "--format", "openfoam", "-o", str(case)], check=True, capture_output=True
    )
    cells = sum(b.n_cells for b in pv.read(vtm))
    mesh, figures = check_mesh(case), lines_figures(vtm)
    return [name, edges, " ".join(options), str(cells), *mesh.values(), *figures.values()]


def main() -> None:
    head = ["case", "edges", "options", "cells", "checkMesh", "fails but aspect", "non-orth"]
    head += ["skewness", "aspect", "worst ratio", "bulged lines", "y=S first", "y=S jump"]
    print("| " + " | ".join(head) + " |")
    print("|" + "---|" * len(head))
    for name, edges, options in CASES:
        with tempfile.TemporaryDirectory() as tmp:
            print("| " + " | ".join(run(name, edges, options, Path(tmp))) + " |", flush=True)


if __name__ == "__main__":
    main()
