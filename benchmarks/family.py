"""Family models (SPEC 16, docs/family.md): fit time, time a member and quality on unseen
members against their own default grids and the elliptic grids.

Usage: ``.venv/bin/python benchmarks/family.py [--out docs/family.md] [--workdir DIR]
[--family channels naca] [--repeat N] [--batches N] [--subsets 6 12] [--stages]
[--section NAME]`` (``--section``: the markers in ``--out`` the tables go between, ``family
benchmark`` by default; the cylinder family's are ``family benchmark cylinder``)

For each family of ``example_data/make_families.py`` (24 training members, 8 unseen members
from the same ranges, 8 from ranges 25 % wider on each side):

- ``pinn-mesh fit train.csv --workers 2``: its wall time, the members' default grids' and
  the model's;
- in this process (warm, set up as a batch worker sets itself up: one BLAS thread, glibc's
  heap tuned; without them a member's default run takes more CPU time than in a worker,
  and the in-process ratios look better than the batch's): each unseen member's default grid,
  elliptic grid and family grid, their times (the median of ``--repeat``, 3) and figures;
  the family grid must have no fold, the default grid's boundary nodes, the worst cell
  within 2 degrees and the mean within 0.5 of the default grid's;
- ``pinn-mesh batch --workers 1`` over the unseen members with and without ``--model``: the
  median of the summary's seconds a member; with ``--batches N`` the pair N times in turn
  (the machine's load drifts between two batches), each pair's ratio and their median;
- the models fitted on the first 6 and 12 training members (``--subsets``; targets
  recomputed): the worst-cell excess on the unseen members, and the wider members;
- with ``--stages``, the CPU seconds a member, default and ``--model`` cases in turn
  (``--repeat`` times), each case as a batch worker runs it (``batch.task.run_case``:
  reading, the run, writing) and the ratio of their medians; of a body's run the layout (and
  its march off the wall), the elliptic grid and the member's own optimisation and choice;
  and for an O-grid family how far the family's linear map (``network.fit_linear`` on the
  boundary encoding) predicts the far-field nodes' angles, which the march places, on the
  unseen members.

It prints the tables and writes them between the markers of ``--out``.
"""

from __future__ import annotations

import argparse
import csv
import functools
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
PINN = str(ROOT / ".venv" / "bin" / "pinn-mesh")
SECTION = "family benchmark"  # the markers the tables go between (--section)
REPEAT = 3  # timings a member: the median (--repeat)
BATCHES = 1  # pairs of batches, default and --model in turn (--batches)
SUBSETS = (6, 12)  # training members of the smaller models (--subsets)


def generate(workdir: Path, family: str) -> tuple[Path, Path]:
    """The family's members (seed 0) and the wider unseen members (seed 1)."""
    make = [sys.executable, str(ROOT / "example_data" / "make_families.py")]
    subprocess.run([*make, str(workdir / "same"), "--family", family], check=True)
    subprocess.run(
        [*make, str(workdir / "wide"), "--family", family, "--train", "0", "--seed", "1", "--wide"],
        check=True,
    )
    return workdir / "same" / family, workdir / "wide" / family


def rows_of(manifest: Path) -> list[dict]:
    with manifest.open() as f:
        return list(csv.DictReader(f))


def settings_and_geometry(folder: Path, row: dict, method: str = "pinn"):
    """A member's settings and geometry as the command line makes them."""
    from pinn_engine.batch.manifest import parse_case
    from pinn_engine.batch.members import member_inputs

    case = parse_case(row["name"], row["input"], [], row["options"], folder, row["name"])
    case.args.method = method
    return member_inputs(case.args)


def timed(run, *args, repeat: int = REPEAT, **kwargs) -> tuple[object, float]:
    """``run(*args, **kwargs)``'s result and its median time over ``repeat`` runs."""
    times, out = [], None
    for _ in range(repeat):
        began = time.perf_counter()
        out = run(*args, **kwargs)
        times.append(time.perf_counter() - began)
    return out, statistics.median(times)


def boundary_and_seam(a: np.ndarray, b: np.ndarray, topology: str) -> tuple[float, float]:
    """The largest difference of two grids' nodes on the domain's boundary (a four-sided
    grid's four sides; a body's wall and far field, and a C-grid's outflow columns) and on
    an O-grid's seam (its columns 0 and ni - 1: interior nodes of the cut; 0 otherwise)."""
    rows = [np.s_[0], np.s_[-1]]
    columns = [np.s_[:, 0], np.s_[:, -1]]
    sides = rows if topology == "o" else rows + columns
    boundary = max(float(np.abs(a[s] - b[s]).max()) for s in sides)
    seam = max(float(np.abs(a[s] - b[s]).max()) for s in columns) if topology == "o" else 0.0
    return boundary, seam


