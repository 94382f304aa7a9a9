"""Folds of the default on four-sided shapes drawn at random: a tuning set and a held-out set.

Usage: ``.venv/bin/python benchmarks/fold_sweep.py [--set tuning|heldout] [--sizes 21x11 ...]
[--per-family 4] [--families NAME ...] [--cases]``

The shapes are of five families where the Winslow grid folds: deep rectangular
notches, sharp forward steps, narrow slots, inward spikes and stairs. This draws shapes of
those families from a fixed seed per set, with their own depths, widths, tip angles, numbers
of teeth and domain aspects (``tuning``: the set the untangling may be tuned on; ``heldout``:
another seed, never tuned on), and meshes each at sizes from 21 x 11 to 121 x 61 and at
non-square lattices, with ``--method elliptic`` and with the default, on the same boundary
nodes. Per family it prints the grids whose elliptic grid folds and whose default folds; of
those, the ones that no grid on those boundary nodes can unfold (``untangle.fold_forced``);
the default's mean and worst ``MaxIncludedAngle`` against the elliptic grid's (mean and
largest difference over the grids that fold); and the time of the default over the elliptic
grid's (fit and grid, in one process: over the folding grids and over all). ``--cases``
prints a row per folding grid as well.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "example_data"))
from make_hard_shapes import resample, slot, step  # noqa: E402

from pinn_engine.geometry.boundary import Boundary  # noqa: E402
from pinn_engine.kinds.four_sided.mesher import Mesher  # noqa: E402
from pinn_engine.settings import make_settings  # noqa: E402
from pinn_engine.starts.untangle import fold_forced  # noqa: E402

SEEDS = {"tuning": 3201, "heldout": 3202}  # any fixed numbers; one set each
# The sizes 41 x 21 and 81 x 41 are the hold-out page's (benchmarks/fold_free.py);
# these are the others: coarser, finer and lattices of other aspects than the domain's
SIZES = ("21x11", "31x16", "61x31", "121x61", "81x21", "25x25")
PER_FAMILY = 4  # shapes per family and set
DENSE = 40_001  # points of a dense side before resampling (resolves edges of 0.003)
SPACING = 0.0125  # boundary point spacing (the hold-out set's)
MIN_SIDE_POINTS = 21  # a short side still gets a few points


def _side(points: np.ndarray) -> np.ndarray:
    """A dense side resampled evenly by arc length at ``SPACING``."""
    length = float(np.linalg.norm(np.diff(points, axis=0), axis=1).sum())
    return resample(points, max(MIN_SIDE_POINTS, int(np.ceil(length / SPACING)) + 1))


def _graph(f: Callable, x0: float, x1: float) -> np.ndarray:
    x = np.linspace(x0, x1, DENSE)
    return _side(np.column_stack([x, f(x)]))


def _line(a, b) -> np.ndarray:
    return _side(np.linspace(np.asarray(a, float), np.asarray(b, float), DENSE))


def _channel(bottom: Callable, top: Callable, width: float) -> tuple[np.ndarray, list[int]]:
    """The ring of a channel between y = bottom(x) and y = top(x), x in [0, width], counter-
    clockwise from the bottom-left corner, and its four corners' indices."""
    sides = [
        _graph(bottom, 0.0, width),
        _line((width, bottom(np.array(width))), (width, top(np.array(width)))),
        _graph(top, width, 0.0),
        _line((0.0, top(np.array(0.0))), (0.0, bottom(np.array(0.0)))),
    ]
    starts = np.cumsum([0] + [len(s) - 1 for s in sides[:-1]])
    return np.vstack([s[:-1] for s in sides]), [int(k) for k in starts]


def _riser(x: np.ndarray, at: float, edge: float, width: float) -> np.ndarray:
    """A step from 0 at x = 0 to 1 at x = ``width``, at ``at`` over about ``edge``."""
    lo, hi = step(-at / edge), step((width - at) / edge)
    return (step((x - at) / edge) - lo) / (hi - lo)


def _mirror(rng, bottom: Callable, top: Callable, height: float):
    """The features on the bottom wall, or (half the time) the same on the top wall."""
    if rng.uniform() < 0.5:
        return bottom, top
    return (lambda x: 0.0 * x), (lambda x: height - bottom(x))


