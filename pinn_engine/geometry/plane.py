"""The plane a boundary lies in: user 3D points to in-plane (u, v) coordinates and back.

The engine meshes in (u, v); the routes hand back points lifted into the user's 3D frame.
A boundary in a plane z = const keeps u = x, v = y exactly (the common case, bit for bit as
before); any other plane gets u along the plane's direction nearest to x and v nearest to +z
(else +y), so a boundary drawn in the XZ plane has its "bottom" at low z.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from pinn_engine.errors import InputError

# Points may lie this far off their plane (relative to the boundary's size, or to the
# coordinates' magnitude for data far from the origin): CAD and float32 noise.
PLANE_TOL = 1e-6


@dataclass(frozen=True)
class Plane:
    """``origin + u * axes[0] + v * axes[1]``; ``axes`` are orthonormal (2, 3)."""

    origin: np.ndarray
    axes: np.ndarray

    @classmethod
    def horizontal(cls, z: float = 0.0) -> Plane:
        return cls(np.array([0.0, 0.0, z]), np.eye(3)[:2])

    @property
    def normal(self) -> np.ndarray:
        return np.cross(self.axes[0], self.axes[1])

    @property
    def is_horizontal(self) -> bool:
        return bool(np.array_equal(self.axes, np.eye(3)[:2]))

    @classmethod
    def fit(cls, points: np.ndarray, source: str | None = None) -> Plane:
        """The plane of ``points`` (n, 3); an error saying how far from planar they are."""
        p = np.asarray(points, dtype=float)
        limit = _tolerance(p)
        z = p[:, 2]
        if float(np.ptp(z)) <= limit:  # z = const: u, v are x, y exactly
            return cls.horizontal(float(np.median(z)))
        centre = p.mean(axis=0)
        normal = np.linalg.svd(p - centre, full_matrices=False)[2][2]
        off = float(np.abs((p - centre) @ normal).max())
        if off > limit:
            size = float(np.linalg.norm(np.ptp(p, axis=0)))
            raise InputError(
                f"is not planar: its points lie up to {off:.3g} ({off / size:.2%} "
                "of its size) off their best-fit plane; the domain must lie in "
                "one plane",
                source,
            )
        return cls(centre, in_plane_axes(normal))

    def to_plane(self, points: np.ndarray, source: str | None = None) -> np.ndarray:
        """In-plane (u, v) of ``points`` (n, 3), which must lie in the plane; (n, 2) points
        are taken as (u, v) already when the plane is horizontal."""
        p = np.asarray(points, dtype=float)
        if p.shape[1] == 2:
            if not self.is_horizontal:
                raise InputError(
                    "has only x, y coordinates but the boundary is not in a "
                    "plane z = const; give x, y, z",
                    source,
                )
            return p
        off = float(np.abs((p - self.origin) @ self.normal).max()) if len(p) else 0.0
        if off > _tolerance(p, extra=self.origin):
            raise InputError(
                f"lies up to {off:.3g} off the boundary's plane; it must lie in "
                "the plane of the boundary",
                source,
            )
        if self.is_horizontal:
            return np.ascontiguousarray(p[:, :2])
        return (p - self.origin) @ self.axes.T

    def lift(self, uv: np.ndarray) -> np.ndarray:
        """User 3D points of in-plane ``uv`` (..., 2)."""
        uv = np.asarray(uv, dtype=float)
        if self.is_horizontal:
            return np.concatenate([uv, np.full(uv.shape[:-1] + (1,), self.origin[2])], axis=-1)
        return self.origin + uv @ self.axes


def _tolerance(p: np.ndarray, extra: np.ndarray | None = None) -> float:
    finite = p[np.isfinite(p).all(axis=1)]
    if not len(finite):
        return 0.0
    size = float(np.linalg.norm(np.ptp(finite, axis=0)))
    magnitude = float(np.abs(finite).max())
    if extra is not None:
        magnitude = max(magnitude, float(np.abs(extra).max()))
    return max(PLANE_TOL * size, PLANE_TOL * magnitude)


def in_plane_axes(normal: np.ndarray) -> np.ndarray:
    """u: the in-plane direction nearest +x (+y if the plane is nearly normal to x);
    v: perpendicular to it in the plane, pointing up (+z, else +y)."""
    n = normal / np.linalg.norm(normal)
    eye = np.eye(3)
    ref = eye[0] if abs(n[0]) < 0.9 else eye[1]
    u = ref - (ref @ n) * n
    u /= np.linalg.norm(u)
    v = np.cross(n, u)
    up = eye[2] if abs(v[2]) > 1e-12 else eye[1]
    if v @ up < 0:
        v = -v
    return np.stack([u, v])
