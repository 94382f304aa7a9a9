"""What the two VTK filters (the four-sided/body one and the multi-block one) share: their
input ports, their setters and how a ParaView enumeration's value is read."""

from __future__ import annotations

import numpy as np


def choice(value, options: tuple[str, ...], what: str) -> str:
    """Accept a name or an index into ``options`` (ParaView enumerations send indices)."""
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        if 0 <= int(value) < len(options):
            return options[int(value)]
        raise ValueError(f"{what} index {value} out of range 0..{len(options) - 1}")
    name = str(value).strip().lower()
    if name not in options:
        raise ValueError(f"unknown {what} {value!r}; use one of {', '.join(options)}")
    return name


class LineInputs:
    """Mixed into a ``VTKPythonAlgorithmBase``: port 0 takes every selected polydata (the
    boundary and the lines selected with it: ParaView's GUI connects them all there), the
    other ports more lines (optional); settings change the algorithm's modified time only when they
    change, so an unchanged Apply does not run it again."""

    def FillInputPortInformation(self, port, info):
        info.Set(self.INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData")
        info.Set(self.INPUT_IS_REPEATABLE(), 1)
        if port >= 1:
            info.Set(self.INPUT_IS_OPTIONAL(), 1)
        return 1

    def _set(self, attr: str, value) -> None:
        if getattr(self, attr) != value:
            setattr(self, attr, value)
            self.Modified()
