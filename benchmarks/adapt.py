"""Grids adapted to analytic fields (SPEC 14): the field's interpolation error before and
after, the worst cell, the time.

Each shape's unadapted grid (``--base``: ``default``, the grid the command gives without
``--adapt``, as a user adapts it, or ``elliptic``; at ``--size``; C-grids of NACA 0012 and,
held out, NACA 4412; multi-block grids of the cylinder channel and, held out, the tee, the
Y-branch, the L-shape and the backward-facing step) is adapted to fields given on a fine
image (``FINE`` points a side over the shape's box, as a solver's result would be): a
curved tanh front, a straight oblique one, a boundary layer along the lowest wall and a
Lamb-Oseen vortex's speed, each scaled to the shape's box. The interpolation error is the
bilinear interpolant of the nodes' values against the field at ``QUAD`` x ``QUAD`` points
inside every cell: the L2 norm (cells weighted by area) and the largest. The tuning shapes
are the examples, the held-out ones ``example_data/holdout`` (no constant was set on them).

    .venv/bin/python benchmarks/adapt.py [--set tuning|holdout|bodies|blocks|all] [--beta 5 10 20]
        [--size 41 31] [--base default|elliptic] [--speed [--runs 3]] [--unguarded]

``--set blocks``: the multi-block grids alone (the bodies less the C-grids).
``--speed`` times adapting a 201 x 201 four-sided grid (40 000 cells) against meshing it
(CPU and wall seconds, ``--runs`` rounds interleaved);
``--unguarded`` solves the C-grid and the multi-block grid at fixed strengths without the
guard, free and with the shear cap: the error ratio and the cells over the guard's bound
(where the bound binds).
"""

from __future__ import annotations

import argparse
import resource
import time
from pathlib import Path

import numpy as np
import torch
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonDataModel import vtkImageData

from pinn_engine.adapt import Field
from pinn_engine.adapt.grids import DEFAULT_STRENGTH, adapt_grids
from pinn_engine.geometry.boundary import Boundary
from pinn_engine.io.fileio import read_boundary_points
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.quality import cell_quality
from pinn_engine.settings import make_settings

ROOT = Path(__file__).resolve().parent.parent
TUNING = ["wavy.vtp", "bump_channel.vtp", "concave.vtp", "fig2.vtp"]
HOLDOUT = [f"holdout/h0{k}_wavy.vtp" for k in range(0, 8, 2)] + [
    "holdout/h08_notch_rect.vtp",
    "holdout/h11_notch_round_v.vtp",
]
FINE = 801  # points a side of the field's image
QUAD = 4  # sample points a cell side for the interpolation error
BASES = {"default": "pinn", "elliptic": "elliptic"}  # --base: the method of the unadapted grid


def fields(box: np.ndarray) -> dict:
    """The analytic fields on a shape's box ((x0, y0), (x1, y1)), as f(x, y)."""
    (x0, y0), (x1, y1) = box
    size = max(x1 - x0, y1 - y0)

    def unit(x, y):
        return (x - x0) / size, (y - y0) / size

    def front(x, y):
        u, v = unit(x, y)
        return np.tanh((np.hypot(u - 0.1, v - 0.1) - 0.55) / 0.02)

    def oblique(x, y):
        u, v = unit(x, y)
        return np.tanh((0.8 * u + 0.6 * v - 0.5) / 0.02)

    def layer(x, y):
        _, v = unit(x, y)
        return 1.0 - np.exp(-v / 0.03)

    def vortex(x, y):
        u, v = unit(x, y)
        cu, cv = 0.5 * (x1 - x0) / size, 0.5 * (y1 - y0) / size
        r2 = np.maximum((u - cu) ** 2 + (v - cv) ** 2, 1e-12)
        return (1.0 - np.exp(-r2 / 0.04**2)) / np.sqrt(r2)

    return {"front": front, "oblique": oblique, "layer": layer, "vortex": vortex}


