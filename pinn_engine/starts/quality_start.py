"""The start of ``--objective quality`` (docs/quality_objective.md): the cell-quality
objective's discrete solution on the lattice, following the auxiliary lines.

Grids on the lattice are ranked (:class:`Ranking`) by how far their mean ``MaxIncludedAngle``
is above that of the converged elliptic grid (or, with auxiliary lines, of the elliptic grid
moved onto them, if larger) plus ``MEAN_TOL``, then by folded cells, then by how far they miss
the auxiliary lines (beyond what the boundary nodes fix), then by the worst
``MaxIncludedAngle``.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Sequence
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine import lbfgs
from pinn_engine.classical.elliptic import stencil_matrix
from pinn_engine.classical.warm import WarmStart
from pinn_engine.geometry.auxlines import AuxLine, crossing_nodes, crossing_turns, line_distances
from pinn_engine.quality import (
    DBL_MIN,
    QUALITY_BARRIER_WEIGHT,
    QUALITY_MEAN_WEIGHT,
    QUALITY_MIN_SINE,
    QUALITY_TAU,
    START_MEAN_TOL,
    folded_cells,
    guard_figures,
    orientation,
    shortest_edges,
    worst_non_orthogonality,
)
from pinn_engine.starts.untangle import untangle

if TYPE_CHECKING:  # SciPy is imported where a function uses it: a body's node optimisation
    import scipy.sparse as sp  # runs on NumPy alone (lbfgs)

MEAN_TOL = START_MEAN_TOL  # the objective's bound on the mean against the elliptic grid
# The grid lines crossing an auxiliary line may turn there by this many degrees (mean over
# them) more than the elliptic grid's do at the same nodes: a grid that follows the line with
# crossing lines as smooth as the elliptic grid's (a split-block grid whose interface is the
# line kinks them by 8.7 and 7.9 degrees mean on wavy and fig2; auxlines.crossing_turns)
TURN_TOL = 2.0
TURN_STEP = 0.01  # the ranking's step of the crossing turn, degrees
NODE_ITERATIONS = 100  # L-BFGS iterations of a body's node optimisation
# A four-sided block's node optimisation sharpens its soft maximum in stages: temperatures in
# QUALITY_TAU's. At 1 degree alone a band of near-worst corners shares the weight and L-BFGS
# settles 2 to 4 degrees above the stages' end (300 iterations: the dart at 41 x 21 147.4,
# the S-duct at 81 x 41 154.2; the stages 143.4 and 152.2, at no more CPU: STAGE_ITERATIONS).
SHARPENING = (1.0, 1 / 2, 1 / 4, 1 / 8)
# A stage's iterations at most (0: no node optimisation, an ablation): the stages then cost
# the CPU one stage of 100 cost on the tuning set at 81 x 41; and a stage ends after
# STAGE_STALL iterations without a better-ranked state (a grid at its floor stops at once;
# 10 ended the S-duct's first stage early: 154.9 at 81 x 41 against 149.6 with 20)
STAGE_ITERATIONS = 67
STAGE_STALL = 20
# A body grid's node optimisation stops after this many iterations without a better-ranked
# state (NACA 0012 at 41x21: the C-grid's best at 20 of its 100 iterations, the O-grid's at 60)
BODY_STALL = 10
# A grid follows the auxiliary lines when it misses them by at most LINE_TOL (of the
# diagonal) more than the boundary nodes fix: half the 2e-3 at which a grid line counts as
# on its drawn line, so that grids within it are ranked by their cells, not by a closeness
# nobody asked (tighter, the ranking trades the worst cell for 1e-5 steps of distance)
LINE_TOL = 1e-3
# the line term's weight in the node optimisation (squared distance in units of the
# lattice's median shortest edge)
LINE_WEIGHT = 100.0
# The crossing-turn term's weight in the node optimisation (its squared mean excess in
# radians): a degree beyond its aim costs 0.03, as about two degrees of the worst angle do in
# the soft maximum (tau 0.0175 rad); and its aim, this much above the elliptic grid's turn:
# half the ranking's bound, so that grids well within it are left to the quality terms and
# the optimisation keeps inside it (aimed at the bound itself, it ends just beyond)
TURN_WEIGHT = 100.0
TURN_AIM = TURN_TOL / 2
PULL_ROUNDS = 15  # rounds of pull_onto_lines at most
PULL_WEIGHT = 1e5  # of the lines against the smoothness of the pull's moves (more: folds)
# A row slid to where it meets a line (slide_to_crossings) changes a cell's width along it by
# at most this share, the move fading out over four times its size: tuned on the tuning
# shapes with default_choice.py's drawn line, 1 of 24 grids left beyond 2e-3 of the
# diagonal (0.5: 2; 1, the move spread over the whole row, 4: it folds a concave corner's rows)
SLIDE_STRETCH = 0.25
RELAX_ITERATIONS = 10  # Winslow iterations of relax_on_lines
RELAX_WEIGHT = 10.0  # of the lines against the Winslow equations there (more: folds)
# The blends of the start (:func:`quality_start`): elliptic + w (TFI - elliptic) for w in
# 0.1 .. 0.9, a tenth apart: the ranking's figures change little within a tenth (TFI has the
# lower worst angle at sharp notches, the elliptic grid the lower mean), and nine grids cost
# nine evaluations of the figures, a small part of the start.
BLEND_WEIGHTS = np.arange(1, 10) / 10
# The ranking's steps (:meth:`Ranking.key`): the mean to 0.01 degrees and the line distance
# to 1e-5 of the diagonal (a step is a difference that matters; smaller ones, of the same
# grid solved twice, must not decide), the worst angle to 0.001 degrees; and the slack of the
# rounding up (a value at the bound to rounding error is at it).
MEAN_STEP = 0.01
LINE_STEP = 1e-5
WORST_DECIMALS = 3
STEP_SLACK = 1e-9
# The pull's step is halved after a round that does not bring the grid closer or folds; it
# gives up below 1/8 (three halvings: a smaller step does not move the grid visibly).
PULL_MIN_STEP = 0.125
# A Jacobian is singular (a degenerate cell at a corner) when its determinant is below this
# share of its squared size (float64's noise on the products, with a margin).
SINGULAR_SHARE = 1e-12
# L-BFGS of the node optimisation: the history kept (10 pairs, scipy's default), at most
# three evaluations an iteration (line searches), tolerances below float64's noise (the
# iterations stop it, and it keeps the best-ranked state it met).
NODE_LBFGS = {"maxcor": 10, "ftol": 1e-15, "gtol": 1e-12}
NODE_EVALUATIONS = 3
FOLDED_ANGLE = 180.0  # degrees: a corner above it is reflex, its cell folded (quality.py)


@dataclass(frozen=True)
class Settle:
    """When a node optimisation has settled, and the state it returns (:func:`optimize_nodes`):
    its last ``window`` iterations left the best-ranked state's ranking above its worst angle
    and lowered that by less than ``worst`` degrees, or that state ranks as none can rank
    better (within every bound but the worst angle, and that at the corners no move of its
    free nodes changes: a four-sided domain's corners); it returns, of the states ranked as
    the best but for their worst angle within ``spare`` degrees of its, the one of least
    mean (a worst angle stuck at a boundary corner leaves every state tied, and the first
    met is the best ranked); none ranked below the state it started from."""

    window: int
    worst: float
    spare: float


@dataclass(frozen=True)
class Ranking:
    """The order of grids on a lattice under ``--objective quality`` (:meth:`key`), with the
    auxiliary lines (working frame) they are to follow within ``line_tol`` of the boundary's
    ``diagonal``, and the bound on their mean ``MaxIncludedAngle``."""

    mean_bound: float
    lines: tuple[AuxLine, ...] = ()
    diagonal: float = 1.0
    line_tol: float = 0.0
    turns: tuple[float, ...] = ()  # the elliptic grid's crossing turn at each line

    @classmethod
    def of(cls, elliptic: np.ndarray, aux: Sequence[AuxLine], diagonal: float) -> Ranking:
        """The ranking of grids with the boundary nodes of the converged ``elliptic`` grid:
        the mean bound is its mean plus ``MEAN_TOL``, and the lines count as followed within
        ``LINE_TOL`` of the distance of their samples on the boundary (which no interior node
        changes)."""
        ends = [
            replace(a, xi_eta=a.xi_eta[((a.xi_eta == 0) | (a.xi_eta == 1)).any(1)]) for a in aux
        ]
        ends = [e for e in ends if len(e.xi_eta)]
        floor = max(line_distances(elliptic, ends, diagonal).values(), default=0.0)
        turns = tuple(_turns(elliptic, aux))
        return cls(-math.inf, tuple(aux), diagonal, floor + LINE_TOL, turns).against(elliptic)

    def against(self, elliptic: np.ndarray) -> Ranking:
        """This ranking with the mean bound raised to ``MEAN_TOL`` above another elliptic
        grid's mean, if that is higher."""
        bound = guard_figures(elliptic)["mean_max_angle"] + MEAN_TOL
        return replace(self, mean_bound=max(self.mean_bound, bound))

    def quality(self, grid: np.ndarray) -> dict[str, float]:
        """:func:`quality.guard_figures`, and with lines the largest distance of the grid's curves
        through them from the drawn lines (``auxlines.line_distances``)."""
        q = guard_figures(grid)
        if self.lines:
            q["aux_distance"] = max(line_distances(grid, list(self.lines), self.diagonal).values())
            q["aux_turn"] = max(
                t - e for t, e in zip(_turns(grid, self.lines), self.turns, strict=True)
            )
        return q

    def holding(self, grid: np.ndarray) -> Ranking:
        """This ranking with the lines' tolerance no more than ``grid``'s distance from them:
        a grid further from them than ``grid`` ranks below it."""
        if not self.lines:
            return self
        return replace(self, line_tol=min(self.line_tol, self.quality(grid)["aux_distance"]))

    def key(self, q: dict[str, float]) -> tuple[float, int, float, float, float]:
        """A mean less above the bound (in steps of 0.01 degrees), then fewer folded cells,
        then a smaller distance from the lines beyond ``line_tol`` (in steps of 1e-5 of the
        diagonal), then crossing lines turning less at them beyond ``TURN_TOL`` more than
        the elliptic grid's (0.01 degrees), then a smaller worst angle (to 0.001 degrees)."""
        return (
            _steps_above(q["mean_max_angle"], self.mean_bound, MEAN_STEP),
            q["folded_cells"],
            _steps_above(q.get("aux_distance", 0.0), self.line_tol, LINE_STEP),
            _steps_above(q.get("aux_turn", 0.0), TURN_TOL, TURN_STEP),
            round(q["worst_max_angle"], WORST_DECIMALS),
        )


def _turns(grid: np.ndarray, lines: Sequence[AuxLine]) -> list[float]:
    """``auxlines.crossing_turns`` of each line, in order (names may repeat)."""
    return [crossing_turns(grid, [line])[line.name] for line in lines]


def _steps_above(value: float, bound: float, step: float) -> float:
    """How far ``value`` is above ``bound``, rounded up to whole ``step`` (0 at or below)."""
    return math.ceil(max(0.0, value - bound) / step - STEP_SLACK) * step


def quality_start(
    warm: WarmStart, elliptic: np.ndarray, ranking: Ranking
) -> tuple[WarmStart, Ranking]:
    """The best (``ranking``) of the elliptic grid, the TFI grid (``warm``'s base: a polar
    grid on an annulus sector, say), blends of them, the elliptic grid untangled where it
    folds (untangle.py), with auxiliary lines the elliptic grid (and the untangled one)
    moved onto them (:func:`follow_lines`), and the best of these with its interior nodes
    optimised (:func:`optimize_nodes`): the objective's discrete solution, as the converged
    elliptic grid is the Winslow objective's. Where that grid's crossing lines turn beyond
    the ranking's bound, the elliptic grid on the lines is optimised too: it turns as the
    elliptic grid does, and the optimisation removes its folds (its barrier), where from a
    fold-free start whose lines fan out round a notch's tip it keeps the fan. Also returns
    the ranking, its mean bound raised to the elliptic grid on the lines'."""
    tfi = elliptic - warm.correction
    found, ranking = candidates(elliptic, tfi, ranking)
    best = min(found, key=lambda c: ranking.key(ranking.quality(c[0])))
    if STAGE_ITERATIONS:
        optimized = (sharpened(best[0], ranking), "optimized")
        turning = ranking.key(ranking.quality(optimized[0]))[3] > 0
        if turning and best[1] != "line-following elliptic":
            on_lines = next(g for g, name in found if name == "line-following elliptic")
            again = (sharpened(on_lines, ranking), "optimized")
            optimized = min([optimized, again], key=lambda c: ranking.key(ranking.quality(c[0])))
        best = min([best, optimized], key=lambda c: ranking.key(ranking.quality(c[0])))
    return WarmStart(best[0] - tfi, start=best[1]), ranking


def sharpened(
    grid: np.ndarray,
    ranking: Ranking,
    iterations: int = STAGE_ITERATIONS,
    settle: Settle | None = None,
    shares: Sequence[float] = SHARPENING,
    leap: bool = False,
) -> np.ndarray:
    """``grid`` with its interior nodes optimised (:func:`optimize_nodes`) in stages whose
    soft maximum sharpens (temperatures ``shares`` of ``QUALITY_TAU``), each from the
    best-ranked state of the one before: a blunt soft maximum moves the whole band of
    near-worst cells, a sharp one then the few that bind. Each stage runs at most
    ``iterations``, and stops after ``STAGE_STALL`` without a better-ranked state or, given
    ``settle``, once settled (a family model's polish); with ``leap``, a stage that settled
    is followed by the last alone (its band of near-worst cells has moved together), and
    the stages between follow one that ran out of iterations. No stage ranks below its
    start; only the first moves the grid onto the auxiliary lines (:func:`follow_lines`),
    the others go on from where it ended."""
    stage, outcome = 0, {}
    while stage < len(shares):
        grid = optimize_nodes(
            grid,
            ranking,
            iterations,
            stall=None if settle else STAGE_STALL,
            settle=settle,
            tau=shares[stage] * QUALITY_TAU,
            follow=stage == 0,
            outcome=outcome,
        )
        last = len(shares) - 1
        stage = max(stage + 1, last) if leap and outcome.get("settled") else stage + 1
    return grid


def best_candidate(
    elliptic: np.ndarray, tfi: np.ndarray, ranking: Ranking
) -> tuple[tuple[np.ndarray, str], Ranking]:
    """The best (``ranking``) of the grids :func:`quality_start` optimises from
    (:func:`candidates`), with its name, and the ranking, its mean bound raised to the
    elliptic grid on the lines'."""
    found, ranking = candidates(elliptic, tfi, ranking)
    return min(found, key=lambda c: ranking.key(ranking.quality(c[0]))), ranking


def candidates(
    elliptic: np.ndarray, tfi: np.ndarray, ranking: Ranking
) -> tuple[list[tuple[np.ndarray, str]], Ranking]:
    """The grids :func:`quality_start` optimises from, each with its name: the elliptic grid,
    the TFI grid, blends of them, the elliptic grid untangled where it folds, with auxiliary
    lines these moved onto them; and the ranking, its mean bound raised to the elliptic grid
    on the lines'."""
    found = [(elliptic, "elliptic"), (tfi, "tfi")] + [
        (elliptic + w * (tfi - elliptic), f"{w:.1f} tfi + elliptic") for w in BLEND_WEIGHTS
    ]
    untangled = untangle(elliptic)
    if untangled is not elliptic:
        found.append((untangled, "untangled"))
    if ranking.lines:
        on_lines = follow_lines(elliptic, ranking)
        ranking = ranking.against(on_lines)
        found.append((on_lines, "line-following elliptic"))
        if untangled is not elliptic:  # the fold-free grid on the lines
            found.append((follow_lines(untangled, ranking), "line-following untangled"))
    return found, ranking


def body_quality_start(
    elliptic: np.ndarray, seam: bool, held: int, begin: np.ndarray | None = None
) -> tuple[np.ndarray, str]:
    """The better ranked (no lines) of a body's (O- or C-grid's) elliptic grid and that grid
    with its nodes optimised (:func:`optimize_nodes` by NumPy's L-BFGS: a body's route
    imports no SciPy), its first ``held`` rows (the wall's, the first layer's and any
    boundary layer's: ``kinds.body.untrained.held_rows``) kept, with its name; ``seam``: an
    O-grid's (column ni - 1 is column 0); ``begin``: the grid the optimisation starts from
    instead (a family model's, on the same wall, first layer and far field)."""
    ranking = Ranking.of(elliptic, [], 1.0)
    begin = elliptic if begin is None else begin
    optimized = optimize_nodes(
        begin, ranking, NODE_ITERATIONS, held, seam, BODY_STALL, numpy_lbfgs=True
    )
    if worst_non_orthogonality(optimized) > worst_non_orthogonality(elliptic):
        return elliptic, "elliptic"  # less orthogonal where a solver's faces meet
    candidates = [(elliptic, "elliptic"), (optimized, "optimized")]
    return min(candidates, key=lambda c: ranking.key(ranking.quality(c[0])))


class _Samples:
    """The bilinear interpolation of grids (nj, ni, 2) at computational points (n, 2) (the
    grid's curve through an auxiliary line's (xi, eta), as ``line_distances`` evaluates it)."""

    def __init__(self, xi_eta: np.ndarray, ni: int, nj: int) -> None:
        u, v = xi_eta[:, 0] * (ni - 1), xi_eta[:, 1] * (nj - 1)
        i = np.clip(np.floor(u).astype(int), 0, ni - 2)
        j = np.clip(np.floor(v).astype(int), 0, nj - 2)
        a, b = u - i, v - j
        self.size = ni, nj
        corners = ((j, i), (j, i + 1), (j + 1, i + 1), (j + 1, i))
        self.index = np.stack([jj * ni + ii for jj, ii in corners], axis=1)  # (n, 4) flat
        self.weight = np.stack([(1 - a) * (1 - b), a * (1 - b), a * b, (1 - a) * b], axis=1)
        self.a, self.b = a[:, None], b[:, None]

    def at(self, grid: np.ndarray) -> np.ndarray:
        """The grid's values at the points, (n, 2)."""
        return (grid.reshape(-1, 2)[self.index] * self.weight[..., None]).sum(1)

    def jacobian(self, grid: np.ndarray) -> np.ndarray:
        """d(x, y) / d(xi, eta) of the grid's bilinear map at the points, (n, 2, 2)."""
        c = grid.reshape(-1, 2)[self.index]  # (n, 4, 2)
        ni, nj = self.size
        d_xi = ((1 - self.b) * (c[:, 1] - c[:, 0]) + self.b * (c[:, 2] - c[:, 3])) * (ni - 1)
        d_eta = ((1 - self.a) * (c[:, 3] - c[:, 0]) + self.a * (c[:, 2] - c[:, 1])) * (nj - 1)
        return np.stack([d_xi, d_eta], axis=-1)

    def matrix(self) -> sp.csr_matrix:
        """The interpolation as a sparse (n, ni nj) matrix on the flattened nodes."""
        import scipy.sparse as sp

        rows = np.repeat(np.arange(len(self.index)), 4)
        return sp.csr_matrix(
            (self.weight.ravel(), (rows, self.index.ravel())),
            shape=(len(self.index), self.size[0] * self.size[1]),
        )


def _curves(ranking: Ranking, ni: int, nj: int) -> list[tuple[_Samples, np.ndarray]]:
    """The samples of an ni x nj grid's curves through the ranking's auxiliary lines, each
    with its drawn line."""
    return [(_Samples(a.xi_eta, ni, nj), a.xy) for a in ranking.lines]


def _picks(curves: list[tuple[_Samples, np.ndarray]]) -> sp.csr_matrix:
    """The curves' samples as one sparse matrix on the flattened nodes."""
    import scipy.sparse as sp

    return sp.vstack([samples.matrix() for samples, _ in curves]).tocsr()


def _smoothing(ni: int, nj: int) -> sp.csr_matrix:
    """The squared 5-point Laplacian on the interior nodes of an ni x nj lattice (boundary
    values zero): the roughness of a displacement field."""
    import scipy.sparse as sp

    def second_difference(n: int) -> sp.spmatrix:
        return sp.diags([-np.ones(n - 1), 2 * np.ones(n), -np.ones(n - 1)], [-1, 0, 1])

    laplacian = sp.kron(sp.identity(nj), second_difference(ni)) + sp.kron(
        second_difference(nj), sp.identity(ni)
    )
    inner = _interior(ni, nj)
    laplacian = laplacian.tocsr()[inner][:, inner]
    return (laplacian.T @ laplacian).tocsr()


def _inverse_times(jac: np.ndarray, v: np.ndarray) -> np.ndarray:
    """``jac^-1 v`` for (n, 2, 2) and (n, 2); zero where ``jac`` is singular (a degenerate
    cell at a corner)."""
    det = jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]
    adj_v = np.stack(
        [
            jac[:, 1, 1] * v[:, 0] - jac[:, 0, 1] * v[:, 1],
            jac[:, 0, 0] * v[:, 1] - jac[:, 1, 0] * v[:, 0],
        ],
        axis=-1,
    )
    scale = np.einsum("nij,nij->n", jac, jac)
    ok = np.abs(det) > SINGULAR_SHARE * scale
    return np.where(ok[:, None], adj_v / np.where(ok, det, 1.0)[:, None], 0.0)


