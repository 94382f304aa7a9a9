"""Mesh a domain built in pyvista with pinn-mesh and save a picture.

    .venv/bin/python examples/pyvista_example.py                 # the network's training
    .venv/bin/python examples/pyvista_example.py --quick -o out/quick.png   # 5 L-BFGS steps

It trains the Winslow objective's network on the drawn line (``objective="winslow"``) to show
a network fitted once and evaluated at another size; the default objective gives the best
grid of the classical and quality-optimised ones without training (README).

Most of a run's time is importing torch, VTK and pyvista and rendering the picture, not
training: ``--quick`` took 5.0-5.6 s wall (5.3-5.5 CPU seconds, 0.3-0.6 of them training) on
the quiet 2-core machine (docs/routes.md, "Time to a first grid").

The domain is a quarter annulus with an elliptic outer arc; one auxiliary line runs from the
inner arc to the outer arc. ``boundary.pinn_mesh(...)`` is the pyvista accessor that
pinn-mesh registers (pyvista 0.48+); ``help(pv.PolyData.pinn_mesh)`` documents it.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path

import numpy as np

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")  # off-screen, no X

import pyvista as pv  # noqa: E402

import pinn_engine.routes.pyvista_accessor  # noqa: E402,F401  (only needed when not pip-installed)


def build_domain() -> tuple[pv.PolyData, pv.PolyData]:
    """Boundary (one closed polyline) and an auxiliary line, both made with pyvista."""
    inner = pv.CircularArc(
        pointa=[1, 0, 0], pointb=[0, 1, 0], center=[0, 0, 0], resolution=40
    ).points
    theta = np.linspace(0.0, np.pi / 2, 61)
    outer = np.column_stack([2.4 * np.cos(theta), 2.0 * np.sin(theta), np.zeros_like(theta)])
    bottom = pv.Line([1, 0, 0], [2.4, 0, 0], resolution=10).points
    top = pv.Line([0, 2, 0], [0, 1, 0], resolution=10).points
    # walk once around: bottom, outer arc, top, inner arc (reversed); drop shared corners
    ring = np.vstack([bottom[:-1], outer[:-1], top[:-1], inner[::-1][:-1]])
    boundary = pv.PolyData(ring, lines=[len(ring) + 1, *range(len(ring)), 0])
    # auxiliary line at 45 degrees, from the inner arc (a vertex of it) to the outer arc
    a = np.pi / 4
    aux = pv.Line([np.cos(a), np.sin(a), 0], [2.4 * np.cos(a), 2.0 * np.sin(a), 0], resolution=20)
    return boundary, aux


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("-o", "--output", default="out/pyvista_example.png")
    p.add_argument("--size", nargs=2, type=int, default=(41, 31), metavar=("NI", "NJ"))
    p.add_argument(
        "--quick", action="store_true", help="5 L-BFGS iterations instead of the default 120"
    )
    args = p.parse_args(argv)

    boundary, aux = build_domain()
    training = {"objective": "winslow", **({"lbfgs_iterations": 5} if args.quick else {})}
    grid = boundary.pinn_mesh(aux=aux, size=tuple(args.size), **training)  # trains once
    # the same network (trained for, and checked at, the first size) evaluated coarser
    preview = boundary.pinn_mesh(aux=aux, size=(11, 8), lattice=tuple(args.size), **training)
    print(
        f"{grid.dimensions} grid, {preview.dimensions} preview, "
        f"{boundary.pinn_mesh.trainings} training(s); worst MaxIncludedAngle "
        f"{grid['MaxIncludedAngle'].max():.1f} deg, folded cells {int(grid['Folded'].sum())}"
    )

    plotter = pv.Plotter(off_screen=True, window_size=(1000, 800))
    plotter.set_background("white")
    plotter.add_mesh(
        grid,
        scalars="MaxIncludedAngle",
        show_edges=True,
        cmap="viridis",
        clim=(90, 180),
        scalar_bar_args={"title": "MaxIncludedAngle (deg)", "color": "black"},
    )
    plotter.add_mesh(boundary, color="red", line_width=3)
    plotter.add_mesh(aux, color="orange", line_width=4)
    plotter.view_xy()
    out = Path(args.output)
    out.parent.mkdir(parents=True, exist_ok=True)
    plotter.screenshot(str(out))
    plotter.close()
    print(f"wrote {out}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
