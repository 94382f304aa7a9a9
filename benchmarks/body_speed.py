"""Where an airfoil grid's seconds go: the whole ``pinn-mesh`` command, its default
and ``--method elliptic``, stage by stage, beside Construct2D's whole run.

Usage: ``.venv/bin/python benchmarks/body_speed.py [--runs 3] [--out docs/speed.md]``

The jobs are ``benchmarks/peers.py``'s airfoils (a NACA 0012 C-grid of 320 x 90 and
Construct2D's sample airfoils as O-grids of 250 x 80, with Construct2D's first layer and far
field; Construct2D at ``$CONSTRUCT2D`` or ``/work/tools/Construct2D/construct2d``). Each run
writes ``--report``; its ``timings`` give the stages: reading the file, the layout (the
wall's nodes and the marched reference grid), the elliptic sweeps, the start (the decision
whether the network can win, and the default's choice of start with its nodes optimised), the
training (where the network trains: torch's import and the training), the quality figures
and writing the grid. The rest of the command's wall time is Python's start and the imports.
Runs alternate between the tools; the table shows the median run of each (by wall time).
With ``--out`` the table replaces the part of that page between the BODY-STAGES markers.

``--in-process N`` times instead the grid's own work in this process, the CPU seconds of the
layout (``bodygrid.layout``: the wall's nodes and the marched reference grid) and of the
elliptic sweeps (``bodygrid.elliptic``), the best of N runs each: figures that other work
on the cores disturbs less than wall times.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

from peers import PINN_MESH, airfoil_jobs, write_between  # noqa: E402

STAGES = ("read", "layout", "elliptic", "start", "training", "quality", "write")
MARK = "<!-- BODY-STAGES {} -->"  # the markers round the table in --out


def run(args: list[str], report: Path) -> dict[str, float]:
    """One ``pinn-mesh`` run: its wall time and its report's stage timings."""
    start = time.perf_counter()
    command = [PINN_MESH, *args, "--quiet", "--report", str(report), "-o", str(report) + ".vts"]
    subprocess.run(command, check=True, capture_output=True, timeout=900)
    wall = time.perf_counter() - start
    timings = json.loads(report.read_text())["timings"]
    stages = {k: float(timings.get(k, 0.0)) for k in STAGES}
    return {"wall": wall, **stages, "start-up": wall - sum(stages.values())}


def in_process(args: list[str], runs: int) -> tuple[float, float]:
    """The best CPU seconds of the layout and of the elliptic sweeps of the job ``args``
    (pinn-mesh's arguments: the file, then ``--topology``, ``--size``, ``--spacing
    bottom=H`` and ``--farfield``)."""
    from pinn_engine.bodies import bodygrid
    from pinn_engine.bodies.airfoil import circle, load_body

    option = {args[k]: args[k + 1 : k + 3] for k in range(1, len(args)) if args[k][:2] == "--"}
    body = load_body(args[0])
    far = circle(body, float(option["--farfield"][0]))
    ni, nj = map(int, option["--size"])
    wall = float(option["--spacing"][0].split("=")[1])
    best = [float("inf"), float("inf")]
    for _ in range(runs):
        start = time.process_time()
        lay = bodygrid.layout(body, far, option["--topology"][0], ni, nj, wall)
        laid = time.process_time()
        bodygrid.elliptic(lay)
        best = [min(best[0], laid - start), min(best[1], time.process_time() - laid)]
    return best[0], best[1]


def table(rows: list[tuple[str, str, dict[str, float], float]], runs: int, load: tuple) -> str:
    """The Markdown table: a row a job and method, its stages and Construct2D's time."""
    head = ("wall", "start-up", *STAGES)
    lines = [
        f"Median run of {runs} a tool, alternating; load average {load[0]:.1f} before, "
        f"{load[1]:.1f} after, on 2 shared cores. Seconds.",
        "",
        "| job | method | " + " | ".join(head) + " | Construct2D | ratio |",
        "|---|---|" + "---:|" * (len(head) + 2),
    ]
    for name, method, t, peer in rows:
        cells = " | ".join(f"{t[k]:.2f}" for k in head)
        lines.append(f"| {name} | {method} | {cells} | {peer:.2f} | {t['wall'] / peer:.1f}x |")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=3, help="runs of each tool on each job")
    parser.add_argument("--out", type=Path, help="the page whose BODY-STAGES table to replace")
    parser.add_argument("--in-process", type=int, metavar="N", help="the grid's own CPU seconds")
    opts = parser.parse_args()
    if opts.in_process:
        with tempfile.TemporaryDirectory(prefix="pinn-mesh-body-speed-") as scratch:
            for name, args, _ in airfoil_jobs(Path(scratch)):
                layout, elliptic = in_process(args, opts.in_process)
                print(f"{name:28s} layout {layout:.3f} s, elliptic {elliptic:.3f} s (CPU)")
        return
    before = os.getloadavg()[0]
    rows = []
    with tempfile.TemporaryDirectory(prefix="pinn-mesh-body-speed-") as scratch:
        work = Path(scratch)
        for name, args, peer in airfoil_jobs(work):
            ours: dict[str, list[dict]] = {"default": [], "elliptic": []}
            theirs = []
            for _ in range(opts.runs):
                ours["default"].append(run(args, work / "default.json"))
                ours["elliptic"].append(run([*args, "--method", "elliptic"], work / "e.json"))
                theirs.append(peer()[0])  # its wall seconds (a timer gives wall and CPU)
            peer_seconds = statistics.median(theirs)
            for method, results in ours.items():
                middle = sorted(results, key=lambda r: r["wall"])[len(results) // 2]
                rows.append((name, method, middle, peer_seconds))
                print(name, method, {k: round(v, 2) for k, v in middle.items()}, flush=True)
    text = table(rows, opts.runs, (before, os.getloadavg()[0]))
    print(text)
    if opts.out:
        write_between(opts.out, MARK, text)


if __name__ == "__main__":
    main()