def rect_notch(rng) -> tuple[dict, Callable, Callable, float]:
    """One or two deep rectangular notches into the domain from a wall."""
    width, height = float(rng.uniform(1.0, 3.0)), float(rng.uniform(0.7, 1.3))
    count = int(rng.integers(1, 3))
    notches = [  # one notch per 1 / count of the width, so that two never overlap
        (
            float((k + rng.uniform(0.3, 0.7)) * width / count),
            float(rng.uniform(0.04, 0.3) * min(1.0, width / count)),
            float(rng.uniform(0.45, 0.8) * height),
            float(rng.uniform(0.004, 0.015)),
        )
        for k in range(count)
    ]

    def bottom(x):
        return sum(slot(x, c, w, d, e) for c, w, d, e in notches)

    params = {"notches": [[round(v, 3) for v in n] for n in notches]}
    return params, bottom, (lambda x: height + 0.0 * x), width


def forward_step(rng) -> tuple[dict, Callable, Callable, float]:
    """A sharp forward step (the channel narrows) of 0.3 to 0.7 of its height."""
    width, height = float(rng.uniform(2.0, 5.0)), float(rng.uniform(0.6, 1.4))
    at, rise = float(rng.uniform(0.2, 0.7) * width), float(rng.uniform(0.3, 0.7) * height)
    edge = float(rng.uniform(0.004, 0.02))

    def bottom(x):
        return rise * _riser(x, at, edge, width)

    params = {"at": round(at, 3), "rise": round(rise, 3), "edge": round(edge, 4)}
    return params, bottom, (lambda x: height + 0.0 * x), width


def slots(rng) -> tuple[dict, Callable, Callable, float]:
    """Two to four narrow slots, staggered from the bottom and the top walls (a baffle maze)."""
    width, height = float(rng.uniform(1.5, 4.0)), float(rng.uniform(0.7, 1.3))
    count = int(rng.integers(2, 5))
    centres = (np.arange(count) + 0.5 + rng.uniform(-0.2, 0.2, count)) * width / count
    shapes = [
        (
            float(c),
            float(rng.uniform(0.03, 0.12)),
            float(rng.uniform(0.35, 0.65) * height),
            float(rng.uniform(0.005, 0.02)),
        )
        for c in centres
    ]
    lower, upper = shapes[0::2], shapes[1::2]

    def bottom(x):
        return sum(slot(x, c, w, d, e) for c, w, d, e in lower)

    def top(x):
        return height - sum(slot(x, c, w, d, e) for c, w, d, e in upper)

    return {"slots": [[round(v, 3) for v in s] for s in shapes]}, bottom, top, width


def spikes(rng) -> tuple[dict, Callable, Callable, float]:
    """One to three inward spikes: V intrusions of 6 to 40 degrees at a tip rounded to 0.2
    to 1 % of the height."""
    width, height = float(rng.uniform(1.0, 3.0)), float(rng.uniform(0.7, 1.3))
    count = int(rng.integers(1, 4))
    spikes = []
    for k in range(count):
        depth = float(rng.uniform(0.3, 0.75) * height)
        angle = float(rng.uniform(6.0, 40.0))
        half = depth * np.tan(np.radians(angle / 2))
        centre = float((k + 0.5 + rng.uniform(-0.25, 0.25)) * width / count)
        spikes.append((centre, half, depth, float(rng.uniform(0.002, 0.01) * height), angle))

    def bottom(x):
        out = 0.0 * x
        for c, half, depth, tip, _ in spikes:
            z = 1 - np.sqrt((x - c) ** 2 + tip**2) / half
            out = out + depth * 0.5 * (z + np.sqrt(z**2 + 1e-4))  # smooth max(0, z)
        return out

    params = {"spikes": [[round(v, 3) for v in s] for s in spikes]}
    return params, bottom, (lambda x: height + 0.0 * x), width


def stairs(rng) -> tuple[dict, Callable, Callable, float]:
    """Two to five sharp steps up (or down) in a row along a wall."""
    width, height = float(rng.uniform(2.0, 5.0)), float(rng.uniform(0.8, 1.4))
    teeth = int(rng.integers(2, 6))
    total = float(rng.uniform(0.35, 0.7) * height)
    rises = rng.dirichlet(np.ones(teeth)) * total
    ats = np.linspace(rng.uniform(0.1, 0.4), rng.uniform(0.6, 0.9), teeth) * width
    edge = float(rng.uniform(0.004, 0.02))
    down = rng.uniform() < 0.5

    def bottom(x):
        up = sum(r * _riser(x, a, edge, width) for r, a in zip(rises, ats))
        return total - up if down else up

    params = {"teeth": teeth, "rises": np.round(rises, 3).tolist(), "down": bool(down)}
    return params, bottom, (lambda x: height + 0.0 * x), width


