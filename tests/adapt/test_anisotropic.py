"""The anisotropic diffusion tensor of the adaptive equations: 1/M across a front and 1
along it, its finite-element operator an M-matrix, and a front carried better than by
Winslow's isotropic 1/M at the same strength."""

from __future__ import annotations

import numpy as np

from pinn_engine.adapt.error import interpolation_error
from pinn_engine.adapt.monitor import diffusion_tensor, monitor_values
from pinn_engine.adapt.nodes import node_graph
from pinn_engine.adapt.parametric import ParameterSpace, _stiffness


def _matrix(d: np.ndarray) -> np.ndarray:
    return np.array([[d[..., 0], d[..., 1]], [d[..., 1], d[..., 2]]]).T


def test_the_tensor_is_one_over_m_across_a_front_and_one_along_it():
    n = np.array([0.6, 0.8])  # the front's normal
    g = np.array([3.0])
    tensor = (g[:, None] ** 2 * np.array([n[0] ** 2, n[0] * n[1], n[1] ** 2]))[None]
    m = monitor_values(g, 5.0, 4.0)[0]
    d = _matrix(diffusion_tensor(g[None], tensor, 5.0, 4.0))[0, 0]
    assert np.allclose(d @ n, n / m) and np.allclose(d @ [-n[1], n[0]], [-n[1], n[0]])
    iso = _matrix(diffusion_tensor(g[None], tensor, 5.0, 4.0, isotropic=True))[0, 0]
    assert np.allclose(iso, np.eye(2) / m)


def test_a_tensor_without_a_direction_is_isotropic():
    """grad f grad f^T averaged over every direction (a vortex's core): D = I / M."""
    g = np.array([[2.0]])
    d = _matrix(diffusion_tensor(g, np.array([[[2.0, 0.0, 2.0]]]), 3.0, 2.0))[0, 0]
    assert np.allclose(d, np.eye(2) / monitor_values(g, 3.0, 2.0)[0, 0])


def test_the_operator_is_an_m_matrix_with_the_tensors_energy():
    """Non-positive off-diagonal entries, rows summing to zero, and a linear function's
    energy the tensor's (|k12| <= min(k11, k22): nothing cut)."""
    shape = (5, 6)
    k11, k22 = np.full(shape, 2.0), np.full(shape, 1.5)
    for k12 in (0.7, -0.7):
        lap = _stiffness(k11, np.full(shape, k12), k22).toarray()
        off = lap - np.diag(np.diag(lap))
        assert off.max() <= 0.0 and np.allclose(lap.sum(axis=1), 0.0)
        v, u = np.mgrid[0 : shape[0] + 1, 0 : shape[1] + 1]
        a = np.array([0.3, -1.1])
        x = (a[0] * u + a[1] * v).ravel()
        k = np.array([[2.0, k12], [k12, 1.5]])
        assert np.isclose(x @ lap @ x, shape[0] * shape[1] * a @ k @ a)


def test_an_oblique_front_is_carried_better_than_by_the_isotropic_form():
    x, y = np.meshgrid(np.linspace(0.0, 1.0, 21), np.linspace(0.0, 1.0, 21))
    grid = np.stack([x, y], axis=-1)

    def front(points: np.ndarray) -> np.ndarray:
        return np.tanh((0.8 * points[:, 0] + 0.6 * points[:, 1] - 0.7) / 0.03)

    graph = node_graph([grid])
    space = ParameterSpace(graph, front)
    strength = np.full(len(graph.points), 20.0)
    errors = [
        interpolation_error(space.solve(strength, isotropic).points, graph.cells, front)
        for isotropic in (False, True)
    ]
    assert errors[0] < 0.7 * errors[1]
