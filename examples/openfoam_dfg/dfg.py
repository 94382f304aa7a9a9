"""The DFG 2D-1 case's steps around OpenFOAM (docs/dfg.md): the inlet profile written as
values, the drag, lift and pressure difference read back, and blockMesh's dictionary of
the same blocks and counts.

    python examples/openfoam_dfg/dfg.py inlet CASE          # 0/U's inlet: the parabola
    python examples/openfoam_dfg/dfg.py coefficients CASE   # Cd Cl dp of the last time
    python examples/openfoam_dfg/dfg.py blockmesh CASE GRID.vtm H   # system/blockMeshDict

Schaefer and Turek (1996), test case 2D-1: a channel [0, 2.2] x [0, 0.41], a cylinder of
diameter D = 0.1 at (0.2, 0.2), the inflow U(y) = 4 Um y (H - y) / H^2 with Um = 0.3 (mean
0.2), nu = 1e-3 (Re 20); Cd = 2 Fx / (U^2 D), Cl = 2 Fy / (U^2 D) with U = 0.2 and the
forces per unit depth, dp = p(0.15, 0.2) - p(0.25, 0.2) (rho = 1).
"""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np

HEIGHT, PEAK = 0.41, 0.3  # the channel's height and the inflow's peak speed (2D-1)
MEAN, DIAMETER = 0.2, 0.1  # the mean inflow speed and the cylinder's diameter
CENTRE = np.array([0.2, 0.2])  # the cylinder's centre
BOX = 0.1  # half the side of the square round it (example_data/make_multiblock.py's DFG_BOX)
REFERENCE = {"Cd": 5.57954, "Cl": 0.010619, "dp": 0.117520}  # the published values


def _foam_list(text: str, start: int) -> tuple[list[str], int]:
    """The items of the OpenFOAM list whose count starts at ``start`` and where it ends."""
    m = re.compile(r"(\d+)\s*\(").search(text, start)
    n, pos, items = int(m[1]), m.end(), []
    item = re.compile(r"\s*(\d+\([^)]*\)|\([^)]*\)|[-+0-9.eE]+)")
    for _ in range(n):
        m = item.match(text, pos)
        items.append(m[1])
        pos = m.end()
    return items, pos


def _body(path: Path) -> str:
    """A file's text after its FoamFile header."""
    text = path.read_text()
    return text[text.index("}", text.index("FoamFile")) + 1 :]


def face_centres(case: Path, patch: str) -> np.ndarray:
    """(n, 3) centres of ``patch``'s faces (the mean of each face's points)."""
    mesh = case / "constant" / "polyMesh"
    rows = _foam_list(_body(mesh / "points"), 0)[0]
    points = np.array([[float(v) for v in p.strip("()").split()] for p in rows])
    boundary = _body(mesh / "boundary")
    block = re.search(rf"\b{patch}\s*\{{([^}}]*)\}}", boundary)[1]
    start = int(re.search(r"startFace\s+(\d+)", block)[1])
    count = int(re.search(r"nFaces\s+(\d+)", block)[1])
    faces, _ = _foam_list(_body(mesh / "faces"), 0)
    ids = [[int(v) for v in f[f.index("(") + 1 : -1].split()] for f in faces[start : start + count]]
    return np.array([points[f].mean(axis=0) for f in ids])


def inlet(case: Path) -> None:
    """Write the parabolic inflow at the inlet's face centres into 0/U."""
    y = face_centres(case, "inlet")[:, 1]
    u = 4 * PEAK * y * (HEIGHT - y) / HEIGHT**2
    values = "\n".join(f"({v:.10g} 0 0)" for v in u)
    path = case / "0" / "U"
    text = path.read_text()
    field = f"value           nonuniform List<vector>\n{len(u)}\n(\n{values}\n);"
    block = re.search(r"inlet\s*\{[^}]*\}", text)
    new = re.sub(r"value\s+[^;]*;", lambda _: field, block[0])
    path.write_text(text[: block.start()] + new + text[block.end() :])


def _last_time(case: Path) -> Path:
    times = [p for p in case.iterdir() if re.fullmatch(r"[0-9.eE+-]+", p.name) and p.name != "0"]
    return max(times, key=lambda p: float(p.name))


