"""O-grids and C-grids around a body (SPEC 9) by tfi, elliptic and pinn.

Index conventions (SPEC 9). O-grid: j = 0 on the body, j = nj - 1 on the far field, i once
around the body counter-clockwise from the trailing edge, column ni - 1 repeating column 0
(the seam). C-grid: j = 0 runs along the lower wake cut from the outflow to the trailing
edge, around the body (lower surface, leading edge, upper surface) and back along the upper
wake cut; the cut is straight, leaves the trailing edge (a blunt base's middle: the lower and
upper halves of the base are wall) in +x, and its lower and upper nodes coincide pairwise
(node (i, 0) is node (ni - 1 - i, 0)).

Nodes on j = 0 are placed once, for every method (:func:`layout`): around the body by a
two-sided Vinokur stretching on each surface, fine at the leading and trailing edges;
along the wake by a one-sided stretching from the trailing edge. The C-grid's far field is
the circle for x up to mid-chord, continued by the lines y = y_c -+ R to the outflow line
x = x_c + R (patch ``outflow``: the columns i = 0 and i = ni - 1).

The wall-normal distribution: the first edge off the wall is ``wall_spacing``
(``--spacing bottom=H``; default half the mean tangential spacing on the body), growing by a
one-sided Vinokur stretching. Every stretching here is the four-sided grids' (SPEC 7,
spacing.py), with its end intervals made exact (:func:`spacing.exact_stretch`).

The reference grid (:func:`reference_grid`, wall-orthogonal, algebraic) is marched off the
wall along the rows' own normals (:func:`march`; the first row exactly along the wall's
normals), its last row projected onto the far field; that projection fixes the far-field
nodes for every method. Then:

- ``tfi``: the two-boundary TFI between the body and far-field nodes (straight columns,
  each stretched to the first edge); not orthogonal at the wall.
- ``elliptic``: Winslow's equations with the control functions that make the reference an
  exact solution at the wall, smoothed away from it (:func:`smoothed_controls`), by relaxed
  point-Jacobi sweeps from the reference (:func:`jacobi`), periodic across the O-grid's
  seam, the C-grid's cut held on its line, the first rows held (first edge and wall angle
  exact); the sweeps stop at the last state no worse than the reference (:func:`elliptic`).
- ``pinn``: kinds/body/problem.py: a network of (cos 2 pi xi, sin 2 pi xi, eta) for the O-grid
  (periodic in xi exactly), a correction vanishing on j = 0 and j = nj - 1 (and on the
  C-grid's outflow columns), added to the elliptic grid and trained on the same equations.
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass

import numpy as np

from pinn_engine.bodies import marching
from pinn_engine.bodies.airfoil import Body, FarField
from pinn_engine.classical.elliptic import winslow_coefficients, winslow_operator
from pinn_engine.classical.spacing import exact_stretch
from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import arc_lengths
from pinn_engine.geometry.spline import CurveSpline
from pinn_engine.quality import guard_figures, no_worse, worst_non_orthogonality

TOPOLOGIES = ("o", "c")
# Set by hand against Construct2D, not swept (docs/tuning.md). Nodes on the body (:func:`layout`),
# in units of the mean tangential spacing on it: the leading edge's (fine where the curvature is),
# a sharp trailing edge's (coarser, the edge is straight), a blunt base's at most 0.1 of its height
# (ten intervals across it); the default first edge off the wall (cells of aspect 2); the C-grid's
# wake nodes a side as a share of ni; at least 3 intervals on either surface.
LE_SPACING, TE_SPACING, BLUNT_TE_SPACING = 0.2, 0.6, 0.1
# A blunt base (drawn straight, SPEC 9) takes at most this share of the wall's intervals (an
# eighth: a coarse grid keeps most of its nodes on the surface, whose curvature needs them).
MAX_BASE_SHARE = 0.125
WALL_SPACING = 0.5
# The wall is the spline through the file's points, held within this share of the chord of
# the drawn polyline (half SPEC 9's 0.1 %: the polyline between the parameters' points)
WALL_HOLD = 5e-4
WAKE_SHARE = 0.14
MIN_SURFACE_INTERVALS = 3
# The marched rows end this many chords inside the far field (room for the blend onto it); the
# C-grid's outflow needs this many chords of wake behind the trailing edge; the first edge at the
# outflow is this share of the far field's mean row spacing (R / (nj - 1)).
FAR_GAP = 0.25
MIN_WAKE = 0.1
OUTFLOW_FIRST = 0.5
# Marching (:func:`march`): the normals' Laplacian smoothing a pass, reached with distance d as
# 1 - exp(-d / NORMAL_REACH chords); the O-grid's tangential slide towards equal spacing.
NORMAL_SMOOTHING, TANGENT_SMOOTHING, NORMAL_REACH = 0.5, 0.1, 0.3
# The row smoothing per unit of a row's shrink, capped at ROW_SMOOTHING_MAX.
CONCAVE_SMOOTHING = 2.0
ROW_SMOOTHING_MAX = 0.5
# Sub-steps: at most SUBSTEP of the distance in which converging lines would meet and at most
# SUBSTEP / SPACING_RATE of the row's smallest spacing (:func:`_substeps`); MAX_SUBSTEPS bounds
# a row's time.
SUBSTEP = 0.5
SPACING_RATE = {"o": 0.5, "c": 1.0}
MAX_SUBSTEPS = 200
# A row turns at a corner (no tangent: its nodes leave along the bisector) by more than this many
# degrees between two segments; smooth walls turn by a few degrees a node.
CORNER_TURN = 45.0
MARCH_PASSES = 2
# The rows' spacing is smoothed by this weight a pass (times the reach 1 - exp(-d / NORMAL_REACH
# chords)), every sub-step: crowded columns spread out along the row (:func:`redistribute`).
SPREAD = 0.5
# A blunt C-grid's cut leaves the base's middle into two concave corners, around which the normals
# and rows are smoothed from the wall on (as hyperbolic generators do), with a weight 1 at the
# middle decaying with a wall node's distance d as exp(-d / reach), the reach CORNER_REACH
# half-base heights. The base takes C_BASE_INTERVALS intervals, two a side of the cut.
CORNER_REACH = 6.0
C_BASE_INTERVALS = 4
# A blunt C-grid's default first layer is at most this share of the base's interval: the base's
# rows march down the wake, whose first interval is the base's (on six blunt NACA sections at
# 41 x 21 to 251 x 81, 0.5 left worst cells of 148 at the base's corners and 0.125 reached
# 161-177 at 41 x 21; 0.25 gives 140-160)
BASE_FIRST = 0.25
# A round trailing edge (no corner) faces downstream like a base where its wall's normal lies
# within ROUND_FACING degrees of +x (BASE_CORNER, the turn that makes a base's corner): its C-grid
# is smoothed as around a base of that height, halved up to ROUND_HALVINGS times while the
# reference folds (the full height gave a circle's worst cell 152.8 degrees; none, 175.2)
ROUND_FACING = 45.0
ROUND_HALVINGS = 3
# The reach is at most CORNER_REACH_MAX chords (a 2 % base's): 0.7 chords on a 23 % base smoothed
# the rows over the aft surface from the wall on, folding them at its convex corners (tuning.md)
CORNER_REACH_MAX = 0.06
# C-grid: behind the thickest point the columns turn vertical within 0.02 chords of the wall (the
# aft normals lean downstream and would overtake the wake's columns), half way at the thickest
# point, fully at the trailing edge (REAR_TURN_START of the turn); a base's columns within the
# larger of that and the base's height (turned sooner, a tall base's columns ran along it).
REAR_TURN = 0.02
REAR_TURN_START = 0.5
# The turn's remainder decays as exp(-d / REAR_REACH chords): a column turned part way drifts
# sideways with d and crossed a fully turned neighbour 1e-3 chords off (1 to 2 chords out); 1 and 3
# raised the sharp C-grids' non-orthogonality or the worst angle (docs/tuning.md)
REAR_REACH = 2.0
# The marched rows turn into straight lines to the far field between 1 and 3 chords from the wall
# (C-grid; near the body the marched lines, far off the straight ones); the O-grid's projection onto
# the far field is blended in as (distance share) ** O_BLEND_POWER (3: the inner rows stay marched,
# the outer ones end on the far field smoothly).
BLEND_START, BLEND_END = 1.0, 3.0  # chords
O_BLEND_POWER = 3
# Elliptic (:func:`elliptic`): the exact controls are kept at the wall and smoothed away from it
# with weight exp(-0.05 (j - 1)) (half at 14 rows from the wall) over 10 Jacobi passes; the sweeps
# are under-relaxed by 0.5 (each moves a node half way to its Jacobi update); 1000 sweeps, the
# paper's PDE iteration; the first two rows are held (first layer height and wall angle exact).
CONTROL_DECAY, CONTROL_PASSES = 0.05, 10
JACOBI_RELAX = 0.5
ELLIPTIC_SWEEPS = 1000
HELD_ROWS = 2
# The sweeps are checked after 10, then after twice as many as before (few whole-grid checks, and a
# run that fails early wastes few sweeps); they stop at the last state with no more folds, mean and
# worst angles (mean, worst tolerances) and worst non-orthogonality no worse than the reference's
# (docs/tuning.md: why the non-orthogonality, and no tolerance).
FIRST_CHECK, CHECK_TOL = 10, (0.0, 0.0)
# The body curve: samples of the spline for the leading edge (20001: 5e-5 of the perimeter) and of
# an arc's length (2001).
CURVE_SAMPLES, ARC_SAMPLES = 20001, 2001


# ---------------------------------------------------------------- the body curve


class BodyCurve:
    """A cubic spline through the body's surface (Selig order, from the upper trailing-edge
    point to the lower one) by cumulative chord length: it keeps a sharp trailing edge's
    corner, and a blunt one's base stays as drawn, the straight segment between the
    surface's two ends (SPEC 9)."""

    def __init__(self, body: Body) -> None:
        pts = body.surface
        t = arc_lengths(pts)
        self.length = float(t[-1])
        self.spline = CurveSpline(t, pts)
        self.knots, self.points, self.chord = t, np.asarray(pts, dtype=float), body.chord
        self.body = body
        dense = np.linspace(0.0, self.length, CURVE_SAMPLES)
        te = 0.5 * (pts[0] + pts[-1])
        self.t_le = float(dense[np.argmax(np.linalg.norm(self.at(dense) - te, axis=1))])

    def at(self, t: np.ndarray) -> np.ndarray:
        """The wall at arc parameters ``t``: the spline, drawn back towards the polyline at
        the same parameter where it swings farther than ``WALL_HOLD`` chord from it (sparse
        points round a tight bend: the spline would leave SPEC 9's tolerance there)."""
        t = np.clip(np.asarray(t, dtype=float), 0.0, self.length)
        out = self.spline(t)
        line = np.stack([np.interp(t, self.knots, self.points[:, k]) for k in (0, 1)], axis=-1)
        off = out - line
        size = np.linalg.norm(off, axis=-1, keepdims=True)
        cap = WALL_HOLD * self.chord
        return np.where(size > cap, line + off * (cap / np.maximum(size, 1e-300)), out)

    def arc(self, t0: float, t1: float) -> float:
        s = self.at(np.linspace(t0, t1, ARC_SAMPLES))
        return float(np.linalg.norm(np.diff(s, axis=0), axis=1).sum())


