"""O- and C-grids around NACA sections, side by side with Construct2D.

Construct2D (https://github.com/furstj/Construct2D, GPL; used here as an external program
only) is built from its source with gfortran (``make``) and run non-interactively with its
default settings::

    printf 'GRID\\nSMTH\\nQUIT\\n' | construct2d naca0012.dat

which writes ``naca0012.p3d`` (PLOT3D, 2D): an O-grid around a blunt trailing edge, a C-grid
around a sharp one, far field 15 chords, first layer from y+ = 0.9 at Re = 1e6. Each of our
methods then meshes the same airfoil file at the same size, with Construct2D's first-layer
height (``--spacing bottom=H``) and a far-field circle of 15 chords.

    python benchmarks/airfoils.py --construct2d /path/to/construct2d [--write docs/airfoils.md]

The airfoil files are written by pinn-mesh's NACA generator (201 points per surface):
``naca0012.dat`` (blunt trailing edge, the classical formula), ``naca0012_sharp.dat`` and
``naca4412_sharp.dat`` (closed trailing edge), ``naca4412.dat`` (blunt),
``naca4417_base07.dat`` (a blunt base of 0.7 % chord, as the LS(1)-0417 file) and
``naca0012_gap1e5.dat`` (open by 1e-5 chord, as many public files). The blunt base of 0.7 %
is meshed as an O-grid and as a C-grid (the cut leaving the base's middle; Construct2D's
C-grid asked for with its TOPO option). Besides the quality
figures, each grid's largest face non-orthogonality (checkMesh's, quality.non_orthogonality)
and its wall nodes' largest distance from the drawn polyline; and the default C-grid's time
at 320 x 90 beside Construct2D's at the same size.
"""

from __future__ import annotations

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from pinn_engine.bodies.airfoil import SHARP_GAP, circle, load_body, naca4  # noqa: E402
from pinn_engine.geometry.boundary import segment_distance  # noqa: E402
from pinn_engine.kinds.body.mesh import mesh_body, wall_metrics  # noqa: E402
from pinn_engine.quality import cell_quality, summary, worst_non_orthogonality  # noqa: E402
from pinn_engine.settings import make_settings  # noqa: E402

CASES = (  # file stem, NACA code, trailing edge: blunt, sharp or a gap in chords
    ("naca0012", "0012", "blunt"),
    ("naca0012_sharp", "0012", "sharp"),
    ("naca4412", "4412", "blunt"),
    ("naca4412_sharp", "4412", "sharp"),
    ("naca4417_base07", "4417", 0.007),  # a blunt base of 0.7 % chord, as LS(1)-0417's
    ("naca0012_gap1e5", "0012", 1e-5),  # open by 1e-5 chord, as many public files
)
METHODS = ("tfi", "elliptic", "pinn")
# blunt trailing edges also meshed as C-grids (the cut leaves the base's middle)
BLUNT_C_GRIDS = ("naca4417_base07",)
# The default C-grid at 320 x 90 (first layer as Construct2D's, 1.04e-5),
# timed over SPEED_RUNS runs (the median), against at most SPEED_TARGET seconds
SPEED_SIZE, SPEED_RUNS, SPEED_TARGET = (320, 90), 3, 1.0
# the worst cell may exceed the bound that the wall's corners force by this much (the corner
# cell's angle equals the bound when its first edge bisects the corner; 0.5 degree of tilt)
FLOOR_TOL = 0.5


def write_dat(path: Path, code: str, te: str | float) -> None:
    """A Selig file of NACA ``code``: ``te`` "sharp", "blunt" (the classical formula) or
    a trailing-edge gap in chords (the sharp section opened linearly along the chord)."""
    xy = naca4(code, points=201, te=te if isinstance(te, str) else "sharp")
    if not isinstance(te, str):
        n = len(xy) // 2
        xy[:, 1] += np.where(np.arange(len(xy)) <= n, 0.5, -0.5) * te * xy[:, 0]
    path.write_text(f"NACA {code}\n" + "".join(f"{x:12.8f} {y:12.8f}\n" for x, y in xy))


