"""Node distributions for boundary layers (SPEC 7): first-edge spacing at chosen sides.

A grid's nodes sit at parameters (xi, eta) of a map from the unit square; without spacing
they are uniform (today's distribution). ``--spacing SIDE=H`` stretches them with Vinokur's
one- or two-sided formula (Vinokur 1983, "On one-dimensional stretching functions for
finite-difference calculations", J. Comput. Phys. 50): bottom/top stretch eta, left/right
stretch xi. A physical first edge H is not one parameter spacing on a curved or tapering
domain, so every grid line gets its own stretching (the eta distribution of column i has its
own first spacing at the bottom and top), and :func:`fit_params` iterates those per-line
spacings against the measured first edges of the grid the method produces, until every
first edge is H within ``tol``. The boundary nodes follow the same parameters (the bottom
row of xi parameters places the nodes on the bottom side), so the boundary stays exact.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from pinn_engine.classical.tfi import tfi_at
from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary_fit import ArcLengthFit
from pinn_engine.quality import first_edges, folded_cells

# the sides a side's first edges run along (their lengths bound the spacing): the sides at
# its first and its last node
ACROSS = {
    "bottom": ("left", "right"),
    "top": ("left", "right"),
    "left": ("bottom", "top"),
    "right": ("bottom", "top"),
}
MAX_B = 1e12  # stretching beyond this (first spacing ~1e-12 of a side) is clipped
# Bisections of Vinokur's delta: 80 halve its bracket (below 1e3) from 1e3 to under 1e-21,
# past a double's resolution; the bracket is checked for standing still every STILL_CHECK
# (about 55 bisections reach the resolution on the body grids' brackets of about 20)
BISECTIONS, STILL_CHECK = 80, 4


def _solve(b: np.ndarray, f: Callable[[np.ndarray], np.ndarray], hi: float) -> np.ndarray:
    """delta in (0, hi) with f(delta) = b for increasing (sinh) or decreasing (sin) f/x: up
    to ``BISECTIONS`` bisections, stopped once one leaves the bracket as it was (a state
    that one bisection keeps, every later one keeps: the result is the same)."""
    lo_, hi_ = np.full_like(b, 1e-12), np.full_like(b, hi)
    increasing = f(np.asarray([hi * 0.5]))[0] > f(np.asarray([hi * 0.25]))[0]
    for step in range(BISECTIONS):
        mid = 0.5 * (lo_ + hi_)
        above = f(mid) > b
        new_hi, new_lo = (
            (np.where(above, mid, hi_), np.where(above, lo_, mid))
            if increasing
            else (np.where(above, hi_, mid), np.where(above, mid, lo_))
        )
        if step % STILL_CHECK == 0 and np.array_equal(new_hi, hi_) and np.array_equal(new_lo, lo_):
            break
        hi_, lo_ = new_hi, new_lo
    return 0.5 * (lo_ + hi_)


def _delta(b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Vinokur's delta for B = b: sinh(d)/d = B when B > 1 (hyperbolic), sin(d)/d = B when
    B < 1 (trigonometric); returns (delta, hyperbolic)."""
    b = np.clip(b, 1e-3, MAX_B)
    hyper = b >= 1.0
    d = np.zeros_like(b)
    if hyper.any():
        lb = np.log(b[hyper])
        d[hyper] = _solve(lb, lambda x: np.log(np.sinh(x) / x), 2 * np.log(2 * b[hyper].max()) + 4)
    if (~hyper).any():
        d[~hyper] = _solve(b[~hyper], lambda x: np.sin(x) / x, np.pi * (1 - 1e-9))
    return d, hyper


def _odd(d: np.ndarray, hyper: np.ndarray, z: np.ndarray) -> np.ndarray:
    """tanh(d z)/tanh(d/2) or tan(d z)/tan(d/2); z in [-1/2, 1/2], linear 2 z as d -> 0."""
    d = d[:, None]
    small = d < 1e-6
    ds = np.where(small, 1.0, d)
    h = np.tanh(ds * z) / np.tanh(ds / 2)
    t = np.tan(ds * z) / np.tan(ds / 2)
    return np.where(small, 2 * z, np.where(hyper[:, None], h, t))


