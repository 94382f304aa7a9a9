"""Every method on the hard four-sided shapes of ``example_data/hard/`` (docs/hard_shapes.md).

Usage: ``.venv/bin/python benchmarks/bench_hard.py [--sizes 41x21 161x81] [--no-speed]
[--variants]``

For each shape and size it meshes with ``tfi``, ``elliptic`` (converged), ``mgnet`` and the
default ``pinn`` and prints mean and worst ``MaxIncludedAngle``, folded cells and time
(fit + grid, torch imported beforehand). For the neural methods it checks the default's bounds
against the converged elliptic grid on the same boundary nodes: mean <= elliptic + 0.5,
worst <= elliptic worst + 2, no folded cell where the elliptic grid has none (where it has
some: no more than it). Shapes with auxiliary lines also get the largest distance of the
grid line through each line's (xi, eta) from the drawn line (``auxlines.line_distances``).

``--variants`` adds two runs of the PINN that show what the default's choices are worth (the
default's own bounds check applies to them too): ``pinn, paper residual`` (the warm start
and guard with the paper's raw residual and lambda2 = 10) and ``pinn, from TFI`` (the
previous default: no warm start, 5000 Adam epochs and 500 L-BFGS iterations, the paper's
residual), and writes ``<out>_variants.md`` instead of the main table.

``--objective`` compares the pinn's two objectives (SPEC 7): ``tfi``, ``elliptic``, ``pinn``
with ``--objective winslow``, ``pinn, quality`` with ``--objective quality`` and its ablation
``pinn, quality, network only`` (no node optimisation of the start: the network trained on the
quality term from the best of the elliptic grid, TFI and their blends), and checks the quality
objective's bounds on each pinn grid: no folded cell, mean <= elliptic + 0.5, worst <= TFI's
worst + 0.5, and worst below the elliptic grid's or at the floor the boundary nodes fix
(``quality.angle_floor``: the largest angle at a domain corner, or half the largest interior
angle at another boundary node). It also runs the example shapes with auxiliary lines outside
the hard set (``AUX_EXAMPLES``) and tabulates, for every shape with auxiliary lines, the
distance of the grid line through them from the drawn lines under each objective. Writes
``<out>_quality.md`` instead of the main table.

The speed section times, on ``bump`` with its auxiliary line at 41 x 21: the ``pinn-mesh``
command with the default settings (a fresh process, start to written grid), the paper preset
(training only) and the plain-autograd paper recipe of ``plain_pinn.py`` (Adam in float32,
L-BFGS in float64, training only), and prints the ratios. Writes ``docs/hard_shapes.md`` and
``docs/hard_shapes.json``.
"""

from __future__ import annotations

import argparse
import json
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from pinn_engine.geometry.auxlines import line_distances
from pinn_engine.io.pipeline import load_aux, load_boundary
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.quality import angle_floor
from pinn_engine.settings import make_settings
from pinn_engine.starts import quality_start

ROOT = Path(__file__).resolve().parents[1]
HARD = ROOT / "example_data" / "hard"
AUX_EXAMPLES = ("concave", "fig2", "wavy")  # in example_data/, with <name>_aux.vtp
RUNS = {method: (method, {}) for method in ("tfi", "elliptic", "mgnet", "pinn")}
VARIANTS = {
    "elliptic": ("elliptic", {}),
    "pinn": ("pinn", {}),
    "pinn, paper residual": ("pinn", {"residual": "paper", "lambda2": 10.0}),
    "pinn, from TFI": ("pinn", {"warm_start": "none"}),
}
OBJECTIVES = {
    "tfi": ("tfi", {}),
    "elliptic": ("elliptic", {}),
    "pinn": ("pinn", {"objective": "winslow"}),
    "pinn, quality": ("pinn", {"objective": "quality"}),
    "pinn, quality, network only": ("pinn", {"objective": "quality", "node_iterations": 0}),
}
QUALITY_RUNS = ("pinn", "pinn, quality", "pinn, quality, network only")
MEAN_BOUND, WORST_BOUND = 0.5, 2.0
UNTANGLED_MEAN_BOUND = 1.0  # the mean's bound for a grid that untangles the elliptic one
FLOOR_TOL = 0.01  # degrees: a worst angle this close to the floor is at it
AUX_TIE = 1e-6  # of the diagonal: auxiliary-line distances this close are equal


