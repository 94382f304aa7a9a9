"""The ``pinn-mesh`` command (SPEC 5)."""

from __future__ import annotations

import argparse
import functools
import json
import os
import re
import signal
import sys
import time
from pathlib import Path

from pinn_engine import heap
from pinn_engine.errors import (
    PinnMeshError,
    grid_warnings,
    network_effect,
)
from pinn_engine.hexa.surface import is_faced_surface
from pinn_engine.settings import (
    METHODS,
    MULTIBLOCK_METHODS,
    NEURAL,
    OBJECTIVES,
    PARAMETER_CONSTRAINTS,
    PRESETS,
    Interval,
    Options,
    Settings,
    grid_size_problem,
    make_settings,
    setting_problem,
)

FORMAT_KEYS = ("vts", "vtk", "xyz", "cgns", "su2", "msh", "openfoam")  # export.FORMATS

DEFAULT_SIZE = (41, 21)  # nodes along xi and eta of a four-sided grid (SPEC 5)
BLOCKS_METHOD = "pinn"  # multi-block's default (SPEC 10)
# Options of four-sided domains and bodies that a multi-block run refuses (SPEC 10)
NOT_FOR_BLOCKS = (
    "size", "corners", "topology", "naca", "farfield", "save_model", "load_model",
)  # fmt: skip
EXIT_ERROR = 2
EXIT_INTERNAL = 3
EXIT_INTERRUPTED = 130
DEVICE_NAMES = re.compile(r"^(auto|cpu|mps|cuda(:\d+)?)$")


def _options(name: str) -> tuple:
    return PARAMETER_CONSTRAINTS[name].values


