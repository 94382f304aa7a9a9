"""The one trainer (paper section 4): Adam with step decay, then L-BFGS, for any block kind.

It trains a network on a :class:`Problem` (its sample points, its loss terms, the base map
that builds the boundary in, the start: all the block kind's business) and knows nothing of
which kind it trains. Callbacks steer it: a :class:`Guard` checks the grid every
``GUARD_EVERY`` L-BFGS iterations and keeps the last state that passed (early stopping on
grid quality), and ``progress(info)`` is called every few steps with the phase, step and loss
terms; returning True cancels (raises :class:`TrainingCancelled`), returning ``errors.STOP`` ends
the training early with the best state so far, as ``settings.time_limit`` does (a
:class:`Stop` records why: the report's ``training.stopped``).

Seeded and repeatable. A non-finite or exploding loss during Adam restores the last good
weights and halves the learning rate, at most ``MAX_RECOVERIES`` times; during L-BFGS it
falls back to the Adam result. Either way the history records it and nothing fails silently.
"""

from __future__ import annotations

import contextlib
import copy
import math
import time
from collections.abc import Callable, Sequence
from typing import Protocol

import numpy as np
import torch

from pinn_engine.blas import one_thread
from pinn_engine.errors import STOP, TrainingCancelled, TrainingError
from pinn_engine.heap import reuse_freed_memory
from pinn_engine.neural.losses import annealed_lambda
from pinn_engine.settings import Settings

ANNEAL_EVERY = 10  # epochs between lambda1 updates (Wang et al. use 10)
EXPLODE_FACTOR = 1e4  # a loss this many times its best value counts as diverged
MAX_RECOVERIES = 3  # Adam restarts from the last good weights before training fails
PROGRESS_EVERY = 50  # Adam epochs between progress calls (ParaView's bar, cancel checks)
GOOD_STATE_EVERY = 100  # Adam epochs between copies of the best weights (a copy costs a step)
GUARD_EVERY = 5  # L-BFGS iterations between grid-quality checks
GUARD_PATIENCE = 2  # rejected checks in a row that end the training
LBFGS_MEMORY = 50  # L-BFGS correction pairs (SciPy's maxcor; the paper's TensorFlow used 50)
LBFGS_EVALUATIONS = 1.25  # loss evaluations allowed per iteration (line searches)

Progress = Callable[[dict], "bool | str | None"]


class Evaluation(Protocol):
    """The loss terms at one batch (``terms``), the weighted loss and its gradient."""

    terms: dict[str, torch.Tensor]

    def loss(self, lambda1: float) -> torch.Tensor: ...

    def gradient(self) -> torch.Tensor: ...

    def weight_grads(self, weights: Sequence[torch.Tensor]) -> tuple[list, list]: ...


class Problem(Protocol):
    """What a block kind hands the trainer."""

    net: torch.nn.Module
    anneals: bool  # whether lambda1 (the boundary term's weight) is annealed (penalty mode)

    def epoch_batch(self, epoch: int) -> tuple: ...

    def lbfgs_batch(self) -> tuple: ...

    def evaluate(self, batch: tuple) -> Evaluation: ...

    def weights(self, lambda1: float) -> dict[str, float]: ...


