"""Derivative jets for any number of inputs: values, first and second derivatives of a
:class:`~pinn_engine.neural.networks.CoordinateNet` in one forward pass, as plain torch
operations that autograd differentiates (the hexahedral block's, kinds/hexa/problem.py).

A jet of ``d`` inputs is a list of ``channels(d)`` tensors: the value, the ``d`` first
derivatives, then the second derivatives in the order of :func:`pairs` (for ``d`` = 2 the
order of layers.py's ``V..ETAETA``). The two-input jets of layers.py have a hand-written
backward and C++ kernels for their six channels; these trade that speed for any ``d``.
"""

from __future__ import annotations

import itertools

import torch

from pinn_engine.neural.jet.layers import activation_derivatives

Jet = list  # channels(d) tensors of one shape, or shapes that broadcast together


def pairs(d: int) -> list[tuple[int, int]]:
    """The (m, n), m <= n, of the second derivatives d^2 / dxi_m dxi_n, in channel order."""
    return list(itertools.combinations_with_replacement(range(d), 2))


def channels(d: int) -> int:
    """Channels of a jet of ``d`` inputs: value, ``d`` first and d (d + 1) / 2 second."""
    return 1 + d + d * (d + 1) // 2


def second(m: int, n: int, d: int) -> int:
    """The channel of d^2 / dxi_m dxi_n."""
    return 1 + d + pairs(d).index((min(m, n), max(m, n)))


def product(u: Jet, w: Jet, d: int) -> Jet:
    """Leibniz rule: the jet of u * w."""
    first = [u[1 + m] * w[0] + u[0] * w[1 + m] for m in range(d)]
    mixed = [
        u[c] * w[0] + u[1 + a] * w[1 + b] + u[1 + b] * w[1 + a] + u[0] * w[c]
        for c, (a, b) in enumerate(pairs(d), start=1 + d)
    ]
    return [u[0] * w[0], *first, *mixed]


def _activate(name: str, z: Jet, d: int) -> Jet:
    """Chain rule for a point-wise activation sigma: sigma', sigma'' times the jet of z."""
    s, d1, d2, _ = activation_derivatives(name, z[0])
    first = [d1 * z[1 + m] for m in range(d)]
    mixed = [d2 * z[1 + a] * z[1 + b] + d1 * z[c] for c, (a, b) in enumerate(pairs(d), start=1 + d)]
    return [s, *first, *mixed]


def _linear(h: Jet, w: torch.Tensor, b: torch.Tensor) -> Jet:
    """A layer's affine map on every channel; only the value gets the bias."""
    return [torch.baddbmm(b, h[0], w), *(torch.matmul(c, w) for c in h[1:])]


def network_jet(net, x: torch.Tensor) -> torch.Tensor:
    """Jet (channels(d), B, outputs) of ``net`` at ``x`` (B, d)."""
    d = x.shape[1]
    it = iter(net.jet_params())
    w_in, b_in = next(it), next(it)
    # the input's jet: x, the unit vectors, zero second derivatives; the first layer's
    # derivative channels are its weight rows (broadcast over the points)
    xk = x.unsqueeze(0).expand(len(w_in), -1, -1)

    def first_layer(w: torch.Tensor, b: torch.Tensor) -> Jet:
        zero = [w.new_zeros(w.shape[0], 1, w.shape[2])] * len(pairs(d))
        rows = [w[:, m : m + 1] for m in range(d)]
        return _activate(net.activation, [torch.baddbmm(b, xk, w), *rows, *zero], d)

    h = first_layer(w_in, b_in)
    if net.kind == "shortcut":
        w_u, b_u, w_v, b_v = next(it), next(it), next(it), next(it)
        u = first_layer(w_u, b_u)
        diff = [p - q for p, q in zip(first_layer(w_v, b_v), u)]
    rest = list(it)
    for w, b in zip(rest[:-2:2], rest[1:-2:2]):
        z = _activate(net.activation, _linear(h, w, b), d)
        # paper eq. 14: U + Z (V - U)
        h = [p + q for p, q in zip(u, product(z, diff, d))] if net.kind == "shortcut" else z
    out = _linear(h, rest[-2], rest[-1])
    return torch.stack([c[..., 0].T for c in out])
