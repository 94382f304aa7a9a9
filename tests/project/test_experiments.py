"""The experiments of the paper's section 4: quick mode end to end, and the logic
that turns numbers into verdicts."""

from __future__ import annotations

import csv
import io
import json
import math
import re
from pathlib import Path

import numpy as np
import pytest
from helpers import ROOT

from experiments import BUDGETS, build_parser, run_experiments
from experiments.analysis import (
    claim_architecture,
    claim_pde,
    sweep_shape,
    tally,
)
from experiments.execute import ProgressBar
from experiments.runs import CASES, METHODS, NEURAL, PRESETS, make_plan

FIGURES = (
    [f"fig4_loss_wavy_{p}.png" for p in PRESETS]
    + [f"fig5_mesh_wavy_{p}.png" for p in PRESETS]
    + [f"fig6_angles_wavy_{p}.png" for p in PRESETS]
    + [f"fig7_mesh_{c}_{p}.png" for c in ("fig2", "concave") for p in PRESETS]
    + [f"fig8_angles_{c}_{p}.png" for c in ("fig2", "concave") for p in PRESETS]
    + ["fig9_architecture.png"]
)
NUMBERS = ["runs.csv", "loss_history_wavy.csv", "architecture.csv", "summary.json"] + [
    f"angles_{c}_{p}.csv" for c in CASES for p in PRESETS
]
VERDICTS = {"supported", "contradicted", "mixed", "n/a"}


@pytest.fixture(scope="module")
def quick(tmp_path_factory):
    """One quick-mode run of every experiment, shared by the tests below."""
    base = tmp_path_factory.mktemp("experiments")
    out, doc, readme = base / "results", base / "docs" / "RESULTS.md", base / "README_part.md"
    summary = run_experiments(
        "quick", out, doc, readme, jobs=1, progress=False, cache=base / "cache"
    )
    return {"out": out, "doc": doc, "readme": readme, "summary": summary, "base": base}


def _rows(path: Path) -> list[dict]:
    with path.open() as fh:
        return list(csv.DictReader(fh))


@pytest.mark.slow  # every experiment in quick mode, end to end (shared fixture)
def test_quick_mode_writes_every_file(quick):
    out = quick["out"]
    for name in FIGURES:
        data = (out / name).read_bytes()
        assert data[:4] == b"\x89PNG" and len(data) > 5_000, name
    for name in NUMBERS:
        assert (out / name).stat().st_size > 50, name
    assert quick["doc"].stat().st_size > 2_000
    assert quick["readme"].stat().st_size > 200


@pytest.mark.slow  # every experiment in quick mode, end to end (shared fixture)
def test_quick_mode_numbers_are_sane(quick):
    rows = _rows(quick["out"] / "runs.csv")
    plan = make_plan(BUDGETS["quick"])
    assert {r["key"] for r in rows} == {j.key for j in plan.jobs}
    compare = [r for r in rows if r["group"] == "compare"]
    assert {(r["case"], r["preset"], r["method"]) for r in compare} == {
        (c, p, m) for c in CASES for p in PRESETS for m in METHODS
    }
    elliptic = {
        (r["case"], r["preset"]): (float(r["mean_max_angle"]), float(r["worst_max_angle"]))
        for r in compare
        if r["method"] == "elliptic"
    }
    for r in compare:
        assert r["ok"] == "True", (r["key"], r["error"])
        mean, worst = float(r["mean_max_angle"]), float(r["worst_max_angle"])
        folded = int(r["folded_cells"])
        # TFI folds cells where the concave case's boundary turns inward; the elliptic grid
        # and, at this size, every neural grid do not
        if (r["case"], r["method"]) == ("concave", "tfi"):
            assert folded > 0
        else:
            assert folded == 0, r["key"]
            assert worst < 180.0, r["key"]  # no fold: every cell convex
        assert 90.0 < mean <= worst
        assert 0.0 < float(r["worst_min_angle"]) < 90.0  # no degenerate cell, no rectangle
        e_mean, e_worst = elliptic[r["case"], r["preset"]]
        if r["method"] == "tfi":
            assert mean > e_mean, r["key"]  # the elliptic grid is the smoother one
        if r["preset"] == "default" and r["method"] in NEURAL:
            # the warm start and its guard: within 0.5 / 2 degrees of the elliptic grid
            assert mean <= e_mean + 0.5 and worst <= e_worst + 2.0, r["key"]
        if r["method"] in NEURAL:
            assert float(r["train_seconds"]) > 0
            assert math.isfinite(float(r["final_total"])) and float(r["final_total"]) > 0
            assert float(r["final_eqns"]) > 0
            if r["preset"] == "paper":  # penalty boundary: one loss term per side
                assert all(
                    float(r[f"final_bcs_{s}"]) > 0 for s in ("bottom", "right", "top", "left")
                )
        else:
            assert r["final_total"] == ""
        if r["preset"] == "default" or r["method"] not in NEURAL:
            assert float(r["boundary_deviation"]) < 1e-9  # exact boundary
        else:  # the paper's penalty boundary: off the boundary (working frame, the unit box)
            assert 1e-3 < float(r["boundary_deviation"]) < 0.25, r["key"]
    hist = _rows(quick["out"] / "loss_history_wavy.csv")
    assert {h["phase"] for h in hist} == {"adam", "lbfgs"}
    assert {(h["preset"], h["method"]) for h in hist} == {(p, m) for p in PRESETS for m in NEURAL}
    angles = _rows(quick["out"] / "angles_concave_default.csv")
    ni, nj = BUDGETS["quick"].size
    assert len(angles) == (ni - 1) * (nj - 1)
    for r in compare:  # the per-cell angles are those the summary was made from
        if (r["case"], r["preset"]) == ("concave", "default"):
            cells = np.array([float(a[f"{r['method']}_MaxIncludedAngle"]) for a in angles])
            assert cells.mean() == pytest.approx(float(r["mean_max_angle"]), abs=1e-3)
            assert cells.max() == pytest.approx(float(r["worst_max_angle"]), abs=1e-3)
    sweep = _rows(quick["out"] / "architecture.csv")
    assert any(r["ok"] == "True" and float(r["final_total"]) > 0 for r in sweep)


