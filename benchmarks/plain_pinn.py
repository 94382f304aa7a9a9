"""The plain baseline that pinn-mesh's speed figures are measured against.

The same recipe as the ``paper`` preset (pinn_engine.settings.PAPER: shortcut networks, Winslow
loss, decision-tree boundary penalty with annealed lambda1, aux-line data term, Adam then
L-BFGS), written the ordinary way:

- two separate ``nn.Module`` sub-networks x(xi, eta), y(xi, eta) built from ``nn.Linear``;
- derivatives by nested ``torch.autograd.grad(create_graph=True)``, one call per derivative;
  boundary and aux-line values by a separate forward pass;
- stock ``torch.optim.Adam`` (not fused) in float32, then ``.double()`` and stock
  ``torch.optim.LBFGS`` in float64; no custom kernels, no jets, no recovery logic.

Only the inputs come from pinn_engine (boundary, aux lines, decision-tree targets, side
coordinates) and the quality score of the output grid.

Usage: ``.venv/bin/python benchmarks/plain_pinn.py BOUNDARY.vtp [--aux AUX.vtp] [--epochs 5000]
[--lbfgs 500] [--size 41 21]``; prints one JSON line.
"""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Sequence

import numpy as np
import torch
from torch import nn

from pinn_engine.geometry.auxlines import AuxLine
from pinn_engine.geometry.boundary import SIDES, Boundary
from pinn_engine.geometry.boundary_fit import make_fit
from pinn_engine.kinds.four_sided.problem import side_points

HIDDEN_LAYERS, NEURONS = 4, 30
LEARNING_RATE, LR_DECAY, LR_DECAY_EVERY = 1e-3, 0.9, 1000
BATCH, LBFGS_POINTS = 100, 1000  # interior points; per side: BATCH (Adam), LBFGS_POINTS // 4
LAMBDA2, ANNEAL_EVERY, ANNEAL_MOMENTUM = 10.0, 10, 0.9


class ShortcutNet(nn.Module):
    """One coordinate sub-network, the shortcut ("modified MLP") network of paper eq. 14:
    H1 = tanh(W1 x + b1), U = tanh(Wu x + bu), V = tanh(Wv x + bv), then per further hidden
    layer Z = tanh(W h + b), h = U + Z (V - U); linear output."""

    def __init__(self, hidden_layers: int = HIDDEN_LAYERS, neurons: int = NEURONS) -> None:
        super().__init__()
        self.first = nn.Linear(2, neurons)
        self.enc_u = nn.Linear(2, neurons)
        self.enc_v = nn.Linear(2, neurons)
        self.hidden = nn.ModuleList(nn.Linear(neurons, neurons) for _ in range(hidden_layers - 1))
        self.out = nn.Linear(neurons, 1)
        for layer in self.modules():
            if isinstance(layer, nn.Linear):
                nn.init.xavier_normal_(layer.weight)  # Glorot normal
                nn.init.zeros_(layer.bias)

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        h = torch.tanh(self.first(x))
        u = torch.tanh(self.enc_u(x))
        v = torch.tanh(self.enc_v(x))
        for layer in self.hidden:
            z = torch.tanh(layer(h))
            h = u + z * (v - u)
        return self.out(h)


class PlainPINN(nn.Module):
    """The map (xi, eta) -> (x, y) in the working frame: two independent sub-networks."""

    def __init__(self) -> None:
        super().__init__()
        self.x_net = ShortcutNet()
        self.y_net = ShortcutNet()

    def forward(self, xi_eta: torch.Tensor) -> torch.Tensor:
        return torch.cat([self.x_net(xi_eta), self.y_net(xi_eta)], dim=1)


def winslow_loss(model: PlainPINN, points: torch.Tensor) -> torch.Tensor:
    """L_eqns: mean of e1^2 + e2^2, e = alpha r_xixi - 2 beta r_xieta + gamma r_etaeta."""
    x = points.detach().requires_grad_(True)
    d = {}
    for name, net in (("x", model.x_net), ("y", model.y_net)):
        f = net(x)
        (g,) = torch.autograd.grad(f.sum(), x, create_graph=True)
        (g_xi,) = torch.autograd.grad(g[:, 0].sum(), x, create_graph=True)
        (g_eta,) = torch.autograd.grad(g[:, 1].sum(), x, create_graph=True)
        d[name] = (g[:, 0], g[:, 1], g_xi[:, 0], g_xi[:, 1], g_eta[:, 1])
    x_xi, x_eta, x_xixi, x_xieta, x_etaeta = d["x"]
    y_xi, y_eta, y_xixi, y_xieta, y_etaeta = d["y"]
    alpha = x_eta**2 + y_eta**2
    beta = x_xi * x_eta + y_xi * y_eta
    gamma = x_xi**2 + y_xi**2
    e1 = alpha * x_xixi - 2 * beta * x_xieta + gamma * x_etaeta
    e2 = alpha * y_xixi - 2 * beta * y_xieta + gamma * y_etaeta
    return (e1**2 + e2**2).mean()


