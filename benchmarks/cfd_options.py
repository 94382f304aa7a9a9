"""SPEC 10 and 11's CFD set-up options on domains none of the examples use, run on the
command line as a user types them, each output read back and checked.

Run ``.venv/bin/python benchmarks/cfd_options.py [--only NAME]``; it prints one table row a
check: a whole hole named as a wall with spacing and orthogonality on every piece, a chain
count, spacing at an interior side, negative patch points, and 3D faces named by FaceId
(a tagged tilted box, an untagged annular-sector STL). Patches are checked in the OpenFOAM
(and checkMesh), SU2 and CGNS exports: names, types, and every face on the hole or face
asked. Needs OpenFOAM's checkMesh for the checkMesh rows (else they read "missing").
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
import pyvista as pv

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "tests"))
sys.path.insert(0, str(ROOT / "example_data"))

from export_checks import foam_list, read_su2  # noqa: E402
from helpers import foam_env  # noqa: E402
from make_hexa import surface  # noqa: E402
from multiblock_checks import first_edges, patch_walls, wall_angles, write_polylines  # noqa: E402

RING_POINTS = 80  # points on a drawn curved hole
SPACING_TOL = 0.10  # SPEC 7: the first edge within 10 % of H
ANGLE_TOL = 2.0  # SPEC 7: lines within 2 degrees of the normal
RATIO_MAX = 1.25  # SPEC 10: no neighbour ratio above 1.25 along a graded chain
ON_CURVE = 1e-3  # a patch face's centre off its curve, over the domain's diagonal
ON_FACE = 1e-6  # SPEC 11: boundary nodes within 1e-6 of the diagonal of the surface


def ellipse(cx, cy, a, b, n=RING_POINTS) -> np.ndarray:
    t = 2 * np.pi * np.arange(n) / n
    return np.column_stack([cx + a * np.cos(t), cy + b * np.sin(t)])


def ring_box(box_lo, box_hi, hole_centre, hole_axes, outer_lo, outer_hi, stars: bool):
    """Block edges round a hole: a box cut along its diagonals (an O-ring of four blocks),
    and either its corners joined to the channel's (``stars``: 8 blocks) or its sides carried
    on to the channel's walls (12 blocks)."""
    (x0, y0), (x1, y1) = box_lo, box_hi
    (cx, cy), (a, b) = hole_centre, hole_axes
    corners = [(x1, y0), (x1, y1), (x0, y1), (x0, y0)]
    edges = [[corners[k - 1], corners[k]] for k in range(4)]
    for x, y in corners:
        t = np.arctan2((y - cy) / b, (x - cx) / a)
        edges.append([(cx + a * np.cos(t), cy + b * np.sin(t)), (x, y)])
    (X0, Y0), (X1, Y1) = outer_lo, outer_hi
    if stars:
        for p, q in zip(corners, [(X1, Y0), (X1, Y1), (X0, Y1), (X0, Y0)]):
            edges.append([p, q])
        return edges
    for x in (x0, x1):
        edges += [[(x, Y0), (x, y0)], [(x, y1), (x, Y1)]]
    for y in (y0, y1):
        edges += [[(X0, y), (x0, y)], [(x1, y), (X1, y)]]
    return edges


def channel(lo, hi) -> np.ndarray:
    return np.array([lo, (hi[0], lo[1]), hi, (lo[0], hi[1])], dtype=float)


