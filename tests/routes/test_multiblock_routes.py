"""The multi-block routes: the VTK algorithm and pyvista's ``blocks=``."""

from __future__ import annotations

import json
import signal

import numpy as np
import pytest
import pyvista as pv
from helpers import ROOT, OutputMessages, run_blocks
from multiblock_checks import first_edges, patch_walls, wall_angles
from vtkmodules.vtkCommonCore import vtkOutputWindow
from vtkmodules.vtkCommonDataModel import vtkCompositeDataSet
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

from pinn_engine.errors import InputError
from pinn_engine.routes.filters import folded_warning
from pinn_engine.routes.multiblock_algorithm import MOVE_EDGES, PinnMultiBlockAlgorithm
from pinn_engine.settings import BLOCKS_METHOD, make_settings

DATA = ROOT / "example_data"
CELL_SIZE = 0.1  # docs/multiblock.md's L-shape and step: well under a second each


def _read(name: str):
    """The polydata of an example file."""
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(DATA / name))
    reader.Update()
    return reader.GetOutput()


def _cli_grids(example: str, method: str = BLOCKS_METHOD, interfaces: str = "free"):
    settings = make_settings(method, cell_size=CELL_SIZE, interfaces=interfaces)
    return run_blocks(settings, DATA / f"{example}.vtp", [DATA / f"{example}_blocks.vtp"])


def _points(grid) -> np.ndarray:
    ext = grid.GetExtent()
    return np.array(grid.GetPoints().GetData()).reshape(ext[3] + 1, ext[1] + 1, 3)


def test_algorithm_gives_the_command_lines_blocks_with_progress():
    alg = PinnMultiBlockAlgorithm()
    alg.SetInputDataObject(0, _read("step.vtp"))
    alg.AddInputDataObject(1, _read("step_blocks.vtp"))
    alg.SetCellSize(CELL_SIZE)
    progress = []
    alg.AddObserver("ProgressEvent", lambda obj, event: progress.append(obj.GetProgress()))
    handlers = {s: signal.getsignal(s) for s in (signal.SIGINT, signal.SIGTERM, signal.SIGUSR1)}
    window = vtkOutputWindow.GetInstance()
    alg.Update()
    assert {s: signal.getsignal(s) for s in handlers} == handlers  # the host as found
    assert vtkOutputWindow.GetInstance() is window
    assert alg.GetLastError() == "" and min(progress) == 0.0 and max(progress) == 1.0
    out = alg.GetOutput()
    expected = _cli_grids("step")
    assert out.GetNumberOfBlocks() == len(expected.grids) == 4
    for k, grid in enumerate(expected.grids):
        block = out.GetBlock(k)
        assert out.GetMetaData(k).Get(vtkCompositeDataSet.NAME()) == f"block{k}"
        assert np.array_equal(_points(block)[..., :2], grid)
        for name in ("MaxIncludedAngle", "MinIncludedAngle", "ScaledJacobian", "Folded"):
            assert block.GetCellData().GetArray(name) is not None
        report = json.loads(block.GetFieldData().GetAbstractArray("Report").GetValue(0))
        assert report["block"] == k and report["multiblock"]["blocks"] == 4


def test_boundary_and_edges_on_one_input_and_the_settings():
    alg = PinnMultiBlockAlgorithm()
    alg.AddInputDataObject(0, _read("lshape_blocks.vtp"))  # selected together
    alg.AddInputDataObject(0, _read("lshape.vtp"))
    alg.SetCellSize(CELL_SIZE)
    alg.SetMethod(0)  # ParaView's enumeration index: tfi
    alg.SetInterfaces("fixed")
    assert alg.GetSettings().method == "tfi" and alg.GetSettings().interfaces == "fixed"
    alg.Update()
    expected = _cli_grids("lshape", "tfi", "fixed").grids
    out = alg.GetOutput()
    assert out.GetNumberOfBlocks() == 2
    for k, grid in enumerate(expected):
        assert np.array_equal(_points(out.GetBlock(k))[..., :2], grid)
    with pytest.raises(ValueError, match="unknown method 'mgnet'"):
        alg.SetMethod("mgnet")


