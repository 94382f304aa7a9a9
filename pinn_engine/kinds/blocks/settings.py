"""A multi-block 2D domain's settings (SPEC 10): the shared core and the blocks' own (the
cells' size, the interfaces solved or held)."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from pinn_engine.settings import Interval, Options, Settings, register

INTERFACES = Options(
    ("free", "fixed"),
    "multi-block: free (interface nodes solved like interior nodes) or fixed (as drawn)",
)


@register("blocks")
@dataclass(frozen=True)
class BlocksSettings(Settings):
    """The core's settings and the blocks': the cells' length in user units (0: the domain's
    diagonal / 40), and whether interface nodes are solved (free) or stay on the drawn
    edges (fixed)."""

    CONSTRAINTS: ClassVar[dict] = {
        **Settings.CONSTRAINTS,
        "cell_size": Interval(
            float, 0.0, help="multi-block: cell size in your units; 0: the diagonal / 40"
        ),
        "interfaces": INTERFACES,
    }

    cell_size: float = 0.0
    interfaces: str = "free"
