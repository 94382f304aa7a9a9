"""Training of the PINN and MGNet (paper section 4): Adam with step decay, then L-BFGS.

With the elliptic warm start (the default, warmstart.py) the map starts as the converged
elliptic grid and L-BFGS runs in rounds of ``GUARD_EVERY`` iterations; after each round the
grid on the warm start's lattice is checked against that elliptic grid, and training ends
with the last state that was no worse (:class:`_Guard`): early stopping on grid quality.

Seeded and repeatable. ``progress(info)`` is called every few steps with the phase, step and
loss terms; returning True cancels (raises :class:`TrainingCancelled`). A non-finite or
exploding loss during Adam restores the last good weights and halves the learning rate, at
most ``MAX_RECOVERIES`` times; during L-BFGS it falls back to the Adam result. Either way
the history records it and nothing fails silently.
"""

from __future__ import annotations

import contextlib
import copy
import math
from collections.abc import Callable, Sequence

import numpy as np
import torch

from .auxlines import AuxLine
from .boundary_fit import make_fit
from .errors import TrainingCancelled, TrainingError
from .geometry import SIDES, Boundary
from .heap import reuse_freed_memory
from .losses import annealed_lambda, loss_data, loss_eqns, loss_points, total_loss
from .mapping import Mapping
from .model import TrainedModel
from .networks import CoordinateNet
from .quality import cell_quality, summary
from .settings import Settings
from .warmstart import WarmStart, lattice_for

ANNEAL_EVERY = 10  # epochs between lambda1 updates (Wang et al. use 10)
EXPLODE_FACTOR = 1e4  # a loss this many times its best value counts as diverged
MAX_RECOVERIES = 3
PROGRESS_EVERY = 50
GUARD_EVERY = 5  # L-BFGS iterations between grid-quality checks
GUARD_PATIENCE = 2  # rejected checks in a row that end the training
# A state is kept if its grid has no more folded cells than the elliptic grid and mean and
# worst MaxIncludedAngle within (mean, worst) degrees of it: half of issue 11's bounds without
# auxiliary lines, the bounds themselves with them (pulling grid lines onto drawn lines may
# cost some quality; the elliptic grid ignores the lines).
GUARD_TOL = {False: (0.25, 1.0), True: (0.5, 2.0)}


def pick_device(name: str) -> torch.device:
    """``auto`` picks CUDA when available, else the CPU."""
    if name == "auto":
        return torch.device("cuda" if torch.cuda.is_available() else "cpu")
    try:
        device = torch.device(name)
        torch.empty(1, device=device)
    except (RuntimeError, AssertionError) as exc:
        raise TrainingError(f"device {name!r} is not available here ({exc}); use auto or cpu"
                            ) from None
    return device


def side_points(side: str, t: np.ndarray) -> np.ndarray:
    """Computational coordinates of parameter ``t`` on a side (SPEC 1)."""
    zero, one = np.zeros_like(t), np.ones_like(t)
    return {"bottom": np.column_stack([t, zero]), "top": np.column_stack([t, one]),
            "left": np.column_stack([zero, t]), "right": np.column_stack([one, t])}[side]


