"""The nodes of gradings along chains (SPEC 10's ``--spacing X,Y=H``), placed after the
method's grid: every grid line of a graded block that leaves its graded side (the blocks of
``chains.graded_sides``) keeps its shape and has its nodes moved along it.

- **The stretching.** Each line's nodes go to the arc lengths of a Vinokur stretching
  (``classical.spacing.exact_stretch``) whose first edge is H at each graded end and free
  at an end no grading asks (one-sided: the cells grow monotonically away from H, SPEC 7),
  as blockMesh places a graded block's nodes and as the layout places the boundary pieces
  along the grading (``chains.graded_params``), which keep their nodes.
- **The rows.** Lines of one block that differ in length (a side bent by the solve, a
  junction the solve moved) put one stretching's nodes at different distances, so the rows
  across them would carry the graded side's bends all along the block. The rows are then
  smoothed along the lines: each node (not the first one off a graded end) moves along its
  line toward the mean of its two neighbours on the lines beside it (across an interface
  for a line two graded blocks share), by Gauss-Seidel sweeps over alternate nodes, and
  never so far that two neighbouring cells of its line differ by more than ROW_GROWTH.

So every line leaving the side starts at H, up to the side's corners, and its cells grow by
at most ROW_GROWTH; a line shared by two blocks is moved once, by its node ids.
"""

from __future__ import annotations

from collections import defaultdict

import numpy as np

from pinn_engine.classical.spacing import exact_stretch
from pinn_engine.geometry.boundary import arc_lengths
from pinn_engine.multiblock.chains import SideItem
from pinn_engine.multiblock.layout import side_lines
from pinn_engine.multiblock.spacing import Requests
from pinn_engine.settings import SIDE_NAMES

# Neighbouring cells along a graded line differ by at most this factor after the rows'
# smoothing (SPEC 10: 1.25; the stretching itself stays within chains.GROWTH_AIM, 1.2)
ROW_GROWTH = 1.22
# Sweeps of the rows' smoothing, and the share of the way to its target a node moves in one
# (the bends decay over a few tens of lines; more sweeps changed no figure of the benchmarks)
ROW_SWEEPS, ROW_PULL = 40, 0.5

# (the item, (block, side), its sign, H): each side a grading asks a first edge H of
Graded = list[tuple[SideItem, tuple[int, int], int, float]]


def _key(line: np.ndarray) -> tuple[tuple[int, ...], bool]:
    """A line's node ids in one direction, the same read either way, and whether that
    reverses ``line``."""
    ids = tuple(int(n) for n in line)
    key = min(ids, ids[::-1])
    return key, key != ids


def _lines(ids: list[np.ndarray], graded: Graded):
    """Each graded line once: its key -> [H at its first node or None, H at its last], and
    its key -> the node ids of the lines beside it in the blocks listing it, aligned, each
    once."""
    asked: dict[tuple[int, ...], list] = {}
    beside: dict[tuple[int, ...], dict[tuple[int, ...], np.ndarray]] = defaultdict(dict)
    for _, (b, s), _, h in graded:
        lines = side_lines(ids[b], SIDE_NAMES[s])
        for m, line in enumerate(lines):
            key, flip = _key(line)
            ask = asked.setdefault(key, [None, None])
            ask[int(flip)] = h if ask[int(flip)] is None else min(ask[int(flip)], h)
            for other in lines[max(m - 1, 0) : m + 2 : 2] if m else lines[1:2]:
                aligned = other[::-1] if flip else other
                beside[key][tuple(int(n) for n in aligned)] = aligned
    return asked, {key: list(found.values()) for key, found in beside.items()}


