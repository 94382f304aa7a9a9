"""Say what the network did: the report, the command line's summary line and
the filter's output tell whether the network's grid or the start was kept, and how far nodes
moved; one case where the network improves on the start, one where the start is kept."""

from __future__ import annotations

import numpy as np
from helpers import EXAMPLES
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

from pinn_engine.io.pipeline import load_aux, load_boundary
from pinn_engine.mesher import Mesher
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

HARD = EXAMPLES / "hard"


def _mesh(method: str, path, aux=(), **settings):
    boundary = load_boundary(path)
    lines = load_aux(list(aux), boundary)
    config = make_settings(method, lattice=(41, 21), **settings)
    return Mesher(config).fit(boundary, lines).predict(41, 21)


def test_the_network_pulls_grid_lines_onto_an_auxiliary_line():
    """fig2 with its two auxiliary lines: the network's grid is kept, it moved nodes, and its
    grid lines lie closer to the drawn lines than the elliptic start's (the same map with no
    L-BFGS iteration)."""
    aux = [EXAMPLES / "fig2_aux.vtp"]
    pinn = _mesh("pinn", EXAMPLES / "fig2.vtp", aux)
    start = _mesh("pinn", EXAMPLES / "fig2.vtp", aux, lbfgs_iterations=0)
    training = pinn.report["training"]
    assert training["result"] == "network"
    assert 1e-4 < training["largest_node_move"] < 0.1
    assert start.report["training"]["largest_node_move"] == 0.0
    near = max(pinn.report["aux_line_distance"].values())
    far = max(start.report["aux_line_distance"].values())
    assert near < 0.95 * far  # measured 0.047 against 0.050 of the diagonal


def test_the_start_is_kept_where_no_trained_state_passes():
    """The Gaussian notch with its auxiliary line: no trained state passes the guard, the
    elliptic grid is returned exactly and the report says so (a move of zero)."""
    aux = [HARD / "notch_gauss_aux.vtp"]
    pinn = _mesh("pinn", HARD / "notch_gauss.vtp", aux)
    elliptic = _mesh("elliptic", HARD / "notch_gauss.vtp")
    training = pinn.report["training"]
    assert (training["result"], training["largest_node_move"]) == ("start", 0.0)
    assert "skipped" not in training
    assert np.abs(pinn.points - elliptic.points).max() < 1e-9


def test_command_line_and_filter_say_it(tmp_path, capsys):
    """The command's summary has a ``network:`` line; the filter's grid carries
    ``NetworkResult`` and ``LargestNodeMove`` field data; a classical method has neither."""
    out = tmp_path / "g.vts"
    args = [str(EXAMPLES / "fig2.vtp"), "--aux", str(EXAMPLES / "fig2_aux.vtp"), "-o", str(out)]
    assert main(args) == 0
    assert "network: its grid kept, nodes moved up to" in capsys.readouterr().err
    notch = [str(HARD / "notch_gauss.vtp"), "--aux", str(HARD / "notch_gauss_aux.vtp")]
    assert main([*notch, "-o", str(out)]) == 0
    assert "network: start kept (elliptic grid" in capsys.readouterr().err
    assert main([str(HARD / "notch_v_sharp.vtp"), "-o", str(out)]) == 0
    assert "network: start kept (elliptic grid; not trained: the start" in capsys.readouterr().err
    assert main([str(HARD / "notch_v_sharp.vtp"), "-o", str(out), "--method", "tfi"]) == 0
    assert "network:" not in capsys.readouterr().err

    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(EXAMPLES / "fig2.vtp"))
    alg = PinnMeshAlgorithm()
    alg.SetInputConnection(0, reader.GetOutputPort())
    alg.Update()
    fd = alg.GetOutput().GetFieldData()
    kept, move = fd.GetAbstractArray("NetworkResult").GetValue(0), fd.GetArray("LargestNodeMove")
    assert kept in ("network", "start")
    # the start kept moves no node; a kept network moves some, by a small part of the diagonal
    assert move.GetValue(0) == 0.0 if kept == "start" else 0.0 < move.GetValue(0) < 0.1
    alg.SetMethod("elliptic")
    alg.Update()
    assert alg.GetOutput().GetFieldData().GetAbstractArray("NetworkResult") is None