FAMILIES = {
    "rect_notch": rect_notch,
    "forward_step": forward_step,
    "slots": slots,
    "spikes": spikes,
    "stairs": stairs,
}


def shapes(set_name: str, families: list[str], per_family: int) -> list[tuple[str, Boundary]]:
    """The set's shapes: ``per_family`` of each family, each from its own random stream."""
    out = []
    for f, family in enumerate(FAMILIES):
        for k in range(per_family):
            rng = np.random.default_rng((SEEDS[set_name], f, k))
            params, bottom, top, width = FAMILIES[family](rng)
            if family != "slots":
                height = float(top(np.array(0.0)))
                bottom, top = _mirror(rng, bottom, top, height)
            if family not in families:
                continue
            ring, corners = _channel(bottom, top, width)
            boundary = Boundary.from_points(ring, tuple(corners), source=f"{family}_{k}")
            out.append((f"{family}_{k}", boundary))
    return out


def run(boundary: Boundary, size: tuple[int, int]) -> dict:
    """Both grids' figures and seconds on one shape and size."""
    out = {}
    for method in ("elliptic", "pinn"):
        began = time.perf_counter()
        result = Mesher(make_settings(method, lattice=size)).fit(boundary, []).predict(*size)
        out[method] = {**result.quality, "seconds": time.perf_counter() - began}
        out[method]["grid"] = np.asarray(result.points)[..., :2]
    return out


def family_line(family: str, rows: list[dict]) -> str:
    folding = [r for r in rows if r["elliptic"]["folded_cells"]]
    forced = sum(fold_forced(r["elliptic"]["grid"]) is not None for r in folding)
    mean = [r["pinn"]["mean_max_angle"] - r["elliptic"]["mean_max_angle"] for r in folding]
    worst = [r["pinn"]["worst_max_angle"] - r["elliptic"]["worst_max_angle"] for r in folding]

    def ratio(rs):
        if not rs:
            return "-"
        seconds = {m: sum(r[m]["seconds"] for r in rs) for m in ("pinn", "elliptic")}
        return f"{seconds['pinn'] / seconds['elliptic']:.2f}x"

    def spread(v):
        return f"{statistics.mean(v):+.2f} / {max(v):+.2f}" if v else "-"

    return (
        f"| {family} | {len(rows)} | {len(folding)} | "
        f"{sum(r['pinn']['folded_cells'] > 0 for r in rows)} | {forced} | {spread(mean)} | "
        f"{spread(worst)} | {ratio(folding)} | {ratio(rows)} |"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", choices=sorted(SEEDS), default="heldout")
    parser.add_argument("--sizes", nargs="+", default=list(SIZES))
    parser.add_argument("--per-family", type=int, default=PER_FAMILY)
    parser.add_argument("--families", nargs="+", default=list(FAMILIES), choices=list(FAMILIES))
    parser.add_argument("--cases", action="store_true", help="a row per folding grid too")
    args = parser.parse_args()
    sizes = [tuple(int(v) for v in s.split("x")) for s in args.sizes]
    rows: dict[str, list[dict]] = {f: [] for f in args.families}
    for name, boundary in shapes(args.set, args.families, args.per_family):
        for size in sizes:
            r = run(boundary, size)
            rows[name.rsplit("_", 1)[0]].append(r)
            if args.cases and r["elliptic"]["folded_cells"]:
                e, p = r["elliptic"], r["pinn"]
                print(
                    f"  {name} {size[0]}x{size[1]}: folded {e['folded_cells']} -> "
                    f"{p['folded_cells']}, mean {p['mean_max_angle'] - e['mean_max_angle']:+.2f}, "
                    f"worst {p['worst_max_angle'] - e['worst_max_angle']:+.2f}, "
                    f"{p['seconds']:.2f} s / {e['seconds']:.2f} s",
                    flush=True,
                )
    print(f"\nset {args.set} (seed {SEEDS[args.set]}), sizes {' '.join(args.sizes)}\n")
    print(
        "| family | grids | elliptic folds | default folds | of them forced | "
        "mean above: mean / largest | worst above: mean / largest | "
        "time default / elliptic: folding | all |"
    )
    print("|---|---|---|---|---|---|---|---|---|")
    for family, family_rows in rows.items():
        print(family_line(family, family_rows))
    print(family_line("all", [r for rs in rows.values() for r in rs]))


if __name__ == "__main__":
    main()