class AutogradEvaluation:
    """The loss terms at one batch (``problem.terms(*batch)``) and the gradient of the
    weighted loss (``problem.loss(terms, lambda1)``) through autograd's graph."""

    def __init__(self, problem, batch: tuple) -> None:
        self.problem = problem
        self.terms = problem.terms(*batch)

    def loss(self, lambda1: float) -> torch.Tensor:
        """The weighted loss; :meth:`gradient` differentiates it."""
        self.lambda1 = lambda1
        self.total = self.problem.loss(self.terms, lambda1)
        return self.total

    def weight_grads(
        self, weights: Sequence[torch.Tensor]
    ) -> tuple[list[torch.Tensor], list[torch.Tensor]]:
        """Gradients of L_eqns and of L_bcs with respect to ``weights`` (for annealing), where
        both reach a weight."""
        g_eq = torch.autograd.grad(
            self.terms["eqns"], weights, retain_graph=True, allow_unused=True
        )
        g_bc = torch.autograd.grad(self.terms["bcs"], weights, retain_graph=True, allow_unused=True)
        used = [(a, b) for a, b in zip(g_eq, g_bc) if a is not None and b is not None]
        return [a for a, _ in used], [b for _, b in used]

    def gradient(self) -> torch.Tensor:
        """The gradient of the last :meth:`loss`: one vector in net.parameters() order."""
        params = list(self.problem.net.parameters())
        grads = torch.autograd.grad(self.total, params, allow_unused=True)
        return torch.cat(
            [p.new_zeros(p.numel()) if g is None else g.reshape(-1) for p, g in zip(params, grads)]
        )


class Guard:
    """Early stopping on grid quality: every ``GUARD_EVERY`` L-BFGS iterations the grid
    (``grid()``) is measured (``figures``) and the state kept if ``accept(figures, kept)``
    (``kept``: the figures of the state kept so far, at first ``start``); training ends after
    ``GUARD_PATIENCE`` rejections in a row and returns the kept state.

    It also says what the network did: whether a trained state was kept or the start, and
    the largest node move between the start's grid and the kept one, relative to ``scale``
    (the block's diagonal in the grid's units)."""

    def __init__(
        self,
        net: torch.nn.Module,
        grid: Callable[[], np.ndarray],
        figures: Callable[[np.ndarray], dict],
        accept: Callable[[dict, dict], bool],
        start: dict,
        scale: float,
    ) -> None:
        self.net, self.grid, self.figures, self.accept = net, grid, figures, accept
        self.kept, self.scale = start, scale
        self.state = copy.deepcopy(net.state_dict())
        self.start_grid = self.kept_grid = grid()
        self.kept_iterations, self.rejected, self.checked = 0, 0, False

    def check(self, iterations: int) -> bool:
        """Keep the current state if its grid passes; False once ``GUARD_PATIENCE`` checks in
        a row failed (training should stop)."""
        grid = self.grid()
        q = self.figures(grid)
        if self.accept(q, self.kept):
            self.state, self.kept, self.kept_grid = copy.deepcopy(self.net.state_dict()), q, grid
            self.kept_iterations, self.rejected, self.checked = iterations, 0, True
        else:
            self.rejected += 1
        return self.rejected < GUARD_PATIENCE

    def restore(self) -> dict:
        """Load the kept state; returns what the report says about the guard and the
        network's effect."""
        self.net.load_state_dict(self.state)
        move = np.linalg.norm(self.kept_grid - self.start_grid, axis=-1).max() / self.scale
        return {
            "kept": self.kept,
            "kept_after_lbfgs_iterations": self.kept_iterations,
            "result": "network" if self.checked else "start",
            "largest_node_move": float(move),
        }


class History:
    """Every loss term, the weights and the total, one row an evaluation."""

    def __init__(self) -> None:
        self.values: dict[str, list[float]] = {}

    def add(
        self, terms: dict[str, torch.Tensor], weights: dict[str, float], total: torch.Tensor
    ) -> None:
        with torch.no_grad():  # one read of all the terms, not one a term
            values = torch.stack([*terms.values(), total]).tolist()
        row = dict(zip(terms, values))
        row["lambda1"] = weights.get("bcs", 0.0)
        row.update({f"weighted_{k}": w * row[k] for k, w in weights.items() if k in row})
        row["total"] = values[-1]
        for k, v in row.items():
            self.values.setdefault(k, []).append(v)


