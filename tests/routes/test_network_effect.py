"""Say what the default chose and what the network did: the report, the command line's
summary line and the filter's output tell which grid was returned (the network's or a start),
whether a network was trained, for how long, and the worst cell against the elliptic grid's;
one case where the network improves on the start, one where the start is kept after
training, one where nothing is trained."""

from __future__ import annotations

import json
import time

import numpy as np
import pytest
from helpers import EXAMPLES
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

from pinn_engine.io.pipeline import load_aux, load_boundary
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.kinds.untrained import QUALITY
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.cli import main
from pinn_engine.settings import make_settings

HARD = EXAMPLES / "hard"
# the stages --report times: the kind's and the command line's (read, write)
STAGES = {"start", "training", "mesh", "quality", "read", "write"}


def _mesh(method: str, path, aux=(), **settings):
    boundary = load_boundary(path)
    lines = load_aux(list(aux), boundary)
    config = make_settings(method, lattice=(41, 21), **settings)
    return Mesher(config).fit(boundary, lines).predict(41, 21)


@pytest.mark.slow  # a network trained with lines, then compared
def test_the_network_pulls_grid_lines_onto_an_auxiliary_line():
    """fig2 with its two auxiliary lines: the network's grid is kept, it moved nodes, and its
    grid lines lie closer to the drawn lines than the elliptic start's (the same map with no
    L-BFGS iteration)."""
    aux = [EXAMPLES / "fig2_aux.vtp"]
    pinn = _mesh("pinn", EXAMPLES / "fig2.vtp", aux, objective="winslow")
    start = _mesh("pinn", EXAMPLES / "fig2.vtp", aux, objective="winslow", lbfgs_iterations=0)
    training = pinn.report["training"]
    assert training["result"] == "network"
    assert 0.0 < pinn.report["train_seconds"] == training["timings"]["training"]
    assert 1e-4 < training["largest_node_move"] < 0.1
    assert start.report["training"]["largest_node_move"] == 0.0
    near = max(pinn.report["aux_line_distance"].values())
    far = max(start.report["aux_line_distance"].values())
    assert near < 0.95 * far  # measured 0.047 against 0.050 of the diagonal


def test_the_start_is_kept_where_no_trained_state_passes():
    """The Gaussian notch with its auxiliary line: no trained state passes the guard, the
    elliptic grid is returned exactly and the report says so (a move of zero)."""
    aux = [HARD / "notch_gauss_aux.vtp"]
    pinn = _mesh("pinn", HARD / "notch_gauss.vtp", aux, objective="winslow")
    elliptic = _mesh("elliptic", HARD / "notch_gauss.vtp")
    training = pinn.report["training"]
    assert (training["result"], training["largest_node_move"]) == ("start", 0.0)
    assert "skipped" not in training
    assert np.abs(pinn.points - elliptic.points).max() < 1e-9


def test_the_default_trains_nothing_and_says_what_it_chose():
    """The default on the bump: its grid is a start (no network trained: 0 s of training),
    its worst cell below the elliptic grid's, and the report's ``choice`` says so."""
    pinn = _mesh("pinn", HARD / "bump.vtp")
    elliptic = _mesh("elliptic", HARD / "bump.vtp")
    training, report = pinn.report["training"], pinn.report
    assert training["skipped"] and report["train_seconds"] == 0.0
    worst, reference = report["quality"]["worst_max_angle"], elliptic.report["quality"]
    assert worst < reference["worst_max_angle"] - 5  # measured 114.8 against 142.0
    assert report["quality"]["mean_max_angle"] <= reference["mean_max_angle"] + 0.5
    assert report["choice"] == (
        f"chose the {training['start']} grid; worst cell {worst:.2f} deg, the elliptic grid's "
        f"{reference['worst_max_angle']:.2f} (no network trained: {training['skipped']})"
    )


@pytest.mark.slow  # a network trained on two routes, the command line in its own process
def test_command_line_and_filter_say_it(tmp_path, capsys):
    """The command's summary has a ``chose ...`` line; the filter's grid carries
    ``NetworkResult`` and ``LargestNodeMove`` field data and ``Trained`` says whether a network
    was trained; a classical method has none of them."""
    out = tmp_path / "g.vts"
    winslow = ["--objective", "winslow", "-o", str(out)]
    args = [str(EXAMPLES / "fig2.vtp"), "--aux", str(EXAMPLES / "fig2_aux.vtp"), *winslow]
    assert main(args) == 0
    assert "chose the network's grid (trained " in capsys.readouterr().err
    notch = [str(HARD / "notch_gauss.vtp"), "--aux", str(HARD / "notch_gauss_aux.vtp")]
    assert main([*notch, *winslow]) == 0
    said = capsys.readouterr().err
    assert "chose the elliptic grid; worst cell " in said
    assert "; no trained state passed the quality guard)" in said
    assert main([str(HARD / "notch_v_sharp.vtp"), "-o", str(out)]) == 0
    assert "(no network trained: the start is the quality" in capsys.readouterr().err
    assert main([str(HARD / "notch_v_sharp.vtp"), "-o", str(out), "--method", "tfi"]) == 0
    assert "chose" not in capsys.readouterr().err

    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(EXAMPLES / "fig2.vtp"))
    alg = PinnMeshAlgorithm()
    alg.SetInputConnection(0, reader.GetOutputPort())
    alg.Update()
    assert not alg.GetTrained() and alg.GetTrainingCount() == 0  # the default trains nothing
    fd = alg.GetOutput().GetFieldData()
    assert fd.GetArray("Trained").GetValue(0) == 0 and fd.GetArray("train_seconds").GetValue(0) == 0
    kept, move = fd.GetAbstractArray("NetworkResult").GetValue(0), fd.GetArray("LargestNodeMove")
    assert kept in ("network", "start")
    # the start kept moves no node; a kept network moves some, by a small part of the diagonal
    assert move.GetValue(0) == 0.0 if kept == "start" else 0.0 < move.GetValue(0) < 0.1
    alg.SetMethod("elliptic")
    alg.Update()
    assert alg.GetOutput().GetFieldData().GetAbstractArray("NetworkResult") is None


def test_the_report_times_every_stage(tmp_path):
    """--report has the seconds of every stage, the network's training included (zero where
    it was not trained), and says why it was not trained."""
    report = tmp_path / "r.json"
    args = [str(HARD / "notch_v_sharp.vtp"), "-o", str(tmp_path / "g.vts"), "--report", str(report)]
    began = time.perf_counter()
    assert main([*args, "--size", "21", "11"]) == 0
    wall = time.perf_counter() - began
    written = json.loads(report.read_text())
    assert set(written["timings"]) >= STAGES
    assert 0 < sum(written["timings"].values()) <= wall
    assert written["timings"]["start"] > 0 and written["timings"]["training"] == 0.0
    assert written["training"]["skipped"] == QUALITY
    assert written["train_seconds"] == 0.0
