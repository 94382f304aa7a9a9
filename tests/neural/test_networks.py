"""The paper's network pieces on hand-set values: the jet algebra, the shortcut network
(eq. 14) and the annealing weight."""

from __future__ import annotations

import pytest
import torch

from pinn_engine.neural.jet import input_jet, jet_product
from pinn_engine.neural.losses import annealed_lambda, winslow_residual
from pinn_engine.neural.networks import CoordinateNet, autograd_jet


def test_z_squared_jet_from_the_jet_algebra_is_harmonic():
    x = torch.rand(32, 2, dtype=torch.float64)
    xi_eta = input_jet(x)
    xi = tuple(c[:, :1] for c in xi_eta)
    eta = tuple(c[:, 1:] for c in xi_eta)
    re = [a - b for a, b in zip(jet_product(xi, xi), jet_product(eta, eta))]
    im = [2 * a for a in jet_product(xi, eta)]
    jet = torch.stack([torch.cat([a, b], dim=1) for a, b in zip(re, im)])
    assert winslow_residual(jet).abs().max() < 1e-14


def test_shortcut_network_shapes_and_gating_on_a_hand_set_network():
    net = CoordinateNet("shortcut", hidden_layers=2, neurons=2)
    with torch.no_grad():
        for p in net.parameters():
            p.zero_()
        net.w_in[0] = torch.tensor([[1.0, 0.0], [0.0, 1.0]])  # H1 = tanh(x)
        net.w_u[0] = torch.tensor([[0.5, 0.0], [0.0, 0.5]])  # U = tanh(x / 2)
        net.w_v[0] = torch.tensor([[0.0, 1.0], [1.0, 0.0]])  # V = tanh(swap(x))
        net.w_hidden[0][0] = torch.tensor([[2.0, 0.0], [0.0, -1.0]])
        net.b_hidden[0][0] = torch.tensor([[0.1, 0.2]])
        net.w_out[0] = torch.tensor([[1.0], [3.0]])
        net.b_out[0] = torch.tensor([[0.25]])
    x = torch.tensor([[0.3, 0.7], [0.9, 0.1]], dtype=torch.float64)
    h1 = torch.tanh(x)
    u, v = torch.tanh(x / 2), torch.tanh(x.flip(1))
    z = torch.tanh(h1 * torch.tensor([2.0, -1.0]).double() + torch.tensor([0.1, 0.2]).double())
    h2 = (1 - z) * u + z * v  # paper eq. 14
    expected = h2 @ torch.tensor([1.0, 3.0]).double() + 0.25
    out = net(x)
    assert out.shape == (2, 2)
    torch.testing.assert_close(out[:, 0], expected)
    torch.testing.assert_close(out[:, 1], torch.zeros(2, dtype=torch.float64))  # y-net is 0
    jet, values = net.jet(x, x)
    assert jet.shape == (6, 2, 2)
    torch.testing.assert_close(jet, autograd_jet(net, x))
    torch.testing.assert_close(values, out)


def test_annealing_weight_against_a_hand_computation():
    g_eqns = [torch.tensor([[1.0, -3.0], [2.0, 0.5]]), torch.tensor([[0.2]])]
    g_bcs = [torch.tensor([[0.5, -1.0], [0.0, 0.5]]), torch.tensor([[-0.5]])]
    # lambda_hat = max|g_eqns| / mean|lambda1 g_bcs| = 3 / (2 * 2.5 / 5) = 3
    assert annealed_lambda(g_eqns, g_bcs, lambda1=2.0, momentum=0.9) == pytest.approx(
        0.9 * 2.0 + 0.1 * 3.0
    )


def test_annealing_on_a_toy_loss_via_autograd():
    w = torch.tensor([1.0, 2.0], requires_grad=True)
    l_eqns = (w**2).sum()  # grad 2w = [2, 4]
    l_bcs = (3 * w).sum()  # grad [3, 3]
    g_e = torch.autograd.grad(l_eqns, [w])
    g_b = torch.autograd.grad(l_bcs, [w])
    assert annealed_lambda(g_e, g_b, 1.0, 0.9) == pytest.approx(0.9 + 0.1 * 4 / 3)
