"""Automatic blocking on domains users bring (SPEC 13), beside gmsh's automatic quads and
a hand blocking: bodies with sharp corners in channels and near walls, bends, tilted tees,
expansions, a cavity and airfoils in channels, in a tuning half and a report half.

Usage: ``.venv/bin/python benchmarks/autoblock_users.py [--out docs/blocking.md]
[--domains NAME ...]``, or ``--sweep``: tilted tees (``SWEEP``: leans of 15 to 60 degrees
both ways, narrow and wide branches, two channel heights) against the better of two hand
blockings, a line for each that misses a bound; or ``--ys``: narrow Ys (``NARROW_YS``)
against their hand-drawn centre, a line each.

Per domain, at ``autoblock.CELLS_ACROSS`` cells across a channel of width 1:

- **auto**: ``--blocks auto``'s proposal and its elliptic grid (``autoblock.meshed``), or
  the one-line refusal;
- **hand**: the elliptic grid of a careful hand blocking drawn here (bodies: the O-ring of
  ``autoblock_domains._box_blocks``, whose four spokes end on a square's or a plate's
  corners); none is drawn for the triangle, the diamond (their corners are not on the
  box's diagonals), the airfoils and the two rectangles;
- **gmsh quads**: gmsh's automatic quadrilaterals on the whole domain (Frontal-Delaunay for
  quads, ``Mesh.Algorithm`` 8, recombined by Blossom, every boundary point at the same
  cell size), measured by pinn-mesh's own MaxIncludedAngle; triangles gmsh leaves are
  counted.

The bounds column is SPEC 13's aims against the hand blocking (``autoblock.checks``). With
``--out`` the tables replace the part of that file between the two AUTOBLOCK-USERS markers.
Times: one run each, on whatever machine runs it.
"""

from __future__ import annotations

import argparse
import itertools
import time
from collections.abc import Callable
from pathlib import Path

import gmsh
import numpy as np
from autoblock import CELLS_ACROSS, _cell, checks, figures, meshed
from autoblock_domains import Domain, _a, _box_blocks, y_branch
from multiblock import write_between

from pinn_engine.errors import InputError
from pinn_engine.multiblock.autoblock import propose_edges

MARK = "<!-- AUTOBLOCK-USERS {} -->"  # the markers round the tables in --out
GMSH_QUADS = 8  # gmsh's Mesh.Algorithm: Frontal-Delaunay for quads
NACA_POINTS = 61  # points per surface of an airfoil


def _turned(points: np.ndarray, degrees: float, about=(0.0, 0.0)) -> np.ndarray:
    c, s = np.cos(np.radians(degrees)), np.sin(np.radians(degrees))
    return (np.asarray(points) - about) @ np.array([[c, s], [-s, c]]) + about


def _naca(thickness: float, chord: float = 1.0) -> np.ndarray:
    """A symmetric NACA 00xx of ``chord`` from (0, 0), its trailing edge closed to a point,
    counter-clockwise from the trailing edge."""
    x = 0.5 * (1 - np.cos(np.linspace(0, np.pi, NACA_POINTS)))
    y = 5 * thickness * (0.2969 * np.sqrt(x) - 0.126 * x - 0.3516 * x**2 + 0.2843 * x**3)
    y -= 5 * thickness * 0.1036 * x**4
    y[-1] = 0.0
    upper = np.column_stack([x, y])[::-1]
    lower = np.column_stack([x, -y])[1:-1]
    return chord * np.vstack([upper, lower])


def bend_60() -> Domain:
    """A channel of width 1 turning left by 60 degrees at a sharp outer corner (3, 0)."""
    d = _a(np.cos(np.pi / 3), np.sin(np.pi / 3))
    n = _a(-d[1], d[0])
    outer = _a(3.0, 0.0)
    inner = _a(outer[0] + n[0] + (1 - n[1]) / d[1] * d[0], 1.0)
    end = outer + 3 * d
    ring = np.array([(0, 0), outer, end, end + n, inner, (0, 1)])
    return [ring], [np.array([inner, outer])]