def graded_asks(
    ids: list[np.ndarray], graded: Graded, boundary: np.ndarray, patches: Requests
) -> dict[tuple[int, ...], list]:
    """Each graded line's key -> [H at its first node or None, H at its last]: the
    grading's H at its graded end; where the ``patches``' first edges (``spacing.requests``,
    spread) ask an end too, the patch's at a ``boundary`` node (the wall's own first edge)
    and the smaller of the two inside the domain (a wall's spacing carried along an
    interface that a grading asks a smaller first edge of: the step's line)."""
    asked = _lines(ids, graded)[0]
    for key, ends in asked.items():
        if key in patches:
            at_wall = boundary[[key[0], key[-1]]]
            ends[:] = [
                g if p is None else p if g is None or wall else min(g, p)
                for g, p, wall in zip(ends, patches[key][:2], at_wall)
            ]
    return asked


def graded_lines(
    points: np.ndarray,
    ids: list[np.ndarray],
    graded: Graded,
    boundary: np.ndarray,
    patches: Requests,
) -> tuple[np.ndarray, Requests]:
    """``points`` with the nodes of every line of ``graded`` placed along it (the module's
    rule), and the ``patches``' first edges (``spacing.requests``) left to
    ``spacing.respace``: a graded line that a patch asks too takes both in its one
    stretching (:func:`graded_asks`), so neither end undoes the other; ``boundary`` masks
    the boundary's nodes, which stay (the layout placed them)."""
    asked = graded_asks(ids, graded, boundary, patches)
    beside = _lines(ids, graded)[1]
    rest = {key: ask for key, ask in patches.items() if key not in asked}
    keys = [key for key in asked if not boundary[list(key)].all()]
    lines_of = np.zeros(len(points), dtype=int)
    for key in keys:
        lines_of[list(key)] += 1
    out = points.copy()
    stacks = []
    for part in _parts(keys):  # lines crossing others placed after them, along their nodes
        stacks.append(_Stack(out, np.array(part), asked, beside, boundary, lines_of))
        stacks[-1].place(out)
    for _ in range(ROW_SWEEPS):
        for parity in (0, 1):
            for stack in stacks:
                stack.sweep(out, parity)
    return out, rest


def _parts(keys: list[tuple[int, ...]]) -> list[list[tuple[int, ...]]]:
    """``keys`` in groups of one node count whose lines share no node (a block graded in
    both directions: its rows in one group, its columns in a later one)."""
    parts: list[tuple[set, list]] = []
    for key in keys:
        part = next(
            (p for p in parts if len(p[1][0]) == len(key) and not p[0].intersection(key)), None
        )
        if part is None:
            part = (set(), [])
            parts.append(part)
        part[0].update(key)
        part[1].append(key)
    return [members for _, members in parts]