@pytest.mark.parametrize(
    ("edges", "message"),
    [
        (
            pv.Line((1.0, 0.6, 0.0), (1.5, 0.7, 0.0)),
            "PINN Structured Mesh (Multi-Block): block edges input line 0: ends nowhere at "
            "(1, 0.6)",
        ),
    ],
)
def test_errors_are_one_line_in_the_panels_words(edges, message):
    alg = PinnMultiBlockAlgorithm()
    alg.SetInputDataObject(0, _read("step.vtp"))
    if edges is not None:
        alg.AddInputDataObject(1, edges)
    with OutputMessages(alg, "ErrorEvent") as said:
        alg.Update()
    assert alg.GetLastError().startswith(message)
    assert alg.GetOutput().GetNumberOfBlocks() == 0
    assert isinstance(alg.GetLastException(), InputError) and len(said.events) == 1
    assert said.lines == [alg.GetLastError()]


def test_manual_blocking_without_edges_proposes_them_in_paraview():
    """The panel's first Apply (Blocking Manual, the default, and no edges connected) meshes
    with the proposed edges, and says so; a script asking for Manual is told."""
    alg = PinnMultiBlockAlgorithm()
    alg.SetMethod("elliptic")
    alg.SetInputDataObject(0, _read("lshape.vtp"))
    alg.Update()
    assert alg.GetLastError() == "" and alg.GetOutput().GetNumberOfBlocks() >= 2
    assert "automatic blocking:" in alg.GetLastSummary()
    assert alg.GetBlockEdges().GetNumberOfCells() >= 1
    script = PinnMultiBlockAlgorithm(route="pyvista")
    script.SetInputDataObject(0, _read("lshape.vtp"))
    script.Update()
    assert "no block edges (open polylines) among the inputs" in str(script.GetLastException())


def test_pyvista_blocks_returns_a_multiblock():
    boundary = pv.read(DATA / "lshape.vtp")
    edges = pv.read(DATA / "lshape_blocks.vtp")
    blocks = boundary.pinn_mesh(blocks=edges, cell_size=CELL_SIZE)
    assert isinstance(blocks, pv.MultiBlock) and blocks.keys() == ["block0", "block1"]
    assert boundary.pinn_mesh.last is blocks
    for grid, expected in zip(blocks, _cli_grids("lshape").grids):
        assert isinstance(grid, pv.StructuredGrid)
        assert np.array_equal(_points(grid)[..., :2], expected)
        assert {"MaxIncludedAngle", "Folded"} <= set(grid.cell_data.keys())
    tfi = boundary.pinn_mesh(blocks=[edges], cell_size=CELL_SIZE, method="tfi")
    assert json.loads(tfi[0].field_data["Report"][0])["method"] == "tfi"


def test_pyvista_blocks_errors_name_its_keywords():
    boundary = pv.read(DATA / "lshape.vtp")
    edges = pv.read(DATA / "lshape_blocks.vtp")
    with pytest.raises(InputError, match="^size= applies to four-sided domains, not to blocks="):
        boundary.pinn_mesh(blocks=edges, size=(41, 21))
    with pytest.raises(InputError, match="no block edges .*; give them as blocks=$"):
        boundary.pinn_mesh(blocks=[])
    with pytest.raises(ValueError, match="cell_size"):
        boundary.pinn_mesh(blocks=edges, cell_size=-1.0)
    with pytest.raises(InputError, match="no closed polyline .* close it"):
        edges.pinn_mesh(blocks=edges)
    with pytest.raises(InputError, match="^blocks: expected a pyvista/VTK PolyData"):
        boundary.pinn_mesh(blocks=[edges, "edges.vtp"])


def test_folded_cells_warning_in_each_routes_words():
    report = {"quality": {"folded_cells": 3}, "cells": 100, "method": "tfi"}
    assert (
        folded_warning(report, "pyvista", MOVE_EDGES)
        == '3 of 100 cells are folded; try method="elliptic"'
    )
    assert (
        folded_warning(report, "paraview", MOVE_EDGES)
        == "3 of 100 cells are folded; try Method elliptic"
    )
    elliptic = {**report, "method": "elliptic", "quality": {"folded_cells": 1}}
    assert folded_warning(elliptic, "paraview", MOVE_EDGES).startswith(
        "1 of 100 cells is folded; try moving"
    )
    assert folded_warning({**report, "quality": {"folded_cells": 0}}, "paraview", "") is None


CYLINDER = {(0.5, 0): "cylinder:wall", (0, 0.5): "cylinder", (-0.5, 0): "cylinder"}
CYLINDER[(0, -0.5)] = "cylinder"
H = 0.005  # the first cell at the cylinder's wall


