"""The OpenFOAM examples of ``examples/`` run on pinn-mesh's grids.

The laminar bump channel and backward-facing step run to convergence through their own
``run.sh``; the NACA 0012
Spalart-Allmaras case (minutes) runs a few iterations on a coarse C-grid, which checks that
its dictionaries fit the patches pinn-mesh writes. Skipped where OpenFOAM is missing;
``.ci/run`` installs it (``scripts/setup_openfoam.sh``).
"""

from __future__ import annotations

import math
import re
import shutil
import subprocess
import sys
from pathlib import Path

import pytest
from helpers import ROOT, foam_env

from pinn_engine.routes.cli import main

pytestmark = pytest.mark.skipif(
    shutil.which("simpleFoam") is None,
    reason="OpenFOAM's simpleFoam is missing (apt-get install openfoam; .ci/run installs it)",
)

BUMP = ROOT / "examples" / "openfoam_bump"
NACA = ROOT / "examples" / "openfoam_naca0012"
STEP = ROOT / "examples" / "openfoam_step"
INFLOW = 1.0 * 1.0 * 0.1  # volume flux in: speed 1 (0/U) x height 1 x depth 0.1 (--extrude)
NU, LENGTH = 0.01, 3.0  # constant/transportProperties; the channel's length (height 1)
# fully developed Poiseuille flow loses 12 nu U L / H^2: the developing inflow and the bump
# only add to that, so the measured drop must be larger
POISEUILLE_DROP = 12 * NU * 1.0 * LENGTH
# the step's reattachment length at Re 100 (expansion ratio 2) is about 3 step heights
# (Armaly et al. 1983's measurements; 2.92 on this case's finest grid, docs/adaptation.md):
# the coarse grid of the test must land near it
REATTACHMENT = (2.7, 3.1)
FEW = 5  # SIMPLE iterations of the NACA case on the coarse grid: enough to read the dictionaries


def run_example(script: Path, *args: str) -> subprocess.CompletedProcess:
    """An example's ``run.sh`` with this interpreter's pinn-mesh where it has one."""
    env = foam_env()
    command = Path(sys.executable).with_name("pinn-mesh")  # this interpreter's, when it has one
    if command.exists():
        env["PINN_MESH"] = str(command)
    proc = subprocess.run(
        ["bash", str(script), *args], capture_output=True, text=True, env=env, timeout=240
    )
    assert proc.returncode == 0, proc.stdout[-2000:] + proc.stderr[-2000:]
    return proc


def last_value(case: Path, function: str) -> float:
    """The last value written by a surfaceFieldValue function object of the case."""
    rows = (case / "postProcessing" / function / "0" / "surfaceFieldValue.dat").read_text()
    return float(rows.strip().splitlines()[-1].split()[1])


@pytest.mark.slow  # OpenFOAM's solver run to convergence
def test_the_bump_channel_converges_and_keeps_its_mass(tmp_path):
    case = tmp_path / "bump"
    proc = run_example(BUMP / "run.sh", str(case))
    assert "Mesh OK." in (case / "log.checkMesh").read_text()
    log = (case / "log.simpleFoam").read_text()
    done = re.search(r"SIMPLE solution converged in (\d+) iterations", log)
    assert done, log[-2000:]
    cap = int(re.search(r"^endTime\s+(\d+);", (BUMP / "system/controlDict").read_text(), re.M)[1])
    assert int(done[1]) < cap
    inflow, outflow = -last_value(case, "inletFlux"), last_value(case, "outletFlux")
    assert inflow == pytest.approx(INFLOW, rel=1e-6)
    assert outflow == pytest.approx(inflow, rel=0.01)
    assert last_value(case, "inletPressure") > POISEUILLE_DROP
    assert f"flux in {-inflow:.8e}" in proc.stdout  # the script's summary line


def test_the_naca_case_reads_a_c_grid(tmp_path):
    case = tmp_path / "naca"
    case.mkdir()
    for part in ("0", "constant", "system"):
        shutil.copytree(NACA / part, case / part)
    control = case / "system" / "controlDict"
    control.write_text(
        re.sub(r"^endTime\s+\d+;", f"endTime {FEW};", control.read_text(), flags=re.M)
    )
    command = ["--naca", "0012", "--topology", "c", "--size", "97", "25", "--method", "elliptic"]
    command += ["--spacing", "bottom=1e-3", "--format", "openfoam", "--extrude", "0.1"]
    assert main([*command, "-o", str(case), "--quiet"]) == 0
    proc = subprocess.run(
        ["simpleFoam", "-case", str(case)],
        capture_output=True,
        text=True,
        env=foam_env(),
        timeout=120,
    )
    assert proc.returncode == 0 and proc.stdout.rstrip().endswith("End"), proc.stdout[-3000:]
    rows = (case / "postProcessing" / "forceCoeffs" / "0" / "coefficient.dat").read_text()
    last = [ln for ln in rows.splitlines() if not ln.startswith("#")][-1].split()
    assert int(last[0]) == FEW and all(math.isfinite(float(v)) for v in last)


@pytest.mark.slow
def test_the_step_converges_and_reattaches_where_measured(tmp_path):
    case = tmp_path / "step"
    proc = run_example(STEP / "run.sh", str(case), "0.2")
    assert "Mesh OK." in (case / "log.checkMesh").read_text()
    assert "SIMPLE solution converged" in (case / "log.simpleFoam").read_text()
    x = float(re.fullmatch(r"reattachment (\S+)", proc.stdout.strip().splitlines()[-1])[1])
    assert REATTACHMENT[0] < x < REATTACHMENT[1]