def rings_nodes(own, fam, geometry) -> tuple[float, float]:
    """A multi-block member's largest node difference between its own and its family grid on
    its holes (the cylinder: nodes its run places as drawn) and on its outer boundary (where
    the edge ends slide along straight walls, the family's ends the model's)."""
    from pinn_engine.geometry.boundary import segment_distance

    a = np.vstack([g.reshape(-1, 2) for g in own.grids])
    b = np.vstack([g.reshape(-1, 2) for g in fam.grids])
    size = float(np.ptp(geometry.rings[0], axis=0).max())
    out = []
    for rings in (geometry.rings[1:], geometry.rings[:1]):
        near = np.min([segment_distance(a, ring) for ring in rings], axis=0) < 1e-9 * size
        out.append(float(np.abs(a[near] - b[near]).max()) if near.any() else 0.0)
    return out[0], out[1]


def outcome_of(report: dict) -> tuple[str, bool]:
    """A family run's result (``family`` or ``start``) and whether the member's own start was
    solved (a multi-block member's: where it fell back)."""
    if "family" in report:
        return report["family"]["result"], report["family"]["result"] == "start"
    return report["training"]["result"], bool(report["training"]["start_solved"])


def compare(folder: Path, rows: list[dict], model, repeat: int = REPEAT) -> list[dict]:
    """Each member's default, elliptic and family grids: times (the median of ``repeat``)
    and figures."""
    from pinn_engine import job

    out = []
    for row in rows:
        settings, geometry = settings_and_geometry(folder, row)
        e_settings, e_geometry = settings_and_geometry(folder, row, "elliptic")
        own, t_own = timed(job.run, settings, geometry, repeat=repeat)
        ell, t_ell = timed(job.run, e_settings, e_geometry, repeat=repeat)
        fam, t_fam = timed(job.run, settings, geometry, family=model, repeat=repeat)
        if len(own.grids) > 1:  # multi-block: the holes' nodes, and the outer boundary's
            boundary, seam = rings_nodes(own, fam, geometry)
        else:
            boundary, seam = boundary_and_seam(own.grids[0], fam.grids[0], settings.topology)
        q, d, e = fam.quality, own.quality, ell.quality
        result, start_solved = outcome_of(fam.report)
        out.append(
            {
                "name": row["name"],
                "t_default": t_own,
                "t_elliptic": t_ell,
                "t_family": t_fam,
                "worst_excess": q["worst_max_angle"] - d["worst_max_angle"],
                "mean_excess": q["mean_max_angle"] - d["mean_max_angle"],
                "worst_vs_elliptic": q["worst_max_angle"] - e["worst_max_angle"],
                "mean_vs_elliptic": q["mean_max_angle"] - e["mean_max_angle"],
                "folds": q["folded_cells"],
                "boundary": boundary,
                "seam": seam,
                "result": result,
                "start_solved": start_solved,
                "steps": (
                    own.report.get("iterations"),
                    fam.report.get("family", {}).get("solve_steps"),
                ),
            }
        )
    return out


def model_manifest(folder: Path, manifest: Path, model: Path) -> Path:
    """``manifest`` with ``--model`` in every case's options, as ``unseen_model.csv``."""
    rows = rows_of(manifest)
    out = folder / "unseen_model.csv"
    with out.open("w", newline="") as f:
        w = csv.DictWriter(f, ["name", "input", "aux", "options"])
        w.writeheader()
        for row in rows:
            w.writerow({**row, "options": f"{row['options']} --model {model}"})
    return out


def batch_median(folder: Path, manifest: Path, outdir: Path, model: Path | None) -> float:
    """The median seconds a member of ``pinn-mesh batch --workers 1`` (with ``--model``);
    the summary stays in ``outdir``."""
    if model is not None:
        manifest = model_manifest(folder, manifest, model)
    subprocess.run(
        [PINN, "batch", str(manifest), "-o", str(outdir), "--workers", "1", "--force"],
        check=True,
        capture_output=True,
    )
    return statistics.median(float(r["seconds"]) for r in rows_of(outdir / "summary.csv"))


