"""Training the correction's network (torch): least squares on the training members'
correction coefficients, its linear part started at the ridge regression's solution."""

from __future__ import annotations

import time
from collections.abc import Callable

import numpy as np
import torch

from pinn_engine.family.network import HIDDEN
from pinn_engine.neural.trainer import training_process

# The ridge regression that starts the linear part: its weight relative to the encodings'
# variance (each coefficient has unit variance: a small fraction of one)
RIDGE = 1e-3
LEARNING_RATE = 3e-3  # Adam's, halved every quarter of the epochs
WEIGHT_DECAY = 1e-4  # on the MLP: a few dozen members, the MLP must not learn each one
REPORT_EVERY = 50  # epochs between progress reports


def ridge(z: np.ndarray, c: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The linear map and offset of the ridge regression of ``c`` on ``z``."""
    f = np.hstack([z, np.ones((len(z), 1))])
    penalty = RIDGE * len(z) * np.eye(f.shape[1])
    penalty[-1, -1] = 0.0
    w = np.linalg.solve(f.T @ f + penalty, f.T @ c)
    return w[:-1].T, w[-1]


def fit_network(
    z: np.ndarray,
    c: np.ndarray,
    epochs: int,
    seed: int = 0,
    progress: Callable[[dict], object] | None = None,
) -> tuple[dict[str, np.ndarray], dict[str, list[float]]]:
    """The network's parameters (NumPy arrays, :func:`network.forward`'s) fitted to map the
    encodings ``z`` (members, k) to the coefficients ``c`` (members, m), and the loss history
    (mean squared node error)."""
    with training_process(torch.device("cpu")):
        return _fit(z, c, epochs, seed, progress)


def _fit(
    z: np.ndarray,
    c: np.ndarray,
    epochs: int,
    seed: int,
    progress: Callable[[dict], object] | None,
) -> tuple[dict[str, np.ndarray], dict[str, list[float]]]:
    """:func:`fit_network` in the training process's settings."""
    torch.manual_seed(seed)
    linear, offset = ridge(z, c)
    sizes = [z.shape[1], *HIDDEN, c.shape[1]]
    layers = [torch.nn.Linear(a, b, dtype=torch.float64) for a, b in zip(sizes, sizes[1:])]
    with torch.no_grad():
        layers[-1].weight.zero_()
        layers[-1].bias.zero_()
    lin = torch.tensor(linear, requires_grad=True)
    off = torch.tensor(offset, requires_grad=True)
    zt, ct = torch.as_tensor(z), torch.as_tensor(c)

    def predict() -> torch.Tensor:
        h = zt
        for k, layer in enumerate(layers):
            h = layer(h)
            if k < len(layers) - 1:
                h = torch.tanh(h)
        return h + zt @ lin.T + off

    mlp = [p for layer in layers for p in layer.parameters()]
    opt = torch.optim.Adam(
        [{"params": mlp, "weight_decay": WEIGHT_DECAY}, {"params": [lin, off]}], lr=LEARNING_RATE
    )
    sched = torch.optim.lr_scheduler.StepLR(opt, step_size=max(1, epochs // 4), gamma=0.5)
    history: dict[str, list[float]] = {"data": []}
    began = time.perf_counter()
    for epoch in range(epochs):
        opt.zero_grad()
        loss = (predict() - ct).pow(2).sum(dim=1).mean()
        loss.backward()
        opt.step()
        sched.step()
        history["data"].append(float(loss.detach()))
        if progress is not None and (epoch % REPORT_EVERY == 0 or epoch == epochs - 1):
            progress(
                {
                    "phase": "fit",
                    "epoch": epoch + 1,
                    "total": epochs,
                    "loss": history["data"][-1],
                    "seconds": time.perf_counter() - began,
                }
            )
    params = {f"w{k}": layer.weight.detach().numpy().copy() for k, layer in enumerate(layers)}
    params |= {f"b{k}": layer.bias.detach().numpy().copy() for k, layer in enumerate(layers)}
    params |= {"linear": lin.detach().numpy().copy(), "offset": off.detach().numpy().copy()}
    return params, history
