"""The default against its own elliptic command, end to end, as ratios taken in one run.

Usage: ``.venv/bin/python benchmarks/default_speed.py [--sizes 41x21 81x41] [--shapes NAME ...]
[--blocks-only | --four-sided-only]``

Each run is the ``pinn-mesh`` command in a fresh Python (start-up, reading, meshing and
writing, as a user waits for it), the default and ``--method elliptic`` alternating on the
same case so that the machine's load hits both alike:

* four-sided: every hold-out shape (``example_data/holdout/``, the sizes of
  ``benchmarks/holdout.py``); the ratio per case and their median;
* multi-block: the examples with a blocking (``example_data/*_blocks.vtp``) at a cell size of
  0.05; the ratio per case and their median.

The default's ``--report`` gives its seconds per stage (``timings``), whose medians are
printed too, and how many runs trained a network. Prints markdown tables (docs/speed.md).
"""

from __future__ import annotations

import argparse
import json
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


def timed(args: list[str], folder: Path, report: bool) -> tuple[float, dict]:
    """Wall seconds of one command in a fresh process, and its report (``--report``). A
    folded grid refused after meshing (``FOLDED``: the elliptic grid on several hold-out
    shapes) counts: its command did all the work."""
    path = folder / "report.json"
    extra = ["--report", str(path)] if report else []
    began = time.perf_counter()
    done = subprocess.run([*COMMAND, *args, *extra], capture_output=True, text=True, cwd=ROOT)
    seconds = time.perf_counter() - began
    if done.returncode and (report or FOLDED not in done.stderr):
        raise RuntimeError(f"{' '.join(args)}: {done.stderr.strip()}")
    return seconds, json.loads(path.read_text()) if report else {}


def compare(args: list[str], folder: Path) -> dict:
    """The default and the elliptic command on the same case, one after the other."""
    default, report = timed(args, folder, True)
    elliptic, _ = timed([*args, "--method", "elliptic"], folder, False)
    return {"default": default, "elliptic": elliptic, "ratio": default / elliptic, **report}


def four_sided(sizes: list[str], shapes: list[str], folder: Path) -> list[dict]:
    rows = []
    for name in shapes:
        for size in sizes:
            ni, nj = size.split("x")
            out = str(folder / "grid.vts")
            args = [str(HOLDOUT / f"{name}.vtp"), "--size", ni, nj, "-o", out, "--quiet"]
            row = {"case": f"{name} {size}", **compare(args, folder)}
            rows.append(row)
            print(f"  {row['case']}: {row['default']:.2f} s / {row['elliptic']:.2f} s", flush=True)
    return rows


def multi_block(folder: Path) -> list[dict]:
    rows = []
    for blocks in sorted(EXAMPLES.glob("*_blocks.vtp")):
        name = blocks.stem.removesuffix("_blocks")
        out = str(folder / "grid.vtm")
        args = [str(EXAMPLES / f"{name}.vtp"), "--blocks", str(blocks), "-o", out]
        args += ["--cell-size", CELL_SIZE, "--quiet"]
        row = {"case": name, **compare(args, folder)}
        rows.append(row)
        print(f"  {row['case']}: {row['default']:.2f} s / {row['elliptic']:.2f} s", flush=True)
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
        "| case | default (s) | elliptic (s) | ratio |",
        "|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['case']} | {r['default']:.2f} | {r['elliptic']:.2f} | {r['ratio']:.2f} |"
        )
    median = statistics.median(r["ratio"] for r in rows)
    lines += ["", f"Median ratio: **{median:.2f}x** over {len(rows)} cases."]
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
    parser.add_argument("--blocks-only", action="store_true")
    parser.add_argument("--four-sided-only", action="store_true")
    args = parser.parse_args()
    shapes = args.shapes or sorted(p.stem for p in HOLDOUT.glob("*.vtp"))
    with tempfile.TemporaryDirectory() as tmp:
        folder = Path(tmp)
        out = []
        if not args.blocks_only:
            print("four-sided, hold-out shapes:", flush=True)
            out.append(
                table(
                    "Four-sided default against `--method elliptic`",
                    four_sided(args.sizes, shapes, folder),
                )
            )
        if not args.four_sided_only:
            print("multi-block examples:", flush=True)
            out.append(
                table("Multi-block default against `--method elliptic`", multi_block(folder))
            )
    print("\n\n".join(out))


if __name__ == "__main__":
    main()