class _SizeAction(argparse.Action):
    """``--size`` takes NI NJ (2D) or NI NJ NK (a six-faced surface), nothing else."""

    def __call__(self, parser, namespace, values, option_string=None):
        if len(values) not in (2, 3):
            parser.error(f"argument {option_string}: expected NI NJ or NI NJ NK")
        setattr(namespace, self.dest, values)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="pinn-mesh",
        description="Structured quadrilateral mesh of a four-sided 2D domain "
        "(PINN of Chen et al., with TFI, elliptic and MGNet baselines).",
        epilog="Many cases at once: pinn-mesh batch MANIFEST -o OUTDIR (pinn-mesh batch -h).",
    )
    p.add_argument(
        "boundary",
        nargs="?",
        default=None,
        help="closed boundary: .vtp, .vtk, .csv or .txt; with --topology an "
        "airfoil .dat (Selig or Lednicer) or a file with two closed "
        "polylines (body inside far field)",
    )
    p.add_argument(
        "--aux",
        action="append",
        default=[],
        metavar="AUX",
        help="auxiliary lines (.vtp/.vtk); repeat for several files. With --blocks: each "
        "line inside one block, from a side to the opposite side (fitted by pinn)",
    )
    p.add_argument(
        "--blocks",
        action="append",
        default=[],
        metavar="EDGES",
        help="block edges (.vtp/.vtk, several open polylines a file; repeatable): mesh a "
        "multi-block domain (SPEC 10) into OUT.vtm; with --cell-size, --interfaces, "
        "--method pinn (the default), elliptic or tfi",
    )
    p.add_argument(
        "--method",
        choices=METHODS,
        default=None,
        help="default pinn (with --blocks too: pinn, elliptic or tfi)",
    )
    p.add_argument(
        "--size",
        nargs="+",
        type=int,
        default=None,
        action=_SizeAction,
        metavar="N",
        help="nodes along xi and eta (default 41 21); NI NJ NK for a six-faced surface "
        "with a FaceId array (default 21 21 21)",
    )
    p.add_argument("--seed", type=int, default=None)
    p.add_argument(
        "--preset",
        choices=PRESETS,
        default="default",
        help="'paper' reproduces the paper's section 4 settings exactly",
    )
    p.add_argument(
        "-o",
        "--output",
        default=None,
        metavar="OUT.vts",
        help="output grid (default out/<boundary>_<method>.vts); the extension "
        "picks the format: .vts, .vtk, .xyz (PLOT3D), .cgns, .su2, .msh "
        "(Gmsh 4.1); a folder with --format openfoam",
    )
    p.add_argument(
        "--format",
        choices=FORMAT_KEYS,
        default=None,
        help="output format instead of the extension of -o (openfoam: -o DIR "
        "gets DIR/constant/polyMesh)",
    )
    p.add_argument(
        "--patch",
        action="append",
        default=[],
        metavar="SIDE=NAME[:TYPE]",
        help="name the boundary patch of a side (bottom, right, top, left; imin, imax, "
        "jmin, jmax, kmin, kmax of a six-faced surface; repeatable; equal names form one "
        "patch) and optionally its type: wall, inflow, outflow, farfield, symmetry, patch "
        "(default: wall for a patch named wall, else patch); OpenFOAM and CGNS write the "
        "types. With --blocks: X,Y=NAME[:TYPE] names "
        "the boundary piece nearest the point (X, Y) (default names: boundary, hole1, ...)",
    )
    p.add_argument(
        "--extrude",
        type=float,
        default=None,
        metavar="T",
        help="one cell of thickness T in z for .xyz, .cgns, .msh and openfoam",
    )
    p.add_argument(
        "--corners",
        nargs=4,
        type=int,
        metavar="I",
        help="the four corner point indices, instead of automatic detection",
    )
    p.add_argument(
        "--png",
        metavar="PATH",
        help="also render the grid, coloured by MaxIncludedAngle, to this PNG (off-screen)",
    )
    p.add_argument("--report", metavar="PATH", help="also write a JSON report")
    p.add_argument(
        "--fail-on-folded",
        action="store_true",
        help="exit with an error (status 2, no output) if any cell is folded",
    )
    p.add_argument(
        "--spacing",
        action="append",
        default=[],
        metavar="SIDE=H",
        help="first grid edge leaving SIDE (bottom, right, top, left) has length "
        "H (your units), growing smoothly away from it; repeat for more sides "
        "(pinn, tfi, elliptic; SPEC 7). O- and C-grids: bottom=H, the first "
        "cell off the body wall. With --blocks: NAME=H, a patch (--patch). Six-faced "
        "surfaces: PATCH=H, PATCH one of imin, imax, jmin, jmax, kmin, kmax",
    )
    p.add_argument(
        "--orthogonal",
        metavar="SIDE[,SIDE...]",
        default=None,
        help="grid lines leave these sides at 90 degrees (pinn: a loss term; "
        "elliptic: Hilgenstock control functions). O- and C-grids: bottom "
        "(elliptic and pinn always do; tfi cannot). With --blocks: patch names. "
        "Six-faced surfaces: imin ... kmax (elliptic)",
    )
    p.add_argument(
        "--quiet",
        action="store_true",
        help="no progress output (a warning about folded cells is still printed)",
    )
    g = p.add_argument_group("training (pinn, mgnet)")
    g.add_argument("--epochs", type=int, dest="adam_epochs", help="Adam epochs")
    g.add_argument("--lbfgs", type=int, dest="lbfgs_iterations", help="L-BFGS iterations")
    g.add_argument("--layers", type=int, dest="hidden_layers", help="hidden layers")
    g.add_argument("--neurons", type=int, help="neurons per hidden layer")
    g.add_argument("--lambda2", type=float, help="weight of the auxiliary-line term")
    g.add_argument(
        "--boundary-mode",
        choices=_options("boundary_mode"),
        dest="boundary_mode",
        help="hard: exact boundary by construction; penalty: the paper's term",
    )
    g.add_argument("--boundary-fit", choices=_options("boundary_fit"), dest="boundary_fit")
    g.add_argument(
        "--warm-start",
        choices=_options("warm_start"),
        dest="warm_start",
        help="elliptic (default): start from the converged elliptic grid and keep "
        "the last state no worse than it; none: train from TFI (paper)",
    )
    g.add_argument(
        "--objective",
        choices=OBJECTIVES,
        dest="objective",
        help="pinn: winslow (the Winslow equations) or quality (plus a cell-quality "
        "term that lowers the worst cell's largest angle; SPEC 7)",
    )
    g.add_argument("--device", help="torch device: auto, cpu, cuda")
    g.add_argument("--save-model", metavar="PATH", help="save the trained model")
    g.add_argument(
        "--load-model", metavar="PATH", help="evaluate a saved model instead of training"
    )
    b = p.add_argument_group("O- and C-grids around a body (SPEC 9)")
    b.add_argument(
        "--topology",
        choices=("o", "c"),
        default=None,
        help="o: O-grid (j = 0 on the body, seam at the trailing edge); c: C-grid "
        "with a wake cut (from a sharp trailing edge or a blunt base's middle)",
    )
    b.add_argument(
        "--naca",
        metavar="DDDD",
        default=None,
        help="NACA 4-digit section of chord 1 instead of a file (blunt trailing "
        "edge for --topology o, closed for c)",
    )
    b.add_argument(
        "--farfield",
        type=float,
        default=None,
        metavar="R",
        help="far-field circle of radius R chords about mid-chord (default 15 for a single body)",
    )
    e = p.add_argument_group("elliptic")
    e.add_argument(
        "--elliptic-iterations",
        type=int,
        dest="elliptic_iterations",
        help="N point-Jacobi sweeps from a zero interior (paper); 0 = converge",
    )
    _table_options(p.add_argument_group("more settings"), p)
    return p


