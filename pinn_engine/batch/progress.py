"""The batch's progress line on stderr: cases done and failed, the rate and the time left."""

from __future__ import annotations

import sys
import time
from typing import TextIO

LINES_EVERY = 0.1  # off a terminal, a new line each time this share of the cases is done


class Bar:
    """One line redrawn in place on a terminal (carriage return), a line per tenth of the
    cases otherwise (a log file stays short)."""

    def __init__(self, total: int, skipped: int = 0, stream: TextIO | None = None) -> None:
        self.total, self.skipped = total, skipped
        self.done = self.failed = 0
        self.stream = stream or sys.stderr
        self.tty = self.stream.isatty()
        self.start = time.perf_counter()
        self.shown = -1
        self.width = 0  # the length of the line on the terminal

    def text(self) -> str:
        """The line: counts, rate and the time left at that rate."""
        elapsed = time.perf_counter() - self.start
        rate = self.done / elapsed if elapsed > 0 else 0.0
        left = (self.total - self.skipped - self.done) / rate if rate else float("nan")
        skipped = f", {self.skipped} skipped" if self.skipped else ""
        eta = f"{left:.0f} s left" if left == left else "time left unknown"
        count = self.done + self.skipped
        return (
            f"[{count}/{self.total}] {self.failed} failed{skipped}, "
            f"{rate * 60:.1f} cases/min, {eta}"
        )

    def update(self, failed: bool) -> None:
        """Count one case finished (``failed``: it got an error row) and redraw."""
        self.done += 1
        self.failed += int(failed)
        todo = max(self.total - self.skipped, 1)
        step = int(self.done / todo / LINES_EVERY)
        if self.tty:  # padded over the end of a longer earlier line
            text = self.text()
            print("\r" + text.ljust(self.width), end="", file=self.stream, flush=True)
            self.width = len(text)
        elif step != self.shown or self.done == todo:
            print(self.text(), file=self.stream, flush=True)
        self.shown = step

    def close(self) -> None:
        """End the line on a terminal."""
        if self.tty and self.done:
            print(file=self.stream, flush=True)
