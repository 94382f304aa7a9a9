"""The correction's network, evaluated in NumPy: a branch net from a member's encoding to
the coefficients of the family's correction modes (the trunk: modes of the training
corrections, as in POD-DeepONet), a linear map plus a small tanh MLP; or the linear map
alone on the leading encoding components, their number and its ridge penalty chosen by
leave-one-out error (:func:`fit_linear`)."""

from __future__ import annotations

import numpy as np

HIDDEN = (64, 64)  # the MLP's hidden widths: a few dozen members need no more
# The ridge penalties tried by :func:`fit_linear` (each encoding coefficient has unit
# variance): from next to none to one that leaves only the members' mean correction
RIDGE_ALPHAS = np.logspace(-3, 4, 29)


def forward(params: dict[str, np.ndarray], z: np.ndarray) -> np.ndarray:
    """The mode coefficients (scaled) of encodings ``z`` (members, k) or (k,)."""
    out = z @ params["linear"].T + params["offset"]
    layers = sum(1 for k in params if k.startswith("w"))
    h = z
    for k in range(layers):
        h = h @ params[f"w{k}"].T + params[f"b{k}"]
        if k < layers - 1:
            h = np.tanh(h)
    return out + h if layers else out


def fit_linear(z: np.ndarray, c: np.ndarray) -> tuple[dict[str, np.ndarray], dict]:
    """The linear map from encodings ``z`` (members, k) to coefficients ``c`` (members, m)
    by ridge regression on the leading encoding components, their number and the penalty
    (``RIDGE_ALPHAS``) those whose leave-one-out error over the members is least (exact, by
    the hat matrix): as complex as members it has not seen support. All components of a
    whitened encoding of n members (n - 1 of them) give every penalty the mean's error, so
    the leading ones are what it can choose. Returns the penalty and count chosen too."""
    best = (np.inf, 0, 0.0)
    for k in range(1, z.shape[1] + 1):
        for alpha in RIDGE_ALPHAS:
            best = min(best, (_loo_error(z[:, :k], c, alpha), k, float(alpha)))
    _, k, alpha = best
    features = np.hstack([z[:, :k], np.ones((len(z), 1))])
    w = np.linalg.solve(features.T @ features + _penalty(k, alpha), features.T @ c)
    linear = np.zeros((c.shape[1], z.shape[1]))
    linear[:, :k] = w[:-1].T
    params = {"linear": linear, "offset": w[-1]}
    return params, {"ridge_alpha": alpha, "ridge_components": k}


def _penalty(k: int, alpha: float) -> np.ndarray:
    """The ridge penalty on ``k`` coefficients and an offset (not penalised)."""
    penalty = alpha * np.eye(k + 1)
    penalty[-1, -1] = 0.0
    return penalty


def _loo_error(z: np.ndarray, c: np.ndarray, alpha: float) -> float:
    """The summed squared leave-one-out error of the ridge regression of ``c`` on ``z``
    with penalty ``alpha``: each residual over one minus its hat-matrix diagonal."""
    features = np.hstack([z, np.ones((len(z), 1))])
    hat = features @ np.linalg.solve(
        features.T @ features + _penalty(z.shape[1], alpha), features.T
    )
    left = 1.0 - np.diag(hat)
    if np.any(left <= 1e-12):  # a member fitted exactly: its leave-one-out is undefined
        return np.inf
    return float((((c - hat @ c) / left[:, None]) ** 2).sum())