def _table_options(group, parser: argparse.ArgumentParser) -> None:
    """A flag ``--name-with-dashes`` for every setting of the constraint table that has no
    hand-written option above: a setting added to the table is an option here too."""
    taken = {action.dest for action in parser._actions}
    for name, rule in PARAMETER_CONSTRAINTS.items():
        if name in taken:
            continue
        flag = "--" + name.replace("_", "-")
        if isinstance(rule, Options):
            group.add_argument(flag, dest=name, choices=rule.values, help=rule.help)
        else:
            kind = rule.kind if isinstance(rule, Interval) else str
            group.add_argument(flag, dest=name, type=kind, help=rule.help)


class _Progress:
    """Progress on stderr: one updating line on a terminal, a line per 10 %% otherwise."""

    def __init__(self, quiet: bool) -> None:
        self.quiet = quiet
        self.tty = sys.stderr.isatty()
        self.last = -1

    def __call__(self, info: dict) -> None:
        if self.quiet:
            return
        done = info["step"] / max(info["total"], 1)
        decile = int(done * 10)
        if info["phase"] == "prepare":  # a stage before training (bodymesh.STAGES)
            text = f"[{info['stage']}]"
        else:
            text = f"[{info['phase']:5s} {info['step']:5d}/{info['total']}] loss {info['loss']:.3e}"
        if self.tty:
            print("\r" + text, end="", file=sys.stderr, flush=True)
        elif decile != self.last:
            print(text, file=sys.stderr, flush=True)
        self.last = decile

    def close(self) -> None:
        if self.tty and not self.quiet and self.last >= 0:
            print(file=sys.stderr)


def _raise_interrupt(signum, frame):  # noqa: ARG001
    raise KeyboardInterrupt


@functools.cache
def _flags() -> dict[str, str]:
    """Each setting's option as the user types it (dest -> the long flag)."""
    return {a.dest: a.option_strings[-1] for a in build_parser()._actions if a.option_strings}


def _check_options(args: argparse.Namespace) -> None:
    """Refuse option values that are out of range, with a message naming the option."""
    ni, nj = args.size
    problem = grid_size_problem(ni, nj)
    if problem:
        raise PinnMeshError(f"--size {ni} {nj}: {problem}")
    flags = _flags()
    for name in PARAMETER_CONSTRAINTS:  # each range, named by the option that set it
        value = getattr(args, name, None)
        problem = setting_problem(name, value) if value is not None else None
        if problem and name in flags:
            raise PinnMeshError(f"{flags[name]} {value}: {problem}")
    if args.device is not None:
        if not DEVICE_NAMES.match(args.device):
            raise PinnMeshError(f"--device {args.device!r}: use auto, cpu, cuda or cuda:N")
        if args.device.startswith("cuda") and args.method in NEURAL:
            import torch

            if not torch.cuda.is_available():
                raise PinnMeshError(
                    f"--device {args.device}: no CUDA device is available; use --device cpu or auto"
                )


