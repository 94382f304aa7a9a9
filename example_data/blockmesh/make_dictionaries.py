"""Writes the three blockMeshDicts of SPEC 15's aims, each in its own case folder
(``<name>/system/blockMeshDict``), as a user would write them by hand:

- ``pipe``: a round pipe (radius 0.05, length 0.5) in the butterfly (O-grid) blocking, a
  centre square and four blocks round it, cells graded toward the wall;
- ``bend``: a square duct (0.1 x 0.1) turning 90 degrees (inner radius 0.1) between two
  straight legs, three blocks;
- ``dfg3d``: the DFG 3D-1Z channel (2.5 x 0.41 x 0.41, a cylinder of D = 0.1 at x = 0.5,
  y = 0.2 spanning z), an O-ring of four blocks round the cylinder and eight blocks round it.

    .venv/bin/python example_data/blockmesh/make_dictionaries.py
"""

from __future__ import annotations

import math
from pathlib import Path

HERE = Path(__file__).resolve().parent
HEADER = """FoamFile
{
    version     2.0;
    format      ascii;
    class       dictionary;
    object      blockMeshDict;
}

"""


def _vec(p) -> str:
    return "(" + " ".join(f"{v:.10g}" for v in p) + ")"


def text(vertices, blocks, edges, patches, scale: float = 1.0) -> str:
    """A blockMeshDict's text."""
    lines = [HEADER, f"scale {scale:g};\n\nvertices\n(\n"]
    lines += [f"    {_vec(v)} // {k}\n" for k, v in enumerate(vertices)]
    lines.append(");\n\nblocks\n(\n")
    lines += [f"    {b}\n" for b in blocks]
    lines.append(");\n\nedges\n(\n")
    lines += [f"    {e}\n" for e in edges]
    lines.append(");\n\nboundary\n(\n")
    for pname, kind, faces in patches:
        body = "\n".join(f"            ({' '.join(map(str, f))})" for f in faces)
        lines.append(
            f"    {pname}\n    {{\n        type {kind};\n        faces\n        (\n{body}\n"
            "        );\n    }\n"
        )
    lines.append(");\n\nmergePatchPairs\n(\n);\n")
    return "".join(lines)


def _write(name: str, dictionary: str) -> None:
    out = HERE / name / "system" / "blockMeshDict"
    out.parent.mkdir(parents=True, exist_ok=True)
    out.write_text(dictionary)


def extruded(base, z0: float, z1: float):
    """Vertices of a 2D blocking at z0, then the same at z1."""
    return [(x, y, z0) for x, y in base] + [(x, y, z1) for x, y in base]


def hexes(quads, n: int, counts, grading):
    """Hex blocks of 2D quads (counter-clockwise) extruded between the two vertex layers."""
    out = []
    for q, c, g in zip(quads, counts, grading):
        ids = " ".join(map(str, [*q, *(v + n for v in q)]))
        out.append(f"hex ({ids}) ({' '.join(map(str, c))}) simpleGrading ({' '.join(map(str, g))})")
    return out


def pipe(
    square: float = 0.4,
    grade: float = 3.0,
    layers: int = 1,
    bulge: float = 1.0,
    cells: tuple[int, int, int] = (12, 10, 40),
) -> str:
    """The butterfly pipe's dictionary: the centre square's half-side ``square`` radii, its
    edges arcs through ``bulge`` times the half-side (1: straight), the outer blocks' cells
    growing ``grade`` times from the wall to the square, ``layers`` blocks along the axis,
    ``cells`` across the square, from the wall to the square and along the axis."""
    r, length = 0.05, 0.5
    a, c = square * r, r / math.sqrt(2)
    base = [(-a, -a), (a, -a), (a, a), (-a, a), (-c, -c), (c, -c), (c, c), (-c, c)]
    n = len(base)
    zs = [length * k / layers for k in range(layers + 1)]
    verts = [(x, y, z) for z in zs for x, y in base]
    quads = [(0, 1, 2, 3), (4, 5, 1, 0), (5, 6, 2, 1), (6, 7, 3, 2), (7, 4, 0, 3)]
    nc, nr, nz = cells[0], cells[1], cells[2] // layers
    counts = [(nc, nc, nz)] + [(nc, nr, nz)] * 4
    grading = [(1, 1, 1)] + [(1, f"{grade:g}", 1)] * 4  # j runs wall to square
    blocks = []
    for layer in range(layers):
        ids = [[v + n * layer for v in q] for q in quads]
        blocks += hexes(ids, n, counts, grading)
    mids = [(0, -r), (r, 0), (0, r), (-r, 0)]
    ring = [(4, 5), (5, 6), (6, 7), (7, 4)]
    edges = []
    for layer, z in enumerate(zs):
        for (p, q), m in zip(ring, mids):
            edges.append(f"arc {p + n * layer} {q + n * layer} {_vec((*m, z))}")
            if bulge != 1:  # the centre square's edge under this ring edge
                out = [bulge * a * v / r for v in m]
                edges.append(f"arc {p - 4 + n * layer} {q - 4 + n * layer} {_vec((*out, z))}")
    top = n * layers
    inlet = [tuple(reversed(q)) for q in quads]
    outlet = [tuple(v + top for v in q) for q in quads]
    wall = [(p + n * k, q + n * k, q + n * (k + 1), p + n * (k + 1)) for k in range(layers)
            for p, q in ring]  # fmt: skip
    patches = [("inlet", "patch", inlet), ("outlet", "patch", outlet), ("wall", "wall", wall)]
    return text(verts, blocks, edges, patches)


