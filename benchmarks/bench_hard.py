"""Every method on the hard four-sided shapes of ``example_data/hard/`` (issue 11's table).

Usage: ``.venv/bin/python benchmarks/bench_hard.py [--sizes 41x21 161x81] [--no-speed]``

For each shape and size it meshes with ``tfi``, ``elliptic`` (converged), ``mgnet`` and the
default ``pinn`` and prints mean and worst ``MaxIncludedAngle``, folded cells and time
(fit + grid, torch imported beforehand). For the neural methods it checks issue 11's bounds
against the converged elliptic grid on the same boundary nodes: mean <= elliptic + 0.5,
worst <= elliptic worst + 2, no folded cell where the elliptic grid has none (where it has
some: no more than it). Shapes with auxiliary lines also get the largest distance of the
grid line through each line's (xi, eta) from the drawn line (``auxlines.line_distances``).

The speed section times, on ``bump`` with its auxiliary line at 41 x 21: the ``pinn-mesh``
command with the default settings (a fresh process, start to written grid), the paper preset
(training only) and the plain-autograd paper recipe of ``plain_pinn.py`` (Adam in float32,
L-BFGS in float64, training only), and prints the ratios. Writes ``docs/hard_shapes.md`` and
``docs/hard_shapes.json``.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from pinn_engine.auxlines import line_distances
from pinn_engine.mesher import Mesher
from pinn_engine.pipeline import load_aux, load_boundary
from pinn_engine.settings import make_settings

ROOT = Path(__file__).resolve().parents[1]
HARD = ROOT / "example_data" / "hard"
METHODS = ("tfi", "elliptic", "mgnet", "pinn")
MEAN_BOUND, WORST_BOUND = 0.5, 2.0


def shapes() -> list[str]:
    return sorted(p.stem for p in HARD.glob("*.vtp") if not p.stem.endswith("_aux"))


def inputs(name: str):
    boundary = load_boundary(HARD / f"{name}.vtp")
    aux_file = HARD / f"{name}_aux.vtp"
    return boundary, load_aux([aux_file], boundary) if aux_file.exists() else []


def within(q: dict, ref: dict) -> bool:
    """Issue 11's bounds for a neural grid ``q`` against the elliptic grid ``ref``."""
    return (q["folded_cells"] <= ref["folded_cells"]
            and q["mean_max_angle"] <= ref["mean_max_angle"] + MEAN_BOUND
            and q["worst_max_angle"] <= ref["worst_max_angle"] + WORST_BOUND)


def run_shape(name: str, size: tuple[int, int]) -> list[dict]:
    boundary, aux = inputs(name)
    rows, ref = [], None
    for method in METHODS:
        start = time.perf_counter()
        settings = make_settings(method, lattice=size)
        result = Mesher(settings).fit(boundary, aux).predict(*size)
        seconds = time.perf_counter() - start
        q = result.quality
        unit = boundary.frame.to_unit(result.points)
        row = {"shape": name, "size": list(size), "method": method, "seconds": seconds,
               **{k: q[k] for k in ("mean_max_angle", "worst_max_angle", "folded_cells")},
               "aux_distance": max(line_distances(unit, aux, boundary.diagonal).values(),
                                   default=None)}
        if method == "elliptic":
            ref = row
        if method in ("mgnet", "pinn"):
            row["within_bounds"] = within(row, ref)
        rows.append(row)
        aux_text = f" aux {row['aux_distance']:.4f}" if aux else ""
        check = {True: " ok", False: " OUT OF BOUNDS"}.get(row.get("within_bounds"), "")
        print(f"{name:26s} {size[0]:3d}x{size[1]:<3d} {method:9s} mean "
              f"{row['mean_max_angle']:7.2f} worst {row['worst_max_angle']:7.2f} folded "
              f"{row['folded_cells']:4d} {seconds:6.2f} s{aux_text}{check}", flush=True)
    return rows


