"""The backward-facing step case's steps around OpenFOAM (examples/openfoam_step/run.sh): the
inlet's parabola written as values, and the reattachment length read back.

    python examples/openfoam_step/step.py inlet CASE          # 0/U's inlet: the parabola
    python examples/openfoam_step/step.py reattachment CASE   # x_r of the last time

The step of example_data/step.vtp: height S = 1, the inlet channel y in [1, 2] from x = -2,
the step's foot at x = 0, the outlet at x = 6 (expansion ratio 2); the inflow is the
developed parabola of mean speed 1, nu 0.02 (Re = U_mean 2 S / nu = 100). The reattachment
length x_r / S is where the flow along the floor behind the step turns forward again.
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "openfoam_dfg"))

from dfg import face_centres  # noqa: E402

BOTTOM, TOP = 1.0, 2.0  # the inlet channel's walls
MEAN = 1.0  # the inflow's mean speed
FLOOR = 1e-9  # a cell touches the floor behind the step when its lowest point is this low


def inlet(case: Path, bottom: float = BOTTOM, top: float = TOP, mean: float = MEAN) -> None:
    """Write the developed parabola of mean speed ``mean`` between the inlet channel's walls
    ``bottom`` and ``top`` at the inlet's face centres into 0/U."""
    y = face_centres(case, "inlet")[:, 1]
    u = 6 * mean * (y - bottom) * (top - y) / (top - bottom) ** 2
    values = "\n".join(f"({v:.10g} 0 0)" for v in u)
    path = case / "0" / "U"
    text = path.read_text()
    field = f"value           nonuniform List<vector>\n{len(u)}\n(\n{values}\n);"
    block = re.search(r"inlet\s*\{[^}]*\}", text)
    new = re.sub(r"value\s+[^;]*;", lambda _: field, block[0])
    path.write_text(text[: block.start()] + new + text[block.end() :])


def reattachment(case: Path) -> float:
    """x_r: where the wall shear on the floor behind the step turns from backward to
    forward at the end of the longest stretch of backward flow: the main eddy's (a fine
    grid also resolves the nested corner eddies in the step's foot, the innermost one's
    backward flow ending a few thousandths of S from it). The shear at each floor cell is
    the slope at the wall of the parabola through the wall (no slip), that cell's and the
    next cell up's streamwise velocities (second order, as the solve; the first cell's
    velocity alone would place x_r where the zero line of u crosses the first cell's
    centre, an O(h) bias), the crossing between cells the cubic through the four nearest."""
    import pyvista as pv

    (case / "case.foam").touch()
    reader = pv.get_reader(str(case / "case.foam"))
    reader.set_active_time_value(reader.time_values[-1])
    mesh = reader.read()["internalMesh"]
    centres, u = mesh.cell_centers().points, mesh.cell_data["U"][:, 0]
    lowest = np.array([mesh.get_cell(k).bounds[2] for k in range(mesh.n_cells)])
    floor = np.flatnonzero((lowest < FLOOR) & (centres[:, 0] > 0))
    floor = floor[np.argsort(centres[floor, 0])]
    shear = []
    for k in floor:
        up = max(mesh.cell_neighbors(k, "faces"), key=lambda j: centres[j, 1])
        (y1, u1), (y2, u2) = (centres[k, 1], u[k]), (centres[up, 1], u[up])
        shear.append((u1 * y2**2 - u2 * y1**2) / (y1 * y2 * (y2 - y1)))
    x, shear = centres[floor, 0], np.array(shear)
    ends = np.flatnonzero((shear[:-1] < 0) & (shear[1:] >= 0))  # backward flow turns forward
    starts = [np.flatnonzero(shear[: e + 1] >= 0)[-1] + 1 if np.any(shear[: e + 1] >= 0) else 0
              for e in ends]  # fmt: skip
    k = ends[np.argmax(x[ends] - x[starts])]  # the main eddy's end, not a corner eddy's
    near = slice(max(k - 1, 0), k + 3)
    cubic = np.polynomial.Polynomial.fit(x[near], shear[near], min(3, len(x[near]) - 1))
    roots = [r.real for r in cubic.roots() if abs(r.imag) < 1e-12 and x[k] <= r.real <= x[k + 1]]
    linear = x[k] - shear[k] * (x[k + 1] - x[k]) / (shear[k + 1] - shear[k])
    return float(roots[0] if roots else linear)


if __name__ == "__main__":
    step, where = sys.argv[1], Path(sys.argv[2])
    if step == "inlet":
        inlet(where)
    else:
        print(f"reattachment {reattachment(where):.5f}")
