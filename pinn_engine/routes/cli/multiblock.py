"""One run of a multi-block domain (SPEC 10)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from pinn_engine.errors import PinnMeshError, family_fallback_warning
from pinn_engine.routes.cli.options import (
    check_options,
    read_adapt_field,
    refuse_options,
    settings_from,
)
from pinn_engine.routes.cli.outputs import output_path, refuse_folded, write_outputs
from pinn_engine.routes.cli.progress import Progress
from pinn_engine.routes.cli.summary import blocks_summary, warn
from pinn_engine.settings import AUTO_BLOCKS, BLOCKS_METHOD, DEFAULT_SIZE, MULTIBLOCK_METHODS


def check_blocks(args: argparse.Namespace) -> None:
    """Refuse, in one line, what a multi-block run does not take (SPEC 10), and set its
    method's default."""
    from pinn_engine import job

    refuse_options(  # SPEC 10: what four-sided domains and bodies take and blocks do not
        args,
        set(job.only_for("four-sided", "blocks")) | set(job.only_for("body", "blocks")),
        "{} applies to four-sided domains and bodies, not to --blocks",
    )
    if args.boundary is None:
        raise PinnMeshError("give a boundary file (outer boundary and holes) with --blocks")
    if AUTO_BLOCKS in args.blocks and len(args.blocks) > 1:
        raise PinnMeshError(f"--blocks {AUTO_BLOCKS} proposes every edge: give no other --blocks")
    if args.save_blocks and Path(args.save_blocks).suffix.lower() != ".vtp":
        raise PinnMeshError(f"--save-blocks {args.save_blocks}: block edges are saved as .vtp")
    args.method = args.method or BLOCKS_METHOD
    if args.method not in MULTIBLOCK_METHODS:
        raise PinnMeshError(
            f"--method {args.method}: multi-block domains are meshed by "
            f"{', '.join(MULTIBLOCK_METHODS[:-1])} or {MULTIBLOCK_METHODS[-1]} in this build "
            f"(default {BLOCKS_METHOD})"
        )


def blocks_inputs(args: argparse.Namespace):
    """The settings and the geometry (``job.BlocksGeometry``) of a multi-block run's checked
    arguments (:func:`check_blocks`)."""
    from pinn_engine import job

    args.size = DEFAULT_SIZE  # checked by check_options, unused by multi-block
    check_options(args)
    # patch names, not sides: passed to the run, not to the four-sided settings
    spacing, orthogonal = args.spacing, [args.orthogonal] if args.orthogonal else []
    args.spacing, args.orthogonal = [], None
    settings = settings_from(args, kind="blocks")
    geometry = job.blocks_from_files(
        args.boundary,
        args.blocks,
        args.aux,
        args.patch,
        spacing,
        orthogonal,
        args.cells,
        args.grading,
        settings.cell_size,
    )
    return settings, geometry


def run_blocks(
    args: argparse.Namespace, written: list[Path], reports: list[dict] | None = None
) -> Path:
    """The boundary and its block edges into ``OUT.vtm`` (or a solver format); appends each
    output file to ``written`` once it is complete, and the report to ``reports``; with
    ``--model`` the family model's run (SPEC 16)."""
    from pinn_engine import job
    from pinn_engine.io.export import blocks_format, write_blocks
    from pinn_engine.io.export.edges import write_edges
    from pinn_engine.io.export.vtm import write_vtm
    from pinn_engine.io.fileio import check_writable

    check_blocks(args)
    out = output_path(args, f"{Path(args.boundary).stem}_{args.method}", "vtm")
    vtm = args.format is None and out.suffix.lower() == ".vtm"
    if vtm and args.extrude is not None:
        raise PinnMeshError(f"{out}: --extrude applies to .xyz, .cgns and --format openfoam")
    if vtm:
        check_writable(out)  # refused before meshing
    else:
        blocks_format(out, args.format, args.extrude)  # refused before meshing
    start = time.perf_counter()
    settings, geometry = blocks_inputs(args)
    field = read_adapt_field(args)
    read = time.perf_counter() - start
    with Progress(args.quiet) as progress:
        outcome = job.run(settings, geometry, progress, field=field, family=args.model)
    report = outcome.report
    report["timings"]["read"] = read
    folded = report["quality"]["folded_cells"]
    refuse_folded(args, args.boundary, folded)
    seconds = time.perf_counter() - start

    def write_grid() -> None:
        if vtm:
            write_vtm(outcome.data, out)
        else:
            write_blocks(outcome.data, out, args.format, extrude=args.extrude)

    def draw(tmp: Path) -> None:
        from pinn_engine.routes.render import render_blocks_png

        title = f"{args.method}: {Path(args.boundary).name}, {report['blocks']} blocks"
        render_blocks_png(outcome.data, tmp, title=title)

    write_outputs(args, out, written, write_grid, report, draw, reports)
    if not args.quiet:  # after the files: a reader that stops early cannot stop a write
        blocks_summary(args.method, report, seconds)
    if args.save_blocks:
        written.append(write_edges(outcome.edges, args.save_blocks))
        print(f"wrote {args.save_blocks} ({len(outcome.edges)} block edges)")
    if folded:
        warn(f"{args.boundary}: {folded} of {report['cells']} cells are folded")
    fallback = family_fallback_warning(report, "cli")
    if fallback:
        warn(f"{args.boundary}: {fallback}")
    return out