class _Problem:
    """Sampled points and targets for one boundary, as tensors on the training device.

    Random points are drawn ``CHUNK`` epochs at a time, with the boundary-fit targets and (hard
    mode) the TFI jets computed once per chunk, so an epoch only slices ready tensors.
    """

    CHUNK = 500

    def __init__(self, mapping: Mapping, boundary: Boundary, aux: Sequence[AuxLine],
                 settings: Settings, dtype: torch.dtype, device: torch.device) -> None:
        self.mapping, self.settings = mapping, settings
        self.dtype, self.device = dtype, device
        self.fit = make_fit(settings.boundary_fit, boundary) if settings.boundary == "penalty" \
            else None
        self.rng = np.random.default_rng(settings.seed)
        self.hard = mapping.mode == "hard"
        self.n_aux = 0
        if aux:
            xe = np.concatenate([a.xi_eta for a in aux])
            self.aux_x = self.tensor(xe)
            self.aux_y = self.tensor(np.concatenate([a.xy for a in aux]))
            self.aux_base = self.tensor(mapping.base_jet(xe)[0]) if self.hard else None
            self.n_aux = len(xe)
        self._chunk: list = []

    def tensor(self, a) -> torch.Tensor:
        return torch.as_tensor(np.asarray(a), dtype=self.dtype, device=self.device)

    def sample(self, n: int, n_side: int) -> tuple:
        """``n`` uniform random interior points (with the TFI jet there in hard mode) and,
        in penalty mode, ``n_side`` random points per side with their boundary-fit targets."""
        x = self.rng.random((n, 2))
        base = self.tensor(self.mapping.base_jet(x)) if self.hard else None
        bx = by = None
        if self.fit is not None:
            t = self.rng.random((4, n_side))
            bx = np.concatenate([side_points(side, ts) for side, ts in zip(SIDES, t)])
            by = np.concatenate([self.fit.sample(side, ts) for side, ts in zip(SIDES, t)])
            bx, by = self.tensor(bx), self.tensor(by)
        return self.tensor(x), base, bx, by

    def epoch_batch(self, epoch: int) -> tuple:
        """The points of one Adam epoch, cut from the current chunk."""
        n, k = self.settings.batch_size, (epoch - 1) % self.CHUNK
        if k == 0:
            x, base, bx, by = self.sample(self.CHUNK * n, self.CHUNK * n)
            if bx is not None:  # side-major -> epoch-major, so that an epoch is one slice
                bx, by = (t.reshape(4, self.CHUNK, n, 2).transpose(0, 1).reshape(
                    self.CHUNK, 4 * n, 2) for t in (bx, by))
            self._chunk = x, base, bx, by
        x, base, bx, by = self._chunk
        cut = slice(k * n, (k + 1) * n)
        return (x[cut], None if base is None else base[:, cut],
                None if bx is None else bx[k], None if by is None else by[k])

    def terms(self, x: torch.Tensor, base: torch.Tensor | None, bx: torch.Tensor | None,
              by: torch.Tensor | None) -> dict[str, torch.Tensor]:
        """Unweighted loss terms; boundary and auxiliary points ride along the jet's pass."""
        points = [p for p in (bx, self.aux_x if self.n_aux else None) if p is not None]
        extra = torch.cat(points) if points else None
        jet, values = self.mapping.jet(x, base, extra, fast=self.settings.fast)
        terms = {"eqns": loss_eqns(jet, self.settings.residual == "scaled")}
        zero = jet.new_zeros(())
        if bx is not None:
            per_side = loss_points(values[:len(bx)].reshape(4, -1, 2), by.reshape(4, -1, 2))
            for j, side in enumerate(SIDES):
                terms[f"bcs_{side}"] = per_side[j]
            terms["bcs"] = per_side.sum()
        else:
            terms["bcs"] = zero
        if self.n_aux:
            pred = self.mapping.compose(values[len(values) - self.n_aux:], self.aux_x,
                                        self.aux_base)
            terms["data"] = loss_data(pred, self.aux_y)
        else:
            terms["data"] = zero
        return terms


