"""A smooth field through the nodes of a hexahedral lattice: the 3D pinn's start.

The pinn of a six-faced domain (kinds/hexa/problem.py) starts as the converged Winslow grid E on a
lattice, and its map is TFI + D + bubble * network with D = E - TFI, zero on the six faces
(classical/warm.py is the 2D form). A tricubic tensor-product spline through a lattice's
values (cubic along a direction with 4 nodes or more, else of degree nodes - 1) gives the
field between the nodes, its derivatives for the training's jets, and its values at the
nodes of any finer grid.
"""

from __future__ import annotations

from functools import cached_property
from typing import TYPE_CHECKING

import numpy as np

from pinn_engine.classical.tfi import node_params

if TYPE_CHECKING:
    from scipy.interpolate import NdBSpline

CUBIC = 3  # the spline's degree where a direction has enough nodes


def node_points(shape: tuple[int, ...]) -> np.ndarray:
    """The (xi, eta, zeta) of a uniform ``shape`` grid's nodes on the unit cube, (*shape, 3)."""
    return np.stack(np.meshgrid(*map(node_params, shape), indexing="ij"), axis=-1)


class LatticeField:
    """A field (ni, nj, nk, 3) of values at the uniform lattice nodes of the unit cube, as
    an interpolating spline."""

    def __init__(self, values: np.ndarray) -> None:
        self.values = np.asarray(values, dtype=float)

    @cached_property
    def spline(self) -> NdBSpline:
        """The spline, built when first needed (the lattice's own nodes need none, nor
        SciPy's splines)."""
        from scipy.interpolate import NdBSpline, make_interp_spline

        degrees = tuple(min(CUBIC, n - 1) for n in self.values.shape[:3])
        c, knots = self.values, []
        for axis, k in enumerate(degrees):  # interpolate along one direction at a time
            along = make_interp_spline(node_params(c.shape[axis]), c, k=k, axis=axis)
            c = np.moveaxis(along.c, 0, axis)
            knots.append(along.t)
        return NdBSpline(tuple(knots), c, degrees)

    def jet(self, x: np.ndarray, orders: list[tuple[int, int, int]]) -> np.ndarray:
        """The derivatives of the given ``orders`` (d/dxi, d/deta, d/dzeta counts) at points
        ``x`` (B, 3): (len(orders), B, 3)."""
        return np.stack([self.spline(x, nu=order) for order in orders])

    def at_nodes(self, shape: tuple[int, int, int]) -> np.ndarray:
        """The field at the nodes of a uniform ``shape`` grid of the unit cube; the
        lattice's own values at its size."""
        if tuple(shape) == self.values.shape[:3]:
            return self.values
        return self.spline(node_points(shape).reshape(-1, 3)).reshape(*shape, 3)
