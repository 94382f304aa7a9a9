"""The two coordinate sub-networks (paper section 3.3) as one batched module.

Each sub-network maps (xi, eta) to one physical coordinate. Their parameters are stacked
along a leading axis of size 2 (x-net, y-net), so both evaluate in one batched matmul while
staying independent networks. ``jet`` propagates values with first and second derivatives
(channels v, d_xi, d_eta, d_xixi, d_xieta, d_etaeta) in one forward pass.
"""

from __future__ import annotations

import math

import torch
from torch import nn

# derivative channels of a jet: value, first, then second derivatives
V, XI, ETA, XIXI, XIETA, ETAETA = range(6)
FIRST = ((XI, 0), (ETA, 1))
SECOND = ((XIXI, XI, XI), (XIETA, XI, ETA), (ETAETA, ETA, ETA))


def _activation(name: str, z: torch.Tensor) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """sigma(z), sigma'(z), sigma''(z)."""
    if name == "tanh":
        s = torch.tanh(z)
        d1 = 1 - s * s
        return s, d1, -2 * s * d1
    if name == "sin":
        s, c = torch.sin(z), torch.cos(z)
        return s, c, -s
    if name == "sigmoid":
        s = torch.sigmoid(z)
        d1 = s * (1 - s)
        return s, d1, d1 * (1 - 2 * s)
    if name == "swish":
        g = torch.sigmoid(z)
        dg = g * (1 - g)
        return z * g, g + z * dg, 2 * dg + z * dg * (1 - 2 * g)
    raise ValueError(f"unknown activation {name!r}; use tanh, sin, sigmoid or swish")


ACTIVATIONS = ("tanh", "sin", "sigmoid", "swish")


Jet = tuple  # six tensors: value, d_xi, d_eta, d_xixi, d_xieta, d_etaeta


def _act_jet(name: str, z: Jet) -> Jet:
    """Chain rule for a point-wise activation on a jet."""
    s, d1, d2 = _activation(name, z[V])
    first = tuple(d1 * z[c] for c, _ in FIRST)
    second = tuple(d2 * z[a] * z[b] + d1 * z[c] for c, a, b in SECOND)
    return (s, *first, *second)


def jet_product(u: Jet, w: Jet) -> Jet:
    """Leibniz rule: the jet of u * w from the jets of u and w."""
    first = tuple(u[c] * w[V] + u[V] * w[c] for c, _ in FIRST)
    second = tuple(u[c] * w[V] + u[a] * w[b] + u[b] * w[a] + u[V] * w[c] for c, a, b in SECOND)
    return (u[V] * w[V], *first, *second)


def input_jet(x: torch.Tensor) -> Jet:
    """Jet of the input (xi, eta) itself, each channel (B, 2)."""
    one_xi = torch.zeros_like(x)
    one_xi[:, 0] = 1.0
    one_eta = torch.zeros_like(x)
    one_eta[:, 1] = 1.0
    zero = torch.zeros_like(x)
    return (x, one_xi, one_eta, zero, zero, zero)


