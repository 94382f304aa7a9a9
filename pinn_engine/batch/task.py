"""One case in a worker: the single-run command's ``run`` on the case's arguments, turned
into a summary row whatever happens (a failure is the case's row, never the batch's end)."""

from __future__ import annotations

import argparse
import contextlib
import copy
import io
import math
import time
from pathlib import Path

from pinn_engine.batch.manifest import Case
from pinn_engine.errors import PinnMeshError, grid_warnings

# Paths of the options that name more outputs are relative to OUTDIR, beside the case's grid
OUTPUT_PATHS = ("report", "png", "save_model")
MESSAGE_CHARS = 300  # a summary message is one line of at most this many characters
DIED = "the worker meshing it died each time it was tried"  # the row of a case that kills


def output_of(args: argparse.Namespace, outdir: Path, name: str) -> Path:
    """Where the case's grid goes: ``OUTDIR/NAME`` with the extension of the format its
    options ask for (a folder for OpenFOAM, ``.vtm`` for multi-block)."""
    if args.blocks:
        return outdir / f"{name}.vtm"
    if args.format == "openfoam":
        return outdir / name
    return outdir / f"{name}.{args.format or 'vts'}"


def prepared(case: Case, outdir: Path) -> argparse.Namespace:
    """The case's single-run arguments with the batch's output and quiet progress (a copy:
    the run fills in defaults)."""
    args = copy.deepcopy(case.args)
    args.output = str(output_of(args, outdir, case.name))
    args.quiet = True
    for key in OUTPUT_PATHS:
        value = getattr(args, key)
        if value is not None:
            setattr(args, key, str(outdir / value))
    return args


def one_line(text: str) -> str:
    """``text`` as one summary line."""
    line = " ".join(str(text).split())
    return line if len(line) <= MESSAGE_CHARS else line[: MESSAGE_CHARS - 3] + "..."


def error_row(name: str, message: str, seconds: float = 0.0) -> dict:
    """The row of a case that gave no grid."""
    return {
        "name": name,
        "status": "error",
        "cells": "",
        "mean_max_angle": "",
        "worst_max_angle": "",
        "folded_cells": "",
        "seconds": round(seconds, 3),
        "message": one_line(message),
    }


def _row(name: str, report: dict, seconds: float) -> dict:
    """The row of a grid from its single-run report: ``warning`` with the command's
    warnings (folded cells, a stopped training, wall angles), else ``ok``."""
    q = report["quality"]
    warnings = [text for text, _ in grid_warnings(report, "cli")]
    return {
        "name": name,
        "status": "warning" if warnings else "ok",
        "cells": report.get("cells") or math.prod(n - 1 for n in report["size"]),
        "mean_max_angle": round(q["mean_max_angle"], 4),
        "worst_max_angle": round(q["worst_max_angle"], 4),
        "folded_cells": q["folded_cells"],
        "seconds": round(seconds, 3),
        "message": one_line("; ".join(warnings)),
    }


def run_case(name: str, args: argparse.Namespace) -> dict:
    """Mesh one case as ``pinn-mesh`` would (``dispatch.run``) and return its summary row; its
    printed lines are kept out of the worker's output."""
    # the workers' server imported it (warm.ENGINE): the batch's own process meshes nothing
    from pinn_engine.routes.cli.dispatch import run

    start = time.perf_counter()
    reports: list[dict] = []  # the run's report, kept in memory (--report writes it too)
    quiet = io.StringIO()
    try:
        with contextlib.redirect_stdout(quiet), contextlib.redirect_stderr(quiet):
            run(args, reports=reports)
        return _row(name, reports[-1], time.perf_counter() - start)
    except PinnMeshError as exc:
        return error_row(name, str(exc), time.perf_counter() - start)
    except OSError as exc:
        where = f"{exc.filename}: " if getattr(exc, "filename", None) else ""
        return error_row(name, f"{where}{exc.strerror or exc}", time.perf_counter() - start)
    except Exception as exc:  # a bug or a training failure: the case's row, not the batch's
        text = f"{type(exc).__name__}: {exc}"
        return error_row(name, text, time.perf_counter() - start)