class Stop:
    """Whether training is to end before its schedule, and why: ``settings.time_limit``
    seconds passed (0: no limit) or a progress callback answered ``errors.STOP``."""

    def __init__(self, time_limit: float) -> None:
        self.started = time.monotonic()
        self.deadline = self.started + time_limit if time_limit > 0 else math.inf
        self.time_limit = time_limit
        self.record: dict | None = None  # the report's ``training.stopped``

    def request(self, reason: str, phase: str, step: int) -> None:
        """End the training at the next step; ``reason``: "time limit" or "request"."""
        if self.record is None:
            seconds = round(time.monotonic() - self.started, 1)
            self.record = {"reason": reason, "phase": phase, "step": step, "seconds": seconds}
            if reason == "time limit":
                self.record["time_limit"] = self.time_limit

    def due(self, phase: str, step: int) -> bool:
        """Whether training ends now (the clock is read here: once a step, about 50 ns)."""
        if self.record is None and time.monotonic() > self.deadline:
            self.request("time limit", phase, step)
        return self.record is not None


def notify(
    progress: Progress | None, phase: str, step: int, total: int, loss: dict, stop: Stop
) -> None:
    """Call ``progress`` with the phase, step and last loss terms; cancel if it answers True,
    ask ``stop`` to end the training if it answers ``errors.STOP``."""
    if progress is None:
        return
    info = {"phase": phase, "step": step, "total": total, "loss": loss["total"], "terms": loss}
    answer = progress(info)
    if isinstance(answer, str) and answer == STOP:
        stop.request("request", phase, step)
    elif answer:
        raise TrainingCancelled(f"training cancelled during {phase} at step {step}")


def pick_device(name: str) -> torch.device:
    """``auto`` picks CUDA when available, else the CPU."""
    if name == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    try:
        device = torch.device(name)
        torch.empty(1, device=device)
    except (RuntimeError, AssertionError) as exc:
        raise TrainingError(
            f"device {name!r} is not available here ({exc}); use auto or cpu"
        ) from None
    return device


@contextlib.contextmanager
def training_process(device: torch.device):
    """One torch thread on the CPU (measured: faster and steadier for these small networks)
    and the heap settings of :mod:`heap`, both restored afterwards: the host is left as it
    was found."""
    if device.type != "cpu":
        yield
        return
    threads = torch.get_num_threads()
    torch.set_num_threads(1)
    try:
        with reuse_freed_memory():
            yield
    finally:
        torch.set_num_threads(threads)


def fit(
    problem: Problem,
    settings: Settings,
    guard: Guard | None = None,
    progress: Progress | None = None,
    lambda1: float = 0.0,
) -> tuple[dict[str, list[float]], dict]:
    """Train ``problem.net`` on ``problem``: ``settings.adam_epochs`` of Adam, then up to
    ``settings.lbfgs_iterations`` of L-BFGS under ``guard``; the net ends in the kept state.
    Training ends early, in the best state so far (the guard's, else the last step's), after
    ``settings.time_limit`` seconds or when ``progress`` answers ``errors.STOP``.
    Returns the loss history and what the report says about the training."""
    history, stop = History(), Stop(settings.time_limit)
    lambda1, recoveries, epochs = _adam(problem, settings, history, lambda1, progress, stop)
    if guard is not None and epochs:
        guard.check(0)  # an Adam phase (not needed from a warm start) is checked too
    lbfgs_ok, lbfgs_iterations = True, 0
    if stop.record is None:
        lbfgs_ok, lbfgs_iterations = _lbfgs(
            problem, settings, history, lambda1, progress, stop, guard
        )
    info = {
        "adam_epochs": epochs,
        "lbfgs_evaluations": len(history.values.get("total", [])) - epochs,
        "lbfgs_iterations": lbfgs_iterations,
        "lambda1": lambda1,
        "recoveries": recoveries,
        "lbfgs_accepted": lbfgs_ok,
        "final_loss": history.values["total"][-1] if history.values else float("nan"),
    }
    if stop.record is not None:
        info["stopped"] = stop.record
    if guard is None:  # trained from scratch: the network's grid is the result
        info.update(result="network", largest_node_move=None)
    else:
        info["guard"] = guard.restore()
        info["result"] = info["guard"].pop("result")
        info["largest_node_move"] = info["guard"].pop("largest_node_move")
    return history.values, info


