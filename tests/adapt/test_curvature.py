"""The interpolation error's curvature metric (Huang 2006) as the adaptive equations'
tensor: |H| recovered from the field at the nodes, the metric's lengths across and along a
front, and a multi-block layer that the gradient's monitor carries worse."""

from __future__ import annotations

import numpy as np

from pinn_engine.adapt.error import interpolation_error
from pinn_engine.adapt.monitor import (
    curvature_diffusion,
    curvature_intensity,
    hessian_tensor,
    symmetric_function,
)
from pinn_engine.adapt.nodes import node_graph
from pinn_engine.adapt.parametric import ParameterSpace, _lattice_cells


def _matrix(d: np.ndarray) -> np.ndarray:
    return np.array([[d[..., 0], d[..., 1]], [d[..., 1], d[..., 2]]]).T


def test_the_recovered_hessian_of_a_quadratic_is_its_absolute_hessian():
    """f = x^2 - 3 x y - y^2 has H = [[2, -3], [-3, -2]], eigenvalues +-sqrt(13): |H| is
    sqrt(13) I, exact at nodes two rings from the sides whatever the passes."""
    x, y = np.meshgrid(np.linspace(0.0, 1.0, 11), np.linspace(0.0, 1.0, 11))
    points = np.column_stack([x.ravel(), y.ravel()])
    f = points[:, 0] ** 2 - 3 * points[:, 0] * points[:, 1] - points[:, 1] ** 2
    h = hessian_tensor(points, _lattice_cells(11, 11), f, passes=0).reshape(11, 11, 3)
    assert np.allclose(h[2:-2, 2:-2], [np.sqrt(13.0), 0.0, np.sqrt(13.0)])


def test_the_metric_compresses_a_front_across_by_the_error_bounds_power():
    """|H| = l n n^T (a straight front): the lengths asked are mu^(-5/12) across and
    mu^(1/12) along, mu = 1 + l / alpha; isotropic: their geometric mean every way; the
    shear cap bounds their ratio."""
    n = np.array([0.6, 0.8])
    hessian = (4.0 * np.array([n[0] ** 2, n[0] * n[1], n[1] ** 2]))[None]
    mu = 1.0 + 4.0 * 2.0
    d = _matrix(curvature_diffusion(hessian, 2.0))[0]
    t = np.array([-n[1], n[0]])
    assert np.allclose(d @ n, mu ** (-5 / 12) * n) and np.allclose(d @ t, mu ** (1 / 12) * t)
    iso = _matrix(curvature_diffusion(hessian, 2.0, isotropic=True))[0]
    assert np.allclose(iso, mu ** (-1 / 6) * np.eye(2))
    capped = _matrix(curvature_diffusion(hessian, 2.0, shear=np.array([1.5])))[0]
    assert np.isclose((t @ capped @ t) / (n @ capped @ n), 1.5)


def test_the_intensity_is_the_mean_cube_root_cubed():
    hessian = symmetric_function(np.array([[8.0, 0.0, 0.0], [0.0, 0.0, 1.0]]), np.abs)
    assert np.isclose(curvature_intensity(hessian, np.array([1.0, 1.0])), 1.5**3)


def _four_blocks() -> list[np.ndarray]:
    """A square cut into four blocks of 13 x 13 nodes at its centre (a junction of four)."""
    out = []
    for x0, y0 in ((0.0, 0.0), (0.5, 0.0), (0.0, 0.5), (0.5, 0.5)):
        x, y = np.meshgrid(np.linspace(x0, x0 + 0.5, 13), np.linspace(y0, y0 + 0.5, 13))
        out.append(np.stack([x, y], axis=-1))
    return out


def test_a_layer_across_a_junction_is_carried_better_by_the_curvature_metric():
    """An exponential layer about two cells thick along the bottom of four blocks: the
    gradient's monitor at strength 20 crowds the wall and leaves the layer's edge coarse
    (its error ratio 0.73), the curvature metric balances the two as the error bound asks
    (0.32)."""
    graph = node_graph(_four_blocks())

    def layer(points: np.ndarray) -> np.ndarray:
        return 1.0 - np.exp(-points[:, 1] / 0.08)

    space = ParameterSpace(graph, layer)
    strength = np.full(len(graph.points), 20.0)
    before = interpolation_error(graph.points, graph.cells, layer)
    gradient, curvature = (
        interpolation_error(space.solve(strength, curvature=c).points, graph.cells, layer)
        for c in (False, True)
    )
    assert curvature < 0.4 * before and curvature < 0.6 * gradient