def _check_inputs(args: argparse.Namespace, body: bool) -> None:
    """Refuse inputs that do not go together, in the command line's words."""
    if not body:
        if args.boundary is None:
            raise PinnMeshError("give a boundary file (or --naca DDDD with --topology o or c)")
        return
    if args.topology is None:
        raise PinnMeshError("an airfoil or body needs --topology o or c")
    if args.naca and args.boundary:
        raise PinnMeshError("give either an airfoil file or --naca, not both")
    if args.naca is None and args.boundary is None:
        raise PinnMeshError("give an airfoil file (.dat) or --naca DDDD")
    if args.aux or args.corners:
        raise PinnMeshError("--aux and --corners apply to four-sided domains, not to --topology")
    if args.save_model or args.load_model:
        raise PinnMeshError(
            "--save-model and --load-model apply to four-sided domains in "
            "this build, not to --topology"
        )


def run(args: argparse.Namespace, written: list[Path] | None = None) -> Path:
    """One meshing run (a four-sided domain or, with --topology, a body; SPEC 5 and 9);
    appends each output file to ``written`` once it is complete."""
    from pinn_engine import job
    from pinn_engine.io import export
    from pinn_engine.mesher import Mesher

    written = written if written is not None else []
    if args.blocks:
        return _run_blocks(args, written)
    if args.boundary and is_faced_surface(args.boundary):
        return _run_hexa(args, written)
    args.method = args.method or "pinn"
    args.size = args.size or DEFAULT_SIZE
    if len(args.size) != len(DEFAULT_SIZE):
        raise PinnMeshError(
            f"--size {' '.join(map(str, args.size))}: a 2D domain takes NI NJ "
            "(NI NJ NK is for a six-faced surface with a FaceId array)"
        )
    body = bool(args.topology or args.naca or (args.boundary or "").lower().endswith(".dat"))
    _check_inputs(args, body)
    name = f"naca{args.naca}" if args.naca else Path(args.boundary).stem
    kind = f"{args.topology}_" if body else ""
    suffix = "" if args.format == "openfoam" else f".{args.format or 'vts'}"
    out = Path(args.output or f"out/{name}_{kind}{args.method}{suffix}")
    found = export.output_format(out, args.format, args.extrude)  # refuse before meshing
    if body and found.key == "msh" and args.extrude is not None:
        raise PinnMeshError(
            f"{out}: an O- or C-grid is written to Gmsh in 2D in this build; "
            "drop --extrude (or write .cgns, .xyz or --format openfoam)"
        )
    _check_options(args)
    ni, nj = args.size
    settings = _settings(args, ni, nj)
    geometry = job.geometry_from_files(
        settings, args.boundary, args.aux, args.corners, args.farfield is not None
    )
    mesher = Mesher.load(args.load_model, geometry.boundary) if args.load_model else None
    progress = _Progress(args.quiet)
    start = time.perf_counter()
    try:
        outcome = job.run(settings, (ni, nj), geometry, args.patch or None, progress, mesher=mesher)
    finally:
        progress.close()
    if args.save_model:
        _save_model(outcome.mesher, args.save_model, written)
    if not args.quiet:
        _summary(outcome.result, settings, ni, nj, time.perf_counter() - start)

    def picture(grid, tmp) -> None:
        from pinn_engine.routes.render import render_body_png, render_png

        if not body:
            render_png(grid, tmp, title=f"{args.method}: {Path(args.boundary).name}")
            return
        le, te = geometry.body.chord_points
        title = f"{args.method} {args.topology.upper()}-grid {name}"
        render_body_png(grid, tmp, title=title, le=le, te=te, zoom=0.08 * geometry.body.chord)

    source = name if body else args.boundary
    return _write_outputs(args, outcome, out, written, source, picture)


def _save_model(model, path: str, written: list[Path]) -> None:
    """``model.save(path)`` (a fitted mesher or a hexahedral pinn), its folder made."""
    try:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        model.save(path)
    except (OSError, RuntimeError) as exc:
        raise PinnMeshError(f"{path}: cannot save the model ({exc})") from None
    written.append(Path(path))


