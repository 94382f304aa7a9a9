"""One run of a six-faced 3D domain (SPEC 11)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from pinn_engine.errors import PinnMeshError, grid_warnings
from pinn_engine.routes.cli.options import check_options, refuse_others, settings_from
from pinn_engine.routes.cli.outputs import keep_report, output_path, save_model
from pinn_engine.routes.cli.summary import warn
from pinn_engine.routes.summary_lines import hexa_lines
from pinn_engine.settings import HEXA_METHOD, HEXA_SIZE


def run_hexa(
    args: argparse.Namespace, written: list[Path], reports: list[dict] | None = None
) -> Path:
    """The surface's hexahedral grid into ``OUT`` (the formats and patches of SPEC 8, never
    extruded; patches named by side or by the input's FaceId; spacing and orthogonality on
    patches); appends each output file to ``written`` once it is complete, and the report
    to ``reports``."""
    from pinn_engine import job
    from pinn_engine.io import export

    # any option the kind does not take is refused, not silently ignored
    refuse_others(args, "hexa", "{} applies to 2D domains, not to six-faced surfaces in this build")
    args.method = args.method or HEXA_METHOD
    args.size = tuple(args.size or HEXA_SIZE)
    if len(args.size) != len(HEXA_SIZE):
        raise PinnMeshError(
            f"--size {' '.join(map(str, args.size))}: a six-faced surface takes NI NJ NK"
        )
    out = output_path(args, f"{Path(args.boundary).stem}_{args.method}", "vts")
    export.output_format(out, args.format)  # refused before meshing
    if (args.save_model or args.load_model) and args.method != "pinn":
        raise PinnMeshError(
            f"--method {args.method} trains no network: --save-model and --load-model are pinn's"
        )
    check_options(args)
    settings = settings_from(args, args.size)
    began = time.perf_counter()
    geometry = job.hexa_from_file(args.boundary, args.patch or None)
    read = time.perf_counter() - began
    outcome = job.run(settings, geometry, model=args.load_model)
    if args.save_model:
        save_model(outcome.model, args.save_model, written)
    began = time.perf_counter()
    export.write(outcome.data, out, args.format)
    written.append(out)
    outcome.report["timings"].update(read=read, write=time.perf_counter() - began)
    keep_report(args, outcome.report, written, reports)
    if not args.quiet:
        print("\n".join(hexa_lines(outcome.report)))
    for warning, _ in grid_warnings(outcome.report, "cli"):  # printed with --quiet too
        warn(warning)
    return out
