"""Speed and memory of the 3D elliptic (Winslow) method on six-faced domains.

Usage: ``.venv/bin/python benchmarks/hexa_speed.py [--sizes 21 41 81] [--repeat 3]``

For each example surface and each size n, one subprocess runs ``mesh_surface`` at n x n x n
with ``--method elliptic`` (read, topology, face grids, 3D TFI, the Winslow solve, the cell
arrays) and prints the whole run's seconds, the Winslow solve's seconds and Picard steps, the
folded cells and the process's peak resident memory (``ru_maxrss``: imports included, about
0.17 GiB; a fresh process per run so that no run's peak hides another's). With ``--repeat
N`` the fastest of N runs is printed (on a shared machine one run's time is noisy). The bound on
elliptic at 21^3 (the whole run within 3 s) is checked.
"""

from __future__ import annotations

import argparse
import json
import resource
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
SURFACES = ("hexa_bump_box.vtp", "hexa_bend.vtp")  # example_data/make_hexa.py's surfaces
SIZES = (21, 41, 81)  # nodes along each direction: 8000, 64 000 and 512 000 cells
BOUND_SIZE, BOUND_SECONDS = 21, 3.0  # elliptic at 21^3 in at most 3 s


def _one(surface: str, n: int) -> dict:
    """One elliptic run at n^3 in this process, with the Winslow solve timed apart."""
    from pinn_engine.hexa import volume
    from pinn_engine.kinds.hexa import mesh
    from pinn_engine.settings import make_settings

    solve = {}
    winslow = volume.winslow

    def timed(g, **kwargs):
        start = time.perf_counter()
        out = winslow(g, **kwargs)
        solve["seconds"], solve["steps"] = time.perf_counter() - start, out[1]
        return out

    volume.winslow = timed
    result = mesh.mesh_surface(
        str(ROOT / "example_data" / surface), make_settings("elliptic", size=(n, n, n))
    )
    return {
        "seconds": result.seconds,
        "solve": solve["seconds"],
        "steps": solve["steps"],
        "folded": int(result.cells["Folded"].sum()),
        "peak_gib": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20,
    }


def _subprocess(surface: str, n: int) -> dict:
    """:func:`_one` in a fresh process."""
    done = subprocess.run(
        [sys.executable, __file__, "--one", surface, str(n)],
        cwd=ROOT,
        check=True,
        capture_output=True,
        text=True,
    )
    return json.loads(done.stdout.splitlines()[-1])


def main() -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", type=int, nargs="+", default=list(SIZES))
    parser.add_argument("--repeat", type=int, default=1)
    parser.add_argument("--one", nargs=2, metavar=("SURFACE", "N"), help=argparse.SUPPRESS)
    args = parser.parse_args()
    if args.one:
        print(json.dumps(_one(args.one[0], int(args.one[1]))))
        return 0
    print(
        "| surface | size | whole run (s) | Winslow solve (s) | Picard steps | folded "
        "| peak RSS (GiB) |"
    )
    print("|---|---|---|---|---|---|---|")
    ok = True
    for n in args.sizes:
        for surface in SURFACES:
            runs = [_subprocess(surface, n) for _ in range(args.repeat)]
            r = min(runs, key=lambda run: run["seconds"])
            print(
                f"| {surface} | {n}^3 | {r['seconds']:.2f} | {r['solve']:.2f} | {r['steps']} "
                f"| {r['folded']} | {r['peak_gib']:.2f} |",
                flush=True,
            )
            if n == BOUND_SIZE and r["seconds"] > BOUND_SECONDS:
                ok = False
    if BOUND_SIZE in args.sizes:
        print(f"elliptic at {BOUND_SIZE}^3 within {BOUND_SECONDS} s: {ok}")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
