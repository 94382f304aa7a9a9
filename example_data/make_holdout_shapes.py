"""Regenerate the hold-out hard four-sided shapes of ``holdout/``, which no code is tuned on.

Run ``.venv/bin/python example_data/make_holdout_shapes.py``. ``example_data/hard/`` is the set
the code was tuned on; this one is drawn at random from a fixed seed and no code is tuned on it.
The families, mixed and randomly parameterised: smooth wavy walls, notched walls (V, rounded and
rectangular notches of random depth, width, position and sign), forward and backward steps
(sharp and smoothed), small corner angles (sheared quads, kites and darts with corners of 25
to 35 degrees) and combinations of these.

Each side is a base curve between two corners (a straight line or a step) plus an offset along
the base's inward normal that vanishes at both corners. The sides are resampled evenly by arc
length, finely enough that no point along a side turns by more than ``SIDE_TURN_FRACTION`` of
the smallest corner turn, so that ``pinn-mesh FILE`` finds the four drawn corners itself (the
convention of ``make_hard_shapes.py``: a closed counter-clockwise ring starting at the
bottom-left corner, one polyline in ``holdout/<name>.vtp``). A draw that the command refuses
(self-intersecting, corners not found as drawn), that pinches two opposite sides closer than
``MIN_GAP_FRACTION`` or that needs more than ``MAX_SIDE_POINTS`` on a side is rejected and
redrawn from the same shape's random stream, so the set is deterministic.
``holdout/manifest.json`` lists each shape's family, parameters and redraws.
"""

from __future__ import annotations

import json
import sys
from collections.abc import Callable
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from make_examples import HERE, polydata  # noqa: E402
from make_hard_shapes import resample, slot, step  # noqa: E402
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter  # noqa: E402

from pinn_engine.errors import InputError  # noqa: E402
from pinn_engine.geometry.boundary import Boundary, turning_angles  # noqa: E402

OUT = HERE / "holdout"
SEED = 226  # any fixed number; a new one draws a new hold-out set
# How many shapes of each family (48 in all: at least 40 asked, notches and corners weighted up
# because they are what breaks structured meshers).
FAMILY_COUNTS = {"wavy": 8, "notch": 12, "step": 8, "angle": 10, "combo": 10}
MAX_DRAWS = 200  # redraws per shape before giving up (a bug, not bad luck, if ever reached)
DENSE = 40_001  # points of the dense curve resampled by arc length (resolves 0.003-wide tips)
BASE_SPACING = 0.0125  # point spacing of a plain side (as the hard set's 81 points per unit)
MIN_SIDE_POINTS = 21  # a short side still gets enough points to carry a wave
MAX_SIDE_POINTS = 1601  # more points than this on one side: the draw is too sharp, redraw it
SIDE_TURN_FRACTION = 0.5  # a side point turns by at most this of the smallest corner turn
# (detection needs the 5th-largest turn below 0.75 of the 4th; this leaves a margin)
REFINE = 1.5  # growth of a side's point count while it turns too sharply
MIN_GAP_FRACTION = 0.03  # of the diagonal: opposite sides closer than this are a near-touch
DECIMALS = 9  # coordinates written rounded to this many decimals (short, exact to re-read)
CORNER_TOL = 1e-7  # of the diagonal: a detected corner this close to a drawn one is it
MAX_WAVE_SLOPE = 1.0  # a wave's largest slope (45 degrees): steeper is a notch, not a wave
MAX_WAVE_AMP = 0.2  # of the height: a wave larger than this is a channel pinch
SMALL_ANGLE = (25.0, 35.0)  # degrees: the small corner angles asked for


# --- profiles: offsets along the inward normal, functions of arc length u along the base ---


def wave(amp: float, k: int, phase: float, length: float) -> Callable:
    """``k`` half-waves over the side (the linear part through the ends is removed later)."""
    return lambda u: amp * np.sin(k * np.pi * u / length + phase)