def domains() -> dict[str, dict]:
    """The 2D domains: rings (outer first), block edges, the wall run's and the chain run's
    options, where the chain's graded side is and which hole the wall is."""
    out = {}
    # an elliptic hole off-centre in a channel reaching negative x and y, 12 blocks
    lo, hi = (-1.0, -0.7), (2.5, 0.6)
    out["ellipse12"] = dict(
        rings=[channel(lo, hi), ellipse(0.3, 0.05, 0.3, 0.15)],
        edges=ring_box((-0.2, -0.35), (0.8, 0.45), (0.3, 0.05), (0.3, 0.15), lo, hi, False),
        wall="hole1",
        patches=["hole1=body:wall", "boundary=walls:wall", "-1,-0.5=inlet:inflow"]
        + ["-1,0=inlet", "-1,0.5=inlet", "2.5,-0.5=outlet:outflow", "2.5,0=outlet"]
        + ["2.5,0.5=outlet"],
        wall_h=0.004,
        cells=["1.6,0.6=30"],
        graded=(0.8, 0.05),
        edge=(2.5, 0.0),
        graded_h=0.01,
        cell_size=0.05,
    )
    # the same hole with the box's corners joined to the channel's: 8 blocks
    out["ellipse8"] = dict(
        out["ellipse12"],
        edges=ring_box((-0.2, -0.35), (0.8, 0.45), (0.3, 0.05), (0.3, 0.15), lo, hi, True),
        patches=["hole1=body:wall", "boundary=walls:wall", "-1,0=inlet:inflow"]
        + ["2.5,0=outlet:outflow"],
        cells=["0.3,0.6=30"],
    )
    # a circle off-centre in a square, two O-rings (the outer one's corners joined to the
    # square's): 8 blocks
    lo, hi = (-1.0, -1.0), (1.0, 1.0)
    out["oring8"] = dict(
        rings=[channel(lo, hi), ellipse(0.1, 0.05, 0.25, 0.25)],
        edges=ring_box((-0.35, -0.3), (0.55, 0.4), (0.1, 0.05), (0.25, 0.25), lo, hi, True),
        wall="hole1",
        patches=["hole1=cyl:wall", "boundary=far:farfield"],
        wall_h=0.003,
        cells=["0,1=40"],
        graded=(0.55, 0.05),
        edge=(1.0, 0.0),
        graded_h=0.01,
        cell_size=0.04,
    )
    # a square hole off-centre, its sides carried on to the walls: 8 blocks
    lo, hi = (0.0, 0.0), (3.0, 1.0)
    square = np.array([(0.5, 0.2), (0.5, 0.55), (0.9, 0.55), (0.9, 0.2)])[::-1]
    edges = []
    for x in (0.5, 0.9):
        edges += [[(x, 0.0), (x, 0.2)], [(x, 0.55), (x, 1.0)]]
    for y in (0.2, 0.55):
        edges += [[(0.0, y), (0.5, y)], [(0.9, y), (3.0, y)]]
    out["square8"] = dict(
        rings=[channel(lo, hi), square],
        edges=edges,
        wall="hole1",
        patches=["hole1=block:wall", "boundary=walls:wall", "0,0.1=inlet:inflow"]
        + ["0,0.4=inlet", "0,0.8=inlet", "3,0.1=outlet:outflow", "3,0.4=outlet", "3,0.8=outlet"],
        wall_h=0.004,
        cells=["2,1=30"],
        graded=(0.9, 0.8),
        edge=(0.0, 0.4),
        graded_h=0.01,
        cell_size=0.04,
    )
    # two holes (a circle and an ellipse), each in an O-ring: 21 blocks
    lo, hi = (0.0, -1.0), (4.0, 1.0)
    edges = ring_box((0.5, -0.5), (1.5, 0.5), (1.0, 0.0), (0.25, 0.25), lo, hi, False)
    edges = [e for e in edges if not (e[0][0] == 1.5 and e[1][0] == 4.0)]
    edges += ring_box((2.2, -0.5), (3.4, 0.5), (2.8, 0.1), (0.35, 0.2), lo, hi, False)
    edges = [e for e in edges if not (e[0][0] == 0.0 and e[1][0] == 2.2)]
    edges += [[(1.5, y), (2.2, y)] for y in (-0.5, 0.5)]
    out["two_holes"] = dict(
        rings=[channel(lo, hi), ellipse(1.0, 0.0, 0.25, 0.25), ellipse(2.8, 0.1, 0.35, 0.2)],
        edges=edges,
        wall="hole2",
        patches=["hole1=front:wall", "hole2=rear:wall", "boundary=walls:wall"]
        + ["0,-0.75=inlet:inflow", "0,0=inlet", "0,0.75=inlet"]
        + ["4,-0.75=outlet:outflow", "4,0=outlet", "4,0.75=outlet"],
        wall_h=0.003,
        cells=["3.7,1=10"],
        graded=(1.85, 0.5),
        edge=(0.0, 0.0),
        graded_h=0.01,
        cell_size=0.05,
    )
    # an L-shaped duct in negative coordinates: a corner block and two arms
    ring = np.array([(-2, -2), (1, -2), (1, -1), (-1, -1), (-1, 1), (-2, 1)], dtype=float)
    out["lduct"] = dict(
        rings=[ring],
        edges=[[(-1.0, -1.0), (-2.0, -1.0)], [(-1.0, -1.0), (-1.0, -2.0)]],
        wall="boundary",
        patches=["boundary=duct:wall", "-1.5,1=inlet:inflow", "1,-1.5=outlet:outflow"],
        wall_h=0.005,
        cells=["0,-2=30"],
        graded=(-1, -1.5),
        edge=(-1.5, 1.0),
        graded_h=0.01,
        cell_size=0.05,
    )
    return out


