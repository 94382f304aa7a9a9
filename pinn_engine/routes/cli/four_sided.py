"""One run of a four-sided domain or, with --topology, a body (SPEC 5 and 9)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from pinn_engine.errors import PinnMeshError, grid_warnings
from pinn_engine.routes.cli.options import (
    check_options,
    read_adapt_field,
    refuse_options,
    settings_from,
)
from pinn_engine.routes.cli.outputs import output_path, refuse_folded, save_model, write_outputs
from pinn_engine.routes.cli.progress import Progress
from pinn_engine.routes.cli.summary import grid_summary, warn
from pinn_engine.settings import DEFAULT_SIZE


def check_inputs(args: argparse.Namespace, body: bool) -> None:
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
    from pinn_engine.job import only_for

    refuse_options(
        args, only_for("four-sided", "body"), "{} applies to four-sided domains, not to --topology"
    )


def run_four_sided(
    args: argparse.Namespace, written: list[Path], body: bool, reports: list[dict] | None = None
) -> Path:
    """Mesh a four-sided domain or (``body``) a body into ``OUT`` (the formats of SPEC 8);
    appends each output file to ``written`` once it is complete, and the report to
    ``reports`` (:func:`outputs.keep_report`)."""
    from pinn_engine import job
    from pinn_engine.io import export

    args.method = args.method or "pinn"
    if args.model and (args.load_model or args.save_model):
        raise PinnMeshError(
            "--model meshes by a family model: it loads no other model and trains none to "
            "save; drop --load-model and --save-model"
        )
    args.size = args.size or (job.family_size(args.model) if args.model else DEFAULT_SIZE)
    if len(args.size) != len(DEFAULT_SIZE):
        raise PinnMeshError(
            f"--size {' '.join(map(str, args.size))}: a 2D domain takes NI NJ "
            "(NI NJ NK is for a six-faced surface with a FaceId array)"
        )
    check_inputs(args, body)
    name = f"naca{args.naca}" if args.naca else Path(args.boundary).stem
    kind = f"{args.topology}_" if body else ""
    out = output_path(args, f"{name}_{kind}{args.method}", "vts")
    found = export.output_format(out, args.format, args.extrude)  # refuse before meshing
    if body and found.key == "msh" and args.extrude is not None:
        raise PinnMeshError(
            f"{out}: an O- or C-grid is written to Gmsh in 2D in this build; "
            "drop --extrude (or write .cgns, .xyz or --format openfoam)"
        )
    check_options(args)
    ni, nj = args.size
    settings = settings_from(args, (ni, nj))
    began = time.perf_counter()
    field = read_adapt_field(args)
    geometry = job.geometry_from_files(
        settings,
        args.boundary,
        args.aux,
        args.corners,
        args.farfield is not None,
        args.patch or None,
    )
    read_seconds = time.perf_counter() - began
    start = time.perf_counter()
    with Progress(args.quiet) as progress:
        outcome = job.run(
            settings, geometry, progress, model=args.load_model, family=args.model, field=field
        )
    if args.save_model:
        save_model(outcome.model, args.save_model, written)
    report = outcome.report
    if "timings" in report:
        report["timings"]["read"] = read_seconds
    seconds = time.perf_counter() - start
    source = name if body else args.boundary
    refuse_folded(args, source, outcome.quality["folded_cells"])

    def write_grid() -> None:
        export.write(outcome.data, out, args.format, extrude=args.extrude)

    def draw(tmp: Path) -> None:
        from pinn_engine.routes.render import render_body_png, render_png

        if not body:
            render_png(outcome.data, tmp, title=f"{args.method}: {Path(args.boundary).name}")
            return
        le, te = geometry.body.chord_points
        title = f"{args.method} {args.topology.upper()}-grid {name}"
        render_body_png(
            outcome.data, tmp, title=title, le=le, te=te, zoom=0.08 * geometry.body.chord
        )

    write_outputs(args, out, written, write_grid, report, draw, reports)
    if not args.quiet:  # after the files: a reader that stops early cannot stop a write
        grid_summary(report, settings, ni, nj, seconds)
    for warning, _ in grid_warnings(report, "cli"):  # printed with --quiet too
        warn(f"{source}: {warning}")
    return out
