"""Folded cells of the Winslow grid and of the default, on the shapes where the first folds.

Usage: ``.venv/bin/python benchmarks/fold_free.py [--set holdout|hard] [--sizes 41x21 81x41]``

For each shape of ``example_data/holdout/`` (the report set; ``--set hard``:
``example_data/hard/``, the tuning set) and size this meshes ``--method elliptic`` and the
default ``pinn`` on the same boundary nodes and, where the elliptic grid folds, prints both
grids' folded cells, the default's mean MaxIncludedAngle above the elliptic grid's (bound:
1 degree), its largest area ratio between neighbouring cells over the elliptic grid's (bound:
1.5) and whether the default's start was untangled (``starts/untangle.py``). Then the totals
per size: grids with folds and folded cells, before (elliptic) and after (default).
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import bench_hard  # noqa: E402

from pinn_engine.kinds.four_sided.mesher import Mesher  # noqa: E402
from pinn_engine.quality import largest_area_ratio  # noqa: E402
from pinn_engine.settings import make_settings  # noqa: E402

FOLDERS = {"holdout": ROOT / "example_data" / "holdout", "hard": bench_hard.HARD}
SIZES = ("41x21", "81x41")  # the hold-out page's sizes
MEAN_OVER, RATIO_TIMES = 1.0, 1.5  # the default's bounds against the Winslow grid


def row(name: str, folder: Path, size: tuple[int, int]) -> dict | None:
    """Both grids' figures on one shape and size; None where the elliptic grid does not fold."""
    boundary, aux = bench_hard.inputs(name, folder)
    grids = {}
    for method in ("elliptic", "pinn"):
        began = time.perf_counter()
        result = Mesher(make_settings(method, lattice=size)).fit(boundary, aux).predict(*size)
        grids[method] = (result, time.perf_counter() - began)
    (ell, _), (pinn, seconds) = grids["elliptic"], grids["pinn"]
    if not ell.quality["folded_cells"]:
        return None
    mean = pinn.quality["mean_max_angle"] - ell.quality["mean_max_angle"]
    ratio = largest_area_ratio(pinn.points) / largest_area_ratio(ell.points)
    return {
        "case": f"{name} {size[0]}x{size[1]}",
        "before": ell.quality["folded_cells"],
        "after": pinn.quality["folded_cells"],
        "mean": mean,
        "ratio": ratio,
        "within": mean <= MEAN_OVER and ratio <= RATIO_TIMES,
        "start": pinn.report["training"].get("start"),
        "seconds": seconds,
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", choices=sorted(FOLDERS), default="holdout")
    parser.add_argument("--sizes", nargs="+", default=list(SIZES))
    args = parser.parse_args()
    folder = FOLDERS[args.set]
    names = sorted(p.stem for p in folder.glob("*.vtp") if not p.stem.endswith("_aux"))
    print("| shape | folded: elliptic | folded: default | mean above | area ratio | start |")
    print("|---|---|---|---|---|---|")
    totals = {}
    for size_text in args.sizes:
        size = tuple(int(v) for v in size_text.split("x"))
        rows = [r for r in (row(n, folder, size) for n in names) if r is not None]
        for r in rows:
            mark = "" if r["within"] else " **out of bounds**"
            print(
                f"| {r['case']} | {r['before']} | {r['after']} | {r['mean']:+.2f} | "
                f"{r['ratio']:.2f}x{mark} | {r['start']} |",
                flush=True,
            )
        totals[size_text] = (len(names), rows)
    print()
    for size_text, (shapes, rows) in totals.items():
        before = sum(r["before"] for r in rows)
        print(
            f"- {size_text}: {len(rows)} of {shapes} elliptic grids fold ({before} cells); "
            f"the default folds {sum(r['after'] > 0 for r in rows)} of them "
            f"({sum(r['after'] for r in rows)} cells); within the bounds: "
            f"{sum(r['within'] for r in rows)} of {len(rows)}"
        )


if __name__ == "__main__":
    main()
