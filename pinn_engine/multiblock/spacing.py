"""First-edge spacing on multi-block patches (SPEC 10 with SPEC 7's ``--spacing``): the
nodes of every grid line that leaves a spaced patch are redistributed along the line, so
that its first edge is H. Gradings along chains (``--spacing X,Y=H``) place their lines
by ``grading.py`` instead.

The method's grid (TFI or the all-block Winslow solve) is a smooth map of index space; a
spacing evaluates that map at stretched parameters, as ``classical.spacing``'s interpolated
elliptic map does for one block: each line is a cubic spline of its nodes over their index,
and its nodes go to the parameters of ``classical.spacing``'s per-line Vinokur stretching
(one two-sided stretching shared by all the lines, each line's own first parameter
interval reached by a correction that decays within a few cells of the wall, so rows stay
rows of the map and no line is shifted as a whole). At an end off the wall a line keeps the
map's own interval, so the spacing runs on into the block beyond. The first parameter
intervals are corrected by the measured first edges until each is H. The lines of one
length are stretched together and each line once, by its node ids, so a line shared by two
blocks (an interface piece leaving the wall) is the same in both and shared nodes stay
identical.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np

from pinn_engine.classical.spacing import LOCAL_CELLS, line_parameters
from pinn_engine.errors import InputError
from pinn_engine.geometry.boundary import arc_lengths
from pinn_engine.multiblock.blocks import CORNER_TURN
from pinn_engine.multiblock.layout import side_lines
from pinn_engine.multiblock.walls import WallSide
from pinn_engine.quality import folded_cells
from pinn_engine.settings import SIDE_NAMES

# Rounds of correcting the first parameter intervals by the measured first edges, and the
# share by which every first edge may still be off when they stop (far inside SPEC 7's 10 %)
FIT_ROUNDS, FIT_TOL = 12, 1e-3
# The first edges asked of a line take less than this share of it (SPEC 7's rule for one
# block: a first edge shorter than half the sides it runs along)
MAX_ASKED_SHARE = 0.5

# Rounds of sliding the first nodes of the lines leaving spaced walls onto H: a node next to
# two walls (a block's corner cell) is on two such lines, each slide moving it along its own
SLIDE_ROUNDS = 3

# a line's ids -> [H at its start, H at its end, the option asking (for messages)]
Requests = dict[tuple[int, ...], list]


def _ask(out: Requests, line: np.ndarray, h: float, label: str) -> None:
    """Ask the first edge ``h`` at ``line``'s start (ids from its node on the side), the
    smaller where two ask."""
    ids = tuple(int(n) for n in line)
    key = min(ids, ids[::-1])
    end = 0 if key == ids else 1
    ask = out.setdefault(key, [None, None, label])
    ask[end] = h if ask[end] is None else min(ask[end], h)


def requests(sides: list[WallSide], spacing: dict[str, float]) -> Requests:
    """Each line leaving a spaced patch once (ids from its lower end), with the first edge
    asked at each end (None: off the wall), the smaller where two patches ask."""
    out: Requests = {}
    for wall in sides:
        h = spacing.get(wall.name)
        if h is None:
            continue
        for line in wall.lines:
            _ask(out, line, h, f"spacing {wall.name}={h:g}")
    return out


def spread(
    asked: Requests,
    ids: list[np.ndarray],
    points: np.ndarray,
    corners: set[int] = frozenset(),
    boundary: np.ndarray | None = None,
) -> Requests:
    """``asked`` with the stretching carried, end by end, to the lines that must share it
    (an end already asked keeps its first edge), until no line gains one:

    - **along a chain:** into every block that has an asked line as a whole side without
      asking its own lines along it (a corner block beside a square hole's wall blocks):
      that block's lines parallel to the side are asked the same first edge at the same
      end, as a grading runs through every block sharing a side along it. Without it such
      a block keeps its own distribution next to a stretched side, and its cells there
      shear;
    - **through a node:** an asked line passes its first edge at an end to the lines that
      leave that node continuing it (turning by less than a block corner's
      ``CORNER_TURN``; ``points``: the layout's nodes). Inside an interface that is a whole
      side of both its blocks, every line of the block across leaving that side takes it
      (its corner lines too, so its sides keep its rows' distribution): a step cut at its
      lip's lines has the inlet's wall spacing on the lines above and below the step's
      line. At a block corner (``corners``: the pieces' ends) only a ``boundary`` line
      passes it on, to the boundary line beyond (a wall's row past the corner). Without it
      the cells jump by the ratio of the spacing to the cell size across the interface.
    """
    out = {key: list(ask) for key, ask in asked.items()}
    sides: dict[tuple[int, ...], list[tuple[int, str]]] = {}
    # node -> the lines leaving it, each with the side it leaves
    leaving: dict[int, list[tuple[np.ndarray, tuple[int, ...], int, str]]] = {}
    for b, block in enumerate(ids):
        for side in SIDE_NAMES:
            lines = side_lines(block, side)
            nodes = tuple(int(n) for n in lines[:, 0])
            sides.setdefault(min(nodes, nodes[::-1]), []).append((b, side))
            for line in lines:
                leaving.setdefault(int(line[0]), []).append(
                    (line, min(nodes, nodes[::-1]), b, side)
                )
    straight = np.cos(np.radians(CORNER_TURN))
    across = {"bottom": ("left", "right"), "top": ("left", "right")}
    across |= {"left": ("bottom", "top"), "right": ("bottom", "top")}
    queue = list(out)
    while queue:
        key = queue.pop()
        first, last, label = out[key]
        for b, side in sides.get(key, ()):
            for node, h in ((key[0], first), (key[-1], last)):
                if h is None:
                    continue
                start = next(
                    t for t in across[side] if node in side_lines(ids[b], t)[:, 0].tolist()
                )
                for line in side_lines(ids[b], start):
                    line_key = tuple(int(n) for n in line)
                    key2 = min(line_key, line_key[::-1])
                    end = 0 if key2 == line_key else 1
                    if key2 in out and out[key2][end] is not None:
                        continue
                    _ask(out, line, h, label)
                    queue.append(key2)
        along = boundary is not None and bool(boundary[list(key)].all())
        for node, before, h in ((key[0], key[1], first), (key[-1], key[-2], last)):
            if h is None or (node in corners and not along):
                continue
            arrive = points[node] - points[before]
            for line, whole, b2, side2 in leaving.get(node, ()):
                if node not in corners and len(sides[whole]) < 2:
                    continue  # an interface that is not a whole side of both blocks
                if node in corners and not bool(boundary[line].all()):
                    continue
                leave = points[line[1]] - points[node]
                cos = arrive @ leave / max(np.linalg.norm(arrive) * np.linalg.norm(leave), 1e-300)
                if cos <= straight:
                    continue
                # inside an interface every line of the block across leaving it, corner
                # lines too, so the block's sides keep its rows' distribution
                for line2 in [line] if node in corners else side_lines(ids[b2], side2):
                    line_key = tuple(int(n) for n in line2)
                    key2 = min(line_key, line_key[::-1])
                    end = 0 if key2 == line_key else 1
                    if key2 not in out or out[key2][end] is None:
                        _ask(out, line2, h, label)
                        queue.append(key2)
    return out


def wall_nodes(sides: list[WallSide], spacing: dict[str, float]) -> dict[int, float]:
    """The first edge asked at each node of a spaced patch (the smaller where two ask)."""
    out: dict[int, float] = {}
    for wall in sides:
        h = spacing.get(wall.name)
        if h is None:
            continue
        for node in wall.lines[wall.on, 0].tolist():
            out[node] = min(h, out.get(node, h))
    return out


def held_pieces(
    asked: Requests, held: set[int], walls: dict[int, float], ids: list[np.ndarray]
) -> tuple[Requests, Requests]:
    """``asked`` with every line cut at its inner nodes in ``held`` (the ends of pieces:
    sharp corners and the places edges meet the boundary, which fix the domain drawn, and
    block corners inside a side of the block beside them, a T-junction, whose blocks end
    their lines there: all must stay grid nodes where they are), each piece stretched on
    its own (a side stretched past a junction moved it, and the sides of the blocks across
    were stretched again from there, one over the other), asked at a cut the first edge of
    the wall there (``walls``: a reflex corner's lines leave it as they leave the rest of
    the wall), else the map's own interval; a piece asked at neither end is left as it is.

    A cut asked a first edge is carried through the block (``ids``: each block's node
    ids) whose line it cuts: every line of the block parallel to it is cut at the same
    index and asked the same first edge there, as a block side beyond a reflex corner would
    pass it on (``spread``). Without it only the wall row beyond the corner crowds its nodes
    against the corner, over the block's next row, and the cells between them shear to
    nearly 180 degrees."""
    # the first edge asked from a node towards its neighbour along a line: at the lines'
    # asked ends, and both ways from every cut asked the wall's first edge
    edge: dict[tuple[int, int], tuple[float, str]] = {}

    def ask(node: int, towards: int, h: float | None, label: str) -> bool:
        if h is None or h >= edge.get((node, towards), (np.inf, ""))[0]:
            return False
        edge[node, towards] = (h, label)
        return True

    lines = {key: label for key, (_, _, label) in asked.items()}
    cuts: set[tuple[int, int]] = set()  # (node, neighbour) of each line cut at the node
    for key, (first, last, label) in asked.items():
        ask(key[0], key[1], first, label)
        ask(key[-1], key[-2], last, label)
        for k in range(1, len(key) - 1):
            if key[k] in held:
                cuts.update({(key[k], key[k + 1]), (key[k], key[k - 1])})
                ask(key[k], key[k - 1], walls.get(key[k]), label)
                ask(key[k], key[k + 1], walls.get(key[k]), label)
    families = [f for block in ids for f in (block, block.T)]
    changed = True
    while changed:
        changed = False
        for family in families:
            n = family.shape[1]
            carried: dict[tuple[int, int], tuple[float, str]] = {}
            for k, d in ((k, d) for k in range(n) for d in (-1, 1) if 0 <= k + d < n):
                pairs = zip(family[:, k].tolist(), family[:, k + d].tolist())
                here = [edge[p] for p in pairs if p in edge]
                if here:
                    carried[k, d] = min(here)
            inner = {
                k
                for k, _ in carried
                if 0 < k < n - 1
                and cuts.intersection(zip(family[:, k].tolist(), family[:, k + 1].tolist()))
            }
            if not inner:
                continue  # no cut inside the block: its lines keep their own ends
            for k in inner:
                cuts.update(zip(family[:, k].tolist(), family[:, k + 1].tolist()))
                cuts.update(zip(family[:, k].tolist(), family[:, k - 1].tolist()))
            for line in family:
                lines.setdefault(_key(line), next(iter(carried.values()))[1])
                for (k, d), (h, label) in carried.items():
                    changed |= ask(int(line[k]), int(line[k + d]), h, label)
    pieces: Requests = {}
    whole: Requests = {}
    for key, label in lines.items():
        inner = range(1, len(key) - 1)
        cut = [0, *(k for k in inner if (key[k], key[k + 1]) in cuts), len(key) - 1]
        out = pieces if len(cut) > 2 else whole
        for a, b in zip(cut, cut[1:]):
            h0 = edge.get((key[a], key[a + 1]), (None, ""))[0]
            h1 = edge.get((key[b], key[b - 1]), (None, ""))[0]
            if b - a < 2 or (h0 is None and h1 is None):
                continue
            piece = np.asarray(key[a : b + 1])
            for node_end, h in ((0, h0), (-1, h1)):
                if h is not None:
                    _ask(out, piece if node_end == 0 else piece[::-1], h, label)
    return pieces, whole


def _key(line: np.ndarray) -> tuple[int, ...]:
    """A line's ids from its lower end, as :data:`Requests` keys it."""
    ids = tuple(int(n) for n in line)
    return min(ids, ids[::-1])


# A boundary node this share of the diagonal off the drawn boundary has been moved off it
# (a node placed on it is within rounding)
OFF_DRAWN = 1e-12


def on_drawn(points: np.ndarray, boundary: np.ndarray, rings: list[np.ndarray]) -> np.ndarray:
    """``points`` with each boundary node (mask ``boundary``) that a stretching moved off
    the drawn ``rings`` put back at its nearest point of them: a line along a curved wall
    is a spline of its nodes, which cuts across the drawn polyline's chords (by their
    sagitta), and the grid must cover the domain drawn."""
    ids = np.flatnonzero(boundary)
    a = np.vstack([np.asarray(r, dtype=float)[:, :2] for r in rings])
    b = np.vstack([np.roll(np.asarray(r, dtype=float)[:, :2], -1, axis=0) for r in rings])
    ab = b - a
    ab2 = np.maximum(np.einsum("mj,mj->m", ab, ab), 1e-300)
    tol = OFF_DRAWN * float(np.linalg.norm(np.ptp(a, axis=0)))
    out = points.copy()
    for k in range(0, len(ids), 256):
        chunk = ids[k : k + 256]
        q = points[chunk][:, None, :]
        u = np.clip(np.einsum("pmj,mj->pm", q - a, ab) / ab2, 0.0, 1.0)
        foot = a + u[..., None] * ab
        dist = np.linalg.norm(foot - q, axis=2)
        near = dist.argmin(axis=1)
        rows = np.arange(len(chunk))
        off = dist[rows, near] > tol
        out[chunk[off]] = foot[rows, near][off]
    return out


def untangled_blocks(
    points: np.ndarray, ids: list[np.ndarray], untangle: Callable[[np.ndarray], np.ndarray]
) -> np.ndarray:
    """``points`` with the interior nodes of every block that folds moved by ``untangle``
    (``starts.untangle.untangle``, passed in from the layer above: a block's grid with its
    sides held), so that moving nodes along lines folds no cell the method's grid had not."""
    out = points.copy()
    for block in ids:
        if folded_cells(out[block]).any():
            out[block[1:-1, 1:-1]] = untangle(out[block])[1:-1, 1:-1]
    return out


def check_room(points: np.ndarray, asked: Requests) -> None:
    """Refuse a spacing of at least half a line leaving its patch or side (measured on the
    start grid, before the solve)."""
    for ids, (first, last, label) in asked.items():
        length = arc_lengths(points[list(ids)])[-1]
        if (first or 0.0) + (last or 0.0) >= MAX_ASKED_SHARE * length:
            raise InputError(
                f"{label}: the first edge must be shorter than half of every grid line "
                f"leaving the patch or side (one is {length:.4g} long); choose a smaller H or "
                "a larger cell size"
            )


def respace(points: np.ndarray, asked: Requests) -> np.ndarray:
    """``points`` with every asked line's nodes moved along it (its ends stay). A line
    asked at one end only is turned to start there, so that the lines stretched together
    (one length) share the stretching's asked end; where one is asked at both ends, the
    stretching they share is the same read either way (``_stretched``). Lines that share a
    node (a block's rows and columns, where two of its sides are walls) are stretched one
    after the other, each from the nodes the ones before left, so the block keeps both
    stretchings."""
    groups: dict[int, list] = {}
    for ids, (first, last, _) in asked.items():
        if first is None:
            ids, first, last = ids[::-1], last, first
        parts = groups.setdefault(len(ids), [])
        part = next((p for p in parts if not p[0].intersection(ids)), None)
        if part is None:
            part = (set(), [])
            parts.append(part)
        part[0].update(ids)
        part[1].append((ids, first, last))
    out = points.copy()
    for group in (members for parts in groups.values() for _, members in parts):
        lines = np.array([ids for ids, _, _ in group])
        asks = [np.array([np.nan if g[k] is None else g[k] for g in group]) for k in (1, 2)]
        out[lines[:, 1:-1]] = _stretched(out[lines], *asks)[:, 1:-1]
    return out


def _stretched(p: np.ndarray, first: np.ndarray, last: np.ndarray) -> np.ndarray:
    """Lines ``p`` (m, n, 2) of the map evaluated at stretched parameters whose first and
    last edges are ``first`` and ``last`` (m,) (NaN: the map's own interval there). Where
    any line is asked at both ends, the lines are stretched with their mirror images, so
    the stretching they share is symmetric: two rows of one block listed from opposite ends
    (a line's ids may run either way) get the same nodes inside, where a stretching steeper
    at one end sheared the cells between them (the Y-branch at +-35 degrees: 179 degrees)."""
    from scipy.interpolate import CubicSpline  # only asked spacings get here

    m, n = p.shape[:2]
    index = np.arange(n)
    splines = [CubicSpline(index, line, axis=0) for line in p]
    ends = ((first, 0, 1), (last, -1, -2))
    # a parameter interval of the map's own index step gives its own edge: start from the
    # ratio of asked to own edges; where nothing is asked, the map's own (uniform) interval
    param = [
        np.where(np.isnan(h), 1.0, h / np.linalg.norm(p[:, b] - p[:, a], axis=1)) / (n - 1)
        for h, a, b in ends
    ]
    for _ in range(FIT_ROUNDS):
        if np.isnan(last).all():
            t = line_parameters(n, param[0], param[1], m) * (n - 1)
        else:
            both = (np.concatenate([param[0], param[1]]), np.concatenate([param[1], param[0]]))
            t = line_parameters(n, *both, 2 * m)[:m] * (n - 1)
        new = np.stack([spline(row) for spline, row in zip(splines, t)])
        new[:, 0], new[:, -1] = p[:, 0], p[:, -1]
        off = 0.0
        for k, (h, a, b) in enumerate(ends):
            ratio = np.where(np.isnan(h), 1.0, h / np.linalg.norm(new[:, b] - new[:, a], axis=1))
            param[k] = param[k] * ratio
            off = max(off, float(np.abs(ratio - 1.0).max()))
        if off <= FIT_TOL:
            break
    return new


def _slid(p: np.ndarray, first: float | None, last: float | None) -> np.ndarray | None:
    """The nodes ``p`` (n, 2) of a line moved along the polyline through them, so that its
    first and last edges are ``first`` and ``last`` (None: as they are; a line whose asked
    edges are already within ``FIT_TOL`` is left as the stretching fitted it): a shift of the
    nodes' arc positions that decays from each asked end over ``LOCAL_CELLS`` cells to
    nothing at the other end, so the line keeps its shape and its far part. None where no
    such shift keeps the nodes in order."""
    n = len(p)
    s = np.concatenate([[0.0], np.cumsum(np.linalg.norm(np.diff(p, axis=0), axis=1))])
    off = [abs(d / h - 1.0) for h, d in ((first, s[1]), (last, s[-1] - s[-2])) if h is not None]
    if max(off) <= FIT_TOL:
        return p  # as the stretching fitted it
    tail = np.exp(-(n - 2) / LOCAL_CELLS)
    w = np.zeros(n)
    w[1:-1] = (np.exp(-np.arange(n - 2) / LOCAL_CELLS) - tail) / (1.0 - tail)
    shift = np.zeros(n)
    if first is not None and last is not None:
        if n < 4:
            return None  # one inner node cannot take both first edges
        system = np.array([[1.0, w[-2]], [w[-2], 1.0]])  # the two decays at both first nodes
        a, b = np.linalg.solve(system, [first - s[1], s[-1] - last - s[-2]])
        shift = a * w + b * w[::-1]
    elif first is not None:
        shift = (first - s[1]) * w
    elif last is not None:
        shift = (s[-1] - last - s[-2]) * w[::-1]
    new = s + shift
    if not (np.diff(new) > 0).all():
        return None
    return np.column_stack([np.interp(new, s, p[:, 0]), np.interp(new, s, p[:, 1])])


def fitted_first_edges(
    points: np.ndarray,
    sides: list[WallSide],
    spacing: dict[str, float],
    graded: dict[tuple[int, ...], list] | None = None,
) -> np.ndarray:
    """``points`` with every inner line leaving a spaced wall side (those SPEC 7 measures:
    a block side's corner lines aside), and every ``graded`` line (``grading.graded_asks``:
    key -> the first edge at each end or None), slid along itself so that its first edge
    is the H asked (:func:`_slid`), at both ends where both ask one. The stretchings
    place each block's lines one family after the other, and a line's nodes moved by the
    lines crossing it (a block's other family, a spline of a few coarse nodes cutting
    across a curved wall, a block untangled) leave its first edge off H, beyond SPEC 7's
    10 % beside reflex corners and T-junctions; the slide moves only nodes inside a block,
    each along its own line, so the cells keep their shapes."""
    ends: dict[tuple[int, ...], list] = {}
    for wall in sides:
        h = spacing.get(wall.name)
        if h is None:
            continue
        for line in wall.lines[1:-1][wall.on[1:-1]]:
            if len(line) > 2:
                _ask(ends, line, h, wall.name)
    for key, asks in (graded or {}).items():
        for line, h in ((np.asarray(key), asks[0]), (np.asarray(key[::-1]), asks[1])):
            if h is not None:
                _ask(ends, line, h, "grading")
    out = points.copy()
    for _ in range(SLIDE_ROUNDS):
        for key, (first, last, _) in ends.items():
            slid = _slid(out[list(key)], first, last)
            if slid is not None:
                out[list(key[1:-1])] = slid[1:-1]
    return out
