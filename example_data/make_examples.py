"""Regenerate the bundled example boundaries and auxiliary lines.

Run ``.venv/bin/python example_data/make_examples.py``; it rewrites the ``.vtp``/``.csv`` files
beside it. Each boundary is a closed counter-clockwise ring starting at the bottom-left corner.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

HERE = Path(__file__).resolve().parent


def polydata(lines: list[np.ndarray], closed: bool) -> vtkPolyData:
    """Polydata with one polyline per array; a closed ring repeats its first point id."""
    pts = np.vstack(lines)
    poly = vtkPolyData()
    points = vtkPoints()
    points.SetData(numpy_to_vtk(np.column_stack([pts, np.zeros(len(pts))]), deep=True))
    poly.SetPoints(points)
    cells = vtkCellArray()
    start = 0
    for line in lines:
        ids = list(range(start, start + len(line)))
        cells.InsertNextCell(len(ids) + closed, ids + ids[:1] * closed)
        start += len(line)
    poly.SetLines(cells)
    return poly


def write(poly: vtkPolyData, name: str) -> None:
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(str(HERE / name))
    writer.SetInputData(poly)
    writer.SetDataModeToAscii()
    writer.Write()


def ring(bottom, right, top, left) -> np.ndarray:
    """Join four sides given as (n, 2) arrays walking counter-clockwise; drop shared corners."""
    return np.vstack([bottom[:-1], right[:-1], top[:-1], left[:-1]])


def curve(fx, fy, n: int) -> np.ndarray:
    s = np.linspace(0.0, 1.0, n)
    return np.column_stack([fx(s), fy(s)])


def wavy() -> tuple[np.ndarray, list[np.ndarray]]:
    """Four deformed, wavy sides, like the paper's first case."""
    bottom = curve(lambda s: 4 * s, lambda s: 0.25 * np.sin(2 * np.pi * s), 81)
    right = curve(lambda s: 4 + 0.2 * np.sin(np.pi * s), lambda s: 2 * s, 41)
    top = curve(lambda s: 4 - 4 * s, lambda s: 2 + 0.3 * np.sin(3 * np.pi * s), 81)
    left = curve(lambda s: -0.15 * np.sin(np.pi * (1 - s)), lambda s: 2 - 2 * s, 41)
    # the vertical through x = 2 (bottom at y = 0, top at y = 1.7) and the horizontal y = 1
    aux = [
        curve(lambda s: 2 + 0 * s, lambda s: 1.7 * s, 41),
        curve(lambda s: -0.15 + 4.35 * s, lambda s: 1 + 0 * s, 81),
    ]
    return ring(bottom, right, top, left), aux


def fig2() -> tuple[np.ndarray, list[np.ndarray]]:
    """Like the paper's Fig. 2: straight left and bottom, a bulging top and a slanted right.

    Auxiliary lines: one parallel to the left boundary, one parallel to the bottom.
    """
    bottom = curve(lambda s: 3 * s, lambda s: 0 * s, 61)
    right = curve(lambda s: 3 + 0.8 * s, lambda s: 1.5 * s, 41)
    top = curve(lambda s: 3.8 - 3.8 * s, lambda s: 1.5 + 0.9 * np.sin(np.pi * s) ** 2, 81)
    left = curve(lambda s: 0 * s, lambda s: 1.5 - 1.5 * s, 41)
    x_aux = 1.2
    y_top = 1.5 + 0.9 * np.sin(np.pi * (3.8 - x_aux) / 3.8) ** 2
    aux = [
        curve(lambda s: x_aux + 0 * s, lambda s: y_top * s, 41),
        curve(lambda s: 3.4 * s, lambda s: 0.75 + 0 * s, 61),
    ]
    return ring(bottom, right, top, left), aux


def _arc(cx: float, cy: float, r: float, a0: float, a1: float, n: int) -> np.ndarray:
    a = np.linspace(a0, a1, n)
    return np.column_stack([cx + r * np.cos(a), cy + r * np.sin(a)])


def concave() -> tuple[np.ndarray, list[np.ndarray]]:
    """An L-shaped domain: the top side turns a re-entrant corner, and TFI folds cells there.

    Corners: (0, 0), (3, 0), (3, 1) and (1, 3); the outer corner at (0, 3) is rounded so that
    it is part of the left side, not a fifth corner.
    """
    bottom = curve(lambda s: 3 * s, lambda s: 0 * s, 61)
    right = curve(lambda s: 3 + 0 * s, lambda s: s, 11)
    top = np.vstack(
        [
            curve(lambda s: 3 - 1.5 * s, lambda s: 1 + 0 * s, 31)[:-1],
            _arc(1.5, 1.5, 0.5, -np.pi / 2, -np.pi, 17)[:-1],  # re-entrant bend, rounded
            curve(lambda s: 1 + 0 * s, lambda s: 1.5 + 1.5 * s, 31),
        ]
    )
    left = np.vstack(
        [
            curve(lambda s: 1 - 0.5 * s, lambda s: 3 + 0 * s, 6)[:-1],
            _arc(0.5, 2.5, 0.5, np.pi / 2, np.pi, 16)[:-1],  # convex outer bend, rounded
            curve(lambda s: 0 * s, lambda s: 2.5 - 2.5 * s, 26),
        ]
    )
    aux = [
        curve(lambda s: 3 * s, lambda s: 0.5 + 0 * s, 31),  # parallel to the bottom
        curve(lambda s: 2 + 0 * s, lambda s: s, 11),
    ]  # parallel to the right
    return ring(bottom, right, top, left), aux


def bump_channel() -> np.ndarray:
    """The boundary-layer example (SPEC 7): a channel 3 long and 1 high with a smooth bump
    of 15 % of the height on its floor (sin^2 over 1 < x < 2, zero slope at its feet)."""
    bottom = curve(
        lambda s: 3 * s,
        lambda s: np.where((s > 1 / 3) & (s < 2 / 3), 0.15 * np.sin(np.pi * (3 * s - 1)) ** 2, 0.0),
        241,
    )
    right = curve(lambda s: 3 + 0 * s, lambda s: s, 41)
    top = curve(lambda s: 3 - 3 * s, lambda s: 1 + 0 * s, 61)
    left = curve(lambda s: 0 * s, lambda s: 1 - s, 41)
    return ring(bottom, right, top, left)


CASES = {"wavy": wavy, "fig2": fig2, "concave": concave}


def main() -> None:
    for name, make in CASES.items():
        boundary, aux = make()
        write(polydata([boundary], closed=True), f"{name}.vtp")
        write(polydata(aux, closed=False), f"{name}_aux.vtp")
    write(polydata([bump_channel()], closed=True), "bump_channel.vtp")
    boundary, _ = wavy()
    np.savetxt(HERE / "wavy.csv", boundary, delimiter=",", header="x,y", comments="", fmt="%.10g")


if __name__ == "__main__":
    main()
