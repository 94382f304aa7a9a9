"""The four-sided block kind's PINN (the paper's): its Winslow residual through the training
path, data term, training, the fused loss against autograd; called as the kind
(``Mesher``, ``QuadProblem``), not through a route."""

from __future__ import annotations

import numpy as np
import pytest
import torch
from helpers import EXAMPLES, needs_compiler

from pinn_engine.io.pipeline import load_aux, load_boundary
from pinn_engine.kinds.four_sided.mapping import Mapping
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.kinds.four_sided.problem import QuadProblem, _FusedEvaluation
from pinn_engine.neural.jet import native
from pinn_engine.neural.losses import loss_eqns, winslow_residual
from pinn_engine.neural.networks import CoordinateNet
from pinn_engine.neural.trainer import AutogradEvaluation
from pinn_engine.settings import make_settings

# a short training of the Winslow objective's network (the default trains none)
QUICK = {"adam_epochs": 200, "lbfgs_iterations": 20, "objective": "winslow"}


@pytest.fixture(scope="module")
def fig2():
    boundary = load_boundary(EXAMPLES / "fig2.vtp")
    return boundary, load_aux([EXAMPLES / "fig2_aux.vtp"], boundary)


def exp_map_jet(x: torch.Tensor) -> torch.Tensor:
    """Jet of the conformal (hence Winslow-harmonic) map x + i y = exp(xi + i eta)."""
    e = torch.exp(x[:, 0])
    c, s = torch.cos(x[:, 1]), torch.sin(x[:, 1])
    fx = [e * c, e * c, -e * s, e * c, -e * s, -e * c]  # value, xi, eta, xixi, xieta, etaeta
    fy = [e * s, e * s, e * c, e * s, e * c, -e * s]
    return torch.stack([torch.stack(fx), torch.stack(fy)], dim=-1)


def test_winslow_residual_of_a_harmonic_map_is_zero_through_the_training_path(fig2):
    boundary, _ = fig2
    net = CoordinateNet("shortcut", 3, 8).double()
    with torch.no_grad():
        net.w_out.zero_()
        net.b_out.zero_()  # the correction vanishes: the map is the base
    mapping = Mapping(net, boundary, "hard")
    x = torch.rand(64, 2, dtype=torch.float64)
    for fast in (True, False):
        jet = mapping.jet(x, exp_map_jet(x), fast=fast)[0]
        assert winslow_residual(jet).abs().max() < 1e-13
        assert loss_eqns(jet) < 1e-26
    # control: a non-harmonic base gives a clearly non-zero residual
    square = exp_map_jet(x)
    square[3] = 1.0  # x_xixi = 1
    assert loss_eqns(mapping.jet(x, square)[0]) > 1e-2


def test_data_term_sees_the_auxiliary_line_points(fig2):
    boundary, aux = fig2
    settings = make_settings("pinn", **QUICK)
    net = CoordinateNet("shortcut", 2, 8).double()
    mapping = Mapping(net, boundary, "hard")
    problem = QuadProblem(mapping, boundary, aux, settings, torch.float64, torch.device("cpu"))
    batch = problem.epoch_batch(1)
    data = problem.terms(*batch)["data"]
    xe = torch.as_tensor(np.concatenate([a.xi_eta for a in aux]))
    xy = torch.as_tensor(np.concatenate([a.xy for a in aux]))
    base = torch.as_tensor(mapping.base_jet(xe.numpy())[0])
    manual = (mapping.values(xe, base) - xy).pow(2).sum(dim=1).mean()
    torch.testing.assert_close(data, manual)
    assert data > 1e-3
    problem.aux_y = mapping.values(xe, base).detach()  # measured points = the prediction
    assert problem.terms(*batch)["data"] < 1e-20
    without = QuadProblem(mapping, boundary, [], settings, torch.float64, torch.device("cpu"))
    assert without.terms(*batch)["data"] == 0


@pytest.mark.slow  # three trainings, two seeds
def test_same_seed_same_grid_and_another_seed_another_grid(fig2):
    boundary, aux = fig2
    grids = [
        Mesher(
            make_settings("pinn", seed=s, adam_epochs=60, lbfgs_iterations=5, objective="winslow")
        )
        .fit(boundary, aux)
        .predict(21, 11)
        .points
        for s in (3, 3, 4)
    ]
    np.testing.assert_array_equal(grids[0], grids[1])
    assert np.abs(grids[0] - grids[2]).max() > 1e-6


def test_short_training_on_an_example_gives_a_conforming_unfolded_grid(fig2, tmp_path):
    boundary, aux = fig2
    mesher = Mesher(make_settings("pinn", **QUICK)).fit(boundary, aux)
    result = mesher.predict(41, 21)
    q = result.quality
    assert q["folded_cells"] == 0 and q["boundary_deviation"] <= 1e-9
    h = result.history
    assert len(h["total"]) >= QUICK["adam_epochs"] and h["total"][-1] < h["total"][0]
    for term in ("eqns", "bcs", "data", "weighted_data", "lambda1"):
        assert len(h[term]) == len(h["total"])
    # the model re-meshes at another resolution without training, and survives save/load
    path = tmp_path / "m.pt"
    mesher.save(path)
    again = Mesher.load(path, boundary).predict(41, 21)
    np.testing.assert_allclose(again.points, result.points, atol=1e-12)
    assert Mesher.load(path, boundary).predict(81, 41).points.shape == (41, 81, 2)


