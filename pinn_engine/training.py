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
from .blas import one_blas_thread
from .boundary_fit import ArcLengthFit, make_fit
from .errors import TrainingCancelled, TrainingError
from .geometry import SIDES, Boundary
from .heap import reuse_freed_memory
from .jet.layers import native_jet
from .losses import (
    annealed_lambda,
    corner_angles,
    loss_data,
    loss_eqns,
    loss_orthogonal,
    loss_points,
    loss_quality,
    total_loss,
)
from .mapping import Mapping
from .model import TrainedModel
from .networks import CoordinateNet
from .quality import guard_figures, orientation, side_report
from .quality_start import Ranking, quality_start
from .settings import Settings
from .spacing import chord_tangents, classical_grid, working_spacing
from .tfi import node_params, tfi_grid
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
GUARD_WALL_ANGLE = 1.0  # degrees off 90 that the guard allows at orthogonal sides (SPEC 7: 2)
WALL_POINTS = 200  # points per orthogonal side in the orthogonality term (SPEC 7)
# --objective quality: weight of the cell-quality term (losses.loss_quality) beside the Winslow
# term (the objective's start and its order of grids: quality_start.py)
QUALITY_WEIGHT = 1.0


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


def wall_tangents(
    boundary: Boundary,
    side: str,
    t: np.ndarray,
    lattice: tuple[int, int],
    params: np.ndarray | None = None,
) -> np.ndarray:
    """Tangents of a side at ``t`` as the grid of ``lattice`` nodes (at ``params``, spacing.py)
    sees them (chords)."""
    along = None
    if params is not None:
        along = {
            "bottom": params[0, :, 0],
            "top": params[-1, :, 0],
            "left": params[:, 0, 1],
            "right": params[:, -1, 1],
        }[side]
    return chord_tangents(boundary, side, t, lattice[0 if side in ("bottom", "top") else 1], along)


def first_steps(lattice: tuple[int, int], params: np.ndarray | None = None) -> dict[str, float]:
    """Parameter distance from each side to the next grid row or column: the mean first
    step of ``params`` (nj, ni, 2) (a spacing, spacing.py), else the uniform one."""
    if params is None:
        du, dv = 1.0 / (lattice[0] - 1), 1.0 / (lattice[1] - 1)
        return {"bottom": dv, "top": dv, "left": du, "right": du}
    return {
        "bottom": float(params[1, :, 1].mean()),
        "top": float(1 - params[-2, :, 1].mean()),
        "left": float(params[:, 1, 0].mean()),
        "right": float(1 - params[:, -2, 0].mean()),
    }


def side_points(side: str, t: np.ndarray, inset: float = 0.0) -> np.ndarray:
    """Computational coordinates of parameter ``t`` on a side (SPEC 1), or ``inset`` inside
    it (on the next grid row or column)."""
    zero, one = np.full_like(t, inset), np.full_like(t, 1.0 - inset)
    return {
        "bottom": np.column_stack([t, zero]),
        "top": np.column_stack([t, one]),
        "left": np.column_stack([zero, t]),
        "right": np.column_stack([one, t]),
    }[side]


