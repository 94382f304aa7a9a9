"""The faces a set of block edges leaves (SPEC 13): their corners, a face of other than four
corners cut into four-cornered blocks round a centre, and the layout's cost.

A convex face of 2m corners is cut by spokes from its centre to every other corner into m
blocks (a Y's hexagonal centre into three: a valence-3 centre); an odd count first gains a
corner at the middle of a long side; a triangle gets spokes to its three sides' middles.
A face of six corners may also be cut along a diagonal into two four-cornered blocks:
then no vertex inside it joins three blocks, where every grid line crossing the centre
turns by about 60 degrees, and the three-block junctions lie on the boundary instead. Both
forms go on to the search, which meshes them.
The cost of a layout is how far its blocks' corner angles are from right angles, plus a
price per block: the cheap ranking that the coarse grid's quality then refines.
"""

from __future__ import annotations

import numpy as np
from shapely.errors import GEOSException
from shapely.geometry import LineString, Point, Polygon

from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import turning_angles
from pinn_engine.multiblock.blocks import CORNER_TURN, polygon_faces
from pinn_engine.multiblock.graph import linework

BLOCK_PRICE = 20.0  # degrees of corner-angle deviation one block fewer is worth
INSIDE_TOL = 1e-9  # share of the diagonal a spoke may stray outside its face (rounding)
ROUND_OFF = 1e-9  # share of its size a named point's coordinate is 0 under: round-off
# (a disc's centre, (-7e-17, 9e-17), reads (0, 0))


class NoBlocking(Exception):
    """A layout that is no blocking: a face with a reflex corner, or too few corners."""


def faces_of(rings: list[np.ndarray], edges: list[np.ndarray]) -> tuple[list[np.ndarray], float]:
    """The faces' outlines (counter-clockwise, not closed) of ``rings`` cut by ``edges``, and
    the diagonal; NoBlocking when the edges cross or enclose a face with a hole."""
    try:
        lines = linework(rings, edges, [f"edge {k}" for k in range(len(edges))], "auto")
        faces = polygon_faces(lines)
    except (InputError, GEOSException) as exc:  # crossing edges; geometry shapely refuses
        raise NoBlocking(str(exc)) from exc
    return [np.asarray(f.exterior.coords)[:-1] for f in faces], lines.diagonal


def place(point: np.ndarray, size: float) -> str:
    """A point as a refusal names it: four significant figures, a coordinate under
    ROUND_OFF of ``size`` (of the thing it places) shown as 0."""
    x, y = np.where(np.abs(point) < ROUND_OFF * size, 0.0, point)
    return f"({x:.4g}, {y:.4g})"


def _at(face: np.ndarray) -> str:
    """The face named by its vertices' mean."""
    return f"the face at {place(face.mean(axis=0), float(np.ptp(face, axis=0).max()))}"


def corners_of(face: np.ndarray) -> np.ndarray:
    """Indices of the face's corners; NoBlocking if it turns the wrong way anywhere."""
    turns = turning_angles(face)
    if np.any(turns <= -CORNER_TURN):
        where = place(face[int(np.argmin(turns))], float(np.ptp(face, axis=0).max()))
        raise NoBlocking(f"a reflex corner at {where} is not cut")
    return np.flatnonzero(turns >= CORNER_TURN)


def _middle(face: np.ndarray, a: int, z: int) -> np.ndarray:
    """The point halfway (by length) along the face's outline from vertex a to vertex z."""
    walk = np.vstack([face[a:], face[: z + 1]]) if z <= a else face[a : z + 1]
    line = LineString(walk)
    return np.array(line.interpolate(0.5 * line.length).coords[0])


def _spoke_sets(face: np.ndarray, corners: np.ndarray) -> list[list[np.ndarray]]:
    """The ways to cut a face with ``corners`` into four-cornered blocks round its centre:
    each a list of spoke ends."""
    n = len(corners)
    points = face[corners]
    sides = [(corners[k], corners[(k + 1) % n]) for k in range(n)]
    if n == 3:
        return [[_middle(face, a, z) for a, z in sides]]
    if n % 2 == 0:
        return [list(points[p::2]) for p in (0, 1)]
    lengths = [LineString(np.vstack([points[k], points[(k + 1) % n]])).length for k in range(n)]
    out = []
    for k in np.argsort(lengths)[::-1][:2]:  # the two longest sides gain a middle corner
        ring = list(points[: k + 1]) + [_middle(face, *sides[k])] + list(points[k + 1 :])
        out += [ring[p::2] for p in (0, 1)]
    return out


def split_face(face: np.ndarray, corners: np.ndarray, diagonal: float) -> list[list[np.ndarray]]:
    """Candidate edge sets cutting a face of other than four corners into four-cornered
    blocks: spokes round its centre, and for six corners each diagonal between opposite
    corners; NoBlocking for fewer than three corners."""
    if len(corners) < 3:
        raise NoBlocking(f"{_at(face)} has {len(corners)} corners")
    polygon = Polygon(face)
    centre = face[corners].mean(axis=0)
    if not polygon.contains(Point(centre)):
        centre = np.array(polygon.representative_point().coords[0])
    grown = polygon.buffer(INSIDE_TOL * diagonal)
    cuts = [[np.array([centre, e]) for e in ends] for ends in _spoke_sets(face, corners)]
    if len(corners) == 6:
        cuts += [[face[corners[[k, k + 3]]]] for k in range(3)]
    return [c for c in cuts if all(grown.contains(LineString(e)) for e in c)]


def _block_cost(face: np.ndarray, corners: np.ndarray) -> float:
    """A four-cornered block's cost: its corner angles' distances from 90, and its price."""
    return float(np.abs(90.0 - turning_angles(face)[corners]).sum()) + BLOCK_PRICE


def layout_cost(rings: list[np.ndarray], edges: list[np.ndarray]) -> float:
    """How far the blocks' corner angles are from 90 degrees (summed) plus BLOCK_PRICE a
    block; NoBlocking if a face is not four-cornered."""
    faces, _ = faces_of(rings, edges)
    cost = 0.0
    for face in faces:
        corners = corners_of(face)
        if len(corners) != 4:
            raise NoBlocking(f"{_at(face)} has {len(corners)} corners")
        cost += _block_cost(face, corners)
    return cost


def completions(
    rings: list[np.ndarray], edges: list[np.ndarray]
) -> list[tuple[list[np.ndarray], float]]:
    """``edges`` with every face of other than four corners cut into four-cornered blocks,
    and each such layout's cost (``layout_cost``): each face every way it can be cut (round
    its centre, along a diagonal), in every combination; NoBlocking where a face cannot be
    cut."""
    faces, diagonal = faces_of(rings, edges)
    layouts = [(list(edges), 0.0)]
    for face in faces:
        corners = corners_of(face)
        if len(corners) == 4:
            layouts = [(done, cost + _block_cost(face, corners)) for done, cost in layouts]
            continue
        cuts = []
        for cut in split_face(face, corners, diagonal):
            try:
                cuts.append((layout_cost([face], cut), cut))
            except NoBlocking:
                continue
        if not cuts:
            raise NoBlocking(
                f"{_at(face)} with {len(corners)} corners cannot be cut round its centre"
            )
        layouts = [(done + cut, cost + extra) for done, cost in layouts for extra, cut in cuts]
    return layouts
