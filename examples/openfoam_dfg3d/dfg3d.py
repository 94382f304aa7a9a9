"""The DFG 3D-1Z case's steps around OpenFOAM (docs/dfg3d.md): the inlet profile written
as values and the drag, lift and pressure difference read back.

    python examples/openfoam_dfg3d/dfg3d.py inlet CASE          # 0/U's inlet profile
    python examples/openfoam_dfg3d/dfg3d.py coefficients CASE   # Cd Cl dp of the last time

Schaefer and Turek (1996), test case 3D-1Z: a channel [0, 2.5] x [0, 0.41] x [0, 0.41], a
cylinder of diameter D = 0.1 along z through (0.5, 0.2), the inflow
U(y, z) = 16 Um y z (H - y) (H - z) / H^4 with Um = 0.45 (mean 0.2), nu = 1e-3 (Re 20);
Cd = 2 Fx / (U^2 D H), Cl = 2 Fy / (U^2 D H) with U = 0.2, and
dp = p(0.45, 0.2, 0.205) - p(0.55, 0.2, 0.205) (rho = 1).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "openfoam_dfg"))

from dfg import _last_time, _wall_values, face_centres  # noqa: E402

HEIGHT, PEAK = 0.41, 0.45  # the channel's height and width, and the inflow's peak speed
MEAN, DIAMETER = 0.2, 0.1  # the mean inflow speed and the cylinder's diameter
CENTRE = np.array([0.5, 0.2])  # the cylinder's axis (x, y)
# the intervals of Schaefer and Turek (1996) and the accurate values of Braack and Richter
# (2006), Cd 6.185333, Cl 0.009401 and dp 0.171007, rounded
PUBLISHED = {"Cd": (6.05, 6.25), "Cl": (0.008, 0.010), "dp": (0.165, 0.175)}
REFERENCE = {"Cd": 6.18533, "Cl": 0.009401, "dp": 0.1710}


def inlet(case: Path) -> None:
    """Write the inflow profile at the inlet's face centres into 0/U."""
    y, z = face_centres(case, "inlet")[:, 1:].T
    u = 16 * PEAK * y * z * (HEIGHT - y) * (HEIGHT - z) / HEIGHT**4
    values = "\n".join(f"({v:.10g} 0 0)" for v in u)
    path = case / "0" / "U"
    text = path.read_text()
    field = f"value           nonuniform List<vector>\n{len(u)}\n(\n{values}\n);"
    block = re.search(r"inlet\s*\{[^}]*\}", text)
    new = re.sub(r"value\s+[^;]*;", lambda _: field, block[0])
    path.write_text(text[: block.start()] + new + text[block.end() :])


def coefficients(case: Path) -> dict[str, float]:
    """Cd, Cl and dp of the case's last time: the forces from postProcessing/forces, the
    pressure at the cylinder's front and back at mid-height from the wall cells of the
    face rings nearest it (interpolated in angle to 180 and 0 degrees, then in z)."""
    rows = (case / "postProcessing" / "forces" / "0" / "force.dat").read_text().splitlines()
    last = [float(v) for v in re.sub(r"[()]", " ", rows[-1]).split()]
    scale = 0.5 * MEAN**2 * DIAMETER * HEIGHT
    centres = face_centres(case, "cylinder")
    p = _wall_values(case, _last_time(case) / "p", "cylinder")
    z = np.round(centres[:, 2], 9)
    levels = np.unique(z)
    below = levels[levels <= HEIGHT / 2].max()
    above = levels[levels >= HEIGHT / 2].min()
    sides = []
    for level in (below, above):
        ring = z == level
        xy = centres[ring, :2] - CENTRE
        angle = np.arctan2(xy[:, 1], xy[:, 0])
        order = np.argsort(angle)
        a, v = angle[order], p[ring][order]
        wrap = np.concatenate([a - 2 * np.pi, a, a + 2 * np.pi])
        sides.append(np.interp([np.pi, 0.0], wrap, np.tile(v, 3)))
    t = 0.5 if above == below else (HEIGHT / 2 - below) / (above - below)
    front, back = (1 - t) * sides[0] + t * sides[1]
    return {"Cd": last[1] / scale, "Cl": last[2] / scale, "dp": float(front - back)}


def main(argv: list[str]) -> None:
    step, case = argv[0], Path(argv[1])
    if step == "inlet":
        inlet(case)
    elif step == "coefficients":
        found = coefficients(case)
        print(" ".join(f"{k} {v:.6g}" for k, v in found.items()))
    else:
        raise SystemExit(f"unknown step {step!r}: inlet or coefficients")


if __name__ == "__main__":
    main(sys.argv[1:])
