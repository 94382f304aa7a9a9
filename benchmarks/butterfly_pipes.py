"""Butterfly (O-grid) pipes meshed by pinn-mesh beside blockMesh (SPEC 15), checkMesh
measuring both: the pipes users write, not only ours.

    .venv/bin/python benchmarks/butterfly_pipes.py                 # both halves
    .venv/bin/python benchmarks/butterfly_pipes.py --set report    # one half

Each dictionary is meshed by ``pinn-mesh DICT -o CASE --format openfoam`` and by blockMesh
(``blockmesh3d.run_case``); printed per pipe: cells and patches (ours / blockMesh's),
checkMesh's verdict, largest and mean non-orthogonality, largest skewness, the grid kept and
the CPU times; then how many pass SPEC 15's aims on the pipe: Mesh OK, the same cells and
patches, skewness no worse and non-orthogonality at least ``GAIN`` degrees lower.

The halves: ``tuning``, a generated sweep (centre square's half-side 0.4 to 0.7 radii, its
edges straight or arcs bulging 1.15 or 1.3 times out, cells uniform or graded 4:1 toward
the wall; ``make_dictionaries.pipe``), on which the method was tuned; ``report``, public
users' dictionaries, held out, each written here from its parameters (radius, length, the
centre square, cell counts, vertex order, axis and patch syntax as its author wrote them):

- ``cylinderMesh.m4`` of CFDEMcoupling's fluidized bed tutorial (ParticulateFlow/
  CFDEMcoupling-PFM, ``tutorials/cfdemSolverRhoPimpleChem/PolydisperseFluidizedBed``): D 68
  mm, the square's half-side R/2, 7 cells across it and 3 to the wall, 24 along y;
- NREL BioReactorDesign's airlift column (``tutorial_cases/airlift_40m``), the same
  template at D 5, L 40, 5 and 5 cells across, 200 along;
- a Python O-grid generator for a Poiseuille pipe study: the square's corners at half the
  wall's radius, 20 cells across and 20 to the wall, 4 along x, inlet and outlet cyclic;
- a GUI's cylinder template: the square's corners at half the radius, 10 cells across and
  6 to the wall, 20 along z;
- a Womersley pipe's rounded square: corners at half the radius, edges arcs through the
  circle of the square's area (0.399 R), uniform cells.

Needs OpenFOAM (blockMesh, checkMesh).
"""

from __future__ import annotations

import argparse
import math
import os
import re
import sys
import tempfile
from pathlib import Path

from blockmesh3d import ROOT, compile_package, run_case, table

sys.path.insert(0, str(ROOT / "example_data" / "blockmesh"))
from make_dictionaries import HEADER, pipe  # noqa: E402

GAIN = 5.0  # degrees of non-orthogonality under blockMesh's that SPEC 15 asks on the pipe


def _v(p) -> str:
    return "(" + " ".join(f"{x:.10g}" for x in p) + ")"


def _dictionary(verts, blocks: list[str], edges: list[str], patches: list[str]) -> str:
    """A dictionary's text of its vertices, blocks, edges and patches (each a ``boundary``
    entry)."""
    return (
        f"{HEADER}convertToMeters 1;\nvertices\n(\n"
        + "\n".join(f"    {_v(p)}" for p in verts)
        + "\n);\nblocks\n(\n    "
        + "\n    ".join(blocks)
        + "\n);\nedges\n(\n    "
        + "\n    ".join(edges)
        + "\n);\nboundary\n(\n    "
        + "\n    ".join(patches)
        + "\n);\n"
    )


