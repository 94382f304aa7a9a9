"""The default against its own elliptic command, end to end, as ratios taken in one run.

Usage: ``.venv/bin/python benchmarks/default_speed.py [--sizes 41x21 81x41] [--shapes NAME ...]
[--kinds four-sided blocks bodies] [--runs 1]``

Each run is the ``pinn-mesh`` command in a fresh Python (start-up, reading, meshing and
writing, as a user waits for it), the default and ``--method elliptic`` alternating on the
same case so that the machine's load hits both alike, timed in wall seconds and in the
command's CPU seconds (user and system; other sessions' load disturbs it least):

* four-sided: every hold-out shape (``example_data/holdout/``, the sizes of
  ``benchmarks/holdout.py``);
* blocks: the examples with a blocking (``example_data/*_blocks.vtp``) at a cell size of 0.05;
* bodies: the O- and C-grids of ``example_data/naca0012.dat``, NACA 0012 and NACA 4412 at the
  default size and first layer.

Per kind: the ratios per case (medians of ``--runs`` runs each) and their median. The
default's ``--report`` gives its seconds per stage (``timings``), whose medians are printed
too, and how many runs trained a network. Prints markdown tables (docs/speed.md).
"""

from __future__ import annotations

import argparse
import json
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HOLDOUT = ROOT / "example_data" / "holdout"
EXAMPLES = ROOT / "example_data"
SIZES = ("41x21", "81x41")  # the hold-out page's sizes
CELL_SIZE = "0.05"  # the multi-block examples' cell size (docs/multiblock.md's finer runs)
COMMAND = [sys.executable, "-m", "pinn_engine.command"]
FOLDED = "the grid is not written"  # the refusal of a folded grid, made after the meshing
KINDS = {  # --kinds: each kind's cases, as the tables name them
    "four-sided": "Four-sided, hold-out shapes",
    "blocks": "Multi-block examples",
    "bodies": "Bodies (O- and C-grids)",
}
BODIES = {  # the body cases: each input at both topologies
    "naca0012.dat": [str(EXAMPLES / "naca0012.dat")],
    "NACA 0012": ["--naca", "0012"],
    "NACA 4412": ["--naca", "4412"],
}


def _children_cpu() -> float:
    """CPU seconds (user and system) of this process's finished children."""
    usage = resource.getrusage(resource.RUSAGE_CHILDREN)
    return usage.ru_utime + usage.ru_stime


def timed(args: list[str], folder: Path, report: bool) -> tuple[float, float, dict]:
    """Wall and CPU seconds of one command in a fresh process, and its report
    (``--report``). A folded grid refused after meshing (``FOLDED``: the elliptic grid on
    several hold-out shapes) counts: its command did all the work."""
    path = folder / "report.json"
    extra = ["--report", str(path)] if report else []
    began, cpu = time.perf_counter(), _children_cpu()
    done = subprocess.run([*COMMAND, *args, *extra], capture_output=True, text=True, cwd=ROOT)
    seconds, cpu = time.perf_counter() - began, _children_cpu() - cpu
    if done.returncode and (report or FOLDED not in done.stderr):
        raise RuntimeError(f"{' '.join(args)}: {done.stderr.strip()}")
    return seconds, cpu, json.loads(path.read_text()) if report else {}


def compare(args: list[str], folder: Path, runs: int) -> dict:
    """The default and the elliptic command on the same case, one after the other, ``runs``
    times: the medians of their wall and CPU seconds, and the default's last report."""
    times: dict[str, list[float]] = {"default": [], "elliptic": [], "cpu": [], "elliptic_cpu": []}
    for _ in range(runs):
        wall, cpu, report = timed(args, folder, True)
        times["default"].append(wall)
        times["cpu"].append(cpu)
        wall, cpu, _ = timed([*args, "--method", "elliptic"], folder, False)
        times["elliptic"].append(wall)
        times["elliptic_cpu"].append(cpu)
    row = {k: statistics.median(v) for k, v in times.items()}
    row["ratio"] = row["default"] / row["elliptic"]
    row["cpu_ratio"] = row["cpu"] / row["elliptic_cpu"]
    return {**row, **report}


