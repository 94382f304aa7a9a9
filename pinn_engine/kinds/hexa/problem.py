"""The hexahedral block kind (SPEC 11): the pinn of a six-faced 3D domain.

Its map (xi, eta, zeta) -> (x, y, z) on the unit cube is the 3D TFI of the six face grids,
plus the start's correction D (hexa/field.py, zero on the faces), plus a bubble times three
coordinate sub-networks (neural/networks.py): the faces are built in (hard boundary, as
kinds/four_sided/mapping.py in 2D). The start is the converged 3D Winslow grid on the same boundary
nodes (the output layer starts at zero, so the map starts as that grid), the loss the 3D
Winslow residual (losses.winslow_residual_3d) at random points, and the guard keeps the last
L-BFGS state no worse than the start by the four-sided ``problem.GUARD_TOL``, else the start: the
grid is never worse than the Winslow grid by more than those tolerances. With a spacing
the start is the spaced Winslow grid, the loss gains its node parameters' control terms
(losses.parameter_controls_3d) and the guard keeps the first edges near H. The trainer
(neural/trainer.py) knows nothing of the third dimension.
"""

from __future__ import annotations

import copy
import os
from dataclasses import dataclass

import numpy as np
import torch

from pinn_engine._version import __version__
from pinn_engine.errors import InputError
from pinn_engine.hexa import quality
from pinn_engine.hexa.field import LatticeField, node_points
from pinn_engine.io.fileio import atomic_path
from pinn_engine.kinds.four_sided.model import network_from, network_payload, read_payload
from pinn_engine.kinds.four_sided.problem import GUARD_TOL, GUARD_WALL_ANGLE
from pinn_engine.kinds.hexa.start import Start
from pinn_engine.neural.jet import nd
from pinn_engine.neural.losses import (
    loss_orthogonal,
    parameter_controls_3d,
    winslow_residual_3d,
)
from pinn_engine.neural.networks import CoordinateNet
from pinn_engine.neural.session import DTYPES, GuardRule, train_network
from pinn_engine.neural.trainer import (
    AutogradEvaluation,
    Progress,
)
from pinn_engine.quality import no_worse
from pinn_engine.settings import Settings, read_settings

DIMENSIONS = 3  # the block's computational coordinates, and its physical ones
FORMAT = "pinn-mesh-hexa-model/1"  # a saved hexahedral model (kinds/four_sided/model.py's is 2D)
GRID_CHUNK = 1 << 14  # nodes per forward pass when a grid is evaluated (bounds its memory)
# The guard keeps a state only if a spaced patch's first edges stay within this fraction of
# H: half of SPEC 7's 10 %, as GUARD_TOL is half of the angle bounds (the start's fit: 1 %)
SPACING_GUARD = 0.05
# random points on each orthogonal patch in the orthogonality term (SPEC 7), as many as the
# interior's L-BFGS points: the guard checks the angle at every patch node anyway
WALL_POINTS = 400


def bubble_jet(x: torch.Tensor) -> nd.Jet:
    """Jet of B = prod_m 4 xi_m (1 - xi_m) at points ``x`` (B, 3), each channel (B, 1): zero
    on the cube's faces."""
    p = 4 * x * (1 - x)
    dp = 4 - 8 * x
    value = p.prod(dim=1, keepdim=True)
    others = [p[:, [n for n in range(DIMENSIONS) if n != m]].prod(dim=1) for m in range(DIMENSIONS)]
    first = [(dp[:, m] * others[m])[:, None] for m in range(DIMENSIONS)]
    mixed = []
    for m, n in nd.pairs(DIMENSIONS):
        if m == n:
            mixed.append((-8 * others[m])[:, None])
        else:
            rest = 3 - m - n  # the third direction
            mixed.append((dp[:, m] * dp[:, n] * p[:, rest])[:, None])
    return [value, *first, *mixed]


def _bubble(x: np.ndarray) -> np.ndarray:
    """B = prod_m 4 xi_m (1 - xi_m) at points ``x`` (B, 3), shape (B, 1)."""
    return np.prod(4 * x * (1 - x), axis=1, keepdims=True)


def _orders() -> list[tuple[int, int, int]]:
    """The derivative orders of ``jet.nd``'s channels for three inputs."""
    unit = np.eye(DIMENSIONS, dtype=int)
    first = [tuple(unit[m]) for m in range(DIMENSIONS)]
    return [(0, 0, 0), *first, *(tuple(unit[m] + unit[n]) for m, n in nd.pairs(DIMENSIONS))]