def bulge(amp: float, k: int, length: float) -> Callable:
    """``k`` bulges of sin^2 shape: zero and flat at both ends (a corner keeps its angle)."""
    return lambda u: amp * np.sin(k * np.pi * u / length) ** 2


def v_notch(depth: float, half: float, centre: float, tip: float, shoulder: float) -> Callable:
    """A V of ``depth`` and half-width ``half``, tip rounded to ``tip``, shoulders rounded."""

    def f(u):
        z = 1 - np.sqrt((u - centre) ** 2 + tip**2) / half
        return depth * 0.5 * (z + np.sqrt(z**2 + shoulder**2))  # smooth max(0, z)

    return f


def round_notch(depth: float, half: float, centre: float) -> Callable:
    """A Gaussian notch of ``depth`` and half-width ``half``."""
    return lambda u: depth * np.exp(-(((u - centre) / half) ** 2))


def rect_notch(depth: float, width: float, centre: float, edge: float) -> Callable:
    """A flat-bottomed notch with edges rounded to ``edge`` (``make_hard_shapes.slot``)."""
    return lambda u: slot(u, centre, width, depth, edge)


# --- sides and shapes ---


def base_curve(a: np.ndarray, b: np.ndarray, riser: dict | None) -> np.ndarray:
    """The dense base of a side from ``a`` to ``b``: a straight line, or with ``riser`` a step
    that climbs b's height difference along y at ``riser['at']`` (fraction) over
    ``riser['edge']`` (length)."""
    s = np.linspace(0.0, 1.0, DENSE)
    pts = a + s[:, None] * (b - a)
    if riser:
        length = abs(b[0] - a[0])
        u = s * length
        c, e = riser["at"] * length, riser["edge"]
        lo, hi = step((0 - c) / e), step((length - c) / e)
        frac = (step((u - c) / e) - lo) / (hi - lo)
        pts[:, 1] = a[1] + frac * (b[1] - a[1])
    return pts


def side_curve(a, b, riser: dict | None, offsets: list[Callable]) -> np.ndarray:
    """A dense side: base curve plus the sum of ``offsets`` along the inward (left) normal,
    less the straight line through their end values (so both corners stay put)."""
    base = base_curve(np.asarray(a, float), np.asarray(b, float), riser)
    seg = np.linalg.norm(np.diff(base, axis=0), axis=1)
    u = np.concatenate([[0.0], np.cumsum(seg)])
    if not offsets:
        return base
    g = sum(f(u) for f in offsets)
    g = g - (g[0] + (g[-1] - g[0]) * u / u[-1])
    t = np.gradient(base, u, axis=0)
    t /= np.linalg.norm(t, axis=1, keepdims=True)
    normal = np.column_stack([-t[:, 1], t[:, 0]])  # left of travel: inward on a CCW ring
    return base + g[:, None] * normal


def sample_ring(dense_sides: list[np.ndarray]) -> np.ndarray | None:
    """The ring of evenly resampled sides, refined side by side until no point along a side
    turns by more than ``SIDE_TURN_FRACTION`` of the smallest corner turn; None if a side would
    need more than ``MAX_SIDE_POINTS``."""
    lengths = [float(np.linalg.norm(np.diff(d, axis=0), axis=1).sum()) for d in dense_sides]
    counts = [max(MIN_SIDE_POINTS, int(np.ceil(n / BASE_SPACING)) + 1) for n in lengths]
    while True:
        sides = [resample(d, n) for d, n in zip(dense_sides, counts)]
        ring = np.vstack([s[:-1] for s in sides])
        turn = np.abs(turning_angles(ring))
        starts = np.cumsum([0] + [n - 1 for n in counts[:-1]])
        limit = SIDE_TURN_FRACTION * turn[starts].min()
        worst = [turn[s + 1 : s + n - 1].max() for s, n in zip(starts, counts)]
        if all(w <= limit for w in worst):
            return ring
        for k, w in enumerate(worst):
            if w > limit:
                counts[k] = int(np.ceil(counts[k] * REFINE))
        if max(counts) > MAX_SIDE_POINTS:
            return None


