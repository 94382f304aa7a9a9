"""PinnMeshAlgorithm in plain VTK pipelines (pip vtk)."""

from __future__ import annotations

import json
import subprocess
import sys
import time

import numpy as np
import pytest
from helpers import EXAMPLES, ROOT, OutputMessages
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkPolyData
from vtkmodules.vtkCommonExecutionModel import vtkStreamingDemandDrivenPipeline
from vtkmodules.vtkFiltersSources import vtkLineSource, vtkPolyLineSource
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

from pinn_engine.errors import TrainingError
from pinn_engine.io.vtkgrid import loss_history
from pinn_engine.routes.algorithm import PREPARE_SHARE, PinnMeshAlgorithm
from pinn_engine.settings import Settings

SHORT = {"adam_epochs": 60, "lbfgs_iterations": 5}


def reader(name: str) -> vtkXMLPolyDataReader:
    r = vtkXMLPolyDataReader()
    r.SetFileName(str(EXAMPLES / name))
    return r


KEEP: list = []  # an output port does not keep its producer alive: hold the readers


def connect(alg, port: int, producer, add: bool = False) -> None:
    KEEP.append(producer)
    if add:
        alg.AddInputConnection(port, producer.GetOutputPort())
    else:
        alg.SetInputConnection(port, producer.GetOutputPort())


def make_alg(case: str = "fig2", aux: bool = True, **settings) -> PinnMeshAlgorithm:
    alg = PinnMeshAlgorithm()
    connect(alg, 0, reader(f"{case}.vtp"))
    if aux:
        connect(alg, 1, reader(f"{case}_aux.vtp"), add=True)
    for name, value in {**SHORT, **settings}.items():
        alg.SetSetting(name, value)
    return alg


def points(alg) -> np.ndarray:
    return vtk_to_numpy(alg.GetOutput().GetPoints().GetData()).copy()


def field(alg, name: str):
    return alg.GetOutput().GetFieldData().GetArray(name).GetValue(0)


@pytest.fixture(scope="module")
def trained():
    """One trained algorithm shared by the tests that only re-evaluate it."""
    alg = make_alg()
    progress: list[float] = []
    alg.AddObserver("ProgressEvent", lambda obj, event: progress.append(obj.GetProgress()))
    alg.Update()
    return alg, progress


def test_pipeline_output(trained):
    alg, progress = trained
    assert alg.GetLastError() == ""
    grid = alg.GetOutput()
    assert grid.GetClassName() == "vtkStructuredGrid"
    assert grid.GetExtent() == (0, 40, 0, 20, 0, 0) and grid.GetNumberOfPoints() == 41 * 21
    for name in ("MaxIncludedAngle", "MinIncludedAngle", "ScaledJacobian", "Folded"):
        assert grid.GetCellData().GetArray(name).GetNumberOfTuples() == 40 * 20
    fd = grid.GetFieldData()
    assert fd.GetAbstractArray("Method").GetValue(0) == "pinn"
    history = loss_history(alg.GetOutput())  # one array, a component per term
    assert len(history["total"]) > 0 and {"eqns", "data"} <= set(history)
    assert fd.GetArray("LossHistory").GetNumberOfComponents() == len(history)
    assert not any(fd.GetArrayName(k).startswith("Loss_") for k in range(fd.GetNumberOfArrays()))
    assert field(alg, "Trained") == 1 and alg.GetTrainingCount() == 1
    assert progress[0] == 0.0 and progress[-1] == 1.0 and len(progress) >= 4
    assert progress == sorted(progress)


def test_progress_text_names_the_filter_and_the_phase():
    alg = make_alg(method="pinn")
    texts: list[str] = []
    alg.AddObserver("ProgressEvent", lambda obj, event: texts.append(obj.GetProgressText()))
    alg.Update()
    assert texts and all(t.startswith("PINN Structured Mesh") for t in texts)
    assert "PINN Structured Mesh: training (Adam)" in texts  # the phase, as training goes
    # "training" only once a step has run (before it, torch's import and the start grid)
    first_step = texts.index("PINN Structured Mesh: training (Adam)")
    assert "PINN Structured Mesh: preparing to train" in texts[:first_step]
    assert not any("training" in t for t in texts[:first_step])
    assert texts.index("PINN Structured Mesh: meshing") < texts.index("PINN Structured Mesh: done")