class _Problem:
    """Sampled points and targets for one boundary, as tensors on the training device.

    Random points are drawn ``CHUNK`` epochs at a time, with the boundary-fit targets and (hard
    mode) the TFI jets computed once per chunk, so an epoch only slices ready tensors.
    """

    CHUNK = 500

    def __init__(
        self,
        mapping: Mapping,
        boundary: Boundary,
        aux: Sequence[AuxLine],
        settings: Settings,
        dtype: torch.dtype,
        device: torch.device,
        wall_steps: dict[str, float] | None = None,
        params: np.ndarray | None = None,
    ) -> None:
        self.mapping, self.settings = mapping, settings
        self.dtype, self.device = dtype, device
        penalty = settings.boundary_mode == "penalty"
        self.fit = make_fit(settings.boundary_fit, boundary) if penalty else None
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
        # fixed points on the sides to be orthogonal (SPEC 7), with the base jet there
        walls = settings.orthogonal if settings.method == "pinn" else ()
        self.n_wall = WALL_POINTS * len(walls)
        if walls:  # the first grid edge leaving each point: from the side to the next row
            t = (np.arange(WALL_POINTS) + 0.5) / WALL_POINTS
            steps = wall_steps or first_steps(settings.lattice)
            xw = np.concatenate([side_points(side, t, steps[side]) for side in walls])
            self.wall_x = self.tensor(xw)
            self.wall_base = self.tensor(mapping.base_jet(xw)) if self.hard else None
            fit = make_fit("arclength", boundary)
            self.wall_origin = self.tensor(np.concatenate([fit.sample(side, t) for side in walls]))
            self.wall_tangent = self.tensor(
                np.concatenate(
                    [wall_tangents(boundary, side, t, settings.lattice, params) for side in walls]
                )
            )
        self.lattice = None
        if settings.objective == "quality" and settings.method == "pinn" and self.hard:
            ni, nj = lattice_for(*settings.lattice)
            base = tfi_grid(ArcLengthFit(boundary).sample, ni, nj)  # the grid's exact base
            if mapping.warm is not None:
                base = base + mapping.warm.grid(ni, nj)
            xi, eta = np.meshgrid(node_params(ni), node_params(nj))
            self.lattice = (
                self.tensor(np.column_stack([xi.ravel(), eta.ravel()])),
                self.tensor(base.reshape(-1, 2)),
                (nj, ni, 2),
                orientation(base),
            )
        net, none = mapping.net, self.tensor(np.zeros((0, 2)))
        fusable = (  # the paper preset's terms
            penalty
            and not self.n_wall
            and self.lattice is None
            and settings.residual == "paper"
            and settings.derivatives == "jets"
            and native_jet(none, none, net.kind, net.activation, net.jet_params()) is not None
        )
        self.fused = _FusedLoss(net, dtype, device) if fusable else None

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
                bx, by = (
                    t.reshape(4, self.CHUNK, n, 2).transpose(0, 1).reshape(self.CHUNK, 4 * n, 2)
                    for t in (bx, by)
                )
            self._chunk = x, base, bx, by
        x, base, bx, by = self._chunk
        cut = slice(k * n, (k + 1) * n)
        return (
            x[cut],
            None if base is None else base[:, cut],
            None if bx is None else bx[k],
            None if by is None else by[k],
        )

    def terms(
        self,
        x: torch.Tensor,
        base: torch.Tensor | None,
        bx: torch.Tensor | None,
        by: torch.Tensor | None,
    ) -> dict[str, torch.Tensor]:
        """Unweighted loss terms; boundary and auxiliary points ride along the jet's pass."""
        lattice = self.lattice[0] if self.lattice is not None else None
        points = [p for p in (bx, self.aux_x if self.n_aux else None, lattice) if p is not None]
        extra = torch.cat(points) if points else None
        n = len(x)
        if self.n_wall:
            x = torch.cat([x, self.wall_x])
            base = None if base is None else torch.cat([base, self.wall_base], dim=1)
        jet, values = self.mapping.jet(x, base, extra, fast=self.settings.derivatives == "jets")
        if lattice is not None:  # the grid on the lattice, for the cell-quality term
            x_lat, base_lat, shape, orientation = self.lattice
            grid = self.mapping.compose(values[len(values) - len(x_lat) :], x_lat, base_lat)
            values = values[: len(values) - len(x_lat)]
        terms = {"eqns": loss_eqns(jet[:, :n], self.settings.residual == "scaled")}
        if self.n_wall:
            terms["orth"] = loss_orthogonal(jet[0, n:] - self.wall_origin, self.wall_tangent)
        zero = jet.new_zeros(())
        if bx is not None:
            per_side = loss_points(values[: len(bx)].reshape(4, -1, 2), by.reshape(4, -1, 2))
            for j, side in enumerate(SIDES):
                terms[f"bcs_{side}"] = per_side[j]
            terms["bcs"] = per_side.sum()
        else:
            terms["bcs"] = zero
        if self.n_aux:
            pred = self.mapping.compose(
                values[len(values) - self.n_aux :], self.aux_x, self.aux_base
            )
            terms["data"] = loss_data(pred, self.aux_y)
        else:
            terms["data"] = zero
        if lattice is not None:
            terms["quality"] = loss_quality(corner_angles(grid.reshape(shape), orientation))
        return terms

    def loss(self, terms: dict[str, torch.Tensor], lambda1: float) -> torch.Tensor:
        """The weighted sum of the terms: paper eq. 9, plus the orthogonality (SPEC 7) and
        cell-quality terms."""
        loss = total_loss(
            terms["eqns"],
            terms["bcs"],
            terms["data"],
            lambda1,
            self.settings.lambda2,
            terms.get("orth", 0.0),
            self.settings.lambda_orthogonal,
        )
        return loss + QUALITY_WEIGHT * terms["quality"] if "quality" in terms else loss

    def evaluate(self, batch: tuple) -> _Evaluation:
        """The loss terms at ``batch`` (from :meth:`sample` or :meth:`epoch_batch`), with
        their gradients on demand."""
        return (_Evaluation if self.fused is None else _FusedEvaluation)(self, batch)


