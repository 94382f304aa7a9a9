"""The shear that turns a grid's lines onto a wall's normals (SPEC 7's ``--orthogonal``), as
the 2D orthogonal start (``starts.orthogonal``) and the six-faced one (``hexa.orthogonal``)
both make their sheared candidate: each line leaving the wall moves by its first node's
offset from the normal times ``w(s) / w(s_1)``, ``w(s) = s (1 - s / R)^2`` (s the line's
parameter from the wall, s_1 its first row's): it leaves along the normal and bends back to
its own line a third of the way across (where ``w`` peaks), not within a cell."""

from __future__ import annotations

import numpy as np

# R: across the domain, or half of it when the opposite wall is sheared too (the two shears
# must not overlap), keyed by whether it is
SHEAR_REACH = {False: 1.0, True: 0.5}


def shear_weights(s: np.ndarray, opposite_sheared: bool) -> np.ndarray:
    """``w(s) / w(s_1)`` of the parameters ``s`` (rows from the wall first, row 0 on it):
    1 on the first row off the wall, 0 on the wall and from R on."""
    reach = SHEAR_REACH[opposite_sheared]
    w = np.where(s < reach, s * (1 - s / reach) ** 2, 0.0)
    return w / np.maximum(w[1:2], 1e-300)