def bend() -> None:
    ri, ro, leg, depth = 0.1, 0.2, 0.4, 0.1
    base = [(-leg, -ro), (0, -ro), (0, -ri), (-leg, -ri), (ro, 0), (ri, 0), (ro, leg), (ri, leg)]
    n = len(base)
    verts = extruded(base, 0.0, depth)
    quads = [(0, 1, 2, 3), (1, 4, 5, 2), (4, 6, 7, 5)]
    nx, ny, nz, nb = 30, 12, 12, 24
    counts = [(nx, ny, nz), (nb, ny, nz), (nx, ny, nz)]
    grading = [(1, 1, 1)] * 3
    blocks = hexes(quads, n, counts, grading)
    edges = []
    for layer, z in ((0, 0.0), (n, depth)):
        h = math.sqrt(0.5)
        edges.append(f"arc {1 + layer} {4 + layer} {_vec((ro * h, -ro * h, z))}")
        edges.append(f"arc {2 + layer} {5 + layer} {_vec((ri * h, -ri * h, z))}")
    sides = [(0, 1), (1, 4), (4, 6), (7, 5), (5, 2), (2, 3)]
    walls = [(p, q, q + n, p + n) for p, q in sides]
    ends = [tuple(reversed(q)) for q in quads] + [tuple(v + n for v in q) for q in quads]
    patches = [
        ("inlet", "patch", [(3, 0, 0 + n, 3 + n)]),
        ("outlet", "patch", [(6, 7, 7 + n, 6 + n)]),
        ("walls", "wall", walls + ends),
    ]
    _write("bend", text(verts, blocks, edges, patches))


def dfg3d(s: float = 0.1, ring: float = 0.25, layers: int = 1, size: float = 1.0) -> str:
    """The DFG 3D-1Z channel's dictionary: the square round the cylinder of half-width
    ``s``, the O-ring's cells shrinking ``1 / ring`` times toward the cylinder, ``layers``
    blocks along z, every block's cell counts ``size`` times the default's (rounded)."""
    length, height, xc, yc, rad = 2.5, 0.41, 0.5, 0.2, 0.05
    h = rad / math.sqrt(2)
    x0, x1 = xc - s, xc + s
    y0, y1 = yc - s, yc + s
    base = [
        (xc - h, yc - h), (xc + h, yc - h), (xc + h, yc + h), (xc - h, yc + h),  # 0-3 cylinder
        (x0, y0), (x1, y0), (x1, y1), (x0, y1),  # 4-7 square
        (0, 0), (x0, 0), (x1, 0), (length, 0),  # 8-11 bottom wall
        (0, y0), (length, y0), (0, y1), (length, y1),  # 12-15
        (0, height), (x0, height), (x1, height), (length, height),  # 16-19 top wall
    ]  # fmt: skip
    n = len(base)
    zs = [height * k / layers for k in range(layers + 1)]
    verts = [(x, y, z) for z in zs for x, y in base]
    quads = [
        (4, 5, 1, 0), (5, 6, 2, 1), (6, 7, 3, 2), (7, 4, 0, 3),  # O-ring
        (8, 9, 4, 12), (9, 10, 5, 4), (10, 11, 13, 5),  # below
        (12, 4, 7, 14), (5, 13, 15, 6),  # beside
        (14, 7, 17, 16), (7, 6, 18, 17), (6, 15, 19, 18),  # above
    ]  # fmt: skip
    nc, nr, nu, nd, nw, nz = (round(size * c) for c in (16, 16, 12, 60, 8, 24 // layers))
    counts = [
        (nc, nr, nz), (nc, nr, nz), (nc, nr, nz), (nc, nr, nz),
        (nu, nw, nz), (nc, nw, nz), (nd, nw, nz),
        (nu, nc, nz), (nd, nc, nz),
        (nu, nw, nz), (nc, nw, nz), (nd, nw, nz),
    ]  # fmt: skip
    ring_grade = (1, f"{ring:g}", 1)  # j runs square to cylinder: cells shrink toward it
    grading = [ring_grade] * 4 + [(1, 1, 1)] * 3 + [(1, 1, 1), (3, 1, 1)] + [(1, 1, 1)] * 3
    grading[6] = (3, 1, 1)
    grading[11] = (3, 1, 1)
    blocks = []
    for layer in range(layers):
        blocks += hexes([[v + n * layer for v in q] for q in quads], n, counts, grading)
    edges = []
    for layer, z in enumerate(zs):
        for (p, q), ang in zip(((0, 1), (1, 2), (2, 3), (3, 0)), (270, 0, 90, 180)):
            t = math.radians(ang)
            mid = (xc + rad * math.cos(t), yc + rad * math.sin(t), z)
            edges.append(f"arc {p + n * layer} {q + n * layer} {_vec(mid)}")

    def side(p, q):
        return [(p + n * k, q + n * k, q + n * (k + 1), p + n * (k + 1)) for k in range(layers)]

    def sides(*pairs):
        return [f for p, q in pairs for f in side(p, q)]

    top = n * layers
    patches = [
        ("inlet", "patch", sides((12, 8), (14, 12), (16, 14))),
        ("outlet", "patch", sides((11, 13), (13, 15), (15, 19))),
        (
            "walls",
            "wall",
            sides((8, 9), (9, 10), (10, 11), (19, 18), (18, 17), (17, 16))
            + [tuple(reversed(q)) for q in quads]
            + [tuple(v + top for v in q) for q in quads],
        ),
        ("cylinder", "wall", sides((1, 0), (2, 1), (3, 2), (0, 3))),
    ]
    return text(verts, blocks, edges, patches)


if __name__ == "__main__":
    _write("pipe", pipe())
    bend()
    _write("dfg3d", dfg3d())
