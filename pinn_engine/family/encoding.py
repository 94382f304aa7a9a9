"""What a family model reads of a member: its boundary nodes, reduced by the principal
components of the training members' (the branch input of a DeepONet, as in MeshONet)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

# The encoding keeps the components that carry all but this share of the boundary nodes'
# variance over the training members (the rest is rounding), at most one fewer than members
KEPT_VARIANCE = 1e-10
# A member lies in the family's range where its leading coefficients (those carrying all but
# RANGE_VARIANCE of the variance) are no farther from the mean, in units of their spread,
# than the farthest training member's by RANGE_MARGIN of it, and the rest of its vector no
# larger than twice the largest training member's rest
RANGE_VARIANCE = 1e-3
RANGE_MARGIN = 0.25


def boundary_vector(grid: np.ndarray, kind: str, drawn: np.ndarray | None = None) -> np.ndarray:
    """The boundary nodes of a member's grid (nj, ni, 2) as one vector: the four sides of a
    four-sided grid, the wall row (j = 0) of a body's (its far field follows from it); of a
    multi-block member's stacked nodes (M, 2) those at ``drawn``, its blocks' sides."""
    if kind == "blocks":
        return grid[drawn].ravel()
    if kind == "body":
        return grid[0].ravel()
    return np.concatenate(
        [grid[0].ravel(), grid[-1].ravel(), grid[:, 0].ravel(), grid[:, -1].ravel()]
    )


@dataclass
class Encoding:
    """The family's boundary encoding: mean vector, principal axes, the coefficients' scale
    (their standard deviation over the members), the number of ``leading`` axes and the
    largest norm of a training member's leading coefficients (``reach``), the largest share
    of a training member's vector the leading axes leave out (its ``rest``), and the range
    of the training members' scaled coefficients (``low``, ``high``)."""

    mean: np.ndarray
    axes: np.ndarray
    scale: np.ndarray
    leading: int
    reach: float
    rest: float
    low: np.ndarray | None = None
    high: np.ndarray | None = None

    @classmethod
    def fit(cls, vectors: np.ndarray) -> Encoding:
        """The encoding of the training members' boundary vectors (one a row)."""
        mean = vectors.mean(axis=0)
        _, s, vt = np.linalg.svd(vectors - mean, full_matrices=False)
        energy = np.cumsum(s**2) / max(float((s**2).sum()), np.finfo(float).tiny)
        keep = int(np.searchsorted(energy, 1 - KEPT_VARIANCE) + 1)
        keep = max(1, min(keep, len(vectors) - 1, len(s)))
        leading = int(np.searchsorted(energy, 1 - RANGE_VARIANCE) + 1)
        axes = vt[:keep]
        coeffs = (vectors - mean) @ axes.T
        scale = np.maximum(coeffs.std(axis=0), np.finfo(float).eps)
        enc = cls(mean, axes, scale, min(leading, keep), 0.0, 0.0)
        enc.low, enc.high = (coeffs / scale).min(axis=0), (coeffs / scale).max(axis=0)
        enc.reach = max(enc.distance(v) for v in vectors)
        enc.rest = max(enc.rest_of(v) for v in vectors)
        return enc

    def encode(self, vector: np.ndarray) -> np.ndarray:
        """The scaled coefficients of ``vector``: the network's input."""
        return (self.axes @ (vector - self.mean)) / self.scale

    def clamped(self, vector: np.ndarray) -> np.ndarray:
        """:meth:`encode` of ``vector``, each coefficient clamped to the training members'
        range: a linear map is not extrapolated beyond the members it was fitted on."""
        return np.clip(self.encode(vector), self.low, self.high)

    def distance(self, vector: np.ndarray) -> float:
        """The norm of ``vector``'s scaled leading coefficients: its distance from the
        family's mean in units of the members' spread."""
        return float(np.linalg.norm(self.encode(vector)[: self.leading]))

    def rest_of(self, vector: np.ndarray) -> float:
        """The share of ``vector`` (relative to the mean vector's norm) that the leading
        axes leave out."""
        centred = vector - self.mean
        lead = self.axes[: self.leading]
        left = float(np.linalg.norm(centred - lead.T @ (lead @ centred)))
        return left / max(float(np.linalg.norm(self.mean)), 1e-300)

    def in_range(self, vector: np.ndarray) -> bool:
        """Whether ``vector`` lies in the family's range (``RANGE_MARGIN``)."""
        near = self.distance(vector) <= (1 + RANGE_MARGIN) * self.reach
        return near and self.rest_of(vector) <= 2 * self.rest + 1e-12

    def state(self) -> dict:
        names = ("mean", "axes", "scale", "leading", "reach", "rest", "low", "high")
        return {k: getattr(self, k) for k in names}
