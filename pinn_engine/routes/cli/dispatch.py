"""Which run a command line is: multi-block, six-faced 3D, or four-sided domain or body."""

from __future__ import annotations

import argparse
from pathlib import Path

from pinn_engine.errors import PinnMeshError
from pinn_engine.io import childread
from pinn_engine.routes.cli.dictionary import run_dictionary
from pinn_engine.routes.cli.four_sided import run_four_sided
from pinn_engine.routes.cli.hexa import run_hexa
from pinn_engine.routes.cli.multiblock import run_blocks
from pinn_engine.routes.cli.options import refuse_options


def run(
    args: argparse.Namespace,
    written: list[Path] | None = None,
    reports: list[dict] | None = None,
) -> Path:
    """One meshing run of the domain kind ``job.kind_of`` names: a blockMeshDict's blocks
    (SPEC 15), with --blocks a multi-block
    domain (SPEC 10), for a surface with faces a six-faced 3D domain (SPEC 11), else a
    four-sided domain or, with --topology, --naca or a .dat, a body (SPEC 5 and 9); appends
    each output file to ``written`` once it is complete, and the run's report to ``reports``
    (a batch reads its summary row there)."""
    written = written if written is not None else []
    if args.cells and not args.blocks:
        raise PinnMeshError("--cells applies to multi-block domains (--blocks); use --size")
    if args.save_blocks and not args.blocks:
        raise PinnMeshError("--save-blocks writes the block edges of --blocks (or --blocks auto)")
    # the input files read while the run imports the engine
    childread.prefetch([args.boundary, *(args.aux or []), *(args.blocks or [])])
    try:
        return _run_kind(args, written, reports)
    finally:
        childread.stop_pending()  # what a refused run prefetched and never read


def _run_kind(args: argparse.Namespace, written: list[Path], reports: list[dict] | None) -> Path:
    """The run of the domain kind ``job.kind_of`` names."""
    from pinn_engine.job import kind_of, only_for

    kind = kind_of(args.boundary, bool(args.blocks), body=bool(args.topology or args.naca))
    if kind == "dictionary":
        return run_dictionary(args, written, reports)
    if kind != "hexa":
        refuse_options(
            args,
            only_for("hexa", "four-sided", "body", "blocks"),
            "{} applies to six-faced surfaces (an .stl), not to 2D domains",
        )
    if kind in ("four-sided", "body"):
        refuse_options(
            args,
            only_for("blocks", "four-sided", "body"),
            "{} applies to multi-block domains (--blocks)",
        )
    if kind == "blocks":
        return run_blocks(args, written, reports)
    if kind == "hexa":
        return run_hexa(args, written, reports)
    return run_four_sided(args, written, kind == "body", reports)
