"""What the tests share: the example data folder, small boundaries, the one-line refusal of
a command, OpenFOAM's environment, ParaView's output messages and its GUI driven under Xvfb
(imported as ``helpers``; conftest.py holds only the session's set-up)."""

from __future__ import annotations

import functools
import os
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from vtkmodules.util.misc import calldata_type
from vtkmodules.vtkCommonCore import VTK_STRING, vtkOutputWindow, vtkStringOutputWindow

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "example_data"
CASES = ("wavy", "fig2", "concave")
# the fused jet kernels need a C++ compiler; without one the torch-operation path is tested
has_compiler = bool(os.environ.get("CXX") or shutil.which("c++") or shutil.which("g++"))
needs_compiler = pytest.mark.skipif(
    not has_compiler,
    reason="no C++ compiler: the fused jet kernels cannot be built here",
)


def foam_env() -> dict[str, str]:
    """The environment OpenFOAM's commands run in (Debian's openfoam package keeps its etc/
    files under /usr/share/openfoam; elsewhere its etc/bashrc sets WM_PROJECT_DIR)."""
    env = dict(os.environ)
    env.setdefault("WM_PROJECT_DIR", "/usr/share/openfoam")
    return env


GUI_TOOLS = ("paraview", "xvfb-run", "Xvfb", "xdotool", "import")


def skip_without_gui() -> None:
    """Skip the calling test module where a ParaView GUI cannot be driven here."""
    missing = [t for t in GUI_TOOLS if shutil.which(t) is None]
    if missing or not (Path(os.environ.get("PINN_PV_VENV", ROOT / ".venv-pv")) / "bin").exists():
        pytest.skip(
            f"ParaView GUI test needs {', '.join(missing) or '.venv-pv'} "
            "(bash scripts/setup_paraview.sh)",
            allow_module_level=True,
        )


def drive_gui(script: str, out: Path) -> Path:
    """Run ``tests/paraview/gui/SCRIPT`` (a GUI driven under its own Xvfb) writing into ``out``."""
    env = {k: v for k, v in os.environ.items() if k not in ("DISPLAY", "PYTHONPATH")}
    proc = subprocess.run(
        ["bash", str(ROOT / "tests" / "paraview" / "gui" / script), str(out)],
        env=env,
        capture_output=True,
        text=True,
        timeout=420,
    )
    assert proc.returncode == 0, proc.stderr[-3000:]
    return out


def refused(capsys, argv: list[str], out: Path) -> str:
    """The one-line error of a ``pinn-mesh`` run that must be refused: exit status 2, no
    file at ``out``, one line on stderr."""
    from pinn_engine.routes.cli import main

    assert main(argv) == 2
    assert not out.exists()
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and err.startswith("pinn-mesh: error:")
    return err


def square_ring(n: int = 10, size: float = 1.0) -> np.ndarray:
    """Counter-clockwise square with ``n`` segments per side, starting at (0, 0)."""
    t = np.linspace(0, size, n + 1)[:-1]
    z, s = np.zeros_like(t), np.full_like(t, size)
    return np.vstack(
        [
            np.column_stack([t, z]),
            np.column_stack([s, t]),
            np.column_stack([size - t, s]),
            np.column_stack([z, size - t]),
        ]
    )


def bumped_l() -> tuple[np.ndarray, list[np.ndarray]]:
    """The L of arm width 1 with a bump 0.15 high on its floor (the autoblock benchmark's)
    and the two edges that cut it into three blocks."""
    x = np.linspace(0.3, 1.7, 21)
    bump = np.c_[x, 0.15 * np.sin(np.pi * (x - 0.3) / 1.4) ** 2][1:-1]
    ring = np.vstack([[(0, 0)], bump, [(2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]])
    return ring, [np.array([(1, 1), (0, 1)]), np.array([(1, 1), (1, 0.15)])]


def wavy_ring(n: int = 24) -> np.ndarray:
    """A four-sided domain with wavy sides (2 x 1), CCW from (0, 0)."""
    s = np.linspace(0, 1, n + 1)[:-1]
    bottom = np.column_stack([2 * s, 0.1 * np.sin(2 * np.pi * s)])
    right = np.column_stack([2 + 0.1 * np.sin(np.pi * s), s])
    top = np.column_stack([2 - 2 * s, 1 + 0.1 * np.sin(3 * np.pi * s)])
    left = np.column_stack([-0.05 * np.sin(np.pi * s), 1 - s])
    return np.vstack([bottom, right, top, left])


class OutputMessages:
    """Collects vtkOutputWindow text (ParaView's Output Messages) and the algorithm's events
    of one kind ("ErrorEvent", "WarningEvent") inside a ``with`` block; ``lines`` are the
    messages but the summary lines a successful update tells (``told``)."""

    def __init__(self, alg, event: str) -> None:
        self.alg = alg
        self.window, self.old = vtkStringOutputWindow(), vtkOutputWindow.GetInstance()
        self.events: list[str] = []

        @calldata_type(VTK_STRING)
        def on_event(obj, name, message):
            self.events.append(message)

        alg.AddObserver(event, on_event)

    def __enter__(self):
        vtkOutputWindow.SetInstance(self.window)
        return self

    def __exit__(self, *exc):
        vtkOutputWindow.SetInstance(self.old)

    @property
    def told(self) -> list[str]:
        summary = getattr(self.alg, "GetLastSummary", lambda: "")()
        return [f"{self.alg.LABEL}: {line}" for line in summary.splitlines()]

    @property
    def lines(self) -> list[str]:
        told = set(self.told)
        return [ln for ln in self.window.GetOutput().splitlines() if ln.strip() and ln not in told]


def run_blocks(
    settings,
    boundary,
    edges,
    patches=(),
    spacing=(),
    orthogonal=(),
    progress=None,
    aux=(),
    cells=(),
):
    """The multi-block job of files, as the command line runs it (``job.blocks_from_files``
    then ``job.run``)."""
    from pinn_engine import job

    geometry = job.blocks_from_files(
        boundary, edges, aux, patches, spacing, orthogonal, cells, (), settings.cell_size
    )
    return job.run(settings, geometry, progress)


def write_selig(path: Path, xy, name: str = "TEST") -> Path:
    """An airfoil's points ``xy`` written to ``path`` as a Selig .dat file named ``name``."""
    path.write_text(name + "\n" + "\n".join(f"{x:.7f} {y:.7f}" for x, y in xy) + "\n")
    return path


@functools.cache
def trained_hexa(name: str, size: tuple[int, int, int]):
    """The hexahedral network of example ``name`` trained from its Winslow start at ``size``
    (the default keeps that start untrained, tests/kinds/test_untrained.py), and its TFI grid;
    trained once a session for the kind's tests and the routes' saved-model tests."""
    from pinn_engine.hexa.spacing import node_params, tfi_at
    from pinn_engine.hexa.surface import find_topology, surface_of
    from pinn_engine.io.fileio import read_polydata
    from pinn_engine.kinds.hexa import problem
    from pinn_engine.kinds.hexa.mesh import boundary_map, surface_key
    from pinn_engine.kinds.hexa.start import winslow_start
    from pinn_engine.settings import FACE_ANGLE, make_settings

    path = str(EXAMPLES / name)
    surface = surface_of(read_polydata(EXAMPLES / name), path, False, FACE_ANGLE)
    boundary, _ = boundary_map(surface, find_topology(surface, path), path)
    start = winslow_start(lambda shape: tfi_at(boundary, node_params(shape, {})), size)
    return problem.train(start, surface_key(surface), make_settings("pinn", size=size)), start.tfi
