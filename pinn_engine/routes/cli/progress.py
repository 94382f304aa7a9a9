"""Training progress on stderr while a run meshes."""

from __future__ import annotations

import sys


class Progress:
    """Progress on stderr: one updating line on a terminal, a line per 10 %% otherwise; as a
    context manager, the terminal's line ended however the run ends."""

    def __init__(self, quiet: bool) -> None:
        self.quiet = quiet
        self.tty = sys.stderr.isatty()
        self.last = -1

    def __call__(self, info: dict) -> None:
        if self.quiet:
            return
        done = info["step"] / max(info["total"], 1)
        decile = int(done * 10)
        if info["phase"] == "prepare":  # a stage before training (kinds.body.mesh.STAGES)
            text = f"[{info['stage']}]"
        else:
            text = f"[{info['phase']:5s} {info['step']:5d}/{info['total']}] loss {info['loss']:.3e}"
        if self.tty:
            print("\r" + text, end="", file=sys.stderr, flush=True)
        elif decile != self.last:
            print(text, file=sys.stderr, flush=True)
        self.last = decile

    def __enter__(self) -> Progress:
        return self

    def __exit__(self, *exc_info: object) -> None:
        if self.tty and not self.quiet and self.last >= 0:
            print(file=sys.stderr)
