"""Start-up: a run imports only what it uses. The classical grids and the exports never
import torch (2 s of a run's start) nor the SciPy packages they do not call (interpolation,
optimisation, images: 0.2 to 0.45 s of CPU); the default four-sided grid no torch (it trains
no network); the network's runs do import torch."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import pytest
from helpers import EXAMPLES

RUNS = (  # runs without a network (four-sided, body, multi-block; exports), their outputs
    (["wavy.vtp", "--aux", "wavy_aux.vtp", "--method", "elliptic", "--size", "21", "11"], "a.vts"),
    (["fig2.vtp", "--method", "tfi", "--size", "11", "7"], "b.su2"),
    (["--naca", "0012", "--topology", "o", "--method", "elliptic", "--size", "33", "9"], "c.msh"),
    (["lshape.vtp", "--blocks", "lshape_blocks.vtp", "--method", "elliptic"], "d.cgns"),
)
UNUSED = (  # pinn_engine._version: the package metadata, read for --version only
    "torch", "scipy.interpolate", "scipy.optimize", "scipy.ndimage", "sklearn", "pyvista",
    "pinn_engine._version",
)  # fmt: skip


def _imported_after(runs, tmp_path, names=UNUSED) -> list[str]:
    """Which of ``names`` are in ``sys.modules`` after ``runs`` (arguments, output file) in
    a fresh Python, as it prints."""
    code = f"""
import sys
from pathlib import Path
from pinn_engine.routes.cli import main
for argv, out in {runs!r}:
    assert main([*argv, "--quiet", "-o", {str(tmp_path)!r} + "/" + out]) == 0, argv
print("imported:" + ",".join(name for name in {names!r} if name in sys.modules))
"""
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=EXAMPLES, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]
    names = done.stdout.rsplit("imported:", 1)[1].strip()
    return names.split(",") if names else []


def test_classical_grids_and_exports_import_only_what_they_use(tmp_path):
    assert _imported_after(RUNS, tmp_path) == []


def test_the_default_four_sided_grid_imports_no_torch(tmp_path):
    """The default pinn on a four-sided domain, with and without lines: the quality
    objective's start (its node optimisation is SciPy's L-BFGS-B on NumPy), no network."""
    runs = [
        (["fig2.vtp", "--size", "21", "11"], "e.vts"),
        (["wavy.vtp", "--aux", "wavy_aux.vtp", "--size", "21", "11"], "f.vts"),
    ]
    names = ("torch", "sklearn", "pyvista", "scipy.optimize")
    assert _imported_after(runs, tmp_path, names) == ["scipy.optimize"]


def test_a_body_grid_imports_no_scipy(tmp_path):
    """An airfoil's C-grid, by the default method on a boundary-layer grid of more than
    ``LAYER_OPTIMISED_NODES`` (its network not trained, its nodes not optimised) and by
    elliptic, and its O-grid by the default at the default size (its nodes optimised by
    NumPy's L-BFGS, lbfgs.py), run on NumPy alone."""
    run = ["--naca", "0012", "--topology", "c", "--size", "241", "17", "--spacing", "bottom=1e-5"]
    runs = [(run, "f.vts"), ([*run, "--method", "elliptic"], "g.vts")]
    runs.append((["--naca", "0012", "--topology", "o"], "h.vts"))
    assert _imported_after(runs, tmp_path, ("scipy", "torch")) == []


@pytest.mark.slow  # trains a small network in a fresh Python (about 5 s)
def test_a_network_run_does_import_torch(tmp_path):
    run = ["concave.vtp", "--size", "11", "7", "--epochs", "20", "--lbfgs", "2"]
    assert "torch" in _imported_after([(run, "f.vts")], tmp_path)  # the check above can see it


def test_an_orthogonal_dictionary_imports_no_scipy(tmp_path):
    """A blockMeshDict whose placement is orthogonal (kept unsolved by the default) is
    placed, checked and written on NumPy alone: SciPy's sparse matrices and multigrid are
    imported only where the Winslow equations are solved."""
    folder = _dictionary(
        tmp_path,
        "box",
        (
            "vertices ((0 0 0) (2 0 0) (2 1 0) (0 1 0) (0 0 1) (2 0 1) (2 1 1) (0 1 1));\n"
            "blocks (hex (0 1 2 3 4 5 6 7) (8 4 2) simpleGrading (3 1 1));\n"
            "boundary ( walls { type wall; faces ((0 3 2 1)); } );\n"
        ),
    )
    run = ([str(folder / "blockMeshDict"), "--format", "openfoam"], "box_case")
    assert _imported_after([run], tmp_path, ("scipy", "pyamg", "torch")) == []


def test_a_dictionary_written_as_an_openfoam_case_imports_no_vtk_nor_torch(tmp_path):
    """A blockMeshDict's Winslow grid written as an OpenFOAM case with its report: the case
    is written from the merged hexahedra, so neither VTK (its dataset is built only where a
    route reads it) nor torch (no network is trained) is imported; the .vtm output does
    build it."""
    folder = _dictionary(
        tmp_path,
        "duct",
        (
            "vertices ((0 0 0) (2 0 0) (2 1 0) (0 1 0) (0 0 1) (2.5 0 1) (2 1 1) (0 1 1));\n"
            "blocks (hex (0 1 2 3 4 5 6 7) (6 4 4) simpleGrading (1 1 1));\n"
            "boundary ( walls { type wall; faces ((0 3 2 1)); } );\n"
        ),
    )
    names = ("vtkmodules", "torch", "pyvista", "scipy.sparse")
    report = str(tmp_path / "duct.json")
    run = ([str(folder / "blockMeshDict"), "--format", "openfoam", "--report", report], "duct_case")
    assert _imported_after([run], tmp_path, names) == ["scipy.sparse"]  # it was solved
    vtm = ([str(folder / "blockMeshDict")], "duct.vtm")
    assert _imported_after([vtm], tmp_path, names) == ["vtkmodules", "scipy.sparse"]


def test_a_swept_dictionary_solves_its_face_without_pyamg(tmp_path):
    """A dictionary one cell thick (a trapezoid swept along z) is solved as its slab's
    face, a 2D system preconditioned by its sparse LU: SciPy's sparse matrices are imported
    and pyamg (about 0.05 s of CPU) is not."""
    folder = _dictionary(
        tmp_path,
        "trapezoid",
        (
            "vertices ((0 0 0) (2 0 0) (2.5 1 0) (0 1 0) (0 0 1) (2 0 1) (2.5 1 1) (0 1 1));\n"
            "blocks (hex (0 1 2 3 4 5 6 7) (8 4 1) simpleGrading (1 1 1));\n"
            "boundary ( walls { type wall; faces ((0 3 2 1)); } );\n"
        ),
    )
    run = ([str(folder / "blockMeshDict"), "--format", "openfoam"], "trapezoid_case")
    assert _imported_after([run], tmp_path, ("pyamg", "scipy.sparse")) == ["scipy.sparse"]


def _dictionary(tmp_path: Path, name: str, text: str) -> Path:
    """A case folder ``name`` under ``tmp_path`` whose system/blockMeshDict is ``text``; its
    system folder."""
    folder = tmp_path / name / "system"
    folder.mkdir(parents=True)
    (folder / "blockMeshDict").write_text(text)
    return folder