def test_whole_extent_in_request_information():
    alg = make_alg(method="tfi")
    alg.SetGridSize(17, 9)
    alg.UpdateInformation()
    info = alg.GetOutputInformation(0)
    assert info.Get(vtkStreamingDemandDrivenPipeline.WHOLE_EXTENT()) == (0, 16, 0, 8, 0, 0)


def test_grid_size_change_reevaluates_without_training():
    alg = make_alg(warm_start="none")  # trained from TFI: nothing depends on the size
    alg.Update()
    before = points(alg)
    alg.SetGridSize(81, 41)
    alg.Update()
    assert alg.GetOutput().GetExtent() == (0, 80, 0, 40, 0, 0)
    assert field(alg, "Trained") == 0 and alg.GetTrainingCount() == 1
    fine = points(alg).reshape(41, 81, 3)
    np.testing.assert_allclose(fine[::2, ::2].reshape(-1, 3), before, atol=1e-12)
    alg.SetGridSize(41, 21)  # and back: still the same network
    alg.Update()
    np.testing.assert_array_equal(points(alg), before)
    assert alg.GetTrainingCount() == 1


def test_warm_start_is_tuned_to_the_grid_size(trained):
    """The default warm start is the grid at the output size: a new size tries the map under
    that size's guard, here the quality objective's ranking; the 41 x 21 map (fig2's
    optimised grid: worst 125.3) ranks above the 31 x 15 start (132.8), so the new size is a
    forward pass, no training; the size it was tuned for comes back from the cache."""
    alg, _ = trained
    alg.SetGridSize(41, 21)
    alg.Update()
    count = alg.GetTrainingCount()
    alg.SetGridSize(31, 15)
    alg.Update()
    assert field(alg, "Trained") == 0 and alg.GetTrainingCount() == count
    report = json.loads(alg.GetOutput().GetFieldData().GetAbstractArray("Report").GetValue(0))
    assert report["resized"]["result"] == "network"
    guard = report["resized"]["guard"]
    assert guard["network"]["worst_max_angle"] < guard["start"]["worst_max_angle"]
    alg.SetGridSize(41, 21)
    alg.Update()
    assert field(alg, "Trained") == 0 and alg.GetTrainingCount() == count


def test_panel_values_left_at_their_defaults_follow_the_preset():
    alg = PinnMeshAlgorithm()
    defaults = Settings()
    for name in ("adam_epochs", "lbfgs_iterations", "lambda2", "seed"):
        alg.SetPanelSetting(name, getattr(defaults, name))
    alg.SetPreset("paper")
    paper = alg.GetSettings()
    assert (paper.adam_epochs, paper.lbfgs_iterations, paper.lambda2) == (5000, 500, 10.0)
    alg.SetPanelSetting("adam_epochs", 700)  # a changed value is used as set
    assert alg.GetSettings().adam_epochs == 700


def test_per_preset_values_are_used_only_under_their_preset():
    # the panel's Adam Epochs (default) and Paper Adam Epochs (paper)
    alg = PinnMeshAlgorithm()
    alg.SetPresetSetting("default", "adam_epochs", 700)
    alg.SetPresetSetting("paper", "lbfgs_iterations", 90)
    assert (alg.GetSettings().adam_epochs, alg.GetSettings().lbfgs_iterations) == (700, 120)
    alg.SetPreset("paper")
    paper = alg.GetSettings()
    assert (paper.adam_epochs, paper.lbfgs_iterations, paper.lambda2) == (5000, 90, 10.0)
    stamp = alg.GetMTime()
    alg.SetPresetSetting("paper", "lambda2", 10.0)  # the preset's own value: no change
    assert alg.GetMTime() == stamp and alg.GetSettings().lambda2 == 10.0


def test_training_setting_change_retrains():
    alg = make_alg(case="wavy", aux=False, method="mgnet", adam_epochs=20, lbfgs_iterations=0)
    alg.Update()
    alg.SetSeed(1)
    alg.Update()
    assert field(alg, "Trained") == 1 and alg.GetTrainingCount() == 2
    alg.SetSeed(0)  # the first network is still cached
    alg.Update()
    assert field(alg, "Trained") == 0 and alg.GetTrainingCount() == 2