def stretch(
    n: int, first: np.ndarray | None, last: np.ndarray | None, lines: int = 1
) -> np.ndarray:
    """Parameters (lines, n) in [0, 1], monotone, with first and last interval ``first`` and
    ``last`` (arrays over the lines; None: that end is free). Vinokur's formulas: the
    derivative at an end is the requested spacing times n - 1; measured edges correct the
    rest (:func:`fit_params`)."""
    u = np.linspace(0.0, 1.0, n)[None, :]
    if first is None and last is None or n < 3:
        return np.repeat(u, lines, axis=0)
    if first is None:  # mirror of a stretching at the start
        return 1.0 - stretch(n, last, None, lines)[:, ::-1]
    n1 = n - 1
    first = np.broadcast_to(np.asarray(first, dtype=float), (lines,))
    if last is None:  # one-sided (Vinokur eq. for s'(0) only)
        d, hyper = _delta(1.0 / (n1 * first))
        return np.clip(1.0 + _odd(d, hyper, (u - 1.0) / 2), 0.0, 1.0)
    last = np.broadcast_to(np.asarray(last, dtype=float), (lines,))
    a = np.sqrt(last / first)[:, None]
    d, hyper = _delta(1.0 / (n1 * np.sqrt(first * last)))
    v = 0.5 * (1.0 + _odd(d, hyper, u - 0.5))
    return np.clip(v / (a + (1.0 - a) * v), 0.0, 1.0)


def exact_stretch(
    n: int, first: np.ndarray | float | None, last: np.ndarray | float | None = None, lines: int = 1
) -> np.ndarray:
    """:func:`stretch` whose first and last intervals are ``first`` and ``last`` themselves,
    not Vinokur's end slopes: each end's requested spacing is scaled by target / measured
    interval until they agree to ``EXACT_TOL`` (the body grids' distributions, which have no grid
    evaluation to correct them as :func:`fit_params` does)."""
    want = [
        None if a is None else np.broadcast_to(np.asarray(a, float), (lines,))
        for a in (first, last)
    ]
    ask = [None if a is None else a.copy() for a in want]
    for _ in range(EXACT_ITERATIONS):
        s = stretch(n, ask[0], ask[1], lines)
        if n < 3:
            break
        off = 0.0
        for k, got in enumerate((s[:, 1] - s[:, 0], s[:, -1] - s[:, -2])):
            if want[k] is not None:
                ratio = want[k] / np.maximum(got, 1e-300)
                off = max(off, float(np.abs(ratio - 1.0).max()))
                ask[k] = ask[k] * ratio
        if off <= EXACT_TOL:
            break
    return s


EXACT_TOL, EXACT_ITERATIONS = 1e-9, 60  # a first interval of 1e-9 is good to about 1e-7


# Lines of one direction share one Vinokur stretching (the geometric mean of their first
# spacings); each line reaches its own first spacing by a scaling of its intervals that decays
# over about this many cells from the side (then rescaled to keep the total): its far part
# hardly moves (rows shifted along a curved wall would fold its thin first cells).
LOCAL_CELLS = 6.0


def line_parameters(
    n: int, first: np.ndarray | None, last: np.ndarray | None, lines: int
) -> np.ndarray:
    """Parameters (lines, n) of one direction for per-line first/last spacings."""
    top = [None if a is None else float(np.exp(np.log(a).mean())) for a in (first, last)]
    t = np.repeat(stretch(n, *top), lines, axis=0)
    if n < 3 or (first is None and last is None):
        return t
    d = np.diff(t, axis=1)
    decay = np.exp(-np.arange(n - 1) / LOCAL_CELLS)
    if first is not None:
        d = d * (1 + (np.asarray(first) / top[0] - 1)[:, None] * decay[None, :])
    if last is not None:
        d = d * (1 + (np.asarray(last) / top[1] - 1)[:, None] * decay[None, ::-1])
    t = np.concatenate([np.zeros((lines, 1)), np.cumsum(d, axis=1)], axis=1)
    t /= t[:, -1:]
    t[:, -1] = 1.0
    return t


def param_grid(ni: int, nj: int, spacing: dict[str, np.ndarray]) -> np.ndarray:
    """Node parameters (nj, ni, 2): xi of row j from the left/right first spacings of that
    row, eta of column i from the bottom/top spacings of that column (parameter units)."""
    xi = line_parameters(ni, spacing.get("left"), spacing.get("right"), nj)
    eta = line_parameters(nj, spacing.get("bottom"), spacing.get("top"), ni)
    return np.stack([xi, eta.T], axis=-1)


def uniform_params(ni: int, nj: int) -> np.ndarray:
    return param_grid(ni, nj, {})


# Rounds of the fit (each one grid evaluation), the share by which every first edge may
# still be off when it stops (SPEC 7 asks for 10 %), and the most a round changes a line's
# spacing by (the first edge is nearly linear in it, but not far from the last guess)
FIT_ROUNDS, FIT_TOL, STEP_CLIP = 12, 0.01, (0.2, 5.0)
# the bounds of a per-line parameter spacing: positive, and under most of the line
PARAM_RANGE = (1e-14, 0.9)