class _Stack:
    """Graded lines of one node count that share no node: their shapes (their nodes when
    they are placed), their nodes' arc lengths along them, which of those move in the rows'
    smoothing (none that another graded line holds too), and the lines beside each."""

    def __init__(self, points, lines, asked, beside, boundary, lines_of) -> None:
        self.lines = lines
        self.shape = points[lines]  # (m, n, 2): the lines' polylines, kept
        self.arc = np.array([arc_lengths(p) for p in self.shape])
        m, n = lines.shape
        total = self.arc[:, -1]
        self.s = np.empty((m, n))
        self.free = ~boundary[lines] & (lines_of[lines] == 1)
        self.free[:, [0, -1]] = False
        for r, key in enumerate(map(tuple, lines.tolist())):
            first, last = asked[key]
            share = [None if h is None else h / total[r] for h in (first, last)]
            self.s[r] = total[r] * exact_stretch(n, *share)[0]
            self.free[r, 1] &= first is None
            self.free[r, -2] &= last is None
        pairs = [beside[key] for key in map(tuple, lines.tolist())]
        two = np.array([len(p) == 2 for p in pairs])
        self.free &= two[:, None]
        self.beside = np.array([p if len(p) == 2 else [lines[r]] * 2 for r, p in enumerate(pairs)])
        # the arc lengths of all lines in one increasing array, for one search over all
        self.offset = np.cumsum(np.concatenate([[0.0], total[:-1] + 1.0]))[:, None]

    def _at(self, s: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Points at arc lengths ``s`` (m, n) along the lines, and the lines' unit tangents
        there."""
        m, n = s.shape
        flat = (self.arc + self.offset).ravel()
        seg = np.searchsorted(flat, (s + self.offset).ravel(), side="right") - 1
        seg = np.clip(seg.reshape(m, n) - np.arange(m)[:, None] * n, 0, n - 2)
        rows = np.arange(m)[:, None]
        a, b = self.shape[rows, seg], self.shape[rows, seg + 1]
        length = self.arc[rows, seg + 1] - self.arc[rows, seg]
        tangent = (b - a) / np.maximum(length, 1e-300)[..., None]
        return a + (s - self.arc[rows, seg])[..., None] * tangent, tangent

    def place(self, out: np.ndarray) -> None:
        out[self.lines] = self._at(self.s)[0]

    def sweep(self, out: np.ndarray, parity: int) -> None:
        """Move the free nodes of one parity toward their row neighbours' mean, each within
        the ROW_GROWTH bounds its line's fixed nodes leave it."""
        s, g = self.s, ROW_GROWTH
        at, tangent = self._at(s)
        target = 0.5 * (out[self.beside[:, 0]] + out[self.beside[:, 1]])
        want = s + ROW_PULL * np.einsum("mnk,mnk->mn", target - at, tangent)
        k = np.arange(s.shape[1])
        move = self.free & (k % 2 == parity)
        prev, nxt = np.roll(s, 1, axis=1), np.roll(s, -1, axis=1)
        span = nxt - prev
        lo, hi = prev + span / (1 + g), prev + span * g / (1 + g)
        before = prev - np.roll(s, 2, axis=1)  # the cell before the previous node
        after = np.roll(s, -2, axis=1) - nxt
        inner = k >= 2
        lo = np.where(inner, np.maximum(lo, prev + before / g), lo)
        hi = np.where(inner, np.minimum(hi, prev + before * g), hi)
        inner = k <= s.shape[1] - 3
        lo = np.where(inner, np.maximum(lo, nxt - after * g), lo)
        hi = np.where(inner, np.minimum(hi, nxt - after / g), hi)
        move &= lo <= hi
        s[move] = np.clip(want, lo, hi)[move]
        out[self.lines[move]] = self._at(s)[0][move]


def graded_report(
    points: np.ndarray,
    ids: list[np.ndarray],
    graded: Graded,
    asked: dict[tuple[int, ...], list],
    walls: dict[int, float],
) -> dict[str, dict]:
    """Per grading (``--spacing X,Y=H``, keyed by its item): the first edges of the lines
    leaving its graded sides (each side's corner lines aside, and lines starting on a
    spaced patch, ``walls``: node -> H, whose figures hold them), as
    ``walls.wall_report`` gives a patch's: min, median and max, and the line farthest off
    the H asked of it (``asked``: :func:`graded_asks`) with that H (``spacing``: the
    item's, or a smaller one a wall's spacing brings, ``chains.joint_ends``)."""
    edges: dict[str, list[float]] = {}
    off: dict[str, list[tuple[float, list[float], float]]] = {}
    for item, (b, s), _, _ in graded:
        label = f"the side of {item.where}"
        for line in side_lines(ids[b], SIDE_NAMES[s])[1:-1]:
            if int(line[0]) in walls:
                continue
            key, flip = _key(line)
            h = asked[key][int(flip)]
            first = float(np.linalg.norm(points[line[1]] - points[line[0]]))
            edges.setdefault(label, []).append(first)
            off.setdefault(label, []).append((abs(first / h - 1.0), points[line[0]].tolist(), h))
    out = {}
    for label, e in edges.items():
        share, at, h = max(off[label], key=lambda found: found[0])
        out[label] = {
            "first_edge": {
                "min": float(min(e)),
                "median": float(np.median(e)),
                "max": float(max(e)),
            },
            "spacing": h,
            "first_edge_off": {"share": share, "at": at},
        }
    return out
