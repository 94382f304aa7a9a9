"""Automatic blocking (SPEC 13): ``--blocks auto`` and its routes, the saved edges' round
trip, the four-sided domain and the refusal. Small grids: each run well under a second."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from conftest import ROOT, refused, square_ring
from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataReader, vtkXMLPolyDataReader

from pinn_engine.errors import InputError
from pinn_engine.io.export.edges import edges_of
from pinn_engine.job import run_blocks
from pinn_engine.multiblock.autoblock import propose_edges
from pinn_engine.routes.cli import main
from pinn_engine.routes.multiblock_algorithm import PinnMultiBlockAlgorithm
from pinn_engine.settings import AUTO_BLOCKS, make_settings

DATA = ROOT / "example_data"
CELL_SIZE = 0.25  # the L of arm width 1: 4 cells across an arm
FAST = ("--method", "elliptic", "--cell-size", str(CELL_SIZE), "--quiet")


def _polydata(path):
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    return reader.GetOutput()


def _vtm_points(path) -> list[np.ndarray]:
    reader = vtkXMLMultiBlockDataReader()
    reader.SetFileName(str(path))
    reader.Update()
    out = reader.GetOutput()
    return [np.array(out.GetBlock(k).GetPoints().GetData()) for k in range(out.GetNumberOfBlocks())]


def test_cli_auto_saves_edges_that_mesh_to_the_same_grid(tmp_path):
    auto, again, edges = tmp_path / "auto.vtm", tmp_path / "again.vtm", tmp_path / "edges.vtp"
    boundary = str(DATA / "lshape.vtp")
    assert (
        main([boundary, "--blocks", "auto", "--save-blocks", str(edges), *FAST, "-o", str(auto)])
        == 0
    )
    assert main([boundary, "--blocks", str(edges), *FAST, "-o", str(again)]) == 0
    saved = edges_of(_polydata(edges))
    assert len(saved) == 1 and np.allclose(saved[0][:, :2], [[1, 1], [0, 1]])  # the L's cut
    first, second = _vtm_points(auto), _vtm_points(again)
    assert len(first) == 2 and all(np.array_equal(a, b) for a, b in zip(first, second))


def test_four_sided_domain_stays_one_block(tmp_path):
    assert propose_edges([square_ring(4)]) == []
    path = tmp_path / "square.csv"
    np.savetxt(path, square_ring(4), delimiter=",")
    out = run_blocks(make_settings("elliptic", cell_size=0.25), path, [AUTO_BLOCKS])
    assert out.edges == [] and out.result.report["blocks"] == 1


def test_no_blocking_is_a_one_line_error(tmp_path, capsys):
    a = np.linspace(0, 2 * np.pi, 40, endpoint=False)
    path = tmp_path / "disc.csv"
    np.savetxt(path, np.column_stack([np.cos(a), np.sin(a)]), delimiter=",")
    out = tmp_path / "disc.vtm"
    err = refused(capsys, [str(path), "--blocks", "auto", *FAST, "-o", str(out)], out)
    assert "automatic blocking found no four-cornered blocks" in err
    assert err.endswith("draw the block edges and give them with --blocks EDGES")
    err = refused(
        capsys, [str(path), "--save-blocks", str(tmp_path / "e.vtp"), "-o", str(out)], out
    )
    assert "--save-blocks writes the block edges of --blocks" in err


@pytest.mark.parametrize(
    ("example", "blocks"),
    [("step", 2), ("tee", 2), ("ybranch", 6)],
)
def test_proposals_are_four_cornered_unfolded_and_few(example, blocks):
    """Every block four-cornered (the mesher refuses others), no fold, and no more blocks
    than the hand blocking of example_data (step 4, tee 4, Y-branch 6)."""
    settings = make_settings("elliptic", cell_size=0.2)
    out = run_blocks(settings, DATA / f"{example}.vtp", [AUTO_BLOCKS])
    report = out.result.report
    assert report["blocks"] == blocks and report["quality"]["folded_cells"] == 0


def test_algorithm_automatic_gives_blocks_and_the_edges_port():
    alg = PinnMultiBlockAlgorithm()
    alg.SetBlocking("automatic")
    alg.SetMethod("elliptic")
    alg.SetCellSize(CELL_SIZE)
    alg.SetInputDataObject(0, _polydata(DATA / "lshape.vtp"))
    alg.Update()
    assert alg.GetLastError() == ""
    assert alg.GetOutput().GetNumberOfBlocks() == 2
    assert alg.GetBlockEdges().GetNumberOfLines() == 1
    alg.AddInputDataObject(1, _polydata(DATA / "lshape_blocks.vtp"))
    alg.Update()
    assert "leave Block Edges empty" in alg.GetLastError()
    assert alg.GetBlockEdges().GetNumberOfLines() == 0


def test_pyvista_auto_matches_the_command_line(tmp_path):
    boundary = pv.read(DATA / "lshape.vtp")
    saved = tmp_path / "edges.vtp"
    blocks = boundary.pinn_mesh(
        blocks="auto", method="elliptic", cell_size=CELL_SIZE, save_blocks=saved
    )
    expected = run_blocks(
        make_settings("elliptic", cell_size=CELL_SIZE), DATA / "lshape.vtp", [AUTO_BLOCKS]
    )
    for grid, points in zip(blocks, expected.result.grids):
        assert np.array_equal(np.asarray(grid.points)[:, :2], points.reshape(-1, 2))
    again = boundary.pinn_mesh(blocks=pv.read(saved), method="elliptic", cell_size=CELL_SIZE)
    assert all(np.array_equal(a.points, b.points) for a, b in zip(blocks, again))
    with pytest.raises(InputError, match="draw the block edges and give them as blocks=$"):
        pv.Circle(radius=1.0, resolution=40).pinn_mesh(blocks="auto")
