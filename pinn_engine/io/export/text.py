"""Fast formatted rows for the text formats (SU2, Gmsh, OpenFOAM)."""

from __future__ import annotations

import numpy as np

CHUNK = 65536  # rows per write


def write_rows(f, rows: np.ndarray, fmt: str) -> None:
    """Write each row of ``rows`` formatted by ``fmt`` (``%`` style, no newline) on its
    own line: one ``%`` over a chunk of rows, several times faster than ``np.savetxt``;
    rows of non-negative integers whose format has ``%d`` conversions alone are written by
    :func:`integer_text`, about twice as fast again (the same text)."""
    rows = np.asarray(rows)
    if rows.ndim == 1:
        rows = rows[:, None]
    pieces = fmt.split("%d")
    if (
        rows.dtype.kind in "iu"
        and len(pieces) == rows.shape[1] + 1
        and not any("%" in p for p in pieces)
        and rows.min(initial=0) >= 0
    ):
        for start in range(0, len(rows), CHUNK):
            f.write(integer_text(rows[start : start + CHUNK], pieces))
        return
    line = fmt + "\n"
    for start in range(0, len(rows), CHUNK):
        chunk = rows[start : start + CHUNK]
        f.write(line * len(chunk) % tuple(chunk.ravel().tolist()))


def integer_text(rows: np.ndarray, pieces: list[str]) -> str:
    """Rows (m, k) of non-negative integers as ``"%d".join(pieces)`` writes each, one a
    line: every row laid out at a fixed width (each number zero-padded to the widest),
    column by column, then the padding dropped by one mask, rather than formatting one
    number at a time."""
    widest = len(str(int(rows.max(initial=0))))
    values = rows.astype(np.int32 if widest < 10 else np.int64)  # int32 divides faster
    literals = [p.encode("ascii") for p in pieces[:-1]] + [(pieces[-1] + "\n").encode("ascii")]
    width = sum(len(lit) for lit in literals) + widest * values.shape[1]
    laid = np.empty((len(values), width), dtype=np.uint8)
    keep = np.ones((len(values), width), dtype=bool)
    at = 0
    for k, lit in enumerate(literals):
        laid[:, at : at + len(lit)] = np.frombuffer(lit, dtype=np.uint8)
        at += len(lit)
        if k == len(literals) - 1:
            break
        rest = values[:, k]
        for d in range(widest - 1, -1, -1):  # the last digit first
            rest, digit = np.divmod(rest, 10)
            laid[:, at + d] = digit + ord("0")
            if d:
                keep[:, at + d - 1] = rest > 0  # a leading zero is padding
        keep[:, at : at + widest] = np.logical_or.accumulate(keep[:, at : at + widest], axis=1)
        at += widest
    return laid[keep].tobytes().decode("ascii")