def square_near_floor() -> Domain:
    """A square of side 0.5 whose bottom is 0.25 above the floor of [-2, 5] x [0, 2]."""
    channel = _a((-2, 0), (5, 0), (5, 2), (-2, 2))
    body = _a((1, 0.25), (1.5, 0.25), (1.5, 0.75), (1, 0.75))
    return [channel, body], _box_blocks(body, (0.75, 0.1, 1.75, 1.0), (-2, 0, 5, 2))


def plate_at_10() -> Domain:
    """A plate 1 x 0.2 at 10 degrees of incidence in the channel [-2, 4] x [-1.5, 1.5]."""
    channel = _a((-2, -1.5), (4, -1.5), (4, 1.5), (-2, 1.5))
    plate = _turned(_a((-0.5, -0.1), (0.5, -0.1), (0.5, 0.1), (-0.5, 0.1)), 10.0)
    return [channel, plate], _box_blocks(plate, (-0.9, -0.6, 0.9, 0.6), (-2, -1.5, 4, 1.5))


def tee_15_upstream() -> Domain:
    """The tee [0, 6] x [0, 1] with its branch of width 1 leaning 15 degrees upstream."""
    up = 2.0 * _a(-np.sin(np.pi / 12), np.cos(np.pi / 12))
    left, right = _a(2.5, 1.0), _a(3.5, 1.0)
    ring = np.array([(0, 0), (6, 0), (6, 1), right, right + up, left + up, left, (0, 1)])
    return [ring], [_a(left, (2.5, 0)), _a(right, (3.5, 0)), np.array([left, right])]


def expansion() -> Domain:
    """A channel of width 1 opening suddenly to width 3 at x = 3 (both walls step out)."""
    ring = _a((0, 1), (3, 1), (3, 0), (10, 0), (10, 3), (3, 3), (3, 2), (0, 2))
    return [ring], [_a((3, 1), (3, 2)), _a((3, 1), (10, 1)), _a((3, 2), (10, 2))]


def cavity() -> Domain:
    """A channel [0, 6] x [0, 1] over an open square cavity [2, 3] x [-1, 0]."""
    ring = _a((0, 0), (2, 0), (2, -1), (3, -1), (3, 0), (6, 0), (6, 1), (0, 1))
    return [ring], [_a((2, 0), (3, 0)), _a((2, 0), (2, 1)), _a((3, 0), (3, 1))]


def naca_at_5() -> Domain:
    """A NACA 0012 of chord 1 at 5 degrees of incidence in the channel [-3, 6] x [-2, 2]."""
    channel = _a((-3, -2), (6, -2), (6, 2), (-3, 2))
    return [channel, _turned(_naca(0.12), 5.0, (0.25, 0.0))], []


def three_elements() -> Domain:
    """A three-element high-lift section built from NACA sections (a slat 0.15 at -25
    degrees, a main NACA 0012 of chord 1 and a flap 0.3 at 30 degrees, gaps of about 0.02
    chord) in the channel [-3, 6] x [-2, 2]: 30P30N's kind, not its coordinates."""
    channel = _a((-3, -2), (6, -2), (6, 2), (-3, 2))
    main = _naca(0.12)
    slat = _turned(_naca(0.10, 0.15), -25.0) + (-0.16, -0.02)
    flap = _turned(_naca(0.10, 0.3), 30.0) + (1.02, -0.05)
    return [channel, slat, main, flap], []


def two_elements() -> Domain:
    """A NACA 0012 of chord 1 and a flap 0.35 deflected 20 degrees down, its leading edge
    tucked 0.03 under and behind the main element's trailing edge, in [-3, 6] x [-2, 2]."""
    channel = _a((-3, -2), (6, -2), (6, 2), (-3, 2))
    flap = _turned(_naca(0.12, 0.35), -20.0) + (0.97, -0.07)
    return [channel, _naca(0.12), flap], []


