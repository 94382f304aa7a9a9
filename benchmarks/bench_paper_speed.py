"""The paper preset against the plain-autograd paper recipe, alternating, on one boundary.

Usage: ``.venv/bin/python benchmarks/bench_paper_speed.py [--pairs 3] [--shape bump]
[--plain-threads 1]``

The comparison: ``benchmarks/plain_pinn.py`` (nn.Linear, nested autograd, torch's
Adam in float32, torch's L-BFGS in float64) and the ``paper`` preset (the same recipe through
pinn-mesh's fast path) train on ``example_data/hard/<shape>.vtp`` with its auxiliary line.
Each training runs in a fresh process (torch imported before the clock starts), plain and
paper alternate ``--pairs`` times, so that load from other work on the machine hits both;
printed: every run's wall and CPU seconds and final loss, the medians, the ratio of the
median wall times (and of CPU times), and the load average before and after.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
HARD = ROOT / "example_data" / "hard"


def job(kind: str, shape: str, threads: int) -> dict:
    """One training in this process; returns seconds (wall, CPU) and the final loss."""
    import torch

    sys.path.insert(0, str(ROOT / "benchmarks"))
    from plain_pinn import train_plain

    from pinn_engine.io.pipeline import load_aux, load_boundary
    from pinn_engine.kinds.four_sided.mesher import Mesher
    from pinn_engine.settings import make_settings

    torch.optim.Adam([torch.zeros(1, requires_grad=True)])  # its first use imports more
    boundary = load_boundary(HARD / f"{shape}.vtp")
    aux = load_aux([HARD / f"{shape}_aux.vtp"], boundary)
    import pinn_engine

    assert Path(pinn_engine.__file__).resolve().parents[1] == ROOT, pinn_engine.__file__
    wall, cpu = time.perf_counter(), time.process_time()
    if kind == "plain":
        result = train_plain(boundary, aux, threads=threads)
        loss = result["final_loss"]
    else:
        mesher = Mesher(make_settings("pinn", "paper"))
        mesher.fit(boundary, aux)
        loss = mesher.model_.info["final_loss"]
    return {
        "kind": kind,
        "wall_s": time.perf_counter() - wall,
        "cpu_s": time.process_time() - cpu,
        "final_loss": loss,
    }


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--pairs", type=int, default=3)
    p.add_argument("--shape", default="bump")
    p.add_argument(
        "--plain-threads",
        type=int,
        default=1,
        help="torch threads of the plain recipe (the paper preset uses one)",
    )
    p.add_argument("--job", nargs=2, metavar=("KIND", "SHAPE"), help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.job:
        print(json.dumps(job(args.job[0], args.job[1], args.plain_threads)))
        return
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join(  # this checkout's engine, always
            [str(ROOT), *filter(None, [os.environ.get("PYTHONPATH")])]
        ),
    }
    load_before = os.getloadavg()
    runs: dict[str, list[dict]] = {"plain": [], "paper": []}
    for _ in range(args.pairs):
        for kind in ("plain", "paper"):
            out = subprocess.run(
                [
                    sys.executable,
                    __file__,
                    "--job",
                    kind,
                    args.shape,
                    "--plain-threads",
                    str(args.plain_threads),
                ],
                check=True,
                capture_output=True,
                text=True,
                cwd=ROOT,
                env=env,
            )
            run = json.loads(out.stdout.strip().splitlines()[-1])
            runs[kind].append(run)
            print(
                f"{kind:5s} wall {run['wall_s']:6.1f} s  cpu {run['cpu_s']:6.1f} s  "
                f"final loss {run['final_loss']:.4e}",
                flush=True,
            )
    med = {
        k: {m: statistics.median(r[m] for r in v) for m in ("wall_s", "cpu_s", "final_loss")}
        for k, v in runs.items()
    }
    print(
        f"\n{args.shape}, 41 x 21 aux line, {args.pairs} pairs alternating; plain recipe on "
        f"{args.plain_threads} torch thread(s), paper preset on 1"
    )
    for kind in ("plain", "paper"):
        print(
            f"  {kind:5s} median wall {med[kind]['wall_s']:6.1f} s, cpu "
            f"{med[kind]['cpu_s']:6.1f} s, final loss {med[kind]['final_loss']:.4e}"
        )
    print(
        f"  plain / paper: {med['plain']['wall_s'] / med['paper']['wall_s']:.2f}x wall, "
        f"{med['plain']['cpu_s'] / med['paper']['cpu_s']:.2f}x cpu"
    )
    print(
        "  load average before: "
        + " ".join(f"{x:.2f}" for x in load_before)
        + "; after: "
        + " ".join(f"{x:.2f}" for x in os.getloadavg())
    )


if __name__ == "__main__":
    main()