def cylinder_m4(d: float, length: float, nps: int, npd: int, npy: int) -> str:
    """The cylinderMesh.m4 template (a cfd-online post's, as CFDEMcoupling and NREL use it):
    axis y, the square's half-side D/4, ring corners at 45 degrees, old ``patches``."""
    r, cw = d / 2, d / 4
    cx = r * math.cos(math.pi / 4)
    names = ["5sqb", "7sqb", "11sqb", "1sqb", "5cb", "7cb", "11cb", "1cb"]
    base = [(cw, cw), (-cw, cw), (-cw, -cw), (cw, -cw), (cx, cx), (-cx, cx), (-cx, -cx), (cx, -cx)]
    at = {}
    verts = []
    for y, tag in ((0.0, "b"), (length, "t")):
        for name, (x, z) in zip(names, base):
            at[name[:-1] + tag] = len(verts)
            verts.append((x, y, z))

    def hx(*ns: str) -> str:
        return " ".join(str(at[n]) for n in ns)

    blocks = [
        (hx("7sqb", "5sqb", "1sqb", "11sqb", "7sqt", "5sqt", "1sqt", "11sqt"), (nps, nps, npy)),
        (hx("7cb", "5cb", "5sqb", "7sqb", "7ct", "5ct", "5sqt", "7sqt"), (nps, npd, npy)),
        (hx("7sqb", "11sqb", "11cb", "7cb", "7sqt", "11sqt", "11ct", "7ct"), (nps, npd, npy)),
        (hx("11sqb", "1sqb", "1cb", "11cb", "11sqt", "1sqt", "1ct", "11ct"), (nps, npd, npy)),
        (hx("1sqb", "5sqb", "5cb", "1cb", "1sqt", "5sqt", "5ct", "1ct"), (nps, npd, npy)),
    ]
    edges = []
    for y, t in ((0.0, "b"), (length, "t")):
        for p, q, mid in (
            ("5c", "7c", (0, y, r)),
            ("7c", "11c", (-r, y, 0)),
            ("11c", "1c", (0, y, -r)),
            ("1c", "5c", (r, y, 0)),
        ):
            edges.append(f"arc {at[p + t]} {at[q + t]} {_v(mid)}")

    def faces(*quads):
        return " ".join("(" + hx(*q) + ")" for q in quads)

    def ends(t: str) -> str:
        return faces(
            (f"5sq{t}", f"1sq{t}", f"11sq{t}", f"7sq{t}"),
            (f"5sq{t}", f"5c{t}", f"1c{t}", f"1sq{t}"),
            (f"5c{t}", f"5sq{t}", f"7sq{t}", f"7c{t}"),
            (f"7sq{t}", f"11sq{t}", f"11c{t}", f"7c{t}"),
            (f"1sq{t}", f"1c{t}", f"11c{t}", f"11sq{t}"),
        )

    walls = faces(
        ("7cb", "5cb", "5ct", "7ct"),
        ("7cb", "7ct", "11ct", "11cb"),
        ("11cb", "11ct", "1ct", "1cb"),
        ("1cb", "1ct", "5ct", "5cb"),
    )
    body = "\n".join(f"    {_v(p)}" for p in verts)
    hexes = "\n".join(f"    hex ({ids}) ({' '.join(map(str, c))}) simpleGrading (1 1 1)"
                      for ids, c in blocks)  # fmt: skip
    return (
        f"{HEADER}convertToMeters 1.0;\n\nvertices\n(\n{body}\n);\n\nblocks\n(\n{hexes}\n);\n\n"
        f"edges\n(\n    " + "\n    ".join(edges) + "\n);\n\npatches\n(\n"
        f"    patch inlet\n    ({ends('b')})\n    patch outlet\n    ({ends('t')})\n"
        f"    wall side-walls\n    ({walls})\n);\n\nmergePatchPairs\n(\n);\n"
    )


def ogrid_generator(a: float, length: float, n_c: int, n_r: int, nx: int, f: float) -> str:
    """A Python O-grid generator's pipe: axis x, the section in (y, z), ring corners at 45
    degrees, the square's corners at ``f`` of theirs, blocks listed clockwise, inlet and
    outlet a cyclic pair."""
    s = a / math.sqrt(2)
    pts = [(f * s, f * s), (-f * s, f * s), (-f * s, -f * s), (f * s, -f * s)]
    pts += [(s, s), (-s, s), (-s, -s), (s, -s)]
    verts = [(x, y, z) for x in (0.0, length) for y, z in pts]
    blocks = [f"hex (0 1 2 3 8 9 10 11) ({n_c} {n_c} {nx}) simpleGrading (1 1 1)"]
    for k in range(4):
        i0, i1, o0, o1 = k, (k + 1) % 4, 4 + k, 4 + (k + 1) % 4
        ids = f"{i1} {i0} {o0} {o1} {i1 + 8} {i0 + 8} {o0 + 8} {o1 + 8}"
        blocks.append(f"hex ({ids}) ({n_c} {n_r} {nx}) simpleGrading (1 1 1)")
    mids = [(0.0, a), (-a, 0.0), (0.0, -a), (a, 0.0)]
    edges = [
        f"arc {4 + k + plane} {4 + (k + 1) % 4 + plane} {_v((x, *mids[k]))}"
        for plane, x in ((0, 0.0), (8, length))
        for k in range(4)
    ]
    inlet = ["(0 1 2 3)"] + [f"({k} {(k + 1) % 4} {4 + (k + 1) % 4} {4 + k})" for k in range(4)]
    outlet = ["(8 11 10 9)"] + [
        f"({k + 8} {4 + k + 8} {4 + (k + 1) % 4 + 8} {(k + 1) % 4 + 8})" for k in range(4)
    ]
    wall = [f"({4 + k} {4 + (k + 1) % 4} {4 + (k + 1) % 4 + 8} {4 + k + 8})" for k in range(4)]
    return _dictionary(
        verts,
        blocks,
        edges,
        [
            f"inlet {{ type cyclic; neighbourPatch outlet; faces ({' '.join(inlet)}); }}",
            f"outlet {{ type cyclic; neighbourPatch inlet; faces ({' '.join(outlet)}); }}",
            f"wall {{ type wall; faces ({' '.join(wall)}); }}",
        ],
    )