def image(f, box: np.ndarray, name: str = "u") -> vtkImageData:
    """``f`` on a FINE x FINE image over ``box`` (a little larger)."""
    (x0, y0), (x1, y1) = box
    pad = 0.01 * max(x1 - x0, y1 - y0)
    x0, y0, x1, y1 = x0 - pad, y0 - pad, x1 + pad, y1 + pad
    im = vtkImageData()
    im.SetDimensions(FINE, FINE, 1)
    im.SetOrigin(x0, y0, 0.0)
    im.SetSpacing((x1 - x0) / (FINE - 1), (y1 - y0) / (FINE - 1), 1.0)
    x, y = np.meshgrid(np.linspace(x0, x1, FINE), np.linspace(y0, y1, FINE))
    arr = numpy_to_vtk(np.ascontiguousarray(f(x.ravel(), y.ravel())), deep=True)
    arr.SetName(name)
    im.GetPointData().AddArray(arr)
    return im


def interpolation_error(grids: list[np.ndarray], f) -> tuple[float, float]:
    """L2 (area-weighted) and largest error of the bilinear interpolant of ``f``'s node
    values, at QUAD x QUAD points inside every cell of every block."""
    u = (np.arange(QUAD) + 0.5) / QUAD
    uu, vv = (a.ravel() for a in np.meshgrid(u, u))
    weights = [(1 - uu) * (1 - vv), uu * (1 - vv), uu * vv, (1 - uu) * vv]
    total, area, largest = 0.0, 0.0, 0.0
    for g in grids:
        corners = [g[:-1, :-1], g[:-1, 1:], g[1:, 1:], g[1:, :-1]]
        values = f(g[..., 0], g[..., 1])
        fc = [values[:-1, :-1], values[:-1, 1:], values[1:, 1:], values[1:, :-1]]
        p = sum(w[None, None, :, None] * c[..., None, :] for w, c in zip(weights, corners))
        interp = sum(w[None, None, :] * c[..., None] for w, c in zip(weights, fc))
        e = interp - f(p[..., 0], p[..., 1])
        d1, d2 = corners[2] - corners[0], corners[3] - corners[1]
        a = 0.5 * np.abs(d1[..., 0] * d2[..., 1] - d1[..., 1] * d2[..., 0])
        total += float((a * (e**2).mean(axis=-1)).sum())
        area += float(a.sum())
        largest = max(largest, float(np.abs(e).max()))
    return float(np.sqrt(total / area)), largest


def four_sided(path: str, size: tuple[int, int], method: str = "elliptic") -> list[np.ndarray]:
    """The ``method``'s grid of a four-sided example."""
    boundary = Boundary.from_points(read_boundary_points(ROOT / "example_data" / path))
    mesher = Mesher(make_settings(method, lattice=size)).fit(boundary)
    return [mesher.predict(*size).points]


def c_grid(
    naca: str = "0012",
    size: tuple[int, int] = (161, 41),
    farfield: float = 5.0,
    wall=1e-3,
    method: str = "elliptic",
) -> list[np.ndarray]:
    """An airfoil's C-grid (the body kind's ``method`` grid): NACA ``naca``, ``size`` nodes,
    far field ``farfield`` chords away, first cell ``wall`` chords thick."""
    from pinn_engine.bodies.airfoil import circle, load_body
    from pinn_engine.kinds.body.mesh import mesh_body

    settings = make_settings(method, topology="c", farfield=farfield)
    body = load_body(naca=naca, te="sharp")
    result = mesh_body(body, circle(body, farfield), "c", method, *size, settings, wall, None)
    return [result.points]


def blocks(name: str = "cylinder_channel", method: str = "elliptic") -> list[np.ndarray]:
    """An example's multi-block ``method`` grid (cell size 0.05)."""
    from pinn_engine.job import blocks_from_files, run

    geometry = blocks_from_files(
        ROOT / f"example_data/{name}.vtp", [ROOT / f"example_data/{name}_blocks.vtp"]
    )
    return run(make_settings(method, cell_size=0.05), geometry).grids


