"""What the default pinn chooses on four-sided shapes, beside the converged elliptic grid
(docs/default_choice.md).

Usage: ``.venv/bin/python benchmarks/default_choice.py [--sizes 41x21] [--set tuning holdout]
[--train-lines] [--lines-only] [--slide-stretch 0.25] [--out docs/default_choice]
[--from-json [--load TEXT]]``

For each shape of the tuning set (``example_data/hard/``, and the examples with lines
``concave``, ``fig2``, ``wavy``) and the hold-out set (``example_data/holdout/``, nothing tuned
on it) this meshes the converged elliptic grid (``method elliptic``) and the default pinn
(``objective best``) on the same boundary nodes, without lines and, where the shape has some,
with its auxiliary lines; each shape also with one drawn line, straight and slanted, from 0.35
of its bottom side to 0.65 of its top (or, where that leaves the domain, from 0.65 of its left
side to 0.35 of its right; none where both do: ``drawn_line``). It prints mean and worst
``MaxIncludedAngle``, folded cells, the largest distance of a drawn line's grid line from it
(of the diagonal), how much the grid lines crossing a drawn line turn there
(``auxlines.crossing_turns``, the largest line's mean, both grids measured at the lines the
default follows: their (xi, eta) in the fit's parameter, SPEC 2, with the sides' sharp vertices
pinned to nodes), which grid the default chose, whether
it trained, and seconds (fit plus grid, one process). Writes ``<out>.json`` and ``<out>.md``
(``--from-json``: the page again from the json). The target: worst at least ``GAIN`` degrees
below the elliptic grid's on most shapes, never more than ``MEAN_TOL`` above it, mean never
more than ``MEAN_TOL`` above; with lines, every line within ``LINE_TOL`` of the diagonal and
the crossing lines turning at most ``TURN_TOL`` more than the elliptic grid's.

``--train-lines`` also trains the quality objective's network from its start on the shapes
with lines (what ``kinds.untrained.cannot_win`` skips), and says whether its guard kept a
trained state (``network``) or the start, and the seconds spent: the rule's measurement.
"""

from __future__ import annotations

import argparse
import json
import os
import time
from pathlib import Path

import numpy as np

from pinn_engine.classical.pins import pinned_lines
from pinn_engine.errors import InputError
from pinn_engine.geometry.auxlines import RawLine, crossing_turns, map_lines
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.io.pipeline import load_aux, load_boundary
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.settings import make_settings
from pinn_engine.starts import quality_start

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "example_data"
SETS = {
    "tuning": sorted((DATA / "hard").glob("*.vtp"))
    + [DATA / f"{name}.vtp" for name in ("concave", "fig2", "wavy")],
    "holdout": sorted((DATA / "holdout").glob("h*.vtp")),
}
GAIN = 5.0  # degrees: the worst cell's drop below the elliptic grid's that counts as a gain
MEAN_TOL = 0.5  # degrees: the most the mean (and the worst) may be above the elliptic grid's
LINE_TOL = 2e-3  # of the diagonal: the farthest a drawn line's grid line may be from it
TURN_TOL = 2.0  # degrees: the most the crossing lines may turn beyond the elliptic grid's
# The shapes' drawn line: from a fraction of one side to another of the opposite
# side (slanted, so that no symmetry follows it), each pair tried in turn
DRAWN = (("bottom", 0.35, "top", 0.65), ("left", 0.65, "right", 0.35))
DRAWN_POINTS = 21  # points of the drawn line


def shapes(name: str) -> list[tuple[Path, list[list[Path] | str]]]:
    """The boundaries of set ``name``, each with the lines it is meshed with besides none: its
    auxiliary-line files where it has some, and ``"drawn"`` (:func:`drawn_line`) where that
    stays inside it."""
    found = []
    for path in SETS[name]:
        if path.stem.endswith("_aux"):
            continue
        aux = path.with_name(f"{path.stem}_aux.vtp")
        variants: list[list[Path] | str] = [[aux]] if aux.exists() else []
        if drawn_line(load_boundary(path)):
            variants.append("drawn")
        found.append((path, variants))
    return found


def drawn_line(boundary: Boundary) -> list:
    """The first of ``DRAWN``'s straight lines that stays inside ``boundary`` (mapped,
    SPEC 2), in a list; empty if none does."""
    for first, t0, second, t1 in DRAWN:
        a = boundary.side(first).at(np.array([t0]))[0]
        b = boundary.side(second).at(np.array([t1]))[0]
        unit = a + np.linspace(0.0, 1.0, DRAWN_POINTS)[:, None] * (b - a)
        raw = RawLine(boundary.plane.lift(boundary.frame.to_user(unit)), None, f"{first} line")
        try:
            return map_lines([raw], boundary)
        except InputError:
            continue
    return []


