"""O- and C-grids around NACA sections with pinn-mesh's pyvista route, with pictures.

    .venv/bin/python examples/airfoil_example.py -o out/airfoils     # about a minute

Makes the NACA 0012 O-grid (blunt trailing edge) and C-grid (sharp), and a NACA 4412 C-grid
from ``example_data/naca4412.dat``, each 240 x 64 with a first layer of 2e-4 chord, and
writes ``<name>.vts``, ``<name>.su2`` and ``<name>.png`` (whole domain, leading and trailing
edges) for each.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")  # off-screen, no X
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from pinn_engine.routes.pyvista_accessor import pinn_mesh, save_mesh  # noqa: E402
from pinn_engine.routes.render import render_body_png  # noqa: E402


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-o", "--out", default="out/airfoils", help="output folder")
    p.add_argument("--method", default="pinn", choices=("pinn", "elliptic", "tfi"))
    args = p.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    cases = {
        "naca0012_o": dict(boundary=None, naca="0012", topology="o"),
        "naca0012_c": dict(boundary=None, naca="0012", topology="c"),
        "naca4412_c": dict(boundary=str(ROOT / "example_data" / "naca4412.dat"), topology="c"),
    }
    for name, kw in cases.items():
        boundary = kw.pop("boundary")
        grid = pinn_mesh(
            boundary,
            size=(240, 64),
            method=args.method,
            farfield=15,
            spacing={"bottom": 2e-4},
            **kw,
        )
        q = grid.field_data
        print(
            f"{name}: mean MaxIncludedAngle {q['mean_max_angle'][0]:.2f}, worst "
            f"{q['worst_max_angle'][0]:.2f} deg, {int(q['folded_cells'][0])} folded"
        )
        grid.save(out / f"{name}.vts")
        save_mesh(grid, out / f"{name}.su2")
        render_body_png(grid, out / f"{name}.png", title=f"{args.method} {name}", zoom=0.08)
    return 0


if __name__ == "__main__":
    sys.exit(main())