def loss_terms(model: PlainPINN, batch: dict) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
    """(L_eqns, L_bcs, L_data) on one batch; L_bcs sums the four per-side mean squares."""
    l_eqns = winslow_loss(model, batch["interior"])
    n_bc = len(batch["side_x"])
    values = model(torch.cat([batch["side_x"], batch["aux_x"]]))
    side_err = ((values[:n_bc] - batch["side_y"]) ** 2).sum(dim=1)
    l_bcs = side_err.reshape(4, -1).mean(dim=1).sum()
    l_data = values.new_zeros(())
    if len(batch["aux_x"]):
        l_data = ((values[n_bc:] - batch["aux_y"]) ** 2).sum(dim=1).mean()
    return l_eqns, l_bcs, l_data


def anneal(model: PlainPINN, l_eqns: torch.Tensor, l_bcs: torch.Tensor, lambda1: float) -> float:
    """Wang, Teng, Perdikaris (2020) Algorithm 1 over the weight matrices (not biases):
    lambda_hat = max|grad L_eqns| / mean|grad (lambda1 L_bcs)|, moving average 0.9."""
    weights = [p for name, p in model.named_parameters() if name.endswith("weight")]
    g_eqns = torch.autograd.grad(l_eqns, weights, retain_graph=True)
    g_bcs = torch.autograd.grad(l_bcs, weights, retain_graph=True)
    top = max(g.abs().max().item() for g in g_eqns)
    mean = torch.cat([(lambda1 * g).abs().flatten() for g in g_bcs]).mean().item()
    return ANNEAL_MOMENTUM * lambda1 + (1 - ANNEAL_MOMENTUM) * top / max(mean, 1e-300)