class _Evaluation:
    """The loss terms at one batch and the gradient of the loss, through autograd's graph."""

    def __init__(self, problem: _Problem, batch: tuple) -> None:
        self.problem = problem
        self.terms = problem.terms(*batch)

    def loss(self, lambda1: float) -> torch.Tensor:
        """The weighted loss (:meth:`_Problem.loss`); :meth:`gradient` differentiates it."""
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
        params = list(self.problem.mapping.net.parameters())
        grads = torch.autograd.grad(self.total, params, allow_unused=True)
        return torch.cat(
            [p.new_zeros(p.numel()) if g is None else g.reshape(-1) for p, g in zip(params, grads)]
        )


class _FusedLoss:
    """The paper preset's loss in one C++ call (``NativeJet.loss``): per block of points the
    networks' forward, the terms' gradients with respect to the jet and values, and backward,
    without autograd. The gradients of L_eqns, L_bcs and L_data come apart (annealing needs
    the first two): rows of ``flat``, each one vector in net.parameters() order as the
    optimizers take it, which the C++ code writes through ``views`` (per row, each
    parameter's slice shaped as the parameter)."""

    def __init__(self, net: CoordinateNet, dtype: torch.dtype, device: torch.device) -> None:
        params = list(net.parameters())
        self.flat = torch.empty(3, sum(p.numel() for p in params), dtype=dtype, device=device)
        self.views = []
        for row in self.flat:
            at, views = 0, {}
            for p in params:
                views[p] = row[at : at + p.numel()].view_as(p)
                at += p.numel()
            self.views.append(views)
        self.params = net.jet_params()
        self.order = [[views[p] for p in self.params] for views in self.views]  # C++'s order
        self.kind, self.activation = net.kind, net.activation

    def __call__(
        self, x: torch.Tensor, extra: torch.Tensor, target: torch.Tensor, ends: list[int]
    ) -> torch.Tensor:
        """The terms (float64): L_eqns at ``x``, then the mean squared distance to ``target``
        of each group of ``extra`` (ending at ``ends``: four sides, then the auxiliary
        lines); their gradients into the rows of ``flat``."""
        net = native_jet(x, extra, self.kind, self.activation, self.params)
        return net.loss(target, ends, [1, 1, 1, 1, 2][: len(ends)], self.order)