def step(inlet: float, height: float, drop: float, length: float) -> dict:
    """A backward-facing step drawn as pitzDaily's blocks: an inlet channel
    [-inlet, 0] x [0, height] and the channel [0, length] x [-drop, height] cut along
    y = 0 (three blocks)."""
    ring = [(-inlet, 0), (0, 0), (0, -drop), (length, -drop), (length, height), (-inlet, height)]
    return dict(
        rings=[np.array(ring, dtype=float)],
        edges=[[(0.0, 0.0), (0.0, height)], [(0.0, 0.0), (length, 0.0)]],
    )


def graded_domains() -> dict[str, dict]:
    """Domains checked by their graded runs only: ``runs`` lists (cells, point, H, more
    --spacing items), the point's side measured. ``step``: the pitzDaily-like step whose
    grading reaches the interface y = 0 (tuned on); the ``held_out`` ones were drawn after
    the rule was fixed and never tuned on."""
    out = {}
    cells = ["-0.5,1=20", "0,-0.5=30", "-1,0.5=30", "4,1=60"]
    out["step"] = dict(
        step(1.0, 1.0, 1.0, 8.0),
        cell_size=0.1,
        runs=[
            (cells, (-0.5, 0.0), 0.01, []),
            (cells, (-0.5, 0.0), 0.01, ["0,-0.5=0.02"]),
            (cells, (4.0, 0.0), 0.01, []),
        ],
    )
    out["held_out_step"] = dict(
        step(2.0, 0.6, 0.4, 5.0),
        cell_size=0.05,
        runs=[([], (-1.0, 0.0), 0.005, []), ([], (2.5, 0.0), 0.005, ["0,-0.2=0.01"])],
    )
    lo, hi = (-1.5, -1.0), (1.5, 1.0)
    out["held_out_star"] = dict(
        rings=[channel(lo, hi), ellipse(0.0, 0.05, 0.2, 0.35)],
        edges=ring_box((-0.4, -0.5), (0.45, 0.6), (0.0, 0.05), (0.2, 0.35), lo, hi, True),
        cell_size=0.05,
        runs=[([], (0.45, 0.0), 0.01, []), ([], (0.0, 1.0), 0.01, [])],
    )
    lo, hi = (0.0, 0.0), (2.0, 1.2)
    out["held_out_oring"] = dict(
        rings=[channel(lo, hi), ellipse(0.7, 0.6, 0.15, 0.15)],
        edges=ring_box((0.4, 0.3), (1.0, 0.9), (0.7, 0.6), (0.15, 0.15), lo, hi, False),
        cell_size=0.04,
        runs=[(["1.5,1.2=30"], (1.0, 0.6), 0.008, []), ([], (0.7, 0.3), 0.008, [])],
    )
    return out


