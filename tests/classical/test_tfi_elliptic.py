"""TFI (paper eq. 1) and the elliptic Winslow solvers."""

from __future__ import annotations

import numpy as np
import pytest
from helpers import EXAMPLES

from pinn_engine.classical.elliptic import winslow_residual, winslow_solve, winslow_sweeps
from pinn_engine.classical.tfi import node_params, tfi_grid
from pinn_engine.quality import folded_cells


def bilinear(xi, eta):
    p = {
        "00": np.array([0.0, 0.0]),
        "10": np.array([3.0, 0.5]),
        "01": np.array([0.4, 2.0]),
        "11": np.array([2.5, 2.8]),
    }
    xi, eta = np.asarray(xi)[..., None], np.asarray(eta)[..., None]
    return (
        (1 - xi) * (1 - eta) * p["00"]
        + xi * (1 - eta) * p["10"]
        + (1 - xi) * eta * p["01"]
        + xi * eta * p["11"]
    )


def bilinear_sides(side, t):
    t = np.asarray(t, dtype=float)
    return {
        "bottom": lambda: bilinear(t, 0 * t),
        "top": lambda: bilinear(t, 0 * t + 1),
        "left": lambda: bilinear(0 * t, t),
        "right": lambda: bilinear(0 * t + 1, t),
    }[side]()


def test_tfi_reproduces_a_bilinear_map_exactly():
    grid = tfi_grid(bilinear_sides, 13, 7)
    xi, eta = np.meshgrid(node_params(13), node_params(7))
    np.testing.assert_allclose(grid, bilinear(xi, eta), atol=1e-14)


def polar_grid(ni: int, nj: int) -> np.ndarray:
    """Annulus sector, angle along xi, logarithmic radius along eta: a harmonic map.

    With equal log-radial and angular steps, (xi, eta) -> (log r, theta) is conformal.
    """
    theta = 0.2 + 1.0 * node_params(ni)
    r = np.exp(1.0 * (nj - 1) / (ni - 1) * node_params(nj))
    return np.stack([r[:, None] * np.cos(theta), r[:, None] * np.sin(theta)], axis=-1)


def test_affine_map_is_a_fixed_point_to_round_off():
    xi, eta = np.meshgrid(node_params(21), node_params(11))
    grid = np.stack([2 * xi + 0.3 * eta, -0.5 * xi + eta], axis=-1)
    shaken = grid + 0.01 * np.random.default_rng(0).normal(size=grid.shape)
    solved, _ = winslow_solve(grid, initial=shaken)
    np.testing.assert_allclose(solved, grid, atol=1e-12)
    assert np.abs(winslow_residual(grid)).max() < 1e-14


def test_harmonic_polar_sector_stays_fixed_up_to_second_order_discretisation():
    """The continuous harmonic map moves only by the O(h^2) error of the central differences.

    (The 9-point Winslow scheme has no exact discrete fixed point at the polar map: it would
    need cosh(c h) = cos(d), so the check is second-order convergence, then round-off
    idempotence of the converged grid.)
    """
    moves = []
    for n in (11, 21, 41):
        grid = polar_grid(n, n)
        solved, _ = winslow_solve(grid)
        moves.append(np.abs(solved - grid).max())
    assert moves[0] < 1e-3
    assert 3.5 < moves[0] / moves[1] < 4.5 and 3.5 < moves[1] / moves[2] < 4.5
    again, _ = winslow_solve(solved, initial=solved)
    np.testing.assert_allclose(again, solved, atol=1e-12)
    assert np.abs(winslow_residual(solved)).max() < 1e-12


def test_paper_sweeps_from_zero_interior_approach_the_converged_grid():
    grid = polar_grid(21, 11)
    converged, iterations = winslow_solve(grid)
    assert iterations < 50
    swept = winslow_sweeps(grid, 1000)
    assert np.abs(swept - converged).max() < 1e-6
    assert not folded_cells(swept).any()


def test_converged_solver_is_fast_on_a_200_by_200_grid():
    """Not a timing test: it bounds the iteration count that makes 200 x 200 take seconds."""
    s = node_params(200)
    bottom = np.column_stack([3 * s, 0.3 * np.sin(2 * np.pi * s)])
    sides = {
        "bottom": bottom,
        "top": bottom + [0, 2],
        "left": np.column_stack([0 * s, 2 * s]),
        "right": np.column_stack([3 + 0 * s, 2 * s]),
    }
    grid = tfi_grid(lambda side, t: sides[side], 200, 200)
    solved, iterations = winslow_solve(grid, tol=1e-10)
    assert iterations < 40
    assert np.abs(winslow_residual(solved)).max() < 1e-8


def test_mesher_fitted_attributes_the_scikit_learn_way():
    from pinn_engine.errors import NotFittedError
    from pinn_engine.io.pipeline import load_boundary
    from pinn_engine.kinds.four_sided.mesher import Mesher
    from pinn_engine.settings import make_settings

    mesher = Mesher(make_settings("elliptic"))
    assert not hasattr(mesher, "boundary_") and not hasattr(mesher, "model_")
    with pytest.raises(NotFittedError, match="call fit"):
        mesher.predict(11, 6)
    boundary = load_boundary(EXAMPLES / "fig2.vtp")
    assert mesher.fit(boundary) is mesher
    assert mesher.boundary_ is boundary and mesher.model_ is None and mesher.aux_lines_ == []
    assert mesher.predict(11, 6).points.shape == (6, 11, 2)
