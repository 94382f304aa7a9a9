"""What the VTK filters (four-sided/body, multi-block, hexahedral) share: their input ports,
their setters and how they read a setting's forms (a ParaView enumeration's index, the
panel's text fields), their last update's outcome and the folded-cells warning."""

from __future__ import annotations

import numpy as np

from pinn_engine.errors import ROUTE_WORDS, SettingsError
from pinn_engine.routes.reporting import announce


def choice(value, options: tuple[str, ...], what: str) -> str:
    """Accept a name or an index into ``options`` (ParaView enumerations send indices)."""
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool):
        if 0 <= int(value) < len(options):
            return options[int(value)]
        raise SettingsError(f"{what} index {value} out of range 0..{len(options) - 1}")
    name = str(value).strip().lower()
    if name not in options:
        raise SettingsError(f"unknown {what} {value!r}; use one of {', '.join(options)}")
    return name


def setting_items(value, separators: str) -> tuple[str, ...]:
    """Items of a setting given as one string (split at whitespace and ``separators``: the
    panel's text field) or as a sequence of strings; None or "" is none."""
    if value is None:
        return ()
    if isinstance(value, str):
        for sep in separators:
            value = value.replace(sep, " ")
        return tuple(value.split())
    return tuple(str(v).strip() for v in value if str(v).strip())


def place_items(value) -> tuple[str, ...]:
    """``KEY=VALUE`` items of a setting whose keys may be names or points (``X,Y``): a
    string of items (separated by whitespace, ``;`` or, between items that each hold a
    ``=``, commas), a sequence of them, or a mapping ``{NAME: VALUE}`` or ``{(x, y):
    VALUE}``."""
    if hasattr(value, "items"):
        return tuple(
            f"{float(key[0])!r},{float(key[1])!r}={v}" if isinstance(key, tuple) else f"{key}={v}"
            for key, v in value.items()
        )
    out: list[str] = []
    for item in setting_items(value, ";"):
        parts = [part for part in item.split(",") if part]
        out += parts if all("=" in part for part in parts) else [item]
    return tuple(out)


def spacing_items(value) -> tuple[str, ...]:
    """``NAME=H`` or ``X,Y=H`` items of a first-edge spacing setting (:func:`place_items`,
    the lengths as floats)."""
    if hasattr(value, "items"):
        value = {key: repr(float(h)) for key, h in value.items()}
    return place_items(value)


def patch_setting(names) -> str | dict:
    """Patch names as a filter keeps them until its update checks them
    (``io.export.patches.patch_specs`` reads every form): the panel's string, a mapping,
    or a sequence joined by spaces; None is ""."""
    if not isinstance(names, str) and names is not None:
        names = dict(names) if hasattr(names, "items") else " ".join(map(str, names))
    return names or ""


class ModifiedOnChange:
    """Mixed into a ``VTKPythonAlgorithmBase``: settings change the algorithm's modified time
    only when they change, so an unchanged Apply does not run it again."""

    def _set(self, attr: str, value) -> None:
        if getattr(self, attr) != value:
            setattr(self, attr, value)
            self.Modified()


class PatchWalls(ModifiedOnChange):
    """Mixed into a filter whose patches are named (multi-block, hexahedral): first-edge
    spacing (``NAME=H`` items) and orthogonal patches, kept as items until its update checks
    them (the command line's ``--spacing`` and ``--orthogonal``)."""

    _spacing: tuple[str, ...] = ()  # NAME=H items
    _orthogonal: tuple[str, ...] = ()  # patch names

    def SetSpacing(self, items) -> None:
        self._set("_spacing", spacing_items(items))

    def GetSpacing(self) -> tuple[str, ...]:
        return self._spacing

    def SetOrthogonal(self, names) -> None:
        self._set("_orthogonal", setting_items(names, ",;"))

    def GetOrthogonal(self) -> tuple[str, ...]:
        return self._orthogonal


class LastOutcome:
    """Mixed into a ``VTKPythonAlgorithmBase`` whose class names its ``LABEL``: progress and
    messages under that name, and what the last update left (``RequestData`` sets
    ``_last_error``, ``_last_warning`` and ``_exception``), for scripts and pyvista."""

    LABEL = ""  # the filter's name in ParaView's menu, progress bar and Output Messages

    def GetLastError(self) -> str:
        """The line of the last failed update ("" after a successful one)."""
        return self._last_error

    def GetLastWarning(self) -> str:
        """The warning line of the last update ("" when it had none)."""
        return self._last_warning

    def GetLastException(self) -> Exception | None:
        """The exception of the last failed update (None after a successful one)."""
        return self._exception

    def _progress(self, fraction: float, phase: str) -> None:
        """Progress with the filter's name and the phase as its text: ParaView's progress bar
        shows it instead of the class name ("PythonAlgorithm")."""
        self.SetProgressText(f"{self.LABEL}: {phase}")
        self.UpdateProgress(fraction)

    def _report(self, message: str, warning: bool = False) -> None:
        """Keep ``message`` as the last error (or warning) line, and in ParaView announce it
        in Output Messages; the other routes raise or warn in their own words."""
        line = f"{self.LABEL}: {'warning: ' if warning else ''}{' '.join(str(message).split())}"
        if warning:
            self._last_warning = line
        else:
            self._last_error = line
        if self._route == "paraview":
            announce(self, line, warning)


class LineInputs(ModifiedOnChange):
    """Mixed into a ``VTKPythonAlgorithmBase``: port 0 takes every selected polydata (the
    boundary and the lines selected with it: ParaView's GUI connects them all there), the
    other ports more lines (optional)."""

    def FillInputPortInformation(self, port, info):
        info.Set(self.INPUT_REQUIRED_DATA_TYPE(), "vtkPolyData")
        info.Set(self.INPUT_IS_REPEATABLE(), 1)
        if port >= 1:
            info.Set(self.INPUT_IS_OPTIONAL(), 1)
        return 1


def folded_warning(report: dict, route: str, otherwise: str) -> str | None:
    """The warning of a grid with folded cells in ``route``'s words, or None: ``report``
    holds ``method``, ``cells`` and ``quality.folded_cells``; a tfi grid is pointed to the
    elliptic method, any other to ``otherwise`` (the fix of the filter's kind of input)."""
    folded = int(report["quality"]["folded_cells"])
    if not folded:
        return None
    if report["method"] == "tfi":
        fix = ROUTE_WORDS[route]["method"].format("elliptic")
    else:
        fix = otherwise
    verb = "is" if folded == 1 else "are"
    return f"{folded} of {report['cells']} cells {verb} folded; try {fix}"