@pytest.mark.slow  # every experiment in quick mode, end to end (shared fixture)
def test_quick_mode_summary_and_documents(quick):
    summary = json.loads((quick["out"] / "summary.json").read_text())
    assert summary["mode"] == "quick"
    assert {c["id"] for c in summary["claims"]} >= {"loss", "angles", "pde", "architecture"}
    for claim in summary["claims"]:
        assert claim["verdict"] in VERDICTS
        assert claim["evidence"]
    assert set(summary["figures"].values()) == set(FIGURES)
    text = quick["doc"].read_text()
    assert "## Verdicts on the paper's claims" in text and "Quick mode" in text
    for claim in summary["claims"]:
        assert claim["claim"] in text
    links = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", text)
    assert len(links) == len(FIGURES)
    for link in links:  # image links are relative to the document and resolve
        assert (quick["doc"].parent / link).is_file(), link
    readme = quick["readme"].read_text()
    (image,) = re.findall(r"!\[[^\]]*\]\(([^)]+)\)", readme)
    assert (ROOT / image).resolve() == (quick["out"] / "fig7_mesh_concave_default.png").resolve()
    assert "| Proposed (PINN) |" in readme


@pytest.mark.slow  # every experiment in quick mode, end to end (shared fixture)
def test_reuse_regenerates_from_the_cache(quick):
    base = quick["base"]
    again = run_experiments(
        "quick",
        base / "again",
        base / "again" / "RESULTS.md",
        base / "again" / "README.md",
        progress=False,
        cache=base / "cache",
        reuse=True,
    )
    ok = sum(r["ok"] == "True" for r in _rows(quick["out"] / "runs.csv"))
    assert again["reused_runs"] == ok
    first = [r for r in _rows(quick["out"] / "runs.csv") if r["ok"] == "True"]
    assert [r for r in _rows(base / "again" / "runs.csv") if r["ok"] == "True"] == first
    assert (base / "again" / "fig9_architecture.png").stat().st_size > 5_000


def test_full_mode_plan_matches_the_issue():
    budget = BUDGETS["full"]
    assert budget.sweep_layers == (1, 2, 3, 4, 5, 6, 7)
    assert budget.sweep_neurons == (10, 20, 30, 40, 50, 60)
    assert len(budget.sweep_seeds) >= 3
    jobs = make_plan(budget).jobs
    sweep = [j for j in jobs if j.group == "sweep"]
    assert len(sweep) == (7 + 6 - 1) * len(budget.sweep_seeds)  # 4 x 30 is shared
    compare = [j for j in jobs if j.group == "compare"]
    neural = [j.settings() for j in compare if j.method in NEURAL]
    assert all(s.adam_epochs == 5000 for s in neural if s.preset == "paper")
    assert all(
        s.warm_start == "elliptic" and s.lattice == budget.size
        for s in neural
        if s.preset == "default"
    )
    assert {j.settings().boundary_mode for j in compare if j.preset == "paper"} == {"penalty"}
    assert build_parser().parse_args([]).mode == "full"


