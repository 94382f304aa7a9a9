"""The boundary pieces an adapted grid's nodes slide on, and an adapted grid's record."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from pinn_engine.adapt.nodes import NodeGraph


class Piece:
    """A boundary piece's curve: a not-a-knot spline through its unadapted nodes in arc
    length (a straight piece stays straight, a curve is followed to fourth order), and its
    nodes' unadapted arc lengths ``s``."""

    def __init__(self, ids: np.ndarray, points: np.ndarray) -> None:
        self.ids = ids
        steps = np.linalg.norm(np.diff(points[ids], axis=0), axis=1)
        self.s = np.concatenate([[0.0], np.cumsum(steps)])
        kind = "not-a-knot" if len(ids) > 3 else "natural"
        self.curve = CubicSpline(self.s, points[ids], bc_type=kind)


def pieces_of(graph: NodeGraph) -> list[Piece]:
    """The boundary pieces of ``graph`` on the curves of its unadapted nodes."""
    return [Piece(ids, graph.points) for ids in graph.pieces]


@dataclass
class Solved:
    """An adapted grid's unique nodes, its boundary pieces' arc lengths (in
    :func:`pieces_of`'s order) and the solves made."""

    points: np.ndarray
    params: list[np.ndarray]
    steps: int
