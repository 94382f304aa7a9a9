"""How well a grid carries a field: the L2 norm (cells weighted by their area) of the
difference between the field and the bilinear interpolant of its values at the nodes, at
``QUAD`` x ``QUAD`` points inside every cell. Measured on the field itself (the solver's
result is the finest description of it there is), it is the figure adaptation lowers and
the one that decides whether an adapted grid is kept (SPEC 14: kept only where better)."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from pinn_engine.adapt.monitor import cell_areas

QUAD = 3  # sample points a cell side (their mean squared error is the cell's)


def interpolation_error(
    points: np.ndarray, cells: np.ndarray, sample: Callable[[np.ndarray], np.ndarray]
) -> float:
    """The field's L2 interpolation error on the cells (m, 4) of nodes ``points``;
    ``sample`` gives the field at points (n, 2)."""
    u = (np.arange(QUAD) + 0.5) / QUAD
    uu, vv = (a.ravel() for a in np.meshgrid(u, u))
    weights = np.stack([(1 - uu) * (1 - vv), uu * (1 - vv), uu * vv, (1 - uu) * vv])  # (4, q)
    corners = points[cells]  # (m, 4, 2)
    inside = np.einsum("kq,mkd->mqd", weights, corners)
    nodal = sample(points)[cells]  # (m, 4)
    error = np.einsum("kq,mk->mq", weights, nodal) - sample(inside.reshape(-1, 2)).reshape(
        len(cells), -1
    )
    area = cell_areas(points, cells)
    return float(np.sqrt((area * (error**2).mean(axis=1)).sum() / area.sum()))