def bodies(method: str = "elliptic") -> dict:
    """The C-grids and multi-block grids by set: the tuning ones (NACA 0012, the cylinder
    channel) and the held-out ones (NACA 4412 at other counts, far field and wall spacing;
    the tee, the Y-branch, the L-shape and the step), each a function giving its blocks."""
    return {
        "tuning": {
            "C-grid NACA 0012": lambda: c_grid(method=method),
            "cylinder channel blocks": lambda: blocks(method=method),
        },
        "holdout": {
            "C-grid NACA 4412 181 x 49": lambda: c_grid("4412", (181, 49), 8.0, 5e-4, method),
            "tee blocks": lambda: blocks("tee", method),
            "Y-branch blocks": lambda: blocks("ybranch", method),
            "L-shape blocks": lambda: blocks("lshape", method),
            "step blocks": lambda: blocks("step", method),
        },
    }


def measure(name: str, grids: list[np.ndarray], betas: list[float], rows: list) -> None:
    """Adapt ``grids`` to every field at every strength; print and collect a row each."""
    flat = np.vstack([g.reshape(-1, 2) for g in grids])
    box = np.array([flat.min(axis=0), flat.max(axis=0)])
    for field_name, f in fields(box).items():
        field = Field(image(f, box), "u", field_name)
        before = interpolation_error(grids, f)
        for beta in betas:
            start = time.perf_counter()
            out = adapt_grids(grids, field, beta)
            seconds = time.perf_counter() - start
            after = interpolation_error(out.grids, f)
            r = out.report
            worst = r["worst_max_angle"]
            folded = sum(int(cell_quality(g)["Folded"].sum()) for g in out.grids)
            row = (
                name,
                field_name,
                beta,
                after[0] / before[0],
                after[1] / before[1],
                worst["before"],
                worst["after"],
                folded,
                r["equidistribution_cv"]["before"],
                r["equidistribution_cv"]["after"],
                r["strength_used"],
                seconds,
            )
            rows.append(row)
            print(
                f"| {name} | {field_name} | {beta:g} | {row[3]:.2f} | {row[4]:.2f} | "
                f"{row[5]:.1f} | {row[6]:.1f} | {folded} | {row[8]:.2f} | {row[9]:.2f} | "
                f"{row[10]:.2f} | {seconds:.1f} |",
                flush=True,
            )


def cpu_seconds() -> float:
    """This process's user and system CPU time (all its threads)."""
    usage = resource.getrusage(resource.RUSAGE_SELF)
    return usage.ru_utime + usage.ru_stime


def timed(job, *args) -> tuple[object, float, float]:
    """``job(*args)``'s result, its CPU seconds and its wall seconds."""
    cpu, wall = cpu_seconds(), time.perf_counter()
    out = job(*args)
    return out, cpu_seconds() - cpu, time.perf_counter() - wall


def speed(runs: int) -> None:
    """Adapting a 201 x 201 grid (40 000 cells) against meshing it by the default method and
    by the elliptic one, ``runs`` rounds interleaved (mesh, mesh, adapt): the median CPU
    and wall seconds of each."""
    boundary = Boundary.from_points(read_boundary_points(ROOT / "example_data/wavy.vtp"))
    size = (201, 201)

    def mesh(method: str) -> np.ndarray:
        return Mesher(make_settings(method, lattice=size)).fit(boundary).predict(*size).points

    times: dict[str, list[tuple[float, float]]] = {"pinn": [], "elliptic": [], "adapt": []}
    for _ in range(runs):
        for method in ("pinn", "elliptic"):
            grid, cpu, wall = timed(mesh, method)
            times[method].append((cpu, wall))
        flat = grid.reshape(-1, 2)
        box = np.array([flat.min(axis=0), flat.max(axis=0)])
        field = Field(image(fields(box)["front"], box), "u", "front")
        out, cpu, wall = timed(adapt_grids, [grid], field, DEFAULT_STRENGTH)
        times["adapt"].append((cpu, wall))
    median = {k: np.median(np.array(v), axis=0) for k, v in times.items()}
    report = out.report
    solves = sum(len(t["solves"]) for t in report["tries"])
    ratio = report["interpolation_error"]["after"] / report["interpolation_error"]["before"]
    print(
        f"201 x 201 wavy, median of {runs} (CPU / wall seconds): meshing pinn "
        f"{median['pinn'][0]:.2f} / {median['pinn'][1]:.2f}, elliptic "
        f"{median['elliptic'][0]:.2f} / {median['elliptic'][1]:.2f}; adapting "
        f"{median['adapt'][0]:.2f} / {median['adapt'][1]:.2f} (strength used "
        f"{report['strength_used']:g}, {report.get('form', 'isotropic')}, {solves} solves; error "
        f"after/before {ratio:.2f})"
    )