def read_p3d(path: Path) -> np.ndarray:
    tok = path.read_text().split()
    ni, nj = int(tok[0]), int(tok[1])
    v = np.array(tok[2 : 2 + 2 * ni * nj], dtype=float)
    return np.stack([v[: ni * nj].reshape(nj, ni), v[ni * nj :].reshape(nj, ni)], axis=-1)


def c2d_figures(g: np.ndarray) -> dict:
    """Quality, first layer and wall angles of a Construct2D grid (O or C, either sense)."""
    q = summary(cell_quality(g), 0.0)
    row = g[0]
    if np.allclose(row[0], row[-1]) and np.allclose(g[:, 0], g[:, -1]):
        topology, n_wake = "o", 0
    else:
        topology = "c"
        same = np.all(np.isclose(row, row[::-1], atol=1e-12), axis=1)
        n_wake = int(np.argmin(same[: len(row) // 2])) - 1
    w = wall_metrics(g, topology, n_wake, sharp=topology == "c")
    return {**q, **w, "topology": topology, "wake_nodes": n_wake}


def run_construct2d(
    exe: str, dat: Path, size: tuple[int, int] | None = None, c_grid: bool = False
) -> tuple[np.ndarray, float]:
    """Construct2D's grid of ``dat`` and its time; at its default size and topology (O for
    a trailing-edge gap, C for none), a C-grid if ``c_grid``, or a C-grid of ``size`` (its
    surface points ni - 2 x its 50 wake points, and ni x nj)."""
    menu = "GRID\nSMTH\nQUIT\n"
    if c_grid or size is not None:
        menu = "VOPT\nTOPO\nCGRD\nQUIT\n" + menu
    if size is not None:
        menu = f"SOPT\nNSRF\n{size[0] - 100}\nQUIT\nVOPT\nJMAX\n{size[1]}\nQUIT\n" + menu
    start = time.perf_counter()
    subprocess.run(
        [exe, dat.name],
        input=menu,
        text=True,
        cwd=dat.parent,
        capture_output=True,
        check=True,
        timeout=600,
    )
    return read_p3d(dat.with_suffix(".p3d")), time.perf_counter() - start


def solver_figures(g: np.ndarray, ring: np.ndarray, wall: np.ndarray, chord: float) -> dict:
    """checkMesh's largest face non-orthogonality (quality.non_orthogonality; the cut's and
    seam's faces aside) and the wall nodes' largest distance from the drawn polyline."""
    return {
        "non_orthogonality": worst_non_orthogonality(g),
        "wall_off": float(segment_distance(wall, ring[:-1]).max()) / chord,
    }


def corner_floor(wall: np.ndarray) -> float:
    """The worst MaxIncludedAngle that an O-grid's wall nodes force (as quality.angle_floor
    on a four-sided grid): half the flow's angle at a wall node, which two cells share (about
    135 degrees at the corners of a blunt base square to the surface, 172 at a sharp edge)."""
    ring = wall[:-1]  # counter-clockwise, the seam's node once
    ahead, back = np.roll(ring, -1, axis=0) - ring, np.roll(ring, 1, axis=0) - ring
    cross = ahead[:, 0] * back[:, 1] - ahead[:, 1] * back[:, 0]
    body = np.degrees(np.arctan2(cross, np.einsum("ij,ij->i", ahead, back))) % 360
    return float(np.max(360 - body)) / 2


def row(name: str, q: dict, seconds: float) -> str:
    return (
        f"| {name} | {q['mean_max_angle']:.2f} | {q['worst_max_angle']:.2f} | "
        f"{q['folded_cells']} | {q['wall_angle_deviation']:.2f} | "
        f"{q['first_layer']['min']:.3g} .. {q['first_layer']['max']:.3g} | "
        f"{q['non_orthogonality']:.1f} | {100 * q['wall_off']:.3f} | {seconds:.1f} |"
    )


def speed(exe: str, dat: Path) -> str:
    """The default C-grid at ``SPEED_SIZE`` in the engine and as a whole
    command, and Construct2D's at the same size (medians of ``SPEED_RUNS`` runs)."""
    c2d = [run_construct2d(exe, dat, SPEED_SIZE) for _ in range(SPEED_RUNS)]
    g = c2d[0][0]
    h = float(np.linalg.norm(g[1] - g[0], axis=1).max())
    body = load_body(dat)
    ni, nj = SPEED_SIZE
    engine, command = [], []
    out = dat.with_suffix(".vts")
    argv = [str(ROOT / ".venv" / "bin" / "pinn-mesh"), str(dat), "--topology", "c"]
    argv += ["--size", str(ni), str(nj), "--spacing", f"bottom={h}", "--quiet", "-o", str(out)]
    for _ in range(SPEED_RUNS):
        t0 = time.perf_counter()
        mesh_body(body, circle(body, 15), "c", "pinn", ni, nj, wall_spacing=h)
        engine.append(time.perf_counter() - t0)
        t0 = time.perf_counter()
        subprocess.run(argv, check=True, capture_output=True)
        command.append(time.perf_counter() - t0)
    t_engine, t_command = float(np.median(engine)), float(np.median(command))
    t_c2d = float(np.median([t for _, t in c2d]))
    return (
        f"Default C-grid {ni} x {nj}, first layer {h:.3g} (median of {SPEED_RUNS}): pinn-mesh "
        f"{t_engine:.2f} s in the engine ({t_command:.2f} s the whole command, Python and "
        f"torch start-up included); Construct2D {t_c2d:.2f} s -> "
        f"{'within' if t_engine <= SPEED_TARGET else 'OUTSIDE'} the target "
        f"({SPEED_TARGET:g} s)"
    )


def compare(
    exe: str, dat: Path, stem: str, code: str, te, c_grid: bool, header: str, verdicts: list
) -> list[str]:
    """Construct2D's grid of ``dat`` (a C-grid if ``c_grid``) and each method's at its size:
    the table's lines; the verdicts against the targets are appended to ``verdicts``."""
    lines = []
    g, secs = run_construct2d(exe, dat, c_grid=c_grid)
    ref = c2d_figures(g)
    nj, ni = g.shape[:2]
    h = ref["first_layer"]["max"]
    edge = te if isinstance(te, str) else f"{te:g} chord open"
    title = (
        f"NACA {code}, {edge} trailing edge, "
        f"{ref['topology'].upper()}-grid {ni} x {nj}, first layer {h:.3g}, "
        "far field 15 chords"
    )
    print(f"\n{title}\n{header}")
    lines += [f"\n**{title}**\n", header]
    body = load_body(dat)
    ring, chord = body.ring(), body.chord
    c2d_wall = g[0][ref["wake_nodes"] : g.shape[1] - ref["wake_nodes"]]
    ref.update(solver_figures(g, ring, c2d_wall, chord))
    text = row("Construct2D (hyperbolic + smoothing)", ref, secs)
    print(text, flush=True)
    lines.append(text)
    for method in METHODS:
        settings = make_settings(method, lattice=(ni, nj))
        t0 = time.perf_counter()
        r = mesh_body(
            body,
            circle(body, 15),
            ref["topology"],
            method,
            ni,
            nj,
            settings,
            wall_spacing=h,
        )
        secs = time.perf_counter() - t0
        q = {**r.quality, **r.report["topology"]}
        n_w = r.report["topology"]["wake_nodes"]
        wall = r.points[0][n_w : r.points.shape[1] - n_w]
        q.update(solver_figures(r.points, ring, wall, chord))
        text = row(f"pinn-mesh {method}", q, secs)
        print(text, flush=True)
        lines.append(text)
        if method != "tfi":
            dm = q["mean_max_angle"] - ref["mean_max_angle"]
            dw = q["worst_max_angle"] - ref["worst_max_angle"]
            floor = corner_floor(wall) if ref["topology"] == "o" else 0.0
            ok = dm <= 2 and q["folded_cells"] == 0
            ok &= q["worst_max_angle"] <= max(ref["worst_max_angle"] + 5, floor + FLOOR_TOL)
            verdicts.append(
                f"{stem} {ref['topology'].upper()}-grid {method}: mean {dm:+.2f}, "
                f"worst {dw:+.2f} deg "
                f"against Construct2D -> {'within' if ok else 'OUTSIDE'} "
                "the target (mean +2, worst +5 or the corners' bound "
                f"{floor:.1f}, no fold)"
            )
    return lines


def write_block(path: str, name: str, lines: list[str]) -> None:
    """Write ``lines`` into the Markdown file ``path`` between its ``name`` markers."""
    md = Path(path)
    text = md.read_text() if md.exists() else ""
    start, end = f"<!-- {name}:begin -->", f"<!-- {name}:end -->"
    block = start + "\n" + "\n".join(lines) + "\n" + end
    if start in text and end in text:
        text = text[: text.index(start)] + block + text[text.index(end) + len(end) :]
    else:
        text += "\n" + block + "\n"
    md.write_text(text)
    print(f"wrote {md}")


def real_set(args: argparse.Namespace) -> int:
    """``--set``: the real files' pass rates beside Construct2D (benchmarks/airfoil_set.py)."""
    from airfoil_set import run_in_processes, table

    rows = run_in_processes(
        Path(args.set), args.construct2d, args.method, args.half, args.limit, args.jobs
    )
    lines = table(rows, args.method)
    print("\n".join(lines))
    if args.write:
        folder = Path(args.set).name
        name = "airfoil-set" + ("" if folder == "airfoils" else f"-{folder}")
        name += f"-{args.half}" if args.half else ""
        write_block(args.write, name + ("-quick" if args.limit else ""), lines)
    return 0


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument(
        "--construct2d",
        default=os.environ.get("CONSTRUCT2D") or shutil.which("construct2d"),
        help="the construct2d executable",
    )
    p.add_argument("--write", metavar="MD", help="also write the table to this Markdown file")
    p.add_argument("--cases", nargs="*", default=[c[0] for c in CASES])
    p.add_argument(
        "--set",
        metavar="DIR",
        help="mesh every .dat file of DIR (e.g. shared/airfoils) instead of the NACA cases: "
        "pass rates O and C beside Construct2D (benchmarks/airfoil_set.py)",
    )
    p.add_argument("--method", default="pinn", help="pinn-mesh's method for --set")
    p.add_argument("--half", choices=("tuning", "report"), help="only this half of --set")
    p.add_argument("--limit", type=int, help="only the first LIMIT files of --set (a quick run)")
    p.add_argument(
        "--jobs", type=int, default=1, help="--set's files split over JOBS processes (default 1)"
    )
    args = p.parse_args()
    if not args.construct2d:
        print("construct2d not found: build it (make) and pass --construct2d PATH", file=sys.stderr)
        return 2
    if args.set:
        return real_set(args)
    lines, verdicts = [], []
    header = (
        "| grid | mean MaxIncludedAngle | worst | folded | wall angle, max deviation "
        "from 90 | first layer (min .. max) | non-orthogonality (checkMesh), max | wall "
        "off the drawn polyline, max (% chord) | seconds |\n"
        "|---|---|---|---|---|---|---|---|---|"
    )
    with tempfile.TemporaryDirectory() as tmp:
        for stem, code, te in (c for c in CASES if c[0] in args.cases):
            dat = Path(tmp) / f"{stem}.dat"
            write_dat(dat, code, te)
            # a gap of at most SHARP_GAP is a sharp edge (SPEC 9): both make C-grids
            sharp = te == "sharp" or (not isinstance(te, str) and te <= SHARP_GAP)
            for c_grid in (
                (True,) if sharp else (False, True) if stem in BLUNT_C_GRIDS else (False,)
            ):
                lines += compare(args.construct2d, dat, stem, code, te, c_grid, header, verdicts)
        if "naca0012_sharp" in args.cases:
            dat = Path(tmp) / "naca0012_sharp.dat"
            verdicts.append(speed(args.construct2d, dat))
    print("\n" + "\n".join(verdicts))
    if args.write:
        write_block(args.write, "airfoils-table", [*lines, "", *(f"- {v}" for v in verdicts)])
    return 0


if __name__ == "__main__":
    sys.exit(main())