def slat_and_main() -> Domain:
    """A slat 0.2 at -40 degrees ahead and below a NACA 0015's leading edge (a gap of
    about 0.04) in [-3, 6] x [-2, 2]."""
    channel = _a((-3, -2), (6, -2), (6, 2), (-3, 2))
    slat = _turned(_naca(0.12, 0.2), -40.0) + (-0.2, 0.05)
    return [channel, slat, _naca(0.15)], []


def squares_side_by_side() -> Domain:
    """Two squares of side 0.5, 0.1 apart across the flow, in [-2, 5] x [-2, 2]."""
    channel = _a((-2, -2), (5, -2), (5, 2), (-2, 2))
    square = _a((0, 0.05), (0.5, 0.05), (0.5, 0.55), (0, 0.55))
    return [channel, square, (square * (1, -1))[::-1]], []


def cylinder_before_plate() -> Domain:
    """A cylinder of diameter 0.5 0.1 upstream of a plate 1 x 0.1, in [-2, 5] x [-1.5, 1.5]."""
    channel = _a((-2, -1.5), (5, -1.5), (5, 1.5), (-2, 1.5))
    t = np.linspace(0, 2 * np.pi, 48, endpoint=False)
    cylinder = np.column_stack([0.25 * np.cos(t), 0.25 * np.sin(t)])
    plate = _a((0.35, -0.05), (1.35, -0.05), (1.35, 0.05), (0.35, 0.05))
    return [channel, cylinder, plate], []


def wedge_and_square() -> Domain:
    """A wedge pointing upstream 0.15 ahead of a square of side 0.6 turned 10 degrees,
    0.3 above the floor of [-2, 5] x [0, 2.5]."""
    channel = _a((-2, 0), (5, 0), (5, 2.5), (-2, 2.5))
    wedge = _a((-0.5, 0.6), (0.0, 0.35), (0.0, 0.85))
    square = _turned(_a((0, 0), (0.6, 0), (0.6, 0.6), (0, 0.6)), 10.0) + (0.2, 0.3)
    return [channel, wedge, square], []


def three_elements_steep() -> Domain:
    """A landing-like three-element section: a slat 0.15 at -35 degrees, a NACA 0012 and a
    flap 0.3 deflected 35 degrees down under its trailing edge, in [-3, 6] x [-2, 2]."""
    channel = _a((-3, -2), (6, -2), (6, 2), (-3, 2))
    slat = _turned(_naca(0.10, 0.15), -35.0) + (-0.15, 0.03)
    flap = _turned(_naca(0.10, 0.3), -35.0) + (0.96, -0.08)
    return [channel, slat, _naca(0.12), flap], []


def triangle_near_floor() -> Domain:
    """An equilateral triangle of side 0.6 pointing up, its base 0.2 above the floor."""
    channel = _a((-2, 0), (5, 0), (5, 2), (-2, 2))
    body = _a((0.7, 0.2), (1.3, 0.2), (1.0, 0.2 + 0.3 * np.sqrt(3)))
    return [channel, body], []


def diamond_near_floor() -> Domain:
    """A square of side 0.5 turned 45 degrees, its lowest corner 0.2 above the floor."""
    channel = _a((-2, 0), (5, 0), (5, 2), (-2, 2))
    r = 0.25 * np.sqrt(2.0)
    c = _a(1.0, 0.2 + r)
    body = np.array([c + (r, 0), c + (0, r), c - (r, 0), c - (0, r)])
    return [channel, body], []


def s_bend() -> Domain:
    """A channel of width 1 that turns up and back along x through two sharp bends."""
    ring = _a((0, 0), (3, 0), (3, 2), (6, 2), (6, 3), (2, 3), (2, 1), (0, 1))
    edges = [_a((2, 1), (2, 0)), _a((2, 1), (3, 1)), _a((3, 2), (2, 2)), _a((3, 2), (3, 3))]
    return [ring], edges


