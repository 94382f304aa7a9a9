"""The default's grids beside the peers' on the same domains (docs/peers.md): mean and worst
``MaxIncludedAngle`` and checkMesh's largest non-orthogonality and skewness.

Usage: ``.venv/bin/python benchmarks/peers_quality.py [--size 41x21] [--airfoils DIR]
[--per-half 4] [--construct2d PATH] [--jobs 2] [--out docs/peers.md]``

- **Four-sided shapes**, the tuning set (``example_data/hard/`` and the examples ``concave``,
  ``fig2``, ``wavy``) and the held-out set (``example_data/holdout/``), without lines, at
  ``--size``: pinn-mesh's default (``objective best``), ``elliptic`` and ``tfi`` on the same
  boundary nodes; gmsh (its Python API) given those nodes as one transfinite surface smoothed
  by ``SMOOTHING`` sweeps (``multiblock_gmsh.gmsh_grids``); blockMesh given the same block, its
  four corners and a ``polyLine`` through each side's nodes (``peers.block_mesh``; it places
  its own nodes along them, evenly by length), its points read back.
- **Airfoils**, real files (``--airfoils``: a folder of UIUC ``.dat`` files, default
  Construct2D's sample airfoils) split into halves by ``airfoil_set.half`` (the tuning half and
  the report half), the first ``--per-half`` of each: O-grids of 250 x 80 and C-grids of
  300 x 80, first layer 1e-5 chord, far field 15 chords (``airfoil_set``'s settings), the
  default and ``elliptic`` beside Construct2D's hyperbolic grid with its smoothing.
- **3D**: the bend's blockMeshDict (``example_data/blockmesh/bend``: three blocks with arc
  edges) meshed by pinn-mesh and by blockMesh (``blockmesh3d.run_case``), and the 90-degree
  bend surface ``example_data/hexa_bend.vtp`` by pinn-mesh's hexahedral route (default,
  ``elliptic``, ``tfi``) beside blockMesh's one block with arc edges at the same counts.

The 2D grids' checkMesh figures are computed as OpenFOAM computes them
(``blocks3d.checks.figures`` on the grid extruded one cell thick, coincident nodes merged);
checkMesh itself runs on every blockMesh case (and on the 3D cases), and the page gives the
largest difference between its figures and ours on the 2D blockMesh grids.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path
from types import SimpleNamespace

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from airfoil_set import calibrate, construct2d, half, pinn_mesh  # noqa: E402
from blockmesh3d import checkmesh, run_case  # noqa: E402
from default_choice import SETS  # noqa: E402
from peers import CONSTRUCT2D, block_mesh, openfoam_env, write_dictionary  # noqa: E402

from pinn_engine.blocks3d.checks import figures  # noqa: E402
from pinn_engine.bodies.airfoil import read_dat  # noqa: E402
from pinn_engine.io.export.openfoam import case_files  # noqa: E402
from pinn_engine.io.pipeline import load_boundary  # noqa: E402
from pinn_engine.kinds.four_sided.mesher import Mesher  # noqa: E402
from pinn_engine.quality import guard_figures, orientation  # noqa: E402
from pinn_engine.settings import make_settings  # noqa: E402

ROOT = HERE.parent
SMOOTHING = 100  # gmsh's sweeps: the figure of its tutorial t6 (as multiblock_gmsh.py)
MERGE = 1e-9  # nodes closer than this share of the grid's extent are one (seams, wake cuts)
OURS = (("default", "pinn"), ("elliptic", "elliptic"), ("TFI", "tfi"))
FOUR_SIDED = ("default", "elliptic", "TFI", "gmsh", "blockMesh")
AIRFOIL = ("default", "elliptic", "Construct2D")
BEND_CELLS = (20, 20, 20)  # the bend surface's hexahedra (radial, round, up)
BEND_RADII, BEND_HEIGHT = (1.0, 2.0), 0.8  # example_data/make_hexa.py's bend


def foam_figures(grid: np.ndarray) -> dict:
    """Mean and worst MaxIncludedAngle and folded cells of a 2D grid (nj, ni, 2), with
    checkMesh's largest non-orthogonality and skewness of it extruded one cell thick."""
    grid = np.asarray(grid, dtype=float)[..., :2]
    if orientation(grid) < 0:  # OpenFOAM's hexahedra: counter-clockwise seen from +z
        grid = grid[:, ::-1]
    nj, ni = grid.shape[:2]
    flat = grid.reshape(-1, 2)
    extent = float(np.ptp(flat, axis=0).max())
    _, first, ids = np.unique(
        np.round(flat / (MERGE * extent)), axis=0, return_index=True, return_inverse=True
    )
    ids = ids.reshape(nj, ni)
    xy = flat[first]
    points = np.concatenate([np.column_stack([xy, np.zeros(len(xy))])] * 2)
    points[len(xy) :, 2] = extent / max(ni, nj)
    base = np.stack([ids[:-1, :-1], ids[:-1, 1:], ids[1:, 1:], ids[1:, :-1]], -1).reshape(-1, 4)
    cells = np.concatenate([base, base + len(xy)], axis=1)
    foam = figures(points, cells)
    q = guard_figures(grid)
    return {
        "mean": q["mean_max_angle"],
        "worst": q["worst_max_angle"],
        "folded": q["folded_cells"],
        "nonorth": foam.max_non_orthogonality,
        "skew": foam.max_skewness,
    }


