"""Forward-mode derivative jets of the coordinate networks: values with first and second
derivatives (channels v, d_xi, d_eta, d_xixi, d_xieta, d_etaeta) in one forward pass, plain
values at extra points (boundary and auxiliary-line samples) riding in the same matmuls, and
a hand-written backward. The whole network runs as one C++ call each way (native.py,
kernels.cpp) where that could be built, else layer by layer as torch operations.
"""

from __future__ import annotations

import ctypes
from collections.abc import Sequence

import torch

from pinn_engine.neural.jet import native

# derivative channels of a jet: value, first, then second derivatives
V, XI, ETA, XIXI, XIETA, ETAETA = range(6)
FIRST = ((XI, 0), (ETA, 1))
SECOND = ((XIXI, XI, XI), (XIETA, XI, ETA), (ETAETA, ETA, ETA))


def activation_derivatives(name: str, z: torch.Tensor) -> tuple[torch.Tensor, ...]:
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


ACTIVATIONS = {
    "tanh": torch.tanh,
    "sin": torch.sin,
    "sigmoid": torch.sigmoid,
    "swish": torch.nn.functional.silu,
}
Jet = tuple  # six tensors: value, d_xi, d_eta, d_xixi, d_xieta, d_etaeta


def _leibniz(u: Jet, w: Jet) -> Jet:
    first = tuple(u[c] * w[V] + u[V] * w[c] for c, _ in FIRST)
    second = tuple(u[c] * w[V] + u[a] * w[b] + u[b] * w[a] + u[V] * w[c] for c, a, b in SECOND)
    return (u[V] * w[V], *first, *second)


def _leibniz_backward(u: Jet, w: Jet, g: Jet) -> tuple[Jet, Jet]:
    """Gradients of a loss with respect to u and w, given its gradient ``g`` w.r.t. u * w."""

    def wrt(a: Jet) -> Jet:  # gradient w.r.t. the other factor of ``a``
        return (
            g[0] * a[0] + g[1] * a[1] + g[2] * a[2] + g[3] * a[3] + g[4] * a[4] + g[5] * a[5],
            g[1] * a[0] + 2 * g[3] * a[1] + g[4] * a[2],
            g[2] * a[0] + g[4] * a[1] + 2 * g[5] * a[2],
            g[3] * a[0],
            g[4] * a[0],
            g[5] * a[0],
        )

    return wrt(w), wrt(u)


def _activation_forward(name: str, z: Jet) -> tuple[Jet, tuple]:
    """Chain rule for a point-wise activation on a jet; also returns what backward needs."""
    s, d1, d2, d3 = activation_derivatives(name, z[V])
    out = (
        s,
        d1 * z[1],
        d1 * z[2],
        d2 * z[1] * z[1] + d1 * z[3],
        d2 * z[1] * z[2] + d1 * z[4],
        d2 * z[2] * z[2] + d1 * z[5],
    )
    return out, (z, d1, d2, d3)


def _activation_backward(saved: tuple, g: Jet) -> Jet:
    (_, z1, z2, z3, z4, z5), d1, d2, d3 = saved
    g0, g1, g2, g3, g4, g5 = g
    g_d1 = g1 * z1 + g2 * z2 + g3 * z3 + g4 * z4 + g5 * z5
    g_d2 = (g3 * z1 + g4 * z2) * z1 + g5 * z2 * z2
    return (
        g0 * d1 + g_d1 * d2 + g_d2 * d3,
        g1 * d1 + d2 * (2 * g3 * z1 + g4 * z2),
        g2 * d1 + d2 * (g4 * z1 + 2 * g5 * z2),
        g3 * d1,
        g4 * d1,
        g5 * d1,
    )


# Row layout of one layer's jet, per sub-network: the five derivative channels (XI..ETAETA)
# of the B jet points, then the values of the jet points and of the value-only points:
# (k, 5 B + B + B_extra, n). One matmul serves every row; only value rows get the bias.


def _linear(h: torch.Tensor, w: torch.Tensor, b: torch.Tensor, n_jet: int) -> torch.Tensor:
    z = torch.bmm(h, w)  # bmm, not matmul: measured 5-15 us less per call
    z[:, 5 * n_jet :] += b
    return z


def _linear_backward(
    h: torch.Tensor, w: torch.Tensor, g: torch.Tensor, n_jet: int, need_input: bool
):
    dw = torch.bmm(h.transpose(1, 2), g)
    db = g[:, 5 * n_jet :].sum(dim=1, keepdim=True)
    dh = torch.bmm(g, w.transpose(1, 2)) if need_input else None
    return dw, db, dh