def rectangles_across() -> Domain:
    """Two rectangles 1 x 0.4 one above the other across the channel [-3, 6] x [-2, 2]."""
    channel = _a((-3, -2), (6, -2), (6, 2), (-3, 2))
    upper = _a((0, 0.4), (1, 0.4), (1, 0.8), (0, 0.8))
    lower = upper * (1, -1)
    lower = lower[::-1]
    return [channel, upper, lower], []


def tee_wide_branch() -> Domain:
    """The tee [0, 8] x [0, 1] with a branch of width 2 leaning 30 degrees downstream."""
    up = 2.0 * _a(np.sin(np.pi / 6), np.cos(np.pi / 6))
    left, right = _a(2.5, 1.0), _a(4.5, 1.0)
    ring = np.array([(0, 0), (8, 0), (8, 1), right, right + up, left + up, left, (0, 1)])
    return [ring], [_a(left, (2.5, 0)), _a(right, (4.5, 0)), np.array([left, right])]


def tilted_tee(lean: float, width: float, height: float = 1.0) -> Domain:
    """The channel [0, 8] x [0, height] with a branch of ``width`` (across its own axis),
    3 long, leaving the top wall at x = 3 and leaning ``lean`` degrees (downstream when
    positive); the hand blocking carries the branch's walls on to the floor and cuts the
    branch at its mouth (from a lean of about 25 degrees the better of the two a careful
    user draws; :func:`tilted_tee_upright` the other)."""
    t = np.radians(lean)
    up = _a(np.sin(t), np.cos(t))
    left = _a(3.0, height)
    right = left + (width / np.cos(t), 0.0)
    ring = np.array(
        [(0, 0), (8, 0), (8, height), right, right + 3 * up, left + 3 * up, left, (0, height)]
    )
    down = -height / up[1] * up
    return [ring], [np.array([left, left + down]), np.array([right, right + down]),
                    np.array([left, right])]  # fmt: skip


def tilted_tee_upright(lean: float, width: float, height: float = 1.0) -> Domain:
    """:func:`tilted_tee` with the other hand blocking: the branch corners cut straight
    down to the floor."""
    rings, edges = tilted_tee(lean, width, height)
    return rings, [np.array([e[0], (e[0][0], 0.0)]) for e in edges[:2]] + edges[2:]