def gmsh_grid(grid: np.ndarray) -> np.ndarray:
    """gmsh's transfinite grid, smoothed, on the boundary nodes of ``grid`` (nj, ni, 2)."""
    import gmsh
    from multiblock_gmsh import gmsh_grids

    nj, ni = grid.shape[:2]
    ids = np.arange(nj * ni).reshape(nj, ni)
    lay = SimpleNamespace(
        points=grid.reshape(-1, 2), ids=[ids], piece_ids=[ids[0], ids[:, -1], ids[-1], ids[:, 0]]
    )
    gmsh.initialize()
    gmsh.option.setNumber("General.Terminal", 0)
    try:
        grids, _ = gmsh_grids(lay, float(np.ptp(grid.reshape(-1, 2), axis=0).max()), SMOOTHING)
    finally:
        gmsh.finalize()
    return grids[0]


def read_points(case: Path) -> np.ndarray:
    """The points (n, 3) of an OpenFOAM case's ``constant/polyMesh/points`` (ASCII)."""
    text = (case / "constant" / "polyMesh" / "points").read_text()
    body = text[text.index("(", text.index("}")) + 1 : text.rindex(")")]
    return np.array(body.replace("(", " ").replace(")", " ").split(), dtype=float).reshape(-1, 3)


def blockmesh_grid(grid: np.ndarray, case: Path) -> tuple[np.ndarray | None, dict | None]:
    """blockMesh's grid of the block whose sides are ``grid``'s boundary nodes (one block,
    a polyLine a side, one cell thick), and checkMesh's figures of it; None, None where
    blockMesh refuses the block."""
    flip = orientation(grid) < 0
    g = grid[:, ::-1] if flip else grid
    nj, ni = g.shape[:2]
    corners = [g[0, 0], g[0, -1], g[-1, -1], g[-1, 0]]
    vertices = [(x, y, z) for z in (0.0, 1.0) for x, y in corners]
    sides = ((0, 1, g[0, 1:-1]), (1, 2, g[1:-1, -1]), (3, 2, g[-1, 1:-1]), (0, 3, g[1:-1, 0]))
    edges = [
        (a + shift, b + shift, [(x, y, z) for x, y in inner])
        for z, shift in ((0.0, 0), (1.0, 4))
        for a, b, inner in sides
    ]
    cells = (ni - 1) * (nj - 1)
    try:
        block_mesh(case, cells, vertices, [(list(range(8)), (ni - 1, nj - 1, 1))], edges)
    except AssertionError:  # it refuses the block (a corner of 180 degrees or more)
        return None, None
    nodes = read_points(case)[: ni * nj, :2].reshape(nj, ni, 2)
    return (nodes[:, ::-1] if flip else nodes), checked(case)


def checked(case: Path) -> dict:
    """checkMesh's figures of a case that blockMesh made, given the ``system/`` files that
    pinn-mesh's OpenFOAM cases carry (checkMesh reads fvSchemes)."""
    for name, text in case_files(case.name).items():
        if name.startswith("system/") and name != "system/controlDict":
            (case / name).write_text(text)
    return checkmesh(case)


