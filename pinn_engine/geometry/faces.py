"""Quad faces of hexahedra matched by their points, whichever cell and corner they are met
from (the polyMesh writer's faces, checkMesh's figures). NumPy alone."""

from __future__ import annotations

import numpy as np


def face_keys(quads: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Each quad's (m, 4) point ids sorted, packed as two int64 keys (the two lowest ids,
    the two highest): one face met from its two cells has the same keys, and sorting by
    them (``np.lexsort((high, low))``) is sorting by the four sorted ids, in a third of the
    time of a four-key sort."""
    key = np.sort(quads, axis=1).astype(np.int64)
    n = int(key[:, 3].max(initial=0)) + 1  # below 3e9 points: n * n fits in an int64
    return key[:, 0] * n + key[:, 1], key[:, 2] * n + key[:, 3]
