"""Start-up figures of the command, each a whole ``pinn-mesh`` process.

Usage: ``.venv/bin/python benchmarks/startup.py [--runs 3] [--against DIR] [--demo]``

- Per domain kind (four-sided with and without auxiliary lines, an O-grid body, multi-block,
  hexahedral), ``--method elliptic`` and the default, end to end: the wall time, the CPU
  time of the process and its children (the file-reading child included; the CPU time is
  what the other sessions on a shared machine disturb least), and the heavy packages the run
  imported (``python -X importtime``). ``--against DIR``: the same runs of the checkout at
  DIR (``git worktree add --detach DIR COMMIT``), alternating with this one's, in one table.
- ``--demo``: the demo (``make demo``: ``wavy.vtp`` with its auxiliary lines, the default
  method) on an empty native cache (a new ``PINN_MESH_CACHE`` folder each run) against a
  warm one: the install compiled the C++ kernels into the package (``setup.py``), so the two
  should match (target: the first run at most 1.5x a warm one); and ``--method elliptic`` on
  the same files with the reading child (the default) and with the files read in this
  process (``PINN_MESH_NO_CHILD=1``, no protection against damaged files).

Runs alternate, ``--runs`` of each; medians are printed.
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "example_data"
PINN_MESH = str(Path(sys.executable).with_name("pinn-mesh"))
DEMO = [
    str(EXAMPLES / "wavy.vtp"),
    "--aux",
    str(EXAMPLES / "wavy_aux.vtp"),
]
FIRST_RUN_TARGET = 1.5  # a first run at most 1.5x a warm one
KINDS = {  # the domain kinds' runs: the command's inputs and output extension
    "four-sided, auxiliary lines": (DEMO, "vts"),
    "four-sided": ([str(EXAMPLES / "holdout" / "h00_wavy.vtp"), "--size", "61", "31"], "vts"),
    "body (O-grid)": (["--naca", "0012", "--topology", "o"], "vts"),
    "multi-block": (
        [str(EXAMPLES / "lshape.vtp"), "--blocks", str(EXAMPLES / "lshape_blocks.vtp")],
        "vtm",
    ),
    "hexahedral": ([str(EXAMPLES / "hexa_bump_box.vtp")], "vts"),
}
METHODS = {"elliptic": ["--method", "elliptic"], "default": []}
# the packages a run may do without: each is named in the table where a run imported it
HEAVY = (
    "torch",
    "sklearn",
    "pyvista",
    "matplotlib",
    "dask",
    "scipy.interpolate",
    "scipy.optimize",
    "scipy.ndimage",
    "scipy.sparse",
    "pyamg",
)


def seconds(argv: list[str], **env: str) -> float:
    """The wall time of the command ``argv`` with ``env`` added to the environment."""
    start = time.perf_counter()
    subprocess.run([PINN_MESH, *argv], check=True, capture_output=True, env={**os.environ, **env})
    return time.perf_counter() - start


def command(checkout: Path, argv: list[str], *python: str) -> subprocess.CompletedProcess:
    """The command on ``argv`` with the package of ``checkout`` (``python``: the
    interpreter's options)."""
    done = subprocess.run(
        [sys.executable, *python, "-m", "pinn_engine.command", *argv],
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": str(checkout)},
        cwd=checkout,
    )
    if done.returncode:
        raise RuntimeError(f"{argv}: {done.stderr[-500:]}")
    return done


def imported(checkout: Path, argv: list[str]) -> set[str]:
    """The packages of :data:`HEAVY` that a run of ``argv`` imports (untimed)."""
    lines = command(checkout, argv, "-X", "importtime").stderr
    modules = set(re.findall(r"\|\s+([\w.]+)\s*$", lines, flags=re.MULTILINE))
    return {name for name in HEAVY if name in modules}


def measured(checkout: Path, argv: list[str]) -> tuple[float, float]:
    """One run of ``argv`` with the package of ``checkout``: wall seconds and CPU seconds
    (its own and its children's)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    command(checkout, argv)
    wall = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    return wall, after.ru_utime + after.ru_stime - before.ru_utime - before.ru_stime


def kinds(runs: int, checkouts: dict[str, Path], scratch: Path) -> None:
    """The per-kind table: medians of ``runs`` alternating runs of each checkout."""
    print(
        "| kind | method | checkout | wall (s) | CPU (s) | imported of "
        + ", ".join(HEAVY)
        + " |\n|---|---|---|---:|---:|---|",
        flush=True,
    )
    for kind, (inputs, ext) in KINDS.items():
        for method, options in METHODS.items():
            argv = [*inputs, *options, "--quiet", "-o", str(scratch / f"grid.{ext}")]
            got: dict[str, list] = {name: [] for name in checkouts}
            # untimed, the first run of each (caches, the native kernel)
            heavy = {name: imported(checkout, argv) for name, checkout in checkouts.items()}
            for _ in range(runs):
                for name, checkout in checkouts.items():
                    got[name].append(measured(checkout, argv))
            for name, figures in got.items():
                wall = statistics.median(f[0] for f in figures)
                cpu = statistics.median(f[1] for f in figures)
                names = ", ".join(sorted(heavy[name])) or "none"
                print(f"| {kind} | {method} | {name} | {wall:.2f} | {cpu:.2f} | {names} |")


def demo(runs: int, scratch: Path) -> None:
    """The demo on an empty native cache against a warm one; the elliptic command with and
    without the reading child."""
    from pinn_engine.neural.jet import native

    packaged = native.packaged_library(native.PACKAGED_DIR)
    print(f"compiled kernels in the package: {'yes' if packaged.exists() else 'NO'} ({packaged})")
    times: dict[str, list[float]] = {"cold": [], "warm": [], "child": [], "no child": []}
    out = str(scratch / "grid.vts")
    warm = str(scratch / "warm-cache")
    seconds([*DEMO, "-o", out], PINN_MESH_CACHE=warm)  # untimed: the warm cache's run
    elliptic = [*DEMO, "--method", "elliptic", "-o", out]
    for k in range(runs):
        cold = str(scratch / f"cold-cache-{k}")
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


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=3, help="runs of each variant")
    parser.add_argument("--against", type=Path, help="another checkout to time alongside")
    parser.add_argument("--demo", action="store_true", help="the native cache and the child")
    opts = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.1f} before", flush=True)
    with tempfile.TemporaryDirectory(prefix="pinn-mesh-startup-") as scratch:
        if opts.demo:
            demo(opts.runs, Path(scratch))
        else:
            checkouts = {"this": ROOT}
            if opts.against:
                checkouts = {opts.against.name: opts.against.resolve(), **checkouts}
            kinds(opts.runs, checkouts, Path(scratch))
    print(f"medians of {opts.runs}; load average {os.getloadavg()[0]:.1f} after")


if __name__ == "__main__":
    main()