def unguarded() -> None:
    """The parameter-space solve alone (no guard, no tries) on the C-grid and the blocks,
    free and with the shear cap: each strength's L2 error ratio and the cells over the
    worst cell's bound (where the bound binds)."""
    from pinn_engine.adapt.guard import GUARD_DEGREES, offending
    from pinn_engine.adapt.nodes import node_graph
    from pinn_engine.adapt.parametric import ParameterSpace

    for name, grids in (("C-grid NACA 0012", c_grid()), ("cylinder blocks", blocks())):
        flat = np.vstack([g.reshape(-1, 2) for g in grids])
        box = np.array([flat.min(axis=0), flat.max(axis=0)])
        graph = node_graph(grids, None)
        worst = max(cell_quality(g)["MaxIncludedAngle"].max() for g in grids)
        for field_name, f in fields(box).items():
            sample = Field(image(f, box), "u", field_name).sample
            space = ParameterSpace(graph, sample, worst + GUARD_DEGREES)
            before = interpolation_error(grids, f)[0]
            for capped in (False, True):
                line = []
                for beta in (1.0, 2.0, 5.0, 10.0, 20.0):
                    out = space.solve(np.full(len(graph.points), beta), capped=capped)
                    ratio = interpolation_error(graph.grids(out.points), f)[0] / before
                    over = int(offending(graph, out.points, worst + GUARD_DEGREES).sum())
                    line.append(f"{ratio:.2f} ({over})")
                form = "capped" if capped else "free"
                print(f"| {name} | {field_name} | {form} | " + " | ".join(line) + " |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--set", default="all", choices=("tuning", "holdout", "bodies", "blocks", "all")
    )
    parser.add_argument("--beta", type=float, nargs="+", default=[DEFAULT_STRENGTH])
    parser.add_argument("--size", type=int, nargs=2, default=(41, 31))
    parser.add_argument("--base", default="default", choices=tuple(BASES))
    parser.add_argument("--speed", action="store_true")
    parser.add_argument("--unguarded", action="store_true")
    parser.add_argument("--runs", type=int, default=3, help="--speed's interleaved rounds")
    args = parser.parse_args()
    torch.set_num_threads(1)
    if args.speed:
        speed(args.runs)
        return
    if args.unguarded:
        unguarded()
        return
    print(
        "| shape | field | beta | L2 error after/before | max error after/before | worst "
        "before | worst after | folded | CV before | CV after | strength used | seconds |"
    )
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    rows: list = []
    shapes = {"tuning": TUNING, "holdout": HOLDOUT}
    for key in ("tuning", "holdout"):
        if args.set in (key, "all"):
            for path in shapes[key]:
                grids = four_sided(path, tuple(args.size), BASES[args.base])
                measure(f"{key}: {Path(path).stem}", grids, args.beta, rows)
    if args.set in ("bodies", "blocks", "all"):
        for key, shapes in bodies(BASES[args.base]).items():
            for name, make in shapes.items():
                if args.set != "blocks" or "blocks" in name:
                    measure(f"{key}: {name}", make(), args.beta, rows)

    def group(row: tuple) -> str:
        kind = "C-grid" if "C-grid" in row[0] else "multi-block" if "blocks" in row[0] else None
        return f"{kind or 'four-sided'}, " + row[0].split(":")[0]

    groups = {"all": rows}
    for row in rows:
        groups.setdefault(group(row), []).append(row)
    print()
    for label, members in groups.items():
        if members:
            ratios = np.array([r[3] for r in members])
            print(
                f"{label}: L2 error after/before median {np.median(ratios):.2f}, worst "
                f"{ratios.max():.2f}; at most 0.5 in {int((ratios <= 0.5).sum())} of {len(members)}"
            )


if __name__ == "__main__":
    main()
