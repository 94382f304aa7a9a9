"""Pass rates on the hold-out hard shapes, next to the tuning set's.

Usage: ``.venv/bin/python benchmarks/holdout.py [--with-tuning] [--sizes 41x21 81x41]
[--shapes NAME ...] [--processes 2] [--out docs/holdout] [--from-json]``

``example_data/hard/`` is the set the code was tuned on; ``example_data/holdout/`` is drawn at
random from a fixed seed by ``example_data/make_holdout_shapes.py`` and nothing is tuned on it.
For each hold-out shape and size this meshes the converged elliptic grid (``--method
elliptic``), TFI (for the quality criteria's references), the default ``pinn``, ``pinn
--orthogonal bottom,top`` (walls) and ``pinn --objective quality``, and checks each pinn grid
with the criteria the tuning set's benchmarks use, imported from them, not rewritten:

* default pinn: the default's bounds, ``bench_hard.within`` (mean <= elliptic + 0.5, worst <=
  elliptic worst + 2, no more folded cells than the elliptic grid);
* walls: SPEC 7, ``orthogonal.spec7`` (grid lines within 2 degrees of normal at the bottom and
  top sides, no folded cell);
* quality objective: its bounds, ``bench_hard.item3`` (no folded cell, mean <= elliptic
  + 0.5, worst <= TFI's worst + 0.5, worst below the elliptic grid's or at the floor).

The meshing runs are ``bench_hard.run_shape`` and ``orthogonal.run`` themselves. The tuning
set's pass counts come from its pages (``docs/hard_shapes.json``, ``docs/orthogonal.md``,
``docs/hard_shapes_quality.json``, at their sizes 41x21 and 161x81) and, with
``--with-tuning``, from the same run at the hold-out's sizes. Runs go to a pool of
``--processes`` spawned workers, one torch thread each. Writes ``<out>.md`` and
``<out>.json`` (``--from-json`` rewrites the page from that json without running).
"""

from __future__ import annotations

import argparse
import json
import multiprocessing
import re
import sys
import time
import traceback
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))
import bench_hard  # noqa: E402
import orthogonal  # noqa: E402

HOLDOUT = ROOT / "example_data" / "holdout"
DOCS = ROOT / "docs"
SIZES = ("41x21", "81x41")  # the two sizes: the default lattice and twice it
RUNS = {  # bench_hard.run_shape's runs: the references first, then the two pinn objectives
    "tfi": ("tfi", {}),
    "elliptic": ("elliptic", {}),
    "pinn": ("pinn", {}),
    "pinn, quality": ("pinn", {"objective": "quality"}),
}
WALLS = "walls"  # orthogonal.CASES' bottom-and-top case
METHODS = {  # what the page calls each checked grid, and its criterion
    "pinn": "the default's bounds (`bench_hard.within`)",
    "walls": "SPEC 7, 2 degrees, no fold (`orthogonal.spec7`)",
    "quality": "the quality objective's bounds (`bench_hard.item3`)",
}
LABELS = {
    "pinn": "default `pinn`",
    "walls": "`pinn --orthogonal bottom,top`",
    "quality": "`pinn --objective quality`",
}
COMMAND = ".venv/bin/python benchmarks/holdout.py"


def holdout_shapes() -> list[str]:
    return sorted(p.stem for p in HOLDOUT.glob("*.vtp"))


def passes(record: dict) -> dict[str, bool]:
    """Each method's verdict on one shape and size, by the tuning benchmarks' own checks."""
    ell, tfi = record["elliptic"], record["tfi"]
    return {
        "pinn": bench_hard.within(record["pinn"], ell),
        "walls": orthogonal.spec7(record["walls"]),
        "quality": bench_hard.item3(record["quality"], ell, tfi, tfi["floor"]),
    }


def _init() -> None:
    import torch

    from pinn_engine.heap import tune_process

    torch.set_num_threads(1)
    tune_process()  # as the command line and bench_hard.py do