class _Guard:
    """Early stopping on grid quality against the elliptic grid of the warm start."""

    def __init__(self, net: CoordinateNet, mapping: Mapping, reference: np.ndarray,
                 with_aux: bool) -> None:
        self.net, self.mapping = net, mapping
        self.mean_tol, self.worst_tol = GUARD_TOL[with_aux]
        self.size = reference.shape[1], reference.shape[0]
        self.reference = self._quality(reference)
        self.kept = self.reference
        self.state = copy.deepcopy(net.state_dict())
        self.kept_iterations = self.rejected = 0

    @staticmethod
    def _quality(grid: np.ndarray) -> dict[str, float]:
        q = summary(cell_quality(grid), 0.0)
        return {k: q[k] for k in ("mean_max_angle", "worst_max_angle", "folded_cells")}

    def check(self, iterations: int) -> bool:
        """Keep the current state if its grid passes; False once ``GUARD_PATIENCE`` checks in
        a row failed (training should stop)."""
        q, ref = self._quality(self.mapping.grid(*self.size)), self.reference
        if (q["folded_cells"] <= ref["folded_cells"]
                and q["mean_max_angle"] <= ref["mean_max_angle"] + self.mean_tol
                and q["worst_max_angle"] <= ref["worst_max_angle"] + self.worst_tol):
            self.state, self.kept = copy.deepcopy(self.net.state_dict()), q
            self.kept_iterations, self.rejected = iterations, 0
        else:
            self.rejected += 1
        return self.rejected < GUARD_PATIENCE

    def restore(self) -> dict:
        """Load the kept state; returns what the report says about the guard."""
        self.net.load_state_dict(self.state)
        return {"lattice": list(self.size), "elliptic": self.reference, "kept": self.kept,
                "kept_after_lbfgs_iterations": self.kept_iterations}


class _History:
    def __init__(self) -> None:
        self.values: dict[str, list[float]] = {}

    def add(self, terms: dict[str, torch.Tensor], lambda1: float, lambda2: float,
            total: torch.Tensor) -> None:
        with torch.no_grad():  # one read of all the terms, not one a term
            values = torch.stack([*terms.values(), total]).tolist()
        row = dict(zip(terms, values))
        row.update(lambda1=lambda1, weighted_bcs=lambda1 * row["bcs"],
                   weighted_data=lambda2 * row["data"], total=values[-1])
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
    cpu = device.type == "cpu"
    if cpu:
        torch.set_num_threads(1)  # measured: faster and steadier for these small networks
    try:
        with reuse_freed_memory() if cpu else contextlib.nullcontext():
            torch.manual_seed(settings.seed)
            kind = "shortcut" if settings.method == "pinn" else "mlp"
            net = CoordinateNet(kind, settings.hidden_layers, settings.neurons,
                                settings.activation).to(device=device, dtype=dtype)
            warm = reference = None
            if settings.warm_start == "elliptic":
                warm, reference = WarmStart.elliptic(boundary,
                                                     *lattice_for(*settings.lattice))
                with torch.no_grad():  # the map starts as the elliptic grid
                    net.w_out.zero_()
            mapping = Mapping(net, boundary, settings.boundary, warm)
            aux = aux if settings.method == "pinn" else ()
            problem = _Problem(mapping, boundary, aux, settings, dtype, device)
            guard = None if reference is None else _Guard(net, mapping, reference, bool(aux))
            history = _History()
            lambda1 = 1.0 if settings.boundary == "penalty" else 0.0
            lambda1, recoveries = _adam(net, problem, settings, history, lambda1, progress)
            if guard is not None and settings.adam_epochs:
                guard.check(0)  # an Adam phase (not needed from the warm start) is checked too
            lbfgs_ok, lbfgs_iterations = _lbfgs(net, problem, settings, history, lambda1,
                                                progress, guard)
            guarded = guard.restore() if guard is not None else None
    finally:
        torch.set_num_threads(threads)
    info = {"adam_epochs": settings.adam_epochs,
            "lbfgs_evaluations": len(history.values.get("total", [])) - settings.adam_epochs,
            "lbfgs_iterations": lbfgs_iterations,
            "lambda1": lambda1, "recoveries": recoveries, "lbfgs_accepted": lbfgs_ok,
            "device": str(device), "final_loss": history.values["total"][-1]
            if history.values else float("nan")}
    if guarded is not None:
        info["guard"] = guarded
    return TrainedModel(mapping=mapping, settings=settings, history=history.values, info=info)


