"""A four-sided domain's settings (SPEC 5): the shared core as it is, with one table."""

from __future__ import annotations

from dataclasses import dataclass

from pinn_engine.settings import Settings, register


@register("four_sided")
@dataclass(frozen=True)
class FourSidedSettings(Settings):
    """The core's settings: a four-sided block's size, sides and training have no more."""
