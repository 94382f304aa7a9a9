"""Speed and memory of pinn-mesh: fast path against the plain-autograd reference, in one run.

Usage: ``.venv/bin/python benchmarks/bench_speed.py [--quick] [--case fig2]``

Every figure is measured in its own subprocess (clean peak memory, no warm caches shared), and
fast and reference runs alternate so that machine noise hits both. Printed:
- time per Adam epoch and per L-BFGS iteration, paper preset, fast vs reference, with ratios;
- the whole paper-preset training, fast (run before and after) vs reference, with final
  losses and their ratio;
- a 1001 x 1001 grid evaluated with its quality arrays (feed-forward);
- the converged elliptic solver at 101 x 101 and 401 x 401;
- peak resident memory of each subprocess.
Training times start once torch is imported (a one-time cost per process, printed apart).
The reference is the same loss with derivatives by nested ``torch.autograd.grad`` in float64
(settings ``derivatives="autograd", dtype="float64"``); the fast path is the default
(``derivatives="jets"``, ``dtype="float32"``).
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
PATHS = {
    "fast": {"derivatives": "jets", "dtype": "float32"},
    "reference": {"derivatives": "autograd", "dtype": "float64"},
}


def _peak_mib() -> float:
    import resource

    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024


def _inputs(case: str):
    from pinn_engine.io.pipeline import load_aux, load_boundary

    boundary = load_boundary(ROOT / "example_data" / f"{case}.vtp")
    return boundary, load_aux([ROOT / "example_data" / f"{case}_aux.vtp"], boundary)


def job_train(case: str, path: str, epochs: int, lbfgs: int) -> dict:
    """Train the paper preset; returns per-phase times from the history lengths."""
    from pinn_engine.kinds.four_sided.mesher import Mesher
    from pinn_engine.settings import make_settings

    boundary, aux = _inputs(case)
    start = time.perf_counter()
    import torch  # once per process, before any training: not part of the training time

    torch.optim.Adam([torch.zeros(1, requires_grad=True)])  # its first use imports more
    startup = time.perf_counter() - start
    stamps = {}

    def progress(info):  # called every 50 Adam epochs: time from the first call on
        now = time.perf_counter()
        phase = info["phase"]
        if phase not in stamps:
            stamps[phase] = (now, info["step"])
        stamps[phase + "_end"] = (now, info["step"])

    settings = make_settings(
        "pinn", "paper", adam_epochs=epochs, lbfgs_iterations=lbfgs, **PATHS[path]
    )
    mesher = Mesher(settings)
    start = time.perf_counter()
    mesher.fit(boundary, aux, progress)
    total = time.perf_counter() - start
    info = mesher.model_.info
    (t0, e0), (t1, e1) = stamps["adam"], stamps["adam_end"]
    lbfgs_s = start + total - t1
    iterations = max(info["lbfgs_iterations"], 1)
    return {
        "total_s": total,
        "adam_epoch_ms": 1e3 * (t1 - t0) / (e1 - e0),
        "lbfgs_iteration_ms": 1e3 * lbfgs_s / iterations,
        "lbfgs_iterations": iterations,
        "final_loss": info["final_loss"],
        "peak_mib": _peak_mib(),
        "startup_s": startup,
    }


def job_evaluate(case: str, n: int) -> dict:
    """Train briefly, then time a feed-forward n x n grid with its quality arrays."""
    from pinn_engine.io.pipeline import to_vtk
    from pinn_engine.kinds.four_sided.mesher import Mesher
    from pinn_engine.settings import make_settings

    boundary, aux = _inputs(case)
    mesher = Mesher(make_settings("pinn", adam_epochs=20, lbfgs_iterations=0)).fit(boundary, aux)
    mesher.predict(11, 11)  # warm-up
    start = time.perf_counter()
    grid = to_vtk(mesher.predict(n, n))
    seconds = time.perf_counter() - start
    assert grid.GetNumberOfPoints() == n * n
    return {"seconds": seconds, "peak_mib": _peak_mib()}


def job_elliptic(case: str, n: int) -> dict:
    from pinn_engine.kinds.four_sided.mesher import Mesher
    from pinn_engine.settings import make_settings

    boundary, _ = _inputs(case)
    mesher = Mesher(make_settings("elliptic")).fit(boundary)
    start = time.perf_counter()
    mesher.predict(n, n)
    return {"seconds": time.perf_counter() - start, "peak_mib": _peak_mib()}


JOBS = {"train": job_train, "evaluate": job_evaluate, "elliptic": job_elliptic}


def run_job(name: str, *args) -> dict:
    """Run one job in a fresh interpreter and return its JSON result."""
    out = subprocess.run(
        [sys.executable, __file__, "--job", name, *map(str, args)],
        capture_output=True,
        text=True,
        check=True,
        cwd=ROOT,
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="short budgets (minutes -> seconds)")
    p.add_argument("--case", default="fig2")
    p.add_argument("--repeats", type=int, default=3, help="repeats of the per-step timings")
    p.add_argument("--job", nargs="+", help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.job:
        name, *rest = args.job
        conv = [int(a) if a.lstrip("-").isdigit() else a for a in rest]
        print(json.dumps(JOBS[name](*conv)))
        return

    case = args.case
    short = (100, 10) if args.quick else (400, 40)
    full = (300, 30) if args.quick else (5000, 500)
    print(
        f"pinn-mesh speed benchmark on example_data/{case}.vtp (paper preset, "
        f"{'quick' if args.quick else 'full'} mode)\n"
    )

    steps = {path: [] for path in PATHS}
    for _ in range(args.repeats):
        for path in PATHS:
            steps[path].append(run_job("train", case, path, *short))
    med = {
        path: {
            k: statistics.median(r[k] for r in runs)
            for k in ("adam_epoch_ms", "lbfgs_iteration_ms")
        }
        for path, runs in steps.items()
    }
    print(
        f"per step (median of {args.repeats}; {short[0]} Adam epochs at batch 100, "
        f"{short[1]} L-BFGS iterations on 1000 points)"
    )
    print(f"  {'':24s}{'fast':>12s}{'reference':>12s}{'ratio':>8s}")
    for key, label in (
        ("adam_epoch_ms", "Adam epoch (ms)"),
        ("lbfgs_iteration_ms", "L-BFGS iteration (ms)"),
    ):
        f, r = med["fast"][key], med["reference"][key]
        print(f"  {label:24s}{f:12.2f}{r:12.2f}{r / f:8.2f}x")

    # fast, reference, fast: a slow spell of the shared machine during one fast run shows
    # up as a difference between the two, and the ratio uses their mean
    first = run_job("train", case, "fast", *full)
    r = run_job("train", case, "reference", *full)
    second = run_job("train", case, "fast", *full)
    fast_s = (first["total_s"] + second["total_s"]) / 2
    print(
        f"\nwhole paper-preset training ({full[0]} Adam epochs + up to {full[1]} L-BFGS "
        "iterations; fast run before and after the reference)"
    )
    print(f"  {'':24s}{'fast':>12s}{'reference':>12s}{'ratio':>8s}")
    print(
        f"  {'seconds':24s}{fast_s:12.1f}{r['total_s']:12.1f}{r['total_s'] / fast_s:8.2f}x"
        f"   (fast runs {first['total_s']:.1f} s and {second['total_s']:.1f} s)"
    )
    print(
        f"  {'final loss':24s}{first['final_loss']:12.4e}{r['final_loss']:12.4e}"
        f"{first['final_loss'] / r['final_loss']:8.2f} (fast / reference)"
    )
    print(f"  {'L-BFGS iterations':24s}{first['lbfgs_iterations']:12d}{r['lbfgs_iterations']:12d}")
    print(f"  {'peak memory (MiB)':24s}{first['peak_mib']:12.0f}{r['peak_mib']:12.0f}")
    print(
        f"  (not included: importing torch and its optimizers, once per process: "
        f"{first['startup_s']:.1f} s)"
    )
    if first["final_loss"] != second["final_loss"]:
        print(
            "  note: the two fast runs ended at different losses "
            f"({first['final_loss']:.6e}, {second['final_loss']:.6e})"
        )

    ev = run_job("evaluate", case, 1001)
    print(
        f"\n1001 x 1001 grid, feed-forward with quality arrays: {ev['seconds']:.2f} s "
        f"(peak {ev['peak_mib']:.0f} MiB)"
    )
    for n in (101, 401):
        el = run_job("elliptic", case, n)
        print(
            f"converged elliptic grid {n} x {n}: {el['seconds']:.2f} s "
            f"(peak {el['peak_mib']:.0f} MiB)"
        )


if __name__ == "__main__":
    from pinn_engine.heap import tune_process

    tune_process()  # as the command line does (the library leaves a host's allocator alone)
    main()
