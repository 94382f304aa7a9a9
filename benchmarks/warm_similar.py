"""Measured: does a network started from a similar case's trained network
(same block kind and size) reach the same quality in less training?

Usage: ``.venv/bin/python benchmarks/warm_similar.py [--lbfgs 120 60 30] [--repeat 2]
[--out docs/batch.md]``

The cases of ``benchmarks/batch.py`` (13 hard shapes at 81 x 41, 19 NACA O-grids), each
meshed in this process by the single-run command's ``run`` (method pinn), one family after
the other, in four arms a budget: every network fresh (the default), or each started from the
network the previous case of its family trained, with ``--lbfgs`` iterations each (the
default is 120). The start is the trained weights, loaded when the network is made: the
four-sided block then zeroes its output layer (its map starts at the elliptic grid, with the
hidden layers' features of the similar case), the O-grid's network keeps them all (its map
starts at the elliptic grid plus the similar case's correction). The experiment patches the
two network classes for its own run only; nothing in the package changes. Prints and writes
(between the markers of ``--out``), per family and arm, the best of ``--repeat`` alternating
runs: wall and training seconds, the mean of the cases' mean and worst MaxIncludedAngle, the
folded cells and the cases whose network grid the guard kept.
"""

from __future__ import annotations

import argparse
import contextlib
import copy
import io
import json
import tempfile
import time
from pathlib import Path

from batch import ROOT, cases  # the sibling benchmark's case list

from pinn_engine import heap
from pinn_engine.kinds.body import problem as body
from pinn_engine.kinds.four_sided import problem as quad
from pinn_engine.routes import cli

BEGIN, END = "<!-- warm from similar: begin -->", "<!-- warm from similar: end -->"


class Similar:
    """Wraps a network class: a new network takes the state the previous one of its class
    ended training with (when ``warm``)."""

    def __init__(self, module, name: str) -> None:
        self.module, self.name = module, name
        self.original = getattr(module, name)
        self.state = None
        self.last = None
        self.warm = False
        setattr(module, name, self.make)

    def make(self, *args, **kwargs):
        net = self.original(*args, **kwargs)
        if self.warm and self.state is not None:
            net.load_state_dict(self.state)
        self.last = net
        return net

    def keep(self) -> None:
        """Remember the last network's trained state for the next case."""
        if self.last is not None:
            self.state = copy.deepcopy(self.last.state_dict())


def mesh(row, lbfgs: int, scratch: Path) -> dict:
    """One case through the single-run command's ``run``; its report."""
    name, source, aux, options = row
    argv = [source] if source else []
    argv += ["--aux", aux] if aux else []
    report = scratch / f"{name}.json"
    argv += [*options.split(), "--lbfgs", str(lbfgs), "--quiet"]
    argv += ["-o", str(scratch / f"{name}.vts"), "--report", str(report)]
    with contextlib.redirect_stdout(io.StringIO()), contextlib.redirect_stderr(io.StringIO()):
        cli.run(cli.build_parser().parse_args(argv))
    return json.loads(report.read_text())


def arm(rows, lbfgs: int, warm: bool, nets: list[Similar], scratch: Path) -> dict:
    """One family in one arm: wall and training seconds, the mean quality figures, the
    folded cells and how many cases kept the network's grid (not the start's)."""
    for n in nets:
        n.warm, n.state = warm, None
    reports = []
    start = time.perf_counter()
    for row in rows:
        reports.append(mesh(row, lbfgs, scratch))
        for n in nets:
            n.keep()
    count = len(reports)
    quality = [r["quality"] for r in reports]
    return {
        "seconds": time.perf_counter() - start,
        "training": sum(r["train_seconds"] for r in reports),
        "mean": sum(q["mean_max_angle"] for q in quality) / count,
        "worst": sum(q["worst_max_angle"] for q in quality) / count,
        "folded": sum(q["folded_cells"] for q in quality),
        "kept": sum(r.get("training", {}).get("result") == "network" for r in reports),
    }


def table(families: dict, opts, nets: list[Similar], scratch: Path) -> str:
    """Each family, budget and start, the best of ``opts.repeat`` alternating runs."""
    lines = [
        "| family | network start | L-BFGS iterations | wall (s) | training (s) | mean of "
        "mean angle | mean of worst angle | folded cells | network's grid kept |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for family, members in families.items():
        mesh(members[0], opts.lbfgs[0], scratch)  # imports and builds the jet code first
        for lbfgs in opts.lbfgs:
            best: dict[bool, dict] = {}
            for _ in range(opts.repeat):
                for warm in (False, True):
                    got = arm(members, lbfgs, warm, nets, scratch)
                    if warm not in best or got["seconds"] < best[warm]["seconds"]:
                        best[warm] = got
            for warm, got in best.items():
                lines.append(
                    f"| {family} ({len(members)}) | {'similar case' if warm else 'fresh'} | "
                    f"{lbfgs} | {got['seconds']:.1f} | {got['training']:.1f} | "
                    f"{got['mean']:.3f} | {got['worst']:.3f} | {got['folded']} | "
                    f"{got['kept']} |"
                )
                print(lines[-1], flush=True)
    return "\n".join(lines)


def write(page: Path, text: str) -> None:
    """Put ``text`` between the markers of ``page``."""
    head, rest = page.read_text().split(BEGIN, 1)
    page.write_text(f"{head}{BEGIN}\n{text}\n{END}{rest.split(END, 1)[1]}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--lbfgs", type=int, nargs="+", default=[120, 60, 30])
    parser.add_argument("--repeat", type=int, default=2, help="alternating runs of each arm")
    parser.add_argument("--out", type=Path, default=ROOT / "docs" / "batch.md")
    opts = parser.parse_args()
    heap.tune_process()  # as the command's process does
    nets = [Similar(quad, "CoordinateNet"), Similar(body, "BodyNet")]
    rows = cases()
    families = {"hard shapes": [r for r in rows if r[1]], "NACA": [r for r in rows if not r[1]]}
    with tempfile.TemporaryDirectory() as scratch:
        text = table(families, opts, nets, Path(scratch))
    if opts.out:
        write(opts.out, text)


if __name__ == "__main__":
    main()
