"""Start-up figures of the command, each a whole ``pinn-mesh`` process.

Usage: ``.venv/bin/python benchmarks/startup.py [--runs 5]``

- The demo (``make demo``: ``wavy.vtp`` with its auxiliary lines, the default method) on an
  empty native cache (a new ``PINN_MESH_CACHE`` folder each run) against a warm one: the
  install compiled the C++ kernels into the package (``setup.py``), so the two should match
  (target: the first run at most 1.5x a warm one). It says whether the package holds them.
- ``--method elliptic`` on the same files end to end, with the reading child (the default)
  and with the files read in this process (``PINN_MESH_NO_CHILD=1``, no protection against
  damaged files): what the child still costs once it reads while the run imports.

Runs alternate, ``--runs`` of each; medians are printed.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PINN_MESH = str(Path(sys.executable).with_name("pinn-mesh"))
DEMO = [
    str(ROOT / "example_data" / "wavy.vtp"),
    "--aux",
    str(ROOT / "example_data" / "wavy_aux.vtp"),
]
FIRST_RUN_TARGET = 1.5  # a first run at most 1.5x a warm one


def seconds(argv: list[str], **env: str) -> float:
    """The wall time of the command ``argv`` with ``env`` added to the environment."""
    start = time.perf_counter()
    subprocess.run([PINN_MESH, *argv], check=True, capture_output=True, env={**os.environ, **env})
    return time.perf_counter() - start


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=5, help="runs of each variant")
    opts = parser.parse_args()
    from pinn_engine.neural.jet import native

    packaged = native.packaged_library(native.PACKAGED_DIR)
    print(f"compiled kernels in the package: {'yes' if packaged.exists() else 'NO'} ({packaged})")
    print(f"load average {os.getloadavg()[0]:.1f} before", flush=True)
    times: dict[str, list[float]] = {"cold": [], "warm": [], "child": [], "no child": []}
    with tempfile.TemporaryDirectory(prefix="pinn-mesh-startup-") as scratch:
        out = str(Path(scratch) / "grid.vts")
        warm = str(Path(scratch) / "warm-cache")
        seconds([*DEMO, "-o", out], PINN_MESH_CACHE=warm)  # untimed: the warm cache's run
        elliptic = [*DEMO, "--method", "elliptic", "-o", out]
        for k in range(opts.runs):
            cold = str(Path(scratch) / f"cold-cache-{k}")
            times["cold"].append(seconds([*DEMO, "-o", out], PINN_MESH_CACHE=cold))
            times["warm"].append(seconds([*DEMO, "-o", out], PINN_MESH_CACHE=warm))
            times["child"].append(seconds(elliptic))
            times["no child"].append(seconds(elliptic, PINN_MESH_NO_CHILD="1"))
    m = {key: statistics.median(t) for key, t in times.items()}
    ratio = m["cold"] / m["warm"]
    print(
        f"demo, default method: empty native cache {m['cold']:.2f} s, warm {m['warm']:.2f} s: "
        f"{ratio:.2f}x ({'within' if ratio <= FIRST_RUN_TARGET else 'OUTSIDE'} the target, "
        f"{FIRST_RUN_TARGET}x)"
    )
    print(
        f"demo, --method elliptic: {m['child']:.2f} s (reading child), {m['no child']:.2f} s "
        f"(files read in this process)"
    )
    print(f"medians of {opts.runs}; load average {os.getloadavg()[0]:.1f} after")


if __name__ == "__main__":
    main()
