"""How a four-sided family model's grid is finished (docs/family.md, "The polish"): where the
member's own node optimisation starts, in which stages and when each stops, against the
member's own default grid, on channels drawn apart from the model's members.

Usage: ``.venv/bin/python benchmarks/family_polish.py MODEL.pt [--seeds 2 3 4] [--members 16]
[--workdir DIR]``

``MODEL.pt``: a model of ``example_data/make_families.py``'s ``channels`` (``pinn-mesh fit``,
as ``benchmarks/family.py`` writes it). For each seed, ``--members`` unseen channels of that
draw are meshed by their own default run and finished from the model's grid by each rule;
the table gives the largest excess of the finished grid's worst angle and mean over the
default grid's, and the median number of evaluations of the optimisation's objective (its
first row: the member's own run's); its last column, the quartiles of the evaluations over
every seed's members.
"""

from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

# (label, start: the model's grid, or the polish's own start (family.mesh.polish_start:
# where the model's grid ranks below the member's start, the best ranked of that start and
# its blends towards the model's grid; "leap": from a model's grid or a blend, a settled
# stage is followed by the last alone), the stages' temperatures (shares of QUALITY_TAU,
# quality_start.sharpened), at most 100 iterations a stage, Settle's window, worst, spare)
STAGES = (1.0, 1 / 2, 1 / 4, 1 / 8)  # the member's own run's (quality_start.SHARPENING)
RULES = (
    ("model's grid, 1 degree alone, settled (15)", "model", (1.0,), (15, 0.05, 0.25)),
    ("blended start, 1 degree alone, settled (15)", "blend", (1.0,), (15, 0.05, 0.25)),
    ("blended start, 1, 1/2, 1/4, 1/8, settled (15)", "blend", STAGES, (15, 0.05, 0.25)),
    ("blended start, 1, 1/2, 1/4, 1/8, settled (10)", "blend", STAGES, (10, 0.05, 0.25)),
    ("blended start, 1, 1/4, 1/8, settled (15)", "blend", (1.0, 1 / 4, 1 / 8), (15, 0.05, 0.25)),
    ("blended start, 1, 1/2, 1/8, settled (15)", "blend", (1.0, 1 / 2, 1 / 8), (15, 0.05, 0.25)),
    ("blended start, 1, 1/8, settled (15)", "blend", (1.0, 1 / 8), (15, 0.05, 0.25)),
    ("blended start, 2, 1/2, 1/8, settled (15)", "blend", (2.0, 1 / 2, 1 / 8), (15, 0.05, 0.25)),
    ("blended start, 2, 1/8, settled (15)", "blend", (2.0, 1 / 8), (15, 0.05, 0.25)),
    (
        "blended start, 2, 1/2, 1/8, settled (15), a settled stage leaps to 1/8",
        "leap",
        (2.0, 1 / 2, 1 / 8),
        (15, 0.05, 0.25),
    ),
)


OWN = "the member's own run (its start, its four stages)"  # its evaluations, for scale


def draw(workdir: Path, seed: int, members: int) -> Path:
    """``members`` unseen channels of draw ``seed`` (no training members)."""
    out = workdir / f"seed{seed}"
    make = [sys.executable, str(ROOT / "example_data" / "make_families.py"), str(out)]
    options = ["--family", "channels", "--train", "0", "--unseen", str(members)]
    subprocess.run([*make, *options, "--seed", str(seed)], check=True)
    return out / "channels"


def finish(model, member, rule, counted: list) -> np.ndarray:
    """The member's grid finished from the model's by ``rule`` (the user's coordinates)."""
    from pinn_engine.family.mesh import polish_start
    from pinn_engine.starts.quality_start import Ranking, Settle, best_candidate, sharpened

    _, start, shares, settle = rule
    grid, _ = model.predict(member)
    elliptic = model.base(member)
    ranking = Ranking.of(elliptic, (), member.boundary.diagonal)
    (begin, _), ranking = best_candidate(elliptic, member.base, ranking)
    share = 1.0
    if start != "model":
        grid, share = polish_start(ranking, begin, ranking.quality(begin), grid)
    counted.clear()
    leap = start == "leap" and share > 0
    done = sharpened(grid, ranking, model.polish, Settle(*settle), shares, leap)
    return member.frame.to_user(done)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("model", type=Path)
    parser.add_argument("--seeds", type=int, nargs="+", default=[2, 3, 4])
    parser.add_argument("--members", type=int, default=16)
    parser.add_argument("--workdir", type=Path, default=ROOT / "out" / "family_polish")
    args = parser.parse_args()
    import torch

    torch.set_num_threads(1)
    from family import rows_of, settings_and_geometry

    from pinn_engine import job
    from pinn_engine.quality import guard_figures
    from pinn_engine.starts import quality_start

    counted: list = []
    real = quality_start.quality_loss

    def counting(*args, **kwargs):
        counted.append(1)
        return real(*args, **kwargs)

    quality_start.quality_loss = counting
    model = job.load_family(args.model)
    table = {label: {} for label in (OWN, *(rule[0] for rule in RULES))}
    for seed in args.seeds:
        folder = draw(args.workdir.resolve(), seed, args.members)
        found = {label: [] for label in table}
        for row in rows_of(folder / "unseen.csv"):
            settings, geometry = settings_and_geometry(folder, row)
            counted.clear()
            own = job.run(settings, geometry).quality
            found[OWN].append((0.0, 0.0, len(counted)))
            member = job.family_member(settings, geometry)
            for rule in RULES:
                q = guard_figures(finish(model, member, rule, counted))
                found[rule[0]].append(
                    (
                        q["worst_max_angle"] - own["worst_max_angle"],
                        q["mean_max_angle"] - own["mean_max_angle"],
                        len(counted),
                    )
                )
        for label, rows in found.items():
            worst, mean, evaluations = zip(*rows)
            table[label][seed] = (max(worst), max(mean), evaluations)
    head = " | ".join(f"seed {s}: worst / mean - default (max), evaluations" for s in args.seeds)
    print(f"| rule | {head} | evaluations, all seeds (quartiles) |")
    print("|---" * (2 + len(args.seeds)) + "|")
    for label, by_seed in table.items():
        cells = " | ".join(
            f"{w:+.2f} / {m:+.2f}, {statistics.median(e):.0f}" for w, m, e in by_seed.values()
        )
        every = [n for _, _, e in by_seed.values() for n in e]
        quartiles = " / ".join(f"{q:.0f}" for q in statistics.quantiles(every, n=4))
        print(f"| {label} | {cells} | {quartiles} |")


if __name__ == "__main__":
    main()