def shapes() -> list[str]:
    return sorted(p.stem for p in HARD.glob("*.vtp") if not p.stem.endswith("_aux"))


def inputs(name: str, folder: Path = HARD):
    boundary = load_boundary(folder / f"{name}.vtp")
    aux_file = folder / f"{name}_aux.vtp"
    return boundary, load_aux([aux_file], boundary) if aux_file.exists() else []


def within(q: dict, ref: dict) -> bool:
    """The default's bounds for a neural grid ``q`` against the elliptic grid ``ref``; where
    ``q`` has fewer folded cells than a folded ``ref`` (it untangled it), the untangled grid's mean
    bound, ``UNTANGLED_MEAN_BOUND``."""
    untangled = q["folded_cells"] < ref["folded_cells"]
    return (
        q["folded_cells"] <= ref["folded_cells"]
        and q["mean_max_angle"]
        <= ref["mean_max_angle"] + (UNTANGLED_MEAN_BOUND if untangled else MEAN_BOUND)
        and q["worst_max_angle"] <= ref["worst_max_angle"] + WORST_BOUND
    )


def item3(q: dict, ell: dict, tfi: dict, floor: float) -> bool:
    """The quality objective's bounds for a pinn grid ``q`` against the elliptic and TFI grids."""
    return (
        q["folded_cells"] == 0
        and q["mean_max_angle"] <= ell["mean_max_angle"] + MEAN_BOUND
        and q["worst_max_angle"] <= tfi["worst_max_angle"] + 0.5
        and (
            q["worst_max_angle"] < ell["worst_max_angle"]
            or q["worst_max_angle"] <= floor + FLOOR_TOL
        )
    )


def run_shape(
    name: str, size: tuple[int, int], runs: dict = RUNS, folder: Path = HARD
) -> list[dict]:
    boundary, aux = inputs(name, folder)
    rows, ref, tfi = [], None, None
    for label, (method, overrides) in runs.items():
        overrides = dict(overrides)
        node_iterations = overrides.pop("node_iterations", quality_start.STAGE_ITERATIONS)
        start = time.perf_counter()
        settings = make_settings(method, lattice=size, **overrides)
        saved, quality_start.STAGE_ITERATIONS = quality_start.STAGE_ITERATIONS, node_iterations
        try:
            result = Mesher(settings).fit(boundary, aux).predict(*size)
        finally:
            quality_start.STAGE_ITERATIONS = saved
        seconds = time.perf_counter() - start
        q = result.quality
        unit = boundary.frame.to_unit(result.points)
        row = {
            "shape": name,
            "hard": folder == HARD,
            "size": list(size),
            "method": label,
            "seconds": seconds,
            **{k: q[k] for k in ("mean_max_angle", "worst_max_angle", "folded_cells")},
            "aux_distance": max(
                line_distances(unit, aux, boundary.diagonal).values(), default=None
            ),
        }
        if method == "elliptic":
            ref = row
        if method == "tfi":
            tfi = row
            row["floor"] = max(angle_floor(result.points))
        if method in ("mgnet", "pinn"):
            row["within_bounds"] = within(row, ref)
            if runs is OBJECTIVES:
                row["item3"] = item3(row, ref, tfi, tfi["floor"])
        rows.append(row)
        aux_text = f" aux {row['aux_distance']:.4f}" if aux else ""
        check = {True: " ok", False: " OUT OF BOUNDS"}.get(row.get("within_bounds"), "")
        check += {True: " item3 ok", False: " ITEM3 FAILS"}.get(row.get("item3"), "")
        print(
            f"{name:26s} {size[0]:3d}x{size[1]:<3d} {label:20s} mean "
            f"{row['mean_max_angle']:7.2f} worst {row['worst_max_angle']:7.2f} folded "
            f"{row['folded_cells']:4d} {seconds:6.2f} s{aux_text}{check}",
            flush=True,
        )
    return rows


