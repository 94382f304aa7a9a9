"""The ``pinn-mesh`` command (SPEC 5)."""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import signal
import sys
import time
from pathlib import Path

from . import heap
from .errors import PinnMeshError, folded_cells_warning, wall_angle_warning
from .settings import (
    METHODS,
    NEURAL,
    OBJECTIVES,
    PARAMETER_CONSTRAINTS,
    PRESETS,
    Settings,
    grid_size_problem,
    make_settings,
    setting_problem,
)

FORMAT_KEYS = ("vts", "vtk", "xyz", "cgns", "su2", "msh", "openfoam")  # export.FORMATS

EXIT_ERROR = 2
EXIT_INTERNAL = 3
EXIT_INTERRUPTED = 130
DEVICE_NAMES = re.compile(r"^(auto|cpu|mps|cuda(:\d+)?)$")


def _options(name: str) -> tuple:
    return PARAMETER_CONSTRAINTS[name].values


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="pinn-mesh",
        description="Structured quadrilateral mesh of a four-sided 2D domain "
        "(PINN of Chen et al., with TFI, elliptic and MGNet baselines).",
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
        help="auxiliary lines (.vtp/.vtk); repeat for several files",
    )
    p.add_argument("--method", choices=METHODS, default="pinn")
    p.add_argument(
        "--size",
        nargs=2,
        type=int,
        default=(41, 21),
        metavar=("NI", "NJ"),
        help="nodes along xi and eta (default 41 21)",
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
        metavar="SIDE=NAME",
        help="name the boundary patch of a side (bottom, right, top, left; "
        "repeatable; equal names form one patch)",
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
        "cell off the body wall",
    )
    p.add_argument(
        "--orthogonal",
        metavar="SIDE[,SIDE...]",
        default=None,
        help="grid lines leave these sides at 90 degrees (pinn: a loss term; "
        "elliptic: Hilgenstock control functions). O- and C-grids: bottom "
        "(elliptic and pinn always do; tfi cannot)",
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
        "with a wake cut (sharp trailing edge)",
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
    return p


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


# the command line's name for each numeric setting
OPTION_FLAGS = {
    "seed": "--seed",
    "lambda2": "--lambda2",
    "hidden_layers": "--layers",
    "neurons": "--neurons",
    "adam_epochs": "--epochs",
    "lbfgs_iterations": "--lbfgs",
    "elliptic_iterations": "--elliptic-iterations",
}


def _check_options(args: argparse.Namespace) -> None:
    """Refuse option values that are out of range, with a message naming the option."""
    ni, nj = args.size
    problem = grid_size_problem(ni, nj)
    if problem:
        raise PinnMeshError(f"--size {ni} {nj}: {problem}")
    for name, flag in OPTION_FLAGS.items():  # the ranges of settings.PARAMETER_CONSTRAINTS
        value = getattr(args, name)
        problem = setting_problem(name, value) if value is not None else None
        if problem:
            raise PinnMeshError(f"{flag} {value}: {problem}")
    if args.device is not None:
        if not DEVICE_NAMES.match(args.device):
            raise PinnMeshError(f"--device {args.device!r}: use auto, cpu, cuda or cuda:N")
        if args.device.startswith("cuda") and args.method in NEURAL:
            import torch

            if not torch.cuda.is_available():
                raise PinnMeshError(
                    f"--device {args.device}: no CUDA device is available; use --device cpu or auto"
                )


def run(args: argparse.Namespace, written: list[Path] | None = None) -> Path:
    """One meshing run; appends each output file to ``written`` once it is complete."""

    from . import export
    from .mesher import Mesher
    from .pipeline import load_aux, load_boundary

    written = written if written is not None else []
    if args.topology or args.naca or (args.boundary or "").lower().endswith(".dat"):
        return run_body(args, written)
    if args.boundary is None:
        raise PinnMeshError("give a boundary file (or --naca DDDD with --topology o or c)")
    suffix = "" if args.format == "openfoam" else f".{args.format or 'vts'}"
    out = Path(args.output or f"out/{Path(args.boundary).stem}_{args.method}{suffix}")
    export.output_format(out, args.format, args.extrude)  # refuse before meshing
    patches = export.parse_patch_options(args.patch)
    _check_options(args)
    ni, nj = args.size
    settings = _settings(
        args,
        ni,
        nj,
        ("lambda2", "boundary_fit", "objective"),
        boundary_mode=args.boundary_mode,
        spacing=args.spacing,
        orthogonal=args.orthogonal,
    )
    boundary = load_boundary(args.boundary, args.corners)
    aux = load_aux(args.aux, boundary)
    mesher = Mesher(settings)
    progress = _Progress(args.quiet)
    start = time.perf_counter()
    try:
        if args.load_model:
            mesher = Mesher.load(args.load_model, boundary)
        else:
            mesher.fit(boundary, aux, progress)
    finally:
        progress.close()
    if args.save_model:
        try:
            Path(args.save_model).parent.mkdir(parents=True, exist_ok=True)
            mesher.save(args.save_model)
        except (OSError, RuntimeError) as exc:
            raise PinnMeshError(f"{args.save_model}: cannot save the model ({exc})") from None
        written.append(Path(args.save_model))
    result = mesher.predict(ni, nj)
    q = result.quality
    if not args.quiet:
        print(
            f"{settings.method} {ni}x{nj} grid in {time.perf_counter() - start:.2f} s: "
            f"mean MaxIncludedAngle {q['mean_max_angle']:.2f}, worst "
            f"{q['worst_max_angle']:.2f} deg, {q['folded_cells']} folded cells, boundary "
            f"deviation {q['boundary_deviation']:.1e}",
            file=sys.stderr,
            flush=True,
        )
        for side in settings.orthogonal + tuple(
            k for k, _ in settings.spacing if k not in settings.orthogonal
        ):
            r = result.report["sides"][side]
            print(
                f"{side}: first edges {r['first_edge_min']:.3g}..{r['first_edge_max']:.3g}, "
                f"wall angles within {r['max_angle_deviation']:.2f} deg of 90, growth "
                f"ratio up to {r['max_growth_ratio']:.3f}",
                file=sys.stderr,
                flush=True,
            )
        distances = result.report["aux_line_distance"]
        if distances:
            print(
                f"auxiliary lines: grid lines within {max(distances.values()):.2e} of the "
                "diagonal of the drawn lines",
                file=sys.stderr,
                flush=True,
            )

    def picture(grid, tmp) -> None:
        from .render import render_png

        render_png(grid, tmp, title=f"{args.method}: {Path(args.boundary).name}")

    return _write_outputs(args, result, out, patches, written, args.boundary, picture)


def _wall_spacing(args: argparse.Namespace) -> float | None:
    """H of ``--spacing bottom=H`` (the wall of an O- or C-grid)."""
    h = None
    for item in args.spacing:
        side, sep, value = item.partition("=")
        if not sep or side.strip().lower() != "bottom":
            raise PinnMeshError(
                f"--spacing {item!r}: an O- or C-grid takes bottom=H (the body wall)"
            )
        try:
            h = float(value)
        except ValueError:
            raise PinnMeshError(f"--spacing {item!r}: H must be a number") from None
        if not (math.isfinite(h) and h > 0):
            raise PinnMeshError(f"--spacing {item!r}: H must be a number > 0")
    if args.orthogonal is not None:
        sides = {t.strip().lower() for t in args.orthogonal.split(",") if t.strip()}
        if sides != {"bottom"}:
            raise PinnMeshError(
                f"--orthogonal {args.orthogonal}: an O- or C-grid takes bottom (the body wall)"
            )
    return h


def run_body(args: argparse.Namespace, written: list[Path]) -> Path:
    """An O- or C-grid around an airfoil or another body (SPEC 9)."""
    from . import export
    from .airfoil import circle, load_body, read_body_and_farfield
    from .bodymesh import mesh_body, patch_names

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
    if args.orthogonal and args.method == "tfi":
        raise PinnMeshError(
            "--orthogonal bottom: tfi's straight columns cannot leave the "
            "wall at right angles; use --method elliptic or pinn"
        )
    name = f"naca{args.naca}" if args.naca else Path(args.boundary).stem
    suffix = "" if args.format == "openfoam" else f".{args.format or 'vts'}"
    out = Path(args.output or f"out/{name}_{args.topology}_{args.method}{suffix}")
    found = export.output_format(out, args.format, args.extrude)
    if found.key == "msh" and args.extrude is not None:
        raise PinnMeshError(
            f"{out}: an O- or C-grid is written to Gmsh in 2D in this build; "
            "drop --extrude (or write .cgns, .xyz or --format openfoam)"
        )
    names = dict(zip(("bottom", "right", "top", "left"), patch_names(args.topology)))
    for item in args.patch:
        side, sep, value = item.partition("=")
        if not sep or side.strip().lower() not in names:
            raise PinnMeshError(f"--patch {item!r}: expected SIDE=NAME")
        names[side.strip().lower()] = value.strip()
    patches = export.patch_names(names)
    _check_options(args)
    h = _wall_spacing(args)
    ni, nj = args.size
    settings = _settings(args, ni, nj)
    if args.naca:
        body = load_body(naca=args.naca, te="blunt" if args.topology == "o" else "sharp")
        far = circle(body, args.farfield or 15.0)
    elif Path(args.boundary).suffix.lower() == ".dat" or args.farfield is not None:
        body = load_body(args.boundary)
        far = circle(body, args.farfield or 15.0)
    else:
        body, far = read_body_and_farfield(args.boundary)
    progress = _Progress(args.quiet)
    start = time.perf_counter()
    try:
        result = mesh_body(body, far, args.topology, args.method, ni, nj, settings, h, progress)
    finally:
        progress.close()
    q, t = result.quality, result.report["topology"]
    if not args.quiet:
        print(
            f"{args.method} {args.topology.upper()}-grid {ni}x{nj} in "
            f"{time.perf_counter() - start:.2f} s: mean MaxIncludedAngle "
            f"{q['mean_max_angle']:.2f}, worst {q['worst_max_angle']:.2f} deg, "
            f"{q['folded_cells']} folded cells; first layer {t['first_layer']['min']:.3g} .. "
            f"{t['first_layer']['max']:.3g}, wall angles within "
            f"{t['wall_angle_deviation']:.2f} deg of 90",
            file=sys.stderr,
            flush=True,
        )

    def picture(grid, tmp) -> None:
        from .render import render_body_png

        le, te = body.chord_points
        title = f"{args.method} {args.topology.upper()}-grid {name}"
        render_body_png(grid, tmp, title=title, le=le, te=te, zoom=0.08 * body.chord)

    return _write_outputs(args, result, out, patches, written, name, picture)


# options of the training and solver settings that both routes (four-sided, body) pass on
_SETTING_FIELDS = (
    "seed",
    "adam_epochs",
    "lbfgs_iterations",
    "hidden_layers",
    "neurons",
    "device",
    "elliptic_iterations",
    "warm_start",
)


def _settings(args, ni: int, nj: int, fields: tuple[str, ...] = (), **given) -> Settings:
    """The settings of the command line's options (``_SETTING_FIELDS`` and ``fields``), with
    a settings error as a one-line command-line error."""
    options = {k: getattr(args, k) for k in _SETTING_FIELDS + fields}
    try:
        return make_settings(args.method, args.preset, lattice=(ni, nj), **options, **given)
    except ValueError as exc:
        raise PinnMeshError(str(exc)) from exc


def _write_outputs(
    args, result, out: Path, patches, written: list[Path], name: str, picture
) -> Path:
    """The grid in the format of ``out``, the report and the picture (``picture(grid, tmp)``)
    if asked, each complete or absent; then the line saying so and the warnings (folded
    cells, wall angles off an orthogonal side)."""
    from . import export
    from .fileio import atomic_path, write_text_atomic
    from .pipeline import to_vtk

    q = result.quality
    if args.fail_on_folded and q["folded_cells"]:
        raise PinnMeshError(
            f"{name}: {q['folded_cells']} folded cells (--fail-on-folded); no output written"
        )
    grid = to_vtk(result, patches)
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
    for warning in (  # not progress: printed with --quiet too; last: an error stays one line
        folded_cells_warning(result.report, "cli"),
        wall_angle_warning(result.report, "cli"),
    ):
        if warning:
            print(f"pinn-mesh: warning: {name}: {warning}", file=sys.stderr, flush=True)
    return out


def main(argv: list[str] | None = None) -> int:
    """Run the command; returns 0, 2 (error, one line on stderr) or 130 (interrupted).

    An unexpected internal failure prints one line and returns 3; set ``PINN_MESH_DEBUG=1``
    to see its traceback instead.
    """
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