def _interior(ni: int, nj: int) -> np.ndarray:
    """Flat indices of the interior nodes of an ni x nj lattice."""
    return (np.arange(1, nj - 1)[:, None] * ni + np.arange(1, ni - 1)).ravel()


def follow_lines(grid: np.ndarray, ranking: Ranking) -> np.ndarray:
    """``grid`` moved onto the auxiliary lines: its nodes slid along the grid lines that cross
    them (:func:`slide_onto_lines`), which keeps those lines as smooth as ``grid``'s; where
    that does not reach them (a move too large for its smooth field to make without a fold),
    also slid first each row at once to where it meets them (:func:`slide_to_crossings`),
    then as before, and the closer of the two kept; where neither reaches them, that one
    pulled (:func:`pull_onto_lines`), relaxed as an elliptic grid that keeps to them
    (:func:`relax_on_lines`), pulled again."""
    slid = slide_onto_lines(grid, ranking)
    if ranking.quality(slid)["aux_distance"] <= ranking.line_tol:
        return slid
    crossed = slide_onto_lines(slide_to_crossings(grid, ranking), ranking)
    slid = min([slid, crossed], key=lambda g: ranking.quality(g)["aux_distance"])
    if ranking.quality(slid)["aux_distance"] <= ranking.line_tol:
        return slid
    pulled = pull_onto_lines(slid, ranking)
    return pull_onto_lines(relax_on_lines(pulled, ranking), ranking)