def fit_first_spacings(
    evaluate: Callable[[np.ndarray], np.ndarray],
    node_params: Callable[[dict[str, np.ndarray]], np.ndarray],
    measured: Callable[[np.ndarray, str], np.ndarray],
    spacing: dict[str, float],
    par: dict[str, np.ndarray],
    checked: Callable[[np.ndarray], np.ndarray],
) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """The fit of every kind with a first-edge spacing (four-sided 2D, six-faced 3D): each
    round evaluates the grid at ``node_params(par)`` and scales each side's per-line
    parameter spacings ``par[side]`` by target / ``measured(grid, side)`` (a one-parameter
    secant step), until every first edge that ``checked`` keeps of a side's ratios (its
    nodes but the corners) is H within ``FIT_TOL``, or ``evaluate.failed`` turns True.
    Returns (params, grid, per-line parameter spacings)."""
    for _ in range(FIT_ROUNDS):
        params = node_params(par)
        grid = evaluate(params)
        if getattr(evaluate, "failed", False):
            break
        worst = 0.0
        for side, h in spacing.items():
            ratio = h / np.maximum(measured(grid, side), 1e-300)
            worst = max(worst, float(np.abs(checked(ratio) - 1.0).max(initial=0.0)))
            par[side] = np.clip(par[side] * np.clip(ratio, *STEP_CLIP), *PARAM_RANGE)
        if worst <= FIT_TOL:
            break
    return params, grid, par


def fit_params(
    evaluate: Callable[[np.ndarray], np.ndarray],
    spacing: dict[str, float],
    ni: int,
    nj: int,
    side_lengths: dict[str, float],
    pin: Callable[[np.ndarray], np.ndarray] = lambda params: params,
) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """Parameters whose grid ``evaluate(params)`` has first edges ``spacing[side]`` (working
    frame) within ``FIT_TOL`` at every node of those sides but the corners
    (:func:`fit_first_spacings`). ``side_lengths``: the lengths of the four sides, for the
    first guess; ``pin``: the nodes' parameters moved onto sharp vertices
    (``pins.pin_sharp``), fitted as they are. Returns (params, grid, per-line parameter
    spacings).
    """
    if not spacing:
        params = pin(uniform_params(ni, nj))
        return params, evaluate(params), {}
    count = {"bottom": ni, "top": ni, "left": nj, "right": nj}
    par = {
        s: np.full(count[s], h / (0.5 * sum(side_lengths[o] for o in ACROSS[s])))
        for s, h in spacing.items()
    }
    return fit_first_spacings(
        evaluate,
        lambda par: pin(param_grid(ni, nj, par)),
        lambda grid, side: first_edges(grid)[side],
        spacing,
        par,
        lambda ratio: ratio[1:-1],
    )


def working_spacing(spacing: tuple[tuple[str, float], ...], boundary) -> dict[str, float]:
    """``Settings.spacing`` (user units) in the working frame, checked against the domain: a
    first edge must be shorter than half the sides it runs along."""
    out = {}
    for side, h in spacing:
        unit = h / boundary.frame.scale
        room = min(boundary.side(s).length for s in ACROSS[side])
        if unit >= 0.5 * room:
            raise InputError(
                f"{{spacing}} {side}={h:g}: the first edge must be shorter than half "
                f"of the {' and '.join(ACROSS[side])} sides "
                f"({0.5 * room * boundary.frame.scale:.4g})"
            )
        out[side] = unit
    return out


def side_lengths(boundary) -> dict[str, float]:
    return {s: boundary.side(s).length for s in ("bottom", "right", "top", "left")}


def elliptic_at(boundary, orthogonal: tuple[str, ...] = ()) -> Callable[[np.ndarray], np.ndarray]:
    """Converged elliptic grid with control functions (elliptic.controlled_solve) on the
    boundary nodes of parameters (nj, ni, 2); each call starts from the previous grid and
    controls. ``evaluate.failed`` turns True when a solve did not converge."""
    from pinn_engine.classical.elliptic import safe_controlled_solve

    tfi = tfi_at(boundary)
    last: list = [None]
    control: dict = {}

    def evaluate(p: np.ndarray) -> np.ndarray:
        base = tfi(p)
        uniform = np.allclose(p, uniform_params(p.shape[1], p.shape[0]), atol=1e-15)
        grid, iterations, kept = safe_controlled_solve(
            base,
            None if uniform else p,
            orthogonal,
            control=control,
            initial=base if last[0] is None else last[0],
            max_iterations=MAX_SOLVE_ITERATIONS,
        )
        evaluate.failed |= (
            iterations >= MAX_SOLVE_ITERATIONS
            or not np.isfinite(grid).all()
            or bool(folded_cells(grid).any())
        )
        evaluate.orthogonal &= kept
        last[0] = grid
        return grid

    evaluate.failed, evaluate.orthogonal = False, True
    return evaluate