TUNING: dict[str, Callable[[], Domain]] = {
    "sharp 60-degree bend": bend_60,
    "tee, branch leaning 20 downstream": lambda: tilted_tee(20.0, 1.0),
    "tee, narrow branch leaning 40 upstream": lambda: tilted_tee(-40.0, 0.5),
    "tee, wide branch leaning 50 downstream, channel 2": lambda: tilted_tee(50.0, 2.0, 2.0),
    "tee, branch 1 wide leaning 60 upstream": lambda: tilted_tee(-60.0, 1.0),
    "Y-branch, arms at +-70 degrees": lambda: y_branch((-70.0, 70.0, 180.0), (1.0,) * 3),
    "Y-branch, three arms 120 apart": lambda: y_branch((-60.0, 60.0, 180.0), (1.0,) * 3),
    "square near the floor": square_near_floor,
    "plate 1 x 0.2 at 10 degrees": plate_at_10,
    "tee, branch leaning 15 upstream": tee_15_upstream,
    "sudden expansion": expansion,
    "open cavity": cavity,
}
REPORT: dict[str, Callable[[], Domain]] = {
    "NACA 0012 at 5 degrees in channel": naca_at_5,
    "three-element section": three_elements,
    "triangle near the floor": triangle_near_floor,
    "diamond near the floor": diamond_near_floor,
    "S-bend": s_bend,
    "two rectangles across": rectangles_across,
    "tee, wide branch leaning 30 downstream": tee_wide_branch,
    "tee, branch leaning 25 upstream": lambda: tilted_tee(-25.0, 0.75),
    "tee, wide branch leaning 35 downstream": lambda: tilted_tee(35.0, 1.5),
    "tee, branch leaning 45 upstream, channel 1.5": lambda: tilted_tee(-45.0, 0.75, 1.5),
    "tee, wide branch leaning 55 downstream, channel 1.5": lambda: tilted_tee(55.0, 1.5, 1.5),
    "Y-branch, skewed": lambda: y_branch((-20.0, 80.0, 200.0), (0.7, 0.9, 1.0)),
    "Y-branch, arms at +-35 degrees": lambda: y_branch((-35.0, 35.0, 180.0), (0.6, 0.6, 1.0), 1.0),
    "main element and flap": two_elements,
    "slat and main element": slat_and_main,
    "two squares side by side": squares_side_by_side,
    "cylinder before a plate": cylinder_before_plate,
    "wedge before a turned square": wedge_and_square,
    "three-element section, landing": three_elements_steep,
}
# the sweep of tilted tees (``--sweep``): leans, branch widths and channel heights of each
# half; a tee's careful hand blocking is the better (lower worst cell) of its two
SWEEP = {
    "tuning half": ((20, 30, 40, 50, 60), (0.5, 1.0, 2.0), (1.0, 2.0)),
    "report half": ((15, 25, 35, 45, 55), (0.75, 1.5), (1.0, 1.5)),
}
TEE_HANDS = (tilted_tee, tilted_tee_upright)


def gmsh_quads(rings: list[np.ndarray], h: float) -> tuple[dict | None, float, int]:
    """gmsh's automatic quads of the domain: mean / worst MaxIncludedAngle of its quads
    (None when gmsh fails), its ``generate`` time and the triangles it leaves."""
    gmsh.model.add("users")
    geo = gmsh.model.geo
    loops = []
    for ring in rings:
        points = [geo.addPoint(float(x), float(y), 0.0, h) for x, y in ring]
        lines = [geo.addLine(points[k], points[(k + 1) % len(points)]) for k in range(len(points))]
        loops.append(geo.addCurveLoop(lines))
    geo.addPlaneSurface(loops)
    geo.synchronize()
    gmsh.option.setNumber("Mesh.Algorithm", GMSH_QUADS)
    gmsh.option.setNumber("Mesh.RecombineAll", 1)
    start = time.perf_counter()
    try:
        gmsh.model.mesh.generate(2)
    except Exception:  # gmsh's own failure is a finding of the table
        gmsh.model.remove()
        return None, time.perf_counter() - start, 0
    seconds = time.perf_counter() - start
    tags, coords, _ = gmsh.model.mesh.getNodes()
    xy = np.zeros((int(tags.max()) + 1, 2))
    xy[tags.astype(int)] = coords.reshape(-1, 3)[:, :2]
    types, _, nodes = gmsh.model.mesh.getElements(2)
    quads = np.zeros((0, 4), dtype=int)
    triangles = 0
    for kind, ids in zip(types, nodes):
        if kind == 3:
            quads = ids.astype(int).reshape(-1, 4)
        elif kind == 2:
            triangles = len(ids) // 3
    gmsh.model.remove()
    p = xy[quads]
    e_in, e_out = p - np.roll(p, 1, axis=1), np.roll(p, -1, axis=1) - p
    cos = -np.einsum("qck,qck->qc", e_in, e_out) / (
        np.linalg.norm(e_in, axis=2) * np.linalg.norm(e_out, axis=2)
    )
    angle = np.degrees(np.arccos(np.clip(cos, -1.0, 1.0)))
    cross = e_in[..., 0] * e_out[..., 1] - e_in[..., 1] * e_out[..., 0]
    sign = np.sign(cross.sum(axis=1, keepdims=True))
    angle = np.where(sign * cross < 0, 360.0 - angle, angle)  # a reflex corner: a fold
    worst = angle.max(axis=1)
    folds = int((sign * cross < 0).any(axis=1).sum())
    quality = {"blocks": len(quads), "mean": float(worst.mean()), "worst": float(worst.max())}
    return quality | {"folds": folds}, seconds, triangles


