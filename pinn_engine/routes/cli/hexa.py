"""One run of a six-faced 3D domain (SPEC 11)."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from pinn_engine.errors import PinnMeshError, grid_warnings
from pinn_engine.routes.cli.outputs import output_path, save_model, write_report
from pinn_engine.routes.cli.parser import build_parser, option_flags
from pinn_engine.routes.cli.summary import warn

# The options a six-faced surface takes; any other given is refused, not silently ignored
HEXA_OPTIONS = frozenset(
    {"boundary", "method", "size", "output", "quiet", "format", "patch"}
    | {"spacing", "orthogonal", "report", "save_model", "load_model"}
)


def run_hexa(args: argparse.Namespace, written: list[Path]) -> Path:
    """The surface's hexahedral grid into ``OUT`` (the formats and patches of SPEC 8, never
    extruded; patches named by side or by the input's FaceId; spacing and orthogonality on
    patches); appends each output file to ``written``
    once it is complete."""
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

    defaults = vars(build_parser().parse_args([]))
    flags = option_flags()
    for name, value in vars(args).items():
        if name not in HEXA_OPTIONS and value != defaults.get(name):
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
    out = output_path(args, f"{Path(args.boundary).stem}_{method}", "vts")
    export.output_format(out, args.format)  # refused before meshing
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
        patches=args.patch or None,  # checked before meshing
    )
    if args.save_model:
        save_model(result.model, args.save_model, written)
    began = time.perf_counter()
    export.write(hexa_grid(result, method), out, args.format)
    written.append(out)
    run = report(result, method)
    run["timings"]["write"] = time.perf_counter() - began
    if args.report:
        write_report(args.report, run, written)
    if not args.quiet:
        print(summary(result, method))
    for warning, _ in grid_warnings(run, "cli"):  # printed with --quiet too
        warn(warning)
    return out