def _run_hexa(args: argparse.Namespace, written: list[Path]) -> Path:
    """A six-faced 3D domain (SPEC 11): the surface's hexahedral grid into ``OUT`` (the
    formats and patches of SPEC 8, never extruded; spacing and orthogonality on patches)."""
    from pinn_engine.hexa.spacing import parse_patches
    from pinn_engine.hexamesh import (
        HEXA_METHOD,
        HEXA_SIZE,
        hexa_grid,
        mesh_surface,
        report,
        summary,
    )
    from pinn_engine.io import export
    from pinn_engine.io.fileio import write_text_atomic

    defaults = vars(build_parser().parse_args([]))
    allowed = {"boundary", "method", "size", "output", "quiet", "format", "patch"}
    allowed |= {"spacing", "orthogonal", "report", "save_model", "load_model"}
    flags = _flags()
    for name, value in vars(args).items():
        if name not in allowed and value != defaults.get(name):
            raise PinnMeshError(
                f"{flags.get(name, name)} applies to 2D domains, not to six-faced surfaces "
                "in this build"
            )
    method = args.method or HEXA_METHOD
    size = tuple(args.size or HEXA_SIZE)
    if len(size) != len(HEXA_SIZE):
        raise PinnMeshError(
            f"--size {' '.join(map(str, size))}: a six-faced surface takes NI NJ NK"
        )
    suffix = "" if args.format == "openfoam" else f".{args.format or 'vts'}"
    out = Path(args.output or f"out/{Path(args.boundary).stem}_{method}{suffix}")
    export.output_format(out, args.format)  # refused before meshing
    export.patch_specs(args.patch or None, sides=export.BOX_SIDES)  # as are the patches
    if (args.save_model or args.load_model) and method != "pinn":
        raise PinnMeshError(
            f"--method {method} trains no network: --save-model and --load-model are pinn's"
        )
    spacing, orthogonal = parse_patches(args.spacing, [args.orthogonal] if args.orthogonal else [])
    result = mesh_surface(
        args.boundary,
        size,
        method,
        spacing=spacing,
        orthogonal=orthogonal,
        load_model=args.load_model,
    )
    if args.save_model:
        _save_model(result.model, args.save_model, written)
    export.write(hexa_grid(result, method), out, args.format, patches=args.patch or None)
    written.append(out)
    run = report(result, method)
    if args.report:
        write_text_atomic(args.report, json.dumps(run, indent=2, default=float))
        written.append(Path(args.report))
    if not args.quiet:
        print(summary(result, method))
    for warning, _ in grid_warnings(run, "cli"):  # printed with --quiet too
        print(f"pinn-mesh: warning: {warning}", file=sys.stderr)
    return out


def _trained(report: dict) -> str:
    """The multi-block pinn's training in the summary: in how many blocks the network's
    grid was kept (the elliptic block elsewhere) and the training's seconds."""
    training = report.get("training")
    if training is None:
        return ""
    return (
        f"; the network's grid kept in {training['network_blocks']} of {report['blocks']} "
        f"blocks, the elliptic grid elsewhere ({training['seconds']:.2f} s training)"
    )