def test_pyvista_blocks_spacing_and_orthogonal_on_a_patch():
    """Spacing and orthogonality at a patch through pyvista: the cylinder's pieces named by
    ``patches=``, a first cell of 0.005 within 10 % and lines within 2 degrees of the normal
    there, node for node the command line's grid with the same ``--patch``, ``--spacing``
    and ``--orthogonal``."""
    boundary = pv.read(DATA / "cylinder_channel.vtp")
    edges = pv.read(DATA / "cylinder_channel_blocks.vtp")
    blocks = boundary.pinn_mesh(
        blocks=edges,
        cell_size=CELL_SIZE,
        method="elliptic",
        patches=CYLINDER,
        spacing={"cylinder": H},
        orthogonal="cylinder",
    )
    walls = patch_walls(blocks, "cylinder")
    assert len(walls) == 4
    assert np.abs(first_edges(walls) / H - 1).max() <= 0.1
    assert wall_angles(walls).max() <= 2.0
    items = [f"--patch={x:g},{y:g}={name}" for (x, y), name in CYLINDER.items()]
    expected = run_blocks(
        make_settings("elliptic", cell_size=CELL_SIZE),
        DATA / "cylinder_channel.vtp",
        [DATA / "cylinder_channel_blocks.vtp"],
        [item.removeprefix("--patch=") for item in items],
        [f"cylinder={H}"],
        ["cylinder"],
    ).grids
    for grid, points in zip(blocks, expected):
        assert np.array_equal(_points(grid)[..., :2], points)


def test_patch_settings_take_strings_sequences_and_mappings():
    alg = PinnMultiBlockAlgorithm()
    alg.SetPatchNames("0.5,0=cylinder:wall  0,0.5=cylinder")
    assert alg.GetPatchNames() == ("0.5,0=cylinder:wall", "0,0.5=cylinder")
    alg.SetPatchNames({(-0.5, 0): "cylinder"})
    assert alg.GetPatchNames() == ("-0.5,0.0=cylinder",)
    alg.SetSpacing("cylinder=0.005, walls=0.01")
    assert alg.GetSpacing() == ("cylinder=0.005", "walls=0.01")
    alg.SetSpacing({"cylinder": 0.005})
    assert alg.GetSpacing() == ("cylinder=0.005",)
    alg.SetSpacing("cylinder=0.005 -0.3,0.2=0.01")  # a side's point keeps its comma
    assert alg.GetSpacing() == ("cylinder=0.005", "-0.3,0.2=0.01")
    alg.SetSpacing({(0.3, 0.2): 0.01})
    assert alg.GetSpacing() == ("0.3,0.2=0.01",)
    alg.SetPatchNames({"hole1": "cylinder:wall"})
    assert alg.GetPatchNames() == ("hole1=cylinder:wall",)
    alg.SetCells({(1.2, 0.41): 40})
    assert alg.GetCells() == ("1.2,0.41=40",)
    alg.SetOrthogonal("cylinder,walls")
    assert alg.GetOrthogonal() == ("cylinder", "walls")
    alg.SetOrthogonal(["cylinder"])
    assert alg.GetOrthogonal() == ("cylinder",)
    alg.SetSpacing(None)
    assert alg.GetSpacing() == ()


@pytest.mark.parametrize(
    ("route", "options", "message"),
    [
        (
            "pyvista",
            {"spacing": {"cylindr": H}},
            "spacing cylindr=: no patch named 'cylindr'; the patches are boundary, hole1 (name "
            'boundary pieces with patches=["X,Y=NAME", ...])',
        ),
        (
            "paraview",
            {"orthogonal": "cylinder"},
            "PINN Structured Mesh (Multi-Block): orthogonal cylinder: no patch named 'cylinder'; "
            "the patches are boundary, hole1 (name boundary pieces with Patch Names' X,Y=NAME "
            "items)",
        ),
        (
            "pyvista",
            {"patches": ["0.5,0"]},
            "patch '0.5,0': expected X,Y=NAME[:TYPE] naming the boundary piece nearest the "
            "point (X, Y)",
        ),
        ("pyvista", {"spacing": ["cylinder"]}, "spacing 'cylinder': expected NAME=H, a patch"),
        (
            "pyvista",
            {"patches": ["0.5,0=cylinder:hot"]},
            "patch type 'hot' of 'cylinder': use wall, inflow, outflow, farfield, symmetry, "
            'patch (patches=["X,Y=NAME", ...])',
        ),
    ],
)
def test_patch_errors_are_one_line_in_each_routes_words(route, options, message):
    """A bad patch item or spacing, or a name no piece carries: one line, before meshing."""
    boundary = pv.read(DATA / "cylinder_channel.vtp")
    edges = pv.read(DATA / "cylinder_channel_blocks.vtp")
    if route == "pyvista":
        with pytest.raises(InputError) as caught:
            boundary.pinn_mesh(blocks=edges, cell_size=CELL_SIZE, method="tfi", **options)
        assert str(caught.value).startswith(message)
        return
    alg = PinnMultiBlockAlgorithm()
    alg.SetInputDataObject(0, boundary)
    alg.AddInputDataObject(1, edges)
    alg.SetMethod("tfi")
    alg.SetOrthogonal(options["orthogonal"])
    with OutputMessages(alg, "ErrorEvent") as said:
        alg.Update()
    assert alg.GetLastError() == message
    assert said.lines == [message]


