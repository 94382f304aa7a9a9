"""The pyvista route: ``pinn_mesh()``, the ``PolyData.pinn_mesh`` accessor, the example."""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
from importlib.metadata import entry_points

import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES, ROOT, wavy_ring

from pinn_engine.errors import InputError, PinnMeshError
from pinn_engine.routes.pyvista_accessor import PinnMeshAccessor, pinn_mesh

SHORT = {"adam_epochs": 60, "lbfgs_iterations": 5}
ARRAYS = ("MaxIncludedAngle", "MinIncludedAngle", "ScaledJacobian", "Folded")


@pytest.fixture
def fig2():
    return pv.read(EXAMPLES / "fig2.vtp"), pv.read(EXAMPLES / "fig2_aux.vtp")


def test_function_returns_structured_grid(fig2):
    boundary, aux = fig2
    grid = pinn_mesh(boundary, aux=aux, size=(31, 16), **SHORT)
    assert isinstance(grid, pv.StructuredGrid)
    assert grid.dimensions == (31, 16, 1) and grid.n_cells == 30 * 15
    assert all(name in grid.cell_data for name in ARRAYS)
    assert grid.active_scalars_name == "MaxIncludedAngle"
    assert str(grid.field_data["Method"][0]) == "pinn"
    history = grid.field_data["LossHistory"]  # a row per evaluation, a component per term
    assert history.ndim == 2 and history.shape[1] > 5 and history.shape[0] > 60
    # boundary nodes lie on the input boundary
    assert np.isclose(grid.points[:, 0].min(), boundary.points[:, 0].min())


@pytest.mark.slow  # several trainings through the accessor
def test_accessor_trains_once_per_training_key(fig2):
    boundary, aux = fig2
    short = {**SHORT, "warm_start": "none"}  # from TFI: the size is not part of the key
    assert isinstance(boundary.pinn_mesh, PinnMeshAccessor)
    coarse = boundary.pinn_mesh(aux=aux, size=(21, 11), **short)
    fine = boundary.pinn_mesh.mesh(aux=aux, size=(41, 21), **short)  # the same, namespaced
    assert boundary.pinn_mesh.trainings == 1
    np.testing.assert_allclose(
        fine.points.reshape(21, 41, 3)[::2, ::2].reshape(-1, 3), coarse.points, atol=1e-12
    )
    boundary.pinn_mesh(aux=aux, size=(21, 11), seed=1, **short)
    assert boundary.pinn_mesh.trainings == 2
    boundary.pinn_mesh.clear()
    boundary.pinn_mesh(aux=aux, size=(21, 11), **short)
    assert boundary.pinn_mesh.trainings == 3


@pytest.mark.slow  # the same training through each input type the accessor takes
def test_inputs_as_vtk_arrays_and_lists(fig2):
    boundary, aux = fig2
    ring = wavy_ring()
    grid = pinn_mesh(ring, size=(11, 6), method="tfi")  # (n, 2) array, closed automatically
    assert grid.dimensions == (11, 6, 1)
    lines = [aux.extract_cells(k) for k in range(aux.n_cells)]  # unstructured grids of lines
    one = pinn_mesh(boundary, aux=aux, size=(11, 6), **SHORT)
    two = pinn_mesh(boundary, aux=lines, size=(11, 6), **SHORT)  # a list of polylines
    np.testing.assert_allclose(one.points, two.points, atol=1e-9)
    vtk_boundary = pv.PolyData()
    vtk_boundary.deep_copy(boundary)
    assert pinn_mesh(vtk_boundary, size=(5, 5), method="elliptic").n_points == 25


def test_errors_are_one_line(fig2):
    boundary, aux = fig2
    with pytest.raises(InputError, match="2 separate curves") as info:
        pinn_mesh(aux, method="tfi")
    assert "\n" not in str(info.value)
    outside = pv.Line((0.5, 0.4, 0), (9, 9, 0), resolution=5)
    with pytest.raises(PinnMeshError, match="auxiliary input 0 line 0"):
        pinn_mesh(boundary, aux=outside, **SHORT)
    with pytest.raises(ValueError, match="method 'magic': use pinn, mgnet, tfi, elliptic"):
        boundary.pinn_mesh(method="magic")
    with pytest.raises(ValueError, match="size"):
        boundary.pinn_mesh(size=(1, 4), method="tfi")


