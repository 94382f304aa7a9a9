"""Off-screen pictures of grids coloured by an included-angle array (pyvista)."""

from __future__ import annotations

import contextlib
import os
from collections.abc import Iterator
from pathlib import Path

import numpy as np

from pinn_engine.geometry.plane import in_plane_axes


@contextlib.contextmanager
def off_screen() -> Iterator[None]:
    """Off-screen rendering for the block (EGL unless the user chose a render window; no
    X display needed), the process's environment and pyvista's setting restored after."""
    import pyvista as pv

    previous = os.environ.get("VTK_DEFAULT_OPENGL_WINDOW")
    flag = pv.OFF_SCREEN
    os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")
    pv.OFF_SCREEN = True
    try:
        yield
    finally:
        pv.OFF_SCREEN = flag
        if previous is None:
            os.environ.pop("VTK_DEFAULT_OPENGL_WINDOW", None)


def render_png(
    grid,
    path: str | os.PathLike,
    scalars: str = "MaxIncludedAngle",
    title: str | None = None,
    clim: tuple[float, float] | None = (90.0, 180.0),
    boundary=None,
    aux=None,
    window_size=(1200, 800),
    view: tuple[float, float, float, float] | None = None,
) -> Path:
    """Draw ``grid`` (a VTK or pyvista structured grid) with its edges, coloured by ``scalars``;
    ``view`` = (xmin, xmax, ymin, ymax) zooms on that box of a grid in a plane z = const (e.g.
    a wall's first cells)."""
    import pyvista as pv

    with off_screen():
        mesh = pv.wrap(grid)
        plotter = pv.Plotter(off_screen=True, window_size=list(window_size))
        plotter.set_background("white")
        plotter.add_mesh(
            mesh,
            scalars=scalars,
            preference="cell",
            show_edges=True,
            edge_color="black",
            line_width=0.5,
            cmap="viridis",
            clim=clim,
            scalar_bar_args={"title": f"{scalars} (deg)", "color": "black"},
        )
        for extra, color in ((boundary, "red"), (aux, "orange")):
            if extra is not None:
                plotter.add_mesh(pv.wrap(extra), color=color, line_width=3)
        if title:
            plotter.add_text(title, font_size=12, color="black")
        normal = np.linalg.svd(mesh.points - mesh.points.mean(axis=0), full_matrices=False)[2][2]
        if abs(normal[2]) > 1 - 1e-9:  # a grid in a plane z = const
            plotter.view_xy()
        else:  # look at the grid's own plane, its v axis up
            plotter.view_vector(normal, viewup=in_plane_axes(normal)[1])
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


# The colour bar of a body's pictures: whole degrees, on a white ground below the trailing
# edge; its labels and then its title go under the bar (render_body_png), apart, where
# VTK's default (both above a short horizontal bar) lets them run into each other
BODY_BAR = {
    "title": "MaxIncludedAngle (deg)",
    "color": "black",
    "fmt": "%.0f",
    "n_labels": 5,
    "title_font_size": 18,
    "label_font_size": 16,
    "position_x": 0.1,
    "position_y": 0.02,
    "width": 0.8,
    "height": 0.14,
    "background_color": "white",
    "fill": True,
}


def render_body_png(
    grid,
    path: str | os.PathLike,
    title: str | None = None,
    le=(0.0, 0.0),
    te=(1.0, 0.0),
    zoom: float = 0.06,
    window_size=(1800, 640),
) -> Path:
    """An O- or C-grid in three panels: the whole domain, and zoomed on the leading edge
    ``le`` and the trailing edge ``te`` (boxes ``zoom`` wide, in the grid's units)."""
    import pyvista as pv

    with off_screen():
        mesh = pv.wrap(grid)
        plotter = pv.Plotter(
            off_screen=True, shape=(1, 3), window_size=list(window_size), border=False
        )
        bounds = mesh.bounds
        whole = (
            0.5 * (bounds[0] + bounds[1]),
            0.5 * (bounds[2] + bounds[3]),
            0.5 * max(bounds[1] - bounds[0], bounds[3] - bounds[2]),
        )
        panels = (
            ("whole", whole),
            ("leading edge", (le[0] + 0.25 * zoom, le[1], 0.5 * zoom)),
            ("trailing edge", (te[0], te[1], 0.5 * zoom)),
        )
        for k, (name, (cx, cy, half)) in enumerate(panels):
            plotter.subplot(0, k)
            plotter.set_background("white")
            plotter.add_mesh(
                mesh.copy(),
                scalars="MaxIncludedAngle",
                preference="cell",
                show_edges=True,
                edge_color="black",
                line_width=0.4,
                cmap="viridis",
                clim=(90.0, 130.0),
                show_scalar_bar=k == 2,
                scalar_bar_args=BODY_BAR,
            )
            if k == 2:
                plotter.scalar_bar.SetTextPositionToPrecedeScalarBar()
            plotter.add_text(
                name if not (title and k == 0) else f"{title}: {name}", font_size=10, color="black"
            )
            plotter.view_xy()
            cam = plotter.camera
            cam.parallel_projection = True
            cam.focal_point = (cx, cy, 0.0)
            cam.position = (cx, cy, 10.0 * max(half, 1.0))
            cam.parallel_scale = half
        path = Path(path)
        path.parent.mkdir(parents=True, exist_ok=True)
        plotter.screenshot(str(path))
        plotter.close()
    return path


def render_blocks_png(dataset, path: str | os.PathLike, title: str | None = None) -> Path:
    """A multi-block grid (a ``vtkMultiBlockDataSet`` of structured grids in a plane
    z = const) coloured by MaxIncludedAngle, each block's outline drawn in red."""
    import pyvista as pv

    blocks = pv.wrap(dataset)
    outlines = pv.merge(
        [
            pv.wrap(block).extract_feature_edges(
                boundary_edges=True,
                feature_edges=False,
                manifold_edges=False,
                non_manifold_edges=False,
            )
            for block in blocks
        ]
    )
    return render_png(blocks.combine(), path, title=title, boundary=outlines)