def _bad(loss: float, best: float) -> bool:
    return not math.isfinite(loss) or (
        math.isfinite(best) and loss > EXPLODE_FACTOR * best and loss > 1.0
    )


class _FlatAdam:
    """torch.optim.Adam's update (betas 0.9, 0.999, eps 1e-8; same formulas) on every
    parameter at once: during training the parameters are views of one flat vector, so a
    step is a handful of vector operations on the flat gradient instead of torch.optim's
    per-tensor bookkeeping (measured 0.64 ms -> 0.1 ms per epoch with zero_grad, before the
    gradient came flat). ``release`` gives the parameters their own storage back."""

    BETAS, EPS = (0.9, 0.999), 1e-8

    def __init__(self, net: torch.nn.Module, lr: float) -> None:
        self.params, self.lr = list(net.parameters()), lr
        self.flat = torch.cat([p.detach().reshape(-1) for p in self.params])
        at = 0
        for p in self.params:
            p.data = self.flat[at : at + p.numel()].view_as(p)
            at += p.numel()
        self.reset()

    def reset(self) -> None:
        self.m, self.v, self.t = torch.zeros_like(self.flat), torch.zeros_like(self.flat), 0

    @torch.no_grad()
    def step(self, grad: torch.Tensor) -> None:
        """One update from the loss's gradient ``grad``, a vector in the parameters' order."""
        (b1, b2), self.t = self.BETAS, self.t + 1
        self.m.lerp_(grad, 1 - b1)
        self.v.mul_(b2).addcmul_(grad, grad, value=1 - b2)
        denom = (self.v.sqrt() / math.sqrt(1 - b2**self.t)).add_(self.EPS)
        self.flat.addcdiv_(self.m, denom, value=-self.lr / (1 - b1**self.t))

    def release(self) -> None:
        for p in self.params:
            p.data = p.data.clone()


def _adam(
    problem: Problem, s: Settings, history: History, lambda1: float, progress, stop: Stop
) -> tuple[float, int, int]:
    """Adam's phase; returns lambda1, the recoveries and the epochs run."""
    if s.adam_epochs == 0:
        return lambda1, 0, 0
    opt = _FlatAdam(problem.net, s.learning_rate)
    try:
        return _adam_epochs(opt, problem, s, history, lambda1, progress, stop)
    finally:
        opt.release()


def _adam_epochs(
    opt: _FlatAdam,
    problem: Problem,
    s: Settings,
    history: History,
    lambda1: float,
    progress,
    stop: Stop,
) -> tuple[float, int, int]:
    net = problem.net
    weights = net.weight_matrices() if problem.anneals else []
    best, recoveries, steps = math.inf, 0, 0
    good_state, good_lambda1 = copy.deepcopy(net.state_dict()), lambda1
    for epoch in range(1, s.adam_epochs + 1):
        evaluation = problem.evaluate(problem.epoch_batch(epoch))
        terms = evaluation.terms
        if problem.anneals and epoch % ANNEAL_EVERY == 1:
            updated = annealed_lambda(*evaluation.weight_grads(weights), lambda1, s.anneal_momentum)
            lambda1 = updated if math.isfinite(updated) else lambda1
        loss = evaluation.loss(lambda1)
        value = loss.item()
        if _bad(value, best):
            recoveries += 1
            if recoveries > MAX_RECOVERIES:
                raise TrainingError(
                    f"training diverged (loss {value:.3g} at Adam epoch "
                    f"{epoch}) after {MAX_RECOVERIES} recoveries; try a smaller "
                    "learning rate or another seed"
                )
            net.load_state_dict(good_state)
            lambda1 = good_lambda1
            opt.lr *= 0.5
            opt.reset()
            continue
        history.add(terms, problem.weights(lambda1), loss)
        if value < best:
            best = value
            if epoch % GOOD_STATE_EVERY == 0:
                good_state, good_lambda1 = copy.deepcopy(net.state_dict()), lambda1
        opt.step(evaluation.gradient())
        steps += 1
        if steps % s.lr_decay_every == 0:  # step decay, as torch's StepLR
            opt.lr *= s.lr_decay
        if epoch % PROGRESS_EVERY == 0 or epoch == s.adam_epochs:
            last = {k: v[-1] for k, v in history.values.items()}
            notify(progress, "adam", epoch, s.adam_epochs, last, stop)
        if stop.due("adam", epoch):
            return lambda1, recoveries, epoch
    return lambda1, recoveries, s.adam_epochs