def _channels(t: torch.Tensor, n_jet: int) -> tuple[Jet, torch.Tensor]:
    """Rows -> (jet channels V..ETAETA of the jet points, values of the value-only points)."""
    k, _, n = t.shape
    d = t[:, : 5 * n_jet].reshape(k, 5, n_jet, n).unbind(1)
    return (t[:, 5 * n_jet : 6 * n_jet], *d), t[:, 6 * n_jet :]


def _rows(jet: Jet, extra: torch.Tensor) -> torch.Tensor:
    """Inverse of :func:`_channels`."""
    return torch.cat([torch.stack(jet[1:], dim=1).flatten(1, 2), jet[0], extra], dim=1)


class NativeCallError(RuntimeError):
    """A C++ kernel refused its call (a non-zero return code): a bug, never a user error."""


def _check(rc: int, what: str) -> None:
    """Raise :class:`NativeCallError` for a kernel's non-zero return code ``rc`` (an
    exception, not an assert: ``python -O`` must not skip it)."""
    if rc != 0:
        raise NativeCallError(f"jet kernels: {what} (return code {rc})")


class _TorchLayers:
    """Jet layers as torch operations: portable (any device), many small operations.

    ``forward(name, z, n_jet, u, diff)`` returns sigma(z) on rows (the jet of it for jet
    points) or, given the shortcut encoders, U + sigma(z) (V - U) with ``diff`` = V - U,
    plus what backward needs. ``backward(saved, g, gu, gdiff)`` returns dL/dz from
    g = dL/d(output) and adds the gradients of U and V - U to ``gu`` and ``gdiff`` in place.
    """

    @staticmethod
    def forward(
        name: str,
        z: torch.Tensor,
        n_jet: int,
        u: torch.Tensor | None = None,
        diff: torch.Tensor | None = None,
    ) -> tuple[torch.Tensor, tuple]:
        z_jet, z_extra = _channels(z, n_jet)
        a, saved = _activation_forward(name, z_jet)
        s, d1 = activation_derivatives(name, z_extra)[:2]
        if u is None:
            return _rows(a, s), (n_jet, saved, d1, None, None)
        (u_jet, u_extra), (w_jet, w_extra) = _channels(u, n_jet), _channels(diff, n_jet)
        h = tuple(p + q for p, q in zip(u_jet, _leibniz(a, w_jet)))
        return _rows(h, u_extra + s * w_extra), (n_jet, saved, d1, (a, s), (w_jet, w_extra))

    @staticmethod
    def backward(
        saved: tuple,
        g: torch.Tensor,
        gu: torch.Tensor | None = None,
        gdiff: torch.Tensor | None = None,
    ) -> torch.Tensor:
        n_jet, s_jet, d1, a, diff = saved
        g_a, g_extra = _channels(g, n_jet)
        if a is not None:
            gu += g
            g_a, g_diff = _leibniz_backward(a[0], diff[0], g_a)
            gdiff += _rows(g_diff, g_extra * a[1])
            g_extra = g_extra * diff[1]
        return _rows(_activation_backward(s_jet, g_a), g_extra * d1)


# Largest workspace the C++ forward fills for backward; above it backward recomputes each
# block's forward in cache instead. Measured, forward and backward of the paper preset's
# networks: 1000 jet and 1202 value points (26 MB) 10.0-11.6 ms stored, 7.6-7.7 ms
# recomputed; 100 and 602 points (4.8 MB) 1.4-1.5 ms stored, 1.7-1.8 ms recomputed.
WORKSPACE_BYTES = 8 << 20