def test_block_edges_from_a_table_mesh_as_from_their_vtp(tmp_path, capsys):
    """``--blocks`` reads .csv/.txt tables as the boundary does, a blank line between
    polylines; ``-q`` is ``--quiet``."""
    from pinn_engine.io.fileio import aux_lines_of
    from pinn_engine.routes.cli import main

    edges = [line.points[:, :2] for line in aux_lines_of(_read("step_blocks.vtp"))]
    table = tmp_path / "edges.csv"
    table.write_text(
        "x,y\n" + "\n\n".join("\n".join(f"{float(x)!r},{float(y)!r}" for x, y in e) for e in edges)
    )
    grids = []
    for name, blocks in (("csv", table), ("vtp", DATA / "step_blocks.vtp")):
        out = tmp_path / f"{name}.vtm"
        argv = [str(DATA / "step.vtp"), "--blocks", str(blocks), "-o", str(out), "-q"]
        assert main([*argv, "--method", "elliptic", "--cell-size", str(CELL_SIZE)]) == 0
        grids.append(pv.read(out))
    assert capsys.readouterr().err == ""
    assert grids[0].n_blocks == grids[1].n_blocks == 4
    for a, b in zip(grids[0], grids[1]):
        assert np.allclose(a.points, b.points)


def test_the_summary_comes_after_the_grid_is_written(tmp_path, monkeypatch):
    """A reader that stops at the first line (``| head -1``) cannot leave an old grid."""
    from pinn_engine.routes.cli import main, summary

    out = tmp_path / "step.vtm"
    said = []
    monkeypatch.setattr(summary, "say", lambda text: said.append(out.exists()))
    argv = [str(DATA / "step.vtp"), "--blocks", str(DATA / "step_blocks.vtp"), "-o", str(out)]
    assert main([*argv, "--method", "elliptic", "--cell-size", str(CELL_SIZE)]) == 0
    assert said and all(said)


def test_the_vtk_and_pyvista_routes_take_the_blocks_training_settings():
    """The multi-block VTK algorithm's SetSetting and pinn_mesh_blocks' keywords reach the
    blocks' settings, as the command line's flags do; another kind's setting is refused."""
    from pinn_engine.errors import SettingsError
    from pinn_engine.routes.pyvista_accessor.multiblock import pinn_mesh_blocks

    alg = PinnMultiBlockAlgorithm()
    alg.SetSetting("adam_epochs", 50)
    alg.SetSetting("hidden_layers", 3)
    settings = alg.GetSettings()
    assert (settings.adam_epochs, settings.hidden_layers) == (50, 3)
    alg.SetSetting("preset", "paper")
    assert alg.GetSettings().lbfgs_iterations == make_settings(preset="paper").lbfgs_iterations
    alg.SetSetting("adam_epochs", None)
    assert alg.GetSettings().adam_epochs == make_settings(preset="paper").adam_epochs
    with pytest.raises(SettingsError, match="unknown setting topology"):
        alg.SetSetting("topology", "o")
    boundary, edges = pv.read(DATA / "lshape.vtp"), pv.read(DATA / "lshape_blocks.vtp")
    with pytest.raises(ValueError, match="hidden_layers 0"):
        pinn_mesh_blocks(boundary, edges, cell_size=CELL_SIZE, hidden_layers=0)
    grid = boundary.pinn_mesh(blocks=edges, cell_size=CELL_SIZE, method="elliptic", seed=3)
    assert grid.n_blocks == 2
