"""Build the network, seed, guard, fit: the set-up every block kind's training shares.

A block kind gives :func:`train_network` its network (built after the seed, so that its
initial weights are the seed's) and a builder of its problem and guard rule; this module
does the rest the same way for every kind: the dtype, the device, the training process's
thread and heap settings (:func:`trainer.training_process`), the seed, the output layer at
zero (the map starts as the start grid), the :class:`trainer.Guard` and the fit.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
import torch

from pinn_engine.neural.trainer import Guard, Problem, Progress, fit, pick_device, training_process
from pinn_engine.settings import Settings

DTYPES = {"float64": torch.float64, "float32": torch.float32}  # Settings.dtype's names


@dataclass
class GuardRule:
    """What a kind's guard checks (:class:`trainer.Guard`): the ``grid`` now, its
    ``figures``, whether figures pass given the kept ones (``accept``), the figures to start
    from (``start``) and the ``scale`` of node moves (the block's diagonal)."""

    grid: Callable[[], np.ndarray]
    figures: Callable[[np.ndarray], dict]
    accept: Callable[[dict, dict], bool]
    start: dict
    scale: float


@dataclass
class Training:
    """A finished training: the network (in its kept state), the problem it was trained on,
    the loss history, what the report says about it, the guard (None without one) and the
    device."""

    net: torch.nn.Module
    problem: Problem
    history: dict[str, list[float]]
    info: dict
    guard: Guard | None
    device: torch.device


def train_network(
    settings: Settings,
    network: Callable[[torch.dtype, torch.device], torch.nn.Module],
    problem: Callable[
        [torch.nn.Module, torch.dtype, torch.device], tuple[Problem, GuardRule | None]
    ],
    progress: Progress | None = None,
    zero_output: bool = True,
    lambda1: float = 0.0,
    device: torch.device | None = None,
) -> Training:
    """Train a kind's network: seeded by ``settings.seed``, built by ``network(dtype,
    device)`` (``settings.dtype``, ``settings.device`` unless ``device`` is given), its
    output layer zeroed if ``zero_output``, trained by :func:`trainer.fit` from ``lambda1``
    on the problem and under the guard rule that ``problem(net, dtype, device)`` returns."""
    dtype = DTYPES[settings.dtype]
    device = device or pick_device(settings.device)
    with training_process(device):
        torch.manual_seed(settings.seed)
        net = network(dtype, device)
        if zero_output:  # the map starts as the start grid
            with torch.no_grad():
                net.w_out.zero_()
        built, rule = problem(net, dtype, device)
        guard = None
        if rule is not None:
            guard = Guard(net, rule.grid, rule.figures, rule.accept, rule.start, rule.scale)
        history, info = fit(built, settings, guard, progress, lambda1)
    return Training(net, built, history, info, guard, device)
