"""Control terms of the 3D Winslow equations that keep a node distribution (SPEC 7 in 3D).

The 3D form of Spekreijse's construction that the 2D elliptic grid uses
(``classical.elliptic.parameter_controls``; Spekreijse 1995, J. Comput. Phys. 118): the
grid is x(s) with the parameters s = (s_1, s_2, s_3) harmonic in x, its nodes at the
parameters ``params``. Expanding the Laplacian of x and of each s_k by the chain rule in
index space gives ``L x + sum_m P_m x_{xi_m} = 0`` with ``P = -T^-1 (L s_1, L s_2, L s_3)``,
L = sum_mn C_mn d_{xi_m xi_n} (C the cofactors of the metric tensor, the Winslow operator)
and T_km = d s_k / d xi_m. On a box whose parameters are a tensor product the stretched grid
is an exact fixed point.
"""

from __future__ import annotations

import numpy as np

SINGULAR = 1e-300  # a parameter Jacobian below this is a degenerate distribution


def _derivatives(p: np.ndarray) -> tuple[list[np.ndarray], dict[tuple[int, int], np.ndarray]]:
    """First and second central differences of one parameter (ni, nj, nk) at interior
    nodes: [d_0, d_1, d_2] and {(m, n): d_mn}."""

    def at(offset: tuple[int, int, int]) -> np.ndarray:
        return p[tuple(slice(1 + o, p.shape[a] - 1 + o) for a, o in enumerate(offset))]

    unit = np.eye(3, dtype=int)
    first = [0.5 * (at(tuple(unit[m])) - at(tuple(-unit[m]))) for m in range(3)]
    second = {
        (m, m): at(tuple(unit[m])) - 2 * at((0, 0, 0)) + at(tuple(-unit[m])) for m in range(3)
    }
    for m, n in ((0, 1), (0, 2), (1, 2)):
        e, f = unit[m], unit[n]
        second[(m, n)] = 0.25 * (
            at(tuple(e + f)) - at(tuple(e - f)) - at(tuple(f - e)) + at(tuple(-e - f))
        )
    return first, second


def parameter_controls(
    c: dict[tuple[int, int], np.ndarray], params: np.ndarray
) -> list[np.ndarray]:
    """P_m (m = 0, 1, 2) at the interior nodes for node ``params`` (ni, nj, nk, 3), with the
    cofactors ``c`` of the grid (``volume._cofactors``: (m, n) for m <= n)."""
    jac = np.empty(c[(0, 0)].shape + (3, 3))
    laplace = np.empty(c[(0, 0)].shape + (3,))
    for k in range(3):
        first, second = _derivatives(params[..., k])
        for m in range(3):
            jac[..., k, m] = first[m]
        laplace[..., k] = sum(
            (1.0 if m == n else 2.0) * c[(m, n)] * second[(m, n)] for (m, n) in second
        )
    det = np.linalg.det(jac)
    ok = np.abs(det) > SINGULAR
    jac[~ok] = np.eye(3)
    p = -np.linalg.solve(jac, laplace[..., None])[..., 0]
    p[~ok] = 0.0
    return [p[..., m] for m in range(3)]
