"""The O/C body block kind (SPEC 9): a correction network on top of the elliptic grid.

The map is x(xi, eta) = X(xi, eta) + B(xi, eta) N(features), in index space:

- X is a bicubic spline through the starting grid (the elliptic grid with the default warm
  start, the TFI grid with ``warm_start="none"``, as the paper preset trains from TFI); for
  the O-grid the spline runs over three periods of xi, so X is periodic;
- N is a network (``hidden_layers`` x ``neurons``, ``activation``) of (cos 2 pi xi,
  sin 2 pi xi, eta) for the O-grid, so that the map is periodic in xi exactly, with no seam
  condition to train; of (xi, eta) for the C-grid;
- B = eta^3 (1 - eta) (times 4 xi (1 - xi) for the C-grid) vanishes on the wall and the far
  field (and the C-grid's outflow columns), and so do its first eta-derivative and second
  at the wall: the nodes on j = 0 and j = nj - 1, the first layer's height and the wall
  angle are those of X. The C-grid's cut stays on its line, its nodes coincident.

The loss is the four-sided PINN's (losses.py) in index space: the mean square of Winslow's
equations with the control functions of the elliptic grid (bodygrid.smoothed_controls),
scaled by (alpha + gamma)^(3/2) so that cells of 1e-5 and of 1 chord weigh alike, plus
``ORTHO_WEIGHT`` times losses.loss_orthogonal between the two grid lines at the same
interior points (a local orthogonality term, where the four-sided one holds only at the
orthogonal sides). The shared trainer (:mod:`pinn_engine.neural.trainer`) runs Adam (if
any epochs), then L-BFGS; with the elliptic warm start its guard checks the grid against the
elliptic grid every few iterations and training ends with the last state that was no worse,
in mean and worst angle, than the elliptic grid.
"""

from __future__ import annotations

import math

import numpy as np
import torch
from scipy.interpolate import RectBivariateSpline

from pinn_engine.bodies import bodygrid
from pinn_engine.classical.warm import JET_ORDERS
from pinn_engine.neural.jet import ETA, XI
from pinn_engine.neural.jet.layers import ACTIVATIONS
from pinn_engine.neural.losses import loss_eqns, loss_orthogonal
from pinn_engine.neural.networks import autograd_jet
from pinn_engine.neural.session import GuardRule, train_network
from pinn_engine.neural.trainer import AutogradEvaluation, Progress
from pinn_engine.quality import guard_figures, no_worse
from pinn_engine.settings import Settings

PAD = 3  # columns of the neighbouring periods on each side of the O-grid's spline
# A state is kept if its grid has no more folded cells than the elliptic grid and mean and
# worst MaxIncludedAngle no worse (measured: with the four-sided problem's tolerances, 0.25 and 1
# degree, the kept states were up to 0.25 degree worse than the elliptic grid on every
# airfoil of benchmarks/airfoils.py; with none, the PINN never loses to it)
BODY_GUARD_TOL = (0.0, 0.0)
# weight of the mean cos^2 of the angle between the grid lines (everywhere, not only at the
# wall): measured on benchmarks/airfoils.py at 0.1, the O-grids' mean MaxIncludedAngle drops
# by 0.2 degree and the worst by 0.3 to 0.4 below the elliptic grid's (1 and 10 gain less);
# on the C-grids the mean rises by a few hundredths while the worst falls, so the guard keeps
# the elliptic grid there
ORTHO_WEIGHT = 0.1
WALL_GAP = 0.02  # eta kept off 0 and 1 by this: the bubble's terms vanish there, no signal


class _Field:
    """Bicubic splines of fields given at the nodes of an index lattice (eta, xi)."""

    def __init__(self, values: np.ndarray, periodic: bool) -> None:
        nj, ni = values.shape[:2]
        xi = np.linspace(0.0, 1.0, ni)
        eta = np.linspace(0.0, 1.0, nj)
        if periodic:  # unique columns 0 .. ni - 2, wrapped by PAD on both sides
            u = values[:, :-1]
            u = np.concatenate([u[:, -PAD:], u, u[:, : PAD + 1]], axis=1)
            step = 1.0 / (ni - 1)
            xi = np.arange(-PAD, ni + PAD) * step
        else:
            u = values
        self.splines = [RectBivariateSpline(eta, xi, u[..., k], s=0) for k in range(u.shape[-1])]

    def jet(self, x: np.ndarray) -> np.ndarray:
        """(6, B, k): value, d_xi, d_eta, d_xixi, d_xieta, d_etaeta at points (xi, eta)."""
        xi, eta = x[:, 0], x[:, 1]
        return np.stack(
            [np.stack([s.ev(eta, xi, dx=a, dy=b) for s in self.splines], -1) for a, b in JET_ORDERS]
        )


class BodyNet(torch.nn.Module):
    """N of the map: features (cos 2 pi xi, sin 2 pi xi, eta) for the O-grid (periodic in
    xi), (xi, eta) for the C-grid; the output times the bubble B of the module docstring."""

    def __init__(self, periodic: bool, layers: int, neurons: int, activation: str) -> None:
        super().__init__()
        width = 3 if periodic else 2
        self.hidden = torch.nn.ModuleList()
        for _ in range(layers):
            self.hidden.append(torch.nn.Linear(width, neurons, dtype=torch.float64))
            width = neurons
        last = torch.nn.Linear(width, 2, dtype=torch.float64)
        torch.nn.init.zeros_(last.weight)
        torch.nn.init.zeros_(last.bias)
        self.last, self.act, self.periodic = last, ACTIVATIONS[activation], periodic

    def forward(self, x: torch.Tensor) -> torch.Tensor:
        xi, eta = x[:, :1], x[:, 1:]
        if self.periodic:
            f = torch.cat([torch.cos(2 * math.pi * xi), torch.sin(2 * math.pi * xi), eta], 1)
        else:
            f = x
        for layer in self.hidden:
            f = self.act(layer(f))
        bubble = eta**3 * (1 - eta)
        if not self.periodic:
            bubble = bubble * 4 * xi * (1 - xi)
        return bubble * self.last(f)


