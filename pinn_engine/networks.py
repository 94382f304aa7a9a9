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


def _leibniz(u: Jet, w: Jet) -> Jet:
    first = tuple(u[c] * w[V] + u[V] * w[c] for c, _ in FIRST)
    second = tuple(u[c] * w[V] + u[a] * w[b] + u[b] * w[a] + u[V] * w[c] for c, a, b in SECOND)
    return (u[V] * w[V], *first, *second)


def _leibniz_backward(u: Jet, w: Jet, g: Jet) -> tuple[Jet, Jet]:
    """Gradients of a loss with respect to u and w, given its gradient ``g`` w.r.t. u * w."""

    def wrt(a: Jet) -> Jet:  # gradient w.r.t. the other factor of ``a``
        return (g[0] * a[0] + g[1] * a[1] + g[2] * a[2] + g[3] * a[3] + g[4] * a[4]
                + g[5] * a[5],
                g[1] * a[0] + 2 * g[3] * a[1] + g[4] * a[2],
                g[2] * a[0] + g[4] * a[1] + 2 * g[5] * a[2],
                g[3] * a[0], g[4] * a[0], g[5] * a[0])

    return wrt(w), wrt(u)


def _activation_forward(name: str, z: Jet) -> tuple[Jet, tuple]:
    """Chain rule for a point-wise activation on a jet; also returns what backward needs."""
    s, d1, d2, d3 = _activation(name, z[V])
    out = (s, d1 * z[1], d1 * z[2], d2 * z[1] * z[1] + d1 * z[3], d2 * z[1] * z[2] + d1 * z[4],
           d2 * z[2] * z[2] + d1 * z[5])
    return out, (z, d1, d2, d3)


def _activation_backward(saved: tuple, g: Jet) -> Jet:
    (_, z1, z2, z3, z4, z5), d1, d2, d3 = saved
    g0, g1, g2, g3, g4, g5 = g
    g_d1 = g1 * z1 + g2 * z2 + g3 * z3 + g4 * z4 + g5 * z5
    g_d2 = (g3 * z1 + g4 * z2) * z1 + g5 * z2 * z2
    return (g0 * d1 + g_d1 * d2 + g_d2 * d3, g1 * d1 + d2 * (2 * g3 * z1 + g4 * z2),
            g2 * d1 + d2 * (g4 * z1 + 2 * g5 * z2), g3 * d1, g4 * d1, g5 * d1)


def _linear(h: torch.Tensor, w: torch.Tensor, b: torch.Tensor) -> torch.Tensor:
    """One matmul for all six channels (k, 6, B, n); the bias shifts only the value."""
    z = torch.matmul(h, w.unsqueeze(1))
    z[:, V] += b
    return z


def _linear_backward(h: torch.Tensor, w: torch.Tensor, g: torch.Tensor, need_input: bool):
    k = g.shape[0]
    h = h.expand(k, *h.shape[1:])
    dw = torch.bmm(h.reshape(k, -1, h.shape[-1]).transpose(1, 2), g.reshape(k, -1, g.shape[-1]))
    db = g[:, V].sum(dim=1, keepdim=True)
    dh = torch.matmul(g, w.transpose(1, 2).unsqueeze(1)) if need_input else None
    return dw, db, dh