def _surface_nodes(curve: BodyCurve, n_up: int, n_lo: int, d_te: float, d_le: float) -> np.ndarray:
    """Nodes from the upper trailing edge to the lower one (Selig order): ``n_up`` intervals
    on the upper surface, ``n_lo`` on the lower, spacings ``d_te`` and ``d_le`` (lengths)."""
    l_up, l_lo = curve.arc(0, curve.t_le), curve.arc(curve.t_le, curve.length)
    up = curve.t_le * exact_stretch(n_up + 1, d_te / l_up, d_le / l_up)[0]
    lo = exact_stretch(n_lo + 1, d_le / l_lo, d_te / l_lo)[0]
    lo = curve.t_le + (curve.length - curve.t_le) * lo
    return curve.at(np.concatenate([up, lo[1:]]))


def _base_intervals(base: float, surface: float, intervals: int, spacing: float | None) -> int:
    """Intervals (even, so that the base's middle is a node) on a blunt trailing edge's base
    of length ``base`` (0: a sharp edge, none) out of the wall's ``intervals``: about
    ``base / BLUNT_TE_SPACING`` (or the given ``spacing``: a C-grid's is ``base /
    C_BASE_INTERVALS``), no finer than the trailing edge's ``TE_SPACING`` asks, at most
    ``MAX_BASE_SHARE`` of them."""
    if base <= 0:
        return 0
    step = spacing or min(TE_SPACING * (surface + base) / intervals, BLUNT_TE_SPACING * base)
    n = 2 * max(1, round(base / (2 * step)))
    return min(n, max(2, 2 * int(MAX_BASE_SHARE * intervals / 2)))