def command_seconds(name: str) -> float:
    """Wall time of the default ``pinn-mesh`` command, start to written grid."""
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [
            sys.executable,
            "-m",
            "pinn_engine.routes.cli",
            str(HARD / f"{name}.vtp"),
            "--aux",
            str(HARD / f"{name}_aux.vtp"),
            "-o",
            str(Path(tmp) / "g.vts"),
            "--quiet",
        ]
        start = time.perf_counter()
        subprocess.run(cmd, check=True, cwd=ROOT, capture_output=True)
        return time.perf_counter() - start


def speed(name: str = "bump") -> dict:
    sys.path.insert(0, str(ROOT / "benchmarks"))
    from plain_pinn import train_plain

    boundary, aux = inputs(name)
    runs = sorted(command_seconds(name) for _ in range(3))
    start = time.perf_counter()
    Mesher(make_settings("pinn", "paper")).fit(boundary, aux)
    paper = time.perf_counter() - start
    plain = train_plain(boundary, aux)["seconds"]
    out = {
        "shape": name,
        "command_median_s": runs[1],
        "command_runs_s": runs,
        "paper_preset_train_s": paper,
        "plain_train_s": plain,
        "default_speedup": plain / runs[1],
        "paper_speedup": plain / paper,
    }
    print(
        f"\nspeed on {name} (41 x 21, one auxiliary line):\n"
        f"  default pinn-mesh command, start to written grid: {runs[1]:.2f} s "
        f"(median of {', '.join(f'{r:.2f}' for r in runs)})\n"
        f"  paper preset, training: {paper:.1f} s\n"
        f"  plain-autograd paper recipe (plain_pinn.py), training: {plain:.1f} s\n"
        f"  plain / default command: {out['default_speedup']:.1f}x; "
        f"plain / paper preset: {out['paper_speedup']:.2f}x",
        flush=True,
    )
    return out


def markdown(rows: list[dict], fast: dict | None, variants: bool) -> str:
    """The table page: what was run, how to run it again, the rows, the speed figures."""
    neural = [r for r in rows if "within_bounds" in r]
    command = "benchmarks/bench_hard.py" + (" --variants --sizes 41x21" if variants else "")
    lines = [
        "# "
        + (
            "The default PINN against its ablations"
            if variants
            else "Every method on the hard four-sided shapes"
        ),
        "",
        f"Made by `.venv/bin/python {command}` on the shapes of `example_data/hard/` "
        "(`example_data/make_hard_shapes.py` draws them). Quality is VTK's Verdict quad "
        "`MaxIncludedAngle`; time is fit plus grid in one process with torch imported "
        "(a few seconds of start-up are not in it). The bounds are the default's, against the "
        "converged elliptic grid on the same boundary nodes: mean <= elliptic + 0.5, worst <= "
        "elliptic worst + 2 degrees, and no more folded cells than it (none where it has "
        "none). The aux-line distance is the largest distance of the grid line through an "
        "auxiliary line's (xi, eta) from the drawn line, relative to the diagonal.",
        "",
        f"**{sum(r['within_bounds'] for r in neural)} of {len(neural)} neural grids within "
        "the bounds.**",
        "",
        "| shape | size | method | mean MaxIncludedAngle | worst MaxIncludedAngle | folded | "
        "time (s) | aux-line distance | bounds |",
        "|" + "---|" * 9,
    ]
    for r in rows:
        aux = f"{r['aux_distance']:.4f}" if r["aux_distance"] is not None else ""
        check = {True: "within", False: "**outside**"}.get(r.get("within_bounds"), "")
        lines.append(
            f"| {r['shape']} | {r['size'][0]} x {r['size'][1]} | {r['method']} | "
            f"{r['mean_max_angle']:.2f} | {r['worst_max_angle']:.2f} | "
            f"{r['folded_cells']} | {r['seconds']:.2f} | {aux} | {check} |"
        )
    if fast:
        lines += [
            "",
            "## Speed",
            "",
            f"On `{fast['shape']}` at 41 x 21 with its auxiliary "
            f"line: the default `pinn-mesh` command took {fast['command_median_s']:.2f} s "
            "from start to written grid (median of "
            f"{', '.join(f'{t:.2f}' for t in fast['command_runs_s'])} s, torch's import "
            "included); the plain-autograd paper recipe (`benchmarks/plain_pinn.py`: "
            "Adam in float32, L-BFGS in float64, nested autograd) trained for "
            f"{fast['plain_train_s']:.1f} s, {fast['default_speedup']:.1f}x the whole "
            "default command; the paper preset trained for "
            f"{fast['paper_preset_train_s']:.1f} s, {fast['paper_speedup']:.2f}x faster "
            "than the plain recipe.",
        ]
    return "\n".join(lines) + "\n"