def slide_onto_lines(grid: np.ndarray, ranking: Ranking) -> np.ndarray:
    """``grid`` with its interior nodes slid along the grid lines that cross the auxiliary
    lines (rows for a line from bottom to top, columns for one from left to right) until the
    grid line through each drawn line's (xi, eta) lies on it: each round moves every curve
    sample, along its crossing grid line, to where that meets the drawn line (a move of xi
    alone, or of eta), and the smoothest field of such moves over the nodes (least squares,
    the squared Laplacian, each direction on its own lines' samples only) moves every node
    within the old grid, in up to ``PULL_ROUNDS`` rounds, halving a step that folds or comes
    no closer. The crossing grid lines keep their shape; their nodes only move along them."""
    from scipy.sparse.linalg import splu

    nj, ni = grid.shape[:2]
    curves = _curves(ranking, ni, nj)
    inner = _interior(ni, nj)
    axes = [0 if line.sides is None or line.sides[0] == "bottom" else 1 for line in ranking.lines]
    smooth = (ni - 1) * (nj - 1) * _smoothing(ni, nj)
    solvers = []
    for axis in (0, 1):
        mine = [c for c, a in zip(curves, axes, strict=True) if a == axis]
        if not mine:
            solvers.append(None)
            continue
        picks = _picks(mine)[:, inner]
        weight = PULL_WEIGHT / picks.shape[0]
        solve = splu((smooth + weight * picks.T @ picks).tocsc()).solve
        solvers.append((solve, weight * picks.T, [curves.index(c) for c in mine]))

    def smoothest(moves: list[np.ndarray]) -> np.ndarray:
        field = np.zeros((len(inner), 2))
        for axis, solver in enumerate(solvers):
            if solver is not None:
                solve, spread, which = solver
                field[:, axis] = solve(spread @ np.concatenate([moves[k] for k in which]))
        return field

    return _pulled(grid, ranking, lambda g, step: _slide_round(g, curves, axes, smoothest, step))