def check_graded(name: str, d: dict, work: Path, method: str | None) -> list[tuple]:
    boundary = write_polylines(work / f"{name}.vtp", d["rings"], closed=True)
    blocks = write_polylines(work / f"{name}_blocks.vtp", d["edges"])
    base = [boundary, "--blocks", blocks, "--cell-size", str(d["cell_size"])]
    base += ["--method", method] if method else []
    rows = []
    for cells, point, h, more in d["runs"]:
        extra = [arg for item in more for arg in ("--spacing", item)]
        rows.append(graded_row(name, base, work, cells, point, h, extra))
    return rows


def cli(args: list[str]) -> tuple[int, str]:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    proc = subprocess.run(
        [sys.executable, "-m", "pinn_engine.command", *args],
        capture_output=True,
        text=True,
        env=env,
    )
    return proc.returncode, (proc.stdout + proc.stderr).strip()


def polyline_distance(points: np.ndarray, line: np.ndarray, closed: bool = True) -> np.ndarray:
    """Each point's distance from a polyline (closed: its last point joined to its first)."""
    a, b = (line, np.roll(line, -1, axis=0)) if closed else (line[:-1], line[1:])
    ab = b - a
    t = np.clip(
        np.einsum("pnk,nk->pn", points[:, None, :] - a[None], ab) / np.einsum("nk,nk->n", ab, ab),
        0,
        1,
    )
    feet = a[None] + t[..., None] * ab[None]
    return np.linalg.norm(points[:, None, :] - feet, axis=2).min(axis=1)


def foam_patches(case: Path) -> dict[str, tuple[str, np.ndarray]]:
    """Patch name -> (type, its faces' centres) of an OpenFOAM case."""
    mesh = case / "constant" / "polyMesh"
    points = np.array([ln.strip("()").split() for ln in foam_list(mesh / "points")], float)
    faces = [list(map(int, ln[ln.index("(") + 1 : -1].split())) for ln in foam_list(mesh / "faces")]
    boundary = (mesh / "boundary").read_text()
    found = re.findall(
        r"(\w+)\s*\{\s*type\s+(\w+);[^}]*?nFaces\s+(\d+);\s*startFace\s+(\d+);", boundary
    )
    return {
        name: (kind, np.array([points[f].mean(axis=0) for f in faces[int(s) : int(s) + int(n)]]))
        for name, kind, n, s in found
    }


def check_mesh(case: Path) -> str:
    if shutil.which("checkMesh") is None:
        return "missing"
    proc = subprocess.run(
        ["checkMesh", "-case", str(case)], capture_output=True, text=True, env=foam_env()
    )
    text = proc.stdout + proc.stderr
    worst = re.search(r"Mesh non-orthogonality Max: ([\d.]+)", text)
    return ("OK" if "Mesh OK." in text else "FAILED") + (
        f", non-orth {float(worst.group(1)):.1f}" if worst else ""
    )


def cgns_families(path: Path) -> dict[str, str]:
    """Family name -> its FamilyBC type, over every zone's BC_t."""
    import h5py

    out = {}
    with h5py.File(path, "r") as f:
        base = next(g for g in f.values() if g.attrs.get("label") == b"CGNSBase_t")
        for name, node in base.items():
            if isinstance(node, h5py.Group) and node.attrs.get("label") == b"Family_t":
                bc = node.get("FamilyBC")
                out[name] = bytes(bc[" data"][()]).decode() if bc is not None else ""
    return out


def block_side_lines(grid: pv.MultiBlock, point) -> list[np.ndarray]:
    """The grid lines leaving the block side nearest ``point`` (in every block having that
    side), each from the side inward, (n, 2); the lines at the side's corners aside."""
    found = []
    for block in grid:
        ni, nj, _ = block.dimensions
        g = block.points[:, :2].reshape(nj, ni, 2)
        for side, lines in (
            (g[0], g.transpose(1, 0, 2)),
            (g[-1], g[::-1].transpose(1, 0, 2)),
            (g[:, 0], g),
            (g[:, -1], g[:, ::-1]),
        ):
            d = polyline_distance(np.array([point]), side, closed=False)[0]
            found.append((d, lines[1:-1]))
    best = min(d for d, _ in found)
    return [lines for d, lines in found if d < best + 1e-9]


