"""The not-a-knot cubic spline through points of a curve, in NumPy alone.

SciPy's ``CubicSpline`` gives the same curve (to rounding), but importing
``scipy.interpolate`` imports SciPy's optimisation, special functions and linear algebra
with it: 0.45 s of CPU, four times NumPy's import, for a body grid that needs nothing else
from SciPy. The slopes at the knots solve a tridiagonal system (de Boor, "A Practical Guide
to Splines", chapter IV), here by elimination without pivoting: after the not-a-knot
rows every pivot is positive and each interior row diagonally dominant.
"""

from __future__ import annotations

import numpy as np


def _slopes(x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """The first derivatives (n, d) at the knots ``x`` (n,) of the not-a-knot spline through
    ``y`` (n, d), n >= 4."""
    dx = np.diff(x)[:, None]
    slope = np.diff(y, axis=0) / dx
    n = len(x)
    lower, diag, upper = np.zeros(n), np.zeros(n), np.zeros(n)
    rhs = np.empty_like(y)
    diag[1:-1] = 2 * (dx[:-1, 0] + dx[1:, 0])
    upper[1:-1] = dx[:-1, 0]
    lower[1:-1] = dx[1:, 0]
    rhs[1:-1] = 3 * (dx[1:] * slope[:-1] + dx[:-1] * slope[1:])
    # the third derivative continuous at the second and the last but one knots
    d = x[2] - x[0]
    diag[0], upper[0] = dx[1, 0], d
    rhs[0] = ((dx[0] + 2 * d) * dx[1] * slope[0] + dx[0] ** 2 * slope[1]) / d
    d = x[-1] - x[-3]
    diag[-1], lower[-1] = dx[-2, 0], d
    rhs[-1] = (dx[-1] ** 2 * slope[-2] + (2 * d + dx[-1]) * dx[-2] * slope[-1]) / d
    # row k holds lower[k] at column k - 1 (row 0's lower is unused), upper[k] at k + 1;
    # Python floats: a loop of NumPy scalars takes five times as long
    low, dia, up, r = lower.tolist(), diag.tolist(), upper.tolist(), rhs.tolist()
    for k in range(1, n):
        m = low[k] / dia[k - 1]
        dia[k] -= m * up[k - 1]
        r[k] = [a - m * b for a, b in zip(r[k], r[k - 1])]
    s = [[a / dia[-1] for a in r[-1]]]
    for k in range(n - 2, -1, -1):
        s.append([(a - up[k] * b) / dia[k] for a, b in zip(r[k], s[-1])])
    return np.array(s[::-1])


class CurveSpline:
    """The not-a-knot cubic spline through ``points`` (n, d) at increasing ``t`` (n,): a
    straight line through two points, a parabola through three."""

    def __init__(self, t: np.ndarray, points: np.ndarray) -> None:
        self.t = np.asarray(t, dtype=float)
        y = np.asarray(points, dtype=float).reshape(len(self.t), -1)
        self.shape = np.shape(points)[1:]
        dx = np.diff(self.t)[:, None]
        slope = np.diff(y, axis=0) / dx
        if len(self.t) == 2:
            s = np.vstack([slope, slope])
        elif len(self.t) == 3:  # the parabola's slopes at its three knots
            h0, h1 = dx[0], dx[1]
            curvature = (slope[1] - slope[0]) / (h0 + h1)
            s = np.vstack(
                [slope[0] - curvature * h0, slope[0] + curvature * h0, slope[1] + curvature * h1]
            )
        else:
            s = _slopes(self.t, y)
        cubic = (s[:-1] + s[1:] - 2 * slope) / dx
        # (4, n - 1, d): per interval, the coefficients of d^3, d^2, d, 1 with d = t - t_k
        self.coefficients = np.stack([cubic / dx, (slope - s[:-1]) / dx - cubic, s[:-1], y[:-1]])

    def __call__(self, t: np.ndarray) -> np.ndarray:
        """The points (*t.shape, *d) at ``t``; outside the knots, the end intervals' cubics."""
        t = np.asarray(t, dtype=float)
        flat = t.ravel()
        k = np.clip(np.searchsorted(self.t, flat, side="right") - 1, 0, len(self.t) - 2)
        d = (flat - self.t[k])[:, None]
        c = self.coefficients.take(k, axis=1)  # contiguous rows: a third of indexing's time
        out = ((c[0] * d + c[1]) * d + c[2]) * d + c[3]
        return out.reshape(*t.shape, *self.shape)