def build(spec: dict) -> tuple[np.ndarray, np.ndarray] | None:
    """Ring and corner points of a drawn shape, or None where it is rejected."""
    corners = np.asarray(spec["corners"], float)
    dense = [
        side_curve(corners[k], corners[(k + 1) % 4], side.get("riser"), side["offsets"])
        for k, side in enumerate(spec["sides"])
    ]
    ring = sample_ring(dense)
    if ring is None:
        return None
    return np.round(ring, DECIMALS), np.round(corners, DECIMALS)


def check(ring: np.ndarray, corners: np.ndarray) -> str | None:
    """Why the command would refuse the ring or find other corners than drawn (None if fine)."""
    try:
        boundary = Boundary.from_points(ring, source="draw")
    except InputError as err:
        return str(err)
    found = boundary.frame.to_user(boundary.corner_points())
    diag = float(np.linalg.norm(ring.max(axis=0) - ring.min(axis=0)))
    near = np.linalg.norm(found[:, None] - corners[None], axis=2).min(axis=1)
    if near.max() > CORNER_TOL * diag:
        return "corners not found as drawn"
    return None


def gap(ring: np.ndarray, corners: np.ndarray) -> float:
    """The smallest distance between points of opposite sides, relative to the diagonal."""
    idx = sorted(int(np.linalg.norm(ring - c, axis=1).argmin()) for c in corners)
    sides = [ring[idx[k] : (idx[k + 1] if k < 3 else len(ring))] for k in range(4)]
    sides[3] = np.vstack([sides[3], ring[:1]])
    diag = float(np.linalg.norm(ring.max(axis=0) - ring.min(axis=0)))
    pairs = ((sides[0], sides[2]), (sides[1], sides[3]))
    return min(float(np.linalg.norm(p[:, None] - q[None], axis=2).min()) for p, q in pairs) / diag


# --- the families: each returns a spec (corners, four sides) and its parameters ---


def _box(rng, width: float, jitter: float) -> np.ndarray:
    """A width x 1 box with corners 1..3 moved by up to ``jitter`` (corner 0 at the origin)."""
    box = np.array([[0, 0], [width, 0], [width, 1], [0, 1]], float)
    box[1:] += rng.uniform(-jitter, jitter, (3, 2))
    return box


def _length(corners: np.ndarray, k: int) -> float:
    return float(np.linalg.norm(corners[(k + 1) % 4] - corners[k]))


def _waves(rng, length: float, count: int, kmax: int, amp_cap: float) -> tuple[list, list]:
    """``count`` random waves on a side of ``length``: amplitude within the slope and size caps."""
    fs, ps = [], []
    for _ in range(count):
        k = int(rng.integers(1, kmax + 1))
        cap = min(amp_cap, MAX_WAVE_SLOPE * length / (k * np.pi))
        amp = float(rng.uniform(0.3, 1.0) * cap * rng.choice([-1, 1]))
        phase = float(rng.uniform(0, 2 * np.pi))
        fs.append(wave(amp, k, phase, length))
        ps.append({"wave": {"amp": amp, "k": k, "phase": phase}})
    return fs, ps


