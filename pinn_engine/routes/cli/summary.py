"""What a run tells on stderr besides its progress: the summary lines and the warnings."""

from __future__ import annotations

import sys

from pinn_engine.routes.summary_lines import blocks_lines, grid_lines
from pinn_engine.settings import Settings


def say(text: str) -> None:
    """One line on stderr, flushed (it stands between progress lines)."""
    print(text, file=sys.stderr, flush=True)


def warn(text: str) -> None:
    """A warning line, printed with --quiet too."""
    say(f"pinn-mesh: warning: {text}")


def grid_summary(report: dict, settings: Settings, ni: int, nj: int, seconds: float) -> None:
    """A four-sided grid's or a body's summary lines (``summary_lines.grid_lines``)."""
    for line in grid_lines(report, settings, ni, nj, seconds):
        say(line)


def blocks_summary(method: str, report: dict, seconds: float) -> None:
    """A multi-block grid's summary lines (``summary_lines.blocks_lines``)."""
    for line in blocks_lines(method, report, seconds):
        say(line)