def _bad(loss: float, best: float) -> bool:
    return not math.isfinite(loss) or (math.isfinite(best) and loss > EXPLODE_FACTOR * best
                                       and loss > 1.0)


class _FlatAdam:
    """torch.optim.Adam's update (betas 0.9, 0.999, eps 1e-8; same formulas) on every
    parameter at once: during training the parameters are views of one flat vector, so a
    step is a handful of vector operations instead of torch.optim's per-tensor bookkeeping
    (measured 0.64 ms -> 0.1 ms per epoch with zero_grad, about a tenth of an Adam epoch).
    ``release`` gives the parameters their own storage back."""

    BETAS, EPS = (0.9, 0.999), 1e-8

    def __init__(self, net: torch.nn.Module, lr: float) -> None:
        self.params, self.lr = list(net.parameters()), lr
        self.flat = torch.cat([p.detach().reshape(-1) for p in self.params])
        at = 0
        for p in self.params:
            p.data = self.flat[at:at + p.numel()].view_as(p)
            at += p.numel()
        self.reset()

    def reset(self) -> None:
        self.m, self.v, self.t = torch.zeros_like(self.flat), torch.zeros_like(self.flat), 0

    def zero_grad(self) -> None:
        for p in self.params:
            p.grad = None

    @torch.no_grad()
    def step(self) -> None:
        grad = torch.cat([p.grad.reshape(-1) if p.grad is not None
                          else p.new_zeros(p.numel()) for p in self.params])
        (b1, b2), self.t = self.BETAS, self.t + 1
        self.m.lerp_(grad, 1 - b1)
        self.v.mul_(b2).addcmul_(grad, grad, value=1 - b2)
        denom = (self.v.sqrt() / math.sqrt(1 - b2 ** self.t)).add_(self.EPS)
        self.flat.addcdiv_(self.m, denom, value=-self.lr / (1 - b1 ** self.t))

    def release(self) -> None:
        for p in self.params:
            p.data = p.data.clone()


def _adam(net, problem: _Problem, s: Settings, history: _History, lambda1: float,
          progress) -> tuple[float, int]:
    if s.adam_epochs == 0:
        return lambda1, 0
    opt = _FlatAdam(net, s.learning_rate)
    try:
        return _adam_epochs(net, opt, problem, s, history, lambda1, progress)
    finally:
        opt.release()


def _adam_epochs(net, opt: _FlatAdam, problem: _Problem, s: Settings, history: _History,
                 lambda1: float, progress) -> tuple[float, int]:
    weights = net.weight_matrices()
    best, recoveries, steps = math.inf, 0, 0
    good_state, good_lambda1 = copy.deepcopy(net.state_dict()), lambda1
    for epoch in range(1, s.adam_epochs + 1):
        terms = problem.terms(*problem.epoch_batch(epoch))
        if s.boundary == "penalty" and epoch % ANNEAL_EVERY == 1:
            g_eq = torch.autograd.grad(terms["eqns"], weights, retain_graph=True,
                                       allow_unused=True)
            g_bc = torch.autograd.grad(terms["bcs"], weights, retain_graph=True,
                                       allow_unused=True)
            used = [(a, b) for a, b in zip(g_eq, g_bc) if a is not None and b is not None]
            updated = annealed_lambda([a for a, _ in used], [b for _, b in used], lambda1,
                                      s.anneal_momentum)
            lambda1 = updated if math.isfinite(updated) else lambda1
        loss = total_loss(terms["eqns"], terms["bcs"], terms["data"], lambda1, s.lambda2)
        value = loss.item()
        if _bad(value, best):
            recoveries += 1
            if recoveries > MAX_RECOVERIES:
                raise TrainingError(f"training diverged (loss {value:.3g} at Adam epoch "
                                    f"{epoch}) after {MAX_RECOVERIES} recoveries; try a smaller "
                                    "learning rate or another seed")
            net.load_state_dict(good_state)
            lambda1 = good_lambda1
            opt.lr *= 0.5
            opt.reset()
            continue
        history.add(terms, lambda1, s.lambda2, loss)
        if value < best:
            best = value
            if epoch % 100 == 0:
                good_state, good_lambda1 = copy.deepcopy(net.state_dict()), lambda1
        opt.zero_grad()
        loss.backward()
        opt.step()
        steps += 1
        if steps % s.lr_decay_every == 0:  # step decay, as torch's StepLR
            opt.lr *= s.lr_decay
        if epoch % PROGRESS_EVERY == 0 or epoch == s.adam_epochs:
            _notify(progress, "adam", epoch, s.adam_epochs, history)
    opt.zero_grad()
    return lambda1, recoveries