def subset_errors(folder: Path, wide: Path, n: int) -> dict:
    """A model fitted on the first ``n`` training members: its grids' largest worst-cell
    excess over the default grid on the unseen and the wider members."""
    from pinn_engine import job

    members, targets = [], []
    for row in rows_of(folder / "train.csv")[:n]:
        settings, geometry = settings_and_geometry(folder, row)
        outcome, member = job.member_run(settings, geometry)
        members.append(member)
        targets.append(job.member_target(member, outcome))
    model = job.fit_family_model(members, targets)
    out = {}
    for name, where in (("unseen", folder), ("wide", wide)):
        excess, fallbacks = [], 0
        for row in rows_of(where / "unseen.csv"):
            settings, geometry = settings_and_geometry(where, row)
            own = job.run(settings, geometry)
            fam = job.run(settings, geometry, family=model)
            excess.append(fam.quality["worst_max_angle"] - own.quality["worst_max_angle"])
            fallbacks += outcome_of(fam.report)[0] == "start"
        out[name] = (max(excess), fallbacks)
    return out


STAGES = (  # (module, function, name) whose CPU time --stages adds up
    ("pinn_engine.job", "run", "run"),
    ("pinn_engine.bodies.bodygrid", "layout", "layout"),
    ("pinn_engine.bodies.bodygrid", "march", "march"),
    ("pinn_engine.bodies.bodygrid", "elliptic", "elliptic"),
    ("pinn_engine.starts.quality_start", "body_quality_start", "optimisation"),
    ("pinn_engine.multiblock.mesh", "winslow", "multi-block solve"),
)


def _cpu_timer(f, key: str, spent: dict[str, float]):
    """``f``, adding its CPU seconds to ``spent[key]``."""

    @functools.wraps(f)
    def timed_stage(*args, **kwargs):
        began = time.process_time()
        try:
            return f(*args, **kwargs)
        finally:
            spent[key] = spent.get(key, 0.0) + time.process_time() - began

    return timed_stage


def stages(folder: Path, model: Path, repeat: int = REPEAT) -> list[str]:
    """The CPU seconds a member (median) of each unseen member's case as a batch worker
    runs it (``batch.task.run_case``: reading, the run, writing, its summary row), default
    and ``--model`` in turn, and of their ``STAGES``; and the ratio of the medians."""
    import importlib

    from pinn_engine.batch.manifest import read_manifest
    from pinn_engine.batch.task import prepared, run_case

    spent: dict[str, float] = {}
    real = []
    for module, name, key in STAGES:
        mod = importlib.import_module(module)
        real.append((mod, name, getattr(mod, name)))
        setattr(mod, name, _cpu_timer(real[-1][2], key, spent))
    routes = {
        "default": read_manifest(folder / "unseen.csv"),
        "--model": read_manifest(model_manifest(folder, folder / "unseen.csv", model)),
    }
    got: dict[str, dict[str, list[float]]] = {label: {} for label in routes}
    try:
        for cases in routes.values():  # the model's loading and each route's first case
            run_case(cases[0].name, prepared(cases[0], folder / "stages"))
        for _ in range(repeat):
            for k in range(len(routes["default"])):
                for label, cases in routes.items():
                    spent.clear()
                    began = time.process_time()
                    row = run_case(cases[k].name, prepared(cases[k], folder / "stages"))
                    spent["case"] = time.process_time() - began
                    assert row["status"] == "ok", row
                    for key, value in spent.items():
                        got[label].setdefault(key, []).append(value)
    finally:
        for mod, name, f in real:
            setattr(mod, name, f)
    keys = ("case", *(key for _, _, key in STAGES))
    lines = ["| route | " + " | ".join(keys) + " |", "|---" * (len(keys) + 1) + "|"]
    for label, times in got.items():
        cells = [f"{statistics.median(times[k]):.3f}" if k in times else "-" for k in keys]
        lines.append(f"| {label} | " + " | ".join(cells) + " |")
    case = {label: statistics.median(times["case"]) for label, times in got.items()}
    lines += ["", f"CPU ratio of the median cases: {case['--model'] / case['default']:.2f}."]
    return lines


