"""The correction's network, evaluated in NumPy: a branch net from a member's encoding to
the coefficients of the family's correction modes (the trunk: modes of the training
corrections, as in POD-DeepONet), a linear map plus a small tanh MLP."""

from __future__ import annotations

import numpy as np

HIDDEN = (64, 64)  # the MLP's hidden widths: a few dozen members need no more


def forward(params: dict[str, np.ndarray], z: np.ndarray) -> np.ndarray:
    """The mode coefficients (scaled) of encodings ``z`` (members, k) or (k,)."""
    h = z
    layers = sum(1 for k in params if k.startswith("w"))
    for k in range(layers):
        h = h @ params[f"w{k}"].T + params[f"b{k}"]
        if k < layers - 1:
            h = np.tanh(h)
    return h + z @ params["linear"].T + params["offset"]