class _FusedEvaluation(_Evaluation):
    """The same for penalty mode with the paper's residual and no orthogonality or quality
    term (the paper preset), through :class:`_FusedLoss`; the loss's gradient is the terms'
    weighted sum."""

    def __init__(self, problem: _Problem, batch: tuple) -> None:
        x, _, bx, by = batch
        self.problem, self.fused = problem, problem.fused
        n_side = len(bx) // 4
        ends = [n_side, 2 * n_side, 3 * n_side, 4 * n_side]
        extra, target = bx, by
        if problem.n_aux:
            extra, target = torch.cat([bx, problem.aux_x]), torch.cat([by, problem.aux_y])
            ends.append(4 * n_side + problem.n_aux)
        terms = self.fused(x, extra, target, ends)
        if not problem.n_aux:
            terms = torch.cat([terms, terms.new_zeros(1)])
        eqns, *sides, data = terms.unbind()
        self.terms = {"eqns": eqns, **{f"bcs_{side}": v for side, v in zip(SIDES, sides)}}
        self.terms.update(bcs=terms[1:5].sum(), data=data)

    def weight_grads(
        self, weights: Sequence[torch.Tensor]
    ) -> tuple[list[torch.Tensor], list[torch.Tensor]]:
        eqns, bcs = self.fused.views[:2]
        return [eqns[w] for w in weights], [bcs[w] for w in weights]

    def gradient(self) -> torch.Tensor:
        eqns, bcs, data = self.fused.flat
        total = torch.add(eqns, bcs, alpha=self.lambda1)
        return (
            total.add_(data, alpha=self.problem.settings.lambda2) if self.problem.n_aux else total
        )


class _Guard:
    """Early stopping on grid quality against the elliptic grid of the warm start.

    Under ``--objective quality`` (``start`` is the start grid) a state is kept if it ranks
    better than the kept one by ``ranking`` (quality_start.py: a mean less above the bound,
    raised to ``reference``'s if that is higher, then fewer folded cells, then closer to the
    auxiliary lines, and never further from them than ``start``, then a smaller worst angle).
    With orthogonal ``walls`` (SPEC 7) a state is also kept only if its grid lines leave them
    within ``GUARD_WALL_ANGLE`` degrees of 90, or no farther off than the reference's.
    """

    def __init__(
        self,
        net: CoordinateNet,
        mapping: Mapping,
        reference: np.ndarray,
        with_aux: bool,
        start: np.ndarray | None = None,
        params: np.ndarray | None = None,
        walls: tuple[str, ...] = (),
        ranking: Ranking | None = None,
    ) -> None:
        self.net, self.mapping, self.params = net, mapping, params  # params: spacing.py
        self.walls = walls
        self.mean_tol, self.worst_tol = GUARD_TOL[with_aux]
        self.size = reference.shape[1], reference.shape[0]
        self.ranking = None if ranking is None else ranking.against(reference).holding(start)
        self._quality = guard_figures if ranking is None else self.ranking.quality
        self.reference = self._quality(reference)
        self.wall_tol = max(GUARD_WALL_ANGLE, self._wall_angle(reference))
        self.kept = self.reference if ranking is None else self._quality(start)
        self.state = copy.deepcopy(net.state_dict())
        self.kept_iterations = self.rejected = 0

    def _wall_angle(self, grid: np.ndarray) -> float:
        """The largest wall-angle deviation (degrees) at the orthogonal sides (0 if none)."""
        if not self.walls:
            return 0.0
        report = side_report(grid)
        return max(report[side]["max_angle_deviation"] for side in self.walls)

    def check(self, iterations: int) -> bool:
        """Keep the current state if its grid passes; False once ``GUARD_PATIENCE`` checks in
        a row failed (training should stop)."""
        grid = self.mapping.grid(*self.size, params=self.params)
        q = self._quality(grid)
        ref = self.reference
        if self.ranking is not None:
            ok = self.ranking.key(q) < self.ranking.key(self.kept)
        else:
            ok = (
                q["folded_cells"] <= ref["folded_cells"]
                and q["mean_max_angle"] <= ref["mean_max_angle"] + self.mean_tol
                and q["worst_max_angle"] <= ref["worst_max_angle"] + self.worst_tol
            )
        ok = ok and self._wall_angle(grid) <= self.wall_tol
        if ok:
            self.state, self.kept = copy.deepcopy(self.net.state_dict()), q
            self.kept_iterations, self.rejected = iterations, 0
        else:
            self.rejected += 1
        return self.rejected < GUARD_PATIENCE

    def restore(self) -> dict:
        """Load the kept state; returns what the report says about the guard."""
        self.net.load_state_dict(self.state)
        return {
            "lattice": list(self.size),
            "elliptic": self.reference,
            "kept": self.kept,
            "kept_after_lbfgs_iterations": self.kept_iterations,
        }


