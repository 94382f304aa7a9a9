"""The monitor of SPEC 14, ``M = sqrt(1 + beta^2 |grad f|^2 / max |grad f|^2)``, of a field
sampled at a grid's nodes, and the equidistribution it asks for."""

from __future__ import annotations

import numpy as np

# Passes of averaging (nodes to cells and back) of |grad f| before the monitor is formed: one
# noisy cell's gradient is spread over its neighbours, a front a few cells wide is kept
SMOOTHING_PASSES = 2
# the strongest compression the shear cap considers (a monitor ratio of 1000: beyond any
# strength asked), and the bisection steps of its log (2^-20 of its range: exact enough)
SHEAR_FLOOR = 1e-3
SHEAR_BISECTIONS = 20
# The curvature metric's exponent on det(I + |H| / alpha) for the L2 norm of linear
# interpolation's error in d = 2 dimensions, -1 / (d + 4) (Huang 2006): a straight front's
# cells are compressed across it as mu^(5/12), an isotropic feature's as mu^(1/3)
CURVATURE_DET_POWER = -1.0 / 6.0


def cell_gradient_vectors(points: np.ndarray, cells: np.ndarray, f: np.ndarray) -> np.ndarray:
    """grad f (m, 2) at each cell's centre (the bilinear map's Jacobian there), cells (m, 4)
    counter-clockwise."""
    p, v = points[cells], f[cells]
    x_xi = 0.5 * (p[:, 1] - p[:, 0] + p[:, 2] - p[:, 3])
    x_eta = 0.5 * (p[:, 3] - p[:, 0] + p[:, 2] - p[:, 1])
    f_xi = 0.5 * (v[:, 1] - v[:, 0] + v[:, 2] - v[:, 3])
    f_eta = 0.5 * (v[:, 3] - v[:, 0] + v[:, 2] - v[:, 1])
    jac = x_xi[:, 0] * x_eta[:, 1] - x_xi[:, 1] * x_eta[:, 0]
    jac = np.where(np.abs(jac) > 1e-300, jac, 1e-300)
    gx = (f_xi * x_eta[:, 1] - f_eta * x_xi[:, 1]) / jac
    gy = (-f_xi * x_eta[:, 0] + f_eta * x_xi[:, 0]) / jac
    return np.column_stack([gx, gy])


def cell_gradients(points: np.ndarray, cells: np.ndarray, f: np.ndarray) -> np.ndarray:
    """|grad f| at each cell's centre."""
    g = cell_gradient_vectors(points, cells, f)
    return np.hypot(g[:, 0], g[:, 1])


def to_nodes(cells: np.ndarray, values: np.ndarray, n: int) -> np.ndarray:
    """The mean of each node's cells' ``values``."""
    total = np.bincount(cells.ravel(), np.repeat(values, 4), minlength=n)
    return total / np.maximum(np.bincount(cells.ravel(), minlength=n), 1)


def gradient_size(
    points: np.ndarray, cells: np.ndarray, f: np.ndarray, passes: int = SMOOTHING_PASSES
) -> np.ndarray:
    """|grad f| at the nodes, smoothed by ``passes``."""
    return smoothed_at_nodes(cells, cell_gradients(points, cells, f), len(points), passes)


def smoothed_at_nodes(cells: np.ndarray, values: np.ndarray, n: int, passes: int) -> np.ndarray:
    """Cell ``values`` at the ``n`` nodes (:func:`to_nodes`), then ``passes`` times averaged
    to the cells and back: one noisy cell spread over its neighbours."""
    out = to_nodes(cells, values, n)
    for _ in range(passes):
        out = to_nodes(cells, out[cells].mean(axis=1), n)
    return out


def monitor_values(
    gradient: np.ndarray, strength: float | np.ndarray, largest: float
) -> np.ndarray:
    """SPEC 14's monitor of the node gradients, ``largest`` the max |grad f| it is scaled by."""
    if largest <= 0.0:
        return np.ones_like(gradient)
    return np.sqrt(1.0 + (strength * gradient / largest) ** 2)


def cell_areas(points: np.ndarray, cells: np.ndarray) -> np.ndarray:
    """Each cell's area (half the cross product of its diagonals)."""
    p = points[cells]
    d1, d2 = p[:, 2] - p[:, 0], p[:, 3] - p[:, 1]
    return 0.5 * np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0])


