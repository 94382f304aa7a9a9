"""The coordinate sub-networks (paper section 3.3) as one batched module.

Each sub-network maps the computational coordinates ((xi, eta), or (xi, eta, zeta) for a
hexahedral block) to one physical coordinate. Their parameters are stacked along a leading
axis (x-net, y-net[, z-net]), so all evaluate in one batched matmul while staying
independent networks. ``jet`` gives values with first and second derivatives in one forward
pass for two inputs (pinn_engine.neural.jet); ``jet.nd`` does it for any number.
"""

from __future__ import annotations

import math
import os
import warnings

import torch
from torch import nn

from pinn_engine.neural.jet.layers import ACTIVATIONS, NetworkJet


class CoordinateNet(nn.Module):
    """One sub-network per output coordinate (``outputs``: x and y, or x, y and z), each a
    shortcut network (paper eq. 14) or a plain MLP of ``inputs`` computational coordinates.

    ``kind="shortcut"`` is the "modified MLP" of Wang, Teng and Perdikaris (2020): encoders
    U and V of the input gate every hidden layer point-wise. ``hidden_layers`` counts the
    hidden states: H1 from the input, then ``hidden_layers - 1`` gated layers.
    ``kind="mlp"`` is MGNet's fully connected network.
    """

    def __init__(
        self,
        kind: str = "shortcut",
        hidden_layers: int = 4,
        neurons: int = 30,
        activation: str = "tanh",
        outputs: int = 2,
        inputs: int = 2,
    ) -> None:
        super().__init__()
        if kind not in ("shortcut", "mlp"):
            raise ValueError(f"unknown network kind {kind!r}")
        if activation not in ACTIVATIONS:
            raise ValueError(
                f"unknown activation {activation!r}; use one of " + ", ".join(ACTIVATIONS)
            )
        self.kind, self.activation = kind, activation
        self.hidden_layers, self.neurons = hidden_layers, neurons
        self.inputs, self.outputs = inputs, outputs
        n, k, d = neurons, outputs, inputs

        def weight(*shape: int) -> nn.Parameter:
            fan_in, fan_out = shape[-2], shape[-1]
            std = math.sqrt(2.0 / (fan_in + fan_out))  # Glorot normal, as the PINN codes
            return nn.Parameter(torch.randn(*shape, dtype=torch.float64) * std)

        def bias(*shape: int) -> nn.Parameter:
            return nn.Parameter(torch.zeros(*shape, dtype=torch.float64))

        self.w_in, self.b_in = weight(k, d, n), bias(k, 1, n)
        if kind == "shortcut":
            self.w_u, self.b_u = weight(k, d, n), bias(k, 1, n)
            self.w_v, self.b_v = weight(k, d, n), bias(k, 1, n)
        self.w_hidden = nn.ParameterList([weight(k, n, n) for _ in range(hidden_layers - 1)])
        self.b_hidden = nn.ParameterList([bias(k, 1, n) for _ in range(hidden_layers - 1)])
        self.w_out, self.b_out = weight(k, n, 1), bias(k, 1, 1)

    def weight_matrices(self) -> list[nn.Parameter]:
        """The weight matrices of the main path (input, hidden, output layers): what Wang et
        al.'s Algorithm 1 takes gradient statistics of (no biases, no U/V encoders)."""
        return [self.w_in, *self.w_hidden, self.w_out]

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        """(B, inputs) computational coordinates -> (B, outputs), one per sub-network."""
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

    def jet_params(self) -> list[nn.Parameter]:
        """The parameters in the jet's order: input layer, encoders, (weight, bias) of each
        hidden layer, output layer."""
        params = [self.w_in, self.b_in]
        if self.kind == "shortcut":
            params += [self.w_u, self.b_u, self.w_v, self.b_v]
        for w, b in zip(self.w_hidden, self.b_hidden):
            params += [w, b]
        return params + [self.w_out, self.b_out]

    def jet(
        self, x: torch.Tensor, extra: torch.Tensor | None = None
    ) -> tuple[torch.Tensor, torch.Tensor]:
        """Jet (6, B, 2) at ``x`` (channels ``V..ETAETA``) and plain values (B', 2) at the
        ``extra`` points, all in one pass (two inputs; ``jet.nd.network_jet`` for more)."""
        extra = x[:0] if extra is None else extra
        return NetworkJet.apply(self.kind, self.activation, x, extra, *self.jet_params())


def autograd_jet(net: nn.Module, x: torch.Tensor) -> torch.Tensor:
    """The reference: the same jet by nested ``torch.autograd.grad`` (create_graph=True)."""
    x = x.detach().requires_grad_(True)
    out = net(x)
    grad = lambda y: torch.autograd.grad(y.sum(), x, create_graph=True)[0]  # noqa: E731
    columns = []
    for k in range(out.shape[1]):
        g = grad(out[:, k])
        g_xi, g_eta = grad(g[:, 0]), grad(g[:, 1])
        columns.append(
            torch.stack([out[:, k], g[:, 0], g[:, 1], g_xi[:, 0], g_xi[:, 1], g_eta[:, 1]])
        )
    return torch.stack(columns, dim=-1)


def load_checkpoint(path: str | os.PathLike) -> object:
    """``torch.load`` of a saved model (tensors and plain data only, on the CPU), torch's own
    warnings silenced: a damaged file is the caller's one-line error, and torch warns on some
    (random bytes that start as a newer pickle protocol) before it raises."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return torch.load(path, map_location="cpu", weights_only=True)
