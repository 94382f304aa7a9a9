"""First-cell spacing and an orthogonal floor on the 3D bump box (SPEC 7 on SPEC 11's
patches): ``example_data/hexa_bump_box.vtp`` at 21 x 21 x 21, ``--spacing kmin=0.002`` (1/300
of the box's height) and ``--orthogonal kmin``, against the plain elliptic grid.

Usage: ``.venv/bin/python benchmarks/hexa_spacing.py [--out docs/hexa.md] [--no-images]``

Prints, per run: time, first edge / H off the floor (min, median, max over its nodes but the
four corners), the largest angle between a grid line leaving the floor and the floor's
normal (the two nodes nearest the floor's rim aside), the largest growth ratio of
consecutive edges along the k lines, mean and worst MaxIncludedAngle, min ScaledJacobian
and folded cells. Rewrites the table of the spacing section of docs/hexa.md and the
pictures ``docs/images/hexa_spacing_*.png``: the cut j = 10 through the bump's top, zoomed on
the bump, coloured by the MaxIncludedAngle of the cells behind it.
"""

from __future__ import annotations

import argparse
import os
import time
from pathlib import Path

import numpy as np
import torch

os.environ.setdefault("VTK_DEFAULT_OPENGL_WINDOW", "vtkEGLRenderWindow")

from pinn_engine.hexa.orthogonal import inner_angles  # noqa: E402
from pinn_engine.hexa.spacing import first_edges  # noqa: E402
from pinn_engine.kinds.hexa.mesh import mesh_surface  # noqa: E402
from pinn_engine.settings import make_settings  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
CASE = ROOT / "example_data" / "hexa_bump_box.vtp"
SIZE = (21, 21, 21)
H = 0.002  # the floor's first cell: 1/300 of the box's height (0.6)
RUNS = (  # (label, method, spacing, orthogonal, picture name or None)
    ("elliptic", "elliptic", {}, (), None),
    ("tfi, spacing", "tfi", {"kmin": H}, (), None),
    ("elliptic, spacing", "elliptic", {"kmin": H}, (), "spacing"),
    ("elliptic, orthogonal", "elliptic", {}, ("kmin",), None),
    ("elliptic, spacing + orthogonal", "elliptic", {"kmin": H}, ("kmin",), "orthogonal"),
)
WARM_UP = (5, 5, 5)  # a first run whose time is not reported
CUT = 10  # the j index of the pictures' cut (y = 0.5, through the bump's top)
VIEW = (0.55, 1.45, 0.0, 0.3)  # x, z box of the pictures: the bump and the cells above it
CLIM = (90.0, 140.0)  # MaxIncludedAngle colour range of the pictures (deg)
COMMAND = ".venv/bin/python benchmarks/hexa_spacing.py"


def _cut(g: np.ndarray, cells: np.ndarray):
    """The j = CUT plane as a flat structured grid in (x, z), with the MaxIncludedAngle of
    the cells between j = CUT and CUT + 1."""
    import pyvista as pv

    plane = g[:, CUT, :]
    grid = pv.StructuredGrid(
        plane[..., 0][..., None], plane[..., 2][..., None], 0 * plane[..., 0][..., None]
    )
    ni, nj, nk = (n - 1 for n in g.shape[:3])
    grid.cell_data["MaxIncludedAngle"] = cells.reshape(nk, nj, ni)[:, CUT, :].ravel()
    return grid


def measure(method: str, spacing: dict, orthogonal: tuple) -> tuple[dict, object]:
    """One run's figures and result."""
    start = time.perf_counter()
    r = mesh_surface(
        str(CASE), make_settings(method, size=SIZE, spacing=spacing, orthogonal=orthogonal)
    )
    seconds = time.perf_counter() - start
    edges = first_edges(r.grid, "kmin")
    edges[[0, 0, -1, -1], [0, -1, 0, -1]] = np.nan
    steps = np.linalg.norm(np.diff(r.grid, axis=2), axis=-1)
    growth = steps[..., 1:] / steps[..., :-1]
    row = {
        "seconds": seconds,
        "first": [float(f(edges) / H) for f in (np.nanmin, np.nanmedian, np.nanmax)],
        "angle": float(inner_angles(r.grid, "kmin").max()),
        "growth": float(np.maximum(growth, 1.0 / growth).max()),
        "mean": float(r.cells["MaxIncludedAngle"].mean()),
        "worst": float(r.cells["MaxIncludedAngle"].max()),
        "jacobian": float(r.cells["ScaledJacobian"].min()),
        "folded": int(r.cells["Folded"].sum()),
    }
    return row, r


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=str(ROOT / "docs" / "hexa.md"))
    parser.add_argument("--no-images", action="store_true")
    args = parser.parse_args()
    torch.set_num_threads(1)
    mesh_surface(
        str(CASE), make_settings("elliptic", size=WARM_UP)
    )  # imports and first calls out of the times
    lines = [
        "| run | time (s) | first edge / H: min, median, max | largest angle from the "
        "normal (deg) | largest growth ratio | MaxIncludedAngle mean / worst (deg) | "
        "min ScaledJacobian | folded |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for label, method, spacing, orthogonal, picture in RUNS:
        row, r = measure(method, spacing, orthogonal)
        first = ", ".join(f"{v:.3f}" for v in row["first"])
        lines.append(
            f"| {label} | {row['seconds']:.1f} | {first} | {row['angle']:.2f} | "
            f"{row['growth']:.3f} | {row['mean']:.2f} / {row['worst']:.2f} | "
            f"{row['jacobian']:.3f} | {row['folded']} |"
        )
        print(lines[-1], flush=True)
        if picture and not args.no_images:
            from pinn_engine.routes.render import render_png

            render_png(
                _cut(r.grid, r.cells["MaxIncludedAngle"]),
                ROOT / "docs" / "images" / f"hexa_spacing_{picture}.png",
                title=f"{label}: cut j = {CUT}",
                clim=CLIM,
                view=VIEW,
            )
    out = Path(args.out)
    text = out.read_text()
    start, end = "<!-- spacing-table:start -->", "<!-- spacing-table:end -->"
    head, rest = text.split(start)
    _, tail = rest.split(end)
    out.write_text(f"{head}{start}\n\n" + "\n".join(lines) + f"\n\n{end}{tail}")
    print(f"wrote {out} ({COMMAND})")


if __name__ == "__main__":
    main()
