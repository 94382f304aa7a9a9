"""Loss terms of the paper (section 3.2): Winslow residual, boundary term, auxiliary-line data term.

All terms are mean squares (the paper writes sums; a mean keeps the weights independent of
the number of sampled points). Jets are (6, B, 2) tensors: channels of ``jet.V..ETAETA``
for the x and y coordinates; the 3D residual's are (10, B, 3), channels of ``jet.nd``.
"""

from __future__ import annotations

import torch

from pinn_engine.neural.jet import ETA, ETAETA, XI, XIETA, XIXI
from pinn_engine.neural.jet.nd import pairs, second
from pinn_engine.quality import (
    QUALITY_BARRIER_WEIGHT,
    QUALITY_MEAN_WEIGHT,
    QUALITY_MIN_SINE,
    QUALITY_TAU,
)


def winslow_residual(jet: torch.Tensor, controls: torch.Tensor | None = None) -> torch.Tensor:
    """e1, e2 of paper eq. 13, with alpha, beta, gamma of eq. 8: shape (B, 2).

    beta is x_xi x_eta + y_xi y_eta (the paper misprints it as x_xi x_eta + y_xi x_eta).
    ``controls`` (B, 2): control functions (P, Q) whose terms P x_xi + Q x_eta are added
    (the body grids' elliptic controls, bodygrid.smoothed_controls).
    """
    r_xi, r_eta = jet[XI], jet[ETA]
    alpha = (r_eta * r_eta).sum(dim=-1, keepdim=True)  # eq. 8
    beta = (r_xi * r_eta).sum(dim=-1, keepdim=True)
    gamma = (r_xi * r_xi).sum(dim=-1, keepdim=True)
    e = alpha * jet[XIXI] - 2 * beta * jet[XIETA] + gamma * jet[ETAETA]
    if controls is not None:
        e = e + controls[:, :1] * r_xi + controls[:, 1:] * r_eta
    return e


def scaled_winslow_residual(
    jet: torch.Tensor, controls: torch.Tensor | None = None
) -> torch.Tensor:
    """e1, e2 of eq. 13 divided by (alpha + gamma)^(3/2): the same equations, measured
    relative to the local cell size (the raw residual is cubic in the map's derivatives, so
    a few points at a sharp feature dominate it and shrinking cells there lowers it)."""
    scale = (jet[XI].pow(2) + jet[ETA].pow(2)).sum(dim=-1, keepdim=True)  # alpha + gamma
    return winslow_residual(jet, controls) / scale.pow(1.5)


def cofactors_3d(first: torch.Tensor) -> torch.Tensor:
    """Cofactors C (3, 3, B) of the metric tensor from the first derivatives (3, B, 3):
    C_mn = (x_{m+1} x x_{m+2}) . (x_{n+1} x x_{n+2}) (indices mod 3)."""
    a = torch.stack([torch.linalg.cross(first[(m + 1) % 3], first[(m + 2) % 3]) for m in range(3)])
    return torch.einsum("mbk,nbk->mnb", a, a)


def parameter_controls_3d(jet: torch.Tensor, params: torch.Tensor) -> torch.Tensor:
    """Control terms P (B, 3) that keep node parameters s (a spacing's distribution) in the
    3D Winslow equations: the grid x(s) with s harmonic in x gives
    ``L x + sum_m P_m x_m = 0`` with ``P = -T^-1 (L s_1, L s_2, L s_3)``, T_km = ds_k/dxi_m,
    L = sum_mn C_mn d_mn (Spekreijse 1995; hexa/controls.py is the discrete form). ``jet``
    and ``params``: (10, B, 3) jets of the map and of s."""
    c = cofactors_3d(jet[1:4])
    laplace = sum(
        (1 if m == n else 2) * c[m, n, :, None] * params[second(m, n, 3)] for m, n in pairs(3)
    )
    t = params[1:4].permute(1, 2, 0)  # (B, k, m) = ds_k / dxi_m
    return -torch.linalg.solve(t, laplace)


def winslow_residual_3d(
    jet: torch.Tensor, scaled: bool = False, controls: torch.Tensor | None = None
) -> torch.Tensor:
    """The 3D Winslow equations' residual sum_mn C_mn x_{xi_m xi_n} (B, 3) from a jet
    (10, B, 3) of ``jet.nd``'s channels; C is the cofactor matrix of the metric tensor
    g_mn = x_m . x_n (:func:`cofactors_3d`; hexa/volume.py's discrete equations). With
    ``controls`` P (B, 3) the terms sum_m P_m x_m are added (:func:`parameter_controls_3d`).
    ``scaled``: divided by (sum_m |x_m|^2)^(5/2), as :func:`scaled_winslow_residual` in 2D
    (the residual is of fifth order in lengths)."""
    r = jet[1:4]
    c = cofactors_3d(r)
    e = sum((1 if m == n else 2) * c[m, n, :, None] * jet[second(m, n, 3)] for m, n in pairs(3))
    if controls is not None:
        e = e + sum(controls[:, m, None] * r[m] for m in range(3))
    if scaled:
        e = e / r.pow(2).sum(dim=(0, 2))[:, None].pow(2.5)
    return e


def loss_eqns(
    jet: torch.Tensor, scaled: bool = False, controls: torch.Tensor | None = None
) -> torch.Tensor:
    """L_eqns of paper eq. 11: mean of e1^2 + e2^2 over the collocation points (of the
    scaled residual if ``scaled``; with the terms of ``controls``, :func:`winslow_residual`)."""
    residual = scaled_winslow_residual if scaled else winslow_residual
    return residual(jet, controls).pow(2).sum(dim=-1).mean()