class _NetworkJet(torch.autograd.Function):
    """The whole network's jet as one autograd node with a hand-written backward.

    Forward propagates values, first and second derivatives layer by layer (chain and
    Leibniz rules); backward runs the layers in reverse with the matching formulas. One node
    instead of hundreds: on batches of ~100 points the autograd bookkeeping, not the
    arithmetic, is what costs.
    """

    @staticmethod
    def forward(ctx, kind: str, name: str, x: torch.Tensor, *params: torch.Tensor):
        it = iter(params)
        w_in, b_in = next(it), next(it)
        shortcut = kind == "shortcut"
        if shortcut:
            w_u, b_u, w_v, b_v = next(it), next(it), next(it), next(it)
        rest = list(it)
        hidden, (w_out, b_out) = list(zip(rest[:-2:2], rest[1:-2:2])), rest[-2:]
        xj = torch.stack(input_jet(x)).unsqueeze(0)  # (1, 6, B, 2)
        h, s_in = _activation_forward(name, _linear(xj, w_in, b_in).unbind(1))
        saved = {"xj": xj, "s_in": s_in, "layers": []}
        if shortcut:
            u, saved["s_u"] = _activation_forward(name, _linear(xj, w_u, b_u).unbind(1))
            v, saved["s_v"] = _activation_forward(name, _linear(xj, w_v, b_v).unbind(1))
            diff = tuple(b - a for a, b in zip(u, v))
            saved["diff"] = diff
        for w, b in hidden:
            hs = torch.stack(h, dim=1)
            a, s_l = _activation_forward(name, _linear(hs, w, b).unbind(1))
            saved["layers"].append((hs, w, s_l, a))
            h = tuple(p + q for p, q in zip(u, _leibniz(a, diff))) if shortcut else a
        hs = torch.stack(h, dim=1)
        saved["out"] = (hs, w_out)
        ctx.kind, ctx.shortcut, ctx.weights, ctx.saved = kind, shortcut, params, saved
        return _linear(hs, w_out, b_out)[..., 0].permute(1, 2, 0).contiguous()

    @staticmethod
    def backward(ctx, g_out: torch.Tensor):
        saved, shortcut = ctx.saved, ctx.shortcut
        params = ctx.weights
        g = g_out.permute(2, 0, 1).unsqueeze(-1)  # (k, 6, B, 1)
        hs, w_out = saved["out"]
        dw_out, db_out, dh = _linear_backward(hs, w_out, g, True)
        dh = dh.unbind(1)
        if shortcut:
            diff = saved["diff"]
            d_u = [torch.zeros_like(c) for c in dh]
            d_diff = [torch.zeros_like(c) for c in dh]
        hidden_grads = []
        for hs, w, s_l, a in reversed(saved["layers"]):
            if shortcut:
                d_u = [p + q for p, q in zip(d_u, dh)]
                d_a, dd = _leibniz_backward(a, diff, dh)
                d_diff = [p + q for p, q in zip(d_diff, dd)]
            else:
                d_a = dh
            d_z = torch.stack(_activation_backward(s_l, d_a), dim=1)
            dw, db, dh_prev = _linear_backward(hs, w, d_z, True)
            hidden_grads.append((dw, db))
            dh = dh_prev.unbind(1)
        xj = saved["xj"]
        d_z = torch.stack(_activation_backward(saved["s_in"], dh), dim=1)
        dw_in, db_in, _ = _linear_backward(xj, params[0], d_z, False)
        grads = [dw_in, db_in]
        if shortcut:
            d_v = d_diff
            d_u_total = [p - q for p, q in zip(d_u, d_diff)]
            for s_key, d in (("s_u", d_u_total), ("s_v", d_v)):
                d_z = torch.stack(_activation_backward(saved[s_key], d), dim=1)
                grads.extend(_linear_backward(xj, params[0], d_z, False)[:2])
        for dw, db in reversed(hidden_grads):
            grads.extend([dw, db])
        grads.extend([dw_out, db_out])
        return (None, None, None, *grads)


def jet_product(u: Jet, w: Jet) -> Jet:
    """Leibniz rule: the jet of u * w from the jets of u and w."""
    return _leibniz(u, w)


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
        params = [self.w_in, self.b_in]
        if self.kind == "shortcut":
            params += [self.w_u, self.b_u, self.w_v, self.b_v]
        for w, b in zip(self.w_hidden, self.b_hidden):
            params += [w, b]
        params += [self.w_out, self.b_out]
        return _NetworkJet.apply(self.kind, self.activation, x, *params)


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