def four_sided(path: Path, size: tuple[int, int], work: Path) -> dict:
    """Every tool's figures on one shape, and checkMesh's own on blockMesh's grid."""
    boundary = load_boundary(path)
    grids = {}
    for label, method in OURS:
        settings = make_settings(method, lattice=size, size=size)
        grids[label] = np.asarray(Mesher(settings).fit(boundary).predict(*size).points)[..., :2]
    grids["gmsh"] = gmsh_grid(grids["elliptic"])
    grids["blockMesh"], check = blockmesh_grid(grids["elliptic"], work / path.stem)
    row = {label: None if g is None else foam_figures(g) for label, g in grids.items()}
    row["checkMesh"] = check and {"nonorth": check["nonorth"], "skew": check["skew"]}
    return row


def shape_row(job: tuple[str, Path, tuple[int, int], Path]) -> dict:
    """:func:`four_sided` of one shape of a set, with its names, printed."""
    name, path, size, work = job
    row = {"set": name, "shape": path.stem, **four_sided(path, size, work / name)}
    print(name, path.stem, {t: _cell(row[t]) for t in FOUR_SIDED}, flush=True)
    return row


def airfoils(folder: Path, per_half: int, exe: str, work: Path) -> list[dict]:
    """The default, elliptic and Construct2D grids of the first ``per_half`` files of each
    half of ``folder``, O and C, with their figures (None where a tool made no grid)."""
    files = sorted(folder.glob("*.dat"))
    chosen = [
        f for h in ("tuning", "report") for f in [f for f in files if half(f.name) == h][:per_half]
    ]
    yplus = calibrate(exe, work)
    rows = []
    for f in chosen:
        for topology in ("o", "c"):
            got = {
                "default": pinn_mesh(f, topology, "pinn", keep=True),
                "elliptic": pinn_mesh(f, topology, "elliptic", keep=True),
                "Construct2D": construct2d(exe, f, topology, yplus, work, keep=True),
            }
            row = {"file": read_dat(f)[1].strip(), "half": half(f.name), "topology": topology}
            for label, g in got.items():
                row[label] = foam_figures(g["grid"]) if "grid" in g else None
                if row[label] is not None:
                    row[label]["class"] = g["class"]
            print(f.stem, topology, {k: _cell(row[k]) for k in AIRFOIL}, flush=True)
            rows.append(row)
    return rows


def bend_surface(work: Path) -> list[tuple[str, dict]]:
    """checkMesh's figures of the bend surface's hexahedra: pinn-mesh's default, elliptic
    and TFI, and blockMesh's one block with arc edges at the same counts."""
    out = []
    nr, nt, nz = BEND_CELLS
    surface = ROOT / "example_data" / "hexa_bend.vtp"
    exe = str(Path(sys.executable).with_name("pinn-mesh"))
    for label, method in OURS:
        case = work / f"bend_{method}"
        size = [str(n + 1) for n in BEND_CELLS]
        command = [exe, str(surface), "--size", *size, "--method", method]
        subprocess.run([*command, "--format", "openfoam", "-o", str(case), "--quiet"], check=True)
        out.append((f"pinn-mesh {label}", checkmesh(case)))
    (r0, r1), h = BEND_RADII, BEND_HEIGHT
    corners = [(r0, 0.0), (r1, 0.0), (0.0, r1), (0.0, r0)]
    vertices = [(x, y, z) for z in (0.0, h) for x, y in corners]
    mid = [np.sqrt(0.5) * r for r in (r0, r1)]
    case = work / "bend_blockmesh"
    block_mesh_arcs(case, vertices, (nr, nt, nz), [(1, 2, mid[1]), (0, 3, mid[0])], h)
    out.append(("blockMesh, one block with arc edges", checked(case)))
    return out