def equidistribution(points: np.ndarray, cells: np.ndarray, m: np.ndarray) -> float:
    """The coefficient of variation of M times cell area over the cells (0: M is
    equidistributed), M at a cell the mean of its nodes'."""
    w = m[cells].mean(axis=1) * cell_areas(points, cells)
    return float(w.std() / w.mean()) if w.mean() > 0 else 0.0


def gradient_tensor(
    points: np.ndarray, cells: np.ndarray, f: np.ndarray, passes: int = SMOOTHING_PASSES
) -> np.ndarray:
    """The mean of grad f grad f^T at the nodes (n, 3: xx, xy, yy), smoothed by ``passes``
    as :func:`gradient_size` smooths |grad f|: its principal direction is the one across a
    front, and a sign change of grad f (a ridge) does not cancel it."""
    g = cell_gradient_vectors(points, cells, f)
    parts = (g[:, 0] ** 2, g[:, 0] * g[:, 1], g[:, 1] ** 2)
    return np.stack([smoothed_at_nodes(cells, p, len(points), passes) for p in parts], axis=-1)


def diffusion_tensor(
    gradient: np.ndarray,
    tensor: np.ndarray,
    strength: float | np.ndarray,
    largest: float,
    isotropic: bool = False,
    shear: np.ndarray | None = None,
) -> np.ndarray:
    """The inverse metric D (..., 3: xx, xy, yy) of the variable-diffusion equations: 1/M
    across the front (the principal direction n of ``tensor``, M SPEC 14's monitor of the
    node ``gradient``) and 1/M' along it, M' the monitor of the gradient times sqrt(l2 / l1)
    (the tensor's eigenvalues l1 >= l2):

        D = n n^T / M + t t^T / M'     (the anisotropic diffusion tensor)

    Along a straight front M' = 1: cells are compressed across it and not along it, so
    grid lines that cross it are not sheared; where grad f has no direction (a vortex's
    core) M' = M, Winslow's isotropic 1/M, which ``isotropic`` asks everywhere. ``shear``
    caps M / M' (:func:`shear_cap`): the compression across a front that the cells there
    take without passing the guard's angle."""
    l1, l2 = eigenvalues(tensor)
    l2 = np.maximum(l2, 0.0)
    ratio = np.sqrt(np.where(l1 > 0.0, l2 / np.where(l1 > 0.0, l1, 1.0), 1.0))
    m_across = monitor_values(gradient, strength, largest)
    m_along = monitor_values(gradient * ratio, strength, largest)
    if shear is not None:
        m_across = np.minimum(m_across, shear * m_along)
    across = 1.0 / m_across
    along = across if isotropic else 1.0 / m_along
    return oriented(principal_direction(tensor), across, along)


def slipped(
    d: np.ndarray, n: np.ndarray, jacobian: np.ndarray, e1: np.ndarray, e2: np.ndarray
) -> np.ndarray:
    """D (..., 3: xx, xy, yy; n its principal direction, (..., 2)) with the cross term that
    turns a compressed cell's grid lines along the front instead of shearing it: the slip.

    Across a straight front the equations' solution is xi = x + g(n . x), and a cell's edge
    e (the lattice's ``e1``, ``e2``) becomes A e, A = [[c, 0], [-s, 1]] in the frame (n, t):
    compressed by c across the front and slipped by s = -c q / p along it, p = n^T D n and
    q = n^T D t the cross term. D as built has q = 0, and an oblique cell shears; here s
    keeps (A e1) . (A e2) = e1 . e2 (a square stays a rectangle, turned along the front):
    the root nearest 0 of (e1.n)(e2.n) (s^2 + c^2 - 1) - ((e1.n)(e2.t) + (e2.n)(e1.t)) s = 0.
    c = 1 / (n^T J n) is read from a solve with D (``jacobian`` J = d xi / d x at the
    nodes); a stretched cell (c >= 1) slips none: no slip along the front makes it square.
    t^T D t grows by q^2 / p, which keeps D positive definite and leaves the front's
    one-dimensional solution as it was."""
    t = np.stack([-n[..., 1], n[..., 0]], axis=-1)
    p, b = _quadratic(d, n, n), _quadratic(d, t, t)
    c = 1.0 / np.maximum(np.einsum("...i,...ij,...j->...", n, jacobian, n), 1.0)
    a1, a2 = (e1 * n).sum(-1), (e2 * n).sum(-1)
    lean = a1 * (e2 * t).sum(-1) + a2 * (e1 * t).sum(-1)
    constant = a1 * a2 * (c**2 - 1.0)
    # the root nearest 0 in the form that does not cancel (constant <= 0: two real roots)
    den = lean + np.where(lean >= 0.0, 1.0, -1.0) * np.sqrt(lean**2 - 4.0 * a1 * a2 * constant)
    slip = 2.0 * constant / np.where(np.abs(den) > 0.0, den, 1.0)
    q = -slip * p / c
    (n1, n2), (t1, t2) = np.moveaxis(n, -1, 0), np.moveaxis(t, -1, 0)
    cross = np.stack([2 * n1 * t1, n1 * t2 + n2 * t1, 2 * n2 * t2], axis=-1)  # n t^T + t n^T
    return oriented(n, p, b + q**2 / p) + q[..., None] * cross