def run_domain(name: str, make) -> list[str]:
    """The table rows of one domain: auto, hand (where drawn), gmsh's quads."""
    rings, hand_edges = make()
    h = 1.0 / CELLS_ACROSS
    start = time.perf_counter()
    try:
        edges = propose_edges(rings, cell_size=h)  # judged at the size meshed, as a run does
        propose = time.perf_counter() - start
        auto_result, auto_time = meshed(rings, edges, h)
        auto = figures(auto_result)
    except InputError as refusal:
        auto, why = None, str(refusal).splitlines()[0].split(": ", 1)[-1]
    rows = []
    hand = None
    if hand_edges:
        hand_result, hand_time = meshed(rings, hand_edges, h)
        hand = figures(hand_result)
    if auto is None:
        rows.append(f"| {name} | auto | refused: {why} | | | | | |")
    else:
        bounds = ("; ".join(checks(auto, hand)) or "hold") if hand else "(no hand blocking)"
        if auto["folds"]:  # job.run refuses it on every route
            bounds = f"folds: refused in one line; {bounds}"
        rows.append(
            f"| {name} | auto | {_cell(auto)} | {propose:.2f} + {auto_time:.2f} s | {bounds} |"
        )
    if hand is not None:
        rows.append(f"| | hand | {_cell(hand)} | {hand_time:.2f} s | |")
    quads, seconds, triangles = gmsh_quads(rings, h)
    if quads is None:
        rows.append("| | gmsh quads | failed | | | | | |")
    else:
        left = f", {triangles} triangles left" if triangles else ""
        rows.append(
            f"| | gmsh quads{left} | {quads['blocks']} quads | {quads['mean']:.2f} / "
            f"{quads['worst']:.2f} | {quads['folds']} | | {seconds:.2f} s | |"
        )
    return rows


def _careful_hand(rings: list[np.ndarray], blockings: list[list[np.ndarray]]) -> dict | None:
    """The figures of the one of ``blockings`` with the lowest worst cell and no fold (one
    whose edge misses the floor, a steep wide branch's carried past the outlet, is none);
    None where every one folds or misses."""
    found = []
    for edges in blockings:
        try:
            found.append(figures(meshed(rings, edges, 1.0 / CELLS_ACROSS)[0]))
        except InputError:
            continue
    return min((f for f in found if not f["folds"]), key=lambda f: f["worst"], default=None)


def sweep() -> str:
    """The tilted tees of ``SWEEP``, each lean both ways, against the better of the two hand
    blockings: a line per tee that misses a bound and the count of each half."""
    h = 1.0 / CELLS_ACROSS
    lines = []
    for half, (leans, widths, heights) in SWEEP.items():
        held = total = nohand = 0
        cpu = 0.0
        for lean, width, height in itertools.product(leans, widths, heights):
            for side in (1.0, -1.0):
                rings, _ = tilted_tee(side * lean, width, height)
                hand = _careful_hand(
                    rings, [make(side * lean, width, height)[1] for make in TEE_HANDS]
                )
                start = time.process_time()
                try:
                    edges = propose_edges(rings, cell_size=h)
                    cpu += time.process_time() - start
                    auto = figures(meshed(rings, edges, h)[0])
                    failed = checks(auto, hand) if hand else ["folds"] * bool(auto["folds"])
                except InputError as refusal:
                    failed = [str(refusal).splitlines()[0]]
                total += 1
                held += not failed
                nohand += hand is None
                if failed:
                    lines.append(
                        f"- {half}, lean {side * lean:+.0f}, width {width}, channel {height}: "
                        f"{'; '.join(failed)} (hand {_cell(hand) if hand else 'none'})"
                    )
        lines.append(
            f"- {half}: {held} of {total} tilted tees hold every bound ({nohand} of them with no "
            f"hand blocking that meshes, judged on folds alone; proposals "
            f"{cpu:.1f} s CPU in all)"
        )
    return "\n".join(lines) + "\n"