def test_several_aux_connections_equal_one_input_with_several_lines(trained):
    alg, _ = trained
    alg.SetGridSize(41, 21)
    alg.Update()
    split = PinnMeshAlgorithm()
    connect(split, 0, reader("fig2.vtp"))
    lines = reader("fig2_aux.vtp")
    lines.Update()
    aux = lines.GetOutput()
    assert aux.GetNumberOfCells() == 2
    for k in range(2):  # each auxiliary polyline through its own connection
        ids = aux.GetCell(k).GetPointIds()
        source = vtkPolyLineSource()
        source.SetNumberOfPoints(ids.GetNumberOfIds())
        for i in range(ids.GetNumberOfIds()):
            source.SetPoint(i, *aux.GetPoint(ids.GetId(i)))
        connect(split, 1, source, add=True)
    for name, value in SHORT.items():
        split.SetSetting(name, value)
    split.Update()
    assert split.GetLastError() == "" and field(split, "Trained") == 1
    np.testing.assert_allclose(points(split), points(alg), atol=1e-9)


def test_bad_boundary_empty_output_one_message_then_recovers():
    alg = make_alg(case="fig2", aux=False)
    connect(alg, 0, reader("fig2_aux.vtp"))  # two open polylines
    with OutputMessages(alg, "ErrorEvent") as errors:
        alg.Update()
        alg.Update()  # nothing changed: not repeated
    assert alg.GetOutput().GetNumberOfPoints() == 0
    expected = (
        "PINN Structured Mesh: boundary input: holds 2 separate curves; the boundary "
        "must be one closed polyline"
    )
    assert errors.lines == [expected] and errors.events == [expected]
    assert alg.GetLastError() == expected
    connect(alg, 0, reader("fig2.vtp"))
    alg.SetMethod("tfi")
    alg.Update()
    assert alg.GetLastError() == "" and alg.GetOutput().GetNumberOfPoints() == 41 * 21


def test_bad_aux_line_is_named():
    line = vtkPolyData()
    src = vtkLineSource()  # from the middle of the domain to far outside
    src.SetPoint1(0.5, 0.4, 0)
    src.SetPoint2(9, 9, 0)
    src.Update()
    line.DeepCopy(src.GetOutput())
    alg = make_alg(case="fig2", aux=False)
    alg.AddInputDataObject(1, line)
    with OutputMessages(alg, "ErrorEvent") as errors:
        alg.Update()
    assert alg.GetOutput().GetNumberOfPoints() == 0
    assert len(errors.lines) == 1
    assert errors.lines[0].startswith("PINN Structured Mesh: auxiliary input 0 line 0")


def test_failed_training_reported(monkeypatch):
    from pinn_engine.kinds.four_sided import mesher

    def fail(self, boundary, aux_lines=(), progress=None):
        raise TrainingError("training diverged (loss nan at Adam epoch 3)")

    monkeypatch.setattr(mesher.Mesher, "fit", fail)
    alg = make_alg()
    with OutputMessages(alg, "ErrorEvent") as errors:
        alg.Update()
    assert errors.lines == ["PINN Structured Mesh: training diverged (loss nan at Adam epoch 3)"]
    assert alg.GetOutput().GetNumberOfPoints() == 0


def test_invalid_settings_reported():
    alg = make_alg(method="tfi")
    alg.SetGridSize(1, 5)
    with OutputMessages(alg, "ErrorEvent") as errors:
        alg.Update()
    assert len(errors.lines) == 1
    assert "invalid settings: Grid Size 1 5: each side" in errors.lines[0]
    alg.SetGridSize(5, 5)
    alg.SetAdamEpochs(-3)
    with OutputMessages(alg, "ErrorEvent") as errors:
        alg.Update()
    assert errors.lines == [
        "PINN Structured Mesh: invalid settings: adam_epochs -3: must be "
        "a whole number from 0 to 1000000"
    ]


@pytest.mark.slow  # two trainings through the filter, one stopped part-way
def test_abort_stops_training_with_its_best_grid_and_next_update_trains():
    """The progress bar's abort button (AbortExecute, read at the worker's next progress
    report) ends the training at once with the grid of its best state and a warning; the
    stopped training is not kept, so the next update trains again."""
    alg = make_alg(adam_epochs=2000, lbfgs_iterations=0)

    pressed = []

    def abort(obj, event):  # the user presses "abort" once, during training
        if obj.GetProgress() > 0.05 and not pressed:
            pressed.append(obj.GetProgress())
            obj.SetAbortExecute(1)

    tag = alg.AddObserver("ProgressEvent", abort)
    began = time.perf_counter()
    with OutputMessages(alg, "WarningEvent") as warnings:
        alg.Update()
    assert time.perf_counter() - began < 20  # 2000 Adam epochs take minutes
    assert alg.GetLastError() == "" and alg.GetOutput().GetNumberOfPoints() == 41 * 21
    assert len(warnings.lines) == 1 and "training stopped after" in warnings.lines[0]
    assert "a stop was asked during adam" in warnings.lines[0]
    assert pressed[0] < PREPARE_SHARE + 0.1 and not alg.GetAbortExecute()
    alg.RemoveObserver(tag)
    alg.SetAdamEpochs(60)
    alg.Update()
    assert alg.GetLastError() == "" and alg.GetOutput().GetNumberOfPoints() == 41 * 21


