"""A VTK algorithm run for pyvista: its inputs on their ports, its exceptions raised in
pyvista's words, its output wrapped, its report read and its warnings given at the line of
the caller outside this package."""

from __future__ import annotations

import functools
import inspect
import numbers
import os
import sys
import warnings
from collections.abc import Callable, Iterable, Iterator
from contextlib import contextmanager
from pathlib import Path

import pyvista as pv
from vtkmodules.vtkCommonDataModel import vtkPolyData

from pinn_engine.errors import (
    FamilyFallbackWarning,
    FoldedCellsWarning,
    InputError,
    KeywordError,
    SettingsError,
    family_fallback_warning,
    grid_warnings,
    unknown_keyword,
)
from pinn_engine.routes.filters import folded_warning
from pinn_engine.routes.pyvista_accessor.inputs import polydata_list

ROUTE = "pyvista"  # the route whose words errors and warnings are given in


@contextmanager
def pyvista_words() -> Iterator[None]:
    """Raise an ``InputError`` of the block in pyvista's words, without the chained one."""
    try:
        yield
    except InputError as exc:
        raise exc.for_route(ROUTE) from None


def public(name: str, also: Iterable[str] = ()) -> Callable:
    """A public function of this route with its keywords checked as pyvista users expect:
    an unknown one (none of its parameters, nor of ``also``, the names its ``**kwargs``
    take) or a wrong count of arguments is a ``KeywordError`` (a ``TypeError``) in one line
    that names the function as users call it, ``name``, and the nearest keyword."""

    def decorate(func: Callable) -> Callable:
        signature = inspect.signature(func)
        named = [
            p.name
            for p in signature.parameters.values()
            if p.kind in (p.POSITIONAL_OR_KEYWORD, p.KEYWORD_ONLY) and p.name != "self"
        ]
        known = {*named, *also}

        @functools.wraps(func)
        def checked(*args, **kwargs):
            for keyword in kwargs:
                if keyword not in known:
                    raise unknown_keyword(keyword, [*named, *also], name)
            try:
                signature.bind(*args, **kwargs)
            except TypeError as exc:
                raise KeywordError(f"{name}: {exc}") from None
            return func(*args, **kwargs)

        return checked

    return decorate


def node_counts(value, keyword: str = "size") -> tuple[int, ...]:
    """``value`` (a sequence of node counts, as ``size=(41, 21)``) as ints; a string, a
    count that is not whole or not a number is refused in one line naming ``keyword``."""
    example = f"e.g. {keyword}=(41, 21)"
    if isinstance(value, str | bytes) or not isinstance(value, Iterable):
        raise SettingsError(f"{keyword}={value!r}: give the node counts as a tuple, {example}")
    counts = tuple(value)
    for n in counts:
        whole = isinstance(n, numbers.Integral) or (
            isinstance(n, numbers.Real) and float(n).is_integer()
        )
        if isinstance(n, bool) or not whole:
            shown = tuple(c.item() if hasattr(c, "item") else c for c in counts)
            raise SettingsError(f"{keyword}={shown}: node counts are whole numbers, {example}")
    return tuple(int(n) for n in counts)


def run(
    alg,
    boundary: Callable[[], vtkPolyData],
    lines=None,
    what: str = "aux",
    progress_bar: bool = False,
) -> pv.DataObject:
    """Give a filter the ``boundary`` (port 0) and the ``lines`` (port 1: auxiliary lines or
    block edges, the argument ``what``), run it (with pyvista's progress bar where
    ``progress_bar``) and return its output; its error is raised in pyvista's words."""
    with pyvista_words():
        alg.SetInputDataObject(0, boundary())
        for poly in polydata_list(lines, what):
            alg.AddInputDataObject(1, poly)
    update(alg, progress_bar)
    return pv.wrap(alg.GetOutput())


def update(alg, progress_bar: bool) -> None:
    """Run a filter or reader (with pyvista's progress bar where ``progress_bar``); its error
    is raised in pyvista's words."""
    if progress_bar:
        with pv.ProgressMonitor(alg, message=alg.LABEL):
            alg.Update()
    else:
        alg.Update()
    error = alg.GetLastException()
    if error is not None:
        raise error.for_route(ROUTE) if isinstance(error, InputError) else error


def give_field(alg, adapt) -> None:
    """Connect ``adapt=(dataset, "ARRAY")`` (a dataset, or a file pyvista reads: an
    OpenFOAM case's ``.foam`` too) to the filter's Field input (SPEC 14)."""
    if adapt is None:
        return
    if not (isinstance(adapt, (tuple, list)) and len(adapt) == 2 and isinstance(adapt[1], str)):
        raise SettingsError(
            f'adapt={type(adapt).__name__}: give (dataset, "ARRAY"), e.g. '
            '(pv.read("case.foam"), "U")'
        )
    data, array = adapt
    if isinstance(data, (str, os.PathLike)):
        if not Path(data).is_file():
            raise InputError("file not found", str(data))
        data = pv.read(data)
    alg.SetInputDataObject(alg.FIELD_PORT, data)
    alg.SetAdaptArray(array)


def _caller_level() -> int:
    """The ``stacklevel`` of the first caller outside this package, for ``warnings.warn``
    called from the function calling this one."""
    frame, level = sys._getframe(1), 1
    while frame is not None and frame.f_globals.get("__package__") == __package__:
        frame, level = frame.f_back, level + 1
    return level


def warn_about(report: dict) -> None:
    """A ``TrainingStoppedWarning``, ``FoldedCellsWarning`` and ``WallAngleWarning`` where
    they apply, attributed to the first caller outside this package."""
    level = _caller_level()
    for text, category in grid_warnings(report, ROUTE):
        warnings.warn(text, category, stacklevel=level)


def warn_folded(report: dict, otherwise: str) -> None:
    """A ``FoldedCellsWarning`` where ``report`` counts folded cells (``otherwise``: the fix
    of a grid not made by tfi), and a ``FamilyFallbackWarning`` where a family model's grid
    was not kept, attributed to the first caller outside this package."""
    level = _caller_level()
    found = (
        (folded_warning(report, ROUTE, otherwise), FoldedCellsWarning),
        (family_fallback_warning(report, ROUTE), FamilyFallbackWarning),
    )
    for text, category in found:
        if text:
            warnings.warn(text, category, stacklevel=level)
