"""The backward-facing step of Armaly et al. (1983) at Re 389 (docs/openfoam.md): its
boundary, the counts and first cells of a grid of N cells across the step, pinn-mesh's
command-line items for it (automatic blocking, a wall spacing) and blockMesh's dictionary
of the same counts and first cells.

    python examples/openfoam_armaly/armaly.py boundary PATH         # the domain (.csv)
    python examples/openfoam_armaly/armaly.py args N                # pinn-mesh's items
    python examples/openfoam_armaly/armaly.py blockmesh CASE N D    # system/blockMeshDict
    python examples/openfoam_armaly/armaly.py viscosity CASE        # nu for Re 389
    python examples/openfoam_armaly/armaly.py inlet CASE            # 0/U's parabola
    python examples/openfoam_armaly/armaly.py reattachment CASE     # x_r and x_r / S

Lengths in millimetres, as the experiment's: the step S = 4.9 high, the inlet channel 5.2
high (y in [S, 10.1], expansion ratio 10.1 / 5.2 = 1.94), the step's foot at (0, 0). The
inflow is the developed parabola of mean speed 1 five inlet heights upstream of the step;
Re = U_mean D / nu with D = 2 x 5.2 the inlet channel's hydraulic diameter (Armaly's
definition, U_mean two thirds of the peak). The outlet is 50 S behind the step, far beyond
the reattachment near 8 S.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from scipy.optimize import brentq

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "openfoam_step"))

import step  # noqa: E402

STEP = 4.9  # the step's height S (mm)
INLET = 5.2  # the inlet channel's height h (mm)
TOP = STEP + INLET  # the channel's top wall behind the step (10.1 mm)
UPSTREAM = 5 * INLET  # the inlet channel's length: the parabola settles over it
DOWNSTREAM = 50 * STEP  # the outlet's distance behind the step
REYNOLDS = 389.0  # U_mean 2 h / nu, the last steady two-dimensional case of Armaly et al.
MEAN = 1.0  # the inflow's mean speed
FIRST = 0.25  # the first cell at every wall, as a share of the mean cell across the step
LONG = 10  # cells along the channel behind the step per cell across the step
INLET_CELLS = 1  # cells along the inlet channel per cell across the step


def boundary() -> np.ndarray:
    """The domain's six corners, counter-clockwise from the inlet's floor."""
    return np.array(
        [
            [-UPSTREAM, STEP], [0.0, STEP], [0.0, 0.0],
            [DOWNSTREAM, 0.0], [DOWNSTREAM, TOP], [-UPSTREAM, TOP],
        ]
    )  # fmt: skip


def counts(n: int) -> dict[str, float]:
    """A grid of ``n`` cells across the step (even): the cells across the inlet channel
    (even, the step's cell height), along the channel behind the step and along the inlet
    channel, and the first cell at every wall."""
    if n % 2:
        raise ValueError(f"N = {n}: an even number of cells across the step (two graded halves)")
    inlet = 2 * round(n * INLET / STEP / 2)
    return {"step": n, "inlet": inlet, "long": LONG * n, "upstream": INLET_CELLS * n,
            "first": FIRST * STEP / n}  # fmt: skip


def args(n: int) -> list[str]:
    """pinn-mesh's items for the grid of ``n`` cells across the step: automatic blocking,
    the counts of the chains across the inlet, across the outlet and along both channels,
    and the first cell at every wall."""
    c = counts(n)
    return [
        "--blocks", "auto",
        "--cells", f"{-UPSTREAM:g},{TOP - INLET / 2:g}={c['inlet']}",
        "--cells", f"{DOWNSTREAM:g},{TOP / 2:g}={c['step'] + c['inlet']}",
        "--cells", f"{DOWNSTREAM / 2:g},0={c['long']}",
        "--cells", f"{-UPSTREAM / 2:g},{TOP:g}={c['upstream']}",
        "--patch", "boundary=walls:wall",
        "--patch", f"{-UPSTREAM:g},{TOP - INLET / 2:g}=inlet:inflow",
        "--patch", f"{DOWNSTREAM:g},{TOP / 2:g}=outlet:outflow",
        "--spacing", f"walls={c['first']:.6g}",
    ]  # fmt: skip


def growth(first: float, length: float, cells: int) -> float:
    """The ratio q of a geometric series of ``cells`` cells over ``length`` whose first
    cell is ``first`` (blockMesh's expansion ratio is q^(cells - 1))."""
    if abs(first * cells - length) < 1e-12 * length:
        return 1.0
    total = lambda q: first * (q**cells - 1) / (q - 1) - length  # noqa: E731
    if first * cells > length:
        return brentq(total, 1e-9, 1 - 1e-12)
    return brentq(total, 1 + 1e-12, (length / first) ** (1 / (cells - 1)))  # last cell < length


def _both_ends(first: float, length: float, cells: int) -> str:
    """blockMesh's grading of a block edge with a first cell ``first`` at both ends: two
    halves graded towards the middle (``cells`` even)."""
    r = growth(first, length / 2, cells // 2) ** (cells // 2 - 1)
    return f"((0.5 0.5 {r:.8g}) (0.5 0.5 {1 / r:.8g}))"


def blockmesh(case: Path, n: int, depth: float) -> None:
    """system/blockMeshDict: three blocks (the inlet channel, the channel behind the step
    below and above the lip's level) of the counts of ``counts(n)``, each cell next to a
    wall and to the lip's level ``first`` high, the cells along both channels ``first``
    long at the step and growing geometrically away from it, as a user grades blockMesh."""
    c = counts(n)
    first = c["first"]
    along = growth(first, DOWNSTREAM, c["long"]) ** (c["long"] - 1)
    back = growth(first, UPSTREAM, c["upstream"]) ** (c["upstream"] - 1)
    xs, ys = (-UPSTREAM, 0.0, DOWNSTREAM), (0.0, STEP, TOP)
    corners = [(x, y) for y in ys for x in xs]  # vertex 3 j + i
    up = len(corners)
    rows = [(i, j) for i, j in ((0, 1), (1, 0), (1, 1))]  # the blocks' lower-left corners

    def hexa(i: int, j: int) -> str:
        ids = [3 * j + i, 3 * j + i + 1, 3 * (j + 1) + i + 1, 3 * (j + 1) + i]
        nx = c["upstream"] if i == 0 else c["long"]
        ny = c["step"] if j == 0 else c["inlet"]
        gx = 1 / back if i == 0 else along
        gy = _both_ends(first, ys[j + 1] - ys[j], ny)
        return (
            f"    hex ({' '.join(map(str, ids))} {' '.join(str(k + up) for k in ids)}) "
            f"({nx} {ny} 1) edgeGrading ({gx:.8g} {gx:.8g} {gx:.8g} {gx:.8g} "
            f"{gy} {gy} {gy} {gy} 1 1 1 1)"
        )

    def face(a: int, b: int) -> str:  # a to b counter-clockwise round the domain: outward
        return f"({a} {b} {b + up} {a + up})"

    patches = {
        "inlet": [face(6, 3)],
        "outlet": [face(2, 5), face(5, 8)],
        "walls": [face(3, 4), face(4, 1), face(1, 2), face(8, 7), face(7, 6)],
        "frontAndBack": [
            f"({3 * j + i} {3 * (j + 1) + i} {3 * (j + 1) + i + 1} {3 * j + i + 1})"
            for i, j in rows
        ]
        + [
            f"({3 * j + i + up} {3 * j + i + 1 + up} {3 * (j + 1) + i + 1 + up} "
            f"{3 * (j + 1) + i + up})"
            for i, j in rows
        ],  # fmt: skip
    }
    kinds = {"inlet": "patch", "outlet": "patch", "walls": "wall", "frontAndBack": "empty"}
    boundary_text = "\n".join(
        f"    {name}\n    {{\n        type {kinds[name]};\n        faces\n        (\n"
        + "\n".join(f"            {f}" for f in faces)
        + "\n        );\n    }"
        for name, faces in patches.items()
    )
    points = [f"    ({x:.12g} {y:.12g} {z:g})" for z in (0.0, depth) for x, y in corners]
    text = (
        "FoamFile\n{\n    version 2.0;\n    format ascii;\n    class dictionary;\n"
        "    object blockMeshDict;\n}\n// Armaly's step: three blocks, "
        f"{n} cells across the step (armaly.py blockmesh)\n\nscale 1;\n\n"
        "vertices\n(\n" + "\n".join(points) + "\n);\n\nblocks\n(\n"
        + "\n".join(hexa(i, j) for i, j in rows) + "\n);\n\nedges\n(\n);\n\nboundary\n(\n"
        + boundary_text + "\n);\n"
    )  # fmt: skip
    (case / "system" / "blockMeshDict").write_text(text)


def viscosity(case: Path) -> None:
    """constant/transportProperties: nu = U_mean 2 h / Re."""
    nu = MEAN * 2 * INLET / REYNOLDS
    (case / "constant" / "transportProperties").write_text(
        "FoamFile\n{\n    version 2.0;\n    format ascii;\n    class dictionary;\n"
        "    object transportProperties;\n}\n"
        f"// Re = U_mean 2 h / nu = {MEAN:g} x {2 * INLET:g} / nu = {REYNOLDS:g}\n\n"
        f"transportModel  Newtonian;\n\nnu              {nu:.10g};\n"
    )


def reattachment(case: Path) -> float:
    """x_r / S of a solved case (step.reattachment's x_r)."""
    return step.reattachment(case) / STEP


def main(argv: list[str]) -> None:
    what = argv[0]
    if what == "boundary":
        np.savetxt(argv[1], boundary(), delimiter=",", header="x,y", comments="", fmt="%.10g")
    elif what == "args":
        print("\n".join(args(int(argv[1]))))
    elif what == "blockmesh":
        blockmesh(Path(argv[1]), int(argv[2]), float(argv[3]))
    elif what == "viscosity":
        viscosity(Path(argv[1]))
    elif what == "inlet":
        step.inlet(Path(argv[1]), STEP, TOP, MEAN)
    elif what == "reattachment":
        x = reattachment(Path(argv[1]))
        print(f"reattachment {x * STEP:.5f} xr_S {x:.5f}")
    else:
        raise SystemExit(f"unknown step {what!r}: boundary, args, blockmesh, viscosity, "
                         "inlet or reattachment")  # fmt: skip


if __name__ == "__main__":
    main(sys.argv[1:])