def far_field_error(folder: Path, wide: Path) -> str:
    """The largest error of the far-field nodes' angles about the far field's centre (the
    family frame's origin) predicted from the training members' boundary encoding by the
    family's linear map, on the unseen and the wider members: in radians and in chords."""
    from pinn_engine import job
    from pinn_engine.family.encoding import Encoding, boundary_vector
    from pinn_engine.family.network import fit_linear, forward

    def members(where: Path, manifest: str) -> list:
        out = []
        for row in rows_of(where / manifest):
            settings, geometry = settings_and_geometry(where, row, "elliptic")
            member = job.family_member(settings, geometry)
            far = member.base[-1]
            angle = np.unwrap(np.arctan2(far[:, 1], far[:, 0]))
            out.append((boundary_vector(member.base, "body"), angle, np.hypot(*far[0])))
        return out

    train = members(folder, "train.csv")
    encoding = Encoding.fit(np.array([v for v, _, _ in train]))
    mean = np.mean([a for _, a, _ in train], axis=0)
    z = np.array([encoding.encode(v) for v, _, _ in train])
    params, _ = fit_linear(z, np.array([a for _, a, _ in train]) - mean)
    errors = []
    for where in (folder, wide):
        for v, angle, radius in members(where, "unseen.csv"):
            miss = float(np.abs(forward(params, encoding.clamped(v)) + mean - angle).max())
            errors.append((miss, miss * radius))
    return (
        f"Far-field nodes' angles by the linear map on the boundary encoding ({len(train)} "
        f"members): each of the {len(errors)} unseen members' largest error "
        f"{min(e for e, _ in errors):.1e} to {max(e for e, _ in errors):.1e} radians "
        f"({min(c for _, c in errors):.2g} to {max(c for _, c in errors):.2g} chords)."
    )


