"""Transfinite interpolation (paper eq. 1), on a grid and as a differentiable jet for the PINN."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from pinn_engine.geometry.boundary_fit import ArcLengthFit

SideEval = Callable[[str, np.ndarray, int], np.ndarray]


def transfinite(xi: np.ndarray, eta: np.ndarray, side: SideEval, order: int = 0) -> list:
    """TFI (paper eq. 1, with its misprint ``+ r_t`` read as ``+ eta r_t``) and derivatives.

    ``side(name, t, nu)`` returns the ``nu``-th derivative of a side curve at ``t``. Returns
    ``[T]`` for ``order=0``, else ``[T, T_xi, T_eta, T_xixi, T_xieta, T_etaeta]``, each of shape
    ``broadcast(xi, eta) + (2,)``.
    """
    xi = np.asarray(xi, dtype=float)[..., None]
    eta = np.asarray(eta, dtype=float)[..., None]
    one = np.ones(1)
    c00, c10 = side("bottom", 0 * one, 0)[0], side("bottom", one, 0)[0]
    c01, c11 = side("top", 0 * one, 0)[0], side("top", one, 0)[0]
    b, t = side("bottom", xi[..., 0], 0), side("top", xi[..., 0], 0)
    left, right = side("left", eta[..., 0], 0), side("right", eta[..., 0], 0)
    T = (
        (1 - xi) * left
        + xi * right
        + (1 - eta) * b
        + eta * t
        - (1 - xi) * (1 - eta) * c00
        - xi * (1 - eta) * c10
        - (1 - xi) * eta * c01
        - xi * eta * c11
    )
    if order == 0:
        return [T]
    b1, t1 = side("bottom", xi[..., 0], 1), side("top", xi[..., 0], 1)
    l1, r1 = side("left", eta[..., 0], 1), side("right", eta[..., 0], 1)
    b2, t2 = side("bottom", xi[..., 0], 2), side("top", xi[..., 0], 2)
    l2, r2 = side("left", eta[..., 0], 2), side("right", eta[..., 0], 2)
    T_xi = right - left + (1 - eta) * b1 + eta * t1 + (1 - eta) * (c00 - c10) + eta * (c01 - c11)
    T_eta = (1 - xi) * l1 + xi * r1 + t - b + (1 - xi) * (c00 - c01) + xi * (c10 - c11)
    T_xixi = (1 - eta) * b2 + eta * t2
    T_etaeta = (1 - xi) * l2 + xi * r2
    T_xieta = r1 - l1 + t1 - b1 - (c00 - c10 - c01 + c11)
    return [T, T_xi, T_eta, T_xixi, np.broadcast_to(T_xieta, T.shape), T_etaeta]


def node_params(n: int) -> np.ndarray:
    """Uniform computational coordinates of ``n`` nodes on [0, 1]."""
    if n < 2:
        raise ValueError("a grid needs at least 2 nodes per direction")
    return np.linspace(0.0, 1.0, n)


def tfi_grid(
    sample: Callable[[str, np.ndarray], np.ndarray], ni: int, nj: int, rows: slice = slice(None)
) -> np.ndarray:
    """TFI grid (nj, ni, 2) whose boundary nodes are ``sample(side, t)`` at uniform t; only
    the grid rows ``rows`` when given (blocks of a large grid)."""
    xi, eta = node_params(ni), node_params(nj)[rows]
    return transfinite(xi[None, :], eta[:, None], lambda s, t, nu: sample(s, t))[0]


def tfi_at(boundary) -> Callable[[np.ndarray], np.ndarray]:
    """TFI of the exact boundary polylines, evaluated at node parameters (nj, ni, 2)."""
    fit = ArcLengthFit(boundary)
    return lambda p: transfinite(p[..., 0], p[..., 1], lambda s, t, nu: fit.sample(s, t))[0]


def tfi_of_sides(
    bottom: np.ndarray, right: np.ndarray, top: np.ndarray, left: np.ndarray
) -> np.ndarray:
    """TFI grid (nj, ni, 2) of four given node rows: ``bottom`` and ``top`` (ni, 2) with i
    increasing, ``left`` and ``right`` (nj, 2) with j increasing, sharing their corner
    nodes; uniform computational coordinates (a block of a multi-block grid)."""
    xi = node_params(len(bottom))[None, :, None]
    eta = node_params(len(left))[:, None, None]
    b, t, lf, r = bottom[None], top[None], left[:, None], right[:, None]
    return (
        (1 - eta) * b
        + eta * t
        + (1 - xi) * lf
        + xi * r
        - (1 - xi) * (1 - eta) * bottom[0]
        - xi * (1 - eta) * bottom[-1]
        - (1 - xi) * eta * top[0]
        - xi * eta * top[-1]
    )
