"""First-cell spacing on the patches of a six-faced domain (SPEC 7 on SPEC 11's patches).

``--spacing PATCH=H`` stretches the nodes along the direction that leaves the patch (i for
``imin``/``imax``, j for ``jmin``/``jmax``, k for ``kmin``/``kmax``) as 2D does: the lines
of that direction share a Vinokur stretching and each line's first intervals are scaled to
its own first spacing (``classical.spacing.line_parameters``), those spacings iterated
against the measured first edges of the grid the method produces until every first edge is H
within 1 % (2D's fit, ``classical.spacing.fit_first_spacings``). The shared stretching
matters more in 3D: a face line and the line next to it inside need different spacings (the
face's Floater parameters are not the interior's), and whole per-line stretchings then shift
their far nodes apart, leaning the thin cells off another patch into folds (the bend with
three spaced patches at 21^3 folded 1458 cells). The lines on the four faces around the
patch are lines of the same direction, so the face grids take the same distribution (the
faces stay conforming), and the volume follows by TFI at the parameters (:func:`tfi_at`), or
by the Winslow equations with the distribution's control terms (``controls``).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from pinn_engine.classical.spacing import fit_first_spacings, line_parameters
from pinn_engine.errors import InputError
from pinn_engine.hexa import volume

PATCH_AXIS = {  # each patch: the index direction leaving it, and which end it is
    "imin": (0, 0),
    "imax": (0, -1),
    "jmin": (1, 0),
    "jmax": (1, -1),
    "kmin": (2, 0),
    "kmax": (2, -1),
}
ROOM = 0.5  # H must be shorter than this fraction of the shortest edge leaving the patch


def leaving(g: np.ndarray, patch: str) -> tuple[np.ndarray, np.ndarray]:
    """The patch's nodes and the next layer's, each (na, nb, 3) over the other two
    indices in order."""
    axis, end = PATCH_AXIS[patch]
    moved = np.moveaxis(g, axis, 0)
    return moved[end], moved[1 if end == 0 else -2]


def first_edges(g: np.ndarray, patch: str) -> np.ndarray:
    """Length of the first grid edge leaving each node of the patch, (na, nb)."""
    wall, first = leaving(g, patch)
    return np.linalg.norm(first - wall, axis=-1)


def check_spacing(spacing: dict[str, float], boundary: np.ndarray) -> None:
    """Refuse an H that is not shorter than half the shortest edge leaving its patch (the
    four block edges along its direction, on the uniform boundary grid)."""
    for patch, h in spacing.items():
        axis, _ = PATCH_AXIS[patch]
        lines = np.moveaxis(boundary, axis, -2)[[0, 0, -1, -1], [0, -1, 0, -1]]
        room = float(np.linalg.norm(np.diff(lines, axis=1), axis=-1).sum(axis=1).min())
        if h >= ROOM * room:
            raise InputError(
                f"{{spacing}} {patch}={h:g}: the first edge must be shorter than half of the "
                f"shortest edge leaving {patch} ({ROOM * room:.4g})"
            )


def node_params(size: tuple[int, int, int], par: dict[str, np.ndarray]) -> np.ndarray:
    """Node parameters (ni, nj, nk, 3): along each direction, per line (indexed by the
    other two indices), the stretching of its patches' first spacings ``par`` (parameter
    units, (na, nb) per patch); uniform where neither end has one."""
    out = np.empty((*size, 3))
    for axis in range(3):
        low, high = (p for p, (a, _) in PATCH_AXIS.items() if a == axis)
        others = [size[a] for a in range(3) if a != axis]
        first, last = (None if p not in par else par[p].reshape(-1) for p in (low, high))
        t = line_parameters(size[axis], first, last, others[0] * others[1])
        out[..., axis] = np.moveaxis(t.reshape(*others, size[axis]), -1, axis)
    return out


def _along(g: np.ndarray, axis: int, common: np.ndarray, own: np.ndarray) -> np.ndarray:
    """Each line of ``g`` along ``axis`` (nodes at the parameters ``common``, the same for
    every line) re-sampled at its own parameters ``own`` (same shape as g[..., 0]),
    piecewise linearly: a node stays on the line's chords and in its order."""
    at = np.clip(np.searchsorted(common, own, side="right") - 1, 0, len(common) - 2)
    w = ((own - common[at]) / (common[at + 1] - common[at]))[..., None]
    lo = np.take_along_axis(g, at[..., None], axis=axis)
    hi = np.take_along_axis(g, at[..., None] + 1, axis=axis)
    return (1.0 - w) * lo + w * hi


def tfi_at(boundary: Callable[[np.ndarray], np.ndarray], params: np.ndarray) -> np.ndarray:
    """3D TFI at node parameters that differ from line to line. The Boolean sum interpolates
    consistently only when each direction's parameters are the same on every line, so: TFI
    at each direction's mean distribution, each line's nodes moved along it to their own
    parameters, and the six faces set to the face grids at the nodes' parameters."""
    common, spread = [], 0.0
    for axis in range(3):
        others = tuple(a for a in range(3) if a != axis)
        common.append(params[..., axis].mean(axis=others))
        spread = max(spread, float(np.ptp(params[..., axis], axis=others).max()))
    mean = np.stack(np.meshgrid(*common, indexing="ij"), axis=-1)
    faces = boundary(params)
    if spread == 0.0:  # every line has the same parameters: the Boolean sum at them
        g = volume.tfi(faces, params)
    else:
        g = volume.tfi(boundary(mean), mean)
        for axis in range(3):
            g = _along(g, axis, common[axis], params[..., axis])
    for axis in range(3):
        for end in (0, -1):
            at = tuple(end if a == axis else slice(None) for a in range(3))
            g[at] = faces[at]
    return g


def fit_params(
    evaluate: Callable[[np.ndarray], np.ndarray],
    spacing: dict[str, float],
    uniform: np.ndarray,
    start: dict[str, np.ndarray] | None = None,
) -> tuple[np.ndarray, np.ndarray, dict[str, np.ndarray]]:
    """Parameters whose grid ``evaluate(params)`` has first edges ``spacing[patch]`` within
    1 % at every node of those patches (their four corners aside), and that grid:
    2D's fit (``classical.spacing.fit_first_spacings``) on the patches' (na, nb) spacings.
    ``uniform`` (the TFI grid of uniform parameters) gives the first guess, H over the length
    of each line, unless ``start`` (a previous fit's per-line spacings) does. Returns
    (params, grid, spacings).
    """
    size = uniform.shape[:3]
    par = {} if start is None else {p: v.copy() for p, v in start.items()}
    for patch, h in spacing.items():
        if patch in par:
            continue
        axis, _ = PATCH_AXIS[patch]
        length = np.linalg.norm(np.diff(uniform, axis=axis), axis=-1).sum(axis=axis)
        par[patch] = h / np.maximum(length, h)
    return fit_first_spacings(
        evaluate, lambda par: node_params(size, par), first_edges, spacing, par, _inner
    )


def _inner(ratio: np.ndarray) -> np.ndarray:
    """A patch's (na, nb) ratios with its four corners set to 1 (left out of the fit)."""
    inner = ratio.copy()
    inner[[0, 0, -1, -1], [0, -1, 0, -1]] = 1.0
    return inner
