"""Numbers from the runs: per-method tables, the architecture sweep, and the claim verdicts.

Everything here works on the plain dictionaries :func:`runs.run_job` returns, so the verdicts
are computed from the same numbers the tables and figures show.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Sequence

import numpy as np

from .runs import CASES, FOUR_METHOD_CASES, LOSS_CASE, NEURAL, PRESETS, SHORT, Budget

# The paper's own numbers (section 4), quoted next to ours.
PAPER_LOSS = {
    "bcs_top": {"pinn": 4.939974e-03, "mgnet": 9.370522e-03},
    "total": {"pinn": 1.742072e-02},
}
PAPER_ANGLES = {
    "pinn": {"mean_max_angle": 101.7, "worst_max_angle": 161.4},
    "mgnet": {"mean_max_angle": 103.1, "worst_max_angle": 174.0},
}
# "Comparable to the PDE method": mean MaxIncludedAngle at most this many degrees above the PDE
# mesh's, worst MaxIncludedAngle at most this many degrees above it, and no more folded cells.
# The grid must also fit the boundary: nodes within this fraction of the bounding-box diagonal.
COMPARABLE_MEAN_DEG = 2.0
COMPARABLE_WORST_DEG = 10.0
COMPARABLE_BOUNDARY = 0.005
# Angle differences up to these many degrees count as ties (neither method better).
TIE_MEAN_DEG = 0.1
TIE_WORST_DEG = 0.5
TIE_LOSS = 0.1  # loss values within 10 % of each other
LOSS_TERMS = ("eqns", "bcs_bottom", "bcs_right", "bcs_top", "bcs_left", "data", "total")
COMPARED_TERMS = ("eqns", "bcs_bottom", "bcs_right", "bcs_top", "bcs_left", "total")
QUALITY_KEYS = (
    "mean_max_angle",
    "worst_max_angle",
    "worst_min_angle",
    "folded_cells",
    "boundary_deviation",
)


def select(
    results: dict[str, dict],
    group: str = "compare",
    case: str | None = None,
    preset: str | None = None,
    method: str | None = None,
    ok: bool = True,
) -> list[dict]:
    """Runs matching the given fields, by seed."""
    out = [
        r
        for r in results.values()
        if r.get("group") == group
        and (case is None or r.get("case") == case)
        and (preset is None or r.get("preset") == preset)
        and (method is None or r.get("method") == method)
        and (not ok or r.get("ok"))
    ]
    return sorted(out, key=lambda r: r.get("seed", 0))


def pictured(runs: Sequence[dict]) -> dict | None:
    """The run a figure shows: seed 0 if it succeeded, else the first that did."""
    return next((r for r in runs if r.get("seed") == 0), runs[0] if runs else None)


def stats(values: Iterable[float]) -> dict:
    v = np.asarray([x for x in values if x is not None and math.isfinite(x)], dtype=float)
    if v.size == 0:
        return {"mean": math.nan, "min": math.nan, "max": math.nan, "n": 0}
    return {"mean": float(v.mean()), "min": float(v.min()), "max": float(v.max()), "n": int(v.size)}


def run_seconds(run: dict) -> float:
    """Time to a grid: training plus evaluation (the classical methods: meshing only)."""
    return float(run.get("train_seconds", 0.0)) + float(run.get("mesh_seconds", 0.0))


def quality_rows(results: dict, case: str, preset: str, methods: Sequence[str]) -> list[dict]:
    """One row per method: quality figures and run time, over the seeds that ran."""
    rows = []
    for method in methods:
        runs = select(results, "compare", case, preset, method)
        row = {"case": case, "preset": preset, "method": method, "seeds": len(runs)}
        for key in QUALITY_KEYS:
            row[key] = stats(r["quality"][key] for r in runs)
        row["run_seconds"] = stats(run_seconds(r) for r in runs)
        row["final_loss"] = (
            stats(r["final"].get("total", math.nan) for r in runs) if method in NEURAL else None
        )
        row["failed"] = len(select(results, "compare", case, preset, method, ok=False)) - len(runs)
        rows.append(row)
    return rows


def loss_rows(results: dict, case: str, preset: str) -> list[dict]:
    """Final value of every loss term, proposed vs MGNet (mean and range over seeds)."""
    rows = []
    for term in LOSS_TERMS:
        row = {"term": term}
        present = False
        for method in NEURAL:
            runs = select(results, "compare", case, preset, method)
            values = [r["final"].get(term, math.nan) for r in runs]
            row[method] = stats(values)
            row[f"{method}_by_seed"] = {r["seed"]: r["final"].get(term, math.nan) for r in runs}
            present |= any(v not in (0.0,) and math.isfinite(v) for v in values)
        if present:
            row["paper"] = PAPER_LOSS.get(term, {}) if preset == "paper" else {}
            rows.append(row)
    return rows


def lbfgs_gain(run: dict) -> dict:
    """Total loss at the end of Adam (mean of its last 1 %) and after L-BFGS."""
    total = np.asarray(run["history"].get("total", []), dtype=float)
    n_adam = int(run.get("n_adam", 0))
    if n_adam == 0 or total.size <= n_adam:
        return {"adam_end": math.nan, "final": float(total[-1]) if total.size else math.nan}
    tail = total[max(0, n_adam - max(n_adam // 100, 1)) : n_adam]
    return {"adam_end": float(tail.mean()), "final": float(total[-1])}


def sweep_data(results: dict, budget: Budget) -> dict[str, dict]:
    """The two architecture sweeps: x values and the final losses of every seed."""
    runs = select(results, "sweep")
    failed = select(results, "sweep", ok=False)
    failed = [r for r in failed if not r.get("ok")]

    def losses(layers: int, neurons: int) -> list[float]:
        return [
            r["final"].get("total", math.nan)
            for r in runs
            if r.get("hidden_layers") == layers and r.get("neurons") == neurons
        ]

    def seconds(layers: int, neurons: int) -> list[float]:
        return [
            r.get("train_seconds", math.nan)
            for r in runs
            if r.get("hidden_layers") == layers and r.get("neurons") == neurons
        ]

    layers = {
        "x": list(budget.sweep_layers),
        "label": "hidden layers",
        "fixed": f"{budget.sweep_fixed_neurons} neurons per layer",
        "losses": [losses(n, budget.sweep_fixed_neurons) for n in budget.sweep_layers],
        "seconds": [seconds(n, budget.sweep_fixed_neurons) for n in budget.sweep_layers],
    }
    neurons = {
        "x": list(budget.sweep_neurons),
        "label": "neurons per hidden layer",
        "fixed": f"{budget.sweep_fixed_layers} hidden layers",
        "losses": [losses(budget.sweep_fixed_layers, w) for w in budget.sweep_neurons],
        "seconds": [seconds(budget.sweep_fixed_layers, w) for w in budget.sweep_neurons],
    }
    return {
        "(a) hidden layers": layers,
        "(b) neurons per layer": neurons,
        "_failed": [r["key"] for r in failed],
    }


def sweep_shape(xs: Sequence[int], losses: Sequence[Sequence[float]]) -> dict:
    """Whether a bigger network ever did worse than a smaller one.

    ``clear``: some larger size's best seed is worse than some smaller size's worst seed;
    ``noise``: only the seed means get worse somewhere (the seed ranges overlap);
    ``monotone``: the mean loss falls with every step in size.
    """
    st = [stats(v) for v in losses]
    keep = [(x, s) for x, s in zip(xs, st) if s["n"]]
    if len(keep) < 2:
        return {"shape": "n/a", "best": None, "worse_steps": [], "clear_pairs": []}
    best = min(keep, key=lambda p: p[1]["mean"])[0]
    worse = [(a[0], b[0]) for a, b in zip(keep, keep[1:]) if b[1]["mean"] > a[1]["mean"]]
    clear = [
        (a[0], b[0]) for i, a in enumerate(keep) for b in keep[i + 1 :] if b[1]["min"] > a[1]["max"]
    ]
    shape = "clear" if clear else ("noise" if worse else "monotone")
    return {
        "shape": shape,
        "best": best,
        "worse_steps": worse,
        "clear_pairs": clear,
        "means": {x: s["mean"] for x, s in keep},
    }


SHAPE_TEXT = {
    "clear": "a larger size worse for every seed",
    "noise": "larger sizes worse only within the seed spread",
    "monotone": "larger always better",
    "n/a": "too few runs",
}


def tally(flags: Sequence[bool]) -> str:
    """All true: supported; at most a third: contradicted; otherwise mixed."""
    if not flags:
        return "n/a"
    wins = sum(bool(f) for f in flags)
    if wins == len(flags):
        return "supported"
    if wins <= len(flags) / 3:
        return "contradicted"
    return "mixed"


def _pct(x: float) -> str:
    """A boundary deviation (fraction of the diagonal) as a percentage; exact fits as 0."""
    return f"{100 * x:.2g} %" if x > 1e-9 else "0 %"


def _counts(words: Sequence[str], what: str) -> str:
    n = len(words)
    return (
        f"{words.count('lower')} of {n} {what} lower, {words.count('tie')} tied, "
        f"{words.count('higher')} higher"
    )


def _e(x: float) -> str:
    return f"{x:.2e}" if math.isfinite(x) else "n/a"


def _d(x: float) -> str:
    return f"{x:.1f}" if math.isfinite(x) else "n/a"


def claim_loss(results: dict) -> dict:
    """Claim 1a: the proposed method reaches lower loss terms than MGNet (paper Fig. 4)."""
    flags, evidence, beyond, words = [], [], [], []
    for case in CASES:
        for preset in PRESETS:
            rows = loss_rows(results, case, preset)
            won, parts = [], []
            for row in rows:
                if row["term"] not in COMPARED_TERMS:
                    continue
                a, b = row["pinn"]["mean"], row["mgnet"]["mean"]
                if not (math.isfinite(a) and math.isfinite(b)) or (a == 0 and b == 0):
                    continue
                word = _compare(a / max(a, b), b / max(a, b), TIE_LOSS)
                won.append(word == "lower")
                parts.append(f"{row['term']} {_e(a)} vs {_e(b)} ({word})")
            if not won:
                continue
            seeds = [
                (row["pinn_by_seed"], row["mgnet_by_seed"])
                for row in rows
                if row["term"] == "total"
            ]
            seed_text = ""
            if seeds and len(seeds[0][0]) > 1:
                p, m = seeds[0]
                common = sorted(set(p) & set(m))
                lower = sum(p[s] < m[s] for s in common)
                seed_text = f"; total lower in {lower} of {len(common)} seeds"
            line = (
                f"{case}, {preset} preset: proposed lower in {sum(won)} of {len(won)} terms "
                f"({'; '.join(parts)}){seed_text}"
            )
            if case == LOSS_CASE:
                flags.extend(won)
                words.extend(w.rsplit("(", 1)[1].rstrip(")") for w in parts)
                evidence.append(line)
            else:
                beyond.append((line, won))
    for preset in PRESETS:
        run = pictured(select(results, "compare", LOSS_CASE, preset, "pinn"))
        if run is not None:
            g = lbfgs_gain(run)
            evidence.append(
                f"{LOSS_CASE}, {preset} preset, proposed: total loss "
                f"{_e(g['adam_end'])} at the end of Adam, {_e(g['final'])} after "
                "L-BFGS"
            )
    beyond_flags = [f for _, won in beyond for f in won]
    return {
        "id": "loss",
        "short": "proposed beats MGNet in loss",
        "claim": "The proposed method beats MGNet in every loss term",
        "paper": "Fig. 4, first case: lower in all terms, e.g. Loss_bcs-up 4.94e-03 vs "
        "9.37e-03; composite loss 1.74e-02",
        "scope": f"verdict from the {LOSS_CASE} case (the paper's), both presets, every loss "
        "term both methods have, mean over seeds (within 10 % = tie, not lower); "
        "other cases listed beyond it",
        "verdict": tally(flags),
        "evidence": evidence,
        "counts": _counts(words, "term comparisons"),
        "beyond": [line for line, _ in beyond],
        "beyond_verdict": tally(beyond_flags),
    }


def _compare(a: float, b: float, tie: float) -> str:
    """'lower', 'tie' (within ``tie``) or 'higher': a against b."""
    if abs(a - b) <= tie:
        return "tie"
    return "lower" if a < b else "higher"


def claim_angles(results: dict) -> dict:
    """Claim 1b: the proposed method's grids have better included angles than MGNet's."""
    flags, evidence, notes, words = [], [], [], []
    for case in CASES:
        for preset in PRESETS:
            p = quality_rows(results, case, preset, ("pinn", "mgnet"))
            a, b = p[0], p[1]
            if not (a["seeds"] and b["seeds"]):
                continue
            mean = _compare(a["mean_max_angle"]["mean"], b["mean_max_angle"]["mean"], TIE_MEAN_DEG)
            worst = _compare(
                a["worst_max_angle"]["mean"], b["worst_max_angle"]["mean"], TIE_WORST_DEG
            )
            fold_ok = a["folded_cells"]["mean"] <= b["folded_cells"]["mean"]
            flags.extend([mean == "lower", worst == "lower" and fold_ok])
            words.extend([mean, worst if fold_ok else "higher"])
            dev_a, dev_b = a["boundary_deviation"]["mean"], b["boundary_deviation"]["mean"]
            evidence.append(
                f"{case}, {preset} preset: mean MaxIncludedAngle {_d(a['mean_max_angle']['mean'])}"
                f" vs {_d(b['mean_max_angle']['mean'])} ({mean}), worst "
                f"{_d(a['worst_max_angle']['mean'])} vs {_d(b['worst_max_angle']['mean'])} "
                f"({worst}), folded cells {a['folded_cells']['mean']:g} vs "
                f"{b['folded_cells']['mean']:g}, boundary deviation {_pct(dev_a)} vs "
                f"{_pct(dev_b)}"
            )
            if mean == "higher" and dev_b > 2 * dev_a and dev_b > 1e-3:
                notes.append(
                    f"{case}, {preset} preset: MGNet's grid misses the boundary by "
                    f"{dev_b / dev_a:.1f} times as much ({_pct(dev_b)} of the diagonal); "
                    "a grid that cuts across a curved boundary has squarer cells than one that "
                    "follows it, so its lower angles partly reflect a worse boundary fit"
                )
    return {
        "id": "angles",
        "short": "proposed beats MGNet in angles",
        "claim": "The proposed method's grids have better angles than MGNet's",
        "paper": "Fig. 6: mean MaxIncludedAngle 101.7 vs 103.1 deg, worst 161.4 vs 174 deg; "
        "Figs. 7-8: MGNet only slightly improves on the algebraic grid",
        "scope": "all three cases, both presets (two checks each: mean lower; worst lower "
        f"with no more folded cells; differences within {TIE_MEAN_DEG:g} deg (mean) "
        f"or {TIE_WORST_DEG:g} deg (worst) are ties, which do not count as lower); "
        "seed means where several seeds ran",
        "verdict": tally(flags),
        "evidence": evidence + notes,
        "counts": _counts(words, "checks"),
        "beyond": [],
        "beyond_verdict": "",
    }


def claim_pde(results: dict) -> dict:
    """Claim 2: the proposed method's grids are comparable to the PDE method's."""
    flags, evidence, notes = [], [], []
    for case in FOUR_METHOD_CASES:
        for preset in PRESETS:
            rows = {
                r["method"]: r for r in quality_rows(results, case, preset, ("pinn", "elliptic"))
            }
            a, b = rows["pinn"], rows["elliptic"]
            if not (a["seeds"] and b["seeds"]):
                continue
            dm = a["mean_max_angle"]["mean"] - b["mean_max_angle"]["mean"]
            dw = a["worst_max_angle"]["mean"] - b["worst_max_angle"]["mean"]
            folds = a["folded_cells"]["mean"] <= b["folded_cells"]["mean"]
            dev = a["boundary_deviation"]["mean"]
            fits = dev <= COMPARABLE_BOUNDARY
            ok = dm <= COMPARABLE_MEAN_DEG and dw <= COMPARABLE_WORST_DEG and folds and fits
            flags.append(ok)
            pde = "1000 sweeps from a zero interior" if preset == "paper" else "converged"
            evidence.append(
                f"{case}, {preset} preset (PDE: {pde}): mean {_d(a['mean_max_angle']['mean'])} vs "
                f"{_d(b['mean_max_angle']['mean'])} ({dm:+.1f}), worst "
                f"{_d(a['worst_max_angle']['mean'])} vs {_d(b['worst_max_angle']['mean'])} "
                f"({dw:+.1f}), folded {a['folded_cells']['mean']:g} vs "
                f"{b['folded_cells']['mean']:g}, boundary deviation {_pct(dev)} vs "
                f"{_pct(b['boundary_deviation']['mean'])}: "
                f"{'comparable' if ok else 'not comparable'}"
            )
            notes.append(
                f"{case}, {preset} preset: time to a grid {a['run_seconds']['mean']:.1f}"
                f" s (proposed, training included) vs {b['run_seconds']['mean']:.2f} s "
                "(PDE)"
            )
    return {
        "id": "pde",
        "short": "proposed comparable to the PDE method",
        "claim": "The proposed method is comparable to the PDE method",
        "paper": "Figs. 7-8, Fig. 2 geometry: 'comparable meshing results to the PDE method', "
        "the PDE method being expensive",
        "scope": f"fig2 and concave, both presets; comparable (or better) = mean "
        f"MaxIncludedAngle at most {COMPARABLE_MEAN_DEG:g} deg and worst at most "
        f"{COMPARABLE_WORST_DEG:g} deg above the PDE grid's, no more folded cells, "
        "boundary nodes within "
        f"{100 * COMPARABLE_BOUNDARY:g} % of the diagonal",
        "verdict": tally(flags),
        "evidence": evidence + notes,
        "counts": f"{sum(flags)} of {len(flags)} case/preset pairs comparable",
        "beyond": [],
        "beyond_verdict": "",
    }


def claim_architecture(results: dict, budget: Budget) -> dict:
    """Claim 3: deeper or wider networks are not always better (paper Fig. 9)."""
    data = sweep_data(results, budget)
    evidence, shapes = [], []
    for name, sweep in data.items():
        if name.startswith("_"):
            continue
        shape = sweep_shape(sweep["x"], sweep["losses"])
        shapes.append(shape["shape"])
        means = shape.get("means", {})
        listing = ", ".join(f"{x}: {_e(m)}" for x, m in means.items())
        what = {
            "clear": "a larger network is worse than a smaller one for every seed: "
            + ", ".join(f"{b} > {a}" for a, b in shape["clear_pairs"][:4]),
            "noise": "mean loss rises at "
            + ", ".join(f"{a} -> {b}" for a, b in shape["worse_steps"])
            + ", but within the seed ranges",
            "monotone": "mean loss falls at every step in size",
            "n/a": "too few successful runs",
        }[shape["shape"]]
        missing = [x for x, v in zip(sweep["x"], sweep["losses"]) if not v]
        gone = (
            f" No successful run at {', '.join(map(str, missing))} (see Failed runs), so "
            "that point is not judged."
            if missing
            else ""
        )
        smallest = min(means) if means else None
        worst_note = ""
        if smallest is not None and len(means) > 1:
            worst = max(means, key=means.get)
            verb = "is" if worst == smallest else "is not"
            worst_note = (
                f" The smallest size ({smallest}) {verb} the worst (worst mean at {worst})."
            )
        evidence.append(
            f"{name} ({sweep['fixed']}): best mean at {shape['best']}; {what}. "
            f"Mean final loss: {listing}.{gone}{worst_note}"
        )
    if shapes and all(s == "clear" for s in shapes):
        verdict = "supported"
    elif shapes and all(s == "monotone" for s in shapes):
        verdict = "contradicted"
    elif not shapes or "n/a" in shapes:
        verdict = "n/a"
    else:
        verdict = "mixed"
    return {
        "id": "architecture",
        "short": "deeper or wider is not always better",
        "claim": "Deeper or wider is not always better",
        "paper": "Fig. 9: one hidden layer is worst; more layers help up to a point, then "
        "hurt; neurons saturate at 30 per layer",
        "scope": f"{budget.sweep_case} case, {budget.sweep_preset} preset, "
        f"{len(budget.sweep_seeds)} seeds per point, {budget.sweep_adam_epochs} Adam "
        f"epochs + {budget.sweep_lbfgs_iterations} L-BFGS iterations; supported when "
        "both sweeps show a size that is worse than a smaller one for every seed",
        "verdict": verdict,
        "evidence": evidence,
        "counts": "; ".join(
            f"{n.split(') ')[1]}: {SHAPE_TEXT[sh]}"
            for n, sh in zip([k for k in data if not k.startswith("_")], shapes)
        ),
        "beyond": [],
        "beyond_verdict": "",
    }


def claim_tfi(results: dict) -> dict:
    """Beyond the three: the algebraic grid is the poorest of the four methods."""
    flags, evidence = [], []
    for case in FOUR_METHOD_CASES:
        for preset in PRESETS:
            rows = quality_rows(results, case, preset, ("pinn", "mgnet", "tfi", "elliptic"))
            rows = [r for r in rows if r["seeds"]]
            if len(rows) < 2:
                continue
            worst = max(rows, key=lambda r: r["mean_max_angle"]["mean"])
            flags.append(worst["method"] == "tfi")
            evidence.append(
                f"{case}, {preset} preset: highest mean MaxIncludedAngle is "
                f"{SHORT[worst['method']]} ({_d(worst['mean_max_angle']['mean'])}); "
                + ", ".join(f"{SHORT[r['method']]} {_d(r['mean_max_angle']['mean'])}" for r in rows)
            )
    return {
        "id": "tfi",
        "short": "the algebraic grid is the poorest",
        "claim": "(beyond the issue) The algebraic grid is the poorest",
        "paper": "Figs. 7-8: the algebraic method gives poorly shaped cells near the walls",
        "scope": "fig2 and concave, both presets; poorest = highest mean MaxIncludedAngle",
        "verdict": tally(flags),
        "evidence": evidence,
        "counts": f"TFI poorest in {sum(flags)} of {len(flags)}",
        "beyond": [],
        "beyond_verdict": "",
    }


def all_claims(results: dict, budget: Budget) -> list[dict]:
    return [
        claim_loss(results),
        claim_angles(results),
        claim_pde(results),
        claim_architecture(results, budget),
        claim_tfi(results),
    ]
