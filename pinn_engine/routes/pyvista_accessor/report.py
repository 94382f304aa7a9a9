"""A grid's report as a dict: what the ``Report`` field data of pinn-mesh's grids holds (as
JSON, so that it travels in ``.vts`` files): ``report``."""

from __future__ import annotations

import json

import pyvista as pv

from pinn_engine.errors import InputError

FIELD = "Report"  # the field data array holding the report's JSON


def report(grid: pv.DataObject) -> dict:
    """The report of a grid pinn-mesh made, as a dict: ``size``, ``method``, ``quality``
    (worst and mean angles, folded cells), ``training`` (for a network), ``settings`` and
    more; the same as the command line's ``--report`` file.

    A ``pyvista.MultiBlock`` from ``blocks=`` gives the whole domain's report (each block's
    own is ``report(blocks["block0"])``). Works as well on a grid read back from a ``.vts``
    file. Raises ``pinn_engine.errors.InputError`` for a grid without a report.

    >>> grid = boundary.pinn_mesh(size=(41, 21), method="elliptic")
    >>> pinn_engine.report(grid)["quality"]["worst_max_angle"]
    """
    if isinstance(grid, pv.MultiBlock):
        if not grid.n_blocks:
            raise InputError("an empty MultiBlock has no report")
        return report(grid[0])["multiblock"]
    data = getattr(grid, "field_data", {})
    if FIELD not in data:
        raise InputError(
            f"this {type(grid).__name__} has no {FIELD} field data: it was not made by "
            "pinn-mesh (or the field data was dropped)"
        )
    return json.loads(data[FIELD][0])