def _pulled(
    grid: np.ndarray, ranking: Ranking, move: Callable[[np.ndarray, float], np.ndarray]
) -> np.ndarray:
    """``grid`` moved by ``move(grid, step)`` in up to ``PULL_ROUNDS`` rounds while it is
    further from the lines than the ranking's tolerance, halving a step that folds more or
    comes no closer (down to ``PULL_MIN_STEP``)."""
    q, step = ranking.quality(grid), 1.0
    for _ in range(PULL_ROUNDS):
        if q["aux_distance"] <= ranking.line_tol or step < PULL_MIN_STEP:
            break
        moved = move(grid, step)
        q_moved = ranking.quality(moved)
        if (
            q_moved["folded_cells"] > q["folded_cells"]
            or q_moved["aux_distance"] >= q["aux_distance"]
        ):
            step /= 2
            continue
        grid, q = moved, q_moved
    return grid


def _slide_round(grid: np.ndarray, curves: list, axes: list, smoothest, step: float):
    """One round of :func:`slide_onto_lines`: each curve sample's move of xi (``axes`` 0) or
    eta (1) along its crossing grid line to the drawn line, to first order (the move along
    the line's tangent direction r_xi or r_eta that covers the miss towards the nearest
    point), turned by ``smoothest`` into the nodes' moves."""
    nj, ni = grid.shape[:2]
    moves = []
    for (samples, xy), axis in zip(curves, axes, strict=True):
        at = samples.at(grid)
        miss = _nearest(at, xy) - at
        along = samples.jacobian(grid)[:, :, axis]  # d(x, y)/d(xi or eta)
        squared, towards = (miss * miss).sum(-1), (miss * along).sum(-1)
        ok = np.abs(towards) > SINGULAR_SHARE * (along * along).sum(-1)
        moves.append(np.where(ok, squared / np.where(ok, towards, 1.0), 0.0))
    params = np.stack(np.meshgrid(np.linspace(0, 1, ni), np.linspace(0, 1, nj)), axis=-1)
    inner = _interior(ni, nj)
    params = np.clip(params.reshape(-1, 2)[inner] + step * smoothest(moves), 0, 1)
    out = grid.reshape(-1, 2).copy()
    out[inner] = _Samples(params, ni, nj).at(grid)
    return out.reshape(grid.shape)