# narrow Ys (``--ys``): arms leaning +-25 to +-45 degrees, 0.5 to 0.7 wide, from an inlet 1
# wide, drawn after the +-35 Y of REPORT, whose refusal the widened search was built on
NARROW_YS = {
    f"arms {a:+g}/{b:+g}, {w:g} wide, mouth {m:g}": ((a, b, 180.0), (w, w, 1.0), m)
    for a, b, w, m in (
        (-25, 25, 0.6, 1.0),
        (-30, 30, 0.6, 1.0),
        (-40, 40, 0.6, 1.0),
        (-45, 45, 0.6, 1.0),
        (-35, 35, 0.5, 1.0),
        (-35, 35, 0.7, 1.0),
        (-30, 40, 0.6, 1.0),
        (-35, 35, 0.6, 1.2),
    )
}


def _line(f: dict) -> str:
    return (
        f"{f['blocks']} blocks, {f['mean']:.2f} / {f['worst']:.2f}, {f['folds']} folds, kinks "
        f"{f['kink']['mean']:.2f} / {f['kink']['max']:.2f}"
    )


def narrow_ys() -> str:
    """The Ys of ``NARROW_YS`` against their hand-drawn three-block centre: a line each."""
    h = 1.0 / CELLS_ACROSS
    lines = []
    for name, (arms, widths, mouth) in NARROW_YS.items():
        rings, hand_edges = y_branch(arms, widths, mouth)
        hand = _careful_hand(rings, [hand_edges])
        start = time.process_time()
        try:
            edges = propose_edges(rings, cell_size=h)
            cpu = time.process_time() - start
            auto = figures(meshed(rings, edges, h)[0])
        except InputError as refusal:
            lines.append(f"- {name}: refused: {str(refusal).split(': ', 1)[-1]}")
            continue
        failed = checks(auto, hand) if hand else ["folds"] * bool(auto["folds"])
        lines.append(
            f"- {name}: {_line(auto)}: {'; '.join(failed) or 'hold'} (hand "
            f"{_line(hand) if hand else 'folds'}; proposal {cpu:.1f} s CPU)"
        )
    return "\n".join(lines) + "\n"


def markdown(names: list[str]) -> str:
    lines = []
    for half, domains in (("tuning half", TUNING), ("report half", REPORT)):
        rows = []
        for name, make in domains.items():
            if name in names:
                mine = run_domain(name, make)
                print("\n".join(mine), flush=True)
                rows += mine
        lines += [
            f"**{half}**:",
            "",
            "| domain | grid | blocks | mean / worst MaxIncludedAngle | folds | interface "
            "kink mean / max | time | bounds |",
            "|---|---|---|---|---|---|---|---|",
            *rows,
            "",
        ]
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, help="a Markdown file with the AUTOBLOCK-USERS markers")
    parser.add_argument("--domains", nargs="+", default=[*TUNING, *REPORT])
    parser.add_argument("--sweep", action="store_true", help="the tilted tees of SWEEP instead")
    parser.add_argument("--ys", action="store_true", help="the narrow Ys of NARROW_YS instead")
    args = parser.parse_args()
    if args.sweep or args.ys:
        print(sweep() if args.sweep else narrow_ys(), end="")
        return
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    gmsh.option.setNumber("General.NumThreads", 1)
    text = markdown(args.domains)
    gmsh.finalize()
    print(text, end="")
    if args.out:
        write_between(args.out, MARK, text)


if __name__ == "__main__":
    import torch

    torch.set_num_threads(1)
    main()