def _wall_values(case: Path, field: Path, patch: str) -> np.ndarray:
    """A scalar field's values on a zero-gradient ``patch``: those of the cells owning its
    faces."""
    mesh = case / "constant" / "polyMesh"
    boundary = _body(mesh / "boundary")
    block = re.search(rf"\b{patch}\s*\{{([^}}]*)\}}", boundary)[1]
    start = int(re.search(r"startFace\s+(\d+)", block)[1])
    count = int(re.search(r"nFaces\s+(\d+)", block)[1])
    owner = np.array([int(v) for v in _foam_list(_body(mesh / "owner"), 0)[0]])
    text = _body(field)
    cells = np.array([float(v) for v in _foam_list(text, text.index("List<scalar>"))[0]])
    return cells[owner[start : start + count]]


def coefficients(case: Path) -> dict[str, float]:
    """Cd, Cl and dp of the case's last time (forces from postProcessing/forces)."""
    rows = (case / "postProcessing" / "forces" / "0" / "force.dat").read_text().splitlines()
    last = [float(v) for v in re.sub(r"[()]", " ", rows[-1]).split()]
    depth = _depth(case)
    fx, fy = last[1] / depth, last[2] / depth
    scale = 0.5 * MEAN**2 * DIAMETER
    centres = face_centres(case, "cylinder")[:, :2] - CENTRE
    angle = np.arctan2(centres[:, 1], centres[:, 0])
    order = np.argsort(angle)
    p = _wall_values(case, _last_time(case) / "p", "cylinder")[order]
    wrap = np.concatenate([angle[order] - 2 * np.pi, angle[order], angle[order] + 2 * np.pi])
    front, back = np.interp([np.pi, 0.0], wrap, np.tile(p, 3))
    return {"Cd": fx / scale, "Cl": fy / scale, "dp": float(front - back)}


def _depth(case: Path) -> float:
    """The extruded mesh's thickness (its points' z range)."""
    mesh = case / "constant" / "polyMesh"
    z = [float(p.strip("()").split()[2]) for p in _foam_list(_body(mesh / "points"), 0)[0]]
    return max(z) - min(z)