@dataclass
class HexaModel:
    """The trained map: TFI of the face grids + correction + bubble * network; with the
    settings, loss history and training info, and the key of the surface it was trained on."""

    net: CoordinateNet
    correction: LatticeField
    settings: Settings
    history: dict[str, list[float]]
    info: dict
    surface_key: str

    def grid(self, tfi: np.ndarray) -> np.ndarray:
        """The grid (ni, nj, nk, 3) whose faces are those of ``tfi`` (the 3D TFI of the face
        grids at the wanted size): one forward pass, no training. The network runs in float32
        (node positions need ~1e-7 of the domain); the base, so the faces, stays float64."""
        shape = tfi.shape[:3]
        x = node_points(shape).reshape(-1, DIMENSIONS)
        p = next(self.net.parameters())
        net = copy.deepcopy(self.net).float() if p.dtype != torch.float32 else self.net
        out = np.empty_like(x)
        with torch.no_grad():
            for start in range(0, len(x), GRID_CHUNK):
                at = x[start : start + GRID_CHUNK]
                y = net(torch.as_tensor(at, dtype=torch.float32, device=p.device))
                out[start : start + GRID_CHUNK] = _bubble(at) * y.cpu().numpy()
        return tfi + self.correction.at_nodes(shape) + out.reshape(tfi.shape)

    def save(self, path: str | os.PathLike) -> None:
        """Write the model (weights, settings, correction, history) to ``path`` atomically."""
        payload = {
            "format": FORMAT,
            "version": __version__,
            "settings": self.settings.to_dict(),
            **network_payload(self.net),
            "correction": torch.as_tensor(self.correction.values),
            "surface_key": self.surface_key,
            "history": self.history,
            "info": self.info,
        }
        with atomic_path(path) as tmp:
            torch.save(payload, tmp)

    @classmethod
    def load(cls, path: str | os.PathLike, surface_key: str) -> HexaModel:
        """Read a model; it must have been trained on the surface of ``surface_key``."""
        payload = read_payload(path, FORMAT)
        try:
            settings = read_settings(payload["settings"], "hexa")
            net = network_from(payload)
            correction = LatticeField(payload["correction"].numpy())
            saved_key = payload["surface_key"]
        except (KeyError, TypeError, RuntimeError, ValueError) as exc:
            raise InputError(f"damaged or incompatible model ({exc})", str(path)) from None
        if saved_key != surface_key:
            raise InputError(
                "model was trained for a different surface; save one for this surface "
                "with --save-model",
                str(path),
            )
        return cls(net, correction, settings, payload["history"], payload["info"], saved_key)


class HexaProblem:
    """Random points in the unit cube with the start's jet there, as tensors on the training
    device; the one loss term is the 3D Winslow residual's mean square."""

    def __init__(
        self,
        net: CoordinateNet,
        start: LatticeField,
        settings: Settings,
        dtype: torch.dtype,
        device: torch.device,
        params: LatticeField | None = None,
        walls: tuple[tuple[int, float], ...] = (),
    ) -> None:
        self.net, self.start, self.params, self.settings = net, start, params, settings
        self.walls = walls  # (axis, 0.0 or 1.0) of each orthogonal patch
        self.dtype, self.device = dtype, device
        self.anneals = False  # the boundary is built in: no boundary term to weigh
        self.rng = np.random.default_rng(settings.seed)
        self.orders = _orders()

    def sample(self, n: int) -> tuple:
        """``n`` uniform random points, the start's jet (10, n, 3) there and, with node
        parameters (a spacing), their control terms (n, 3) frozen at the start; then
        ``WALL_POINTS`` random points on each orthogonal patch and the start's jet there."""

        def tensor(a: np.ndarray) -> torch.Tensor:
            return torch.as_tensor(a, dtype=self.dtype, device=self.device)

        x = self.rng.random((n, DIMENSIONS))
        base = tensor(self.start.jet(x, self.orders))
        controls = None
        if self.params is not None:
            controls = parameter_controls_3d(base, tensor(self.params.jet(x, self.orders)))
        on = []
        for axis, value in self.walls:
            w = self.rng.random((WALL_POINTS, DIMENSIONS))
            w[:, axis] = value
            on.append(w)
        if not on:
            return tensor(x), base, controls, None, None
        w = np.concatenate(on)
        return tensor(x), base, controls, tensor(w), tensor(self.start.jet(w, self.orders))

    def epoch_batch(self, epoch: int) -> tuple:
        """The points of one Adam epoch."""
        return self.sample(self.settings.batch_size)

    def lbfgs_batch(self) -> tuple:
        """L-BFGS's fixed batch."""
        return self.sample(self.settings.lbfgs_points)

    def weights(self, lambda1: float) -> dict[str, float]:
        """No weighted terms: the residual is the loss."""
        return {}

    def _jet(self, x: torch.Tensor, base: torch.Tensor) -> torch.Tensor:
        """The map's jet at ``x``: the start's plus the bubble's times the network's (Leibniz
        rule)."""
        net_jet = nd.network_jet(self.net, x)
        return base + torch.stack(nd.product(bubble_jet(x), list(net_jet), DIMENSIONS))

    def terms(
        self,
        x: torch.Tensor,
        base: torch.Tensor,
        controls: torch.Tensor | None,
        wall_x: torch.Tensor | None,
        wall_base: torch.Tensor | None,
    ) -> dict[str, torch.Tensor]:
        """The Winslow term at ``x`` (with the spacing's control terms) and, on orthogonal
        patches, the orthogonality term: the grid line leaving the patch against the
        patch's two tangents (:func:`losses.loss_orthogonal`, SPEC 7)."""
        jet = self._jet(x, base)
        residual = winslow_residual_3d(jet, self.settings.residual == "scaled", controls)
        terms = {"eqns": residual.pow(2).sum(dim=-1).mean()}
        if wall_x is not None:
            wall = self._jet(wall_x, wall_base)
            orth = []
            for k, (axis, _) in enumerate(self.walls):
                at = slice(k * WALL_POINTS, (k + 1) * WALL_POINTS)
                leave = wall[1 + axis, at]
                for m in (m for m in range(DIMENSIONS) if m != axis):
                    orth.append(loss_orthogonal(leave, wall[1 + m, at]))
            terms["orth"] = torch.stack(orth).mean()
        return terms

    def loss(self, terms: dict[str, torch.Tensor], lambda1: float) -> torch.Tensor:
        """The Winslow term plus the orthogonality term (weight 1, as the 2D kind's: both
        are means of order one per point, and the guard decides what is kept)."""
        return terms["eqns"] + terms.get("orth", 0.0)

    def evaluate(self, batch: tuple) -> AutogradEvaluation:
        return AutogradEvaluation(self, batch)