def _run_blocks(args: argparse.Namespace, written: list[Path]) -> Path:
    """A multi-block run (SPEC 10): the boundary and its block edges into ``OUT.vtm``."""
    from pinn_engine import job
    from pinn_engine.io.export.multiblock import blocks_format, write_blocks
    from pinn_engine.io.export.vtm import write_vtm
    from pinn_engine.io.fileio import atomic_path, write_text_atomic

    flags = _flags()
    for name in NOT_FOR_BLOCKS:
        if getattr(args, name, None):
            raise PinnMeshError(
                f"{flags[name]} applies to four-sided domains and bodies, not to --blocks"
            )
    if args.boundary is None:
        raise PinnMeshError("give a boundary file (outer boundary and holes) with --blocks")
    args.method = args.method or BLOCKS_METHOD
    if args.method not in MULTIBLOCK_METHODS:
        raise PinnMeshError(
            f"--method {args.method}: multi-block domains are meshed by "
            f"{', '.join(MULTIBLOCK_METHODS[:-1])} or {MULTIBLOCK_METHODS[-1]} in this build "
            f"(default {BLOCKS_METHOD})"
        )
    suffix = "" if args.format == "openfoam" else f".{args.format or 'vtm'}"
    out = Path(args.output or f"out/{Path(args.boundary).stem}_{args.method}{suffix}")
    vtm = args.format is None and out.suffix.lower() == ".vtm"
    if vtm and args.extrude is not None:
        raise PinnMeshError(f"{out}: --extrude applies to .xyz, .cgns and --format openfoam")
    if not vtm:
        blocks_format(out, args.format, args.extrude)  # refused before meshing
    args.size = DEFAULT_SIZE  # checked by _check_options, unused by multi-block
    _check_options(args)
    # patch names, not sides: passed to the run, not to the four-sided settings
    spacing, orthogonal = args.spacing, [args.orthogonal] if args.orthogonal else []
    args.spacing, args.orthogonal = [], None
    settings = _settings(args, *DEFAULT_SIZE)
    start = time.perf_counter()
    progress = _Progress(args.quiet)
    try:
        outcome = job.run_blocks(
            settings,
            args.boundary,
            args.blocks,
            args.patch,
            spacing,
            orthogonal,
            progress,
            args.aux,
        )
    finally:
        progress.close()
    report = outcome.result.report
    q, kink = report["quality"], report["interface_kink"]
    if args.fail_on_folded and q["folded_cells"]:
        raise PinnMeshError(
            f"{args.boundary}: {q['folded_cells']} folded cells (--fail-on-folded); no output "
            "written"
        )
    if not args.quiet:
        print(
            f"{args.method} {report['blocks']} blocks, {report['cells']} cells in "
            f"{time.perf_counter() - start:.2f} s: mean MaxIncludedAngle "
            f"{q['mean_max_angle']:.2f}, worst {q['worst_max_angle']:.2f} deg, "
            f"{q['folded_cells']} folded cells; grid lines cross interfaces with kinks of "
            f"{kink['mean']:.2f} deg mean, {kink['max']:.2f} max{_trained(report)}",
            file=sys.stderr,
            flush=True,
        )
        distances = report["aux_line_distance"]
        if distances:
            print(
                f"auxiliary lines: grid lines within {max(distances.values()):.2e} of their "
                "block's diagonal of the drawn lines",
                file=sys.stderr,
                flush=True,
            )
    if vtm:
        write_vtm(outcome.dataset, out)
    else:
        write_blocks(outcome.dataset, out, args.format, extrude=args.extrude)
    written.append(out)
    if args.report:
        write_text_atomic(args.report, json.dumps(report, indent=2, default=float))
        written.append(Path(args.report))
    if args.png:
        from pinn_engine.routes.render import render_blocks_png

        with atomic_path(args.png, suffix=Path(args.png).suffix or ".png") as tmp:
            title = f"{args.method}: {Path(args.boundary).name}, {report['blocks']} blocks"
            render_blocks_png(outcome.dataset, tmp, title=title)
        written.append(Path(args.png))
    print(f"wrote {out}" + (f" and {args.png}" if args.png else ""))
    if q["folded_cells"]:
        print(
            f"pinn-mesh: warning: {args.boundary}: {q['folded_cells']} of {report['cells']} "
            "cells are folded",
            file=sys.stderr,
            flush=True,
        )
    return out


def _summary(result, settings: Settings, ni: int, nj: int, seconds: float) -> None:
    """The summary lines on stderr: quality, the wall or the sides asked for, the auxiliary
    lines, and what the network did."""
    q = result.quality

    def say(text: str) -> None:
        print(text, file=sys.stderr, flush=True)

    t = result.report.get("topology")
    grid = f"{settings.topology.upper()}-grid" if t else "grid"
    say(
        f"{settings.method} {ni}x{nj} {grid} in {seconds:.2f} s: mean MaxIncludedAngle "
        f"{q['mean_max_angle']:.2f}, worst {q['worst_max_angle']:.2f} deg, "
        f"{q['folded_cells']} folded cells"
        + (
            f"; first layer {t['first_layer']['min']:.3g} .. {t['first_layer']['max']:.3g}, "
            f"wall angles within {t['wall_angle_deviation']:.2f} deg of 90"
            if t
            else f", boundary deviation {q['boundary_deviation']:.1e}"
        )
    )
    effect = network_effect(result.report)
    if effect:
        say(effect)
    if t:
        return
    spaced = tuple(k for k, _ in settings.spacing if k not in settings.orthogonal)
    for side in settings.orthogonal + spaced:
        r = result.report["sides"][side]
        say(
            f"{side}: first edges {r['first_edge_min']:.3g}..{r['first_edge_max']:.3g}, "
            f"wall angles within {r['max_angle_deviation']:.2f} deg of 90, growth "
            f"ratio up to {r['max_growth_ratio']:.3f}"
        )
    distances = result.report["aux_line_distance"]
    if distances:
        say(
            f"auxiliary lines: grid lines within {max(distances.values()):.2e} of the "
            "diagonal of the drawn lines"
        )


