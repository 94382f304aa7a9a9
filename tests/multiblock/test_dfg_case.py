"""The DFG 2D-1 example's set-up (examples/openfoam_dfg, docs/dfg.md) on a coarse grid: the
12 blocks meshed with the example's patch items, grading and counts, exported for OpenFOAM
into a copy of the case, the inlet's parabola written as values and, where OpenFOAM is
installed, checkMesh and a short simpleFoam run reading the case; the blockMesh dictionary
of the same blocks and counts."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys

import numpy as np
import pytest
from helpers import EXAMPLES, ROOT, foam_env

from pinn_engine.routes.cli import main

CASE = ROOT / "examples" / "openfoam_dfg"
sys.path.insert(0, str(CASE))
import dfg  # noqa: E402

H = 0.04  # a coarse cell size: about 300 cells
FEW = 3  # SIMPLE iterations: enough to read every dictionary
ITEMS = [
    "--cell-size", str(H), "--cells", "1.2,0.41=24", "--spacing", f"0.3,0.2={H / 2}",
    "--patch", "boundary=walls:wall", "--patch", "hole1=cylinder:wall",
    "--patch", "0,0.05=inlet:inflow", "--patch", "0,0.2=inlet", "--patch", "0,0.355=inlet",
    "--patch", "2.2,0.05=outlet:outflow", "--patch", "2.2,0.2=outlet",
    "--patch", "2.2,0.355=outlet", "--spacing", f"cylinder={H / 4}", "--orthogonal", "cylinder",
    "--method", "elliptic", "--quiet",
]  # fmt: skip
BLOCKS = [str(EXAMPLES / "dfg.vtp"), "--blocks", str(EXAMPLES / "dfg_blocks.vtp")]


def _case(tmp_path):
    case = tmp_path / "dfg"
    case.mkdir()
    for part in ("0", "constant", "system"):
        shutil.copytree(CASE / part, case / part)
    return case


@pytest.mark.slow  # checkMesh and simpleFoam started (about 8 s CPU)
def test_the_case_is_set_up_from_a_few_items(tmp_path):
    """Five patches from eight items (the channel's walls and the cylinder each one ring),
    the inlet's values the parabola at its face centres (peak 0.3, mean 0.2), and, with
    OpenFOAM, checkMesh's Mesh OK and a few SIMPLE iterations."""
    case = _case(tmp_path)
    assert (
        main([*BLOCKS, *ITEMS, "--format", "openfoam", "--extrude", "0.01", "-o", str(case)]) == 0
    )
    boundary = (case / "constant" / "polyMesh" / "boundary").read_text()
    names = re.findall(r"^\s{4}(\w+)\s*$", boundary, re.M)
    assert sorted(names) == ["cylinder", "frontAndBack", "inlet", "outlet", "walls"]
    dfg.inlet(case)
    y = dfg.face_centres(case, "inlet")[:, 1]
    text = (case / "0" / "U").read_text()
    block = re.search(r"inlet\s*\{[^}]*\}", text)[0]
    u = np.array([float(v) for v in re.findall(r"\(([-0-9.e]+) 0 0\)", block)])
    assert len(u) == len(y) and np.allclose(u, 4 * 0.3 * y * (0.41 - y) / 0.41**2)
    assert 0.2 == pytest.approx(np.average(u, weights=np.gradient(np.sort(y))), rel=0.05)
    if shutil.which("checkMesh") is None:
        pytest.skip("OpenFOAM is missing: the mesh and case files are checked, not run")
    env = foam_env()
    check = subprocess.run(
        ["checkMesh", "-case", str(case)], capture_output=True, text=True, env=env
    )
    assert "Mesh OK." in check.stdout, check.stdout[-2000:]
    control = case / "system" / "controlDict"
    control.write_text(
        re.sub(r"^endTime\s+\d+;", f"endTime {FEW};", control.read_text(), flags=re.M)
    )
    control.write_text(
        control.read_text().replace("writeInterval   20000;", f"writeInterval   {FEW};")
    )
    solve = subprocess.run(
        ["simpleFoam", "-case", str(case)], capture_output=True, text=True, env=env
    )
    assert solve.returncode == 0, solve.stdout[-2000:] + solve.stderr[-2000:]
    found = dfg.coefficients(case)
    assert set(found) == {"Cd", "Cl", "dp"} and all(np.isfinite(v) for v in found.values())


@pytest.mark.slow  # blockMesh started on the 12 blocks (about 8 s CPU)
def test_blockmesh_gets_the_same_blocks_and_counts(tmp_path):
    """dfg.py blockmesh writes the 12 blocks with pinn-mesh's counts, the cylinder's four
    sides as arcs, the O-ring graded outward and the column downstream graded to the
    outlet; with OpenFOAM, blockMesh makes as many cells as pinn-mesh."""
    case = _case(tmp_path)
    grid = tmp_path / "dfg.vtm"
    assert main([*BLOCKS, *ITEMS, "-o", str(grid)]) == 0
    dfg.blockmesh(case, grid, 0.01)
    text = (case / "system" / "blockMeshDict").read_text()
    hexes = re.findall(
        r"hex \(([\d ]+)\) \((\d+) (\d+) 1\) simpleGrading \(([\d.e+-]+) ([\d.e+-]+) 1\)", text
    )
    assert len(hexes) == 12 and text.count("arc ") == 8
    cells = sum(int(ni) * int(nj) for _, ni, nj, _, _ in hexes)
    gradings = sorted(
        float(g) for *_, gx, gy in hexes for g in (gx, gy) if abs(float(g) - 1) > 1e-9
    )
    assert len(gradings) == 7 and gradings[0] < 1 < gradings[-1]  # 4 radial, 3 downstream
    import pyvista as pv

    assert cells == sum(b.n_cells for b in pv.read(grid))
    if shutil.which("blockMesh") is None:
        pytest.skip("OpenFOAM is missing: the dictionary is checked, not run")
    made = subprocess.run(
        ["blockMesh", "-case", str(case)], capture_output=True, text=True, env=foam_env()
    )
    assert made.returncode == 0, made.stdout[-2000:]
    assert f"nCells: {cells}" in made.stdout