class NativeJet:
    """The whole network's jet as C++ calls (native.py, kernels.cpp), matrix products
    included: forward, and backward from the workspace forward filled; or the paper's loss
    terms and their gradients in one call (:meth:`loss`)."""

    CODES = {"tanh": 0, "sin": 1, "sigmoid": 2, "swish": 3}

    def __init__(
        self,
        lib,
        x: torch.Tensor,
        extra: torch.Tensor,
        kind: str,
        name: str,
        params: Sequence[torch.Tensor],
        size: int,
    ) -> None:
        suffix = "f32" if x.dtype == torch.float32 else "f64"
        self.fwd = getattr(lib, f"net_forward_{suffix}")
        self.bwd = getattr(lib, f"net_backward_{suffix}")
        self.loss_call = getattr(lib, f"net_loss_{suffix}")
        self.code, self.gated = self.CODES[name], int(kind == "shortcut")
        self.params = [p.detach().contiguous() for p in params]
        k, n = self.params[0].shape[0], self.params[0].shape[2]
        hidden = (len(params) - (8 if self.gated else 4)) // 2
        self.x, self.extra = x.contiguous(), extra.contiguous()
        self.dims = (k, hidden + 1, n, len(x), len(extra))
        self.size, self.ws = k * size, None

    @staticmethod
    def pointers(tensors) -> ctypes.Array:
        return (ctypes.c_void_p * len(tensors))(*[t.data_ptr() for t in tensors])

    def _inputs(self) -> tuple:
        """The arguments forward and backward start with: the network, its inputs, the
        workspace."""
        return (
            self.code,
            self.gated,
            native.threads(),
            *self.dims,
            self.pointers(self.params),
            self.x.data_ptr(),
            self.extra.data_ptr(),
            _ptr(self.ws),
        )

    def forward(self) -> tuple[torch.Tensor, torch.Tensor]:
        k, _, _, b, e = self.dims
        # a large workspace costs more memory traffic than backward recomputing it
        if self.size * self.x.element_size() <= WORKSPACE_BYTES:
            self.ws = self.x.new_empty(self.size)
        jet, values = self.x.new_empty(6, b, k), self.x.new_empty(e, k)
        rc = self.fwd(
            *self._inputs(),
            jet.data_ptr(),
            values.data_ptr(),
        )
        _check(rc, "unsupported width")
        return jet, values

    def backward(self, g_jet: torch.Tensor, g_values: torch.Tensor) -> list[torch.Tensor]:
        grads = [torch.empty_like(p) for p in self.params]
        g_jet, g_values = (None if g is None else g.contiguous() for g in (g_jet, g_values))
        rc = self.bwd(
            *self._inputs(),
            _ptr(g_jet),
            _ptr(g_values),
            self.pointers(grads),
        )
        _check(rc, "unsupported width")
        return grads

    def loss(
        self,
        target: torch.Tensor,
        ends: Sequence[int],
        sets: Sequence[int],
        grads: Sequence[Sequence[torch.Tensor]],
    ) -> torch.Tensor:
        """The paper's loss terms and their gradients in one call, block by block, no
        workspace (kernels.cpp ``loss_net``; K = 2 outputs): term 0 is L_eqns (the paper's
        Winslow residual, losses.loss_eqns) at the jet points, term 1 + g the mean squared
        distance to ``target`` (losses.loss_points) of the value points of group g (ending at
        ``ends[g]``). Returns the 1 + G terms (float64); writes the gradients of term 0 into
        ``grads[0]`` and of group g's into ``grads[sets[g]]`` (each set in :meth:`backward`'s
        order; a set no term reaches gets zeros)."""
        terms = torch.zeros(1 + len(ends), dtype=torch.float64)
        target = target.contiguous()  # held here: the C++ call reads it
        rc = self.loss_call(
            self.code,
            self.gated,
            *self.dims,
            self.pointers(self.params),
            self.x.data_ptr(),
            self.extra.data_ptr(),
            target.data_ptr(),
            len(ends),
            (ctypes.c_ssize_t * len(ends))(*ends),
            (ctypes.c_int * len(sets))(*sets),
            len(grads),
            terms.data_ptr(),
            self.pointers([g for group in grads for g in group]),
        )
        _check(rc, "unsupported network for the fused loss")
        return terms


def _ptr(t: torch.Tensor | None) -> int | None:
    return None if t is None else t.data_ptr()


def native_jet(
    x: torch.Tensor, extra: torch.Tensor, kind: str, name: str, params: Sequence[torch.Tensor]
) -> NativeJet | None:
    """The C++ network on the CPU when it could be built (and the width fits), else None;
    outside autograd (gradients come in the order of ``params``)."""
    if x.device.type != "cpu" or x.dtype not in (torch.float32, torch.float64):
        return None
    lib = native.kernels()
    if lib is None:
        return None
    hidden = (len(params) - (8 if kind == "shortcut" else 4)) // 2
    size = lib.net_workspace(
        hidden + 1, params[0].shape[2], len(x), len(extra), int(kind == "shortcut")
    )
    return None if size < 0 else NativeJet(lib, x, extra, kind, name, params, size)