def _quadratic(d: np.ndarray, a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """a^T D b of tensors D (..., 3: xx, xy, yy) and vectors a, b (..., 2)."""
    return (
        d[..., 0] * a[..., 0] * b[..., 0]
        + d[..., 1] * (a[..., 0] * b[..., 1] + a[..., 1] * b[..., 0])
        + d[..., 2] * a[..., 1] * b[..., 1]
    )


def eigenvalues(tensor: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The larger and the smaller eigenvalue of symmetric 2 x 2 tensors (..., 3: xx, xy,
    yy)."""
    a, b, c = tensor[..., 0], tensor[..., 1], tensor[..., 2]
    half = np.sqrt(np.maximum(0.25 * (a - c) ** 2 + b**2, 0.0))
    return 0.5 * (a + c) + half, 0.5 * (a + c) - half


def principal_direction(tensor: np.ndarray) -> np.ndarray:
    """The unit eigenvector (..., 2) of the largest eigenvalue of ``tensor`` (..., 3: xx,
    xy, yy): the direction across a front."""
    theta = 0.5 * np.arctan2(2.0 * tensor[..., 1], tensor[..., 0] - tensor[..., 2])
    return np.stack([np.cos(theta), np.sin(theta)], axis=-1)


def _max_angle(e1: np.ndarray, e2: np.ndarray) -> np.ndarray:
    """The largest angle (degrees) of the parallelogram on the edges e1, e2 (..., 2)."""
    dot = np.abs((e1 * e2).sum(-1))
    size = np.linalg.norm(e1, axis=-1) * np.linalg.norm(e2, axis=-1)
    return 180.0 - np.degrees(np.arccos(np.clip(dot / np.maximum(size, 1e-300), 0.0, 1.0)))


def shear_cap(e1: np.ndarray, e2: np.ndarray, n: np.ndarray, limit: float) -> np.ndarray:
    """The largest compression 1/c (c <= 1) across the unit direction n that a cell with the
    edges e1, e2 (..., 2) takes before its largest angle passes ``limit`` degrees.

    A compression across a front that crosses grid lines obliquely shears the cells (a
    square compressed by half along its diagonal is a rhombus of 127 degrees): the cap is the
    guard's bound turned into a bound on the monitor's anisotropy, set before solving, so
    that the whole front is compressed as far as the bound allows rather than the strength
    lowered everywhere for the cells where it breaks."""

    def squeezed(c: np.ndarray) -> np.ndarray:
        c = c[..., None]
        a1 = e1 - (1.0 - c) * (e1 * n).sum(-1, keepdims=True) * n
        a2 = e2 - (1.0 - c) * (e2 * n).sum(-1, keepdims=True) * n
        return _max_angle(a1, a2)

    shape = e1.shape[:-1]
    lo, hi = np.full(shape, np.log(SHEAR_FLOOR)), np.zeros(shape)  # log c: fails, holds
    ok_floor = squeezed(np.exp(lo)) <= limit
    for _ in range(SHEAR_BISECTIONS):
        mid = 0.5 * (lo + hi)
        holds = squeezed(np.exp(mid)) <= limit
        hi, lo = np.where(holds, mid, hi), np.where(holds, lo, mid)
    c = np.where(ok_floor, SHEAR_FLOOR, np.exp(hi))
    return 1.0 / c


def hessian_tensor(
    points: np.ndarray, cells: np.ndarray, f: np.ndarray, passes: int = SMOOTHING_PASSES
) -> np.ndarray:
    """The absolute Hessian |H| of f at the nodes (n, 3: xx, xy, yy; H's eigenvectors with
    its eigenvalues' magnitudes), smoothed by ``passes`` as :func:`gradient_size` smooths
    |grad f|: the gradient recovered at the nodes (its cells' mean), differentiated again
    on the cells. A front's |H| is largest on its two flanks, where linear interpolation
    errs most, and zero at its centre."""
    n = len(points)
    g = cell_gradient_vectors(points, cells, f)
    hx, hy = (cell_gradient_vectors(points, cells, to_nodes(cells, g[:, k], n)) for k in (0, 1))
    h = np.stack([hx[:, 0], 0.5 * (hx[:, 1] + hy[:, 0]), hy[:, 1]], axis=-1)
    absolute = symmetric_function(h, np.abs)
    return np.stack(
        [smoothed_at_nodes(cells, absolute[:, k], n, passes) for k in range(3)], axis=-1
    )


def symmetric_function(tensor: np.ndarray, fn) -> np.ndarray:
    """``fn`` of symmetric 2 x 2 tensors (..., 3: xx, xy, yy): the same eigenvectors,
    ``fn`` of the eigenvalues."""
    big, small = (fn(x) for x in eigenvalues(tensor))
    return oriented(principal_direction(tensor), big, small)


def oriented(n: np.ndarray, first: np.ndarray, second: np.ndarray) -> np.ndarray:
    """The symmetric 2 x 2 tensors (..., 3: xx, xy, yy) whose eigenvalue along the unit
    vectors ``n`` (..., 2) is ``first`` and across them ``second``."""
    cos, sin = n[..., 0], n[..., 1]
    return np.stack(
        [
            first * cos**2 + second * sin**2,
            (first - second) * cos * sin,
            first * sin**2 + second * cos**2,
        ],
        axis=-1,
    )


def curvature_intensity(hessian: np.ndarray, weights: np.ndarray) -> float:
    """Huang's intensity alpha of the curvature metric: the ``weights``-weighted mean of
    l1^(1/3), cubed (l1 the larger eigenvalue of |H|, in place of Huang's det|H|^(1/6),
    which a straight front's one-eigenvalue |H| makes zero), so that about half the
    density goes to where |H| is large and half stays in the bulk."""
    largest = eigenvalues(hessian)[0]
    mean = float((weights * np.cbrt(np.maximum(largest, 0.0))).sum() / weights.sum())
    return mean**3


def curvature_diffusion(
    hessian: np.ndarray,
    intensity: float | np.ndarray,
    isotropic: bool = False,
    shear: np.ndarray | None = None,
) -> np.ndarray:
    """The inverse square root D (..., 3) of the curvature metric of the interpolation
    error (Huang, "Mathematical principles of anisotropic mesh adaptation", 2006):

        G = det(I + |H| / alpha)^(-1/6) (I + |H| / alpha)     (the metric, d = 2, L2 norm)

    ``intensity`` the factor 1 / alpha (the strength scaled); D's eigenvalues are the
    cells' lengths asked in H's eigen-directions. ``shear`` caps the ratio of the lengths
    along and across (:func:`shear_cap`); ``isotropic``: their geometric mean in every
    direction."""
    mu = symmetric_function(hessian * np.asarray(intensity)[..., None], lambda x: 1.0 + x)
    det = mu[..., 0] * mu[..., 2] - mu[..., 1] ** 2
    metric = mu * (det**CURVATURE_DET_POWER)[..., None]
    lengths = symmetric_function(metric, lambda x: 1.0 / np.sqrt(np.maximum(x, 1e-300)))
    long, short = eigenvalues(lengths)
    if shear is not None:
        short = np.maximum(short, long / shear)
        lengths = symmetric_function(lengths, lambda x: np.maximum(x, short))
    if isotropic:
        mean = np.sqrt(long * short)
        return np.stack([mean, np.zeros_like(mean), mean], axis=-1)
    return lengths