def _notch(rng, length: float, kinds=("v", "round", "rect")) -> tuple[Callable, dict]:
    """A random notch on a side of ``length``: V, rounded or rectangular, into the domain (an
    intrusion, as the tuning set's) three times in four, else out of it (a cavity)."""
    kind = str(rng.choice(kinds))
    sign = 1.0 if rng.uniform() < 0.75 else -1.0
    depth = sign * float(rng.uniform(0.15, 0.7 if sign > 0 else 0.5))
    centre = float(rng.uniform(0.15, 0.85) * length)
    if kind == "v":
        half, tip = float(rng.uniform(0.05, 0.25)), float(rng.uniform(0.003, 0.03))
        shoulder = float(rng.uniform(0.02, 0.1))
        f = v_notch(depth, half, centre, tip, shoulder)
        p = {"half_width": half, "tip": tip, "shoulder": shoulder}
    elif kind == "round":
        half = float(rng.uniform(0.04, 0.25))
        f, p = round_notch(depth, half, centre), {"half_width": half}
    else:
        width, edge = float(rng.uniform(0.05, 0.4)), float(rng.uniform(0.01, 0.04))
        f, p = rect_notch(depth, width, centre, edge), {"width": width, "edge": edge}
    return f, {"notch": {"kind": kind, "depth": depth, "centre": centre, **p}}


def _empty_sides() -> list[dict]:
    return [{"offsets": [], "params": []} for _ in range(4)]


def _add(side: dict, fs, ps) -> None:
    side["offsets"] += fs if isinstance(fs, list) else [fs]
    side["params"] += ps if isinstance(ps, list) else [ps]


def draw_wavy(rng) -> tuple[dict, str]:
    """Smooth wavy walls (1 or 2 waves each), sometimes wavy ends, on a jittered box."""
    corners = _box(rng, float(rng.uniform(1.0, 3.0)), 0.15)
    sides = _empty_sides()
    for k in (0, 2):
        _add(sides[k], *_waves(rng, _length(corners, k), int(rng.integers(1, 3)), 6, MAX_WAVE_AMP))
    for k in (1, 3):
        if rng.uniform() < 0.5:
            _add(sides[k], *_waves(rng, _length(corners, k), 1, 2, 0.1))
    return {"corners": corners, "sides": sides}, "wavy"


def draw_notch(rng) -> tuple[dict, str]:
    """One notch (two, three times in ten) on random sides of a jittered box."""
    corners = _box(rng, float(rng.uniform(1.0, 3.0)), 0.1)
    sides = _empty_sides()
    kinds = []
    for _ in range(2 if rng.uniform() < 0.3 else 1):
        k = int(rng.choice([0, 2])) if rng.uniform() < 0.85 else int(rng.choice([1, 3]))
        f, p = _notch(rng, _length(corners, k))
        _add(sides[k], f, p)
        kinds.append(p["notch"]["kind"])
    return {"corners": corners, "sides": sides}, "notch_" + "_".join(kinds)


def _step_channel(rng, edge: tuple[float, float]) -> tuple[np.ndarray, list[dict], str]:
    """A channel (length 2 to 4, height 1) with a step on the bottom or the top wall,
    forward (narrowing) or backward (widening), of 0.2 to 0.6 of the height."""
    width, h = float(rng.uniform(2.0, 4.0)), float(rng.uniform(0.2, 0.6))
    forward, on_bottom = rng.uniform() < 0.5, rng.uniform() < 0.5
    corners = np.array([[0, 0], [width, 0], [width, 1], [0, 1]], float)
    if on_bottom:
        corners[1 if forward else 0, 1] = h
    else:
        corners[2 if forward else 3, 1] = 1 - h
    sides = _empty_sides()
    at = float(rng.uniform(0.25, 0.7))
    e = float(rng.uniform(*edge))
    # the top wall runs right to left: a step at fraction `at` from the inlet is at 1 - at
    sides[0 if on_bottom else 2]["riser"] = {"at": at if on_bottom else 1 - at, "edge": e}
    sides[0 if on_bottom else 2]["params"].append(
        {"step": {"height": h, "at": at, "edge": e, "forward": bool(forward)}}
    )
    name = f"step_{'forward' if forward else 'backward'}_{'bottom' if on_bottom else 'top'}"
    return corners, sides, name