def lines_of(boundary: Boundary, aux: list[Path] | str) -> list:
    """The auxiliary lines of files ``aux``, or ``"drawn"``: :func:`drawn_line`'s."""
    return drawn_line(boundary) if aux == "drawn" else load_aux(aux, boundary)


def mesh(method: str, path: Path, aux: list[Path] | str, size: tuple[int, int], **options) -> dict:
    """One grid's figures: quality, lines' distance, what was chosen, seconds."""
    boundary = load_boundary(path)
    lines = lines_of(boundary, aux)
    began = time.perf_counter()
    settings = make_settings(method, lattice=size, size=size, **options)
    mesher = Mesher(settings).fit(boundary, lines)
    result = mesher.predict(*size)
    seconds = time.perf_counter() - began
    report = result.report
    training = report.get("training", {})
    # the lines' (xi, eta) in the fit's parameter (SPEC 2), the sides' sharp vertices pinned
    # to nodes as every method's grid pins them: the lines the default follows
    pinned = pinned_lines(lines, mesher.boundary_)
    turns = crossing_turns(boundary.frame.to_unit(result.points), pinned)
    return {
        "mean": report["quality"]["mean_max_angle"],
        "worst": report["quality"]["worst_max_angle"],
        "folded": report["quality"]["folded_cells"],
        "lines": max(report["aux_line_distance"].values(), default=0.0),
        "turn": max(turns.values(), default=0.0),
        "chosen": training.get("start", method),
        "network": training.get("result") == "network",
        "trained": bool(training) and not training.get("skipped"),
        "train_seconds": report["train_seconds"],
        "seconds": seconds,
    }


def trained_lines(path: Path, aux: list[Path] | str, size: tuple[int, int]) -> dict:
    """The quality objective's network trained from its start with the lines (the run the
    default skips): whether the guard kept a trained state, and the training's seconds."""
    from pinn_engine.kinds.four_sided.problem import train

    boundary = load_boundary(path)
    lines = lines_of(boundary, aux)
    settings = make_settings("pinn", lattice=size, size=size, objective="quality")
    began = time.perf_counter()
    model = train(boundary, lines, settings, None)
    kept = model.info["result"]
    return {"kept": kept, "seconds": time.perf_counter() - began}


def run_row(name: str, path: Path, aux: list[Path] | str, size_text: str, train: bool) -> dict:
    """The elliptic grid and the default on one shape (with the lines ``aux``), printed."""
    size = tuple(int(n) for n in size_text.split("x"))
    row = {
        "set": name,
        "shape": path.stem,
        "size": size_text,
        "lines": bool(aux),
        "drawn": aux == "drawn",
    }
    row["elliptic"] = mesh("elliptic", path, aux, size)
    row["default"] = mesh("pinn", path, aux, size)
    if train and aux:
        row["trained"] = trained_lines(path, aux, size)
    e, d = row["elliptic"], row["default"]
    print(
        f"{name:8s} {path.stem + label(row):34s} {size_text:7s} elliptic "
        f"{e['mean']:7.2f} / {e['worst']:7.2f} ({e['folded']}) {e['lines']:.5f} "
        f"turn {e['turn']:5.2f} | default "
        f"{d['mean']:7.2f} / {d['worst']:7.2f} ({d['folded']}) {d['lines']:.5f} "
        f"turn {d['turn']:5.2f} "
        f"{'network' if d['network'] else d['chosen']:22s} "
        f"trained {d['trained']!s:5s} {d['train_seconds']:.2f} s, "
        f"{d['seconds']:.2f} s (elliptic {e['seconds']:.2f} s)"
        + (
            f" | trained: {row['trained']['kept']} {row['trained']['seconds']:.2f} s"
            if "trained" in row
            else ""
        ),
        flush=True,
    )
    return row


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sizes", nargs="+", default=["41x21"])
    parser.add_argument("--set", nargs="+", default=["tuning", "holdout"], dest="sets")
    parser.add_argument("--train-lines", action="store_true")
    parser.add_argument("--lines-only", action="store_true", help="only the grids with lines")
    parser.add_argument("--out", default=None)
    parser.add_argument("--from-json", action="store_true", help="rewrite the page from <out>.json")
    parser.add_argument("--load", help="with --from-json: the load average its run met")
    parser.add_argument(
        "--slide-stretch",
        type=float,
        help="quality_start.SLIDE_STRETCH for this run (its tuning, on the tuning set)",
    )
    args = parser.parse_args()
    if args.slide_stretch is not None:
        quality_start.SLIDE_STRETCH = args.slide_stretch
    before = os.getloadavg()[0]
    rows = []
    if args.from_json:
        rows = json.loads(Path(args.out).with_suffix(".json").read_text())
    for name in args.sets if not args.from_json else ():
        for size_text in args.sizes:
            for path, variants in shapes(name):
                for lines in ([] if args.lines_only else [[]]) + variants:
                    rows.append(run_row(name, path, lines, size_text, args.train_lines))
    summaries = [summary(rows, name) for name in args.sets]
    summaries += [s for n in args.sets for d in (False, True) if (s := lines_summary(rows, n, d))]
    print("\n".join(summaries))
    if args.out:
        out = Path(args.out)
        out.with_suffix(".json").write_text(json.dumps(rows, indent=1))
        load = args.load or (
            "not recorded"
            if args.from_json
            else f"{before:.1f} before, {os.getloadavg()[0]:.1f} after"
        )
        out.with_suffix(".md").write_text(page(rows, summaries, load))