def _settings(args, ni: int, nj: int) -> Settings:
    """The settings of the command line's options, with a settings error as a one-line
    command-line error."""
    skip = ("method", "preset")  # given first: the preset is the base the others override
    options = {k: getattr(args, k) for k in PARAMETER_CONSTRAINTS if k not in skip}
    try:
        return make_settings(
            args.method,
            args.preset,
            lattice=(ni, nj),
            spacing=args.spacing,
            orthogonal=args.orthogonal,
            device=args.device,
            **options,
        )
    except ValueError as exc:
        raise PinnMeshError(str(exc)) from exc


def _write_outputs(args, outcome, out: Path, written: list[Path], name: str, picture) -> Path:
    """The grid in the format of ``out``, the report and the picture (``picture(grid, tmp)``)
    if asked, each complete or absent; then the line saying so and the warnings (folded
    cells, wall angles off an orthogonal side)."""
    from pinn_engine.io import export
    from pinn_engine.io.fileio import atomic_path, write_text_atomic

    result, grid = outcome.result, outcome.grid
    q = result.quality
    if args.fail_on_folded and q["folded_cells"]:
        raise PinnMeshError(
            f"{name}: {q['folded_cells']} folded cells (--fail-on-folded); no output written"
        )
    export.write(grid, out, args.format, extrude=args.extrude)
    written.append(out)
    if args.report:
        write_text_atomic(args.report, json.dumps(result.report, indent=2, default=float))
        written.append(Path(args.report))
    if args.png:
        with atomic_path(args.png, suffix=Path(args.png).suffix or ".png") as tmp:
            picture(grid, tmp)
        written.append(Path(args.png))
    print(f"wrote {out}" + (f" and {args.png}" if args.png else ""))
    for warning, _ in grid_warnings(result.report, "cli"):  # printed with --quiet too
        print(f"pinn-mesh: warning: {name}: {warning}", file=sys.stderr, flush=True)
    return out


def main(argv: list[str] | None = None) -> int:
    """Run the command; returns 0, 2 (error, one line on stderr) or 130 (interrupted).

    An unexpected internal failure prints one line and returns 3; set ``PINN_MESH_DEBUG=1``
    to see its traceback instead.
    """
    argv = sys.argv[1:] if argv is None else argv
    args = build_parser().parse_args(argv)
    heap.tune_process()  # this process is ours: glibc's heap tuned for training and meshing
    previous = signal.signal(signal.SIGTERM, _raise_interrupt)
    written: list[Path] = []
    try:
        run(args, written)
    except PinnMeshError as exc:
        print(f"pinn-mesh: error: {exc}", file=sys.stderr)
        return EXIT_ERROR
    except KeyboardInterrupt:
        done = (
            f"; already written: {', '.join(map(str, written))}"
            if written
            else "; no output written"
        )
        print(f"pinn-mesh: interrupted{done}", file=sys.stderr)
        return EXIT_INTERRUPTED
    except OSError as exc:
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        print(f"pinn-mesh: error: {where}{exc.strerror or exc}", file=sys.stderr)
        return EXIT_ERROR
    except MemoryError:
        print("pinn-mesh: error: out of memory; try a smaller --size", file=sys.stderr)
        return EXIT_ERROR
    except Exception as exc:  # a bug: one line, not a traceback, unless debugging
        if os.environ.get("PINN_MESH_DEBUG"):
            raise
        print(
            f"pinn-mesh: internal error: {type(exc).__name__}: {exc} (please report it; "
            "PINN_MESH_DEBUG=1 shows the traceback)",
            file=sys.stderr,
        )
        return EXIT_INTERNAL
    finally:
        signal.signal(signal.SIGTERM, previous)
    return 0


if __name__ == "__main__":
    sys.exit(main())