def slide_to_crossings(grid: np.ndarray, ranking: Ranking) -> np.ndarray:
    """``grid`` with its interior nodes slid along the grid lines that cross the auxiliary
    lines (rows for a line from bottom to top, columns for one from left to right) until the
    grid line through each drawn line's (xi, eta) lies on it: each row re-sampled so that its
    node parameter at the line's xi moves to where the row meets the drawn line
    (:func:`_slide_rows`), the rows for the lines from bottom to top, then the columns for
    those from left to right, in up to ``PULL_ROUNDS`` rounds while the grid is further from
    the lines than the ranking's tolerance, halving a step that folds or comes no closer. The
    crossing grid lines keep their shape to the chords between their nodes: their nodes move
    along them, linear between the nodes."""
    vertical = [line.sides is None or line.sides[0] == "bottom" for line in ranking.lines]
    rows = [line for line, v in zip(ranking.lines, vertical, strict=True) if v]
    columns = [  # a line from left to right is one from bottom to top of the transposed grid
        replace(line, xi_eta=line.xi_eta[:, ::-1])
        for line, v in zip(ranking.lines, vertical, strict=True)
        if not v
    ]

    def move(grid: np.ndarray, step: float) -> np.ndarray:
        moved = _slide_rows(grid, rows, step) if rows else grid
        if columns:
            moved = _slide_rows(moved.transpose(1, 0, 2), columns, step).transpose(1, 0, 2)
        return moved

    return _pulled(grid, ranking, move)


def _slide_rows(grid: np.ndarray, lines: Sequence[AuxLine], step: float) -> np.ndarray:
    """``grid`` (nj, ni, 2) with each interior row's nodes moved along the row (linear
    between its nodes) so that the row's node parameter at each line's xi (the lines from
    bottom to top) moves ``step`` of the way to where the row meets the drawn line (of its
    meetings, the nearest). The move of the parameter is piecewise linear along the row: the
    full move at the line, none from the line's largest move divided by ``SLIDE_STRETCH`` on
    either side of it (or from the next line), so that no cell's width along its row changes
    by more than that share, and cells away from the line stay."""
    nj, ni = grid.shape[:2]
    centre = np.full((len(lines), nj), np.nan)  # the line's node parameter on each row
    target = np.full((len(lines), nj), np.nan)  # where it is to move
    for k, line in enumerate(lines):
        order = np.argsort(line.xi_eta[:, 1])
        eta, xi = line.xi_eta[order, 1], line.xi_eta[order, 0]
        for j in range(1, nj - 1):
            at = np.interp(j / (nj - 1), eta, xi) * (ni - 1)
            meets = _meetings(grid[j], line.xy)
            if len(meets):
                centre[k, j] = at
                target[k, j] = at + step * (meets[np.argmin(np.abs(meets - at))] - at)
    reach = np.nanmax(np.abs(target - centre), axis=1, initial=0.0) / SLIDE_STRETCH
    out = grid.copy()
    for j in range(1, nj - 1):
        have = ~np.isnan(centre[:, j])
        c, t, w = centre[have, j], target[have, j], reach[have]
        points = [(0.0, 0.0), (ni - 1.0, ni - 1.0), *zip(c, t)]
        for k in range(len(c)):  # where the move ends, unless inside another line's reach
            for a in (c[k] - w[k], c[k] + w[k]):
                if 0 < a < ni - 1 and all(abs(a - c[m]) >= w[m] for m in range(len(c)) if m != k):
                    points.append((a, a))
        src, dst = np.array(sorted(points)).T
        if np.any(np.diff(src) <= 0) or np.any(np.diff(dst) <= 0):
            continue  # lines met in another order than drawn: the row stays
        u = np.interp(np.arange(ni), src, dst)
        i = np.clip(np.floor(u).astype(int), 0, ni - 2)
        f = (u - i)[:, None]
        out[j] = (1 - f) * grid[j, i] + f * grid[j, i + 1]
    return out


def _meetings(row: np.ndarray, line: np.ndarray) -> np.ndarray:
    """The node parameters (index plus fraction) at which the polyline ``row`` (n, 2) meets
    the polyline ``line`` (m, 2)."""
    p, r = row[:-1, None], np.diff(row, axis=0)[:, None]
    q, s = line[None, :-1], np.diff(line, axis=0)[None]

    def cross(u: np.ndarray, v: np.ndarray) -> np.ndarray:
        return u[..., 0] * v[..., 1] - u[..., 1] * v[..., 0]

    den, qp = cross(r, s), q - p
    ok = np.abs(den) > SINGULAR_SHARE * np.linalg.norm(r, axis=-1) * np.linalg.norm(s, axis=-1)
    den = np.where(ok, den, 1.0)
    u, v = cross(qp, s) / den, cross(qp, r) / den
    hit = ok & (u >= 0) & (u <= 1) & (v >= 0) & (v <= 1)
    return np.nonzero(hit)[0] + u[hit]