def test_docstrings_teach_the_call():
    doc = PinnMeshAccessor.__doc__ + PinnMeshAccessor.__call__.__doc__
    assert "boundary.pinn_mesh(aux=" in doc and "size" in doc
    for word in ("aux", "size", "method", "preset", "adam_epochs", "Returns", "Examples"):
        assert word in pinn_mesh.__doc__


def test_entry_point_declares_the_accessor_module():
    eps = [ep for ep in entry_points(group="pyvista.accessors") if ep.name == "pinn_mesh"]
    assert len(eps) == 1, "pinn-mesh is not installed (pip install -e .)"
    # pyvista 0.49 imports the entry point's value with importlib.import_module: a module path
    assert eps[0].value == "pinn_engine.routes.pyvista_accessor", (
        f"entry point value {eps[0].value!r}: pyvista imports it as a module; it must be "
        "'pinn_engine.routes.pyvista_accessor' in pyproject.toml"
    )
    importlib.import_module(eps[0].value)


def test_accessor_found_through_entry_point_without_import():
    code = (
        "import sys, pyvista as pv\n"
        f"b = pv.read({str(EXAMPLES / 'wavy.vtp')!r})\n"
        "assert 'pinn_engine' not in sys.modules\n"
        "g = b.pinn_mesh(size=(9, 5), method='tfi')\n"
        "print(type(g).__name__, g.dimensions)\n"
    )
    proc = subprocess.run(
        [sys.executable, "-c", code], cwd="/", capture_output=True, text=True, timeout=120
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert proc.stdout.strip() == "StructuredGrid (9, 5, 1)"


@pytest.mark.slow  # the example script end to end, a picture off screen
def test_example_script_saves_a_picture(tmp_path):
    out = tmp_path / "example.png"
    env = dict(os.environ, VTK_DEFAULT_OPENGL_WINDOW="vtkEGLRenderWindow")
    proc = subprocess.run(
        [sys.executable, str(ROOT / "examples" / "pyvista_example.py"), "--quick", "-o", str(out)],
        cwd=tmp_path,
        env=env,
        capture_output=True,
        text=True,
        timeout=300,
    )
    assert proc.returncode == 0, proc.stderr[-2000:]
    assert "1 training(s)" in proc.stdout
    assert out.stat().st_size > 10_000
    image = pv.read(out)
    assert image.dimensions[:2] == (1000, 800)
    pixels = image.point_data[image.point_data.keys()[0]]
    assert len(np.unique(pixels.reshape(len(pixels), -1)[:, :3], axis=0)) > 20  # not blank


def test_every_keyword_reaches_the_settings(fig2):
    boundary, _ = fig2
    grid = pinn_mesh(
        boundary,
        size=(11, 6),
        boundary_mode="penalty",
        adam_epochs=20,
        lbfgs_iterations=20,  # the soft boundary's grid, placed on the boundary, unfolded
        hidden_layers=2,
        neurons=8,
        lambda2=5.0,
        seed=3,
        device="cpu",
    )
    import json

    report = json.loads(str(grid.field_data["Report"][0]))
    settings = report["settings"]
    assert settings["boundary_mode"] == "penalty" and settings["warm_start"] == "none"
    # the soft boundary's network only approached the sides; the grid's nodes are on them
    assert report["boundary_placed"]["network_deviation"] > 1e-4
    assert report["quality"]["boundary_deviation"] < 1e-12
    assert (settings["hidden_layers"], settings["neurons"], settings["seed"]) == (2, 8, 3)


def test_time_limit_and_a_stop_answer_return_the_best_grid_with_a_warning(fig2):
    from pinn_engine.errors import STOP, TrainingStoppedWarning

    boundary, aux = fig2
    long = {"adam_epochs": 100_000, "lbfgs_iterations": 0, "warm_start": "none"}
    with pytest.warns(TrainingStoppedWarning, match=r"time limit of 1 s .*time_limit="):
        grid = pinn_mesh(boundary, aux=aux, size=(21, 11), time_limit=1, **long)
    assert grid.n_points == 21 * 11
    steps = []

    def stop_after_two(info):
        steps.append(info["step"])
        return STOP if len(steps) == 2 else None

    with pytest.warns(TrainingStoppedWarning, match="a stop was asked during adam at step 100"):
        grid = pinn_mesh(boundary, aux=aux, size=(21, 11), progress=stop_after_two, **long)
    assert grid.n_points == 21 * 11 and steps == [50, 100]