def _with_base(surf: np.ndarray, n_base: int) -> np.ndarray:
    """The O-grid's line j = 0: from the middle of a blunt base up to its upper corner,
    along ``surf`` (upper corner, leading edge, lower corner) and up the base's lower half
    back to its middle, ``n_base`` intervals on the base; for a sharp edge (``n_base`` 0),
    ``surf`` closed at its trailing edge."""
    if not n_base:
        out = surf.copy()
        out[-1] = out[0]
        return out
    mid = 0.5 * (surf[0] + surf[-1])
    k = np.linspace(0.0, 1.0, n_base // 2 + 1)[:, None]
    upper, lower = mid + k * (surf[0] - mid), surf[-1] + k * (mid - surf[-1])
    return np.concatenate([upper[:-1], surf, lower[1:]])


@dataclass
class Layout:
    """The fixed nodes of a body grid: ``inner`` (ni, 2) on j = 0, ``outer`` (ni, 2) on
    j = nj - 1, the first-edge length ``first`` (ni,) of each column, and for the C-grid the
    index ``n_wake`` of the lower trailing-edge node (a blunt base's middle)."""

    topology: str
    inner: np.ndarray
    outer: np.ndarray
    first: np.ndarray
    n_wake: int = 0
    wall_spacing: float = 0.0
    reference: np.ndarray | None = None
    sweeps_kept: int = 0

    @property
    def ni(self) -> int:
        return len(self.inner)

    def wall_aspect(self) -> float:
        """The wall cells' median aspect ratio: the spacing along the wall over the first
        layer's height."""
        along = lengths(np.diff(self.inner[self.wall_columns()], axis=0))
        return float(np.median(along) / self.wall_spacing)

    def wall_columns(self) -> np.ndarray:
        """Indices of the j = 0 nodes on the body."""
        if self.topology == "o":
            return np.arange(self.ni)
        return np.arange(self.n_wake, self.ni - self.n_wake)


def lengths(v: np.ndarray) -> np.ndarray:
    """The length of each vector (n, 2): np.linalg.norm(v, axis=1) in one call, the march's
    most frequent operation."""
    return np.hypot(v[:, 0], v[:, 1])


def _pairs(a: np.ndarray) -> np.ndarray:
    """Each entry of ``a`` (n,) twice, (n, 2): a factor a node for a row of nodes. NumPy runs
    a broadcast over a last axis of 2 (``a[:, None]``) one row at a time, and an operation on
    two (n, 2) arrays in one loop, about three times faster on the march's rows."""
    return a.repeat(2).reshape(-1, 2)


def _units(v: np.ndarray) -> np.ndarray:
    """Each vector (n, 2) divided by its length."""
    return v / _pairs(lengths(v))


def _unit(v: np.ndarray) -> np.ndarray:
    """:func:`_units` in place: ``v``, a vector of the caller's own, divided by its length."""
    v /= _pairs(lengths(v))
    return v


# The march's neighbours along a row: the row padded with one entry before and after, so
# that each entry's predecessor and successor are two slices of one array (an operation a
# step instead of a slice and its ends): an O-grid's nodes (node n - 1 repeats node 0, so both
# have the neighbours n - 2 and 1), a loop of entries (an O-grid's segments), or an open row
# (a C-grid's nodes: an end is its own missing neighbour)
_PADS = {"o": (slice(-2, -1), slice(1, 2)), "closed": (slice(-1, None), slice(0, 1))}
_OPEN = (slice(0, 1), slice(-1, None))


@functools.cache
def _pad_index(n: int, kind: str) -> np.ndarray:
    """The rows of ``_padded`` for ``n`` entries: one ``take`` a pad, a third of the time of
    concatenating its slices (the march pads a row about 6000 times a grid)."""
    before, after = _PADS.get(kind, _OPEN)
    i = np.arange(n)
    return np.concatenate((i[before], i, i[after]))


def _padded(u: np.ndarray, kind: str) -> np.ndarray:
    """``u`` (n, ...) with its entries' neighbours before and after (``_PADS``)."""
    return u.take(_pad_index(len(u), kind), axis=0)


def _neighbour_sums(u: np.ndarray, closed: bool) -> np.ndarray:
    """Each entry's predecessor plus successor along a row (n, ...): wrapped where ``closed``,
    else the end entry counted for its missing neighbour."""
    pad = _padded(u, "closed" if closed else "c")
    return pad[:-2] + pad[2:]


def row_chords(p: np.ndarray, topology: str) -> np.ndarray:
    """Half the chord between each node's two neighbours along a grid row ``p`` (ni, 2), in
    the direction of i (wrapped across the O-grid's seam, whose node p[-1] repeats p[0]:
    their neighbours are p[1] and p[-2]; one-sided at the C-grid's ends): the row's
    tangents, as long as its local spacing."""
    return _chords(_padded(p, topology), topology)


def _chords(pad: np.ndarray, topology: str) -> np.ndarray:
    """:func:`row_chords` of a row from its padded rows ``pad``: the neighbours' difference
    halved, whole at a C-grid's ends (one-sided there)."""
    out = pad[2:] - pad[:-2]
    if topology == "c":
        out[1:-1] *= 0.5
    else:
        out *= 0.5
    return out


def _row_tangents(p: np.ndarray, topology: str) -> np.ndarray:
    return _units(row_chords(p, topology))


# the cosine of CORNER_TURN: two segments whose unit vectors' dot product is below it meet at
# a corner
CORNER_COS = math.cos(math.radians(CORNER_TURN))
ROUND_FACING_COS = math.cos(math.radians(ROUND_FACING))


# a row's tangent (t_x, t_y) turned to its outward normal, as (t_y, t_x) times these (i runs
# counter-clockwise in the O-grid, clockwise in the C-grid)
_TURNS = {"o": np.array([1.0, -1.0]), "c": np.array([-1.0, 1.0])}


@functools.cache
def _turn(n: int, topology: str) -> tuple[np.ndarray, np.ndarray]:
    """For a row of ``n`` tangents: the indices of its flattened (t_y, t_x) pairs, and
    ``_TURNS`` for each (n, 2): the normals in two operations on (n, 2) arrays."""
    swap = np.arange(2 * n).reshape(-1, 2)[:, ::-1].ravel()
    return swap, np.tile(_TURNS[topology], (n, 1))


def _row_normals(p: np.ndarray, topology: str) -> np.ndarray:
    """Unit normals of a grid row ``p`` (ni, 2), pointing away from the body: normal to the
    chord between each node's neighbours (:func:`row_chords`), and at a corner, where the
    row turns by more than ``CORNER_TURN`` (a sharp trailing edge, a blunt base's corners),
    the corner's bisector, whatever the spacing on either side."""
    t = _unit(row_chords(p, topology))
    # i runs counter-clockwise in the O-grid (body on the left), clockwise in the C-grid
    swap, turns = _turn(len(p), topology)
    n = t.reshape(-1).take(swap).reshape(-1, 2)  # (t_y, t_x)
    n *= turns  # (sign t_y, -sign t_x), sign 1 (O) or -1 (C)
    u = _unit(p[1:] - p[:-1])  # segment i runs from node i to node i + 1
    cos = np.ones(len(p))  # the C-grid's end nodes have one segment: no corner
    if topology == "o":  # node i's segments i - 1 and i, wrapped: node 0's and n - 1's
        w = u * _padded(u, "closed")[:-2]
        cos[:-1] = w[:, 0] + w[:, 1]
        cos[-1] = cos[0]
    else:
        w = u[1:] * u[:-1]
        cos[1:-1] = w[:, 0] + w[:, 1]
    corners = np.flatnonzero(cos < CORNER_COS)
    if len(corners):  # the bisector of the segments ahead and behind (wrapped in the O-grid)
        ahead = u[np.minimum(corners, len(u) - 1) if topology == "c" else corners % len(u)]
        back = u[np.maximum(corners - 1, 0) if topology == "c" else corners - 1]
        n[corners] = _units((ahead + back)[:, ::-1] * _TURNS[topology])
    if topology == "c":
        n[0], n[-1] = (0.0, -1.0), (0.0, 1.0)
    return n


def _smooth_row(q: np.ndarray, eps, topology: str) -> np.ndarray:
    """One Laplacian pass along a row (ends held for the C-grid, wrapped for the O-grid, whose
    last node repeats its first); ``eps`` a number or one per node (ni, 1)."""
    return _smoothed(q, _padded(q, topology), eps, topology)


def _smoothed(q: np.ndarray, pad: np.ndarray, eps, topology: str) -> np.ndarray:
    """:func:`_smooth_row` of ``q`` from its padded rows ``pad``: q + eps (the neighbours'
    mean - q), each operation in place on one new array."""
    out = pad[:-2] + pad[2:]
    out *= 0.5
    out -= q
    out *= eps
    out += q
    if topology == "o":
        out[-1] = out[0]
    else:
        out[0], out[-1] = q[0], q[-1]
    return out


def redistribute(q: np.ndarray, eps: float, topology: str, passes: int) -> np.ndarray:
    """The row ``q`` (ni, 2) with its nodes slid along it so that its spacing is smoothed:
    ``passes`` Laplacian passes of weight ``eps`` over the lengths of its segments, the
    nodes then placed at the smoothed lengths' cumulative sums along the row (node 0 and, for
    the C-grid, the last node held). Sliding along the row keeps the nodes in order, so the
    columns cannot cross within a row, and a crowd of columns spreads out however strongly
    the lines converge (off a concave wall, under an aft surface)."""
    seg = lengths(q[1:] - q[:-1])
    s_old = np.empty(len(q))
    s_old[0] = 0.0
    np.add.accumulate(seg, out=s_old[1:])
    ds = seg
    for _ in range(passes):  # ds + eps (half the neighbours' sum - ds)
        step = _neighbour_sums(ds, topology == "o")
        step *= 0.5
        step -= ds
        step *= eps
        step += ds
        ds = step
    s_new = np.empty(len(q))
    s_new[0] = 0.0
    np.add.accumulate(ds, out=s_new[1:])
    s_new *= s_old[-1] / s_new[-1]
    out = np.empty_like(q)
    out[:, 0] = np.interp(s_new, s_old, q[:, 0])
    out[:, 1] = np.interp(s_new, s_old, q[:, 1])
    out[0], out[-1] = q[0], q[-1]
    return out


def _smooth_normals(n: np.ndarray, eps, topology: str) -> np.ndarray:
    return _unit(_smooth_row(n, eps, topology))  # a C-grid's end normals held


def rear_start(inner: np.ndarray, n_wake: int) -> np.ndarray:
    """Per node of a C-grid's line j = 0, the x of its surface's thickest point (where the
    wall's normal is closest to vertical): the columns behind it run straight up or down."""
    ni = len(inner)
    n = _row_normals(inner, "c")
    lower = np.arange(n_wake + 1, ni // 2)
    upper = np.arange(ni // 2, ni - n_wake - 1)
    x_lo = inner[lower[np.argmin(np.abs(n[lower, 0]))], 0]
    x_up = inner[upper[np.argmin(np.abs(n[upper, 0]))], 0]
    return np.where(np.arange(ni) < ni // 2, x_lo, x_up)


def _march_constants(topology: str) -> list[float]:
    """:func:`march`'s constants as the compiled loop takes them (march.cpp's Constants)."""
    return [
        NORMAL_REACH,
        NORMAL_SMOOTHING,
        CONCAVE_SMOOTHING,
        ROW_SMOOTHING_MAX,
        SPREAD,
        REAR_REACH,
        SUBSTEP,
        MAX_SUBSTEPS,
        SPACING_RATE[topology],
        CORNER_COS,
    ]


@dataclass
class _Marching:
    """What each of :func:`march`'s rows reads beside the row before it: the wall row's
    spacing, a blunt C-grid's corner weights (ni, 1) or None, the nodes whose spacing limits
    a sub-step, and the C-grid's turn behind its thickest point (rear weights (ni, 1),
    lengths (ni, 1) and the vertical directions (ni, 2); None for the O-grid)."""

    topology: str
    scale: float
    n_wake: int
    passes: int
    tangent: float
    spacing0: np.ndarray
    corner: np.ndarray | None
    free: np.ndarray
    rear: np.ndarray | None = None
    turn_length: np.ndarray | None = None
    vertical: np.ndarray | None = None


def march(
    inner: np.ndarray,
    topology: str,
    distances: np.ndarray,
    scale: float,
    n_wake: int = 0,
    passes: int = MARCH_PASSES,
    tangent: float = 0.0,
    base: float = 0.0,
) -> np.ndarray:
    """Rows marched from ``inner`` along their own normals by the steps of ``distances``
    (nj,): the wall-orthogonal reference grid (nj, ni, 2). The normals are smoothed along
    the row, and each new row along itself, lightly near the wall and more farther out
    (relative to ``scale``, the chord) and where it has shrunk (lines converging off a
    concave wall); and from the wall on, by a weight that decays away from it, around the
    concave corners where a blunt C-grid's cut leaves its base of length ``base`` (see
    ``CORNER_REACH``). The rows after the first are marched by the compiled loop
    (``marching.py``) where it was built, else by :func:`_march_numpy`: the same grid."""
    corner = None  # the weight of a blunt C-grid's concave corners at its base
    free = np.ones(len(inner), dtype=bool)  # the nodes whose spacing limits a sub-step
    if topology == "c" and base > 0:
        distance = np.linalg.norm(inner - inner[n_wake], axis=1)
        reach = min(CORNER_REACH * base / 2, CORNER_REACH_MAX * scale)
        corner = np.exp(-distance / reach)[:, None]
        free = distance > base
    setup = _Marching(
        topology, scale, n_wake, passes, tangent, _row_spacing(inner, topology), corner, free
    )
    if topology == "c":
        # behind the thickest point the C-grid's columns turn straight down (lower side)
        # or up (upper side) within ``REAR_TURN`` chords of the wall, as the wake's do (the
        # aft surface's normals lean downstream and would overtake the wake's columns); the
        # base's columns (the nodes not ``free``) within the base's height if it is larger
        setup.turn_length = np.where(free, REAR_TURN * scale, max(REAR_TURN * scale, base))[:, None]
        ni = len(inner)
        x = inner[:, 0]
        x_t = rear_start(inner, n_wake)
        share = np.clip((x - x_t) / (x[n_wake] - x_t), 0.0, 1.0)
        share[: n_wake + 1] = share[ni - n_wake - 1 :] = 1.0
        setup.rear = np.where(x >= x_t, 1.0, 0.0)[:, None] * (
            REAR_TURN_START + (1 - REAR_TURN_START) * share[:, None]
        )
        side = np.where(np.arange(ni) < ni // 2, -1.0, 1.0)
        setup.vertical = np.column_stack([np.zeros(ni), side])
    rows = np.empty((len(distances), len(inner), 2))
    rows[0] = inner
    if len(distances) > 1:
        rows[1] = first_row(inner, topology, distances[1] - distances[0])
    lib = marching.library()
    if lib is None or _march_compiled(lib, rows, distances, setup):
        _march_numpy(rows, distances, setup)
    return rows


def _array(a: np.ndarray | None, dtype=np.float64) -> np.ndarray | None:
    return None if a is None else np.ascontiguousarray(a, dtype=dtype)


def _march_compiled(lib, rows: np.ndarray, distances: np.ndarray, setup: _Marching) -> int:
    """Rows 2 .. of ``rows`` marched by the compiled loop; non-zero where it stopped (a
    sub-step count not finite: :func:`_march_numpy` then raises as before)."""
    arrays = [
        _array(setup.spacing0),
        _array(setup.corner),
        _array(setup.free, np.uint8),
        _array(setup.rear),
        _array(setup.turn_length),
        _array(setup.vertical),
        np.array(_march_constants(setup.topology)),
    ]
    dist = _array(distances)
    return lib.march_rows(
        rows.shape[1],
        len(dist),
        dist.ctypes.data,
        float(setup.scale),
        int(setup.topology == "o"),
        setup.passes,
        float(setup.tangent),
        setup.n_wake,
        *(None if a is None else a.ctypes.data for a in arrays),
        rows.ctypes.data,
    )


def _march_numpy(rows: np.ndarray, distances: np.ndarray, setup: _Marching) -> None:
    """Rows 2 .. of ``rows`` (the wall and the first row given) marched off the row before
    each by NumPy operations (:func:`march`)."""
    topology, scale, n_wake, passes = setup.topology, setup.scale, setup.n_wake, setup.passes
    corner, rear, tangent, inner = setup.corner, setup.rear, setup.tangent, rows[0]
    q = rows[1]
    for j in range(2, len(distances)):
        step = distances[j] - distances[j - 1]
        n = _row_normals(q, topology)
        subs, rate = _substeps(q, n, step, topology, setup.free)
        start, length, k, marched = distances[j - 1], step, 0, 0.0
        while k < subs:
            if k:
                n = _row_normals(q, topology)
            if rate > 0 and marched > 1 / rate - length / subs / SUBSTEP:
                # the row may have neared the converging lines' focus (1 / rate ahead at
                # the last check): the rest of the step re-split if they converge faster
                rate, marched = _converging_rate(q, n), 0.0
                more = _count(length * (subs - k) / subs, rate)
                if more > subs - k:
                    start, length = start + length * k / subs, length * (subs - k) / subs
                    subs, k = min(more, MAX_SUBSTEPS), 0
            k += 1
            marched += length / subs
            d = start + length * k / subs
            grow = 1 - math.exp(-d / (NORMAL_REACH * scale))
            weight = grow if corner is None else np.maximum(corner, grow)
            for _ in range(passes):
                n = _smooth_normals(n, NORMAL_SMOOTHING * weight, topology)
            if rear is not None:
                turn = rear * np.minimum(1.0, (d - distances[1]) / setup.turn_length)
                fade = math.exp(-d / (REAR_REACH * scale))
                turn = np.where(rear > 0, 1 - (1 - turn) * fade, 0.0)
                n = _units((1 - turn) * n + turn * setup.vertical)
            n *= length / subs
            q = q + n
            pad = _padded(q, topology)  # the row's neighbours: its spacing, then smoothed
            shrink = 1 - lengths(_chords(pad, topology)) / setup.spacing0  # clipped below
            concave = np.maximum(np.minimum(ROW_SMOOTHING_MAX, CONCAVE_SMOOTHING * shrink), 0.0)
            concave = _pairs(concave)
            eps = grow * concave
            if topology == "c":  # the wake's columns run straight: no sliding along rows
                eps[:n_wake] = eps[len(q) - n_wake :] = 0.0
            if corner is not None:  # around the base's corners: from the wall on, wake too
                eps = np.maximum(eps, corner * concave)
            for p in range(passes):
                q = _smoothed(q, pad if p == 0 else _padded(q, topology), eps, topology)
                if tangent:  # slid along its tangent towards its own smoothing
                    pad = _padded(q, topology)
                    slide = _smoothed(q, pad, tangent * grow, topology)
                    t = _unit(_chords(pad, topology))
                    slide -= q
                    slide *= t
                    t *= _pairs(slide[:, 0] + slide[:, 1])
                    q = q + t
            if topology == "o":
                q = redistribute(q, SPREAD * grow, topology, passes)
            else:  # the body's columns (the wake's run straight)
                body = slice(n_wake, len(q) - n_wake)
                q[body] = redistribute(q[body], SPREAD * grow, topology, passes)
            if topology == "c":  # the outflow columns march straight
                q[0], q[-1] = inner[0] + (0, -d), inner[-1] + (0, d)
        rows[j] = q


def first_row(inner: np.ndarray, topology: str, h: float) -> np.ndarray:
    """The first row off the line j = 0 ``inner`` (ni, 2): straight along the wall's normals,
    height ``h`` exactly (the C-grid's outflow columns straight down and up). The elliptic and
    pinn grids hold it."""
    q = inner + h * _row_normals(inner, topology)
    if topology == "c":
        q[0], q[-1] = inner[0] + (0, -h), inner[-1] + (0, h)
    return q


def _converging_rate(q: np.ndarray, n: np.ndarray) -> float:
    """The rate at which the row ``q``'s most converging neighbours, leaving along the
    normals ``n``, close their gap, per unit of their gap and of the distance marched."""
    e, dn = np.diff(q, axis=0), np.diff(n, axis=0)
    return float(np.max(-np.einsum("ik,ik->i", dn, e) / np.einsum("ik,ik->i", e, e)))


def _count(step: float, rate: float) -> int:
    """Sub-steps of at most ``SUBSTEP`` / ``rate`` in a step of ``step`` (at most
    ``MAX_SUBSTEPS``, which bounds a row's time)."""
    return int(min(MAX_SUBSTEPS, max(1, math.ceil(step * rate / SUBSTEP))))


def _substeps(
    q: np.ndarray, n: np.ndarray, step: float, topology: str, free: np.ndarray
) -> tuple[int, float]:
    """How many sub-steps a step of ``step`` off row ``q`` takes: each at most ``SUBSTEP`` of
    the distance in which the row's most converging neighbours would meet (their spacing
    over the rate at which their normals close it), and at most ``SUBSTEP / SPACING_RATE``
    of the smallest spacing at the nodes ``free`` (the smoothing passes of each sub-step
    damp the rows' sawtooth; a blunt C-grid's base, smoothed from the wall on, is not free).
    A longer step crosses lines off a concave wall before any smoothing acts. Also the
    converging rate alone (``n``: the row's normals), which :func:`march` checks again as the
    row nears the lines' focus: under a deep concave wall they converge faster there, and a
    step split by the rate at its start carried the row past it, turned inside out."""
    rate = _converging_rate(q, n)
    spacing = SPACING_RATE[topology] / float(_row_spacing(q, topology)[free].min())
    return _count(step, max(rate, spacing)), rate


def _row_spacing(p: np.ndarray, topology: str) -> np.ndarray:
    """Half the distance between each node's two neighbours along a row."""
    return lengths(row_chords(p, topology))


def layout(
    body: Body,
    far: FarField,
    topology: str,
    ni: int,
    nj: int,
    wall_spacing: float | None = None,
    wake_nodes: int | None = None,
    le_spacing: float | None = None,
    te_spacing: float | None = None,
) -> Layout:
    """Place the nodes of j = 0 and j = nj - 1 (see the module's docstring)."""
    if topology not in TOPOLOGIES:
        raise InputError(f"unknown topology {topology!r}; use o or c")
    if ni < 9 or nj < 3:
        raise InputError(
            f"grid size {ni} x {nj}: a body grid needs at least 9 x 3 nodes ({{size}})"
        )
    curve = BodyCurve(body)
    chord = body.chord
    center = far.center
    if topology == "c":
        if far.radius is None:
            raise InputError(
                "the C-grid takes a far-field circle ({farfield}); a far field "
                "from a file works with {topology}",
                body.source,
            )
        n_w = wake_nodes if wake_nodes is not None else max(2, round(WAKE_SHARE * ni))
        n_b = ni - 1 - 2 * n_w
        if n_b < 6:
            raise InputError(
                f"grid size {ni}: too few nodes for the body after {n_w} wake "
                "nodes on each side ({size})"
            )
    else:
        n_w, n_b = 0, ni - 1
    l_up, l_lo = curve.arc(0, curve.t_le), curve.arc(curve.t_le, curve.length)
    base = 0.0 if body.sharp else body.te_gap
    base_step = base / C_BASE_INTERVALS if topology == "c" else None
    n_base = _base_intervals(
        base, l_up + l_lo, n_b, te_spacing * chord if te_spacing else base_step
    )
    n_s = n_b - n_base  # intervals on the surface
    n_up = round(n_s * l_up / (l_up + l_lo))
    n_up = int(np.clip(n_up, MIN_SURFACE_INTERVALS, n_s - MIN_SURFACE_INTERVALS))
    mean = (l_up + l_lo) / n_s
    d_le = le_spacing * chord if le_spacing else LE_SPACING * mean
    if n_base:  # the surface's end spacing is the base's: no jump at the corners
        d_te = base / n_base
    else:
        d_te = te_spacing * chord if te_spacing else TE_SPACING * mean
    surf = _surface_nodes(curve, n_up, n_s - n_up, d_te, d_le)
    h = wall_spacing * 1.0 if wall_spacing else WALL_SPACING * mean
    if topology == "c" and n_base and not wall_spacing:
        h = min(h, BASE_FIRST * d_te)
    radius = far.radius
    if topology == "o":
        inner = _with_base(surf, n_base)
    else:
        body_c = _with_base(surf, n_base)[::-1]  # trailing edge, lower surface, ..., back
        te = body_c[0]
        x_out = center[0] + radius
        if x_out <= te[0] + MIN_WAKE * chord:
            raise InputError(
                f"the far-field radius leaves no room for the wake (outflow at "
                f"x = {x_out:.3g}); give a larger radius ({{farfield}})",
                body.source,
            )
        wake_len = x_out - te[0]
        wake = te[0] + wake_len * exact_stretch(n_w + 1, d_te / wake_len)[0]
        wake_pts = np.column_stack([wake, np.full_like(wake, te[1])])
        inner = np.concatenate([wake_pts[::-1], body_c[1:-1], wake_pts])
    # the wall-orthogonal reference: rows marched off j = 0, the last one projected onto the
    # far field, the projection blended in over the outer rows
    reach = _far_distance(inner, far, topology) - FAR_GAP * chord
    dist = reach * exact_stretch(nj, h / reach)[0]
    tries = _corner_heights(inner, topology, n_w, base, body.rounded)
    for corner in tries:  # the first whose reference has no fold, else the first
        reference, outer = reference_grid(inner, far, topology, dist, chord, n_w, corner)
        if len(tries) == 1 or not guard_figures(reference)["folded_cells"]:
            break
    else:
        reference, outer = reference_grid(inner, far, topology, dist, chord, n_w, tries[0])
    if topology == "c" and tries[0]:
        folded = guard_figures(reference)["folded_cells"]
        if folded:
            what = (
                f"round trailing edge (facing downstream over {tries[0] / chord:.2g} chords)"
                if body.rounded
                else f"blunt trailing edge (a base of {base / chord:.2g} chords)"
            )
            fix = "{topology}, whose grid keeps the whole edge as wall"
            if n_base:
                fix += f", or a first layer of at most {BASE_FIRST * d_te:.1e} ({{spacing}})"
            raise InputError(
                f"the C-grid around this {what} folds {folded} cells at the wake cut; use {fix}",
                body.source,
            )
    first = np.full(ni, h)
    if topology == "c":  # the first edge grows along the wake to the outflow
        far_first = OUTFLOW_FIRST * radius / (nj - 1)
        x = inner[:, 0]
        frac = np.clip((x - inner[n_w, 0]) / (x[0] - inner[n_w, 0]), 0.0, 1.0)
        idx = np.arange(ni)
        body_nodes = (idx >= n_w) & (idx <= ni - 1 - n_w)
        first = np.where(body_nodes, h, h * (max(far_first, h) / h) ** frac)
    return Layout(topology, inner, outer, first, n_w, h, reference)


def facing_height(inner: np.ndarray, n_wake: int) -> float:
    """The height over which a C-grid's wall (line j = 0 ``inner``, the lower trailing-edge
    node ``n_wake``) faces downstream about its trailing edge: the span in y of the wall
    nodes on either side of it whose outward normal lies within ``ROUND_FACING`` degrees of
    +x (a round edge's "base": a circle's is 0.71 of its diameter)."""
    ni = len(inner)
    n = _row_normals(inner, "c")
    facing = n[:, 0] >= ROUND_FACING_COS
    lower, upper = n_wake + 1, ni - n_wake - 2
    while lower < ni // 2 and facing[lower]:
        lower += 1
    while upper > ni // 2 and facing[upper]:
        upper -= 1
    return float(inner[upper, 1] - inner[lower, 1])


def _corner_heights(
    inner: np.ndarray, topology: str, n_wake: int, base: float, rounded: bool
) -> list[float]:
    """The heights tried, in order, for the smoothing around a C-grid's cut (``march``'s
    ``base``) until the reference grid has no fold: the base's (0 for a sharp edge), then
    the height facing downstream (:func:`facing_height`), halved ``ROUND_HALVINGS``
    times; for a round trailing edge (no corner, SPEC 9), the facing heights first."""
    if topology != "c":
        return [base]
    tall = facing_height(inner, n_wake)
    tries = [max(base, tall / 2**k) for k in range(ROUND_HALVINGS + 1)]
    return list(dict.fromkeys([*tries, base] if rounded else [base, *tries]))


def reference_grid(
    inner: np.ndarray,
    far: FarField,
    topology: str,
    dist: np.ndarray,
    chord: float,
    n_wake: int,
    base: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """The wall-orthogonal reference grid and its far-field nodes. O-grid: rows marched off
    the wall all the way (:func:`march`), the last one projected radially onto the far
    field, the projection blended in over the outer rows. C-grid: rows marched to
    ``BLEND_END`` chords, turning over ``BLEND_START`` .. ``BLEND_END`` chords into straight
    lines from the row at ``BLEND_START`` to that row's projection onto the far field
    (radially about its centre, straight up or down behind the thickest point: lines that
    cannot cross), so that every column ends on the far field."""
    if topology == "o":
        marched = march(inner, topology, dist, chord, n_wake, tangent=TANGENT_SMOOTHING)
        outer = _project(marched[-1], far, topology, inner)
        outer[-1] = outer[0]
        blend = ((dist / dist[-1]) ** O_BLEND_POWER)[:, None, None]
        grid = marched + blend * (outer - marched[-1])[None]
        grid[-1] = outer
        return grid, outer
    a = int(np.searchsorted(dist, BLEND_START * chord))
    b = int(np.searchsorted(dist, BLEND_END * chord))
    a, b = min(a, len(dist) - 2), min(max(b, a + 1), len(dist) - 1)
    marched = march(inner, topology, dist[: b + 1], chord, n_wake, tangent=0.0, base=base)
    start = marched[a]
    outer = _project(start, far, topology, inner, n_wake)
    t = ((dist - dist[a]) / (dist[-1] - dist[a])).clip(0.0, 1.0)
    straight = start[None] + t[:, None, None] * (outer - start)[None]
    w = np.clip((dist - dist[a]) / max(dist[b] - dist[a], 1e-300), 0.0, 1.0)
    w = (w * w * (3 - 2 * w))[:, None, None]
    grid = straight.copy()
    grid[: b + 1] = (1 - w[: b + 1]) * marched + w[: b + 1] * straight[: b + 1]
    grid[0] = inner
    grid[-1] = outer
    return grid, outer


def _far_distance(inner: np.ndarray, far: FarField, topology: str) -> float:
    """About how far the far field lies from the body (for the marching distance)."""
    if far.radius is not None:
        return float(far.radius)
    r = np.linalg.norm(far.polyline - far.center, axis=1)
    return float(r.min())


def _project(
    row: np.ndarray, far: FarField, topology: str, inner: np.ndarray, n_wake: int = 0
) -> np.ndarray:
    """Points of the far field for a marched row: radially about the far field's centre
    onto the circle (or polyline); for the C-grid, the row's nodes behind the centre
    straight up or down onto the lines y = y_c -+ R (both maps keep the nodes' order, so
    straight lines to them cannot cross)."""
    c = far.center
    ang = np.arctan2(row[:, 1] - c[1], row[:, 0] - c[0])
    if far.radius is not None:
        out = c + far.radius * np.column_stack([np.cos(ang), np.sin(ang)])
    else:
        ring = far.polyline
        pa = np.arctan2(ring[:, 1] - c[1], ring[:, 0] - c[0])
        order = np.argsort(pa)
        pa, pts = pa[order], ring[order]
        pa = np.r_[pa[-1] - 2 * np.pi, pa, pa[0] + 2 * np.pi]
        pts = np.concatenate([pts[-1:], pts, pts[:1]])
        out = np.column_stack([np.interp(ang, pa, pts[:, k]) for k in range(2)])
    if topology == "c":  # the D-shaped far field: behind its centre, the lines y_c -+ R
        half = len(row) // 2
        sign = np.where(np.arange(len(row)) < half, -1.0, 1.0)
        x = row[:, 0]
        rear = x > c[0]  # radially in front of the centre, straight up or down behind it
        on_circle = np.sqrt(np.maximum(far.radius**2 - (x - c[0]) ** 2, 0.0))
        line = np.column_stack([x, c[1] + sign * np.where(x < c[0], on_circle, far.radius)])
        out[rear] = line[rear]
        out[0, 0], out[-1, 0] = row[0, 0], row[-1, 0]
        out[0, 1], out[-1, 1] = c[1] - far.radius, c[1] + far.radius
    return out


# ---------------------------------------------------------------- algebraic grids


def tfi(lay: Layout, nj: int) -> np.ndarray:
    """The two-boundary TFI grid (nj, ni, 2): straight columns, each stretched so that its
    first edge is ``lay.first``."""
    vec = lay.outer - lay.inner
    length = np.linalg.norm(vec, axis=1)
    s = exact_stretch(nj, lay.first / length, None, lay.ni).T
    return lay.inner[None] + s[..., None] * vec[None]


# ---------------------------------------------------------------- elliptic solver


def _d(g: np.ndarray, periodic: bool) -> tuple[np.ndarray, ...]:
    """Central differences at interior rows (j = 1 .. nj - 2) of the grid's unique columns
    (O: wrapped; C: columns 1 .. ni - 2): x_xi, x_eta, x_xixi, x_etaeta, x_xieta."""
    if periodic:
        u = g[:, :-1]
        e, w = np.roll(u, -1, axis=1), np.roll(u, 1, axis=1)
        c = u
    else:
        u = g
        e, w, c = u[:, 2:], u[:, :-2], u[:, 1:-1]
    n, s = c[2:], c[:-2]
    ne, nw, se, sw = e[2:], w[2:], e[:-2], w[:-2]
    e, w, c = e[1:-1], w[1:-1], c[1:-1]
    return (0.5 * (e - w), 0.5 * (n - s), e - 2 * c + w, n - 2 * c + s, 0.25 * (ne - nw - se + sw))


def residual(
    g: np.ndarray, periodic: bool, s_xi: np.ndarray | None = None, s_eta: np.ndarray | None = None
) -> np.ndarray:
    """alpha x_xixi - 2 beta x_xieta + gamma x_etaeta + s_xi x_xi + s_eta x_eta at the
    unknown nodes."""
    x_xi, x_eta, x_xixi, x_etaeta, x_xieta = _d(g, periodic)
    r = winslow_operator(x_xi, x_eta, x_xixi, x_etaeta, x_xieta)
    if s_xi is not None:
        r = r + s_xi[..., None] * x_xi + s_eta[..., None] * x_eta
    return r


def exact_controls(g: np.ndarray, periodic: bool) -> tuple[np.ndarray, np.ndarray]:
    """Sources (s_xi, s_eta) that make ``g`` an exact solution: s_xi x_xi + s_eta x_eta
    = -(alpha x_xixi - 2 beta x_xieta + gamma x_etaeta)."""
    x_xi, x_eta, *_ = _d(g, periodic)
    r = -residual(g, periodic)
    det = x_xi[..., 0] * x_eta[..., 1] - x_xi[..., 1] * x_eta[..., 0]
    s_xi = (r[..., 0] * x_eta[..., 1] - r[..., 1] * x_eta[..., 0]) / det
    s_eta = (x_xi[..., 0] * r[..., 1] - x_xi[..., 1] * r[..., 0]) / det
    return s_xi, s_eta


def smoothed_controls(
    g: np.ndarray, periodic: bool, decay: float = CONTROL_DECAY, passes: int = CONTROL_PASSES
) -> tuple[np.ndarray, np.ndarray]:
    """The exact sources of ``g`` (see :func:`exact_controls`), kept at the wall and
    blended, with weight exp(-decay (j - 1)), into ``passes`` Jacobi passes of their
    smoothing away from it."""
    out = []
    j = np.arange(1, g.shape[0] - 1)[:, None]
    w = np.exp(-decay * (j - 1))
    for a in exact_controls(g, periodic):
        b = np.nan_to_num(a)
        for _ in range(passes):
            if periodic:
                e, west = np.roll(b, -1, axis=1), np.roll(b, 1, axis=1)
            else:
                e = np.concatenate([b[:, 1:], b[:, -1:]], axis=1)
                west = np.concatenate([b[:, :1], b[:, :-1]], axis=1)
            n = np.concatenate([b[1:], b[-1:]])
            south = np.concatenate([b[:1], b[:-1]])
            b = 0.5 * b + 0.125 * (e + west + n + south)
        out.append(w * np.nan_to_num(a) + (1 - w) * b)
    return out[0], out[1]


def jacobi(
    grid: np.ndarray,
    periodic: bool,
    s_xi: np.ndarray,
    s_eta: np.ndarray,
    sweeps: int,
    relax: float = JACOBI_RELAX,
    hold: int = HELD_ROWS,
) -> np.ndarray:
    """``sweeps`` relaxed point-Jacobi sweeps of the controlled Winslow equations (the
    paper's PDE iteration) on the interior of ``grid``; rows j = 0, nj - 1 (and the C-grid's
    outflow columns) held, and the first ``hold`` rows off the wall (the first layer's height
    and the wall angle are the reference's), the O-grid's seam column kept equal to
    column 0."""
    g = np.array(grid, dtype=float)
    kept = g[1 : hold + 1].copy()
    sx, se = s_xi[..., None], s_eta[..., None]
    for _ in range(sweeps):
        x_xi, x_eta, _, _, x_xieta = _d(g, periodic)
        a, b, c = (v[..., None] for v in winslow_coefficients(x_xi, x_eta))
        if periodic:
            u = g[:, :-1]
            ew = np.roll(u, -1, axis=1)[1:-1] + np.roll(u, 1, axis=1)[1:-1]
            centre = u[1:-1]
            ns = u[2:] + u[:-2]
        else:
            ew = g[1:-1, 2:] + g[1:-1, :-2]
            centre = g[1:-1, 1:-1]
            ns = g[2:, 1:-1] + g[:-2, 1:-1]
        new = (a * ew + c * ns - 2 * b * x_xieta + sx * x_xi + se * x_eta) / (2 * (a + c))
        upd = centre + relax * (new - centre)
        if periodic:
            g[1:-1, :-1] = upd
            g[1:-1, -1] = upd[:, 0]
        else:
            g[1:-1, 1:-1] = upd
        g[1 : hold + 1] = kept
    return g


def elliptic(lay: Layout, sweeps: int = ELLIPTIC_SWEEPS) -> tuple[np.ndarray, tuple]:
    """The elliptic grid: up to ``sweeps`` Jacobi sweeps of Winslow's equations from the
    reference grid, with the controls of :func:`smoothed_controls`; also returns them.

    After ``FIRST_CHECK`` sweeps, then after twice as many each time, the grid is checked
    against the reference: the sweeps stop at the last state with no more folded cells,
    mean and worst MaxIncludedAngle within ``CHECK_TOL`` of the reference's and a worst
    non-orthogonality no higher (the relaxed Jacobi iteration with smoothed controls can
    drift off a good marched grid, most on thin wall and wake cells, where a worst angle
    held elsewhere, as at a blunt C-grid's base, does not see it; ``lay.sweeps_kept`` says
    how far it went)."""
    periodic = lay.topology == "o"
    controls = smoothed_controls(lay.reference, periodic)
    ref = guard_figures(lay.reference)
    ref_non_orthogonality = worst_non_orthogonality(lay.reference)
    g, kept, done = lay.reference, lay.reference, 0
    lay.sweeps_kept = 0
    step = FIRST_CHECK
    while done < sweeps:
        n = min(step, sweeps - done)
        g = jacobi(g, periodic, *controls, n)
        done, step = done + n, 2 * step
        if not no_worse(guard_figures(g), ref, *CHECK_TOL):
            break
        if worst_non_orthogonality(g) > ref_non_orthogonality:
            break
        kept, lay.sweeps_kept = g, done
    return kept, controls


__all__ = [
    "TOPOLOGIES",
    "BodyCurve",
    "Layout",
    "elliptic",
    "first_row",
    "jacobi",
    "layout",
    "march",
    "reference_grid",
    "residual",
    "row_chords",
    "smoothed_controls",
    "tfi",
]