class _History:
    def __init__(self) -> None:
        self.values: dict[str, list[float]] = {}

    def add(
        self, terms: dict[str, torch.Tensor], lambda1: float, lambda2: float, total: torch.Tensor
    ) -> None:
        with torch.no_grad():  # one read of all the terms, not one a term
            values = torch.stack([*terms.values(), total]).tolist()
        row = dict(zip(terms, values))
        row.update(
            lambda1=lambda1,
            weighted_bcs=lambda1 * row["bcs"],
            weighted_data=lambda2 * row["data"],
            total=values[-1],
        )
        for k, v in row.items():
            self.values.setdefault(k, []).append(v)


def _notify(progress, phase: str, step: int, total_steps: int, history: _History) -> None:
    if progress is None:
        return
    last = {k: v[-1] for k, v in history.values.items()}
    info = {
        "phase": phase,
        "step": step,
        "total": total_steps,
        "loss": last["total"],
        "terms": last,
    }
    if progress(info):
        raise TrainingCancelled(f"training cancelled during {phase} at step {step}")


def _warm_start(
    boundary: Boundary, settings: Settings, lattice: tuple[int, int], aux: Sequence[AuxLine]
) -> tuple:
    """(warm start, the guard's reference grid, the quality objective's start grid or None,
    the lattice's node parameters or None, the quality objective's ranking of grids or None)
    on ``lattice``. The reference is the converged elliptic grid, under the spacing if one is
    set (its node parameters, spacing.py), or the orthogonal start grid itself under
    ``--orthogonal`` (orthogonal.py)."""
    spacing = working_spacing(settings.spacing, boundary) if settings.spacing else {}
    params = reference = None
    if spacing:
        params, reference = classical_grid(boundary, *lattice, "elliptic", spacing)
    if settings.orthogonal:
        heights = {s: h for s, h in spacing.items() if s in settings.orthogonal}
        warm, reference = WarmStart.orthogonal(
            boundary, *lattice, settings.orthogonal, params, heights
        )
        lattice_params = None if warm.nodes is None else np.stack(np.meshgrid(*warm.nodes), -1)
        return warm, reference, None, lattice_params, None
    warm, elliptic = WarmStart.elliptic(boundary, *lattice)
    start = ranking = None
    if settings.objective == "quality" and settings.method == "pinn":
        tfi = elliptic - warm.correction  # the TFI base plus the new start's correction
        ranking = Ranking.of(elliptic, aux, boundary.diagonal)
        with one_blas_thread():  # its L-BFGS, as _lbfgs's
            warm, ranking = quality_start(warm, elliptic, ranking)
        start = tfi + warm.correction
    return warm, elliptic if reference is None else reference, start, params, ranking


def train(
    boundary: Boundary,
    aux: Sequence[AuxLine],
    settings: Settings,
    progress: Callable[[dict], bool | None] | None = None,
) -> TrainedModel:
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
            net = CoordinateNet(
                kind, settings.hidden_layers, settings.neurons, settings.activation
            ).to(device=device, dtype=dtype)
            aux = aux if settings.method == "pinn" else ()
            warm = reference = start = params = ranking = None
            if settings.warm_start == "elliptic":
                lattice = lattice_for(*settings.lattice)
                warm, reference, start, params, ranking = _warm_start(
                    boundary, settings, lattice, aux
                )
                with torch.no_grad():  # the map starts as the warm start's grid
                    net.w_out.zero_()
            mapping = Mapping(net, boundary, settings.boundary_mode, warm)
            steps = first_steps(lattice, params) if warm is not None else None
            problem = _Problem(mapping, boundary, aux, settings, dtype, device, steps, params)
            guard = (
                None
                if reference is None
                else _Guard(
                    net,
                    mapping,
                    reference,
                    bool(aux),
                    start,
                    params,
                    settings.orthogonal,
                    ranking,
                )
            )
            history = _History()
            lambda1 = 1.0 if settings.boundary_mode == "penalty" else 0.0
            lambda1, recoveries = _adam(net, problem, settings, history, lambda1, progress)
            if guard is not None and settings.adam_epochs:
                guard.check(0)  # an Adam phase (not needed from the warm start) is checked too
            lbfgs_ok, lbfgs_iterations = _lbfgs(
                net, problem, settings, history, lambda1, progress, guard
            )
            guarded = guard.restore() if guard is not None else None
    finally:
        torch.set_num_threads(threads)
    info = {
        "adam_epochs": settings.adam_epochs,
        "lbfgs_evaluations": len(history.values.get("total", [])) - settings.adam_epochs,
        "lbfgs_iterations": lbfgs_iterations,
        "lambda1": lambda1,
        "recoveries": recoveries,
        "lbfgs_accepted": lbfgs_ok,
        "device": str(device),
        "final_loss": history.values["total"][-1] if history.values else float("nan"),
    }
    if guarded is not None:
        info["guard"] = guarded
        info["start"] = warm.start
    return TrainedModel(mapping=mapping, settings=settings, history=history.values, info=info)


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
    net, problem: _Problem, s: Settings, history: _History, lambda1: float, progress
) -> tuple[float, int]:
    if s.adam_epochs == 0:
        return lambda1, 0
    opt = _FlatAdam(net, s.learning_rate)
    try:
        return _adam_epochs(net, opt, problem, s, history, lambda1, progress)
    finally:
        opt.release()