def block_mesh_arcs(case: Path, vertices: list, counts: tuple, arcs: list, height: float):
    """A blockMesh case of one block over ``vertices`` with circular ``arcs`` (a, b, the
    coordinate of their midpoint on the diagonal) at both ends, meshed."""
    body = [f"blocks ( hex (0 1 2 3 4 5 6 7) ({' '.join(map(str, counts))}) "]
    body += ["simpleGrading (1 1 1) );", "edges ("]
    for a, b, m in arcs:
        for shift, z in ((0, 0.0), (4, height)):
            body.append(f"  arc {a + shift} {b + shift} ({m:.12g} {m:.12g} {z:.12g})")
    body += [");", "boundary ();", "defaultPatch { name walls; type wall; }"]
    write_dictionary(case, vertices, body)
    subprocess.run(
        ["blockMesh", "-case", str(case)], env=openfoam_env(), check=True, capture_output=True
    )


def _cell(f: dict | None) -> str:
    """A tool's figures in a table cell: mean / worst (folded), non-orthogonality, skewness."""
    if f is None:
        return "refused"
    folded = f" ({f['folded']} folded)" if f["folded"] else ""
    return f"{f['mean']:.1f} / {f['worst']:.1f}{folded}, {f['nonorth']:.1f}, {f['skew']:.2f}"


def summary(rows: list[dict], tools: tuple[str, ...], label: str) -> list[str]:
    """Medians of each tool's figures over ``rows``, and on how many rows the default's worst
    cell is below each peer's."""
    out = [
        f"**{label}** ({len(rows)} grids): medians of mean / worst MaxIncludedAngle, largest "
        "non-orthogonality and skewness; folded grids; the default's worst cell lower / "
        "higher than the tool's.",
        "",
        "| tool | mean | worst | non-orthogonality | skewness | folded grids | "
        "default's worst lower / higher |",
        "|---|---:|---:|---:|---:|---:|---|",
    ]
    for tool in tools:
        have = [r for r in rows if r[tool] is not None and r["default"] is not None]
        if not have:
            continue

        def median(key: str, tool: str = tool, have: list = have) -> float:
            return statistics.median(r[tool][key] for r in have)

        lower = sum(r["default"]["worst"] < r[tool]["worst"] - 1e-9 for r in have)
        higher = sum(r["default"]["worst"] > r[tool]["worst"] + 1e-9 for r in have)
        folded = sum(r[tool]["folded"] > 0 for r in have)
        beside = "-" if tool == "default" else f"{lower} / {higher}"
        out.append(
            f"| {tool} | {median('mean'):.2f} | {median('worst'):.2f} | "
            f"{median('nonorth'):.2f} | {median('skew'):.3f} | {folded} of {len(have)} | "
            f"{beside} |"
        )
    return out + [""]


