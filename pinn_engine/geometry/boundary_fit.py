"""Boundary fits (paper section 3.1): side parameter t in [0, 1] -> (x, y) in the working frame.

Every fit uses the same parameter, the arc-length fraction along the side polyline, so that
auxiliary-line coordinates (SPEC 2) and boundary samples agree.
"""

from __future__ import annotations

import numpy as np

from pinn_engine.errors import MissingExtraError
from pinn_engine.geometry.boundary import SIDES, Boundary

TREE_SAMPLES_PER_SIDE = 256


class ArcLengthFit:
    """Exact linear interpolation of the side polylines: samples lie on the input boundary."""

    def __init__(self, boundary: Boundary) -> None:
        self.sides = {s: boundary.side(s) for s in SIDES}

    def sample(self, side: str, t: np.ndarray) -> np.ndarray:
        return self.sides[side].at(t)


class DecisionTreeFit:
    """The paper's fit: a ``DecisionTreeRegressor`` from t to (x, y) per side.

    Trained on the side's vertices plus arc-length resamples (so a two-point side still gets
    enough control points); piecewise constant, so its samples sit near, not on, the boundary.
    """

    def __init__(self, boundary: Boundary, random_state: int = 0) -> None:
        try:  # only the paper preset needs it (0.5 s to import)
            from sklearn.tree import DecisionTreeRegressor
        except ModuleNotFoundError as exc:
            raise MissingExtraError("the tree boundary fit (the paper preset's)", "paper") from exc

        self.trees = {}
        for s in SIDES:
            line = boundary.side(s)
            t = np.union1d(line.t, np.linspace(0.0, 1.0, TREE_SAMPLES_PER_SIDE))
            tree = DecisionTreeRegressor(random_state=random_state)
            self.trees[s] = tree.fit(t[:, None], line.at(t))

    def sample(self, side: str, t: np.ndarray) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return self.trees[side].predict(t.reshape(-1, 1)).reshape(*t.shape, 2)


class SplineFit:
    """C2 cubic spline through the side vertices in the arc-length parameter.

    Gives the smooth boundary derivatives that the hard-constrained PINN needs in its
    Winslow residual; the grid itself is still placed on the exact polyline.
    """

    def __init__(self, boundary: Boundary) -> None:
        from scipy.interpolate import CubicSpline  # only the hard-boundary network needs it

        self.splines = {}
        for s in SIDES:
            line = boundary.side(s)
            bc = "not-a-knot" if len(line.t) > 3 else "natural"
            self.splines[s] = CubicSpline(line.t, line.points, bc_type=bc)

    def sample(self, side: str, t: np.ndarray, nu: int = 0) -> np.ndarray:
        return self.splines[side](np.asarray(t, dtype=float), nu)


FITS = {"arclength": ArcLengthFit, "tree": DecisionTreeFit}


def make_fit(name: str, boundary: Boundary) -> ArcLengthFit | DecisionTreeFit:
    """Build the boundary fit called ``name`` ("arclength" or "tree")."""
    try:
        return FITS[name](boundary)
    except KeyError:
        raise ValueError(f"unknown boundary fit {name!r}; use one of {sorted(FITS)}") from None
