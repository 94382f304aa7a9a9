"""One run of a blockMeshDict (SPEC 15): ``pinn-mesh system/blockMeshDict -o CASE --format
openfoam``, or ``-o OUT.vtm``, ``.cgns``, ``.su2`` or ``.msh``."""

from __future__ import annotations

import argparse
import time
from pathlib import Path

from pinn_engine.errors import PinnMeshError
from pinn_engine.routes.cli.options import refuse_others
from pinn_engine.routes.cli.outputs import keep_report, output_path
from pinn_engine.routes.cli.summary import say
from pinn_engine.routes.summary_lines import dictionary_line

# The outputs a dictionary's grid is written to (--format or the extension)
DICTIONARY_FORMATS = ("openfoam", "vtm", "cgns", "su2", "msh")


def _entries(extra: dict) -> dict[str, str]:
    """A patch's further entries (``neighbourPatch``, ``transform`` ...) as OpenFOAM text."""

    def text(value) -> str:
        if isinstance(value, list):
            return "(" + " ".join(text(v) for v in value) + ")"
        return str(value)

    return {k: text(v) for k, v in extra.items() if not isinstance(v, dict)}


def run_dictionary(
    args: argparse.Namespace, written: list[Path], reports: list[dict] | None = None
) -> Path:
    """The dictionary's grid into ``OUT.vtm`` or, with ``--format openfoam``, an OpenFOAM
    case with the dictionary's patches; appends each output file to ``written`` once it is
    complete, and the report to ``reports``."""
    from pinn_engine import job
    from pinn_engine.io.export import write_case
    from pinn_engine.io.export.openfoam import write_hex_polymesh
    from pinn_engine.settings import make_settings

    # any option the kind does not take is refused, not silently ignored
    refuse_others(
        args,
        "dictionary",
        "{} does not apply to a blockMeshDict: its blocks, counts, gradings and patches are "
        "the dictionary's",
    )
    method = args.method or job.DICTIONARY_METHODS[0]
    stem = Path(args.boundary).resolve().parent.parent.name or "blockMeshDict"
    out = output_path(args, f"{stem}_{method}", "vtm")
    foam = args.format == "openfoam"
    kind = "openfoam" if foam else (args.format or out.suffix.lower().lstrip("."))
    if kind not in DICTIONARY_FORMATS or (not foam and out.suffix.lower() != f".{kind}"):
        raise PinnMeshError(
            f"{out}: a blockMeshDict's grid is written as .vtm, .cgns, .su2, .msh or "
            "--format openfoam in this build"
        )
    try:
        settings = make_settings(method, kind="blocks3d", interfaces=args.interfaces)
    except ValueError as exc:
        raise PinnMeshError(str(exc)) from exc
    began = time.perf_counter()
    geometry = job.dictionary_from_file(args.boundary)
    outcome = job.run(settings, geometry)
    result = outcome.mesh
    if foam:
        entries = {p.name: _entries(p.extra) for p in geometry.dictionary.patches if p.extra}
        write_case(
            out,
            lambda mesh: write_hex_polymesh(
                result.points, result.faces, result.place.patches, mesh, entries
            ),
        )
    elif kind == "cgns":
        job.write_cgns(result, out)
    elif kind in ("su2", "msh"):
        job.write_unstructured(result, out, kind)
    else:
        from pinn_engine.io.export.vtm import write_vtm  # VTK's XML writer: for .vtm only

        write_vtm(outcome.data, out)
    written.append(out)
    outcome.report["timings"]["run"] = time.perf_counter() - began
    keep_report(args, outcome.report, written, reports)
    if not args.quiet:
        say(dictionary_line(outcome.report))
        print(f"wrote {out}" + ("" if args.output else " (the default place without -o)"))
    return out
