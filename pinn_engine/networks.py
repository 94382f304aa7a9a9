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


def _activation(name: str, z: torch.Tensor) -> tuple[torch.Tensor, ...]:
    """sigma(z) and its first three derivatives."""
    if name == "tanh":
        s = torch.tanh(z)
        d1 = 1 - s * s
        d2 = -2 * s * d1
        return s, d1, d2, -2 * (d1 * d1 + s * d2)
    if name == "sin":
        s, c = torch.sin(z), torch.cos(z)
        return s, c, -s, -c
    if name == "sigmoid":
        s = torch.sigmoid(z)
        d1 = s * (1 - s)
        d2 = d1 * (1 - 2 * s)
        return s, d1, d2, d2 * (1 - 2 * s) - 2 * d1 * d1
    if name == "swish":
        g = torch.sigmoid(z)
        g1 = g * (1 - g)
        g2 = g1 * (1 - 2 * g)
        g3 = g2 * (1 - 2 * g) - 2 * g1 * g1
        return z * g, g + z * g1, 2 * g1 + z * g2, 3 * g2 + z * g3
    raise ValueError(f"unknown activation {name!r}; use tanh, sin, sigmoid or swish")


ACTIVATIONS = {"tanh": torch.tanh, "sin": torch.sin, "sigmoid": torch.sigmoid,
               "swish": torch.nn.functional.silu}
Jet = tuple  # six tensors: value, d_xi, d_eta, d_xixi, d_xieta, d_etaeta


def _zeros_for_none(grads: tuple, like: torch.Tensor) -> list[torch.Tensor]:
    return [torch.zeros_like(like) if g is None else g for g in grads]


class _ActivationJet(torch.autograd.Function):
    """Chain rule for a point-wise activation on a jet, with a hand-written backward.

    One autograd node instead of a dozen: the fast path's main saving on small batches.
    """

    @staticmethod
    def forward(ctx, name: str, z0, z1, z2, z3, z4, z5):
        s, d1, d2, d3 = _activation(name, z0)
        ctx.save_for_backward(z1, z2, z3, z4, z5, d1, d2, d3)
        return (s, d1 * z1, d1 * z2, d2 * z1 * z1 + d1 * z3, d2 * z1 * z2 + d1 * z4,
                d2 * z2 * z2 + d1 * z5)

    @staticmethod
    def backward(ctx, *grads):
        z1, z2, z3, z4, z5, d1, d2, d3 = ctx.saved_tensors
        g0, g1, g2, g3, g4, g5 = _zeros_for_none(grads, z1)
        g_d1 = g1 * z1 + g2 * z2 + g3 * z3 + g4 * z4 + g5 * z5
        g_d2 = (g3 * z1 + g4 * z2) * z1 + g5 * z2 * z2
        return (None, g0 * d1 + g_d1 * d2 + g_d2 * d3,
                g1 * d1 + d2 * (2 * g3 * z1 + g4 * z2), g2 * d1 + d2 * (g4 * z1 + 2 * g5 * z2),
                g3 * d1, g4 * d1, g5 * d1)


class _ProductJet(torch.autograd.Function):
    """Leibniz rule for the jet of u * w, with a hand-written backward."""

    @staticmethod
    def forward(ctx, *uw):
        u, w = uw[:6], uw[6:]
        ctx.save_for_backward(*uw)
        return _leibniz(u, w)

    @staticmethod
    def backward(ctx, *grads):
        saved = ctx.saved_tensors
        u, w = saved[:6], saved[6:]
        g = _zeros_for_none(grads, u[0])

        def wrt(a: Jet) -> list[torch.Tensor]:  # gradient w.r.t. the other factor of a
            return [g[0] * a[0] + g[1] * a[1] + g[2] * a[2] + g[3] * a[3] + g[4] * a[4]
                    + g[5] * a[5],
                    g[1] * a[0] + 2 * g[3] * a[1] + g[4] * a[2],
                    g[2] * a[0] + g[4] * a[1] + 2 * g[5] * a[2],
                    g[3] * a[0], g[4] * a[0], g[5] * a[0]]

        return (*wrt(w), *wrt(u))


def _leibniz(u: Jet, w: Jet) -> Jet:
    first = tuple(u[c] * w[V] + u[V] * w[c] for c, _ in FIRST)
    second = tuple(u[c] * w[V] + u[a] * w[b] + u[b] * w[a] + u[V] * w[c] for c, a, b in SECOND)
    return (u[V] * w[V], *first, *second)


def activation_jet(name: str, z: Jet) -> Jet:
    """Chain rule for a point-wise activation on a jet."""
    return _ActivationJet.apply(name, *z)


def jet_product(u: Jet, w: Jet) -> Jet:
    """Leibniz rule: the jet of u * w from the jets of u and w."""
    return _ProductJet.apply(*u, *w)


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
        if activation not in ACTIVATIONS:
            raise ValueError(f"unknown activation {activation!r}; use one of "
                             + ", ".join(ACTIVATIONS))
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
        act = ACTIVATIONS[self.activation]
        xk = x.unsqueeze(0).expand(len(self.w_in), -1, -1)
        h = act(torch.baddbmm(self.b_in, xk, self.w_in))  # H1 = sigma(W1 x + b1)
        if self.kind == "shortcut":
            u = act(torch.baddbmm(self.b_u, xk, self.w_u))
            diff = act(torch.baddbmm(self.b_v, xk, self.w_v)) - u
        for w, b in zip(self.w_hidden, self.b_hidden):
            z = act(torch.baddbmm(b, h, w))
            # paper eq. 14: FC_{k+1} = (1 - FC'_k) x FC_b1 + FC'_k x FC_b2 = U + Z (V - U)
            h = torch.addcmul(u, z, diff) if self.kind == "shortcut" else z
        return torch.baddbmm(self.b_out, h, self.w_out)[..., 0].T

    def jet(self, x: torch.Tensor) -> torch.Tensor:
        """Values and derivatives in one pass: (B, 2) -> (6, B, 2), channels as ``V..ETAETA``."""

        def linear(h: Jet, w: torch.Tensor, b: torch.Tensor) -> Jet:
            # one matmul for all six channels; the bias shifts only the value
            z = torch.matmul(torch.stack(h, dim=-3), w.unsqueeze(-3)).unbind(-3)
            return (z[V] + b, *z[1:])

        xj = input_jet(x)
        h = activation_jet(self.activation, linear(xj, self.w_in, self.b_in))
        if self.kind == "shortcut":
            u = activation_jet(self.activation, linear(xj, self.w_u, self.b_u))
            v = activation_jet(self.activation, linear(xj, self.w_v, self.b_v))
            diff = tuple(b - a for a, b in zip(u, v))
        for w, b in zip(self.w_hidden, self.b_hidden):
            z = activation_jet(self.activation, linear(h, w, b))
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