def show(row: dict) -> None:
    print(
        f"  {row['case']}: {row['default']:.2f} s / {row['elliptic']:.2f} s, "
        f"CPU {row['cpu']:.2f} s / {row['elliptic_cpu']:.2f} s",
        flush=True,
    )


def four_sided(sizes: list[str], shapes: list[str], folder: Path, runs: int) -> list[dict]:
    rows = []
    for name in shapes:
        for size in sizes:
            ni, nj = size.split("x")
            out = str(folder / "grid.vts")
            args = [str(HOLDOUT / f"{name}.vtp"), "--size", ni, nj, "-o", out, "--quiet"]
            rows.append({"case": f"{name} {size}", **compare(args, folder, runs)})
            show(rows[-1])
    return rows


def multi_block(folder: Path, runs: int) -> list[dict]:
    rows = []
    for blocks in sorted(EXAMPLES.glob("*_blocks.vtp")):
        name = blocks.stem.removesuffix("_blocks")
        out = str(folder / "grid.vtm")
        args = [str(EXAMPLES / f"{name}.vtp"), "--blocks", str(blocks), "-o", out]
        args += ["--cell-size", CELL_SIZE, "--quiet"]
        rows.append({"case": name, **compare(args, folder, runs)})
        show(rows[-1])
    return rows


def bodies(folder: Path, runs: int) -> list[dict]:
    rows = []
    for name, source in BODIES.items():
        for topology in ("o", "c"):
            args = [*source, "--topology", topology, "-o", str(folder / "grid.vts"), "--quiet"]
            rows.append({"case": f"{name} {topology.upper()}-grid", **compare(args, folder, runs)})
            show(rows[-1])
    return rows


def trained(row: dict) -> bool:
    """Whether the default's run trained a network (in some block, for a multi-block grid)."""
    training = row.get("training") or {}
    parts = training.get("blocks", [training] if training else [])
    return any(not part.get("skipped") for part in parts)


def table(title: str, rows: list[dict]) -> str:
    """The rows as markdown, with the median ratio and the default's stages."""
    lines = [
        f"### {title}",
        "",
        "| case | default (s) | elliptic (s) | ratio | default CPU (s) | elliptic CPU (s) "
        "| CPU ratio |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['case']} | {r['default']:.2f} | {r['elliptic']:.2f} | {r['ratio']:.2f} "
            f"| {r['cpu']:.2f} | {r['elliptic_cpu']:.2f} | {r['cpu_ratio']:.2f} |"
        )
    median = statistics.median(r["ratio"] for r in rows)
    cpu = statistics.median(r["cpu_ratio"] for r in rows)
    lines += ["", f"Median ratio: **{median:.2f}x** (CPU {cpu:.2f}x) over {len(rows)} cases."]
    stages = [r["timings"] for r in rows if "timings" in r]
    if stages:
        names = sorted({k for s in stages for k in s})
        parts = [f"{k} {statistics.median(s.get(k, 0.0) for s in stages):.3f} s" for k in names]
        lines.append(f"The default's stages, medians: {', '.join(parts)}.")
    lines.append(f"Runs that trained a network: {sum(map(trained, rows))} of {len(rows)}.")
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="+", default=list(SIZES))
    parser.add_argument("--shapes", nargs="+", default=None)
    parser.add_argument("--kinds", nargs="+", choices=KINDS, default=list(KINDS))
    parser.add_argument("--runs", type=int, default=1, help="runs of each command, median")
    args = parser.parse_args()
    shapes = args.shapes or sorted(p.stem for p in HOLDOUT.glob("*.vtp"))
    cases = {
        "four-sided": lambda folder: four_sided(args.sizes, shapes, folder, args.runs),
        "blocks": lambda folder: multi_block(folder, args.runs),
        "bodies": lambda folder: bodies(folder, args.runs),
    }
    with tempfile.TemporaryDirectory() as tmp:
        out = []
        for kind in args.kinds:
            print(f"{KINDS[kind]}:", flush=True)
            out.append(
                table(
                    f"{KINDS[kind]}: the default against `--method elliptic`",
                    cases[kind](Path(tmp)),
                )
            )
    print("\n\n".join(out))


if __name__ == "__main__":
    main()
