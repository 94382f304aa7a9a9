"""L-BFGS in NumPy (Nocedal and Wright, "Numerical Optimization", algorithms 7.4 and 7.5, with
the strong Wolfe line search of algorithms 3.5 and 3.6): SciPy's L-BFGS-B without bounds (its
memory, scaling and line search's constants, another line search's steps), for routes that
import no SciPy (importing ``scipy.optimize`` costs about 0.4 s of CPU, more than a small
grid's whole optimisation)."""

from __future__ import annotations

from collections import deque
from collections.abc import Callable

import numpy as np

# The line search's sufficient decrease and curvature constants, and the most evaluations it
# makes: L-BFGS-B's (its MINPACK line search's ftol, gtol and maxls)
DECREASE = 1e-3
CURVATURE = 0.9
LINE_EVALUATIONS = 20
# A step that has not yet bracketed the minimum along the line grows this many times (the
# extrapolation MINPACK's line search allows at most)
EXPAND = 4.0
# An interpolated step keeps this share of the bracket's width from either end (else the
# bracket's midpoint): a step at an end would not shrink it
SAFEGUARD = 0.1
# A correction pair (s, y) is kept only where its curvature s.y exceeds this share of the
# decrease predicted along s (L-BFGS-B's test: float64's epsilon)
CURVATURE_FLOOR = float(np.finfo(float).eps)

Objective = Callable[[np.ndarray], tuple[float, np.ndarray]]


def minimize(
    fun: Objective,
    x0: np.ndarray,
    iterations: int,
    evaluations: int,
    callback: Callable[[np.ndarray], None] | None = None,
    history: int = 10,
    gtol: float = 0.0,
) -> np.ndarray:
    """The point where L-BFGS, keeping ``history`` correction pairs, stops minimising
    ``fun`` (the value and gradient at a point) from ``x0``: after ``iterations``
    iterations or ``evaluations`` evaluations, where the largest gradient component is at
    most ``gtol``, where no step along the search direction lowers ``fun`` (from steepest
    descent), or where ``callback`` (called with each iterate) raises StopIteration."""
    calls = [0]

    def counted(point: np.ndarray) -> tuple[float, np.ndarray]:
        calls[0] += 1
        return fun(point)

    x = np.array(x0, dtype=float)
    f, g = counted(x)
    pairs: deque[tuple[np.ndarray, np.ndarray, float]] = deque(maxlen=history)
    for _ in range(iterations):
        if not np.abs(g).max(initial=0.0) > gtol:
            break
        d = -_times_inverse_hessian(g, pairs)
        step = 1.0 if pairs else 1.0 / float(np.linalg.norm(d))
        found = _wolfe(counted, x, f, g, d, step, min(LINE_EVALUATIONS, evaluations - calls[0]))
        if found is None and pairs:  # the direction failed: start again from steepest descent
            pairs.clear()
            continue
        if found is None:
            break
        step, x_new, f, g_new = found
        s, y = x_new - x, g_new - g
        sy = float(s @ y)
        if sy > CURVATURE_FLOOR * -step * float(g @ d):
            pairs.append((s, y, 1.0 / sy))
        x, g = x_new, g_new
        if callback is not None:
            try:
                callback(x)
            except StopIteration:
                break
        if calls[0] >= evaluations:
            break
    return x


def _times_inverse_hessian(
    g: np.ndarray, pairs: deque[tuple[np.ndarray, np.ndarray, float]]
) -> np.ndarray:
    """The L-BFGS inverse Hessian times ``g`` (the two-loop recursion), its initial matrix
    s.y / y.y of the newest pair times the identity (the identity without pairs)."""
    q = g.copy()
    alphas = []
    for s, y, rho in reversed(pairs):
        alpha = rho * float(s @ q)
        q -= alpha * y
        alphas.append(alpha)
    if pairs:
        s, y, rho = pairs[-1]
        q *= 1.0 / (rho * float(y @ y))
    for (s, y, rho), alpha in zip(pairs, reversed(alphas), strict=True):
        q += (alpha - rho * float(y @ q)) * s
    return q


def _wolfe(
    fun: Objective,
    x: np.ndarray,
    f0: float,
    g0: np.ndarray,
    d: np.ndarray,
    step: float,
    budget: int,
) -> tuple[float, np.ndarray, float, np.ndarray] | None:
    """A step along ``d`` from ``x`` (value ``f0``, gradient ``g0``) meeting the strong Wolfe
    conditions, with the point and its value and gradient, in at most
    ``budget`` evaluations from the trial ``step``: the trial grows until it brackets such a
    step, then the bracket shrinks to the minimum of the cubic through its ends. Where the
    budget runs out, the lowest trial that decreased ``fun`` enough; None where none did (or
    ``d`` does not descend)."""
    slope0 = float(g0 @ d)
    if not slope0 < 0:
        return None
    low = (0.0, f0, slope0, x, g0)  # the lowest trial meeting the decrease condition
    high = None  # the bracket's other end, once a trial passes the minimum
    for _ in range(budget):
        point = x + step * d
        f, g = fun(point)
        slope = float(g @ d)
        if not f <= f0 + DECREASE * step * slope0 or f >= low[1]:
            high = (step, f, slope)
        elif abs(slope) <= -CURVATURE * slope0:
            return step, point, f, g
        else:
            if slope * ((high[0] if high else np.inf) - low[0]) >= 0:
                high = low[:3]
            low = (step, f, slope, point, g)
        if high is None:
            step *= EXPAND
        else:
            step = _cubic_step(low[:3], high)
    if low[0] > 0:
        return low[0], low[3], low[1], low[4]
    return None


def _cubic_step(low: tuple[float, float, float], high: tuple[float, float, float]) -> float:
    """The minimiser of the cubic through the bracket's ends (step, value, slope), kept
    ``SAFEGUARD`` of its width inside it; the midpoint where the cubic has none."""
    (a, fa, da), (b, fb, db) = low, high
    d1 = da + db - 3 * (fa - fb) / (a - b)
    root = d1 * d1 - da * db
    lo, hi = min(a, b), max(a, b)
    margin = SAFEGUARD * (hi - lo)
    if not (np.isfinite(root) and root >= 0):
        return 0.5 * (lo + hi)
    d2 = np.copysign(np.sqrt(root), b - a)
    trial = b - (b - a) * (db + d2 - d1) / (db - da + 2 * d2)
    if not np.isfinite(trial):
        return 0.5 * (lo + hi)
    return float(min(max(trial, lo + margin), hi - margin))