def test_tally_and_sweep_shape():
    assert tally([True, True]) == "supported"
    assert tally([True, False, False, False]) == "contradicted"
    assert tally([True, True, False]) == "mixed"
    assert tally([]) == "n/a"
    xs = [1, 2, 3]
    assert sweep_shape(xs, [[3, 3.1], [2, 2.1], [1, 1.1]])["shape"] == "monotone"
    clear = sweep_shape(xs, [[3, 3.1], [1, 1.1], [2, 2.1]])
    assert clear["shape"] == "clear" and clear["best"] == 2 and (2, 3) in clear["clear_pairs"]
    noise = sweep_shape(xs, [[3, 3.1], [1, 2.0], [1.2, 1.9]])
    assert noise["shape"] == "noise"  # mean rises 2 -> 3, but the ranges overlap
    assert sweep_shape(xs, [[], [1.0], []])["shape"] == "n/a"


def _fake(
    case, preset, method, mean, worst, folded=0, deviation=0.0, seed=0, group="compare", **extra
):
    q = {
        "mean_max_angle": mean,
        "worst_max_angle": worst,
        "worst_min_angle": 180 - worst,
        "folded_cells": folded,
        "boundary_deviation": deviation,
    }
    run = {
        "key": f"{group}/{case}/{preset}/{method}/{seed}/{extra}",
        "group": group,
        "case": case,
        "preset": preset,
        "method": method,
        "seed": seed,
        "ok": True,
        "quality": q,
        "train_seconds": 1.0,
        "mesh_seconds": 0.0,
        "final": {"total": 1.0},
    }
    run.update(extra)
    return run


def test_pde_claim_thresholds():
    runs = []
    for case in ("fig2", "concave"):
        runs += [
            _fake(case, "default", "elliptic", 104.0, 133.0),
            _fake(case, "default", "pinn", 105.5, 140.0),  # comparable
            _fake(case, "paper", "elliptic", 104.0, 133.0),
            _fake(case, "paper", "pinn", 104.0, 133.0, deviation=0.02),
        ]  # off boundary
    claim = claim_pde({r["key"]: r for r in runs})
    assert claim["verdict"] == "mixed"
    assert sum("not comparable" in e for e in claim["evidence"]) == 2


def test_architecture_claim_from_seed_ranges():
    budget = BUDGETS["quick"]
    losses = {(1, 30): [5.0, 6.0], (4, 30): [1.0, 1.2], (4, 10): [2.0, 2.5]}

    def sweep() -> dict:
        runs = [
            _fake(
                "wavy",
                "paper",
                "pinn",
                100,
                120,
                seed=s,
                group="sweep",
                hidden_layers=n,
                neurons=w,
                final={"total": v},
            )
            for (n, w), values in losses.items()
            for s, v in enumerate(values)
        ]
        return {r["key"]: r for r in runs}

    claim = claim_architecture(sweep(), budget)
    assert claim["verdict"] == "contradicted"  # both sweeps: bigger was better every time
    losses[(4, 30)] = [7.0, 8.0]
    assert claim_architecture(sweep(), budget)["verdict"] == "supported"


def test_progress_bar_text():
    stream = io.StringIO()
    bar = ProgressBar(10.0, stream=stream, width=10)
    bar.update(5.0, "half way")
    bar.close("finished")
    lines = stream.getvalue().splitlines()
    assert lines[0].startswith("[#####.....]  50.0%") and lines[0].endswith("half way")
    assert lines[-1].startswith("[##########] 100.0%") and "finished" in lines[-1]


def test_one_hidden_layer_trains_under_the_paper_preset():
    from experiments.runs import Job, run_job

    job = Job(
        "sweep",
        "wavy",
        "pinn",
        "paper",
        0,
        (("adam_epochs", 20), ("lbfgs_iterations", 2), ("hidden_layers", 1), ("lbfgs_points", 100)),
        (11, 6),
    )
    result = run_job(job, ROOT / "example_data")
    assert result["ok"], result["error"]
    assert np.isfinite(result["final"]["total"])