def guard_figures(g: np.ndarray) -> dict[str, float]:
    """Mean and worst MaxIncludedAngle and folded cells of a hexahedral grid (the keys of
    quality.no_worse)."""
    largest = quality.included_angles(g)[0]
    return {
        "mean_max_angle": float(largest.mean()),
        "worst_max_angle": float(largest.max()),
        "folded_cells": int(quality.folded(g).sum()),
    }


def coordinate_net(settings: Settings, dtype: torch.dtype, device: torch.device) -> CoordinateNet:
    """The block's network of ``settings``' shape: three sub-networks of three inputs."""
    return CoordinateNet(
        "shortcut",
        settings.hidden_layers,
        settings.neurons,
        settings.activation,
        outputs=DIMENSIONS,
        inputs=DIMENSIONS,
    ).to(device=device, dtype=dtype)


def untrained_model(
    correction: LatticeField, settings: Settings, info: dict, surface_key: str
) -> HexaModel:
    """The trained model a start equals (untrained.HexaStartModel): the seeded network with
    its output layer at zero on the start's ``correction``, to save and load as any trained
    model."""
    torch.manual_seed(settings.seed)
    net = coordinate_net(settings, DTYPES[settings.dtype], torch.device("cpu"))
    with torch.no_grad():
        net.w_out.zero_()
    return HexaModel(net, correction, settings, {}, info, surface_key)


def train(
    start: Start,
    surface_key: str,
    settings: Settings,
    progress: Progress | None = None,
) -> HexaModel:
    """Train the network from ``start`` under the guard and ``settings`` (a six-faced
    domain's: ``settings.make_settings(size=...)``); ``progress`` is the trainer's callback
    (neural/trainer.py)."""
    tfi = start.tfi
    correction = LatticeField(start.grid - tfi)
    params = None if start.params is None else LatticeField(start.params)

    def figures(g: np.ndarray) -> dict[str, float]:
        q = guard_figures(g)
        if start.spacing_error is not None:
            q["spacing_error"] = start.spacing_error(g)
        if start.wall_angle is not None:
            q["wall_angle"] = start.wall_angle(g)
        return q

    def accept(q: dict, kept: dict) -> bool:
        wall_tol = max(GUARD_WALL_ANGLE, reference.get("wall_angle", 0.0))
        return (
            no_worse(q, reference, *GUARD_TOL)
            and q.get("spacing_error", 0.0) <= SPACING_GUARD
            and q.get("wall_angle", 0.0) <= wall_tol
        )

    reference = figures(start.grid)
    built: list[HexaModel] = []

    def network(dtype: torch.dtype, device: torch.device) -> CoordinateNet:
        return coordinate_net(settings, dtype, device)

    def problem(net, dtype, device) -> tuple[HexaProblem, GuardRule]:
        model = HexaModel(net, correction, settings, {}, {}, surface_key)
        built.append(model)
        diagonal = float(np.linalg.norm(np.ptp(tfi.reshape(-1, DIMENSIONS), axis=0)))
        return HexaProblem(
            net, LatticeField(start.grid), settings, dtype, device, params, start.walls
        ), GuardRule(lambda: model.grid(tfi), figures, accept, reference, diagonal)

    training = train_network(settings, network, problem, progress)
    model, device = built[0], training.device
    model.history, model.info = training.history, training.info
    model.info.update(device=str(device), start=start.name, elliptic=reference)
    return model