def pull_onto_lines(grid: np.ndarray, ranking: Ranking) -> np.ndarray:
    """``grid`` with its interior nodes slid within it towards following the auxiliary lines,
    in up to ``PULL_ROUNDS`` rounds (:func:`_pull_round`) while it is further from them than
    the ranking's tolerance. A round that does not bring the grid closer, or folds cells, is
    retried at half its step, up to three times. A grid line far from its drawn line moves
    the rows or columns beside it along, in proportion to their spacing (the node
    optimisation, one node at a time, would fold them)."""
    from scipy.sparse.linalg import splu

    nj, ni = grid.shape[:2]
    curves = _curves(ranking, ni, nj)
    inner = _interior(ni, nj)
    picks = _picks(curves)[:, inner]
    weight = PULL_WEIGHT / picks.shape[0]  # a mean over the samples
    # the roughness in computational units, whatever the lattice
    system = (ni - 1) * (nj - 1) * _smoothing(ni, nj) + weight * picks.T @ picks
    solve = splu(system.tocsc()).solve

    def smoothest(miss: np.ndarray) -> np.ndarray:
        return solve(weight * (picks.T @ miss))

    q, step = ranking.quality(grid), 1.0
    for _ in range(PULL_ROUNDS):
        if q["aux_distance"] <= ranking.line_tol or step < PULL_MIN_STEP:
            break
        moved = _pull_round(grid, curves, smoothest, step)
        q_moved = ranking.quality(moved)
        if (
            q_moved["folded_cells"] > q["folded_cells"]
            or q_moved["aux_distance"] >= q["aux_distance"]
        ):
            step /= 2
            continue
        grid, q = moved, q_moved
    return grid


def _pull_round(grid: np.ndarray, curves: list, smoothest, step: float) -> np.ndarray:
    """One round of :func:`pull_onto_lines`: each sample of the grid's curves through the
    lines is to move to its nearest point on its drawn line, a move of its (xi, eta) through
    the inverse of the grid's Jacobian there; ``smoothest`` turns these moves (n, 2) into the
    smoothest field of moves of the interior nodes' (xi, eta) that makes them (least squares),
    and the new node is the grid at its (xi, eta) moved by ``step`` times that (bilinear)."""
    nj, ni = grid.shape[:2]
    misses = []
    for samples, xy in curves:
        at = samples.at(grid)
        misses.append(_inverse_times(samples.jacobian(grid), _nearest(at, xy) - at))
    params = np.stack(np.meshgrid(np.linspace(0, 1, ni), np.linspace(0, 1, nj)), axis=-1)
    inner = _interior(ni, nj)
    params = np.clip(params.reshape(-1, 2)[inner] + step * smoothest(np.concatenate(misses)), 0, 1)
    out = grid.reshape(-1, 2).copy()
    out[inner] = _Samples(params, ni, nj).at(grid)
    return out.reshape(grid.shape)


def relax_on_lines(grid: np.ndarray, ranking: Ranking) -> np.ndarray:
    """``grid`` after ``RELAX_ITERATIONS`` Picard iterations of the Winslow equations (the
    coefficients frozen at each, ``elliptic.stencil_matrix``) with the grid's curves through
    the auxiliary lines held at their nearest points on the drawn lines by a penalty
    (``RELAX_WEIGHT`` times the equations' median diagonal): the elliptic grid that follows
    the lines, which the pull only approaches (it shears cells where lines move far, and the
    node optimisation does not undo that: the mean angle rises). ``grid`` itself if that
    folds more cells."""
    from scipy.sparse.linalg import spsolve

    nj, ni = grid.shape[:2]
    curves = _curves(ranking, ni, nj)
    picks = _picks(curves)
    inner = _interior(ni, nj)
    inside = picks[:, inner]
    g = grid.reshape(-1, 2).copy()
    fixed = picks @ g - inside @ g[inner]  # the samples' part from the boundary nodes
    for _ in range(RELAX_ITERATIONS):
        mat, rhs = stencil_matrix(g.reshape(grid.shape))
        weight = RELAX_WEIGHT * float(np.median(-mat.diagonal()))
        targets = np.concatenate([_nearest(s.at(g), xy) for s, xy in curves])
        system = (weight * inside.T @ inside - mat).tocsc()
        g[inner] = spsolve(system, weight * inside.T @ (targets - fixed) - rhs)
    relaxed = g.reshape(grid.shape)
    return relaxed if folded_cells(relaxed).sum() <= folded_cells(grid).sum() else grid


def _nearest(points: np.ndarray, line: np.ndarray) -> np.ndarray:
    """The nearest point (n, 2) of the polyline ``line`` (m, 2) to each of ``points`` (n, 2):
    ``losses.nearest_on_line`` on arrays."""

    def foot(a: np.ndarray, ab: np.ndarray, p: np.ndarray) -> np.ndarray:
        along = ((p - a) * ab).sum(-1) / np.maximum((ab * ab).sum(-1), 1e-300)
        return a + np.clip(along, 0.0, 1.0)[..., None] * ab

    a, ab = line[:-1], line[1:] - line[:-1]
    nearest = ((foot(a, ab, points[:, None]) - points[:, None]) ** 2).sum(-1).argmin(1)
    return foot(a[nearest], ab[nearest], points)


# The corners of every cell of a grid (nj, ni, 2) as slices, counter-clockwise in (i, j)
# (``losses.corner_angles``' order)
_CORNERS = (
    (slice(None, -1), slice(None, -1)),
    (slice(None, -1), slice(1, None)),
    (slice(1, None), slice(1, None)),
    (slice(1, None), slice(None, -1)),
)