class CoordinateNet(nn.Module):
    """Two sub-networks (x and y), each a shortcut network (paper eq. 14) or a plain MLP.

    ``kind="shortcut"`` is the "modified MLP" of Wang, Teng and Perdikaris (2020): encoders
    U and V of the input gate every hidden layer point-wise. ``hidden_layers`` counts the
    hidden states: H1 from the input, then ``hidden_layers - 1`` gated layers.
    ``kind="mlp"`` is MGNet's fully connected network.
    """

    def __init__(self, kind: str = "shortcut", hidden_layers: int = 4, neurons: int = 30,
                 activation: str = "tanh", outputs: int = 2) -> None:
        super().__init__()
        if kind not in ("shortcut", "mlp"):
            raise ValueError(f"unknown network kind {kind!r}")
        _activation(activation, torch.zeros(1))  # validate the name early
        self.kind, self.activation = kind, activation
        self.hidden_layers, self.neurons = hidden_layers, neurons
        n, k = neurons, outputs

        def weight(*shape: int) -> nn.Parameter:
            fan_in, fan_out = shape[-2], shape[-1]
            std = math.sqrt(2.0 / (fan_in + fan_out))  # Glorot normal, as the PINN codes
            return nn.Parameter(torch.randn(*shape, dtype=torch.float64) * std)

        def bias(*shape: int) -> nn.Parameter:
            return nn.Parameter(torch.zeros(*shape, dtype=torch.float64))

        self.w_in, self.b_in = weight(k, 2, n), bias(k, 1, n)
        if kind == "shortcut":
            self.w_u, self.b_u = weight(k, 2, n), bias(k, 1, n)
            self.w_v, self.b_v = weight(k, 2, n), bias(k, 1, n)
        self.w_hidden = nn.ParameterList([weight(k, n, n) for _ in range(hidden_layers - 1)])
        self.b_hidden = nn.ParameterList([bias(k, 1, n) for _ in range(hidden_layers - 1)])
        self.w_out, self.b_out = weight(k, n, 1), bias(k, 1, 1)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """(B, 2) computational coordinates -> (B, 2) outputs, one per sub-network."""
        act = lambda z: _activation(self.activation, z)[0]  # noqa: E731
        x = x.unsqueeze(0)  # broadcast over the sub-networks
        h = act(x @ self.w_in + self.b_in)  # H1 = sigma(W1 x + b1)
        if self.kind == "shortcut":
            u, v = act(x @ self.w_u + self.b_u), act(x @ self.w_v + self.b_v)
        for w, b in zip(self.w_hidden, self.b_hidden):
            z = act(torch.bmm(h, w) + b)
            # paper eq. 14: FC_{k+1} = (1 - FC'_k) x FC_b1 + FC'_k x FC_b2
            h = (1 - z) * u + z * v if self.kind == "shortcut" else z
        return (torch.bmm(h, self.w_out) + self.b_out)[..., 0].T

    def jet(self, x: torch.Tensor) -> torch.Tensor:
        """Values and derivatives in one pass: (B, 2) -> (6, B, 2), channels as ``V..ETAETA``."""

        def linear(h: Jet, w: torch.Tensor, b: torch.Tensor) -> Jet:
            # one matmul for all six channels; the bias shifts only the value
            z = torch.matmul(torch.stack(h, dim=-3), w.unsqueeze(-3)).unbind(-3)
            return (z[V] + b, *z[1:])

        xj = input_jet(x)
        h = _act_jet(self.activation, linear(xj, self.w_in, self.b_in))
        if self.kind == "shortcut":
            u = _act_jet(self.activation, linear(xj, self.w_u, self.b_u))
            v = _act_jet(self.activation, linear(xj, self.w_v, self.b_v))
            diff = tuple(b - a for a, b in zip(u, v))
        for w, b in zip(self.w_hidden, self.b_hidden):
            z = _act_jet(self.activation, linear(h, w, b))
            # paper eq. 14 on jets: H = U + Z (V - U)
            h = tuple(a + g for a, g in zip(u, jet_product(z, diff))) \
                if self.kind == "shortcut" else z
        out = linear(h, self.w_out, self.b_out)  # six (k, B, 1)
        return torch.stack(out)[..., 0].transpose(1, 2)


def autograd_jet(net: nn.Module, x: torch.Tensor) -> torch.Tensor:
    """The reference: the same jet by nested ``torch.autograd.grad`` (create_graph=True)."""
    x = x.detach().requires_grad_(True)
    out = net(x)
    grad = lambda y: torch.autograd.grad(y.sum(), x, create_graph=True)[0]  # noqa: E731
    columns = []
    for k in range(out.shape[1]):
        g = grad(out[:, k])
        g_xi, g_eta = grad(g[:, 0]), grad(g[:, 1])
        columns.append(torch.stack([out[:, k], g[:, 0], g[:, 1], g_xi[:, 0], g_xi[:, 1],
                                    g_eta[:, 1]]))
    return torch.stack(columns, dim=-1)