def draw_step(rng) -> tuple[dict, str]:
    """A forward or backward step, sharp (edge 0.015 to 0.04) or smoothed (0.1 to 0.5); the
    other wall wavy two times in five."""
    sharp = rng.uniform() < 0.5
    corners, sides, name = _step_channel(rng, (0.015, 0.04) if sharp else (0.1, 0.5))
    other = 2 if "riser" in sides[0] else 0
    if rng.uniform() < 0.4:
        _add(sides[other], *_waves(rng, _length(corners, other), 1, 4, 0.1))
    return {"corners": corners, "sides": sides}, name + ("_sharp" if sharp else "_smooth")


def _sheared(rng, angle: float) -> np.ndarray:
    """A parallelogram (half the time) or trapezoid with ``angle`` at the bottom-left corner,
    mirrored half the time so that the angle is at the bottom-right."""
    width, height = float(rng.uniform(1.5, 3.0)), float(rng.uniform(0.6, 1.2))
    c3 = np.array([height / np.tan(np.radians(angle)), height])
    if rng.uniform() < 0.5:
        c2 = np.array([width, 0]) + c3
    else:
        beta = np.radians(rng.uniform(60, 120))  # direction of the right side
        c2 = np.array([width + height / np.tan(beta), height])
    corners = np.array([[0, 0], [width, 0], c2, c3])
    if rng.uniform() < 0.5:  # mirror x, keep the ring counter-clockwise from the bottom-left
        m = corners * [-1, 1]
        corners = np.array([m[1], m[0], m[3], m[2]])
        corners -= corners[0]
    return corners


def _kite(rng, angle: float) -> np.ndarray:
    """A kite with ``angle`` at its tip; the tail angle small too three times in ten."""
    p = float(rng.uniform(1.5, 3.0))
    q = p * np.tan(np.radians(angle) / 2)
    if rng.uniform() < 0.3:
        tail = q / np.tan(np.radians(rng.uniform(*SMALL_ANGLE)) / 2)
    else:
        tail = q * float(rng.uniform(0.3, 2.0))
    return np.array([[0, 0], [p, -q], [p + tail, 0], [p, q]])


def _dart(rng, angle: float) -> np.ndarray:
    """A convex quad with ``angle`` at its tip, lopsided: the tip's two sides of different
    lengths and directions, the far corner pushed out beyond the middle of the other two."""
    a = np.radians(angle)
    tilt = float(rng.uniform(0.2, 0.8)) * a
    lb, lq = rng.uniform(1.5, 3.0, 2)
    b = lb * np.array([np.cos(-tilt), np.sin(-tilt)])
    q = lq * np.array([np.cos(a - tilt), np.sin(a - tilt)])
    mid, axis = (b + q) / 2, (b + q) / np.linalg.norm(b + q)
    r = mid + axis * float(rng.uniform(0.15, 1.0)) * np.linalg.norm(q - b) / 2
    return np.array([[0, 0], b, r, q])


def draw_angle(rng) -> tuple[dict, str]:
    """A sheared quad, kite or dart with a corner of 25 to 35 degrees; each side gently curved
    half the time (one or two bulges of up to 6 % of its length, flat at the corners so that
    they keep the drawn angles)."""
    angle = float(rng.uniform(*SMALL_ANGLE))
    kind = str(rng.choice(["sheared", "kite", "dart"]))
    corners = {"sheared": _sheared, "kite": _kite, "dart": _dart}[kind](rng, angle)
    sides = _empty_sides()
    for k in range(4):
        if rng.uniform() < 0.5:
            length, n = _length(corners, k), int(rng.integers(1, 3))
            amp = float(rng.uniform(-0.06, 0.06) * length / n)
            _add(sides[k], bulge(amp, n, length), {"bulge": {"amp": amp, "k": n}})
    sides[0]["params"].append({"small_angle": angle})
    return {"corners": corners, "sides": sides}, f"angle_{kind}"


