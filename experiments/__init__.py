"""The paper's section 4 experiments on pinn-mesh: one command, figures, numbers and a report.

    .venv/bin/python -m experiments --mode full

runs every experiment (method comparisons on the example cases under the paper preset and the
default, and the architecture sweep), with a progress bar on stderr, and writes PNG figures,
CSV and JSON numbers into ``results/``, the report ``docs/RESULTS.md`` and the README section
``docs/README_results_section.md``. ``--mode quick`` runs the same code with tiny budgets (the
test suite does) and by default writes its documents into the output folder instead.
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from datetime import datetime, timezone
from pathlib import Path

from .execute import clock
from .runs import BUDGETS, LOSS_CASE, Budget, make_plan

ROOT = Path(__file__).resolve().parents[1]

__all__ = ["BUDGETS", "Budget", "main", "run_experiments"]


def _examples_dir() -> Path:
    here = ROOT / "example_data"
    return here if here.is_dir() else Path.cwd() / "example_data"


def run_experiments(
    mode: str = "quick",
    out: str | os.PathLike = "results",
    doc: str | os.PathLike | None = None,
    readme: str | os.PathLike | None = None,
    jobs: int = 1,
    device: str = "cpu",
    example_dir: str | os.PathLike | None = None,
    progress: bool = True,
    command: str | None = None,
    budget: Budget | None = None,
    cache: str | os.PathLike | None = None,
    reuse: bool = False,
) -> dict:
    """Run every experiment of ``mode`` and write figures, numbers and documents.

    ``cache``: a folder where each finished run is kept (one pickle per run); with ``reuse``
    the successful runs found there are not run again (e.g. to rerun only failed runs, or to
    regenerate the figures and documents). Returns the summary (also in ``out/summary.json``).
    """
    from . import report
    from .analysis import all_claims, loss_rows, quality_rows, sweep_data
    from .execute import ProgressBar, RunCache, execute
    from .figures import N_FIGURES, make_figures
    from .runs import CASES, LABELS, METHODS, PRESETS

    budget = budget or BUDGETS[mode]
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    doc = (
        Path(doc)
        if doc
        else (ROOT / "docs" / "RESULTS.md" if budget.mode == "full" else out / "RESULTS.md")
    )
    readme = (
        Path(readme)
        if readme
        else (
            ROOT / "docs" / "README_results_section.md"
            if budget.mode == "full"
            else out / "README_results_section.md"
        )
    )
    example_dir = Path(example_dir) if example_dir else _examples_dir()
    command = command or (
        f".venv/bin/python -m experiments --mode {budget.mode}"
        + (f" --out {out}" if str(out) != "results" else "")
    )
    plan = make_plan(budget, device)
    run_cost = sum(j.cost() for j in plan.jobs)
    fig_cost = 0.4 * N_FIGURES  # about a second each, in the cost unit (100 epochs)
    bar = ProgressBar(run_cost + fig_cost, enabled=progress)
    started = time.perf_counter()
    store = RunCache(cache) if cache else None
    done = store.load(plan.jobs) if (store and reuse) else {}
    results = execute(
        plan.jobs, example_dir, jobs, bar, fig_cost, done, store.save if store else None
    )

    fig_steps = [0]

    def step(label: str) -> None:
        fig_steps[0] += 1
        bar.update(run_cost + fig_cost * fig_steps[0] / N_FIGURES, f"figures: {label}")

    figs, renderers = make_figures(results, budget, out, step)
    report.write_numbers(results, out)
    claims = all_claims(results, budget)
    sweeps = sweep_data(results, budget)
    wall = time.perf_counter() - started
    cpu = sum(r.get("run_seconds", 0.0) for r in results.values())
    date = datetime.now(timezone.utc).strftime("%Y-%m-%d %H:%M UTC")
    session = {
        "date": date,
        "wall_seconds": round(wall, 1),
        "processes": jobs,
        "executed": len(results) - len(done),
        "succeeded": sum(bool(r.get("ok")) for k, r in results.items() if k not in done),
    }
    sessions = store.add_session(session) if store else [session]
    computing = [x for x in sessions if x.get("succeeded")]
    ctx = {
        "budget": budget,
        "out": out,
        "root": ROOT,
        "command": command,
        "date": date,
        "wall": clock(wall),
        "cpu_minutes": cpu / 60,
        "processes": jobs,
        "n_runs": len(results),
        "machine": _machine(),
        "reused": len(done),
        "sessions_wall": clock(sum(x["wall_seconds"] for x in computing)),
        "sessions": len(computing),
    }
    doc.parent.mkdir(parents=True, exist_ok=True)
    doc.write_text(report.results_markdown(ctx, results, claims, figs, doc))
    readme.parent.mkdir(parents=True, exist_ok=True)
    readme.write_text(report.readme_markdown(ctx, results, claims, figs, ROOT, doc))
    summary = {
        "mode": budget.mode,
        "command": command,
        "date": ctx["date"],
        "wall_seconds": wall,
        "run_seconds_total": cpu,
        "processes": jobs,
        "machine": ctx["machine"],
        "reused_runs": len(done),
        "sessions": sessions,
        "budget": budget.to_dict(),
        "renderer": sorted(renderers),
        "figures": {k: p.name for k, p in figs.items()},
        "documents": {"results": str(doc), "readme_section": str(readme)},
        "labels": LABELS,
        "claims": claims,
        "quality": {
            f"{c}/{p}": quality_rows(results, c, p, METHODS) for c in CASES for p in PRESETS
        },
        "loss": {p: loss_rows(results, LOSS_CASE, p) for p in PRESETS},
        "architecture": {k: v for k, v in sweeps.items()},
        "failed": {r["key"]: r.get("error", "") for r in results.values() if not r.get("ok")},
    }
    report.write_json(summary, out / "summary.json")
    bar.close(f"done: {len(results)} runs, {len(figs)} figures in {out}")
    return summary


def _machine() -> str:
    try:
        import torch

        torch_version = torch.__version__
    except ImportError:  # pragma: no cover
        torch_version = "?"
    return (
        f"{platform.system()} {platform.machine()}, {os.cpu_count()} CPUs, Python "
        f"{platform.python_version()}, torch {torch_version}"
    )


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="python -m experiments",
        description="Run the paper's section 4 experiments (Figs. 4-9 analogues) on the "
        "example cases; write figures, CSV/JSON numbers and docs/RESULTS.md.",
    )
    p.add_argument(
        "--mode",
        choices=sorted(BUDGETS),
        default="full",
        help="full: the committed results (about an hour on 2 cores); quick: tiny "
        "budgets, under a minute, checks the code end to end",
    )
    p.add_argument(
        "--out", default="results", help="folder for figures and numbers (default results)"
    )
    p.add_argument(
        "--doc",
        help="the report (default: docs/RESULTS.md in full mode, OUT/RESULTS.md in quick mode)",
    )
    p.add_argument(
        "--readme-section",
        dest="readme",
        help="the README results section "
        "(default: docs/README_results_section.md in full mode, in OUT otherwise)",
    )
    p.add_argument(
        "--jobs",
        type=int,
        default=None,
        help="worker processes (default: 2 in full mode if 2+ CPUs, else 1)",
    )
    p.add_argument(
        "--device", default="cpu", help="torch device for training (default cpu, as the paper)"
    )
    p.add_argument(
        "--cache",
        default=None,
        help="keep every finished run here (default: "
        "out/experiments_cache/MODE, git-ignored); 'none' to keep nothing",
    )
    p.add_argument(
        "--reuse",
        action="store_true",
        help="reuse the successful runs in the "
        "cache instead of running them again (reruns failed and missing runs, "
        "then regenerates every figure and document)",
    )
    p.add_argument("--quiet", action="store_true", help="no progress bar")
    return p


def main(argv: list[str] | None = None) -> int:
    args = build_parser().parse_args(argv)
    jobs = args.jobs or (min(2, os.cpu_count() or 1) if args.mode == "full" else 1)
    command = f".venv/bin/python -m experiments --mode {args.mode}"
    for flag, value, default in (
        ("--out", args.out, "results"),
        ("--doc", args.doc, None),
        ("--readme-section", args.readme, None),
    ):
        if value not in (None, default):
            command += f" {flag} {value}"
    cache = (
        None
        if args.cache == "none"
        else (args.cache or ROOT / "out" / "experiments_cache" / args.mode)
    )
    summary = run_experiments(
        args.mode,
        args.out,
        args.doc,
        args.readme,
        jobs,
        args.device,
        progress=not args.quiet,
        command=command.strip(),
        cache=cache,
        reuse=args.reuse,
    )
    print(
        f"wrote {len(summary['figures'])} figures and the numbers to {args.out}, "
        f"{summary['documents']['results']} and {summary['documents']['readme_section']}"
    )
    for claim in summary["claims"]:
        print(f"  {claim['verdict']:>12}: {claim['claim']}")
    return 0