def blockmesh(case: Path, grid: Path, depth: float) -> None:
    """system/blockMeshDict of the drawn DFG blocks with the counts of ``grid`` (a
    pinn-mesh .vtm of the same blocks) and its gradings: the ratio of last to first cell
    along the O-ring's radial lines and along the rows downstream of the square (the
    geometric mean over their blocks: blockMesh needs one per chain), the cylinder's sides
    as arcs."""
    import pyvista as pv

    sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "example_data"))
    from make_multiblock import dfg

    from pinn_engine.multiblock.blocks import topology
    from pinn_engine.multiblock.graph import linework

    rings, edges = dfg()
    topo = topology(linework(rings, edges, [f"edge {k}" for k in range(len(edges))], "dfg"))
    blocks = list(pv.read(grid))
    vertices: list[tuple[float, float]] = []

    def vertex(p) -> int:
        key = (round(float(p[0]), 9), round(float(p[1]), 9))
        if key not in vertices:
            vertices.append(key)
        return vertices.index(key)

    for block in topo.blocks:
        for corner in block.corners:
            vertex(corner)
    up = len(vertices)  # vertex k at z = depth is vertex k + up
    radial, downstream = [], []  # the grid's expansion ratios of the two graded chains
    for block, made in zip(topo.blocks, blocks):  # pinn-mesh's blocks in the same order
        ni, nj, _ = made.dimensions
        mesh = made.points[:, :2].reshape(nj, ni, 2)
        arc = _arc_side(topo, block)
        if arc is not None:
            ratio = _ratio(mesh[:, ni // 2] if arc in (0, 2) else mesh[nj // 2])
            radial.append(ratio if arc in (0, 3) else 1.0 / ratio)  # from the cylinder out
        elif block.corners[:, 0].min() >= CENTRE[0] + BOX - 1e-9:
            downstream.append(_ratio(mesh[nj // 2]))
    grow = float(np.exp(np.mean(np.log(radial))))
    stretch = float(np.exp(np.mean(np.log(downstream))))
    hexes, arcs = [], []
    for block, made in zip(topo.blocks, blocks):
        ids = [vertex(c) for c in block.corners]
        ni, nj, _ = made.dimensions
        grading = [1.0, 1.0]
        arc = _arc_side(topo, block)
        if arc is not None:
            grading[1 if arc in (0, 2) else 0] = grow if arc in (0, 3) else 1.0 / grow
            a, b = ids[arc], ids[(arc + 1) % 4]
            mid = CENTRE + DIAMETER / 2 * _unit(
                block.corners[arc] + block.corners[(arc + 1) % 4] - 2 * CENTRE
            )
            for z, off in ((0.0, 0), (depth, up)):
                arcs.append(f"    arc {a + off} {b + off} ({mid[0]:.12g} {mid[1]:.12g} {z:g})")
        elif block.corners[:, 0].min() >= CENTRE[0] + BOX - 1e-9:
            grading[0] = stretch
        hexes.append(
            f"    hex ({' '.join(map(str, ids))} {' '.join(str(i + up) for i in ids)}) "
            f"({ni - 1} {nj - 1} 1) simpleGrading ({grading[0]:.6g} {grading[1]:.6g} 1)"
        )
    points = [f"    ({x:.12g} {y:.12g} {z:g})" for z in (0.0, depth) for x, y in vertices]
    patches = {name: [] for name in ("inlet", "outlet", "walls", "cylinder", "frontAndBack")}
    for block in topo.blocks:
        ids = [vertex(c) for c in block.corners]
        patches["frontAndBack"] += [
            f"({ids[0]} {ids[3]} {ids[2]} {ids[1]})",
            f"({ids[0] + up} {ids[1] + up} {ids[2] + up} {ids[3] + up})",
        ]
        for s, side in enumerate(block.sides):
            if any(topo.pieces[p].interface for p, _ in side):
                continue
            a, b = ids[s], ids[(s + 1) % 4]
            face = f"({a} {b} {b + up} {a + up})"
            x = np.vstack([topo.pieces[p].points for p, _ in side])[:, 0]
            name = (
                "inlet" if np.all(x == 0) else "outlet" if np.all(x == 2.2) else
                "cylinder" if np.all(np.abs(x - CENTRE[0]) <= DIAMETER / 2 + 1e-9) and
                np.ptp(x) < DIAMETER else "walls"
            )  # fmt: skip
            patches[name].append(face)
    kinds = {"inlet": "patch", "outlet": "patch", "walls": "wall", "cylinder": "wall"}
    kinds["frontAndBack"] = "empty"
    boundary = "\n".join(
        f"    {name}\n    {{\n        type {kinds[name]};\n        faces\n        (\n"
        + "\n".join(f"            {f}" for f in faces)
        + "\n        );\n    }"
        for name, faces in patches.items()
    )
    text = (
        "FoamFile\n{\n    version 2.0;\n    format ascii;\n    class dictionary;\n"
        "    object blockMeshDict;\n}\n// The DFG 2D-1 blocks of example_data/dfg_blocks.vtp "
        f"with the counts and gradings of {grid.name} (dfg.py blockmesh)\n\n"
        "convertToMeters 1;\n\nvertices\n(\n" + "\n".join(points) + "\n);\n\nblocks\n(\n"
        + "\n".join(hexes) + "\n);\n\nedges\n(\n" + "\n".join(arcs) + "\n);\n\nboundary\n(\n"
        + boundary + "\n);\n"
    )  # fmt: skip
    (case / "system" / "blockMeshDict").write_text(text)


def _arc_side(topo, block) -> int | None:
    """The side of a block that lies on the cylinder, or None."""
    for s, side in enumerate(block.sides):
        points = np.vstack([topo.pieces[p].points for p, _ in side])
        if np.allclose(np.linalg.norm(points - CENTRE, axis=1), DIAMETER / 2):
            return s
    return None


def _unit(v: np.ndarray) -> np.ndarray:
    return v / np.linalg.norm(v)


def _ratio(line: np.ndarray) -> float:
    """Last cell over first cell along a grid line (blockMesh's expansion ratio)."""
    cells = np.linalg.norm(np.diff(line, axis=0), axis=1)
    return float(cells[-1] / cells[0])


def main(argv: list[str]) -> None:
    step, case = argv[0], Path(argv[1])
    if step == "inlet":
        inlet(case)
    elif step == "coefficients":
        found = coefficients(case)
        print(" ".join(f"{k} {v:.6g}" for k, v in found.items()))
    elif step == "blockmesh":
        blockmesh(case, Path(argv[2]), float(argv[3]))
    else:
        raise SystemExit(f"unknown step {step!r}: inlet, coefficients or blockmesh")


if __name__ == "__main__":
    main(sys.argv[1:])
