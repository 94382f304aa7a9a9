"""Where the seconds of a multi-block and a hexahedral run go: ``benchmarks/peers.py``'s DFG
cylinder (12 blocks, about 34 000 cells) and square duct (80 x 20 x 20 hexahedra), the
default and ``--method elliptic``, each command in a fresh Python as a user runs it.

Usage: ``.venv/bin/python benchmarks/stages.py [--runs 3] [--against DIR] [--profile 12]``

Per run: the wall time; Python's own start (``python -c pass``); the imports (the run's
``python -X importtime``, top-level modules' cumulative times); each stage of the report's
``timings`` (reading, layout or face grids, the solve, the start, training, quality,
writing); and the rest (argument parsing, the summary line, the reading child's start where
the run waits for it). Medians over ``--runs``. ``--against DIR``: the same commands with
the package of the checkout at DIR, alternating with this one's (a report without
``timings``, an older checkout's, shows its wall time and imports only). With ``--profile N``
each command runs once more under cProfile and its N functions of most own time are printed.
"""

from __future__ import annotations

import argparse
import json
import os
import pstats
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path[:0] = [str(HERE), str(HERE.parent / "example_data")]

from make_hexa import surface  # noqa: E402
from peers import DFG_CELL, DUCT_CELLS, DUCT_LENGTH, ROOT  # noqa: E402

METHODS = ("default", "elliptic")
MICRO = 1e-6  # -X importtime reports microseconds


def commands(work: Path) -> dict[str, list[str]]:
    """Each job's pinn-mesh arguments (as peers.py gives them)."""
    duct = work / "duct.vtp"
    surface(lambda u, v, w: np.stack([DUCT_LENGTH * u, v, w], axis=-1)).save(duct)
    data = ROOT / "example_data"
    return {
        "DFG cylinder, 12 blocks": [
            str(data / "dfg.vtp"),
            "--blocks",
            str(data / "dfg_blocks.vtp"),
            "--cell-size",
            str(DFG_CELL),
            "-o",
            str(work / "dfg.vtm"),
        ],
        "square duct, 32000 hexahedra": [
            str(duct),
            "--size",
            *(str(n + 1) for n in DUCT_CELLS),
            "-o",
            str(work / "duct.vts"),
        ],
    }


def imports(stderr: str) -> float:
    """Seconds of a run's imports: the top-level modules' cumulative times."""
    total = 0
    for line in stderr.splitlines():
        if line.startswith("import time:") and "|" in line:
            _, cumulative, name = line.split("|")
            if not name.startswith("  ") and cumulative.strip().isdigit():
                total += int(cumulative)
    return total * MICRO


def environment(checkout: Path) -> dict[str, str]:
    """The runs' environment: the package of ``checkout``, and bytecode cached as an
    installed package's is (a shell that forbids it would make each run compile its
    modules again)."""
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    return {**env, "PYTHONPATH": str(checkout)}


def one_run(checkout: Path, args: list[str], report: Path) -> dict[str, float]:
    """The wall time, imports and report stages of one command with the package of
    ``checkout``."""
    command = [sys.executable, "-X", "importtime", "-m", "pinn_engine.command", *args]
    began = time.perf_counter()
    done = subprocess.run(
        [*command, "--quiet", "--report", str(report)],
        capture_output=True,
        text=True,
        cwd=checkout,
        env=environment(checkout),
    )
    wall = time.perf_counter() - began
    if done.returncode:
        raise RuntimeError(done.stderr[-2000:])
    stages = json.loads(report.read_text()).get("timings", {})
    return {"wall": wall, "imports": imports(done.stderr), **stages}


def python_start() -> float:
    """Seconds of a bare Python's start and exit."""
    began = time.perf_counter()
    subprocess.run([sys.executable, "-c", "pass"], check=True, env=environment(ROOT))
    return time.perf_counter() - began


def profile(args: list[str], work: Path, top: int) -> None:
    """Run the command under cProfile and print its ``top`` functions by own time."""
    out = work / "run.prof"
    command = [sys.executable, "-m", "cProfile", "-o", str(out), "-m", "pinn_engine.command"]
    subprocess.run(
        [*command, *args, "--quiet"],
        check=True,
        capture_output=True,
        cwd=ROOT,
        env=environment(ROOT),
    )
    pstats.Stats(str(out), stream=sys.stdout).sort_stats("tottime").print_stats(top)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=3, help="runs of each command")
    parser.add_argument("--against", type=Path, help="another checkout to time alike")
    parser.add_argument("--profile", type=int, default=0, help="functions to print per run")
    opts = parser.parse_args()
    checkouts = {"this": ROOT, **({"against": opts.against.resolve()} if opts.against else {})}
    print(f"load average {os.getloadavg()[0]:.1f} before")
    start = statistics.median(python_start() for _ in range(opts.runs))
    with tempfile.TemporaryDirectory(prefix="pinn-mesh-stages-") as scratch:
        work = Path(scratch)
        for job, args in commands(work).items():
            for method in METHODS:
                argv = args if method == "default" else [*args, "--method", method]
                runs: dict[str, list] = {name: [] for name in checkouts}
                for _ in range(opts.runs):
                    for name, checkout in checkouts.items():
                        runs[name].append(one_run(checkout, argv, work / "report.json"))
                for name, got in runs.items():
                    keys = list(dict.fromkeys(k for run in got for k in run))
                    med = {k: statistics.median(run.get(k, 0.0) for run in got) for k in keys}
                    rest = med["wall"] - start - sum(v for k, v in med.items() if k != "wall")
                    parts = {"python": start, **{k: v for k, v in med.items() if k != "wall"}}
                    shown = ", ".join(f"{k} {v:.2f}" for k, v in {**parts, "rest": rest}.items())
                    print(f"{job}, {method} ({name}): {med['wall']:.2f} s = {shown}", flush=True)
                if opts.profile:
                    profile(argv, work, opts.profile)
    print(f"medians of {opts.runs}; load average {os.getloadavg()[0]:.1f} after")


if __name__ == "__main__":
    main()