MAX_SOLVE_ITERATIONS = 800


def interpolated_elliptic_at(
    boundary, ni: int, nj: int, orthogonal: tuple[str, ...] = ()
) -> Callable[[np.ndarray], np.ndarray]:
    """The elliptic map solved on the uniform ``ni`` x ``nj`` lattice (with orthogonality
    control), as a smooth map of the parameters (TFI plus a bicubic spline of the elliptic
    correction, classical/warm.py) evaluated at node parameters: the fallback where the solve
    with distribution controls does not converge."""
    from pinn_engine.classical.elliptic import safe_controlled_solve, winslow_solve
    from pinn_engine.classical.warm import WarmStart

    tfi = tfi_at(boundary)
    base = tfi(uniform_params(ni, nj))
    grid = (
        safe_controlled_solve(base, None, orthogonal)[0] if orthogonal else winslow_solve(base)[0]
    )
    warm = WarmStart(grid - base)
    return lambda p: tfi(p) + warm.at(p.reshape(-1, 2)).reshape(p.shape)


def classical_grid(
    boundary,
    ni: int,
    nj: int,
    method: str,
    spacing: dict[str, float],
    orthogonal: tuple[str, ...] = (),
    info: dict | None = None,
    pin: Callable[[np.ndarray], np.ndarray] = lambda params: params,
) -> tuple[np.ndarray, np.ndarray]:
    """(params, grid) of the tfi or (converged) elliptic method under the spacing (working
    frame) and orthogonality settings. The elliptic grid is solved with control functions
    (distribution and Hilgenstock orthogonality); if that fails (no convergence, a folded
    cell or first edges off by more than 10 %), the interpolated elliptic map is evaluated
    at the distribution instead; ``info["elliptic"]`` says which. ``pin``: as
    :func:`fit_params`."""

    lengths = side_lengths(boundary)
    if method == "tfi":
        params, grid, _ = fit_params(tfi_at(boundary), spacing, ni, nj, lengths, pin)
        return params, grid
    evaluate = elliptic_at(boundary, orthogonal)
    params, grid, _ = fit_params(evaluate, spacing, ni, nj, lengths, pin)
    edges = first_edges(grid)
    off = max(
        (float(np.abs(edges[s][1:-1] / h - 1).max(initial=0.0)) for s, h in spacing.items()),
        default=0.0,
    )
    ok = not evaluate.failed and off <= 0.1 and not folded_cells(grid).any()
    if not ok and spacing:
        evaluate = interpolated_elliptic_at(boundary, ni, nj, orthogonal)
        params, grid, _ = fit_params(evaluate, spacing, ni, nj, lengths, pin)
    if info is not None:
        info["elliptic"] = "control functions" if ok or not spacing else "interpolated"
        info["orthogonality_control"] = bool(orthogonal) and getattr(evaluate, "orthogonal", True)
    return params, grid


def chord_tangents(
    boundary, side: str, t: np.ndarray, nodes: int, along: np.ndarray | None = None
) -> np.ndarray:
    """Tangents (len(t), 2) of ``side`` at parameters ``t`` as a grid of ``nodes`` nodes
    along it sees them: the chord between the neighbouring nodes (what the reported wall
    angle measures, :func:`quality.grid_lines_angle`), not the curve's own tangent, which differs
    from it where the wall bends within a cell. ``along``: the parameters of the side's
    nodes when they are not uniform."""

    fit, step = ArcLengthFit(boundary), 1.0 / max(nodes - 1, 1)
    if along is not None:  # the nodes' parameters along the side (a spacing across it)
        u = np.linspace(0.0, 1.0, len(along))
        at = np.interp(t, along, u)
        ahead = np.interp(np.clip(at + step, 0.0, 1.0), u, along)
        behind = np.interp(np.clip(at - step, 0.0, 1.0), u, along)
        return fit.sample(side, ahead) - fit.sample(side, behind)
    ahead, behind = np.clip(t + step, 0.0, 1.0), np.clip(t - step, 0.0, 1.0)
    return fit.sample(side, ahead) - fit.sample(side, behind)
