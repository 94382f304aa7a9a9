"""An O- or C-grid's settings (SPEC 9): the shared core, a body's own (its topology, NACA
section and far field) and the rules that make its wall the one side spacing and
orthogonality apply to."""

from __future__ import annotations

from dataclasses import dataclass
from typing import ClassVar

from pinn_engine.errors import SettingsError
from pinn_engine.settings import (
    BODY_METHODS,
    OBJECTIVES,
    Interval,
    Options,
    Pattern,
    Places,
    Settings,
    register,
)

WALL = ("bottom",)  # a body's wall is its grid's side j = 0


@register("body")
@dataclass(frozen=True)
class BodySettings(Settings):
    """The core's settings and the body's: an O- or C-grid (``topology``), a NACA 4-digit
    section instead of a body file (``naca``, "": none), the far-field circle's radius in
    chords about mid-chord (a body given with its own far-field curve ignores it); the
    first-layer height off the wall is ``spacing`` of the side bottom."""

    CONSTRAINTS: ClassVar[dict] = {
        **Settings.CONSTRAINTS,
        "method": Options(BODY_METHODS),
        "objective": Options(tuple(o for o in OBJECTIVES if o != "quality")),
        "spacing": Places(True, WALL, "the first layer's height off the wall"),
        "orthogonal": Places(False, WALL, "the wall, left by grid lines at 90 degrees"),
        "topology": Options(("o", "c")),
        "naca": Pattern(r"(\d{4})?", "a NACA 4-digit code such as 0012"),
        "farfield": Interval(float, 1.0),  # chords: a far field inside the body is no domain
    }
    REFUSALS: ClassVar[dict[str, str]] = {
        "method": f"method {{value}}: O- and C-grids are made by {', '.join(BODY_METHODS)} "
        "({value} meshes four-sided domains only)",
        "objective": "objective {value}: for four-sided domains, not O- and C-grids",
        "spacing": "spacing: an O- or C-grid takes bottom=H (the first layer off the wall)",
        "orthogonal": "orthogonal: an O- or C-grid takes bottom (the body wall)",
        "topology": "topology {value!r}: use none, o, c",  # none: a four-sided domain
    }

    topology: str = "o"
    naca: str = ""
    farfield: float = 15.0

    def check(self) -> None:
        """The core's rules, tfi's straight columns first in the body's words."""
        self.check_start()
        if self.orthogonal and self.method == "tfi":
            raise SettingsError(
                "orthogonal bottom: tfi's straight columns cannot leave the wall at right "
                "angles; use method elliptic or pinn"
            )
        self.check_places()
