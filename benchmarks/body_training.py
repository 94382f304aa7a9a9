"""Where a body grid's network wins: the network trained on every grid, also where the
default does not train it (``kinds.body.untrained.body_cannot_win``), and what its guard kept.

Usage::

    .venv/bin/python benchmarks/body_training.py [FILE.dat ...] [--set shared/airfoils]
        [--half tuning] [--first 1e-5 ...] [--naca 0012 4412] [--limit N]

Each airfoil (the files given, the ``.dat`` files of ``--set``, of one half if given, and
the NACA sections ``--naca``, sharp) is meshed as an O-grid of 250 x 80 and a C-grid of
300 x 80 nodes, far field 15 chords, at each first layer ``--first`` (chords; ``default``:
the default first layer), by the elliptic method, then its network is trained from that
grid (``kinds.body.problem.train_body``, the default settings). Per grid: its wall cells'
aspect ratio (``Layout.wall_aspect``), whether the guard kept the network's grid or the
start, and the mean and worst MaxIncludedAngle before and after. The summary counts the grids whose
network's grid was kept, by the aspect ratio's side of ``untrained.THIN_WALL``.
"""

from __future__ import annotations

import argparse
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from airfoil_set import FAR_FIELD, SIZES, half  # noqa: E402

from pinn_engine.bodies import bodygrid  # noqa: E402
from pinn_engine.bodies.airfoil import circle, load_body, naca4  # noqa: E402
from pinn_engine.errors import InputError  # noqa: E402
from pinn_engine.kinds.body.problem import train_body  # noqa: E402
from pinn_engine.kinds.body.untrained import THIN_WALL  # noqa: E402
from pinn_engine.quality import guard_figures  # noqa: E402
from pinn_engine.settings import make_settings  # noqa: E402


def grids(path: Path, first: list[str]) -> list[dict]:
    """Both topologies of the airfoil ``path`` at each first layer: what training kept."""
    rows = []
    body = load_body(path)
    for topology, (ni, nj) in SIZES.items():
        for h in first:
            wall = None if h == "default" else float(h) * body.chord
            try:
                lay = bodygrid.layout(body, circle(body, FAR_FIELD), topology, ni, nj, wall)
            except InputError:
                continue  # refused (a blunt C-grid that would fold): nothing to train
            start, controls = bodygrid.elliptic(lay)
            _, _, info = train_body(lay, start, controls, make_settings("pinn", lattice=(ni, nj)))
            before, after = guard_figures(start), info["guard"]["kept"]
            row = {
                "grid": f"{path.name} {topology.upper()} first {h}",
                "aspect": lay.wall_aspect(),
                "result": info["result"],
                "mean": (before["mean_max_angle"], after["mean_max_angle"]),
                "worst": (before["worst_max_angle"], after["worst_max_angle"]),
            }
            print(
                f"{row['grid']:48s} aspect {row['aspect']:7.1f} {row['result']:8s} mean "
                f"{row['mean'][0]:.2f} -> {row['mean'][1]:.2f}, worst {row['worst'][0]:.2f} "
                f"-> {row['worst'][1]:.2f}",
                flush=True,
            )
            rows.append(row)
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("files", nargs="*", type=Path, help="airfoil .dat files")
    parser.add_argument("--set", type=Path, help="a folder of airfoil .dat files")
    parser.add_argument("--half", choices=("tuning", "report"), help="only this half of --set")
    parser.add_argument("--limit", type=int, help="only the first LIMIT files of --set")
    parser.add_argument("--naca", nargs="*", default=[], help="NACA 4-digit sections (sharp)")
    parser.add_argument("--first", nargs="+", default=["1e-5"], help="first layers (chords)")
    opts = parser.parse_args()
    files = sorted(opts.set.glob("*.dat")) if opts.set else []
    files = [f for f in files if not opts.half or half(f.name) == opts.half][: opts.limit]
    files = [*opts.files, *files]
    rows = []
    with tempfile.TemporaryDirectory() as scratch:
        for code in opts.naca:
            dat = Path(scratch) / f"naca{code}.dat"
            points = "".join(f"{x:.10f} {y:.10f}\n" for x, y in naca4(code))
            dat.write_text(f"NACA {code}\n{points}")
            files.insert(0, dat)
        for path in files:
            rows += grids(path, opts.first)
    for label, thin in (("under", False), ("at or over", True)):
        sel = [r for r in rows if (r["aspect"] >= THIN_WALL) == thin]
        kept = [r for r in sel if r["result"] == "network"]
        print(
            f"wall aspect {label} {THIN_WALL:g}: {len(sel)} grids, "
            f"the network's kept on {len(kept)}"
        )
        for r in kept:
            print(
                f"  {r['grid']}: aspect {r['aspect']:.1f}, mean {r['mean'][0]:.2f} -> "
                f"{r['mean'][1]:.2f}, worst {r['worst'][0]:.2f} -> {r['worst'][1]:.2f}"
            )


if __name__ == "__main__":
    main()