def _input_rows(x: torch.Tensor, extra: torch.Tensor) -> torch.Tensor:
    """Rows (1, 6 B + B_extra, 2) of the input (xi, eta): d_xi = (1, 0), d_eta = (0, 1)."""
    d = x.new_zeros(5, len(x), 2)
    d[XI - 1, :, 0] = 1.0
    d[ETA - 1, :, 1] = 1.0
    return torch.cat([d.flatten(0, 1), x, extra]).unsqueeze(0)


class NetworkJet(torch.autograd.Function):
    """The whole network's jet as one autograd node with a hand-written backward.

    Forward propagates values, first and second derivatives layer by layer (chain and
    Leibniz rules) at the jet points, and plain values at the extra points, in the same
    matmuls; backward runs the layers in reverse with the matching formulas. One node
    instead of hundreds: on batches of ~100 points the autograd bookkeeping, not the
    arithmetic, is what costs.
    """

    @staticmethod
    def forward(
        ctx, kind: str, name: str, x: torch.Tensor, extra: torch.Tensor, *params: torch.Tensor
    ):
        ctx.native = native_jet(x, extra, kind, name, params)
        ctx.set_materialize_grads(False)  # an unused output's gradient comes as None
        if ctx.native is not None:
            return ctx.native.forward()
        layers, b = _TorchLayers, len(x)
        it = iter(params)
        w_in, b_in = next(it), next(it)
        shortcut = kind == "shortcut"
        if shortcut:
            w_u, b_u, w_v, b_v = next(it), next(it), next(it), next(it)
        rest = list(it)
        hidden, (w_out, b_out) = list(zip(rest[:-2:2], rest[1:-2:2])), rest[-2:]
        xr = _input_rows(x, extra).expand(len(params[0]), -1, -1)
        h, s_in = layers.forward(name, _linear(xr, w_in, b_in, b), b)
        saved = {"xr": xr, "s_in": s_in, "layers": []}
        u = diff = None
        if shortcut:
            u, saved["s_u"] = layers.forward(name, _linear(xr, w_u, b_u, b), b)
            v, saved["s_v"] = layers.forward(name, _linear(xr, w_v, b_v, b), b)
            diff = v - u
        for w, bias in hidden:
            hs = h
            h, s_l = layers.forward(name, _linear(hs, w, bias, b), b, u, diff)
            saved["layers"].append((hs, w, s_l))
        saved["out"] = (h, w_out)
        ctx.layers, ctx.shortcut, ctx.weights, ctx.saved = layers, shortcut, params, saved
        jet, values = _channels(_linear(h, w_out, b_out, b), b)
        jet, values = (
            torch.stack(jet)[..., 0].permute(0, 2, 1).contiguous(),
            values[..., 0].T.contiguous(),
        )
        ctx.shapes = jet.shape, values.shape
        return jet, values

    @staticmethod
    def backward(ctx, g_jet: torch.Tensor, g_values: torch.Tensor):
        if ctx.native is not None:  # jet or extra points that no gradient reaches are skipped
            return (None, None, None, None, *ctx.native.backward(g_jet, g_values))
        p = ctx.weights[0]
        g_jet = p.new_zeros(ctx.shapes[0]) if g_jet is None else g_jet
        g_values = p.new_zeros(ctx.shapes[1]) if g_values is None else g_values
        saved, shortcut, layers = ctx.saved, ctx.shortcut, ctx.layers
        params, b = ctx.weights, g_jet.shape[1]
        g = _rows(g_jet.permute(0, 2, 1).unsqueeze(-1).unbind(0), g_values.T.unsqueeze(-1))
        hs, w_out = saved["out"]
        dw_out, db_out, dh = _linear_backward(hs, w_out, g, b, True)
        d_u = torch.zeros_like(dh) if shortcut else None
        d_diff = torch.zeros_like(dh) if shortcut else None
        hidden_grads = []
        for hs, w, s_l in reversed(saved["layers"]):
            d_z = layers.backward(s_l, dh, d_u, d_diff)
            dw, db, dh = _linear_backward(hs, w, d_z, b, True)
            hidden_grads.append((dw, db))
        xr = saved["xr"]
        d_z = layers.backward(saved["s_in"], dh)
        grads = list(_linear_backward(xr, params[0], d_z, b, False)[:2])
        if shortcut:
            for s_key, d in (("s_u", d_u - d_diff), ("s_v", d_diff)):
                d_z = layers.backward(saved[s_key], d)
                grads.extend(_linear_backward(xr, params[0], d_z, b, False)[:2])
        for dw, db in reversed(hidden_grads):
            grads.extend([dw, db])
        grads.extend([dw_out, db_out])
        return (None, None, None, None, *grads)


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