def side_samples(fit, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(xi, eta) and decision-tree targets (4 n, 2) at side parameters ``t`` (4, n), one row of
    ``t`` per side (bottom, right, top, left)."""
    xe = np.concatenate([side_points(s, ts) for s, ts in zip(SIDES, t)])
    xy = np.concatenate([fit.sample(s, ts) for s, ts in zip(SIDES, t)])
    return xe, xy


def train_plain(
    boundary: Boundary,
    aux: Sequence[AuxLine],
    adam_epochs: int = 5000,
    lbfgs_iterations: int = 500,
    seed: int = 0,
    threads: int = 1,
) -> dict:
    """Train the paper recipe plainly on ``boundary`` (working frame) and its aux lines, on
    ``threads`` torch threads.

    Returns {"seconds": training wall time, "final_loss": loss on the L-BFGS batch at the end,
    "lambda1": final boundary weight, "model": the float64 PlainPINN,
    "grid": (ni, nj) -> (nj, ni, 2) grid in user coordinates}.
    """
    before = torch.get_num_threads()
    torch.set_num_threads(threads)
    try:
        start = time.perf_counter()
        torch.manual_seed(seed)
        rng = np.random.default_rng(seed)
        model = PlainPINN()
        fit = make_fit("tree", boundary)
        aux_xe = np.concatenate([a.xi_eta for a in aux]) if aux else np.zeros((0, 2))
        aux_xy = np.concatenate([a.xy for a in aux]) if aux else np.zeros((0, 2))

        def tensors(dtype: torch.dtype, **arrays: np.ndarray) -> dict:
            return {k: torch.as_tensor(v, dtype=dtype) for k, v in arrays.items()}

        # Adam: fresh uniform random points every epoch, all drawn in one go
        side_xe, side_xy = side_samples(fit, rng.random((4, adam_epochs * BATCH)))
        adam = tensors(
            torch.float32,
            interior=rng.random((adam_epochs, BATCH, 2)),
            side_x=side_xe.reshape(4, adam_epochs, BATCH, 2),
            side_y=side_xy.reshape(4, adam_epochs, BATCH, 2),
        )
        aux32 = tensors(torch.float32, aux_x=aux_xe, aux_y=aux_xy)
        opt = torch.optim.Adam(model.parameters(), lr=LEARNING_RATE)
        sched = torch.optim.lr_scheduler.StepLR(opt, step_size=LR_DECAY_EVERY, gamma=LR_DECAY)
        lambda1, loss = 1.0, torch.tensor(float("nan"))
        for epoch in range(adam_epochs):
            points = {
                "interior": adam["interior"][epoch],
                "side_x": adam["side_x"][:, epoch].reshape(-1, 2),
                "side_y": adam["side_y"][:, epoch].reshape(-1, 2),
                **aux32,
            }
            l_eqns, l_bcs, l_data = loss_terms(model, points)
            if epoch % ANNEAL_EVERY == 0:
                lambda1 = anneal(model, l_eqns, l_bcs, lambda1)
            loss = l_eqns + lambda1 * l_bcs + LAMBDA2 * l_data
            opt.zero_grad()
            loss.backward()
            opt.step()
            sched.step()

        # L-BFGS in float64 on one fixed batch
        model.double()
        side_xe, side_xy = side_samples(fit, rng.random((4, LBFGS_POINTS // 4)))
        points = tensors(
            torch.float64,
            interior=rng.random((LBFGS_POINTS, 2)),
            side_x=side_xe,
            side_y=side_xy,
            aux_x=aux_xe,
            aux_y=aux_xy,
        )

        def total() -> torch.Tensor:
            l_eqns, l_bcs, l_data = loss_terms(model, points)
            return l_eqns + lambda1 * l_bcs + LAMBDA2 * l_data

        if lbfgs_iterations:
            lbfgs = torch.optim.LBFGS(
                model.parameters(),
                lr=1.0,
                max_iter=lbfgs_iterations,
                max_eval=int(lbfgs_iterations * 1.25) + 1,
                history_size=50,
                tolerance_grad=1e-12,
                tolerance_change=1e-15,
                line_search_fn="strong_wolfe",
            )

            def closure() -> torch.Tensor:
                lbfgs.zero_grad()
                value = total()
                value.backward()
                return value

            lbfgs.step(closure)
            loss = total()
        seconds = time.perf_counter() - start
    finally:
        torch.set_num_threads(before)
    return {
        "seconds": seconds,
        "final_loss": float(loss.item()),
        "lambda1": lambda1,
        "model": model,
        "grid": lambda ni, nj: plain_grid(model, ni, nj, boundary),
    }


@torch.no_grad()
def plain_grid(model: PlainPINN, ni: int, nj: int, boundary: Boundary) -> np.ndarray:
    """The networks at uniform (xi, eta), ``ni`` x ``nj`` nodes: grid (nj, ni, 2) in the
    user's coordinates (float64)."""
    xi, eta = np.meshgrid(np.linspace(0.0, 1.0, ni), np.linspace(0.0, 1.0, nj))
    points = torch.as_tensor(np.stack([xi, eta], axis=-1).reshape(-1, 2), dtype=torch.float64)
    unit = model.double()(points).numpy().reshape(nj, ni, 2)
    return boundary.frame.to_user(unit)


def main(argv: Sequence[str] | None = None) -> None:
    from pinn_engine.io.pipeline import load_aux, load_boundary
    from pinn_engine.quality import boundary_nodes, cell_quality, summary

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("boundary")
    p.add_argument("--aux", action="append", default=[], help="aux-line file (repeatable)")
    p.add_argument("--epochs", type=int, default=5000)
    p.add_argument("--lbfgs", type=int, default=500)
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--size", type=int, nargs=2, default=[41, 21], metavar=("NI", "NJ"))
    args = p.parse_args(argv)
    boundary = load_boundary(args.boundary)
    aux = load_aux(args.aux, boundary) if args.aux else []
    result = train_plain(boundary, aux, args.epochs, args.lbfgs, args.seed)
    grid = result["grid"](*args.size)
    deviation = boundary.deviation(boundary_nodes(boundary.frame.to_unit(grid))).max()
    quality = summary(cell_quality(grid), float(deviation))
    print(
        json.dumps(
            {
                "seconds": round(result["seconds"], 3),
                "final_loss": result["final_loss"],
                "lambda1": result["lambda1"],
                "epochs": args.epochs,
                "lbfgs": args.lbfgs,
                "size": args.size,
                **quality,
            }
        )
    )


if __name__ == "__main__":
    main()
