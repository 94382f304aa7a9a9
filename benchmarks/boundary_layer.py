"""Boundary-layer example (SPEC 7): the bump channel at 81 x 41, first cell 1e-3 of the
channel height on the floor, grid lines orthogonal there; pinn against elliptic and tfi under
the same spacing.

Usage: ``.venv/bin/python benchmarks/boundary_layer.py [--out docs/boundary_layer.md]``

Prints, per method: run time, the first-edge lengths off the floor relative to the target
(min, median, max over the floor's nodes but its corners), the largest deviation from 90
degrees of the grid lines leaving the floor (the two nodes nearest each corner aside), the
largest growth ratio of consecutive edges along the lines leaving it, the mean and worst
MaxIncludedAngle and the folded cells. Writes the markdown page with the table and the
command, and pictures of each grid zoomed on the floor (``docs/images/boundary_layer_*.png``).
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

from pinn_engine.io.pipeline import load_boundary, to_vtk  # noqa: E402
from pinn_engine.kinds.four_sided.mesher import Mesher  # noqa: E402
from pinn_engine.settings import make_settings  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "example_data" / "bump_channel.vtp"
SIZE = (81, 41)
RUNS = (("tfi", ()), ("elliptic", ("bottom",)), ("pinn", ("bottom",)))
ZOOM = (1.18, 1.32, 0.045, 0.145)  # on the upslope of the bump: x, y box of the pictures
COMMAND = ".venv/bin/python benchmarks/boundary_layer.py"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=str(ROOT / "docs" / "boundary_layer.md"))
    parser.add_argument("--no-images", action="store_true")
    args = parser.parse_args()
    boundary = load_boundary(CASE)
    height = boundary.side("left").length * boundary.frame.scale
    h = 1e-3 * height
    rows = []
    for method, orthogonal in RUNS:
        settings = make_settings(method, lattice=SIZE, spacing={"bottom": h}, orthogonal=orthogonal)
        start = time.perf_counter()
        result = Mesher(settings).fit(boundary).predict(*SIZE)
        seconds = time.perf_counter() - start
        q, floor = result.quality, result.report["sides"]["bottom"]
        row = {
            "method": method + (" (orthogonal floor)" if orthogonal else ""),
            "seconds": seconds,
            "first": [floor[f"first_edge_{k}"] / h for k in ("min", "median", "max")],
            "angle": floor["max_angle_deviation"],
            "growth": floor["max_growth_ratio"],
            "mean": q["mean_max_angle"],
            "worst": q["worst_max_angle"],
            "folded": q["folded_cells"],
        }
        rows.append(row)
        print(
            f"{row['method']:28s} {seconds:6.1f} s  first edge / H "
            f"{row['first'][0]:.3f} {row['first'][1]:.3f} {row['first'][2]:.3f}  wall angle "
            f"+-{row['angle']:.2f} deg  growth {row['growth']:.3f}  MaxIncludedAngle mean "
            f"{row['mean']:.2f} worst {row['worst']:.2f}  folded {row['folded']}",
            flush=True,
        )
        if not args.no_images:
            from pinn_engine.routes.render import render_png

            render_png(
                to_vtk(result),
                ROOT / "docs" / "images" / f"boundary_layer_{method}.png",
                title=f"{method}: bump channel, first cell {h:g} on the floor",
                view=ZOOM,
                window_size=(1000, 700),
                clim=(90.0, 120.0),
            )
    table = [
        "| method | time (s) | first edge / H: min, median, max | wall angle: largest "
        "deviation from 90 (deg) | largest growth ratio | MaxIncludedAngle mean / worst "
        "(deg) | folded |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        table.append(
            f"| {r['method']} | {r['seconds']:.1f} | {r['first'][0]:.3f}, "
            f"{r['first'][1]:.3f}, {r['first'][2]:.3f} | {r['angle']:.2f} | "
            f"{r['growth']:.3f} | {r['mean']:.2f} / {r['worst']:.2f} | "
            f"{r['folded']} |"
        )
    out = Path(args.out)
    text = out.read_text() if out.exists() else ""
    start, end = "<!-- table:start -->", "<!-- table:end -->"
    block = "\n".join([start, "", *table, "", end])
    if start in text and end in text:
        text = text[: text.index(start)] + block + text[text.index(end) + len(end) :]
    else:
        text = text + "\n" + block + "\n"
    out.write_text(text)
    print(f"wrote {out}")


if __name__ == "__main__":
    main()
