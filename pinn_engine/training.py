"""Training of the PINN and MGNet (paper section 4): Adam with step decay, then L-BFGS.

Seeded and repeatable. ``progress(info)`` is called every few steps with the phase, step and
loss terms; returning True cancels (raises :class:`TrainingCancelled`). A non-finite or
exploding loss during Adam restores the last good weights and halves the learning rate, at
most ``MAX_RECOVERIES`` times; during L-BFGS it falls back to the Adam result. Either way
the history records it and nothing fails silently.
"""

from __future__ import annotations

import copy
import math
from collections.abc import Callable, Sequence

import numpy as np
import torch

from .auxlines import AuxLine
from .boundary_fit import make_fit
from .errors import TrainingCancelled, TrainingError
from .geometry import SIDES, Boundary
from .losses import annealed_lambda, loss_data, loss_eqns, loss_points, total_loss
from .mapping import Mapping
from .model import TrainedModel
from .networks import CoordinateNet
from .settings import Settings

ANNEAL_EVERY = 10  # epochs between lambda1 updates (Wang et al. use 10)
EXPLODE_FACTOR = 1e4  # a loss this many times its best value counts as diverged
MAX_RECOVERIES = 3
PROGRESS_EVERY = 50


def pick_device(name: str) -> torch.device:
    """``auto`` picks CUDA when available, else the CPU."""
    if name == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    return torch.device(name)


def side_points(side: str, t: np.ndarray) -> np.ndarray:
    """Computational coordinates of parameter ``t`` on a side (SPEC 1)."""
    zero, one = np.zeros_like(t), np.ones_like(t)
    return {"bottom": np.column_stack([t, zero]), "top": np.column_stack([t, one]),
            "left": np.column_stack([zero, t]), "right": np.column_stack([one, t])}[side]


class _Problem:
    """Sampled points and targets for one boundary, as tensors on the training device."""

    def __init__(self, mapping: Mapping, boundary: Boundary, aux: Sequence[AuxLine],
                 settings: Settings, dtype: torch.dtype, device: torch.device) -> None:
        self.mapping, self.settings = mapping, settings
        self.tensor = lambda a: torch.as_tensor(np.asarray(a), dtype=dtype, device=device)
        self.fit = make_fit(settings.boundary_fit, boundary) if settings.boundary == "penalty" \
            else None
        self.rng = np.random.default_rng(settings.seed)
        if aux:
            xe = np.concatenate([a.xi_eta for a in aux])
            self.aux_x = self.tensor(xe)
            self.aux_y = self.tensor(np.concatenate([a.xy for a in aux]))
            self.aux_base = self._base_values(xe)
        else:
            self.aux_x = None

    def _base_values(self, x: np.ndarray) -> torch.Tensor | None:
        return self.tensor(self.mapping.tfi_jet(x)[0]) if self.mapping.mode == "hard" else None

    def collocation(self, n: int) -> tuple[torch.Tensor, torch.Tensor | None]:
        """``n`` uniform random interior points and, in hard mode, the TFI jet there."""
        x = self.rng.random((n, 2))
        base = self.tensor(self.mapping.tfi_jet(x)) if self.mapping.mode == "hard" else None
        return self.tensor(x), base

    def boundary_batch(self, n: int) -> list[tuple[torch.Tensor, torch.Tensor]]:
        """Per side: ``n`` random side points and their boundary-fit targets (penalty mode)."""
        if self.fit is None:
            return []
        out = []
        for side in SIDES:
            t = self.rng.random(n)
            out.append((self.tensor(side_points(side, t)), self.tensor(self.fit.sample(side, t))))
        return out

    def terms(self, x: torch.Tensor, base: torch.Tensor | None,
              bnd: list[tuple[torch.Tensor, torch.Tensor]]) -> dict[str, torch.Tensor]:
        """Unweighted loss terms at the given points."""
        jet = self.mapping.jet(x, base, fast=self.settings.fast)
        terms = {"eqns": loss_eqns(jet)}
        for side, (xs, target) in zip(SIDES, bnd):
            terms[f"bcs_{side}"] = loss_points(self.mapping.values(xs, None), target)
        zero = jet.new_zeros(())
        terms["bcs"] = sum((terms[f"bcs_{s}"] for s in SIDES), zero) if bnd else zero
        if self.aux_x is not None:
            pred = self.mapping.values(self.aux_x, self.aux_base)
            terms["data"] = loss_data(pred, self.aux_y)
        else:
            terms["data"] = zero
        return terms


class _History:
    def __init__(self) -> None:
        self.values: dict[str, list[float]] = {}

    def add(self, terms: dict[str, torch.Tensor], lambda1: float, lambda2: float,
            total: torch.Tensor) -> None:
        row = {k: v.item() for k, v in terms.items()}
        row.update(lambda1=lambda1, weighted_bcs=lambda1 * row["bcs"],
                   weighted_data=lambda2 * row["data"], total=total.item())
        for k, v in row.items():
            self.values.setdefault(k, []).append(v)


def _notify(progress, phase: str, step: int, total_steps: int, history: _History) -> None:
    if progress is None:
        return
    last = {k: v[-1] for k, v in history.values.items()}
    info = {"phase": phase, "step": step, "total": total_steps, "loss": last["total"],
            "terms": last}
    if progress(info):
        raise TrainingCancelled(f"training cancelled during {phase} at step {step}")