def quality_loss(
    grid: np.ndarray, turn: float, tau: float = QUALITY_TAU
) -> tuple[float, np.ndarray, np.ndarray]:
    """``losses.loss_quality`` of ``losses.corner_angles(grid, turn)`` at temperature ``tau``
    in NumPy, with its gradient by the grid's nodes (nj, ni, 2) and the corner angles
    (4, nj - 1, ni - 1): the node optimisation's objective without torch. Coordinates are
    taken apart (x, y) and sine and cosine come from the cross and dot products: a third of
    the time of stacked pairs and np.sin (arctan2 and exp are most of what is left)."""
    x, y = grid[..., 0], grid[..., 1]
    # the edge from each cell corner to the next counter-clockwise; corner k's edges are
    # e[k] (to the next) and -e[k - 1] (to the previous)
    ex = [x[_CORNERS[(k + 1) % 4]] - x[_CORNERS[k]] for k in range(4)]
    ey = [y[_CORNERS[(k + 1) % 4]] - y[_CORNERS[k]] for k in range(4)]
    cross = np.stack([turn * (ex[k - 1] * ey[k] - ey[k - 1] * ex[k]) for k in range(4)])
    dot = np.stack([-(ex[k] * ex[k - 1] + ey[k] * ey[k - 1]) for k in range(4)])
    theta = np.pi + np.arctan2(-cross, -dot)
    scaled = theta / tau
    cell_top = scaled.max(0)
    cells = np.exp(scaled - cell_top)
    cell_sum = cells.sum(0)
    cell_max = tau * (cell_top + np.log(cell_sum))
    top = cell_top.max()
    every = cells * np.exp(cell_top - top)  # each corner's weight in the soft maximum
    total = every.sum()
    square = cross**2 + dot**2
    radius = np.sqrt(square)
    short = np.maximum(QUALITY_MIN_SINE - cross / radius, 0.0)  # sin theta: cross / radius
    loss = tau * (top + np.log(total)) + QUALITY_MEAN_WEIGHT * cell_max.mean()
    loss += QUALITY_BARRIER_WEIGHT * float((short**2).sum())
    d_theta = every / total + (QUALITY_MEAN_WEIGHT / cell_max.size) * (cells / cell_sum)
    d_theta -= 2 * QUALITY_BARRIER_WEIGHT * short * (dot / radius)  # cos theta: dot / radius
    d_cross = turn * d_theta * dot / square
    d_dot = -d_theta * cross / square
    gx, gy = np.zeros_like(x), np.zeros_like(y)
    for k in range(4):
        ax, ay, bx, by = ex[k], ey[k], -ex[k - 1], -ey[k - 1]
        dax, day = d_cross[k] * by + d_dot[k] * bx, d_dot[k] * by - d_cross[k] * bx
        dbx, dby = d_dot[k] * ax - d_cross[k] * ay, d_cross[k] * ax + d_dot[k] * ay
        ahead, here, behind = _CORNERS[(k + 1) % 4], _CORNERS[k], _CORNERS[k - 1]
        gx[ahead] += dax
        gy[ahead] += day
        gx[behind] += dbx
        gy[behind] += dby
        gx[here] -= dax + dbx
        gy[here] -= day + dby
    return float(loss), np.stack([gx, gy], -1), theta


def optimize_nodes(
    grid: np.ndarray,
    ranking: Ranking,
    iterations: int,
    held_rows: int = 1,
    seam: bool = False,
    stall: int | None = None,
    settle: Settle | None = None,
    tau: float = QUALITY_TAU,
    follow: bool = True,
    numpy_lbfgs: bool = False,
    outcome: dict | None = None,
) -> np.ndarray:
    """``grid`` with its interior nodes moved to minimise ``losses.loss_quality``
    (:func:`quality_loss` at temperature ``tau``; L-BFGS in float64, at most
    ``iterations``), with auxiliary lines from the grid moved onto them (:func:`follow_lines`,
    unless it follows them or not ``follow``) and plus ``LINE_WEIGHT`` times the line term
    (:func:`_line_term`); the boundary nodes stay, and the first ``held_rows`` rows from
    j = 0 (a body's wall and first layer: its first edges and wall angles). ``seam``: column
    ni - 1 is column 0 (an O-grid's seam), which moves with it.
    ``stall``: stop once that many iterations have not found a better-ranked state.
    ``settle``: stop once it has settled, and return its state (:class:`Settle`).
    ``outcome``: given, its ``settled`` says whether it stopped before its iterations (or
    their evaluations) ran out: settled, stalled or converged.
    ``numpy_lbfgs``: L-BFGS in NumPy (``lbfgs.minimize``: SciPy's L-BFGS-B without bounds,
    another line search) instead of SciPy's, whose import a body's route saves.
    Returns the evaluated state that ranks best (``ranking``, on the corner angles): the soft
    maximum is a surrogate of the worst angle, not the same. Each node moves in units of its
    shortest edge (a diagonal preconditioner: angles change with a node's move relative to
    its cells, 100 times smaller at a notch than in the open)."""
    if follow and ranking.lines and ranking.key(ranking.quality(grid))[2] > 0:  # misses them
        grid = follow_lines(grid, ranking)
    grid = np.asarray(grid, dtype=float)
    turn = orientation(grid)
    nj, ni = grid.shape[:2]
    free = (slice(held_rows, nj - 1), slice(0 if seam else 1, ni - 1))
    inner0 = grid[free].copy()
    unit = _node_units(grid, seam)[held_rows - 1 :, :, None]
    line_term = _line_term(grid, ranking, float(np.median(unit)))
    turn_term = _turn_term(grid, ranking)
    best = [(math.inf,), np.zeros(inner0.size)]
    since = [0]  # iterations since the best state was found
    keys: list[tuple] = []  # with settle: the best state's key after each iteration
    met: list[tuple[tuple, float, np.ndarray]] = []  # with settle: each state's key, mean, x
    held = _held_corners(grid.shape[:2], free, seam) if settle is not None else None
    floor = [-math.inf]  # with settle: the held corners' worst angle, no state's worst below
    spent = [0, 0]  # iterations and evaluations run

    def moved(x: np.ndarray) -> np.ndarray:
        g = grid.copy()
        g[free] = inner0 + unit * x.reshape(inner0.shape)
        if seam:
            g[:, -1] = g[:, 0]
        return g

    def loss_and_grad(x: np.ndarray) -> tuple[float, np.ndarray]:
        spent[1] += 1
        g = moved(x)
        loss, grad, theta = quality_loss(g, turn, tau)
        if seam:
            grad[:, 0] += grad[:, -1]
        q = {}
        if line_term is not None:
            term, d_term, q["aux_distance"] = line_term(g)
            loss += LINE_WEIGHT * term
            grad += LINE_WEIGHT * d_term
            q["aux_turn"] = max(
                t - e for t, e in zip(_turns(g, ranking.lines), ranking.turns, strict=True)
            )
            term, d_term = turn_term(g)
            loss += TURN_WEIGHT * term
            grad += TURN_WEIGHT * d_term
        largest = np.rad2deg(theta.max(0))
        if held is not None and not met and held.any():  # the same in every state
            floor[0] = round(float(np.rad2deg(theta[held].max())), WORST_DECIMALS)
        q.update(
            folded_cells=int((largest > FOLDED_ANGLE).sum()),
            mean_max_angle=float(largest.mean()),
            worst_max_angle=float(largest.max()),
        )
        key = ranking.key(q)
        if key < best[0]:
            best[:] = key, x.copy()
            since[0] = 0
        if settle is not None:
            met.append((key, q["mean_max_angle"], x.copy()))
        return loss, (grad[free] * unit).ravel()

    def stalled(_) -> None:
        since[0] += 1
        spent[0] += 1
        if stall is not None and since[0] > stall:
            raise StopIteration
        if settle is not None:
            if not any(best[0][:-1]) and best[0][-1] <= floor[0]:  # no state ranks better
                raise StopIteration
            keys.append(best[0])
            then = keys[-1 - settle.window] if len(keys) > settle.window else None
            if then is not None and then[:-1] == best[0][:-1]:
                if then[-1] - best[0][-1] < settle.worst:
                    raise StopIteration

    evaluations = NODE_EVALUATIONS * iterations
    if numpy_lbfgs:
        lbfgs.minimize(
            loss_and_grad,
            np.zeros(inner0.size),
            iterations,
            evaluations,
            stalled,
            NODE_LBFGS["maxcor"],
            NODE_LBFGS["gtol"],
        )
    else:
        from scipy.optimize import minimize

        minimize(
            loss_and_grad,
            np.zeros(inner0.size),
            jac=True,
            method="L-BFGS-B",
            callback=stalled,
            options={"maxiter": iterations, "maxfun": evaluations, **NODE_LBFGS},
        )
    if outcome is not None:
        outcome["settled"] = spent[0] < iterations and spent[1] < evaluations
    if settle is not None:
        near = [  # ranked no worse than the start, whose key is the first met
            (mean, x)
            for key, mean, x in met
            if key[:-1] == best[0][:-1]
            and key[-1] <= best[0][-1] + settle.spare
            and key <= met[0][0]
        ]
        return moved(min(near, key=lambda m: m[0])[1])
    return moved(best[1])


