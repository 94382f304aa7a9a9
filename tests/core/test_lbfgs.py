"""L-BFGS in NumPy (lbfgs.py): it minimises as SciPy's L-BFGS-B does without bounds, within
its budgets, and stops where its callback says."""

from __future__ import annotations

import numpy as np
import pytest

from pinn_engine import lbfgs


def _rosenbrock(x: np.ndarray) -> tuple[float, np.ndarray]:
    """The Rosenbrock function of len(x) variables (minimum 0 at all ones), its gradient."""
    a, b = x[:-1], x[1:]
    grad = np.zeros_like(x)
    grad[:-1] = -400 * a * (b - a * a) - 2 * (1 - a)
    grad[1:] += 200 * (b - a * a)
    return float((100 * (b - a * a) ** 2 + (1 - a) ** 2).sum()), grad


def _counted(fun):
    calls = []

    def counted(x):
        calls.append(x.copy())
        return fun(x)

    return counted, calls


def test_it_finds_the_minimum_of_a_curved_valley():
    start = np.tile([-1.2, 1.0], 5)
    fun, calls = _counted(_rosenbrock)
    x = lbfgs.minimize(fun, start, 500, 1500, gtol=1e-10)
    assert np.abs(x - 1).max() < 1e-8
    assert len(calls) < 200  # SciPy's L-BFGS-B: 94 evaluations from here


def test_it_keeps_to_its_budgets_and_its_callback():
    start = np.tile([-1.2, 1.0], 5)
    fun, calls = _counted(_rosenbrock)
    lbfgs.minimize(fun, start, 500, 30)
    assert len(calls) == 30

    seen = []

    def stop_at_five(x: np.ndarray) -> None:
        seen.append(x)
        if len(seen) == 5:
            raise StopIteration

    fun, calls = _counted(_rosenbrock)
    x = lbfgs.minimize(fun, start, 500, 1500, stop_at_five)
    assert len(seen) == 5 and x is seen[-1]
    values = [_rosenbrock(p)[0] for p in [start, *seen]]
    assert all(b < a for a, b in zip(values, values[1:], strict=False))  # each step descends


@pytest.mark.parametrize("value", [np.inf, np.nan])
def test_a_step_into_overflow_is_stepped_back_from(value):
    """A trial step where the function overflows (a grid's edge of length ~0) is a step too
    far: the line search shrinks it."""

    def walled(x: np.ndarray) -> tuple[float, np.ndarray]:
        if x[0] > 0.5:
            return value, np.full_like(x, value)
        return float(((x - 0.4) ** 2).sum()), 2 * (x - 0.4)

    x = lbfgs.minimize(walled, np.array([-10.0, 3.0]), 50, 200)
    assert np.abs(x - 0.4).max() < 1e-6
