"""The grid-size limits are checked in one place and are the same on every route."""

from __future__ import annotations

import re

import numpy as np
import pytest
from helpers import EXAMPLES, OutputMessages, square_ring
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

from pinn_engine.geometry.boundary import Boundary
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.cli import main
from pinn_engine.routes.pyvista_accessor import pinn_mesh
from pinn_engine.settings import MAX_NODES, MAX_SIDE_NODES, grid_size_problem, make_settings

TOO_BIG = [(1, 5), (MAX_SIDE_NODES + 1, 2), (2001, 2001)]  # the last: 4,004,001 nodes


@pytest.mark.parametrize(("ni", "nj"), TOO_BIG)
def test_every_route_refuses_the_same_sizes_in_its_own_words(ni, nj, tmp_path, capsys):
    assert grid_size_problem(ni, nj)
    assert (
        main(
            [
                str(EXAMPLES / "fig2.vtp"),
                "--method",
                "tfi",
                "--size",
                str(ni),
                str(nj),
                "-o",
                str(tmp_path / "g.vts"),
            ]
        )
        == 2
    )
    assert f"--size {ni} {nj}: each side must have 2 to" in capsys.readouterr().err
    ring = np.column_stack([square_ring(4), np.zeros(16)])
    with pytest.raises(ValueError, match=re.escape(f"size=({ni}, {nj}): each side")):
        pinn_mesh(ring, size=(ni, nj), method="tfi")
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(EXAMPLES / "fig2.vtp"))
    alg = PinnMeshAlgorithm()
    alg.SetInputConnection(0, reader.GetOutputPort())
    alg.SetMethod("tfi")
    alg.SetGridSize(ni, nj)
    with OutputMessages(alg, "ErrorEvent"):
        alg.Update()
    assert f"Grid Size {ni} {nj}: each side must have 2 to" in alg.GetLastError()
    mesher = Mesher(make_settings("tfi")).fit(Boundary.from_points(square_ring(4)))
    with pytest.raises(ValueError, match="each side must have 2 to"):
        mesher.predict(ni, nj)


def test_the_largest_sizes_pass_and_the_panel_allows_exactly_them():
    assert grid_size_problem(MAX_SIDE_NODES, 2) is None
    assert grid_size_problem(2000, MAX_NODES // 2000) is None
    from pinn_engine.routes.panel import FOUR_SIDED_PANEL  # the plugin's panel, as data

    size = next(p for p in FOUR_SIDED_PANEL if p.name == "GridSize")
    assert size.bounds == {"min": 2, "max": MAX_SIDE_NODES}  # the Grid Size range


def test_one_table_of_setting_rules_read_by_every_route(tmp_path, capsys):
    """settings.option_constraints(): the same range on the command line, in the panel, in
    Settings (pyvista, the VTK filter)."""

    from pinn_engine.routes.cli import main
    from pinn_engine.settings import make_settings, option_constraints

    top = option_constraints()["hidden_layers"].high
    assert make_settings("pinn", hidden_layers=top).hidden_layers == top
    with pytest.raises(ValueError, match=f"hidden_layers {top + 1}: must be a whole number"):
        make_settings("pinn", hidden_layers=top + 1)
    assert (
        main([str(EXAMPLES / "fig2.vtp"), "--layers", str(top + 1), "-o", str(tmp_path / "g.vts")])
        == 2
    )
    assert f"--layers {top + 1}: must be a whole number from 1 to {top}" in capsys.readouterr().err
    from pinn_engine.routes.panel import FOUR_SIDED_PANEL, whole_range

    ranges = {
        p.name: p.bounds
        for p in FOUR_SIDED_PANEL
        if p.name in ("HiddenLayers", "Neurons", "AdamEpochs", "LBFGSIterations")
    }
    assert ranges == {
        "HiddenLayers": whole_range("hidden_layers"),
        "Neurons": whole_range("neurons"),
        "AdamEpochs": whole_range("adam_epochs"),
        "LBFGSIterations": whole_range("lbfgs_iterations"),
    }
    assert ranges["HiddenLayers"]["max"] == top
