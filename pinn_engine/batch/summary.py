"""``OUTDIR/summary.csv`` (SPEC 12): one row a case, written atomically, read back by a rerun
to skip what is done."""

from __future__ import annotations

import csv
import io
from pathlib import Path

from pinn_engine.io.fileio import write_text_atomic

COLUMNS = (
    "name", "status", "cells", "mean_max_angle", "worst_max_angle", "folded_cells",
    "seconds", "message",
)  # fmt: skip
DONE = ("ok", "warning")  # a grid was written: a rerun skips the case
FILE = "summary.csv"
NUMBERS = {"cells": int, "mean_max_angle": float, "worst_max_angle": float,
           "folded_cells": int, "seconds": float}  # fmt: skip


def read_rows(outdir: Path) -> dict[str, dict]:
    """The rows of an earlier run by case name (none when there is no readable summary)."""
    try:
        text = (outdir / FILE).read_text()
    except (OSError, UnicodeDecodeError):
        return {}
    rows = csv.DictReader(io.StringIO(text))
    return {row["name"]: _typed(row) for row in rows if row.get("name") and row.get("status")}


def _typed(row: dict) -> dict:
    """A row read back with its numbers as numbers (an empty field stays empty)."""
    try:
        return {k: NUMBERS[k](v) if k in NUMBERS and v else (v or "") for k, v in row.items()}
    except ValueError:  # a hand-edited row: kept as text, and the case is not skipped
        return {**row, "status": "unknown"}


def write_rows(outdir: Path, rows: list[dict]) -> Path:
    """Write the summary (complete or absent, never half-written)."""
    out = io.StringIO()
    writer = csv.DictWriter(out, COLUMNS, extrasaction="ignore", lineterminator="\n")
    writer.writeheader()
    writer.writerows(rows)
    return write_text_atomic(outdir / FILE, out.getvalue())
