"""Start-up: a run imports only what it uses. The classical grids and the exports never
import torch (2 s of a run's start); the network's runs do."""

from __future__ import annotations

import subprocess
import sys

import pytest
from helpers import EXAMPLES

RUNS = (  # runs without a network (four-sided, body, multi-block; exports), their outputs
    (["wavy.vtp", "--aux", "wavy_aux.vtp", "--method", "elliptic", "--size", "21", "11"], "a.vts"),
    (["fig2.vtp", "--method", "tfi", "--size", "11", "7"], "b.su2"),
    (["--naca", "0012", "--topology", "o", "--method", "elliptic", "--size", "33", "9"], "c.msh"),
    (["lshape.vtp", "--blocks", "lshape_blocks.vtp", "--method", "elliptic"], "d.cgns"),
)


def _torch_after(runs, tmp_path) -> str:
    """Whether torch is in ``sys.modules`` after ``runs`` (arguments, output file) in a
    fresh Python, as it prints."""
    code = f"""
import sys
from pinn_engine.routes.cli import main
for argv, out in {runs!r}:
    assert main([*argv, "--quiet", "-o", {str(tmp_path)!r} + "/" + out]) == 0, argv
print("torch" in sys.modules)
"""
    done = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, cwd=EXAMPLES, timeout=300
    )
    assert done.returncode == 0, done.stderr[-2000:]
    return done.stdout.split()[-1]


def test_classical_grids_and_exports_import_no_torch(tmp_path):
    assert _torch_after(RUNS, tmp_path) == "False"


@pytest.mark.slow  # trains a small network in a fresh Python (about 5 s)
def test_a_network_run_does_import_torch(tmp_path):
    run = ["concave.vtp", "--size", "11", "7", "--epochs", "20", "--lbfgs", "2"]
    assert _torch_after([(run, "e.vts")], tmp_path) == "True"  # the check above can see torch