def markdown_quality(rows: list[dict]) -> str:
    """The page of ``--objective``: the hard shapes' table (both pinn objectives against TFI,
    the elliptic grid and the floor), then the auxiliary lines' table."""
    runs: dict[tuple, dict] = {}
    for r in rows:
        runs.setdefault((r["shape"], tuple(r["size"])), {})[r["method"]] = r
    hard = {k: r for k, r in runs.items() if r["tfi"]["hard"]}
    with_aux = {k: r for k, r in runs.items() if r["tfi"]["aux_distance"] is not None}
    return "\n".join(_quality_table(hard) + [""] + _aux_table(with_aux)) + "\n"


def _cell(r: dict, extra: bool = True) -> str:
    """Mean / worst MaxIncludedAngle, with folded cells and seconds (or folded cells if any)."""
    text = f"{r['mean_max_angle']:.2f} / {r['worst_max_angle']:.2f}"
    return text + (
        f", {r['folded_cells']} folded, {r['seconds']:.1f} s"
        if extra
        else (f", {r['folded_cells']} folded" if r["folded_cells"] else "")
    )


def _quality_table(runs: dict[tuple, dict]) -> list[str]:
    """The quality objective's bounds on the hard shapes: one row per shape and size."""
    pinn = [r[m] for r in runs.values() for m in QUALITY_RUNS]
    count = {
        m: (sum(r["item3"] for r in pinn if r["method"] == m), sum(r["method"] == m for r in pinn))
        for m in QUALITY_RUNS
    }
    lines = [
        "# The pinn's objectives: winslow and quality",
        "",
        "Made by `.venv/bin/python benchmarks/bench_hard.py --objective` on the shapes of "
        "`example_data/hard/`. Each cell: mean / worst `MaxIncludedAngle` (VTK's Verdict "
        "quad metric, degrees), then folded cells and the time of fit plus grid in seconds "
        "(one process, torch imported, 2 cores shared with other work). The floor is the "
        "lower bound the boundary nodes put on the worst angle (`quality.angle_floor`): the "
        "largest angle at a domain corner between the first boundary edges, or half the "
        "largest interior angle at another boundary node (the two cells there share it). "
        "Item 3 holds for a pinn grid with no folded cell, mean <= elliptic + 0.5, worst <= "
        "TFI's worst + 0.5, and worst below the elliptic grid's or at the floor (within "
        f"{FLOOR_TOL} degrees).",
        "",
        f"**Item 3 holds on {count['pinn, quality'][0]} of {count['pinn, quality'][1]} grids "
        f"with `--objective quality`, on {count['pinn'][0]} of {count['pinn'][1]} with "
        "`--objective winslow`, on "
        f"{count['pinn, quality, network only'][0]} of {count['pinn, quality, network only'][1]}"
        " with the quality objective's network alone (no node optimisation of the start).**",
        "",
        "| shape | size | floor | tfi | elliptic | pinn, winslow | pinn, quality | pinn, "
        "quality, network only | item 3 (winslow / quality / network only) |",
        "|" + "---|" * 9,
    ]
    for (shape, size), r in runs.items():
        marks = " / ".join({True: "holds", False: "**fails**"}[r[m]["item3"]] for m in QUALITY_RUNS)
        lines.append(
            f"| {shape} | {size[0]} x {size[1]} | {r['tfi']['floor']:.2f} | "
            f"{_cell(r['tfi'], False)} | {_cell(r['elliptic'], False)} | "
            + " | ".join(_cell(r[m]) for m in QUALITY_RUNS)
            + f" | {marks} |"
        )
    return lines