def ratios(lines: np.ndarray) -> np.ndarray:
    """Largest ratio of neighbouring edges along each line."""
    edges = np.linalg.norm(np.diff(lines, axis=1), axis=2)
    r = edges[:, 1:] / edges[:, :-1]
    return np.maximum(r, 1 / r).max(axis=1)


def folded(grid: pv.MultiBlock) -> int:
    return int(sum(np.asarray(b.cell_data["Folded"]).sum() for b in grid))


def check_2d(name: str, d: dict, work: Path, method: str | None) -> list[tuple[str, str, str]]:
    rows = []
    boundary = write_polylines(work / f"{name}.vtp", d["rings"], closed=True)
    blocks = write_polylines(work / f"{name}_blocks.vtp", d["edges"])
    diag = float(np.linalg.norm(np.ptp(np.vstack(d["rings"]), axis=0)))
    base = [boundary, "--blocks", blocks, "--cell-size", str(d["cell_size"])]
    base += ["--method", method] if method else []
    wall_name = next(p.split("=")[1].split(":")[0] for p in d["patches"] if p.startswith(d["wall"]))
    ring = d["rings"][0 if d["wall"] == "boundary" else int(d["wall"][4:])]
    wall = [arg for p in d["patches"] for arg in ("--patch", p)]  # as typed: -1,0=... too
    wall += ["--spacing", f"{wall_name}={d['wall_h']}", "--orthogonal", wall_name]

    rc, out = cli([*base, *wall, "-o", str(work / f"{name}.vtm")])
    if rc != 0:
        return [(name, "wall run", f"FAILED: {out.splitlines()[-1]}")]
    grid = pv.read(work / f"{name}.vtm")
    walls = patch_walls(grid, wall_name)
    pieces = sum(
        1 for b in grid for p in b.field_data["PieceNames"] if p == wall_name
    )  # block sides holding the wall
    h = first_edges(walls) / d["wall_h"]
    ang = wall_angles(walls).max()
    ok = abs(h - 1).max() <= SPACING_TOL and ang <= ANGLE_TOL and folded(grid) == 0
    rows.append(
        (
            name,
            f"{d['wall']}={wall_name} spacing {d['wall_h']} + orthogonal ({pieces} pieces)",
            f"{'ok' if ok else 'BAD'}: first edge {h.min():.3f}-{h.max():.3f} H, "
            f"max angle off normal {ang:.2f} deg, {folded(grid)} folded",
        )
    )

    case = work / f"{name}_case"
    rc, out = cli([*base, *wall, "--format", "openfoam", "--extrude", "0.05", "-o", str(case)])
    if rc != 0:
        rows.append((name, "openfoam", f"FAILED: {out.splitlines()[-1]}"))
    else:
        patches = foam_patches(case)
        kinds = {k: v[0] for k, v in patches.items()}
        off = polyline_distance(patches[wall_name][1][:, :2], ring).max() / diag
        want = {p.split("=")[1].split(":")[0] for p in d["patches"]} | {"frontAndBack"}
        ok = set(kinds) == want and kinds[wall_name] == "wall" and off < ON_CURVE
        rows.append(
            (
                name,
                "openfoam patches",
                f"{'ok' if ok else 'BAD'}: {' '.join(f'{k}:{v}' for k, v in kinds.items())}; "
                f"{wall_name}'s faces off the ring {off:.1e} diag",
            )
        )
        rows.append((name, "checkMesh", check_mesh(case)))
    for ext in ("su2", "cgns"):
        path = work / f"{name}.{ext}"
        rc, out = cli([*base, *wall, "-o", str(path)])
        if rc != 0:
            rows.append((name, ext, f"FAILED: {out.splitlines()[-1]}"))
            continue
        if ext == "su2":
            mesh = read_su2(path)
            ids = np.unique(mesh["markers"][wall_name][:, 1:])
            off = polyline_distance(mesh["points"][ids, :2], ring).max() / diag
            found = sorted(mesh["markers"])
            ok = off < ON_CURVE
            rows.append(
                (
                    name,
                    "su2 markers",
                    f"{'ok' if ok else 'BAD'}: {found}; {wall_name} off {off:.1e}",
                )
            )
        else:
            fams = cgns_families(path)
            ok = fams.get(wall_name) == "BCWall"
            rows.append((name, "cgns families", f"{'ok' if ok else 'BAD'}: {fams}"))

    rows.append(graded_row(name, base, work, d["cells"], d["graded"], d["graded_h"]))
    return [*rows, graded_row(name, base, work, [], d["edge"], d["graded_h"])]


