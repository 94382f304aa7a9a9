"""``--objective quality`` (SPEC 7, issue 14 item 3): the pinn's cell-quality objective."""

from __future__ import annotations

import json

import numpy as np
import pytest
import torch
from conftest import EXAMPLES, square_ring

from pinn_engine.algorithm import PinnMeshAlgorithm
from pinn_engine.boundary_fit import ArcLengthFit
from pinn_engine.cli import main
from pinn_engine.losses import corner_angles, loss_quality
from pinn_engine.mesher import Mesher
from pinn_engine.pipeline import load_aux, load_boundary
from pinn_engine.quality import angle_floor
from pinn_engine.settings import make_settings
from pinn_engine.tfi import tfi_grid

HARD = EXAMPLES / "hard"


def test_quality_objective_beats_the_elliptic_grid_on_a_deep_notch():
    """On the narrow deep notch (41 x 21, its auxiliary line), where the converged elliptic
    grid folds 2 cells: no fold, worst angle below the elliptic grid's and within 0.5 degrees
    of TFI's, mean within 0.5 of the elliptic grid's, boundary exact."""
    boundary = load_boundary(HARD / "notch_narrow_deep.vtp")
    aux = load_aux([HARD / "notch_narrow_deep_aux.vtp"], boundary)
    settings = make_settings("pinn", lattice=(41, 21), objective="quality")
    result = Mesher(settings).fit(boundary, aux).predict(41, 21)
    ell = Mesher(make_settings("elliptic")).fit(boundary).predict(41, 21)
    tfi = Mesher(make_settings("tfi")).fit(boundary).predict(41, 21)
    q, e, t = result.quality, ell.quality, tfi.quality
    assert q["folded_cells"] == 0 < e["folded_cells"]
    assert q["worst_max_angle"] < e["worst_max_angle"]
    assert q["worst_max_angle"] <= t["worst_max_angle"] + 0.5
    assert q["worst_max_angle"] >= max(angle_floor(tfi.points)) - 1e-9
    assert q["mean_max_angle"] <= e["mean_max_angle"] + 0.5
    assert q["boundary_deviation"] < 1e-12
    assert result.report["training"]["start"].startswith("optimized")


def test_corner_angles_and_the_quality_term():
    square = torch.tensor([[[0.0, 0.0], [1.0, 0.0]], [[0.0, 1.0], [1.0, 1.0]]])
    assert torch.allclose(corner_angles(square, 1.0), torch.full((4, 1, 1), torch.pi / 2))
    dart = square.clone()
    dart[1, 1] = torch.tensor([0.2, 0.2])  # a reflex corner: the cell is folded
    assert corner_angles(dart, 1.0).max() > torch.pi
    assert loss_quality(corner_angles(dart, 1.0)) > loss_quality(corner_angles(square, 1.0)) + 1


def test_angle_floor_is_set_by_the_boundary_nodes():
    boundary = load_boundary(HARD / "kite_35.vtp")
    grid = tfi_grid(ArcLengthFit(boundary).sample, 41, 21)
    corner, side = angle_floor(grid)
    ell = Mesher(make_settings("elliptic")).fit(boundary).predict(41, 21).quality
    assert corner == pytest.approx(ell["worst_max_angle"], abs=0.01)  # 158.25: a corner's
    xi, eta = np.meshgrid(np.linspace(0, 2, 5), np.linspace(0, 1, 3))
    assert angle_floor(np.stack([xi, eta], axis=-1)) == pytest.approx((90.0, 90.0))


def test_settings_rules_for_the_objective():
    assert make_settings("pinn", objective="quality").objective == "quality"
    assert make_settings("pinn", "paper").objective == "winslow"
    assert make_settings("pinn", warm_start="none").objective == "winslow"
    assert make_settings("mgnet").objective == "winslow"
    with pytest.raises(ValueError, match="pinn method"):
        make_settings("mgnet", objective="quality")
    with pytest.raises(ValueError, match="objective 'smooth': use winslow, quality"):
        make_settings("pinn", objective="smooth")
    key = dict(make_settings("pinn", warm_start="none", objective="quality").training_key())
    assert "lattice" in key  # the quality term is computed on the lattice


def test_objective_on_the_command_line(tmp_path, capsys):
    ring = tmp_path / "square.csv"
    np.savetxt(ring, square_ring(8), delimiter=",")
    out, report = tmp_path / "g.vts", tmp_path / "r.json"
    assert (
        main(
            [
                str(ring),
                "--size",
                "9",
                "5",
                "--objective",
                "quality",
                "--lbfgs",
                "0",
                "-o",
                str(out),
                "--report",
                str(report),
                "--quiet",
            ]
        )
        == 0
    )
    saved = json.loads(report.read_text())
    assert saved["settings"]["objective"] == "quality" and saved["quality"]["folded_cells"] == 0
    with pytest.raises(SystemExit) as exc:
        main([str(ring), "--objective", "smooth", "-o", str(out)])
    assert exc.value.code == 2
    assert "--objective" in capsys.readouterr().err


def test_objective_in_the_accessor_and_the_filter():
    pv = pytest.importorskip("pyvista")
    from pinn_engine.pyvista_accessor import pinn_mesh

    grid = pinn_mesh(square_ring(8), size=(9, 5), objective="quality", lbfgs_iterations=0)
    report = json.loads(str(grid.field_data["Report"][0]))
    assert isinstance(grid, pv.StructuredGrid) and report["settings"]["objective"] == "quality"
    alg = PinnMeshAlgorithm()
    alg.SetObjective(1)
    assert alg.GetSettings().objective == "quality"
    alg.SetMethod("tfi")  # the panel keeps Objective set when the method changes
    assert alg.GetSettings().objective == "winslow"
    alg.SetMethod("pinn")
    alg.SetObjective("winslow")
    assert alg.GetSettings().objective == "winslow"
    with pytest.raises(ValueError, match="objective"):
        alg.SetObjective("smooth")
