"""Resolution as a family (docs/family.md): a size change of a grid whose network is trained,
against the asked size's own default run.

Usage: ``.venv/bin/python benchmarks/resize.py [--out docs/family.md] [--sizes 61x31 81x41]``

For each case (a boundary whose default run trains a network: auxiliary lines under the
Winslow objective, a spacing), pyvista's accessor meshes it at 41 x 21 (a training), then
at each asked size: the size change (the network trained at 41 x 21, evaluated at the new
size under that size's guard, kinds.four_sided.resize; the median of 3) and the size's own
default run in a fresh cache (its own training). It prints, per case and size, both times
and their ratio, the worst and mean MaxIncludedAngle of the size change's grid minus the
own run's, the folded cells, the boundary nodes' largest distance from the boundary
(``boundary_deviation``) and from the own run's (a share of the diagonal), and what the size
change kept (``network``, or ``trained anew`` where the guard failed). The ratios are
measured in one process, one after the other, so load moves both alike. It writes the
table between the markers of ``--out``.
"""

from __future__ import annotations

import argparse
import os
import statistics
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "example_data"
BEGIN, END = "<!-- resize benchmark: begin -->", "<!-- resize benchmark: end -->"
TRAINED_AT = (41, 21)
REPEAT = 3  # size changes timed a case and size: the median
WINSLOW = {"objective": "winslow"}  # lines followed by a trained network (the default's
# quality objective follows them by its start and trains none)
SPACING = 2e-3  # a spacing's first edge off the bottom, a share of the diagonal: the default trains
CASES = {
    "fig2, lines, winslow": ("fig2", True, WINSLOW),
    "wavy, lines, winslow": ("wavy", True, WINSLOW),
    "concave, lines, winslow": ("concave", True, WINSLOW),
    "hard/bump, lines, winslow": ("hard/bump", True, WINSLOW),
    "hard/notch_gauss, lines, winslow": ("hard/notch_gauss", True, WINSLOW),
    "fig2, bottom spacing": ("fig2", False, "spacing"),
    "bump_channel, bottom spacing": ("bump_channel", False, "spacing"),
}


def boundary_nodes(grid) -> np.ndarray:
    ni, nj, _ = grid.dimensions
    p = np.asarray(grid.points).reshape(nj, ni, 3)
    return np.concatenate([p[0], p[-1], p[:, 0], p[:, -1]])


def measure(name: str, sizes: list[tuple[int, int]]) -> list[dict]:
    """The rows of one case: a size change and the own run at each of ``sizes``."""
    import pyvista as pv

    import pinn_engine
    from pinn_engine.routes.pyvista_accessor import pinn_mesh

    case, lines, options = CASES[name]
    boundary = pv.read(EXAMPLES / f"{case}.vtp")
    aux = pv.read(EXAMPLES / f"{case}_aux.vtp") if lines else None
    diagonal = float(np.linalg.norm(np.ptp(boundary.points[:, :2], axis=0)))
    if options == "spacing":
        options = {"spacing": {"bottom": SPACING * diagonal}}
    began = time.perf_counter()
    boundary.pinn_mesh(aux=aux, size=TRAINED_AT, **options)
    first = time.perf_counter() - began
    rows = []
    for size in sizes:
        times = []
        for _ in range(REPEAT):
            began = time.perf_counter()
            changed = boundary.pinn_mesh(aux=aux, size=size, **options)
            times.append(time.perf_counter() - began)
            if pinn_engine.report(changed)["resized"]["result"] != "network":
                break  # trained anew: cached now, a repeat would time the cache
        began = time.perf_counter()
        own = pinn_mesh(boundary, aux=aux, size=size, **options)
        own_seconds = time.perf_counter() - began
        r, o = pinn_engine.report(changed), pinn_engine.report(own)
        q, qo = r["quality"], o["quality"]
        rows.append(
            {
                "case": name,
                "size": f"{size[0]} x {size[1]}",
                "first": first,
                "change": statistics.median(times),
                "own": own_seconds,
                "worst": q["worst_max_angle"] - qo["worst_max_angle"],
                "mean": q["mean_max_angle"] - qo["mean_max_angle"],
                "folds": q["folded_cells"],
                "nodes": float(np.abs(boundary_nodes(changed) - boundary_nodes(own)).max())
                / diagonal,
                "deviation": q["boundary_deviation"],
                "kept": r["resized"]["result"],
                "guard": r["resized"]["timings"]["start"],
            }
        )
        print(table(rows[-1:], header=False), flush=True)
    return rows


def table(rows: list[dict], header: bool = True) -> str:
    head = (
        "| case | size | size change (s) | own default run (s) | ratio | start's solve (s) "
        "| worst - own | mean - own | folds | boundary deviation | boundary nodes - own | kept |\n"
        "|---|---|---|---|---|---|---|---|---|---|---|---|\n"
    )
    body = "\n".join(
        f"| {r['case']} | {r['size']} | {r['change']:.3f} | {r['own']:.2f} | "
        f"{r['change'] / r['own']:.3f} | {r['guard']:.3f} | {r['worst']:+.3f} | "
        f"{r['mean']:+.4f} | {r['folds']} | {r['deviation']:.1e} | {r['nodes']:.1e} | "
        f"{r['kept']} |"
        for r in rows
    )
    return (head if header else "") + body


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path)
    parser.add_argument("--sizes", nargs="+", default=["61x31", "81x41", "161x81"])
    parser.add_argument("--cases", nargs="+", default=list(CASES))
    args = parser.parse_args()
    import torch

    torch.set_num_threads(1)
    sizes = [tuple(int(n) for n in s.split("x")) for s in args.sizes]
    load = os.getloadavg()[0]
    rows = [row for name in args.cases for row in measure(name, sizes)]
    ratios = [r["change"] / r["own"] for r in rows]
    kept = sum(r["kept"] == "network" for r in rows)
    text = (
        f"Measured on a shared 2-core machine (load average {load:.1f} at the start, "
        f"{os.getloadavg()[0]:.1f} at the end); trained at {TRAINED_AT[0]} x {TRAINED_AT[1]} "
        f"first.\n\n{table(rows)}\n\nThe network kept at {kept} of {len(rows)} size changes; "
        f"a size change took {statistics.median(ratios):.3f} of the own run's time "
        f"(median; largest {max(ratios):.3f}).\n"
    )
    print("\n" + text)
    if args.out:
        doc = args.out.read_text()
        start, end = doc.index(BEGIN) + len(BEGIN), doc.index(END)
        args.out.write_text(doc[:start] + "\n" + text + doc[end:])


if __name__ == "__main__":
    main()
