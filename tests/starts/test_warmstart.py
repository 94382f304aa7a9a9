"""The default PINN's elliptic warm start and quality guard on hard shapes."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import EXAMPLES

from pinn_engine.io.pipeline import load_aux, load_boundary
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.kinds.four_sided.model import TrainedModel
from pinn_engine.neural.networks import CoordinateNet
from pinn_engine.settings import make_settings
from pinn_engine.starts.warmstart import MAX_LATTICE_NODES, elliptic_start, lattice_for

HARD = EXAMPLES / "hard"


def inputs(name: str):
    boundary = load_boundary(HARD / f"{name}.vtp")
    aux = HARD / f"{name}_aux.vtp"
    return boundary, load_aux([aux], boundary) if aux.exists() else []


@pytest.mark.parametrize("name", ["notch_gauss", "notch_v_sharp"])
def test_default_pinn_keeps_to_the_elliptic_grid_on_sharp_notches(name):
    """No fold, mean within 0.5 and worst within 2 degrees of the converged elliptic grid on
    the same boundary nodes, boundary exact."""
    boundary, aux = inputs(name)
    pinn = Mesher(make_settings("pinn", lattice=(41, 21))).fit(boundary, aux).predict(41, 21)
    ell = Mesher(make_settings("elliptic")).fit(boundary).predict(41, 21).quality
    q = pinn.quality
    assert ell["folded_cells"] == 0 and q["folded_cells"] == 0
    assert q["mean_max_angle"] <= ell["mean_max_angle"] + 0.5
    assert q["worst_max_angle"] <= ell["worst_max_angle"] + 2.0
    assert q["boundary_deviation"] < 1e-12
    guard = pinn.report["training"]["guard"]
    assert guard["lattice"] == [41, 21]
    assert guard["elliptic"]["mean_max_angle"] == pytest.approx(ell["mean_max_angle"])


@pytest.mark.slow  # two trainings on the deep slot (about 4 s CPU)
def test_paper_loss_from_tfi_folds_where_the_warm_start_does_not():
    """Why the warm start exists: the paper's recipe from TFI, on the deep narrow slot, ends
    with folded cells (short budget here; the full one folds too)."""
    boundary, aux = inputs("notch_narrow_deep")
    cold = make_settings("pinn", warm_start="none", adam_epochs=300, lbfgs_iterations=30)
    warm = make_settings("pinn", lattice=(41, 21))
    folded = [
        Mesher(s).fit(boundary, aux).predict(41, 21).quality["folded_cells"] for s in (cold, warm)
    ]
    ell = Mesher(make_settings("elliptic")).fit(boundary).predict(41, 21).quality
    assert folded[0] > ell["folded_cells"] >= folded[1]


def test_warm_start_is_zero_on_the_boundary_and_the_elliptic_grid_at_its_nodes():
    boundary, _ = inputs("two_slots")
    warm, grid = elliptic_start(boundary, 33, 17)
    d = warm.grid(33, 17)
    np.testing.assert_allclose(d, warm.correction, atol=1e-12)
    fine = warm.grid(129, 65)
    for edge in (fine[0], fine[-1], fine[:, 0], fine[:, -1]):
        np.testing.assert_allclose(edge, 0.0, atol=1e-12)
    jet = warm.jet(np.array([[0.3, 0.4], [0.7, 0.2]]))
    assert jet.shape == (6, 2, 2)
    assert np.isfinite(grid).all()


@pytest.mark.parametrize("size", [(21, 3), (2, 9), (3, 3)])
def test_thin_grids_start_at_their_own_elliptic_grid(size):
    """Fewer than 4 nodes a side: the spline runs through added nodes, the grid at the
    output size is still exactly the elliptic one at the start."""
    boundary, _ = inputs("bump")
    warm, grid = elliptic_start(boundary, *size)
    np.testing.assert_allclose(warm.grid(*size), warm.correction, atol=1e-12)
    assert np.isfinite(warm.jet(np.array([[0.5, 0.5]]))).all()


def test_saved_model_keeps_its_warm_start(tmp_path):
    boundary, aux = inputs("bump")
    mesher = Mesher(make_settings("pinn", lattice=(21, 11), lbfgs_iterations=10))
    before = mesher.fit(boundary, aux).predict(21, 11).points
    mesher.save(tmp_path / "m.pt")
    loaded = Mesher.load(tmp_path / "m.pt", boundary)
    assert loaded.model_.mapping.warm is not None
    np.testing.assert_allclose(loaded.predict(21, 11).points, before, atol=1e-6)
    assert TrainedModel.load(tmp_path / "m.pt").settings.lattice == (21, 11)


def test_annealing_takes_the_weight_matrices_only():
    """Wang et al.'s Algorithm 1: gradient statistics of the weight matrices, no biases and
    no U/V encoders."""
    net = CoordinateNet("shortcut", 4, 8)
    mats = net.weight_matrices()
    assert [tuple(m.shape) for m in mats] == [(2, 2, 8), (2, 8, 8), (2, 8, 8), (2, 8, 8), (2, 8, 1)]
    ids = {id(m) for m in mats}
    assert not ids & {id(net.w_u), id(net.w_v), id(net.b_in), id(net.b_out)}


def test_settings_rules_for_the_warm_start():
    assert make_settings("pinn").warm_start == "elliptic"
    assert make_settings("pinn", "paper").warm_start == "none"
    penalty = make_settings("pinn", boundary_mode="penalty")
    assert penalty.warm_start == "none" and penalty.adam_epochs == 5000
    with pytest.raises(ValueError, match="hard boundary"):
        make_settings("pinn", boundary_mode="penalty", warm_start="elliptic")
    with pytest.raises(ValueError, match="lattice"):
        make_settings("pinn", lattice=(1, 5))
    assert make_settings("pinn", lattice=[9, 5]).lattice == (9, 5)
    key = dict(make_settings("pinn", "paper", lattice=(9, 5)).training_key())
    assert "lattice" not in key


def test_an_adam_phase_from_the_warm_start_is_checked_too():
    boundary, aux = inputs("notch_gauss")
    settings = make_settings("pinn", lattice=(21, 11), adam_epochs=50, lbfgs_iterations=0)
    result = Mesher(settings).fit(boundary, aux).predict(21, 11)
    guard, q = result.report["training"]["guard"], result.quality
    assert guard["kept_after_lbfgs_iterations"] == 0
    assert q["folded_cells"] <= guard["elliptic"]["folded_cells"]
    assert q["mean_max_angle"] == pytest.approx(guard["kept"]["mean_max_angle"])
    assert q["mean_max_angle"] <= guard["elliptic"]["mean_max_angle"] + 0.5


def test_large_grids_warm_start_on_a_coarser_lattice():
    """The elliptic solve would take minutes at 641 x 321 on a notch: the warm start runs on a
    lattice of about MAX_LATTICE_NODES nodes and the network is evaluated at the full size."""
    assert lattice_for(41, 21) == (41, 21) and lattice_for(21, 3) == (21, 3)
    ni, nj = lattice_for(641, 321)
    assert ni * nj <= 1.05 * MAX_LATTICE_NODES and abs((ni - 1) / (nj - 1) - 2) < 0.05
    boundary, aux = inputs("bump")
    mesher = Mesher(make_settings("pinn", lattice=(641, 321), lbfgs_iterations=5))
    result = mesher.fit(boundary, aux).predict(641, 321)
    assert result.report["training"]["guard"]["lattice"] == [ni, nj]
    assert result.quality["folded_cells"] == 0 and result.points.shape == (321, 641, 2)