def _held_corners(shape: tuple[int, int], free: tuple[slice, slice], seam: bool) -> np.ndarray:
    """Which cell corners of a grid of ``shape`` (nj, ni) no move of its ``free`` nodes
    changes, (4, nj - 1, ni - 1) in ``_CORNERS``' order: those whose node and both
    neighbours along the cell's edges are held (a four-sided domain's corners)."""
    held = np.ones(shape, dtype=bool)
    held[free] = False
    if seam:
        held[:, -1] = held[:, 0]
    return np.stack(
        [held[_CORNERS[k]] & held[_CORNERS[(k + 1) % 4]] & held[_CORNERS[k - 1]] for k in range(4)]
    )


def _node_units(grid: np.ndarray, seam: bool) -> np.ndarray:
    """``quality.shortest_edges`` of the nodes off the boundary rows, (nj - 2, ni - 2); with a
    ``seam`` (column ni - 1 is column 0) of columns 0 .. ni - 2, (nj - 2, ni - 1), the seam's
    nodes with their neighbours across it."""
    if not seam:
        return shortest_edges(grid)
    around = np.concatenate([grid[:, -2:-1], grid, grid[:, 1:2]], axis=1)
    return shortest_edges(around)[:, :-1]


def _line_term(grid: np.ndarray, ranking: Ranking, scale: float):
    """``g -> (term, gradient, distance)`` for grids shaped like ``grid``: the mean squared
    distance (in units of ``scale``) of the grid's curves through the auxiliary lines from the
    drawn lines (the nearest point chosen without gradient: ``losses.nearest_on_line``), its
    gradient by the nodes, and the largest distance (relative to the diagonal); None without
    lines."""
    if not ranking.lines:
        return None
    curves = _curves(ranking, grid.shape[1], grid.shape[0])
    picks = _picks(curves) / scale
    lines = [xy / scale for _, xy in curves]
    counts = np.cumsum([0] + [len(s.index) for s, _ in curves])

    def term(g: np.ndarray) -> tuple[float, np.ndarray, float]:
        points = picks @ g.reshape(-1, 2)
        miss = np.concatenate(
            [
                points[lo:hi] - _nearest(points[lo:hi], xy)
                for lo, hi, xy in zip(counts[:-1], counts[1:], lines, strict=True)
            ]
        )
        squared = (miss**2).sum(-1)
        gradient = (picks.T @ (2 * miss / len(miss))).reshape(g.shape)
        distance = float(np.sqrt(squared.max())) * scale / ranking.diagonal
        return float(squared.mean()), gradient, distance

    return term


def _turn_term(grid: np.ndarray, ranking: Ranking):
    """``g -> (term, gradient)`` for grids shaped like ``grid``: over the auxiliary lines, the
    squared excess (radians) of the mean turn of the grid lines crossing each
    (``auxlines.crossing_turns``) over the elliptic grid's there plus ``TURN_AIM``, and its
    gradient by the nodes; None without lines."""
    if not ranking.lines:
        return None
    nodes = [crossing_nodes(grid.shape, line) for line in ranking.lines]
    targets = np.radians(np.asarray(ranking.turns) + TURN_AIM)

    def term(g: np.ndarray) -> tuple[float, np.ndarray]:
        flat = g.reshape(-1, 2)
        total, grad = 0.0, np.zeros_like(flat)
        for (before, at, after), target in zip(nodes, targets, strict=True):
            a, b = flat[at] - flat[before], flat[after] - flat[at]
            cross = a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]
            dot = (a * b).sum(-1)
            excess = float(np.arctan2(np.abs(cross), dot).mean()) - target
            if excess <= 0:
                continue
            total += excess**2
            square = np.maximum(cross**2 + dot**2, DBL_MIN)
            d_cross = (2 * excess / len(dot) * np.sign(cross) * dot / square)[:, None]
            d_dot = (-2 * excess / len(dot) * np.abs(cross) / square)[:, None]
            d_a = d_cross * np.stack([b[:, 1], -b[:, 0]], -1) + d_dot * b
            d_b = d_cross * np.stack([-a[:, 1], a[:, 0]], -1) + d_dot * a
            np.add.at(grad, before, -d_a)
            np.add.at(grad, at, d_a - d_b)
            np.add.at(grad, after, d_b)
        return total, grad.reshape(g.shape)

    return term