def summary(rows: list[dict], name: str) -> str:
    """The target's counts on set ``name``'s grids without lines."""
    plain = [r for r in rows if r["set"] == name and not r["lines"]]
    gains = sum(r["default"]["worst"] <= r["elliptic"]["worst"] - GAIN for r in plain)
    worse = sum(r["default"]["worst"] > r["elliptic"]["worst"] + MEAN_TOL for r in plain)
    mean = sum(r["default"]["mean"] > r["elliptic"]["mean"] + MEAN_TOL for r in plain)
    folds = sum(r["default"]["folded"] > 0 for r in plain)
    return (
        f"{name}: {len(plain)} grids without lines: worst >= {GAIN} below elliptic on "
        f"{gains}, worst > {MEAN_TOL} above on {worse}, mean > {MEAN_TOL} above on {mean}, "
        f"folded on {folds}"
    )


def label(row: dict) -> str:
    """What a row's shape is meshed with: nothing, its own lines, or the drawn line."""
    if not row["lines"]:
        return ""
    return " + drawn line" if row.get("drawn", row["set"] == "holdout") else " + lines"


def lines_summary(rows: list[dict], name: str, with_drawn: bool) -> str:
    """The target's counts on set ``name``'s grids with their own lines, or (``with_drawn``)
    with :func:`drawn_line`'s; empty where there are none."""
    drawn = [
        r
        for r in rows
        if r["set"] == name and r["lines"] and label(r).endswith("drawn line") == with_drawn
    ]
    if not drawn:
        return ""
    near = sum(r["default"]["lines"] <= LINE_TOL for r in drawn)
    turn = sum(r["default"]["turn"] > r["elliptic"]["turn"] + TURN_TOL for r in drawn)
    folds = sum(r["default"]["folded"] > 0 for r in drawn)
    return (
        f"{name}: {len(drawn)} grids with {'a drawn line' if with_drawn else 'their lines'}: "
        f"lines within {LINE_TOL:g} of the diagonal on "
        f"{near}, crossing turn > {TURN_TOL} beyond elliptic's on {turn}, folded on {folds}"
    )


def page(rows: list[dict], summaries: list[str], load: str) -> str:
    """docs/default_choice.md: the summaries, then one row a grid."""
    lines = [
        "# What the default chooses, beside the elliptic grid",
        "",
        "Made by `.venv/bin/python benchmarks/default_choice.py --sizes 41x21 81x41 --out "
        "docs/default_choice` (its docstring says what it runs; each shape is also "
        "meshed with one drawn line, straight and slanted, from 0.35 of its bottom side to "
        "0.65 of its top, or from 0.65 of its left side to 0.35 of its right where that "
        "leaves the domain). Each grid: mean / worst "
        "`MaxIncludedAngle` (degrees), folded cells in brackets; the largest distance of a "
        "drawn line's grid line from it, of the diagonal; the turn of the grid lines crossing a "
        "drawn line at their node nearest it (degrees, mean over them, the largest line's; both "
        "grids at the (xi, eta) the default follows, the sides' sharp vertices pinned to "
        "nodes); "
        "the grid the default returned "
        "(`optimized`: the quality objective's node-optimised grid); seconds of fit plus grid "
        f"in one process (2 cores shared with other sessions; load average {load}).",
        "",
        *[f"- {s}" for s in summaries],
        "",
        "| set | shape | size | elliptic | default | lines' distance | crossing turn "
        "(elliptic / default) | chosen | "
        "trained | seconds (elliptic / default) |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        e, d = r["elliptic"], r["default"]
        chosen = "network" if d["network"] else d["chosen"]
        lines.append(
            f"| {r['set']} | {r['shape']}{label(r)} | {r['size']} | "
            f"{e['mean']:.2f} / {e['worst']:.2f} ({e['folded']}) | "
            f"{d['mean']:.2f} / {d['worst']:.2f} ({d['folded']}) | "
            f"{d['lines']:.5f} | {e.get('turn', 0.0):.2f} / {d.get('turn', 0.0):.2f} | {chosen} | "
            f"{'yes' if d['trained'] else 'no'} | {e['seconds']:.2f} / {d['seconds']:.2f} |"
        )
    return "\n".join(lines) + "\n"


if __name__ == "__main__":
    main()