def run_family(
    family: str,
    workdir: Path,
    repeat: int = REPEAT,
    subsets: tuple[int, ...] = SUBSETS,
    batches: int = BATCHES,
    with_stages: bool = False,
) -> list[str]:
    folder, wide = generate(workdir, family)
    model = workdir / f"{family}.pt"
    began = time.perf_counter()
    fit = subprocess.run(
        [PINN, "fit", str(folder / "train.csv"), "-o", str(model), "--workers", "2"],
        check=True,
        capture_output=True,
        text=True,
    )
    wall = time.perf_counter() - began
    print(fit.stdout.strip())
    from pinn_engine import job

    loaded = job.load_family(model)
    unseen = compare(folder, rows_of(folder / "unseen.csv"), loaded, repeat)
    wider = compare(wide, rows_of(wide / "unseen.csv"), loaded, repeat)
    pairs = []
    for _ in range(batches):
        b_default = batch_median(folder, folder / "unseen.csv", workdir / "b_default", None)
        b_family = batch_median(folder, folder / "unseen.csv", workdir / "b_family", model)
        pairs.append((b_default, b_family, os.getloadavg()[0]))
    b_default, b_family, _ = pairs[-1]
    ratios = [f / d for d, f, _ in pairs]
    own = {r["name"]: r for r in rows_of(workdir / "b_default" / "summary.csv")}
    by_model = rows_of(workdir / "b_family" / "summary.csv")
    excess = [
        [float(r[k]) - float(own[r["name"]][k]) for k in ("worst_max_angle", "mean_max_angle")]
        for r in by_model
    ]
    worst_excess, mean_excess = (max(x) for x in zip(*excess))
    r = loaded.report
    blocks = r["kind"] == "blocks"
    # a blocking named by its blocks and cells alone: a hex digest in a page looks like history
    counts = r["topology"].split(", blocking")[0] if blocks else f"{r['size'][0]} x {r['size'][1]}"
    nodes = (
        "cylinder nodes (max diff) | channel's sides, beside sliding ends (max diff)"
        if blocks
        else "boundary nodes (max diff) | O-grid seam (max diff)"
    )
    lines = [
        f"### {family}: {r['members']} members, {counts}",
        "",
        f"`pinn-mesh fit --workers 2`: {wall:.1f} s wall ({r['targets_seconds']:.1f} s the "
        f"members' default grids, {r['fit_seconds']:.1f} s the model: encoding "
        f"{r['encoding_components']} components, {r['correction_modes']} correction modes, "
        f"Winslow steps {'yes' if r['winslow_step'] else 'no'}).",
        "",
        f"`pinn-mesh batch --workers 1`, median seconds a member: {b_default:.3f} default, "
        f"{b_family:.3f} with `--model` ({b_family / b_default:.2f} of the default"
        + (
            f"; {len(pairs)} pairs in turn: "
            + ", ".join(f"{r:.2f} (load {load:.1f})" for r, (_, _, load) in zip(ratios, pairs))
            + f", median {statistics.median(ratios):.2f}"
            if len(pairs) > 1
            else ""
        )
        + f"); the grids against the default command's: worst {worst_excess:+.3f}, mean "
        f"{mean_excess:+.4f} (largest excess).",
        "",
        "| members | time default / elliptic / family (s, median) | worst - default (max) | "
        f"mean - default (max) | worst - elliptic (max) | folds | {nodes} | fell back | "
        "start solved |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for label, rows in (("unseen, same ranges", unseen), ("unseen, 25 % wider", wider)):
        med = {
            k: statistics.median(x[k] for x in rows)
            for k in ("t_default", "t_elliptic", "t_family")
        }
        lines.append(
            f"| {label} ({len(rows)}) | {med['t_default']:.4f} / {med['t_elliptic']:.4f} / "
            f"{med['t_family']:.4f} | {max(x['worst_excess'] for x in rows):+.3f} | "
            f"{max(x['mean_excess'] for x in rows):+.4f} | "
            f"{max(x['worst_vs_elliptic'] for x in rows):+.3f} | "
            f"{sum(x['folds'] for x in rows)} | {max(x['boundary'] for x in rows):.1e} | "
            f"{max(x['seam'] for x in rows):.1e} | "
            f"{sum(x['result'] == 'start' for x in rows)} | "
            f"{sum(bool(x['start_solved']) for x in rows)} |"
        )
    if blocks:
        steps = [x["steps"] for x in unseen + wider]
        lines += [
            "",
            "Picard steps a member (median of the 16 unseen members): the own run's from its "
            f"layout {statistics.median(a for a, _ in steps):.0f}, from the model's nodes "
            f"{statistics.median(b for _, b in steps):.0f} (largest {max(b for _, b in steps)}).",
        ]
    if with_stages:
        lines += [
            "",
            f"CPU seconds a member (median of {len(rows_of(folder / 'unseen.csv')) * repeat}; "
            "the unseen members' cases as a batch worker runs them, default and `--model` "
            "in turn; the run, `job.run`, is the case less reading and writing):",
            "",
            *stages(folder, model, repeat),
        ]
        if loaded.topology == "o":
            lines += ["", far_field_error(folder, wide)]
    lines += ["", "| training members | worst - default, unseen (max; fell back) | "
              "worst - default, 25 % wider (max; fell back) |", "|---|---|---|"]  # fmt: skip
    for n in subsets:
        errors = subset_errors(folder, wide, n)
        lines.append(
            f"| {n} | {errors['unseen'][0]:+.3f}; {errors['unseen'][1]} | "
            f"{errors['wide'][0]:+.3f}; {errors['wide'][1]} |"
        )
    lines.append(
        f"| {r['members']} | {max(x['worst_excess'] for x in unseen):+.3f}; "
        f"{sum(x['result'] == 'start' for x in unseen)} | "
        f"{max(x['worst_excess'] for x in wider):+.3f}; "
        f"{sum(x['result'] == 'start' for x in wider)} |"
    )
    return lines


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path)
    parser.add_argument("--workdir", type=Path, default=ROOT / "out" / "family_bench")
    parser.add_argument(
        "--family", nargs="+", default=["channels", "channels_winslow", "naca", "naca_c"]
    )
    parser.add_argument("--repeat", type=int, default=REPEAT, help="timings a member")
    parser.add_argument("--subsets", type=int, nargs="*", default=list(SUBSETS))
    parser.add_argument("--batches", type=int, default=BATCHES, help="pairs of batches")
    parser.add_argument("--stages", action="store_true", help="a body family's stages")
    parser.add_argument("--section", default=SECTION, help="the markers' name in --out")
    args = parser.parse_args()
    args.workdir = args.workdir.resolve()
    import torch

    from pinn_engine.batch.warm import setup_worker

    torch.set_num_threads(1)
    setup_worker()  # one BLAS thread and glibc's heap tuned, as a batch worker
    load = os.getloadavg()[0]
    lines = [f"Measured on a shared 2-core machine (load average {load:.1f} at the start)."]
    for family in args.family:
        lines += [
            "",
            *run_family(
                family,
                args.workdir / family,
                args.repeat,
                tuple(args.subsets),
                args.batches,
                args.stages,
            ),
        ]
    lines.append(f"\nload average {os.getloadavg()[0]:.1f} at the end.")
    text = "\n".join(lines)
    print(text)
    if args.out:
        begin, end = f"<!-- {args.section}: begin -->", f"<!-- {args.section}: end -->"
        page = args.out.read_text()
        head, rest = page.split(begin, 1)
        args.out.write_text(head + begin + "\n" + text + "\n" + end + rest.split(end, 1)[1])


if __name__ == "__main__":
    main()