def page(
    shapes: dict, foils: list[dict], bends: list, size: str, load: tuple, airfoils: str
) -> str:
    """docs/peers.md (``airfoils``: what the airfoil folder holds, in words)."""
    checked = [r for rows in shapes.values() for r in rows if r["checkMesh"]]
    worst_gap = max(abs(r["checkMesh"]["nonorth"] - r["blockMesh"]["nonorth"]) for r in checked)
    skew_gap = max(abs(r["checkMesh"]["skew"] - r["blockMesh"]["skew"]) for r in checked)
    lines = [
        "# The default beside the peers",
        "",
        "Written by `.venv/bin/python benchmarks/peers_quality.py --airfoils DIR --out "
        f"docs/peers.md` (its docstring says what it runs), DIR holding {airfoils}; load "
        "average "
        f"{load[0]:.1f} before, {load[1]:.1f} after, on 2 shared cores. Each figure: "
        "`MaxIncludedAngle` (degrees; the largest corner angle of a cell, 90 for a "
        "rectangle), mean and worst over the grid; checkMesh's largest face "
        "non-orthogonality (degrees) and largest skewness. The 2D grids' checkMesh figures "
        "are computed as OpenFOAM computes them, on the grid extruded one cell thick; on "
        "every blockMesh grid checkMesh itself ran too, and the two differ by at most "
        f"{worst_gap:.1e} degrees of non-orthogonality and {skew_gap:.1e} of skewness.",
        "",
        f"## Four-sided shapes at {size}, without lines",
        "",
        "The same boundary nodes for pinn-mesh's grids and gmsh's (a transfinite surface "
        f"smoothed by {SMOOTHING} sweeps); blockMesh gets the same block, a `polyLine` "
        "through each side's nodes, and places its own nodes along them; it refuses a block "
        "with a corner of 180 degrees or more (`refused`).",
        "",
    ]
    for name, rows in shapes.items():
        lines += summary(rows, FOUR_SIDED, f"{name} set")
    lines += [
        "## Airfoils: real files, O-grids 250 x 80 and C-grids 300 x 80",
        "",
        "First layer 1e-5 chord, far field 15 chords; Construct2D's hyperbolic grid with its "
        "smoothing at the same sizes, far field and first layer.",
        "",
    ]
    for name in ("tuning", "report"):
        for topology in ("o", "c"):
            rows = [r for r in foils if r["half"] == name and r["topology"] == topology]
            if rows:
                lines += summary(rows, AIRFOIL, f"{name} half, {topology.upper()}-grids")
    lines += [
        "## 3D bends: checkMesh",
        "",
        "| grid | checkMesh | cells | non-orthogonality max / average | skewness max |",
        "|---|---|---:|---|---:|",
    ]
    for label, c in bends:
        lines.append(
            f"| {label} | {'Mesh OK' if c['ok'] else 'failed'} | {c['cells']:.0f} | "
            f"{c['nonorth']:.2f} / {c['mean']:.2f} | {c['skew']:.3f} |"
        )
    lines += ["", "## Every grid", ""]
    lines += [
        "Each cell: mean / worst MaxIncludedAngle (folded cells), largest non-orthogonality, "
        "largest skewness.",
        "",
        "| set | shape | " + " | ".join(FOUR_SIDED) + " |",
        "|---|---|" + "---|" * len(FOUR_SIDED),
    ]
    for name, rows in shapes.items():
        for r in rows:
            cells = " | ".join(_cell(r[t]) for t in FOUR_SIDED)
            lines.append(f"| {name} | {r['shape']} | {cells} |")
    lines += ["", "| half | section (its file's title) | grid | " + " | ".join(AIRFOIL) + " |"]
    lines += ["|---|---|---|" + "---|" * len(AIRFOIL)]
    for r in foils:
        cells = " | ".join(_cell(r[t]) for t in AIRFOIL)
        lines.append(f"| {r['half']} | {r['file']} | {r['topology'].upper()} | {cells} |")
    return "\n".join(lines) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--size", default="41x21")
    parser.add_argument(
        "--airfoils", type=Path, default=Path(CONSTRUCT2D).parent / "sample_airfoils"
    )
    parser.add_argument("--per-half", type=int, default=4)
    parser.add_argument("--construct2d", default=CONSTRUCT2D)
    parser.add_argument("--jobs", type=int, default=2, help="processes meshing the shapes")
    parser.add_argument("--out", type=Path)
    args = parser.parse_args()
    size = tuple(int(n) for n in args.size.split("x"))
    before = os.getloadavg()[0]
    with tempfile.TemporaryDirectory(prefix="pinn-mesh-peers-") as scratch:
        work = Path(scratch)
        jobs = [
            (name, path, size, work)
            for name in ("tuning", "holdout")
            for path in SETS[name]
            if not path.stem.endswith("_aux")
        ]
        with ProcessPoolExecutor(args.jobs) as pool:
            rows = list(pool.map(shape_row, jobs))
        shapes = {name: [r for r in rows if r["set"] == name] for name in ("tuning", "holdout")}
        (work / "airfoils").mkdir()
        foils = airfoils(args.airfoils, args.per_half, args.construct2d, work / "airfoils")
        bend_dict = ROOT / "example_data" / "blockmesh" / "bend" / "system" / "blockMeshDict"
        case = run_case("bend", bend_dict.read_text(), work / "bend_dict", 1)
        bends = [
            ("bend blockMeshDict (3 blocks, arc edges): pinn-mesh default", case["ours"]),
            ("bend blockMeshDict: blockMesh", case["ref"]),
            *bend_surface(work),
        ]
    held = f"{len(list(args.airfoils.glob('*.dat')))} `.dat` files ({args.airfoils.name})"
    load = (before, os.getloadavg()[0])
    text = page(shapes, foils, bends, args.size, load, held)
    print(text)
    if args.out:
        args.out.write_text(text)


if __name__ == "__main__":
    main()
