"""The README's 3D picture: hexahedral grids cut open, coloured by ScaledJacobian.

Usage (from the repository root): ``.venv/bin/python scripts/hexa_picture.py
[-o docs/images/hexa_cut.png]``

Meshes the box with a bump and the sheared hexahedron with a wavy top of
``example_data/make_hexa.py`` at 21 x 21 x 21 by the default method (through pyvista's
``surface.pinn_mesh``, as a user would), keeps the cells from the middle j layer on (a cut
along grid surfaces, so the cut face shows whole cells with their edges) and draws them
off-screen (EGL, no display) with the 12 edges of the whole grid.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import pyvista as pv

from pinn_engine.routes.render import off_screen

ROOT = Path(__file__).resolve().parents[1]
SIZE = (21, 21, 21)  # SPEC 11's default size
CLIM = (0.6, 1.0)  # the ScaledJacobian range shown: the examples' cells lie within it
SHAPES = {  # stem: the picture's title
    "hexa_bump_box": "Box with a bump",
    "hexa_sheared_wavy": "Sheared hexahedron, wavy top",
}
VIEW = ((0.3, -1.0, 0.35), (0.0, 0.0, 1.0))  # from the cut face's side (-y), z up
FEATURE_ANGLE = 40.0  # the whole grid's 12 edges: where its boundary bends (SPEC 11's angle)
AMBIENT = 0.4  # light that keeps the colours readable on faces turned from the light


def draw(path: Path) -> Path:
    """The two cut grids side by side, one colour bar, written to ``path``."""
    with off_screen():
        plotter = pv.Plotter(off_screen=True, shape=(1, 2), window_size=(1800, 760), border=False)
        plotter.set_background("white")
        for column, (stem, title) in enumerate(SHAPES.items()):
            surface = pv.read(ROOT / "example_data" / f"{stem}.vtp")
            grid = surface.pinn_mesh(size=SIZE)
            method = grid.field_data["Method"][0]
            ni, nj, nk = grid.dimensions
            kept = grid.extract_subset((0, ni - 1, nj // 2, nj - 1, 0, nk - 1))
            plotter.subplot(0, column)
            plotter.add_mesh(
                kept,
                scalars="ScaledJacobian",
                preference="cell",
                show_edges=True,
                edge_color="black",
                line_width=0.6,
                cmap="viridis",
                clim=CLIM,
                ambient=AMBIENT,
                diffuse=1.0 - AMBIENT,
                show_scalar_bar=True,
                scalar_bar_args={
                    "title": "ScaledJacobian",
                    "color": "black",
                    "title_font_size": 20,
                    "label_font_size": 18,
                    "position_x": 0.2,
                    "position_y": 0.04,
                    "width": 0.6,
                },
            )
            edges = grid.extract_surface(algorithm="dataset_surface").extract_feature_edges(
                feature_angle=FEATURE_ANGLE
            )
            plotter.add_mesh(edges, color="gray", line_width=2)
            plotter.add_text(
                f"{title}: cut at the middle j layer ({method}, {ni} x {nj} x {nk})",
                font_size=13,
                color="black",
            )
            plotter.view_vector(VIEW[0], viewup=VIEW[1])
            plotter.enable_parallel_projection()  # the cut face undistorted
            plotter.camera.zoom(1.1)
        path.parent.mkdir(parents=True, exist_ok=True)
        plotter.screenshot(str(path))
        plotter.close()
    return path


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", type=Path, default=ROOT / "docs" / "images" / "hexa_cut.png")
    print(draw(parser.parse_args().o))


if __name__ == "__main__":
    main()