def test_corners_and_choices():
    alg = make_alg(case="wavy", aux=False, method="tfi")
    alg.Update()
    auto = points(alg)
    from pinn_engine.geometry.boundary import detect_corners
    from pinn_engine.io.fileio import read_boundary_points

    ring = read_boundary_points(EXAMPLES / "wavy.vtp")[:, :2]
    alg.SetCorners(*(int(i) for i in detect_corners(ring)))
    alg.Update()
    np.testing.assert_allclose(points(alg), auto, atol=1e-12)
    alg.SetCorners(0, 1, 2, 3)  # not four corners of this boundary: still a grid or an error
    alg.Update()
    alg.SetCorners(None)
    assert alg.GetCorners() is None
    alg.SetMethod(3)
    assert alg.GetMethod() == "elliptic"
    alg.SetPreset("paper")
    assert alg.GetSettings().boundary_fit == "tree" and alg.GetSettings().adam_epochs == 60
    with pytest.raises(ValueError):
        alg.SetMethod("magic")


def test_import_needs_no_torch_nor_pyvista():
    code = (
        "import sys, pinn_engine.routes.algorithm as a; a.PinnMeshAlgorithm(); "
        "print(sorted(m for m in ('torch', 'pyvista') if m in sys.modules))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code],
        cwd=ROOT,
        capture_output=True,
        text=True,
        timeout=120,
        check=True,
    ).stdout
    assert out.strip() == "[]"


@pytest.mark.slow  # the filter run once per way of connecting its inputs
def test_inputs_connected_together_are_told_apart():
    """ParaView's GUI connects every selected source to port 0: the closed curve is the
    boundary, the open polylines are auxiliary lines; two closed curves are an error."""
    together = PinnMeshAlgorithm()
    connect(together, 0, reader("fig2_aux.vtp"), add=True)
    connect(together, 0, reader("fig2.vtp"), add=True)
    for name, value in SHORT.items():
        together.SetSetting(name, value)
    together.Update()
    apart = make_alg()
    apart.Update()
    np.testing.assert_allclose(points(together), points(apart), atol=1e-9)
    report = json.loads(together.GetOutput().GetFieldData().GetAbstractArray("Report").GetValue(0))
    assert len(report["aux_lines"]) == 2
    two = PinnMeshAlgorithm()
    connect(two, 0, reader("fig2.vtp"), add=True)
    connect(two, 0, reader("wavy.vtp"), add=True)
    two.Update()
    assert two.GetOutput().GetNumberOfPoints() == 0
    assert "2 of the 2 connected inputs hold a closed curve" in two.GetLastError()


@pytest.mark.slow  # trains until the signal comes (about 3 s)
def test_sigusr1_stops_a_training_with_its_best_grid_and_the_handler_is_restored():
    """ParaView 5.11 runs no GUI event during a filter: ``pkill -USR1 -x paraview`` stops it,
    and the grid of the training so far comes with a warning (not an empty output)."""
    import os
    import signal
    import threading

    alg = make_alg(adam_epochs=200_000, lbfgs_iterations=0, warm_start="none")
    before = signal.getsignal(signal.SIGUSR1)
    timer = threading.Timer(3.0, os.kill, (os.getpid(), signal.SIGUSR1))
    timer.start()
    try:
        alg.Update()
    finally:
        timer.cancel()
    assert alg.GetLastError() == "" and alg.GetOutput().GetNumberOfPoints() == 41 * 21
    warning = alg.GetLastWarning()
    assert "training stopped after" in warning and "a stop was asked during adam" in warning
    assert "the grid of the best state so far is produced" in warning
    assert signal.getsignal(signal.SIGUSR1) == before