def gui_template(radius: float, length: float, n_circ: int, n_radial: int, n_axial: int) -> str:
    """A GUI's cylinder template: axis z, the square's corners at half the radius (45
    degrees), the outer blocks from the square's side to the ring's, (radial, circ, axial)."""
    inner = radius * 0.5
    angles = [math.radians(45 + 90 * k) for k in range(4)]
    verts = []
    for z in (0.0, length):
        verts += [(inner * math.cos(t), inner * math.sin(t), z) for t in angles]
        verts += [(radius * math.cos(t), radius * math.sin(t), z) for t in angles]
    blocks = [f"hex (0 1 2 3 8 9 10 11) ({n_circ} {n_circ} {n_axial}) simpleGrading (1 1 1)"]
    for k in range(4):
        nx = (k + 1) % 4
        ids = f"{k} {4 + k} {4 + nx} {nx} {8 + k} {12 + k} {12 + nx} {8 + nx}"
        blocks.append(f"hex ({ids}) ({n_radial} {n_circ} {n_axial}) simpleGrading (1 1 1)")
    edges = []
    for side, z in enumerate((0.0, length)):
        base = 4 + side * 8
        for k in range(4):
            t = math.radians(90 + 90 * k)
            mid = (radius * math.cos(t), radius * math.sin(t), z)
            edges.append(f"arc {base + k} {base + (k + 1) % 4} {_v(mid)}")
    inlet = ["(0 1 2 3)"] + [f"({k} {(k + 1) % 4} {4 + (k + 1) % 4} {4 + k})" for k in range(4)]
    outlet = ["(8 9 10 11)"] + [
        f"({8 + k} {8 + (k + 1) % 4} {12 + (k + 1) % 4} {12 + k})" for k in range(4)
    ]
    walls = [f"({4 + k} {4 + (k + 1) % 4} {12 + (k + 1) % 4} {12 + k})" for k in range(4)]
    return _dictionary(
        verts,
        blocks,
        edges,
        [
            f"inlet {{ type patch; faces ({' '.join(inlet)}); }}",
            f"outlet {{ type patch; faces ({' '.join(outlet)}); }}",
            f"walls {{ type wall; faces ({' '.join(walls)}); }}",
        ],
    )


def womersley() -> str:
    """A Womersley pipe's rounded square (R 1 scaled to the example's 0.05): corners at half
    the radius, edges arcs through the circle of the square's area."""
    square = 0.5 / math.sqrt(2)  # corners at r = R / 2
    rounded = math.sqrt(0.5 / math.pi)  # the circle of the square's area (R = 1)
    return pipe(square=square, grade=1, bulge=rounded / square, cells=(8, 8, 12))


SETS = {
    "tuning": {
        f"square {sq:g} R, bulge {b:g}, grading {g:g}": (sq, b, g)
        for sq in (0.4, 0.5, 0.6, 0.7)
        for b in (1.0, 1.15, 1.3)
        for g in (1.0, 4.0)
    },
    "report": {
        "CFDEMcoupling cylinderMesh.m4": lambda: cylinder_m4(0.068, 0.150, 7, 3, 24),
        "NREL airlift cylinderMesh.m4": lambda: cylinder_m4(5.0, 40.0, 5, 5, 200),
        "O-grid generator (cyclic)": lambda: ogrid_generator(1.0, 0.5, 20, 20, 4, 0.5),
        "GUI cylinder template": lambda: gui_template(0.5, 2.0, 10, 6, 20),
        "Womersley rounded square": womersley,
    },
}


def text_of(where) -> str:
    if callable(where):
        return where()
    sq, b, g = where
    return pipe(square=sq, grade=g, bulge=b)


def passes(row: dict) -> bool:
    """SPEC 15's aims on the pipe: Mesh OK, blockMesh's cells and patches, skewness no
    worse, non-orthogonality at least ``GAIN`` degrees lower."""
    ours, ref = row.get("ours"), row.get("ref")
    return bool(
        ours
        and ref
        and ours["ok"]
        and ours["cells"] == ref["cells"]
        and ours["patches"] == ref["patches"]
        and ours["skew"] <= ref["skew"]
        and ours["nonorth"] <= ref["nonorth"] - GAIN
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", choices=tuple(SETS), action="append", help="default: both")
    parser.add_argument("--runs", type=int, default=1, help="runs of each tool (their median)")
    opts = parser.parse_args()
    compile_package()
    before = os.getloadavg()[0]
    summary = []
    with tempfile.TemporaryDirectory(prefix="pinn-mesh-butterfly-") as scratch:
        for set_name in opts.set or SETS:
            rows = []
            for name, where in SETS[set_name].items():
                folder = Path(scratch) / set_name / re.sub(r"\W+", "_", name)
                rows.append(run_case(name, text_of(where), folder, opts.runs))
                print(table(rows[-1:]).splitlines()[-1], flush=True)
            print(table(rows))
            good = sum(passes(r) for r in rows)
            summary.append(f"{set_name}: {good} of {len(rows)} pass")
    print("; ".join(summary))
    print(f"load average {before:.1f} before, {os.getloadavg()[0]:.1f} after, on 2 shared cores")


if __name__ == "__main__":
    main()
