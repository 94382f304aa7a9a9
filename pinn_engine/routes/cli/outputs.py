"""A run's files: where its grid goes, and the grid, report, picture and model written, each
complete or absent, with the line saying so."""

from __future__ import annotations

import argparse
import json
import time
from collections.abc import Callable
from pathlib import Path

from pinn_engine.errors import PinnMeshError


def output_path(args: argparse.Namespace, stem: str, extension: str) -> Path:
    """``-o``, else ``out/<stem>.<extension>`` (the --format's extension if given; a folder for
    OpenFOAM)."""
    suffix = "" if args.format == "openfoam" else f".{args.format or extension}"
    return Path(args.output or f"out/{stem}{suffix}")


def refuse_folded(args: argparse.Namespace, name: str, folded: int) -> None:
    """With --fail-on-folded, a grid with folded cells is an error and nothing is written."""
    if args.fail_on_folded and folded:
        raise PinnMeshError(f"{name}: {folded} folded cells (--fail-on-folded); no output written")


def save_model(model, path: str, written: list[Path]) -> None:
    """``model.save(path)`` (a fitted mesher or a hexahedral pinn), its folder made."""
    try:
        Path(path).parent.mkdir(parents=True, exist_ok=True)
        model.save(path)
    except (OSError, RuntimeError) as exc:
        raise PinnMeshError(f"{path}: cannot save the model ({exc})") from None
    written.append(Path(path))


def write_report(path: str, report: dict, written: list[Path]) -> None:
    """The run's report as JSON (--report)."""
    from pinn_engine.io.atomic import write_text_atomic  # io.fileio would import VTK

    write_text_atomic(path, json.dumps(report, indent=2, default=float))
    written.append(Path(path))


def keep_report(
    args: argparse.Namespace, report: dict, written: list[Path], reports: list[dict] | None
) -> None:
    """The run's report: appended to ``reports`` where the caller keeps it (a batch's summary
    row, without a file to write and read back), and written to --report if asked."""
    if reports is not None:
        reports.append(report)
    if args.report:
        write_report(args.report, report, written)


def write_outputs(
    args: argparse.Namespace,
    out: Path,
    written: list[Path],
    write_grid: Callable[[], None],
    report: dict,
    draw: Callable[[Path], None],
    reports: list[dict] | None = None,
) -> None:
    """The grid (``write_grid()`` into ``out``), then the report (with the grid's writing
    among its ``timings``, if it has them: :func:`keep_report`) and the picture
    (``draw(tmp)``) if asked, then the line saying what was written."""
    from pinn_engine.io.fileio import atomic_path

    began = time.perf_counter()
    write_grid()
    if "timings" in report:
        report["timings"]["write"] = time.perf_counter() - began
    written.append(out)
    keep_report(args, report, written, reports)
    if args.png:
        with atomic_path(args.png, suffix=Path(args.png).suffix or ".png") as tmp:
            draw(tmp)
        written.append(Path(args.png))
    default = "" if args.output else " (the default place without -o)"
    print(f"wrote {out}{default}" + (f" and {args.png}" if args.png else ""))