def draw_combo(rng) -> tuple[dict, str]:
    """A notch on a box, a sheared quad (corner of 30 to 60 degrees) or a step channel, plus
    waves on the other wall (seven times in ten) and a second notch (three times in ten)."""
    base = str(rng.choice(["box", "sheared", "step"]))
    if base == "box":
        corners, sides = _box(rng, float(rng.uniform(1.5, 3.0)), 0.15), _empty_sides()
    elif base == "sheared":
        corners, sides = _sheared(rng, float(rng.uniform(30, 60))), _empty_sides()
    else:
        corners, sides, _ = _step_channel(rng, (0.02, 0.4))
    k = int(rng.choice([0, 2]))
    _add(sides[k], *_notch(rng, _length(corners, k)))
    if rng.uniform() < 0.7:
        _add(sides[2 - k], *_waves(rng, _length(corners, 2 - k), 1, 4, 0.12))
    if rng.uniform() < 0.3:
        j = int(rng.choice([0, 2]))
        _add(sides[j], *_notch(rng, _length(corners, j)))
    return {"corners": corners, "sides": sides}, f"combo_{base}"


FAMILIES = {
    "wavy": draw_wavy,
    "notch": draw_notch,
    "step": draw_step,
    "angle": draw_angle,
    "combo": draw_combo,
}


def schedule() -> list[str]:
    """The family of each shape, in file order."""
    return [family for family, n in FAMILY_COUNTS.items() for _ in range(n)]


def _rounded(params):
    """Parameters with floats to 6 significant digits (the manifest is for reading)."""
    if isinstance(params, dict):
        return {k: _rounded(v) for k, v in params.items()}
    if isinstance(params, list):
        return [_rounded(v) for v in params]
    return float(f"{params:.6g}") if isinstance(params, float) else params


def draw_shape(index: int) -> tuple[str, np.ndarray, dict]:
    """Shape ``index``: its name, ring and record, from its own stream ``(SEED, index)``."""
    family = schedule()[index]
    rng = np.random.default_rng((SEED, index))
    rejected: dict[str, int] = {}
    for _ in range(MAX_DRAWS):
        spec, kind = FAMILIES[family](rng)
        built = build(spec)
        why = "a side needs more than MAX_SIDE_POINTS" if built is None else check(*built)
        if why is None and gap(*built) < MIN_GAP_FRACTION:
            why = "opposite sides closer than MIN_GAP_FRACTION"
        if why is None:
            ring, corners = built
            at = [int(np.linalg.norm(ring - c, axis=1).argmin()) for c in corners]
            record = {
                "family": family,
                "kind": kind,
                "corners": corners.tolist(),
                "corner_angles": [round(180 - float(t), 2) for t in turning_angles(ring)[at]],
                "points": len(ring),
                "sides": _rounded([side["params"] for side in spec["sides"]]),
                "rejected": rejected,
            }
            return f"h{index:02d}_{kind}", ring, record
        key = why.split(" (")[0]
        rejected[key] = rejected.get(key, 0) + 1
    raise RuntimeError(f"shape {index} ({family}): no valid draw in {MAX_DRAWS}")


def write_ring(ring: np.ndarray, path: Path) -> None:
    """The ring as one closed polyline, ASCII like ``example_data/hard/``."""
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(polydata([ring], closed=True))
    writer.SetDataModeToAscii()
    writer.Write()


def main(out: Path = OUT, indices: list[int] | None = None) -> dict:
    """Write the shapes ``indices`` (all by default) and, for all, the manifest, into ``out``."""
    out.mkdir(parents=True, exist_ok=True)
    manifest = {}
    for index in range(len(schedule())) if indices is None else indices:
        name, ring, record = draw_shape(index)
        write_ring(ring, out / f"{name}.vtp")
        manifest[name] = record
        print(f"{name}: {len(ring)} points, redraws {record['rejected'] or 'none'}", flush=True)
    if indices is None:
        rows = ",\n".join(f" {json.dumps(k)}: {json.dumps(v)}" for k, v in manifest.items())
        (out / "manifest.json").write_text(f'{{"seed": {SEED}, "shapes": {{\n{rows}\n}}}}\n')
    return manifest


if __name__ == "__main__":
    main()
