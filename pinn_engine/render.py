"""Off-screen pictures of grids coloured by an included-angle array (pyvista)."""

from __future__ import annotations

import os
from pathlib import Path

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")


def render_png(grid, path: str | os.PathLike, scalars: str = "MaxIncludedAngle",
               title: str | None = None, clim: tuple[float, float] | None = (90.0, 180.0),
               boundary=None, aux=None, window_size=(1200, 800),
               view: tuple[float, float, float, float] | None = None) -> Path:
    """Draw ``grid`` (a VTK or pyvista structured grid) with its edges, coloured by ``scalars``;
    ``view`` = (xmin, xmax, ymin, ymax) zooms on that box (e.g. a wall's first cells)."""
    import pyvista as pv

    pv.OFF_SCREEN = True
    mesh = pv.wrap(grid)
    plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
    plotter.set_background("white")
    plotter.add_mesh(mesh, scalars=scalars, preference="cell", show_edges=True,
                     edge_color="black", line_width=0.5, cmap="viridis", clim=clim,
                     scalar_bar_args={"title": f"{scalars} (deg)", "color": "black"})
    for extra, color in ((boundary, "red"), (aux, "orange")):
        if extra is not None:
            plotter.add_mesh(pv.wrap(extra), color=color, line_width=3)
    if title:
        plotter.add_text(title, font_size=12, color="black")
    plotter.view_xy()
    if view is None:
        plotter.camera.zoom(1.1)
    else:
        x0, x1, y0, y1 = view
        plotter.enable_parallel_projection()
        centre = ((x0 + x1) / 2, (y0 + y1) / 2)
        plotter.camera.focal_point = (*centre, 0.0)
        plotter.camera.position = (*centre, 10.0 * max(x1 - x0, y1 - y0))
        aspect = window_size[0] / window_size[1]
        plotter.camera.parallel_scale = max(y1 - y0, (x1 - x0) / aspect) / 2
    path = Path(path)
    path.parent.mkdir(parents=True, exist_ok=True)
    plotter.screenshot(str(path))
    plotter.close()
    return path