def measure(task: tuple[str, str, str]) -> dict:
    """All runs on one shape (of set ``holdout`` or ``tuning``) at one size."""
    which, name, size_text = task
    folder = HOLDOUT if which == "holdout" else bench_hard.HARD
    size = tuple(int(v) for v in size_text.split("x"))
    record = {"set": which, "shape": name, "size": size_text}
    start = time.perf_counter()
    try:
        rows = {r["method"]: r for r in bench_hard.run_shape(name, size, RUNS, folder)}
        record.update(tfi=rows["tfi"], elliptic=rows["elliptic"], pinn=rows["pinn"])
        record["quality"] = rows["pinn, quality"]
        record["walls"] = orthogonal.run(folder / f"{name}.vtp", size, WALLS, "pinn")
        record["pass"] = passes(record)
    except Exception:  # a run that raises fails every check; the page shows the error
        record["error"] = traceback.format_exc(limit=3)
        record["pass"] = dict.fromkeys(METHODS, False)
    record["seconds"] = time.perf_counter() - start
    return record


# --- the tuning set's counts from its pages ---


def tuning_from_pages() -> dict[str, dict]:
    """The tuning set's pass counts as its benchmark pages report them (sizes as there)."""
    hard = set(bench_hard.shapes())
    rows = json.loads((DOCS / "hard_shapes.json").read_text())["rows"]
    pinn = [r["within_bounds"] for r in rows if r["method"] == "pinn"]
    rows = json.loads((DOCS / "hard_shapes_quality.json").read_text())["rows"]
    quality = [r["item3"] for r in rows if r["method"] == "pinn, quality" and r["hard"]]
    walls, sizes = [], set()
    pattern = r"\| (\S+) \| (\d+x\d+) \| walls \| pinn \| ([\d.]+)(?: \*\*x\*\*)? \| (\d+) \|"
    for line in (DOCS / "orthogonal.md").read_text().splitlines():
        m = re.match(pattern, line)
        if m and m[1] in hard:
            walls.append(orthogonal.spec7({"deviation": float(m[3]), "folded": int(m[4])}))
            sizes.add(m[2])
    source = {
        "pinn": "docs/hard_shapes.json",
        "walls": "docs/orthogonal.md",
        "quality": "docs/hard_shapes_quality.json",
    }
    return {
        k: {"passed": sum(v), "total": len(v), "source": source[k]}
        for k, v in (("pinn", pinn), ("walls", walls), ("quality", quality))
    } | {"sizes": sorted(sizes, key=lambda s: int(s.split("x")[0]))}


# --- the page ---


def _count(records: list[dict], method: str) -> tuple[int, int]:
    return sum(r["pass"][method] for r in records), len(records)


def _frac(counts: tuple[int, int]) -> str:
    passed, total = counts
    return f"{passed} of {total}" + (f" ({100 * passed / total:.0f} %)" if total else "")


def _grid(r: dict) -> str:
    folded = r.get("folded_cells", r.get("folded"))
    mean = r.get("mean_max_angle", r.get("mean"))
    worst = r.get("worst_max_angle", r.get("worst"))
    return f"{mean:.2f} / {worst:.2f}" + (f", {folded} folded" if folded else "")


