"""Six-faced 3D domains (SPEC 11): quality, time and peak memory of every method
of ``settings.HEXA_METHODS`` on the five example shapes of ``example_data/make_hexa.py``.

Usage: ``.venv/bin/python benchmarks/hexa.py [--size NI NJ NK] [--out docs/hexa.md]``

Each run is a fresh Python process (``--one``) that meshes one surface by one method, so
that its peak resident memory (``ru_maxrss``) is that run's alone: the interpreter and its
imports (numpy, scipy, VTK; torch for a network) included. The time is the meshing's
(``HexResult.seconds``: reading the surface, face grids, volume grid, quality), one run each
on whatever machine runs it. The ``elliptic`` row is the converged 3D Winslow grid on the
same boundary nodes: the reference of the 3D bound, checked for every other method (no
folded cell, mean / worst MaxIncludedAngle at most 0.5 / 2 degrees above the reference's).
With ``--out`` the table replaces the part of that file between the two BENCHMARK markers of
its size (``<!-- BENCHMARK 21x21x21 start -->`` ... ``end -->``).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "example_data"
SHAPES = {  # name: file stem of make_hexa.py's surface
    "box with a bump": "hexa_bump_box",
    "duct twisted by 90 degrees": "hexa_twisted_duct",
    "90-degree bend": "hexa_bend",
    "contracting nozzle": "hexa_nozzle",
    "sheared, wavy top": "hexa_sheared_wavy",
}
REFERENCE = "elliptic"  # the converged 3D Winslow grid: the bound's reference
MEAN_OVER, WORST_OVER = 0.5, 2.0  # degrees above the reference allowed
MARK = "<!-- BENCHMARK {} {} -->"  # the markers round a size's table in --out (size, start/end)
KIB = 1024  # ru_maxrss is in KiB on Linux


def one(stem: str, method: str, size: tuple[int, int, int]) -> dict:
    """Mesh ``stem`` by ``method`` in this process: its figures, seconds and peak memory."""
    from pinn_engine.kinds.hexa.mesh import figures, mesh_surface
    from pinn_engine.settings import make_settings

    result = mesh_surface(str(DATA / f"{stem}.vtp"), make_settings(method, size=size))
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / KIB
    return {**figures(result.cells), "seconds": result.seconds, "peak_mib": peak}


def measure(stem: str, method: str, size: tuple[int, int, int]) -> dict:
    """:func:`one` in a fresh process that imports this checkout's ``pinn_engine``."""
    env = dict(
        os.environ, PYTHONPATH=os.pathsep.join([str(ROOT), os.environ.get("PYTHONPATH", "")])
    )
    cmd = [sys.executable, __file__, "--one", stem, method, *map(str, size)]
    out = subprocess.run(cmd, env=env, cwd=ROOT, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.splitlines()[-1])


def markdown(size: tuple[int, int, int]) -> str:
    """The table of every shape and method at ``size``, and the bound checks' lines."""
    from pinn_engine.settings import HEXA_METHOD
    from pinn_engine.settings import HEXA_METHODS as METHODS

    table, checks = [], []
    for name, stem in SHAPES.items():
        runs = {m: measure(stem, m, size) for m in METHODS}
        for m, r in runs.items():
            label = f"{m} (default)" if m == HEXA_METHOD else m
            table.append(
                f"| {name if m == METHODS[0] else ''} | {label} | {r['folded_cells']} | "
                f"{r['min_scaled_jacobian']:.3f} | {r['mean_max_angle']:.2f} / "
                f"{r['worst_max_angle']:.2f} | {r['seconds']:.2f} s | {r['peak_mib']:.0f} MiB |"
            )
        ref = runs[REFERENCE]
        for m, r in runs.items():
            if m == REFERENCE:
                continue
            mean = r["mean_max_angle"] - ref["mean_max_angle"]
            worst = r["worst_max_angle"] - ref["worst_max_angle"]
            holds = {
                "no fold": r["folded_cells"] == 0,
                f"mean <= reference + {MEAN_OVER:g} ({mean:+.2f})": mean <= MEAN_OVER,
                f"worst <= reference + {WORST_OVER:g} ({worst:+.2f})": worst <= WORST_OVER,
            }
            verdict = "; ".join(f"{k}: {'holds' if v else 'FAILS'}" for k, v in holds.items())
            checks.append(f"- {name}, {m}: {verdict}")
    cells = (size[0] - 1) * (size[1] - 1) * (size[2] - 1)
    lines = [
        f"{' x '.join(map(str, size))} nodes ({cells} cells); the elliptic grid is the reference.",
        "",
        "| shape | method | folds | min ScaledJacobian | mean / worst MaxIncludedAngle (deg) "
        "| time | peak memory |",
        "|---|---|---|---|---|---|---|",
        *table,
        "",
        f"The 3D bound against the reference (the default must meet it; {HEXA_METHOD} is "
        "the default here):",
        "",
        *checks,
    ]
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", type=int, nargs=3, default=(21, 21, 21), metavar="N")
    parser.add_argument("--out", type=Path, help="Markdown with the size's BENCHMARK markers")
    parser.add_argument("--one", nargs=5, help=argparse.SUPPRESS)  # STEM METHOD NI NJ NK
    args = parser.parse_args()
    if args.one:
        stem, method, *size = args.one
        print(json.dumps(one(stem, method, tuple(int(n) for n in size))))
        return
    text = markdown(tuple(args.size))
    print(text, end="")
    if args.out:
        label = "x".join(map(str, args.size))
        start, end = MARK.format(label, "start"), MARK.format(label, "end")
        page = args.out.read_text()
        head, rest = page.split(start)
        _, tail = rest.split(end)
        args.out.write_text(f"{head}{start}\n{text}{end}{tail}")


if __name__ == "__main__":
    main()