def _lbfgs(
    problem: Problem,
    s: Settings,
    history: History,
    lambda1: float,
    progress,
    stop: Stop,
    guard: Guard | None = None,
) -> tuple[bool, int]:
    """Full-batch L-BFGS (SciPy's L-BFGS-B without bounds, as the paper's TensorFlow code
    used, and without torch.optim's 1.5 s import of torch._dynamo); returns (accepted,
    iterations): not accepted if it diverged and the Adam weights were kept. With a
    ``guard``, the guard checks the grid every ``GUARD_EVERY`` iterations and may stop it;
    ``stop`` ends it after an iteration (an accepted iterate, not a line search's trial)."""
    if s.lbfgs_iterations == 0:
        return True, 0
    from scipy.optimize import minimize

    net = problem.net
    batch = problem.lbfgs_batch()
    params = list(net.parameters())
    sizes = [p.numel() for p in params]
    start_state = copy.deepcopy(net.state_dict())
    calls, iterations = [0], [0]

    def load(theta: np.ndarray) -> None:
        with torch.no_grad():
            for p, chunk in zip(params, np.split(theta, np.cumsum(sizes)[:-1])):
                p.copy_(torch.from_numpy(chunk).view_as(p))

    def loss_and_grad(theta: np.ndarray) -> tuple[float, np.ndarray]:
        load(theta)
        evaluation = problem.evaluate(batch)
        loss = evaluation.loss(lambda1)
        value = loss.item()
        calls[0] += 1
        if not math.isfinite(value):
            return math.inf, np.zeros_like(theta)
        history.add(evaluation.terms, problem.weights(lambda1), loss)
        grad = evaluation.gradient()
        if calls[0] % 10 == 0:
            last = {k: v[-1] for k, v in history.values.items()}
            notify(progress, "lbfgs", calls[0], s.lbfgs_iterations, last, stop)
        return value, grad.double().cpu().numpy()

    def each_iteration(xk: np.ndarray) -> None:
        iterations[0] += 1
        if guard is not None and iterations[0] % GUARD_EVERY == 0:
            load(xk)
            if not guard.check(iterations[0]):
                raise StopIteration
        if stop.due("lbfgs", iterations[0]):
            raise StopIteration

    before = history.values["total"][-1] if history.values else math.inf
    theta = torch.cat([p.detach().flatten() for p in params]).double().cpu().numpy()
    with one_thread():
        result = minimize(
            loss_and_grad,
            theta,
            jac=True,
            method="L-BFGS-B",
            callback=each_iteration,
            options={
                "maxiter": s.lbfgs_iterations,
                "maxcor": LBFGS_MEMORY,
                "ftol": 1e-15,  # no stop on a flat loss: the iterations or the guard end it
                "gtol": 1e-12,
                "maxfun": int(s.lbfgs_iterations * LBFGS_EVALUATIONS) + 1,
            },
        )
    load(result.x)
    final = problem.evaluate(batch).loss(lambda1).item()
    if not math.isfinite(final) or final > before * EXPLODE_FACTOR:
        net.load_state_dict(start_state)
        return False, iterations[0]
    return True, iterations[0]
