"""Quality and run time of every method on every example case: the table of docs/quality.md.

Usage: ``.venv/bin/python -m experiments.compare [--quick] [--out results/comparison]``

For each case (with its auxiliary lines) and each method it prints mean and worst
``MaxIncludedAngle``, worst ``MinIncludedAngle``, folded cells, boundary deviation, run time
(training included), the largest distance of the grid line through each auxiliary line's
(xi, eta) from the drawn line (``auxlines.line_distances``, per line, relative to the
diagonal), and for the neural methods the mean angle of the converged elliptic grid on the
same boundary nodes, with the difference. "pinn, from TFI" is the default before the
elliptic warm start (``warm_start="none"``: TFI start, 5000 Adam epochs, 500 L-BFGS
iterations, the paper's residual and lambda2 = 10); the two "default but" runs change one
choice of the default back to the paper's. Writes ``<out>.json`` and
``<out>.md`` (the markdown table of docs/quality.md).
"""

from __future__ import annotations

import argparse
import json
import time
from pathlib import Path

from pinn_engine.classical.elliptic import winslow_solve
from pinn_engine.geometry.auxlines import line_distances
from pinn_engine.io.pipeline import load_aux, load_boundary
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.quality import cell_quality, summary
from pinn_engine.settings import NEURAL, make_settings

ROOT = Path(__file__).resolve().parents[1]
CASES = ("wavy", "fig2", "concave")
RUNS = (  # label, method, preset, overrides
    ("tfi", "tfi", "default", {}),
    ("elliptic, paper (1000 sweeps from 0)", "elliptic", "paper", {}),
    ("elliptic, converged", "elliptic", "default", {}),
    ("mgnet, paper", "mgnet", "paper", {}),
    ("mgnet, default", "mgnet", "default", {}),
    ("pinn, paper", "pinn", "paper", {}),
    ("pinn, from TFI (previous default)", "pinn", "default", {"warm_start": "none"}),
    ("pinn, default but lambda2 = 10", "pinn", "default", {"lambda2": 10.0}),
    ("pinn, default but the paper's residual", "pinn", "default", {"residual": "paper"}),
    ("pinn, default", "pinn", "default", {}),
)


def run_case(case: str, size: tuple[int, int], quick: bool) -> list[dict]:
    boundary = load_boundary(ROOT / "example_data" / f"{case}.vtp")
    aux = load_aux([ROOT / "example_data" / f"{case}_aux.vtp"], boundary)
    rows = []
    for label, method, preset, overrides in RUNS:
        budget = {"adam_epochs": 300, "lbfgs_iterations": 30} if quick else {}
        settings = make_settings(method, preset, lattice=size, **budget, **overrides)
        start = time.perf_counter()
        result = Mesher(settings).fit(boundary, aux).predict(*size, on_boundary=False)
        unit = boundary.frame.to_unit(result.points)
        row = {
            "case": case,
            "run": label,
            "seconds": time.perf_counter() - start,
            **result.quality,
            "aux_distance": list(line_distances(unit, aux, boundary.diagonal).values()),
        }
        if method in NEURAL:
            ref = winslow_solve(result.points)[0]
            row["elliptic_same_nodes_mean"] = summary(cell_quality(ref), 0.0)["mean_max_angle"]
            row["delta_mean"] = row["mean_max_angle"] - row["elliptic_same_nodes_mean"]
        rows.append(row)
        print(
            f"{case:8s} {label:38s} mean {row['mean_max_angle']:7.2f} worst "
            f"{row['worst_max_angle']:7.2f} folded {row['folded_cells']:3d} dev "
            f"{row['boundary_deviation']:.1e} {row['seconds']:7.1f} s aux "
            f"{' / '.join(f'{d:.4f}' for d in row['aux_distance'])}",
            flush=True,
        )
    return rows


def markdown(rows: list[dict]) -> str:
    lines = [
        "| case | method | mean MaxIncludedAngle | worst MaxIncludedAngle | worst "
        "MinIncludedAngle | folded | boundary dev. | time (s) | aux-line distance (per "
        "line) | Δ mean vs elliptic on same nodes |",
        "|" + "---|" * 10,
    ]
    for r in rows:
        delta = f"{r['delta_mean']:+.2f}" if "delta_mean" in r else ""
        lines.append(
            f"| {r['case']} | {r['run']} | {r['mean_max_angle']:.2f} | "
            f"{r['worst_max_angle']:.2f} | {r['worst_min_angle']:.2f} | "
            f"{r['folded_cells']} | {r['boundary_deviation']:.1e} | "
            f"{r['seconds']:.1f} | {' / '.join(f'{d:.4f}' for d in r['aux_distance'])} | "
            f"{delta} |"
        )
    return "\n".join(lines) + "\n"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true", help="300 Adam epochs, 30 L-BFGS")
    p.add_argument("--size", nargs=2, type=int, default=(41, 21))
    p.add_argument("--out", default=str(ROOT / "results" / "comparison"))
    args = p.parse_args()
    rows = [row for case in CASES for row in run_case(case, tuple(args.size), args.quick)]
    out = Path(args.out)
    out.parent.mkdir(parents=True, exist_ok=True)
    out.with_suffix(".json").write_text(json.dumps(rows, indent=2))
    out.with_suffix(".md").write_text(markdown(rows))
    print(f"\nwrote {out.with_suffix('.json')} and {out.with_suffix('.md')}")


if __name__ == "__main__":
    main()