def failure_text(r: dict, method: str) -> str:
    """The figures of a failed check against each bound it has (the verdict is ``passes``')."""
    if "error" in r:
        return "error: " + r["error"].strip().splitlines()[-1]
    ell, tfi = r["elliptic"], r["tfi"]
    if method == "walls":
        w = r["walls"]
        return "; ".join(
            [
                _over(
                    f"off 90 {w['deviation']:.2f} (bound {orthogonal.TOL:g})",
                    w["deviation"] > orthogonal.TOL,
                ),
                _over(f"folded {w['folded']} (bound 0)", w["folded"] > 0)
                + f" (elliptic grid: {ell['folded_cells']})",
                f"mean / worst {w['mean']:.2f} / {w['worst']:.2f}",
            ]
        )
    q = r["pinn" if method == "pinn" else "quality"]
    mean, worst, folded = q["mean_max_angle"], q["worst_max_angle"], q["folded_cells"]
    mean_bound = ell["mean_max_angle"] + bench_hard.MEAN_BOUND
    parts = [_over(f"mean {mean:.2f} (bound {mean_bound:.2f})", mean > mean_bound)]
    if method == "pinn":
        worst_bound = ell["worst_max_angle"] + bench_hard.WORST_BOUND
        parts += [
            _over(f"worst {worst:.2f} (bound {worst_bound:.2f})", worst > worst_bound),
            _over(
                f"folded {folded} (elliptic {ell['folded_cells']})", folded > ell["folded_cells"]
            ),
        ]
    else:
        tfi_bound, floor = tfi["worst_max_angle"] + 0.5, tfi["floor"] + bench_hard.FLOOR_TOL
        parts += [
            _over(f"worst {worst:.2f} (bound TFI's + 0.5: {tfi_bound:.2f})", worst > tfi_bound),
            _over(
                f"worst below the elliptic grid's {ell['worst_max_angle']:.2f} or at the floor "
                f"{tfi['floor']:.2f}",
                worst >= ell["worst_max_angle"] and worst > floor,
            ),
            _over(f"folded {folded} (bound 0)", folded > 0)
            + f" (elliptic grid: {ell['folded_cells']}, TFI: {tfi['folded_cells']})",
        ]
    return "; ".join(parts)


def _over(text: str, broken: bool) -> str:
    """A bound's figures, in bold where the grid breaks it (for the reader; the verdict is
    ``passes``')."""
    return f"**{text}**" if broken else text


def _folds(records: list[dict], which: str) -> str:
    """Where the grids fold, and the default's closest approach to its mean and worst bounds:
    its bounds let the default fold where the elliptic grid folds as much."""
    rs = [r for r in records if "error" not in r]
    folding = {
        m: sum(r[m][k] > 0 for r in rs)
        for m, k in (
            ("elliptic", "folded_cells"),
            ("pinn", "folded_cells"),
            ("walls", "folded"),
            ("quality", "folded_cells"),
        )
    }
    mean_margin = min(
        r["elliptic"]["mean_max_angle"] + bench_hard.MEAN_BOUND - r["pinn"]["mean_max_angle"]
        for r in rs
    )
    worst_margin = min(
        r["elliptic"]["worst_max_angle"] + bench_hard.WORST_BOUND - r["pinn"]["worst_max_angle"]
        for r in rs
    )
    return (
        f"On the {which} set, grids with folded cells: elliptic {folding['elliptic']} of "
        f"{len(rs)}, default pinn {folding['pinn']} (its bounds allow a fold where the "
        f"elliptic grid has as many), walls {folding['walls']}, quality "
        f"{folding['quality']}. The default pinn's smallest margins to its bounds: "
        f"{mean_margin:.2f} degrees on the mean, {worst_margin:.2f} on the worst angle."
    )


def _family(name: str) -> str:
    return name.split("_")[1] if name.startswith("h") else "tuning"


NOTES = "## Stopping criteria and bounds"  # a hand-written section the page keeps


def kept_notes(page: Path) -> list[str]:
    """The lines of the hand-written section ``NOTES`` of an existing page (up to the next
    section), so that a rerun keeps it."""
    if not page.exists():
        return []
    lines = page.read_text().splitlines()
    if NOTES not in lines:
        return []
    start = lines.index(NOTES)
    end = next((k for k in range(start + 1, len(lines)) if lines[k].startswith("## ")), None)
    notes = lines[start:end]
    while notes and not notes[-1].strip():
        notes.pop()
    return notes + [""]


