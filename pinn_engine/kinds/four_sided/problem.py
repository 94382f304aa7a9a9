"""The four-sided block kind (paper sections 3 and 4): its problem, start and guard.

A four-sided block's map is x(xi, eta) on the unit square (SPEC 1), with the boundary built in
(hard mode: the TFI base plus the start's correction, mapping.py) or trained (penalty mode,
the paper). This module builds what :mod:`pinn_engine.neural.trainer` trains: the sampled
points and loss terms (:class:`QuadProblem`; auxiliary lines, orthogonal sides and the
quality objective are terms here), the start (the converged elliptic grid, the orthogonal
start or the quality objective's start, :mod:`pinn_engine.starts`) and the guard's rule
(:func:`guard_rule`): with the elliptic warm start (the default) L-BFGS runs in rounds of
``trainer.GUARD_EVERY`` iterations, after each the grid on the start's lattice is checked
against the start's reference, and training ends with the last state that was no worse.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence

import numpy as np
import torch

from pinn_engine.classical.spacing import chord_tangents
from pinn_engine.classical.tfi import node_params, tfi_grid
from pinn_engine.classical.warm import WarmStart
from pinn_engine.geometry.auxlines import AuxLine
from pinn_engine.geometry.boundary import SIDES, Boundary
from pinn_engine.geometry.boundary_fit import ArcLengthFit, make_fit
from pinn_engine.kinds.four_sided.mapping import Mapping
from pinn_engine.kinds.four_sided.model import TrainedModel
from pinn_engine.neural.jet.layers import native_jet
from pinn_engine.neural.losses import (
    corner_angles,
    loss_data,
    loss_eqns,
    loss_orthogonal,
    loss_points,
    loss_quality,
    total_loss,
)
from pinn_engine.neural.networks import CoordinateNet
from pinn_engine.neural.session import DTYPES, GuardRule, train_network
from pinn_engine.neural.trainer import (
    AutogradEvaluation,
    Progress,
)
from pinn_engine.quality import guard_figures, no_worse, orientation, side_report
from pinn_engine.settings import Settings
from pinn_engine.starts.quad_start import quad_start
from pinn_engine.starts.quality_start import Ranking
from pinn_engine.starts.untangle import acceptable, untangled_report
from pinn_engine.starts.warmstart import lattice_for

# A state is kept if its grid has no more folded cells than the elliptic grid and mean and
# worst MaxIncludedAngle within (mean, worst) degrees of it: half the hard shapes' acceptance
# bounds (0.5, 2), a margin because the guard checks the lattice and the output may differ;
# the same with auxiliary lines or without.
GUARD_TOL = (0.25, 1.0)
GUARD_WALL_ANGLE = 1.0  # degrees off 90 that the guard allows at orthogonal sides (SPEC 7: 2)
# points per orthogonal side in the orthogonality term (SPEC 7): five per cell at 41 nodes,
# more than one per cell up to 201 (the guard checks the wall angle at every node anyway)
WALL_POINTS = 200
# --objective quality: weight of the cell-quality term (losses.loss_quality) beside the Winslow
# term (the objective's start and its order of grids: quality_start.py); 1: both are means of
# order one per point, and the guard's ranking, not the weight, decides what is kept
QUALITY_WEIGHT = 1.0
# L-BFGS's fixed batch has a quarter as many points a side as inside: the four sides
# together as many as the interior (penalty mode)
SIDE_SHARE = 4


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


class QuadProblem:
    """Sampled points and targets for one boundary, as tensors on the training device.

    Random points are drawn ``CHUNK`` epochs at a time, with the boundary-fit targets and (hard
    mode) the TFI jets computed once per chunk, so an epoch only slices ready tensors.
    """

    CHUNK = 500  # Adam epochs of points drawn at once (one draw costs about an epoch)

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
        self.mapping, self.settings, self.net = mapping, settings, mapping.net
        self.dtype, self.device = dtype, device
        penalty = settings.boundary_mode == "penalty"
        self.anneals = penalty  # lambda1 is annealed only with a boundary term to weigh
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
        if settings.quality_objective and self.hard:
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

    def lbfgs_batch(self) -> tuple:
        """L-BFGS's fixed batch: ``lbfgs_points`` interior points, a quarter as many a side."""
        n = self.settings.lbfgs_points
        return self.sample(n, max(n // SIDE_SHARE, 1))

    def weights(self, lambda1: float) -> dict[str, float]:
        """The weights of the boundary and auxiliary-line terms, for the history."""
        return {"bcs": lambda1, "data": self.settings.lambda2}

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

    def evaluate(self, batch: tuple) -> AutogradEvaluation:
        """The loss terms at ``batch`` (from :meth:`sample` or :meth:`epoch_batch`), with
        their gradients on demand."""
        return (AutogradEvaluation if self.fused is None else _FusedEvaluation)(self, batch)


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


class _FusedEvaluation(AutogradEvaluation):
    """The same for penalty mode with the paper's residual and no orthogonality or quality
    term (the paper preset), through :class:`_FusedLoss`; the loss's gradient is the terms'
    weighted sum."""

    def __init__(self, problem: QuadProblem, batch: tuple) -> None:
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


def guard_rule(
    reference: np.ndarray,
    start: np.ndarray | None = None,
    walls: tuple[str, ...] = (),
    ranking: Ranking | None = None,
    winslow: np.ndarray | None = None,
) -> tuple[Callable[[np.ndarray], dict], Callable[[dict, dict], bool], dict, dict]:
    """The four-sided block's guard against the start's ``reference`` grid: (figures of a
    grid, whether figures pass given the kept ones, the figures to start from, the
    reference's figures).

    A state passes if its grid has no more folded cells than the reference and mean and worst
    MaxIncludedAngle within ``GUARD_TOL`` of it. Under ``--objective quality`` (``start`` is
    the start grid) a state passes if it ranks better than the kept one by ``ranking``
    (quality_start.py: a mean less above the bound, raised to ``reference``'s if that is
    higher, then fewer folded cells, then closer to the auxiliary lines, and never further
    from them than ``start``, then a smaller worst angle). With orthogonal ``walls`` (SPEC 7)
    a state also passes only if its grid lines leave them within ``GUARD_WALL_ANGLE`` degrees
    of 90, or no farther off than the reference's. With the ``winslow`` grid that the
    reference untangles (untangle.py), a state passes only if it keeps as close to it as
    the untangled grid must (``untangle.acceptable``)."""
    mean_tol, worst_tol = GUARD_TOL
    if ranking is not None:
        ranking = ranking.against(reference).holding(start)
    quality = guard_figures if ranking is None else ranking.quality

    def figures(grid: np.ndarray) -> dict:
        q = quality(grid)
        if winslow is not None:
            q["close_to_winslow"] = acceptable(grid, winslow)
        if walls:
            report = side_report(grid)
            q["wall_angle"] = max(report[side]["max_angle_deviation"] for side in walls)
        return q

    ref = figures(reference)
    wall_tol = max(GUARD_WALL_ANGLE, ref.get("wall_angle", 0.0))

    def accept(q: dict, kept: dict) -> bool:
        if ranking is not None:
            ok = ranking.key(q) < ranking.key(kept)
        else:
            ok = no_worse(q, ref, mean_tol, worst_tol)
        close = q.get("close_to_winslow", True)
        return ok and close and q.get("wall_angle", 0.0) <= wall_tol

    return figures, accept, ref if ranking is None else figures(start), ref


def network(settings: Settings, dtype: torch.dtype, device: torch.device) -> CoordinateNet:
    """The four-sided block's network: the shortcut network for pinn, a plain MLP for mgnet."""
    kind = "shortcut" if settings.method == "pinn" else "mlp"
    net = CoordinateNet(kind, settings.hidden_layers, settings.neurons, settings.activation)
    return net.to(device=device, dtype=dtype)


def train(
    boundary: Boundary,
    aux: Sequence[AuxLine],
    settings: Settings,
    progress: Progress | None = None,
) -> TrainedModel:
    """Train the networks for ``boundary`` (working frame) and return the trained model."""
    aux = aux if settings.method == "pinn" else ()
    warm_start = settings.warm_start == "elliptic"
    lattice = lattice_for(*settings.lattice)
    built: dict = {}

    began = time.perf_counter()

    def problem(net, dtype, device) -> tuple[QuadProblem, GuardRule | None]:
        began_start = time.perf_counter()
        begin = quad_start(boundary, settings, lattice, aux) if warm_start else None
        built["start_seconds"] = time.perf_counter() - began_start
        warm = None if begin is None else begin.warm
        params = None if begin is None else begin.params
        mapping = Mapping(net, boundary, settings.boundary_mode, warm)
        steps = first_steps(lattice, params) if warm is not None else None
        quad = QuadProblem(mapping, boundary, aux, settings, dtype, device, steps, params)
        built.update(begin=begin, mapping=mapping)
        if begin is None:
            return quad, None
        reference = begin.reference
        size = reference.shape[1], reference.shape[0]
        figures, accept, kept, ref = guard_rule(
            reference, begin.start, settings.orthogonal, begin.ranking, begin.winslow
        )
        built.update(size=size, ref=ref)
        grid = lambda: mapping.grid(*size, params=params)  # noqa: E731
        return quad, GuardRule(grid, figures, accept, kept, boundary.diagonal)

    lambda1 = 1.0 if settings.boundary_mode == "penalty" else 0.0
    training = train_network(
        settings,
        lambda dtype, device: network(settings, dtype, device),
        problem,
        progress,
        zero_output=warm_start,
        lambda1=lambda1,
    )
    info, begin = training.info, built["begin"]
    info["device"] = str(training.device)
    start_seconds = built["start_seconds"]
    training_seconds = time.perf_counter() - began - start_seconds
    info["timings"] = {"start": start_seconds, "training": training_seconds}
    if begin is not None:
        info["guard"].update(lattice=list(built["size"]), elliptic=built["ref"])
        info["start"] = begin.warm.start
        if begin.winslow is not None:
            info["untangled"] = untangled_report(begin.winslow, begin.reference)
    return TrainedModel(
        mapping=built["mapping"], settings=settings, history=training.history, info=info
    )


def untrained_model(
    boundary: Boundary, warm: WarmStart, settings: Settings, info: dict
) -> TrainedModel:
    """The trained model a start equals (untrained.StartModel): the seeded network with its
    output layer at zero on the ``warm`` start, to save and load as any trained model."""
    torch.manual_seed(settings.seed)
    net = network(settings, DTYPES[settings.dtype], torch.device("cpu"))
    with torch.no_grad():
        net.w_out.zero_()
    mapping = Mapping(net, boundary, "hard", warm)
    return TrainedModel(mapping=mapping, settings=settings, history={}, info=info)
