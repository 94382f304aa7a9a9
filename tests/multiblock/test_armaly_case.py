"""Armaly's step example (examples/openfoam_armaly, docs/openfoam.md) on a coarse grid:
pinn-mesh's automatic blocking with the example's items keeps the lip a node and the wall
spacing, and blockMesh's dictionary has the same counts and first cells. The simpleFoam
runs are benchmarks/armaly.py's."""

from __future__ import annotations

import re
import shutil
import subprocess
import sys

import numpy as np
import pytest
from helpers import EXAMPLES, ROOT, foam_env

from pinn_engine.routes.cli import main

CASE = ROOT / "examples" / "openfoam_armaly"
sys.path.insert(0, str(CASE))
import armaly  # noqa: E402

N = 4  # cells across the step: a coarse grid of 272 cells


def test_the_example_s_boundary_file_is_the_case_s_domain():
    drawn = np.loadtxt(EXAMPLES / "armaly_step.csv", delimiter=",", skiprows=1)
    assert np.allclose(drawn, armaly.boundary(), rtol=0, atol=1e-12)


def test_a_geometric_series_of_the_growth_fills_its_length_from_its_first_cell():
    for first, length, cells in ((0.06, 245.0, 200), (0.306, 26.0, 4), (1.0, 4.0, 8)):
        q = armaly.growth(first, length, cells)
        assert np.sum(first * q ** np.arange(cells)) == pytest.approx(length, rel=1e-9)


@pytest.mark.slow  # automatic blocking, a multi-block grid and blockMesh (about 2 s CPU)
def test_automatic_blocking_keeps_the_lip_and_the_counts_and_first_cells_of_blockmesh_s(
    tmp_path,
):
    """The grid of the example's items: the lip (0, S) a node, the first cell on the floor
    behind the step and on the step's face the wall spacing (within SPEC 7's 10 %), and as
    many cells as the blockMesh dictionary, whose gradings give the same first cells."""
    import pyvista as pv

    grid = tmp_path / "armaly.vtm"
    argv = [str(EXAMPLES / "armaly_step.csv"), *armaly.args(N), "--quiet", "-o", str(grid)]
    assert main(argv) == 0
    blocks = list(pv.read(grid))
    first = armaly.counts(N)["first"]
    points = np.vstack([b.points[:, :2] for b in blocks])
    assert np.min(np.linalg.norm(points - [0.0, armaly.STEP], axis=1)) < 1e-9
    behind = next(b for b in blocks if b.bounds[0] > -1e-9)
    ni, nj, _ = behind.dimensions
    mesh = behind.points[:, :2].reshape(nj, ni, 2)
    floor = mesh[1, 1:-1, 1] - mesh[0, 1:-1, 1]  # the first edges up from the floor
    face = mesh[1 : armaly.counts(N)["step"], 1, 0] - mesh[1 : armaly.counts(N)["step"], 0, 0]
    assert np.allclose(floor, first, rtol=0.1) and np.allclose(face, first, rtol=0.1)

    case = tmp_path / "case"
    shutil.copytree(ROOT / "examples" / "openfoam_step" / "system", case / "system")
    armaly.blockmesh(case, N, 0.1)
    text = (case / "system" / "blockMeshDict").read_text()
    hexes = re.findall(r"hex \([\d ]+\) \((\d+) (\d+) 1\) edgeGrading \(([^\n]+)\)\n", text)
    assert len(hexes) == 3
    cells = sum(int(ni) * int(nj) for ni, nj, _ in hexes)
    assert cells == sum(b.n_cells for b in blocks)
    heights = (armaly.INLET, armaly.STEP, armaly.INLET)  # the inlet, below and above the lip
    for (_, nj, grading), height in zip(hexes, heights):
        r = float(re.search(r"\(\(0\.5 0\.5 ([\d.e+-]+)\)", grading)[1])
        m = int(nj) // 2
        q = r ** (1 / (m - 1))
        assert height / 2 * (q - 1) / (q**m - 1) == pytest.approx(first, rel=1e-6)
    if shutil.which("blockMesh") is None:
        pytest.skip("OpenFOAM is missing: the dictionary is checked, not run")
    made = subprocess.run(
        ["blockMesh", "-case", str(case)], capture_output=True, text=True, env=foam_env()
    )
    assert made.returncode == 0, made.stdout[-2000:] + made.stderr[-2000:]
    assert f"nCells: {cells}" in made.stdout