def markdown(
    records: list[dict],
    pages: dict,
    sizes: list[str],
    with_tuning: bool,
    notes: list[str] | None = None,
) -> str:
    hold = [r for r in records if r["set"] == "holdout"]
    tune = [r for r in records if r["set"] == "tuning"]
    n_shapes = len({r["shape"] for r in hold})
    size_text = " and ".join(s.replace("x", " x ") for s in sizes)
    page_sizes = " and ".join(s.replace("x", " x ") for s in pages["sizes"])
    command = COMMAND + (" --with-tuning" if with_tuning else "")
    lines = [
        "# Hold-out hard shapes: pass rates next to the tuning set's",
        "",
        "The benchmarks' pass rates on `example_data/hard/` are on the set the code was tuned "
        f"on. `example_data/holdout/` holds {n_shapes} hard four-sided shapes drawn at random "
        "by `example_data/make_holdout_shapes.py` (fixed seed, families: wavy walls, notches "
        "of V, rounded and rectangular form into and out of the domain, forward and backward "
        "steps sharp and smoothed, corners of 25 to 35 degrees on sheared quads, kites and "
        "darts, and combinations; `holdout/manifest.json` lists each shape's parameters). "
        "Nothing in `pinn_engine` was tuned on them, nor changed for this page.",
        "",
        f"Regenerate this page with `{command}` ({sum(r['seconds'] for r in records) / 60:.0f} "
        "min of runs, over a pool of 2 processes on 2 cores shared with other work; "
        "the shapes with `.venv/bin/python example_data/make_holdout_shapes.py`). "
        f"Each shape is meshed at {size_text} with the converged elliptic grid, TFI, the "
        "default `pinn`, `pinn --orthogonal bottom,top` and `pinn --objective quality`, "
        "through `bench_hard.run_shape` and `orthogonal.run`, and each pinn grid is checked "
        "with the tuning benchmarks' own functions: the default's bounds "
        "(`bench_hard.within`: mean <= elliptic + 0.5, worst <= elliptic worst + 2 degrees, "
        "no more folded cells than the elliptic grid), SPEC 7 for the walls "
        "(`orthogonal.spec7`: lines within 2 degrees of normal at the bottom and top, no "
        "fold), the quality objective's bounds (`bench_hard.item3`: no fold, "
        "mean <= elliptic + 0.5, worst <= TFI's worst + 0.5, worst below the elliptic "
        "grid's or at the floor the boundary nodes fix). Angles are VTK's Verdict quad "
        "`MaxIncludedAngle` in degrees.",
        "",
        "## Pass counts",
        "",
        "| method | criterion | hold-out, "
        + " | hold-out, ".join(s.replace("x", " x ") for s in sizes)
        + " | hold-out, all | "
        + (f"tuning set, this run ({size_text}) | " if with_tuning else "")
        + f"tuning set, its pages ({page_sizes}) |",
        "|" + "---|" * (len(sizes) + 4 + with_tuning),
    ]
    for method, criterion in METHODS.items():
        cells = [_frac(_count([r for r in hold if r["size"] == s], method)) for s in sizes]
        cells.append(f"**{_frac(_count(hold, method))}**")
        if with_tuning:
            cells.append(_frac(_count(tune, method)))
        page = pages[method]
        cells.append(f"{_frac((page['passed'], page['total']))} ({page['source']})")
        lines.append(f"| {LABELS[method]} | {criterion} | " + " | ".join(cells) + " |")
    lines += ["", _folds(hold, "hold-out")] + (["", _folds(tune, "tuning")] if with_tuning else [])
    lines += [
        "",
        "### Hold-out passes by family (both sizes)",
        "",
        "| family | grids | " + " | ".join(LABELS[m] for m in METHODS) + " |",
        "|" + "---|" * (len(METHODS) + 2),
    ]
    for family in sorted({_family(r["shape"]) for r in hold}):
        rs = [r for r in hold if _family(r["shape"]) == family]
        lines.append(
            f"| {family} | {len(rs)} | " + " | ".join(str(_count(rs, m)[0]) for m in METHODS) + " |"
        )
    failures = [(r, m) for r in hold for m in METHODS if not r["pass"][m]]
    lines += ["", "## Failures on the hold-out set", ""]
    if not failures:
        lines.append("None.")
    for r, m in failures:
        lines.append(f"- `{r['shape']}` {r['size']}, {LABELS[m]}: {failure_text(r, m)}")
    if with_tuning:
        tune_failures = [(r, m) for r in tune for m in METHODS if not r["pass"][m]]
        lines += ["", "## Failures on the tuning set in this run", ""]
        lines += [
            f"- `{r['shape']}` {r['size']}, {LABELS[m]}: {failure_text(r, m)}"
            for r, m in tune_failures
        ] or ["None."]
    lines += [""] + (notes or [])
    lines += [
        "## Every grid",
        "",
        "Mean / worst `MaxIncludedAngle` (folded cells if any); walls: degrees off 90 at the "
        "bottom and top, then mean / worst; the floor is `quality.angle_floor`'s, from the "
        "TFI run. **fails** marks a failed check.",
        "",
        "| set | shape | size | elliptic | tfi | pinn | walls | quality | floor |",
        "|" + "---|" * 9,
    ]
    for r in hold + tune:
        if "error" in r:
            lines.append(f"| {r['set']} | {r['shape']} | {r['size']} | error | | | | | |")
            continue
        mark = {m: "" if r["pass"][m] else " **fails**" for m in METHODS}
        w = r["walls"]
        lines.append(
            f"| {r['set']} | {r['shape']} | {r['size']} | {_grid(r['elliptic'])} | "
            f"{_grid(r['tfi'])} | {_grid(r['pinn'])}{mark['pinn']} | "
            f"{w['deviation']:.2f}; {_grid(w)}{mark['walls']} | "
            f"{_grid(r['quality'])}{mark['quality']} | {r['tfi']['floor']:.2f} |"
        )
    return "\n".join(lines) + "\n"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", nargs="+", default=list(SIZES))
    p.add_argument("--shapes", nargs="+", default=None, help="hold-out shape names")
    p.add_argument("--with-tuning", action="store_true", help="the tuning set in the same run")
    p.add_argument("--processes", type=int, default=2)
    p.add_argument("--out", default=str(DOCS / "holdout"))
    p.add_argument(
        "--from-json", action="store_true", help="rewrite <out>.md from <out>.json, no runs"
    )
    args = p.parse_args()
    out = Path(args.out)
    if args.from_json:
        data = json.loads(out.with_suffix(".json").read_text())
        tuning = any(r["set"] == "tuning" for r in data["records"])
        notes = kept_notes(out.with_suffix(".md"))
        md = markdown(data["records"], data["tuning_pages"], data["sizes"], tuning, notes)
        out.with_suffix(".md").write_text(md)
        print(f"wrote {out.with_suffix('.md')}")
        return
    names = args.shapes or holdout_shapes()
    sets = [("holdout", names)] + ([("tuning", bench_hard.shapes())] if args.with_tuning else [])
    # the larger sizes first, so that the pool does not end on one long run
    sizes = sorted(args.sizes, key=lambda s: -int(s.split("x")[0]))
    tasks = [(which, name, size) for size in sizes for which, ns in sets for name in ns]
    records = []
    start = time.perf_counter()
    context = multiprocessing.get_context("spawn")
    with context.Pool(args.processes, initializer=_init) as pool:
        for k, record in enumerate(pool.imap_unordered(measure, tasks), 1):
            records.append(record)
            verdict = " ".join(f"{m} {'ok' if v else 'FAILS'}" for m, v in record["pass"].items())
            print(
                f"[{k}/{len(tasks)} {time.perf_counter() - start:6.0f} s] {record['set']} "
                f"{record['shape']} {record['size']}: {verdict}"
                + (" (error)" if "error" in record else ""),
                flush=True,
            )
    order = {(t[0], t[1], t[2]): i for i, t in enumerate(sorted(tasks))}
    records.sort(key=lambda r: order[(r["set"], r["shape"], r["size"])])
    pages = tuning_from_pages()
    out.with_suffix(".json").write_text(
        json.dumps({"sizes": args.sizes, "tuning_pages": pages, "records": records}, indent=1)
    )
    notes = kept_notes(out.with_suffix(".md"))
    md = markdown(records, pages, args.sizes, args.with_tuning, notes)
    out.with_suffix(".md").write_text(md)
    for method in METHODS:
        hold = [r for r in records if r["set"] == "holdout"]
        print(f"{method}: hold-out {_frac(_count(hold, method))}")
    print(f"wrote {out.with_suffix('.md')} and {out.with_suffix('.json')}")


if __name__ == "__main__":
    main()