def _one_blas_thread():
    """SciPy's L-BFGS-B on one BLAS thread. Its vectors (a few thousand numbers, 50 pairs)
    are far too small for threads: OpenBLAS's spinning workers made each iteration cost
    about 20 ms instead of 1.4 ms (measured on this 2-core machine with other work on it),
    and competed with the loss evaluations for the cores."""
    try:
        from threadpoolctl import threadpool_limits  # installed with scikit-learn
    except ImportError:
        return contextlib.nullcontext()
    return threadpool_limits(1, user_api="blas")


def _lbfgs(net, problem: _Problem, s: Settings, history: _History, lambda1: float,
           progress, guard: _Guard | None = None) -> tuple[bool, int]:
    """Full-batch L-BFGS (SciPy's L-BFGS-B without bounds, as the paper's TensorFlow code
    used, and without torch.optim's 1.5 s import of torch._dynamo); returns (accepted,
    iterations): not accepted if it diverged and the Adam weights were kept. With a
    ``guard``, the guard checks the grid every ``GUARD_EVERY`` iterations and may stop it."""
    if s.lbfgs_iterations == 0:
        return True, 0
    from scipy.optimize import minimize

    batch = problem.sample(s.lbfgs_points, max(s.lbfgs_points // 4, 1))
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
        for p in params:
            p.grad = None
        terms = problem.terms(*batch)
        loss = total_loss(terms["eqns"], terms["bcs"], terms["data"], lambda1, s.lambda2)
        value = loss.item()
        calls[0] += 1
        if not math.isfinite(value):
            return math.inf, np.zeros_like(theta)
        history.add(terms, lambda1, s.lambda2, loss)
        loss.backward()
        if calls[0] % 10 == 0:
            _notify(progress, "lbfgs", calls[0], s.lbfgs_iterations, history)
        grad = [p.grad if p.grad is not None else torch.zeros_like(p) for p in params]
        return value, torch.cat([g.flatten() for g in grad]).double().cpu().numpy()

    def each_iteration(xk: np.ndarray) -> None:
        iterations[0] += 1
        if guard is not None and iterations[0] % GUARD_EVERY == 0:
            load(xk)
            if not guard.check(iterations[0]):
                raise StopIteration

    before = history.values["total"][-1] if history.values else math.inf
    theta = torch.cat([p.detach().flatten() for p in params]).double().cpu().numpy()
    with _one_blas_thread():
        result = minimize(loss_and_grad, theta, jac=True, method="L-BFGS-B",
                          callback=each_iteration,
                          options={"maxiter": s.lbfgs_iterations, "maxcor": 50, "ftol": 1e-15,
                                   "gtol": 1e-12, "maxfun": int(s.lbfgs_iterations * 1.25) + 1})
    load(result.x)
    terms = problem.terms(*batch)
    final = total_loss(terms["eqns"], terms["bcs"], terms["data"], lambda1, s.lambda2).item()
    if not math.isfinite(final) or final > before * EXPLODE_FACTOR:
        net.load_state_dict(start_state)
        return False, iterations[0]
    return True, iterations[0]
