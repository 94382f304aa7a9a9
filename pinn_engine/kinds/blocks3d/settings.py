"""A blockMeshDict's settings (SPEC 15): the shared core and whether its blocks' interfaces
are solved; its blocks, counts, gradings and patches are the dictionary's."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from pinn_engine.kinds.blocks.settings import INTERFACES
from pinn_engine.settings import Settings, register


@register("blocks3d")
@dataclass(frozen=True)
class DictionarySettings(Settings):
    """The core's settings and the interfaces of the dictionary's blocks: solved (free) or
    held as the dictionary places them (fixed)."""

    CONSTRAINTS: ClassVar[dict] = {**Settings.CONSTRAINTS, "interfaces": INTERFACES}

    interfaces: str = "free"
