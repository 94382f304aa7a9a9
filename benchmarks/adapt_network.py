"""The network on the adaptive equations (SPEC 14's ``pinn``) against their classical solve.

For a given monitor the adaptive equations are linear in each block's computational
coordinates (``adapt/parametric.py``): ``parametric.solve_lattice`` finds their discrete
solution, the unique minimiser of the energy ``x^T L x`` with the sides held. A network
trained on the same equations minimises the same energy over its own outputs at the same
lattice nodes: ``x = start + N(u, v)``, ``N`` a tanh network whose last layer starts at zero
(the network starts from the unadapted grid, SPEC 14's start), trained by Adam then L-BFGS
on that energy. It can at best reach the minimiser the factorisation gives; this script
measures how near it gets, and what it costs, on every solve of the route (each strength and
form the guard tries) of the analytic fields of ``benchmarks/adapt.py``:

    .venv/bin/python benchmarks/adapt_network.py [--set tuning|holdout] [--fields front oblique]

Printed per case: the error ratio (adapted over unadapted, the exact field at ``adapt.QUAD``
points a cell side) of the classical route and of the same route with the network in the
solve's place, the worst cell of each, the network's largest excess of energy over the
minimiser (relative to the minimiser's energy) and both times. The product trains no network
for adaptation (docs/adaptation.md): this is the measurement behind that rule.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
import torch
from adapt import HOLDOUT, TUNING, fields, four_sided, image, interpolation_error

import pinn_engine.adapt.parametric as parametric
from pinn_engine.adapt import Field
from pinn_engine.adapt.grids import DEFAULT_STRENGTH, adapt_grids

WIDTH, DEPTH = 30, 3  # the network: DEPTH hidden tanh layers of WIDTH (the paper's size)
ADAM_STEPS, ADAM_RATE = 500, 1e-3  # Adam's steps and learning rate (the paper's rate)
LBFGS_STEPS = 100  # L-BFGS iterations after Adam (at most; its tolerances stop it earlier)
SEED = 0  # the networks' initial weights


class Excess:
    """The largest relative excess of a network's energy over the minimiser's seen."""

    largest = 0.0


def network_solve(lap, values: np.ndarray, fixed: np.ndarray) -> None:
    """``parametric.solve_lattice``'s contract, by a network trained on the same energy;
    records its excess over the factorisation's minimiser in ``Excess``."""
    rows, cols = values.shape
    free = np.flatnonzero(~fixed.ravel())
    known = np.flatnonzero(fixed.ravel())
    flat = values.ravel()
    exact = values.copy()
    parametric_solve(lap, exact, fixed)
    a = lap[free][:, free].tocoo()
    b = -lap[free][:, known] @ flat[known]
    matrix = torch.sparse_coo_tensor(
        np.vstack([a.row, a.col]), a.data, a.shape, dtype=torch.float64
    ).coalesce()
    rhs = torch.as_tensor(b, dtype=torch.float64)
    start = torch.as_tensor(flat[free], dtype=torch.float64)
    scale = float(np.ptp(flat)) or 1.0  # the outputs' span: the lattice's coordinate range
    jj, ii = np.divmod(free, cols)
    coords = torch.as_tensor(
        np.column_stack([ii / (cols - 1), jj / (rows - 1)]), dtype=torch.float64
    )
    torch.manual_seed(SEED)
    layers: list[torch.nn.Module] = []
    width_in = 2
    for _ in range(DEPTH):
        layers += [torch.nn.Linear(width_in, WIDTH), torch.nn.Tanh()]
        width_in = WIDTH
    last = torch.nn.Linear(WIDTH, 1)
    torch.nn.init.zeros_(last.weight)
    torch.nn.init.zeros_(last.bias)
    net = torch.nn.Sequential(*layers, last).double()

    def energy() -> torch.Tensor:
        x = start + net(coords)[:, 0] * scale
        return 0.5 * x @ torch.sparse.mm(matrix, x[:, None])[:, 0] - rhs @ x

    adam = torch.optim.Adam(net.parameters(), lr=ADAM_RATE)
    for _ in range(ADAM_STEPS):
        adam.zero_grad()
        loss = energy()
        loss.backward()
        adam.step()
    lbfgs = torch.optim.LBFGS(net.parameters(), max_iter=LBFGS_STEPS, line_search_fn="strong_wolfe")

    def closure() -> torch.Tensor:
        lbfgs.zero_grad()
        loss = energy()
        loss.backward()
        return loss

    lbfgs.step(closure)
    with torch.no_grad():
        found = (start + net(coords)[:, 0] * scale).numpy()
        e_net = float(energy())
    x = exact.ravel()[free]
    e_min = float(0.5 * x @ (a @ x) - b @ x)
    Excess.largest = max(Excess.largest, (e_net - e_min) / max(abs(e_min), 1e-300))
    flat[free] = found


parametric_solve = parametric.solve_lattice


def adapted(grids: list[np.ndarray], field: Field, network: bool):
    """The route's adaptation of ``grids`` (classical, or with the network's solve), and
    its CPU seconds."""
    parametric.solve_lattice = network_solve if network else parametric_solve
    began = time.process_time()
    try:
        out = adapt_grids(grids, field, DEFAULT_STRENGTH)
    finally:
        parametric.solve_lattice = parametric_solve
    return out, time.process_time() - began


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", choices=["tuning", "holdout"], default="tuning")
    parser.add_argument("--fields", nargs="+", default=["front", "oblique"])
    parser.add_argument("--size", type=int, nargs=2, default=(41, 31))
    args = parser.parse_args()
    torch.set_num_threads(1)
    shapes = TUNING if args.set == "tuning" else HOLDOUT
    print(f"load average {os.getloadavg()[0]:.1f}; strength {DEFAULT_STRENGTH:g}")
    print(
        "| shape | field | error ratio classical / network | worst classical / network |"
        " network's energy excess | CPU s classical / network |"
    )
    print("|---|---|---|---|---|---|")
    for path in shapes:
        grids = four_sided(path, tuple(args.size))
        flat = np.vstack([g.reshape(-1, 2) for g in grids])
        box = np.array([flat.min(0), flat.max(0)])
        for name in args.fields:
            f = fields(box)[name]
            field = Field(image(f, box), "u", name)
            before = interpolation_error(grids, f)[0]
            Excess.largest = 0.0
            classical, t_c = adapted(grids, field, network=False)
            net, t_n = adapted(grids, field, network=True)
            ratios = [interpolation_error(o.grids, f)[0] / before for o in (classical, net)]
            worst = [o.report["worst_max_angle"]["after"] for o in (classical, net)]
            print(
                f"| {path} | {name} | {ratios[0]:.2f} / {ratios[1]:.2f} | "
                f"{worst[0]:.1f} / {worst[1]:.1f} | {Excess.largest:.1e} | "
                f"{t_c:.2f} / {t_n:.1f} |",
                flush=True,
            )
    print(f"load average {os.getloadavg()[0]:.1f}")


if __name__ == "__main__":
    main()