def _aux_table(runs: dict[tuple, dict]) -> list[str]:
    """How far each objective's grid follows the auxiliary lines, on every shape with them."""
    followed = sum(
        r["pinn, quality"]["aux_distance"] <= r["pinn"]["aux_distance"] + AUX_TIE
        for r in runs.values()
    )
    lines = [
        "## Auxiliary lines",
        "",
        "The shapes of `example_data/hard/` with auxiliary lines and the examples "
        f"{', '.join(f'`{n}`' for n in AUX_EXAMPLES)} of `example_data/` (with their "
        "`_aux.vtp`). The distance is the largest distance of the grid line through an "
        "auxiliary line's (xi, eta) from the drawn line, relative to the diagonal "
        "(`auxlines.line_distances`, the report's `aux_line_distance`); it is never below "
        "what the boundary nodes fix where the line meets the boundary. Then mean / worst "
        "`MaxIncludedAngle`, folded cells and seconds of the two objectives.",
        "",
        f"**The quality objective's grid follows the lines at least as closely as winslow's "
        f"(within {AUX_TIE:g} of the diagonal) on {followed} of {len(runs)} grids.**",
        "",
        "| shape | size | distance: tfi / elliptic / winslow / quality / network only | "
        "pinn, winslow | pinn, quality |",
        "|" + "---|" * 5,
    ]
    for (shape, size), r in runs.items():
        distances = " / ".join(
            f"{r[m]['aux_distance']:.5f}" for m in ("tfi", "elliptic", *QUALITY_RUNS)
        )
        lines.append(
            f"| {shape} | {size[0]} x {size[1]} | {distances} | {_cell(r['pinn'])} | "
            f"{_cell(r['pinn, quality'])} |"
        )
    return lines


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--sizes", nargs="+", default=["41x21", "161x81"])
    p.add_argument("--shapes", nargs="+", default=None)
    p.add_argument("--no-speed", action="store_true", help="skip the speed section")
    p.add_argument(
        "--variants",
        action="store_true",
        help="the default against its ablations instead of the method table",
    )
    p.add_argument(
        "--objective",
        action="store_true",
        help="the pinn's objectives winslow and quality",
    )
    p.add_argument("--out", default=str(ROOT / "docs" / "hard_shapes"))
    args = p.parse_args()
    import torch  # noqa: F401  (imported once, before any timing)

    sizes = [tuple(int(n) for n in s.split("x")) for s in args.sizes]
    runs = OBJECTIVES if args.objective else VARIANTS if args.variants else RUNS
    rows = [
        row
        for name in (args.shapes or shapes())
        for size in sizes
        for row in run_shape(name, size, runs)
    ]
    if args.objective and not args.shapes:
        rows += [
            row
            for name in AUX_EXAMPLES
            for size in sizes
            for row in run_shape(name, size, runs, ROOT / "example_data")
        ]
    neural = [r for r in rows if "within_bounds" in r]
    print(
        f"\n{sum(r['within_bounds'] for r in neural)} of {len(neural)} neural grids within "
        "the default's bounds"
    )
    fast = None if args.no_speed or args.variants or args.objective else speed()
    out = Path(args.out + ("_variants" if args.variants else "_quality" if args.objective else ""))
    out.with_suffix(".json").write_text(json.dumps({"rows": rows, "speed": fast}, indent=2))
    out.with_suffix(".md").write_text(
        markdown_quality(rows) if args.objective else markdown(rows, fast, args.variants)
    )
    print(f"wrote {out.with_suffix('.md')} and {out.with_suffix('.json')}")


if __name__ == "__main__":
    from pinn_engine.heap import tune_process

    tune_process()  # as the command line does (the library leaves a host's allocator alone)
    main()