def train(boundary: Boundary, aux: Sequence[AuxLine], settings: Settings,
          progress: Callable[[dict], bool | None] | None = None) -> TrainedModel:
    """Train the networks for ``boundary`` (working frame) and return the trained model."""
    dtype = {"float64": torch.float64, "float32": torch.float32}[settings.dtype]
    device = pick_device(settings.device)
    threads = torch.get_num_threads()
    if device.type == "cpu":
        torch.set_num_threads(1)  # measured: faster and steadier for these small networks
    try:
        torch.manual_seed(settings.seed)
        kind = "shortcut" if settings.method == "pinn" else "mlp"
        net = CoordinateNet(kind, settings.hidden_layers, settings.neurons,
                            settings.activation).to(device=device, dtype=dtype)
        mapping = Mapping(net, boundary, settings.boundary)
        problem = _Problem(mapping, boundary, aux if settings.method == "pinn" else (),
                           settings, dtype, device)
        history = _History()
        lambda1 = 1.0 if settings.boundary == "penalty" else 0.0
        lambda1, recoveries = _adam(net, problem, settings, history, lambda1, progress)
        lbfgs_ok = _lbfgs(net, problem, settings, history, lambda1, progress)
    finally:
        torch.set_num_threads(threads)
    info = {"adam_epochs": settings.adam_epochs,
            "lbfgs_evaluations": len(history.values.get("total", [])) - settings.adam_epochs,
            "lambda1": lambda1, "recoveries": recoveries, "lbfgs_accepted": lbfgs_ok,
            "device": str(device), "final_loss": history.values["total"][-1]
            if history.values else float("nan")}
    return TrainedModel(mapping=mapping, settings=settings, history=history.values, info=info)


def _bad(loss: float, best: float) -> bool:
    return not math.isfinite(loss) or (math.isfinite(best) and loss > EXPLODE_FACTOR * best
                                       and loss > 1.0)


def _adam(net, problem: _Problem, s: Settings, history: _History, lambda1: float,
          progress) -> tuple[float, int]:
    lr = s.learning_rate
    opt = torch.optim.Adam(net.parameters(), lr=lr)
    sched = torch.optim.lr_scheduler.StepLR(opt, step_size=s.lr_decay_every, gamma=s.lr_decay)
    weights = [p for p in net.parameters() if p.ndim >= 2]
    best, good_state, recoveries = math.inf, copy.deepcopy(net.state_dict()), 0
    for epoch in range(1, s.adam_epochs + 1):
        x, base = problem.collocation(s.batch_size)
        bnd = problem.boundary_batch(s.batch_size)
        terms = problem.terms(x, base, bnd)
        if s.boundary == "penalty" and epoch % ANNEAL_EVERY == 1:
            g_eq = torch.autograd.grad(terms["eqns"], weights, retain_graph=True)
            g_bc = torch.autograd.grad(terms["bcs"], weights, retain_graph=True)
            lambda1 = annealed_lambda(g_eq, g_bc, lambda1, s.anneal_momentum)
        loss = total_loss(terms["eqns"], terms["bcs"], terms["data"], lambda1, s.lambda2)
        value = loss.item()
        if _bad(value, best):
            recoveries += 1
            if recoveries > MAX_RECOVERIES:
                raise TrainingError(f"training diverged (loss {value:.3g} at Adam epoch "
                                    f"{epoch}) after {MAX_RECOVERIES} recoveries; try a smaller "
                                    "learning rate or another seed")
            net.load_state_dict(good_state)
            for group in opt.param_groups:
                group["lr"] *= 0.5
            opt.state.clear()
            continue
        history.add(terms, lambda1, s.lambda2, loss)
        if value < best:
            best = value
            if epoch % 100 == 0:
                good_state = copy.deepcopy(net.state_dict())
        opt.zero_grad(set_to_none=True)
        loss.backward()
        opt.step()
        sched.step()
        if epoch % PROGRESS_EVERY == 0 or epoch == s.adam_epochs:
            _notify(progress, "adam", epoch, s.adam_epochs, history)
    return lambda1, recoveries


def _lbfgs(net, problem: _Problem, s: Settings, history: _History, lambda1: float,
           progress) -> bool:
    """Full-batch L-BFGS; returns False if it diverged and the Adam weights were kept."""
    if s.lbfgs_iterations == 0:
        return True
    x, base = problem.collocation(s.lbfgs_points)
    bnd = problem.boundary_batch(max(s.lbfgs_points // 4, 1))
    opt = torch.optim.LBFGS(net.parameters(), lr=1.0, max_iter=s.lbfgs_iterations,
                            max_eval=int(s.lbfgs_iterations * 1.25) + 1, history_size=50,
                            tolerance_grad=1e-12, tolerance_change=1e-15,
                            line_search_fn="strong_wolfe")
    start_state = copy.deepcopy(net.state_dict())
    calls = [0]

    def closure():
        opt.zero_grad(set_to_none=True)
        terms = problem.terms(x, base, bnd)
        loss = total_loss(terms["eqns"], terms["bcs"], terms["data"], lambda1, s.lambda2)
        if math.isfinite(float(loss)):
            history.add(terms, lambda1, s.lambda2, loss)
            loss.backward()
        calls[0] += 1
        if calls[0] % 10 == 0:
            _notify(progress, "lbfgs", calls[0], s.lbfgs_iterations, history)
        return loss

    before = history.values["total"][-1] if history.values else math.inf
    opt.step(closure)
    final = float(total_loss(*(problem.terms(x, base, bnd)[k] for k in ("eqns", "bcs", "data")),
                             lambda1, s.lambda2).detach())
    if not math.isfinite(final) or final > before * EXPLODE_FACTOR:
        net.load_state_dict(start_state)
        return False
    return True