def test_paper_preset_and_mgnet_train_with_penalty_terms(fig2):
    boundary, aux = fig2
    paper = Mesher(make_settings("pinn", "paper", adam_epochs=60, lbfgs_iterations=5))
    h = paper.fit(boundary, aux).predict(21, 11).history
    assert {"bcs_bottom", "bcs_right", "bcs_top", "bcs_left"} <= set(h)
    assert h["lambda1"][-1] != 1.0  # the annealing moved lambda1
    mg = Mesher(make_settings("mgnet", adam_epochs=60, lbfgs_iterations=5)).fit(boundary, aux)
    assert mg.aux_lines_ == [] and mg.model_.mapping.net.kind == "mlp"


@pytest.mark.parametrize("backend", [pytest.param("native", marks=needs_compiler), "torch"])
@pytest.mark.parametrize("kind", ["shortcut", "mlp"])
@pytest.mark.parametrize("mode", ["hard", "penalty"])
def test_fast_path_residuals_and_gradients_equal_the_autograd_reference(
    fig2, kind, mode, backend, monkeypatch
):
    boundary, _ = fig2
    if backend == "torch":
        monkeypatch.setattr(native, "kernels", lambda: None)
    else:
        assert native.kernels() is not None, "the fused kernels did not build"
    torch.manual_seed(1)
    net = CoordinateNet(kind, 4, 12).double()
    mapping = Mapping(net, boundary, mode)
    x = torch.rand(40, 2, dtype=torch.float64)
    extra = torch.rand(30, 2, dtype=torch.float64)  # boundary / auxiliary points: values only
    base = torch.as_tensor(mapping.base_jet(x.numpy())) if mode == "hard" else None
    results = []
    for fast in (True, False):
        net.zero_grad()
        jet, values = mapping.jet(x, base, extra, fast=fast)
        (loss_eqns(jet) + values.pow(2).mean()).backward()
        results.append(
            (
                winslow_residual(jet).detach(),
                values.detach(),
                [p.grad.clone() for p in net.parameters()],
            )
        )
    (r_fast, v_fast, g_fast), (r_ref, v_ref, g_ref) = results
    torch.testing.assert_close(r_fast, r_ref, rtol=1e-10, atol=1e-12)
    torch.testing.assert_close(v_fast, v_ref, rtol=1e-12, atol=1e-14)
    for a, b in zip(g_fast, g_ref):
        torch.testing.assert_close(a, b, rtol=1e-9, atol=1e-12)


@needs_compiler
@pytest.mark.parametrize("dtype", [torch.float64, torch.float32])
@pytest.mark.parametrize("with_aux", [True, False])
@pytest.mark.parametrize("kind", ["shortcut", "mlp"])
def test_the_fused_paper_loss_equals_the_autograd_loss_terms(fig2, kind, with_aux, dtype):
    """The C++ loss (terms, annealing gradients, the loss's gradient) against losses.py's
    terms through autograd, on batches that fill no C++ block evenly."""
    boundary, aux = fig2
    torch.manual_seed(2)
    net = CoordinateNet(kind, 4, 30).to(dtype)
    problem = QuadProblem(
        Mapping(net, boundary, "penalty"),
        boundary,
        aux if with_aux else [],
        make_settings("pinn", "paper"),
        dtype,
        torch.device("cpu"),
    )
    assert problem.fused is not None
    batch = problem.sample(37, 23)
    fused = problem.evaluate(batch)
    problem.fused = None
    plain = problem.evaluate(batch)
    assert (type(fused), type(plain)) == (_FusedEvaluation, AutogradEvaluation)
    f64 = dtype == torch.float64
    tol = {"rtol": 1e-10 if f64 else 1e-4, "atol": 0.0}
    near = 1e-12 if f64 else 1e-5  # gradients: absolute tolerance, relative to the largest
    assert list(fused.terms) == list(plain.terms)
    for name, value in plain.terms.items():
        torch.testing.assert_close(fused.terms[name], value.double(), **tol)
    assert with_aux == (plain.terms["data"] > 0)
    weights = net.weight_matrices()
    for a, b in zip(fused.weight_grads(weights), plain.weight_grads(weights)):
        for g_fused, g_plain in zip(a, b, strict=True):
            torch.testing.assert_close(
                g_fused, g_plain, rtol=tol["rtol"], atol=near * g_plain.abs().max()
            )
    torch.testing.assert_close(fused.loss(3.0), plain.loss(3.0).double(), **tol)
    g_plain = plain.gradient()
    torch.testing.assert_close(
        fused.gradient(), g_plain, rtol=tol["rtol"], atol=near * g_plain.abs().max()
    )


def test_the_fused_loss_only_where_it_applies(fig2):
    boundary, aux = fig2
    net = CoordinateNet("shortcut", 2, 8).double()
    problems = {
        preset: QuadProblem(
            Mapping(net, boundary, make_settings("pinn", preset).boundary_mode),
            boundary,
            aux,
            make_settings("pinn", preset),
            torch.float64,
            torch.device("cpu"),
        )
        for preset in ("paper", "default")
    }
    assert (problems["paper"].fused is not None) == (native.kernels() is not None)
    assert problems["default"].fused is None  # hard boundary, scaled residual: autograd