def command_seconds(name: str) -> float:
    """Wall time of the default ``pinn-mesh`` command, start to written grid."""
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "pinn_engine.cli", str(HARD / f"{name}.vtp"), "--aux",
               str(HARD / f"{name}_aux.vtp"), "-o", str(Path(tmp) / "g.vts"), "--quiet"]
        start = time.perf_counter()
        subprocess.run(cmd, check=True, cwd=ROOT, capture_output=True)
        return time.perf_counter() - start


def speed(name: str = "bump") -> dict:
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from plain_pinn import train_plain

    boundary, aux = inputs(name)
    runs = sorted(command_seconds(name) for _ in range(3))
    start = time.perf_counter()
    Mesher(make_settings("pinn", "paper")).fit(boundary, aux)
    paper = time.perf_counter() - start
    plain = train_plain(boundary, aux)["seconds"]
    out = {"shape": name, "command_median_s": runs[1], "command_runs_s": runs,
           "paper_preset_train_s": paper, "plain_train_s": plain,
           "default_speedup": plain / runs[1], "paper_speedup": plain / paper}
    print(f"\nspeed on {name} (41 x 21, one auxiliary line):\n"
          f"  default pinn-mesh command, start to written grid: {runs[1]:.2f} s "
          f"(median of {', '.join(f'{r:.2f}' for r in runs)})\n"
          f"  paper preset, training: {paper:.1f} s\n"
          f"  plain-autograd paper recipe (plain_pinn.py), training: {plain:.1f} s\n"
          f"  plain / default command: {out['default_speedup']:.1f}x; "
          f"plain / paper preset: {out['paper_speedup']:.2f}x", flush=True)
    return out


def markdown(rows: list[dict], fast: dict | None) -> str:
    lines = ["| shape | size | method | mean MaxIncludedAngle | worst MaxIncludedAngle | "
             "folded | time (s) | aux-line distance | issue 11 bounds |", "|" + "---|" * 9]
    for r in rows:
        aux = f"{r['aux_distance']:.4f}" if r["aux_distance"] is not None else ""
        check = {True: "within", False: "**outside**"}.get(r.get("within_bounds"), "")
        lines.append(f"| {r['shape']} | {r['size'][0]} x {r['size'][1]} | {r['method']} | "
                     f"{r['mean_max_angle']:.2f} | {r['worst_max_angle']:.2f} | "
                     f"{r['folded_cells']} | {r['seconds']:.2f} | {aux} | {check} |")
    if fast:
        lines += ["", f"Speed on `{fast['shape']}` at 41 x 21 with its auxiliary line: the "
                  f"default `pinn-mesh` command took {fast['command_median_s']:.2f} s from start "
                  f"to written grid (median of three); the plain-autograd paper recipe "
                  f"(`benchmarks/plain_pinn.py`) trained for {fast['plain_train_s']:.1f} s "
                  f"({fast['default_speedup']:.1f}x the command); the paper preset trained for "
                  f"{fast['paper_preset_train_s']:.1f} s ({fast['paper_speedup']:.2f}x faster "
                  "than the plain recipe)."]
    return "\n".join(lines) + "\n"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", nargs="+", default=["41x21", "161x81"])
    p.add_argument("--shapes", nargs="+", default=None)
    p.add_argument("--no-speed", action="store_true", help="skip the speed section")
    p.add_argument("--out", default=str(ROOT / "docs" / "hard_shapes"))
    args = p.parse_args()
    import torch  # noqa: F401  (imported once, before any timing)

    sizes = [tuple(int(n) for n in s.split("x")) for s in args.sizes]
    rows = [row for name in (args.shapes or shapes()) for size in sizes
            for row in run_shape(name, size)]
    neural = [r for r in rows if "within_bounds" in r]
    print(f"\n{sum(r['within_bounds'] for r in neural)} of {len(neural)} neural grids within "
          "issue 11's bounds")
    fast = None if args.no_speed else speed()
    out = Path(args.out)
    out.with_suffix(".json").write_text(json.dumps({"rows": rows, "speed": fast}, indent=2))
    out.with_suffix(".md").write_text(markdown(rows, fast))
    print(f"wrote {out.with_suffix('.md')} and {out.with_suffix('.json')}")


if __name__ == "__main__":
    main()