def loss_points(pred: torch.Tensor, target: torch.Tensor) -> torch.Tensor:
    """Mean of |x - x*|^2 + |y - y*|^2 over the points (axis -2): the boundary term e3, e4
    (eq. 12, 13) of one side, or of each side for stacked (sides, B, 2) inputs."""
    return (pred - target).pow(2).sum(dim=-1).mean(dim=-1)


def loss_data(pred: torch.Tensor, target: torch.Tensor) -> torch.Tensor:
    """L_data of paper eq. 10: the auxiliary-line data term on the line samples."""
    return loss_points(pred, target)


def nearest_on_line(points: torch.Tensor, line: torch.Tensor) -> torch.Tensor:
    """The nearest point (B, 2) of the polyline ``line`` (m, 2) to each of ``points`` (B, 2),
    differentiable in ``points`` (the nearest segment is chosen without gradient). The
    auxiliary-line term of ``--objective quality`` is the squared distance to it: unlike
    :func:`loss_data`, it lets the grid's curve through a line's (xi, eta) slide along the
    drawn line."""

    def foot(a: torch.Tensor, ab: torch.Tensor, p: torch.Tensor) -> torch.Tensor:
        along = ((p - a) * ab).sum(dim=-1) / (ab * ab).sum(dim=-1).clamp_min(1e-300)
        return a + along.clamp(0.0, 1.0)[..., None] * ab

    a, ab = line[:-1], line[1:] - line[:-1]
    with torch.no_grad():
        nearest = (foot(a, ab, points[:, None]) - points[:, None]).pow(2).sum(dim=-1).argmin(1)
    return foot(a[nearest], ab[nearest], points)


def loss_orthogonal(leave: torch.Tensor, tangent: torch.Tensor) -> torch.Tensor:
    """Mean squared cosine of the angle between the map's derivative ``leave`` (B, 2) leaving
    a side that is to be orthogonal (SPEC 7) and the side's tangent (B, 2) there: zero where
    grid lines leave it at 90 degrees. The body PINN passes x_eta and x_xi at interior
    points: the same cosine between the two grid lines, everywhere."""
    dot = (leave * tangent).sum(dim=-1)
    return (dot.pow(2) / (leave.pow(2).sum(dim=-1) * tangent.pow(2).sum(dim=-1))).mean()


def total_loss(
    l_eqns: torch.Tensor,
    l_bcs: torch.Tensor,
    l_data: torch.Tensor,
    lambda1: float,
    lambda2: float,
    l_orth: torch.Tensor | float = 0.0,
    lambda_orth: float = 0.0,
) -> torch.Tensor:
    """Paper eq. 9: Loss = L_eqns + lambda1 L_bcs + lambda2 L_data (+ lambda_orth L_orth)."""
    return l_eqns + lambda1 * l_bcs + lambda2 * l_data + lambda_orth * l_orth


def annealed_lambda(
    grads_eqns: list[torch.Tensor], grads_bcs: list[torch.Tensor], lambda1: float, momentum: float
) -> float:
    """Learning-rate annealing weight (Wang, Teng, Perdikaris 2020, Algorithm 1).

    lambda_hat = max |grad L_eqns| / mean |grad (lambda1 L_bcs)| over the network weights;
    returns the moving average momentum * lambda1 + (1 - momentum) * lambda_hat.
    """
    top = max(float(g.abs().max()) for g in grads_eqns)
    mean = torch.cat([(lambda1 * g).abs().flatten() for g in grads_bcs]).mean()
    lambda_hat = top / max(float(mean), 1e-300)
    return momentum * lambda1 + (1 - momentum) * lambda_hat


def corner_angles(grid: torch.Tensor, orientation: float) -> torch.Tensor:
    """Interior angle (radians) at the four corners of every cell of a grid (nj, ni, 2):
    (4, nj - 1, ni - 1), in (0, 2 pi); above pi at a reflex corner (a folded cell)."""
    p = [grid[:-1, :-1], grid[:-1, 1:], grid[1:, 1:], grid[1:, :-1]]  # counter-clockwise
    angles = []
    for k in range(4):
        a, b = p[(k + 1) % 4] - p[k], p[k - 1] - p[k]
        cross = orientation * (a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0])
        angles.append(torch.pi + torch.atan2(-cross, -(a * b).sum(dim=-1)))  # smooth to 2 pi
    return torch.stack(angles)


def loss_quality(
    theta: torch.Tensor, tau: float = QUALITY_TAU, mean_weight: float = QUALITY_MEAN_WEIGHT
) -> torch.Tensor:
    """Cell-quality term of ``--objective quality`` from the corner angles ``theta`` of a
    grid's cells (:func:`corner_angles`): a soft maximum (log-sum-exp at temperature ``tau``
    radians, 1 degree) of all of them, which pulls the worst cell's largest angle down, plus
    ``mean_weight`` times the mean over cells of each cell's soft largest angle (the mean
    MaxIncludedAngle), plus ``QUALITY_BARRIER_WEIGHT`` times a barrier on corners whose sine
    is below ``QUALITY_MIN_SINE`` (nearly flat, reflex: folded), which unfolds cells."""
    soft_max = tau * torch.logsumexp(theta.flatten() / tau, dim=0)
    cell_max = tau * torch.logsumexp(theta / tau, dim=0)
    barrier = torch.relu(QUALITY_MIN_SINE - torch.sin(theta)).pow(2).sum()
    return soft_max + mean_weight * cell_max.mean() + QUALITY_BARRIER_WEIGHT * barrier