@pytest.mark.slow  # trains until the limit (about 3 s)
def test_time_limit_gives_the_best_grid_so_far_with_a_warning_and_is_not_cached():
    alg = make_alg(adam_epochs=200_000, lbfgs_iterations=0, warm_start="none", time_limit=1.5)
    with OutputMessages(alg, "WarningEvent") as warnings:
        alg.Update()
    assert alg.GetLastError() == "" and alg.GetOutput().GetNumberOfPoints() == 41 * 21
    assert len(warnings.lines) == 1
    assert "its time limit of 1.5 s ran out during adam" in warnings.lines[0]
    assert "give a larger Time Limit (0: none)" in warnings.lines[0]
    report = json.loads(alg.GetOutput().GetFieldData().GetAbstractArray("Report").GetValue(0))
    stopped = report["training"]["stopped"]
    assert stopped["reason"] == "time limit" and 1.5 <= stopped["seconds"] < 10
    assert 0 < report["training"]["adam_epochs"] < 200_000
    alg.Modified()  # a stopped training is not kept: the next update trains again
    alg.Update()
    assert alg.GetTrainingCount() == 2


def test_time_limit_in_lbfgs_keeps_the_state_the_guard_kept():
    """A time limit that ends L-BFGS (the Winslow objective, no Adam) gives the grid of the
    state the guard kept, never a line search's trial point: the grid written has the kept
    state's figures (the guard's lattice is the output's size)."""
    alg = make_alg(adam_epochs=0, lbfgs_iterations=100_000, time_limit=1.0, objective="winslow")
    alg.Update()
    report = json.loads(alg.GetOutput().GetFieldData().GetAbstractArray("Report").GetValue(0))
    training, quality = report["training"], report["quality"]
    assert training["stopped"]["phase"] == "lbfgs" and training["lbfgs_iterations"] < 100_000
    kept = training["guard"]["kept"]
    assert training["guard"]["lattice"] == [41, 21] and quality["folded_cells"] == 0
    for name in ("mean_max_angle", "worst_max_angle"):
        assert quality[name] == pytest.approx(kept[name], abs=1e-6), name


def test_an_airfoil_o_grid_reports_its_stages_before_training():
    """The elliptic grid and torch's set-up took seconds without a progress step."""
    from pinn_engine.routes.airfoil_algorithm import AirfoilSource

    alg = PinnMeshAlgorithm()
    connect(alg, 0, AirfoilSource())
    alg.SetTopology("o")
    alg.SetObjective("winslow")  # the default objective trains no body network
    alg.SetGridSize(65, 25)
    steps: list[tuple[float, str]] = []
    alg.AddObserver(
        "ProgressEvent", lambda obj, event: steps.append((obj.GetProgress(), obj.GetProgressText()))
    )
    alg.Update()
    assert alg.GetLastError() == ""
    texts = [text.removeprefix("PINN Structured Mesh: ") for _, text in steps]
    stages = ["body layout", "elliptic grid", "network set-up"]
    assert [t for t in texts if t in stages] == stages
    assert texts.index("network set-up") < texts.index("training (L-BFGS)")
    fractions = [f for f, t in steps if t.endswith(tuple(stages))]
    assert fractions == sorted(fractions) and fractions[-1] < PREPARE_SHARE


def test_topology_automatic_meshes_a_body_as_an_o_grid_and_a_boundary_as_four_sided():
    """The panel's default Topology (Automatic, index 3): the Airfoil source's curve and two
    closed rings (body inside far field) give O-grids at the first Apply; a four-sided
    boundary stays one."""
    from vtkmodules.vtkFiltersCore import vtkAppendPolyData

    from pinn_engine.routes.airfoil_algorithm import AirfoilSource
    from pinn_engine.routes.pyvista_accessor.inputs import ring_polydata

    source = AirfoilSource()
    t = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    rings = vtkAppendPolyData()
    rings.AddInputData(ring_polydata(np.column_stack([0.5 * np.cos(t), 0.2 * np.sin(t)]), True))
    rings.AddInputData(ring_polydata(np.column_stack([8 * np.cos(t), 8 * np.sin(t)]), True))
    for body in (source, rings):
        alg = PinnMeshAlgorithm()
        alg.SetTopology(3)
        alg.SetMethod("elliptic")
        alg.SetGridSize(65, 9)
        alg.SetInputConnection(0, body.GetOutputPort())
        alg.Update()
        assert alg.GetLastError() == "", alg.GetLastError()
        topology = alg.GetOutput().GetFieldData().GetAbstractArray("Topology")
        assert topology is not None and topology.GetValue(0) == "o"
        assert alg.GetLastSummary().startswith("Topology Automatic: the input is a body")
    four = make_alg(aux=False, method="tfi")
    four.SetTopology("auto")
    four.Update()
    assert four.GetOutput().GetFieldData().GetAbstractArray("Topology") is None
    assert four.GetOutput().GetNumberOfPoints() == 41 * 21