def graded_row(name, base, work, cells, point, h, extra=()) -> tuple[str, str, str]:
    """A run with ``--cells`` items and ``--spacing X,Y=H`` at ``point``: the first edges
    across the side (every line leaving it but the two at its corners, which SPEC 7
    excepts; and the middle half of each side's lines), the largest ratio of neighbouring
    cells along the lines leaving it, folds."""
    where = "{:g},{:g}".format(*point)
    args = [arg for c in cells for arg in ("--cells", c)] + [*extra, "--spacing", f"{where}={h}"]
    label = " ".join(args)
    rc, out = cli([*base, *args, "-o", str(work / f"{name}_graded.vtm")])
    if rc != 0:
        return (name, label, f"FAILED: {out.splitlines()[-1]}")
    grid = pv.read(work / f"{name}_graded.vtm")
    lines = block_side_lines(grid, point)
    first = np.concatenate([np.linalg.norm(v[:, 1] - v[:, 0], axis=1) for v in lines]) / h
    mid = [v[len(v) // 4 : len(v) - len(v) // 4] for v in lines]
    mid = np.concatenate([np.linalg.norm(v[:, 1] - v[:, 0], axis=1) for v in mid]) / h
    worst = max(ratios(v).max() for v in lines)
    ok = abs(first - 1).max() <= SPACING_TOL and worst <= RATIO_MAX and folded(grid) == 0
    return (
        name,
        f"{label} ({len(lines)} sides)",
        f"{'ok' if ok else 'BAD'}: first edge {first.min():.2f}-{first.max():.2f} H "
        f"(middle half {mid.min():.2f}-{mid.max():.2f}), neighbour ratio {worst:.3f}, "
        f"{folded(grid)} folded",
    )


def tilted_box(u, v, w):
    """A box 2 x 1 x 0.6 turned 155 degrees about z and 10 about x, reaching negative
    coordinates."""
    p = np.stack([2.0 * u - 1.2, v - 0.7, 0.6 * w - 0.2], axis=-1)
    a, b = np.radians(155.0), np.radians(10.0)
    rz = np.array([[np.cos(a), -np.sin(a), 0], [np.sin(a), np.cos(a), 0], [0, 0, 1]])
    rx = np.array([[1, 0, 0], [0, np.cos(b), -np.sin(b)], [0, np.sin(b), np.cos(b)]])
    return p @ (rx @ rz).T


def sector(u, v, w):
    """An annular sector: radii 0.8 to 1.5, 10 to 70 degrees, z from -0.3 to 0.4."""
    r, t = 0.8 + 0.7 * u, np.radians(10.0 + 60.0 * v)
    return np.stack([r * np.cos(t), r * np.sin(t), 0.7 * w - 0.3], axis=-1)


# the 3D domains: shape, file suffix, names of faces 0..5 (the surface's FaceId order:
# u = 0, u = 1, v = 0, v = 1, w = 0, w = 1; an STL's faces are numbered in that order too)
SOLIDS = {
    "tilted_box": (
        tilted_box,
        "vtp",
        ["inlet:inflow", "outlet:outflow", "side:wall"]
        + ["side:wall", "floor:wall", "lid:symmetry"],
    ),
    "sector_stl": (
        sector,
        "stl",
        ["inner:wall", "outer:wall", "start:inflow", "end:outflow"] + ["floor:wall", "top:wall"],
    ),
}


def check_3d(name: str, work: Path) -> list[tuple[str, str, str]]:
    shape, ext, names = SOLIDS[name]
    tagged = surface(shape)
    path = work / f"{name}.{ext}"
    tagged.save(path)
    diag = tagged.length
    patches = [arg for k, n in enumerate(names) for arg in ("--patch", f"face{k}={n}")]
    base = [str(path), "--size", "9", "8", "7", "--method", "elliptic", *patches]
    rows = []
    case = work / f"{name}_case"
    rc, out = cli([*base, "--format", "openfoam", "-o", str(case)])
    if rc != 0:
        return [(name, "openfoam", f"FAILED: {out.splitlines()[-1]}")]
    summary = out.splitlines()[-1]
    found = foam_patches(case)
    wrong, kinds = [], {}
    for patch, (kind, centres) in found.items():
        kinds[patch] = kind
        faces = {k for k, n in enumerate(names) if n.split(":")[0] == patch}
        ids = tagged.cell_data["FaceId"][tagged.find_closest_cell(centres)]
        wrong += [patch] * int(np.sum(~np.isin(ids, list(faces))))
    want = {n.split(":")[0]: n.split(":")[1] for n in names}
    types = {"inflow": "patch", "outflow": "patch", "wall": "wall", "symmetry": "symmetryPlane"}
    ok = not wrong and kinds == {k: types[v] for k, v in want.items()}
    rows.append(
        (
            name,
            "faceN patches in openfoam",
            f"{'ok' if ok else 'BAD'}: {' '.join(f'{k}:{v}' for k, v in kinds.items())}; "
            f"{len(wrong)} faces on another face than asked; {summary.split(';')[-1].strip()}",
        )
    )
    rows.append((name, "checkMesh", check_mesh(case)))
    grid_path = work / f"{name}.vts"
    rc, out = cli([*base, "-o", str(grid_path)])
    grid = pv.read(grid_path)
    outer = grid.extract_surface().points
    _, closest = tagged.find_closest_cell(outer, return_closest_point=True)
    off = np.linalg.norm(outer - closest, axis=1).max() / diag
    rows.append(
        (
            name,
            "face nodes on the surface",
            f"{'ok' if off <= ON_FACE else 'BAD'}: {off:.1e} of the diagonal, "
            f"{int(grid.cell_data['Folded'].sum())} folded",
        )
    )
    for ext in ("su2", "cgns"):
        path = work / f"{name}.{ext}"
        rc, out = cli([*base, "-o", str(path)])
        if rc != 0:
            rows.append((name, ext, f"FAILED: {out.splitlines()[-1]}"))
        elif ext == "su2":
            got = sorted(read_su2(path)["markers"])
            rows.append((name, "su2 markers", f"{'ok' if got == sorted(want) else 'BAD'}: {got}"))
        else:
            fams = cgns_families(path)
            cgns = {"inflow": "BCInflow", "outflow": "BCOutflow", "wall": "BCWall"}
            cgns["symmetry"] = "BCSymmetryPlane"
            ok = fams == {k: cgns[v] for k, v in want.items()}
            rows.append((name, "cgns families", f"{'ok' if ok else 'BAD'}: {fams}"))
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--only", help="one domain by name")
    parser.add_argument("--method", help="the 2D runs' method (default: the command's)")
    args = parser.parse_args()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, d in domains().items():
            if args.only and name != args.only:
                continue
            rows += check_2d(name, d, Path(tmp), args.method)
            for row in rows[-7:]:
                print(" | ".join(row), flush=True)
        for name, d in graded_domains().items():
            if args.only and name != args.only:
                continue
            found = check_graded(name, d, Path(tmp), args.method)
            rows += found
            for row in found:
                print(" | ".join(row), flush=True)
        for name in SOLIDS:
            if args.only and name != args.only:
                continue
            rows += check_3d(name, Path(tmp))
            for row in rows[-5:]:
                print(" | ".join(row), flush=True)
    print("| domain | check | result |\n|---|---|---|")
    for row in rows:
        print("| " + " | ".join(row) + " |")


if __name__ == "__main__":
    main()
