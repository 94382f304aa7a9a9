"""The curve spline and bilinear sampling that stand in for SciPy's (start-up time): the
same curves as ``scipy.interpolate`` to rounding."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.interpolate import CubicSpline, RegularGridInterpolator

from pinn_engine.geometry.auxlines import bilinear
from pinn_engine.geometry.spline import CurveSpline


@pytest.mark.parametrize("n", [2, 3, 4, 5, 40])
def test_the_curve_spline_is_scipys_not_a_knot_spline(n):
    rng = np.random.default_rng(n)
    t = np.r_[0.0, np.cumsum(rng.uniform(0.05, 1.0, n - 1))]
    points = rng.normal(size=(n, 2))
    at = np.linspace(t[0] - 0.2, t[-1] + 0.2, 301)  # the end cubics continue outside
    expected = CubicSpline(t, points, axis=0, bc_type="not-a-knot")(at)
    np.testing.assert_allclose(CurveSpline(t, points)(at), expected, rtol=0, atol=1e-12)
    assert CurveSpline(t, points)(t[1]).shape == (2,)


def test_bilinear_sampling_is_scipys_linear_interpolation():
    rng = np.random.default_rng(0)
    grid = rng.normal(size=(7, 11, 2))
    xi_eta = np.vstack([rng.uniform(0, 1, (50, 2)), [[0, 0], [1, 1], [1, 0], [0, 1]]])
    axes = (np.linspace(0, 1, 7), np.linspace(0, 1, 11))
    expected = RegularGridInterpolator(axes, grid)(xi_eta[:, ::-1])
    np.testing.assert_allclose(bilinear(grid, xi_eta), expected, rtol=0, atol=1e-12)