def _adam_epochs(
    net, opt: _FlatAdam, problem: _Problem, s: Settings, history: _History, lambda1: float, progress
) -> tuple[float, int]:
    weights = net.weight_matrices()
    best, recoveries, steps = math.inf, 0, 0
    good_state, good_lambda1 = copy.deepcopy(net.state_dict()), lambda1
    for epoch in range(1, s.adam_epochs + 1):
        evaluation = problem.evaluate(problem.epoch_batch(epoch))
        terms = evaluation.terms
        if s.boundary_mode == "penalty" and epoch % ANNEAL_EVERY == 1:
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
        history.add(terms, lambda1, s.lambda2, loss)
        if value < best:
            best = value
            if epoch % 100 == 0:
                good_state, good_lambda1 = copy.deepcopy(net.state_dict()), lambda1
        opt.step(evaluation.gradient())
        steps += 1
        if steps % s.lr_decay_every == 0:  # step decay, as torch's StepLR
            opt.lr *= s.lr_decay
        if epoch % PROGRESS_EVERY == 0 or epoch == s.adam_epochs:
            _notify(progress, "adam", epoch, s.adam_epochs, history)
    return lambda1, recoveries


def _lbfgs(
    net,
    problem: _Problem,
    s: Settings,
    history: _History,
    lambda1: float,
    progress,
    guard: _Guard | None = None,
) -> tuple[bool, int]:
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
        evaluation = problem.evaluate(batch)
        loss = evaluation.loss(lambda1)
        value = loss.item()
        calls[0] += 1
        if not math.isfinite(value):
            return math.inf, np.zeros_like(theta)
        history.add(evaluation.terms, lambda1, s.lambda2, loss)
        grad = evaluation.gradient()
        if calls[0] % 10 == 0:
            _notify(progress, "lbfgs", calls[0], s.lbfgs_iterations, history)
        return value, grad.double().cpu().numpy()

    def each_iteration(xk: np.ndarray) -> None:
        iterations[0] += 1
        if guard is not None and iterations[0] % GUARD_EVERY == 0:
            load(xk)
            if not guard.check(iterations[0]):
                raise StopIteration

    before = history.values["total"][-1] if history.values else math.inf
    theta = torch.cat([p.detach().flatten() for p in params]).double().cpu().numpy()
    with one_blas_thread():
        result = minimize(
            loss_and_grad,
            theta,
            jac=True,
            method="L-BFGS-B",
            callback=each_iteration,
            options={
                "maxiter": s.lbfgs_iterations,
                "maxcor": 50,
                "ftol": 1e-15,
                "gtol": 1e-12,
                "maxfun": int(s.lbfgs_iterations * 1.25) + 1,
            },
        )
    load(result.x)
    final = problem.evaluate(batch).loss(lambda1).item()
    if not math.isfinite(final) or final > before * EXPLODE_FACTOR:
        net.load_state_dict(start_state)
        return False, iterations[0]
    return True, iterations[0]