class BodyProblem:
    """The body grid's collocation points (eta kept ``WALL_GAP`` off the wall and the far
    field, where the bubble and its derivatives vanish), the start's and the controls'
    splines, and the loss terms."""

    anneals = False  # no boundary term: the bubble builds the wall and far field in

    def __init__(
        self, net: BodyNet, start: np.ndarray, controls, periodic: bool, settings: Settings
    ) -> None:
        self.net, self.settings, self.start = net, settings, start
        self.nj, self.ni = start.shape[:2]
        self.periodic = periodic
        self.base = _Field(start, periodic)
        sx, se = controls
        pad = np.stack([sx, se], axis=-1)
        pad = np.concatenate([pad[:1], pad, pad[-1:]])  # rows j = 0 and nj - 1: nearest
        if periodic:
            pad = np.concatenate([pad, pad[:, :1]], axis=1)
        else:
            pad = np.concatenate([pad[:, :1], pad, pad[:, -1:]], axis=1)
        self.controls = _Field(pad, periodic)
        self.rng = np.random.default_rng(settings.seed)

    def sample(self, n: int) -> tuple[torch.Tensor, torch.Tensor, torch.Tensor]:
        x = self.rng.random((n, 2))
        x[:, 1] = WALL_GAP + (1 - 2 * WALL_GAP) * x[:, 1]
        t = lambda a: torch.as_tensor(a, dtype=torch.float64)  # noqa: E731
        return t(x), t(self.base.jet(x)), t(self.controls.jet(x)[0])

    def epoch_batch(self, epoch: int) -> tuple:
        return self.sample(self.settings.batch_size)

    def lbfgs_batch(self) -> tuple:
        return self.sample(self.settings.lbfgs_points)

    def weights(self, lambda1: float) -> dict[str, float]:
        return {"orth": ORTHO_WEIGHT}

    def evaluate(self, batch: tuple) -> AutogradEvaluation:
        return AutogradEvaluation(self, batch)

    def terms(self, x, base, ctl) -> dict[str, torch.Tensor]:
        """The scaled Winslow residual with the elliptic grid's controls and the cosine
        between the grid lines, in index space."""
        si, sj = self.ni - 1, self.nj - 1  # index space: d/di = d/dxi / (ni - 1)
        scale = torch.tensor([1, si, sj, si**2, si * sj, sj**2], dtype=torch.float64)
        jet = (base + autograd_jet(self.net, x)) / scale[:, None, None]
        return {
            "eqns": loss_eqns(jet, scaled=True, controls=ctl),
            "orth": loss_orthogonal(jet[ETA], jet[XI]),  # everywhere, not only at the wall
        }

    def loss(self, terms: dict[str, torch.Tensor], lambda1: float) -> torch.Tensor:
        return terms["eqns"] + ORTHO_WEIGHT * terms["orth"]

    @torch.no_grad()
    def grid(self) -> np.ndarray:
        """The grid (nj, ni, 2): the start plus the network's correction at the nodes."""
        xi = np.linspace(0.0, 1.0, self.ni)
        eta = np.linspace(0.0, 1.0, self.nj)
        pts = np.stack(np.meshgrid(xi, eta), -1).reshape(-1, 2)
        out = self.net(torch.as_tensor(pts, dtype=torch.float64)).numpy()
        g = self.start + out.reshape(self.nj, self.ni, 2)
        if self.periodic:
            g[:, -1] = g[:, 0]
        return g


def train_body(
    lay,
    elliptic_grid: np.ndarray,
    controls,
    settings: Settings,
    progress: Progress | None = None,
) -> tuple[np.ndarray, dict, dict]:
    """Train the correction network; returns (grid, loss history, training info)."""
    periodic = lay.topology == "o"
    warm = settings.warm_start == "elliptic"
    start = elliptic_grid if warm else bodygrid.tfi(lay, elliptic_grid.shape[0])
    reference = guard_figures(elliptic_grid) if warm else None

    def problem(net, dtype, device) -> tuple[BodyProblem, GuardRule | None]:
        body = BodyProblem(net, start, controls, periodic, settings)
        if not warm:
            return body, None
        diagonal = float(np.linalg.norm(np.ptp(start.reshape(-1, 2), axis=0)))
        return body, GuardRule(
            body.grid,
            guard_figures,
            lambda q, kept: no_worse(q, reference, *BODY_GUARD_TOL),
            guard_figures(start),
            diagonal,
        )

    def network(dtype, device) -> BodyNet:
        return BodyNet(periodic, settings.hidden_layers, settings.neurons, settings.activation)

    training = train_network(
        settings, network, problem, progress, zero_output=False, device=torch.device("cpu")
    )
    history, info, guard = training.history, training.info, training.guard
    grid = guard.kept_grid if guard is not None else training.problem.grid()
    info["warm_start"] = settings.warm_start
    if guard is not None:
        info["guard"]["elliptic"] = reference
    return grid, history, info


__all__ = ["BodyNet", "BodyProblem", "train_body"]
