"""pinn-mesh against the classical tools in one run: the whole ``pinn-mesh``
command (Python's start, imports and file reading included, as a user meets it), its default
and ``--method elliptic``, against Construct2D, blockMesh and gmsh on the same jobs.

Usage: ``.venv/bin/python benchmarks/peers.py [--construct2d PATH] [--runs 3]
[--out docs/speed.md] [--only airfoils|blocks|dictionaries]``

- **Airfoils against Construct2D** (built from its source with ``make``; default
  ``/work/tools/Construct2D/construct2d``, or ``$CONSTRUCT2D``): a NACA 0012 C-grid of 320 x
  90 and O-grids of 250 x 80 around Construct2D's sample airfoils, pinn-mesh with
  Construct2D's first-layer height (``--spacing bottom=H``) and its far field (15 chords).
- **blockMesh** (OpenFOAM, ``scripts/setup_openfoam.sh``): the DFG 2D-1 channel and cylinder
  (``example_data/dfg*.vtp``, 12 blocks) at a cell size giving about 34 000 cells, blockMesh
  given pinn-mesh's blocks, cell counts and its drawn nodes along each curved block side (a
  ``polyLine`` edge), one cell thick; and a straight 1 x 1 x 4 square duct of 80 x 20 x 20
  hexahedra, one block; and two of ``example_data/blockmesh``'s dictionaries (the butterfly
  pipe and the DFG 3D channel), pinn-mesh reading the dictionary itself
  (``pinn-mesh DICT --format openfoam``, SPEC 15) and blockMesh meshing it.
- **gmsh** (its Python API, the test extra): the same DFG blocks with the same nodes on every
  block side, each a transfinite surface smoothed by 100 Winslow sweeps (as
  ``benchmarks/multiblock_gmsh.py``); the model's build and meshing in this process, without
  the import.

Each job runs ``--runs`` times, the tools alternating; the table shows the median wall times
and the ratios of pinn-mesh's times to the peer's, then the median CPU times (user and system:
a command's own and its children's, gmsh's this process's) and the default's ratio, which a
shared machine's load disturbs less than the wall times. With ``--out`` the table replaces
the part of that page between the PEERS markers.
"""

from __future__ import annotations

import argparse
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
sys.path[:0] = [str(HERE), str(ROOT / "example_data")]

from airfoils import read_p3d, write_dat  # noqa: E402
from make_hexa import surface  # noqa: E402

PINN_MESH = str(Path(sys.executable).with_name("pinn-mesh"))
CONSTRUCT2D = os.environ.get("CONSTRUCT2D", "/work/tools/Construct2D/construct2d")
OPENFOAM = Path("/usr/share/openfoam/etc/bashrc")
SAMPLES = Path(CONSTRUCT2D).parent / "sample_airfoils"
C_SIZE, O_SIZE = (320, 90), (250, 80)  # the O- and C-grids compared
FARFIELD = 15.0  # chords: Construct2D's default far field
DFG_CELL = 0.0053  # the DFG cylinder's cell size: about 34 000 cells in 12 blocks
DUCT_CELLS = (80, 20, 20)  # the square duct's hexahedra along x, y, z (32 000)
DUCT_LENGTH = 4.0  # its length along x (the section is 1 x 1)
SMOOTHING = 100  # gmsh's Winslow sweeps (its tutorial t6's figure)
MARK = "<!-- PEERS {} -->"  # the markers round the table in --out
# the jobs' groups: Construct2D's airfoils, the DFG blocks and the duct (blockMesh and gmsh
# given pinn-mesh's blocks), the blockMeshDicts read by both
GROUPS = ("airfoils", "blocks", "dictionaries")
Timer = Callable[[], tuple[float, float]]  # a run's wall and CPU seconds
Timers = dict[str, Timer]  # pinn-mesh's default and elliptic, or the peers


def seconds(command: list[str], **kwargs) -> tuple[float, float]:
    """The wall time of ``command`` (it must succeed) and its CPU time (user and system, its
    own and its waited-for children's)."""
    used = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    subprocess.run(command, check=True, capture_output=True, timeout=900, **kwargs)
    took = time.perf_counter() - start
    now = resource.getrusage(resource.RUSAGE_CHILDREN)
    return took, (now.ru_utime - used.ru_utime) + (now.ru_stime - used.ru_stime)


def pinn_mesh(args: list[str], out: Path) -> Timers:
    """The default and elliptic commands on ``args``, each a timer.

    They run with Python's bytecode cache written and read, as an installed package's
    modules are (``PYTHONDONTWRITEBYTECODE`` set in the caller's shell would make every run
    compile the package again, a cost no user pays).
    """
    base = [PINN_MESH, *args, "--quiet", "-o", str(out)]
    env = {k: v for k, v in os.environ.items() if k != "PYTHONDONTWRITEBYTECODE"}
    return {
        "default": lambda: seconds(base, env=env),
        "elliptic": lambda: seconds([*base, "--method", "elliptic"], env=env),
    }


def construct2d(dat: Path, size: tuple[int, int], topology: str) -> tuple[Timer, float]:
    """Construct2D's timer on ``dat`` (an O- or C-grid of ``size``, smoothed) and its grid's
    first-layer height."""
    if topology == "c":  # its surface points are ni less 2 x its 50 wake points
        menu = f"SOPT\nNSRF\n{size[0] - 100}\nQUIT\nVOPT\nTOPO\nCGRD\n"
    else:
        menu = f"SOPT\nNSRF\n{size[0]}\nQUIT\nVOPT\nTOPO\nOGRD\n"
    menu += f"JMAX\n{size[1]}\nQUIT\nGRID\nSMTH\nQUIT\n"

    def run() -> tuple[float, float]:
        return seconds([CONSTRUCT2D, dat.name], input=menu.encode(), cwd=dat.parent)

    run()
    g = read_p3d(dat.with_suffix(".p3d"))
    return run, float(np.linalg.norm(g[1] - g[0], axis=1).max())


def openfoam_env() -> dict[str, str]:
    """The environment that OpenFOAM's bashrc sets (sourced once, not timed)."""
    done = subprocess.run(
        ["bash", "-c", f"source {OPENFOAM} >/dev/null 2>&1; env -0"],
        capture_output=True,
        check=True,
    )
    return dict(line.split("=", 1) for line in done.stdout.decode().split("\0") if "=" in line)


def write_dictionary(case: Path, vertices, body: list[str]) -> None:
    """A blockMesh case's ``controlDict`` and ``blockMeshDict``: ``vertices`` (x, y, z), then
    the ``body`` lines (blocks, edges, boundary)."""
    (case / "system").mkdir(parents=True)
    (case / "system" / "controlDict").write_text(
        "FoamFile { version 2.0; format ascii; class dictionary; object controlDict; }\n"
        "application blockMesh; startFrom startTime; startTime 0; stopAt endTime;\n"
        "endTime 1; deltaT 1; writeControl timeStep; writeInterval 1;\n"
    )
    lines = ["FoamFile { version 2.0; format ascii; class dictionary; object blockMeshDict; }"]
    lines += ["convertToMeters 1;", "vertices ("]
    lines += [f"  ({x:.12g} {y:.12g} {z:.12g})" for x, y, z in vertices]
    (case / "system" / "blockMeshDict").write_text("\n".join([*lines, ");", *body]) + "\n")


def block_mesh(case: Path, cells: int, vertices, blocks, edges) -> Timer:
    """A blockMesh case of ``vertices`` (x, y, z), ``blocks`` (8 vertex ids, 3 counts) and
    ``edges`` (a, b, interior points): its timer, once it made ``cells`` cells."""
    body = ["blocks ("]
    body += [
        f"  hex ({' '.join(map(str, ids))}) ({' '.join(map(str, n))}) simpleGrading (1 1 1)"
        for ids, n in blocks
    ]
    body += [");", "edges ("]
    for a, b, points in edges:
        inner = " ".join(f"({x:.12g} {y:.12g} {z:.12g})" for x, y, z in points)
        body.append(f"  polyLine {a} {b} ({inner})")
    body += [");", "boundary ();"]
    write_dictionary(case, vertices, body)
    env = openfoam_env()
    done = subprocess.run(["blockMesh", "-case", str(case)], env=env, capture_output=True)
    assert f"nCells: {cells}" in done.stdout.decode(), done.stdout.decode()[-2000:]
    return lambda: seconds(["blockMesh", "-case", str(case)], env=env)


def dfg_blocks(lay) -> tuple[list, list, list]:
    """pinn-mesh's DFG blocks as blockMesh's: the corners at z = 0 and 1, the counts, and a
    polyLine through the drawn nodes of every side that is not straight."""
    corner_ids = sorted({int(i[c]) for i in lay.ids for c in ((0, 0), (0, -1), (-1, -1), (-1, 0))})
    index = {n: k for k, n in enumerate(corner_ids)}
    xy = lay.points[corner_ids]
    vertices = [(x, y, z) for z in (0.0, 1.0) for x, y in xy]
    top = len(corner_ids)
    blocks, edges, seen = [], [], set()
    for ids in lay.ids:
        corners = [index[int(ids[c])] for c in ((0, 0), (0, -1), (-1, -1), (-1, 0))]
        counts = (ids.shape[1] - 1, ids.shape[0] - 1, 1)
        x, y = xy[corners].T
        if np.dot(x, np.roll(y, -1)) < np.dot(y, np.roll(x, -1)):  # clockwise: turn it over
            corners, counts = [corners[0], *corners[:0:-1]], (counts[1], counts[0], 1)
        blocks.append(([*corners, *(c + top for c in corners)], counts))
        for side in (ids[0], ids[:, -1], ids[-1], ids[:, 0]):
            a, b = index[int(side[0])], index[int(side[-1])]
            pts = lay.points[side]
            chord = pts[-1] - pts[0]
            rel = pts - pts[0]
            off = np.abs(chord[0] * rel[:, 1] - chord[1] * rel[:, 0]) / np.linalg.norm(chord)
            if (min(a, b), max(a, b)) in seen or off.max() < 1e-12 * np.linalg.norm(chord):
                continue
            seen.add((min(a, b), max(a, b)))
            for z, shift in ((0.0, 0), (1.0, top)):
                edges.append((a + shift, b + shift, [(x, y, z) for x, y in pts[1:-1]]))
    return vertices, blocks, edges


def gmsh_timer(lay) -> Timer:
    """gmsh's transfinite and smoothed DFG blocks: the model's build and meshing (wall and
    this process's CPU time)."""
    import gmsh
    from multiblock_gmsh import gmsh_model

    def run() -> tuple[float, float]:
        gmsh.initialize()
        gmsh.option.setNumber("General.Terminal", 0)
        start, cpu = time.perf_counter(), time.process_time()
        gmsh_model(lay, SMOOTHING)
        gmsh.model.mesh.generate(2)
        took = time.perf_counter() - start, time.process_time() - cpu
        gmsh.finalize()
        return took

    return run


def airfoil_jobs(work: Path) -> list[tuple[str, list[str], Timer]]:
    """The airfoil jobs: each one's name, pinn-mesh's arguments (Construct2D's first layer and
    far field) and Construct2D's timer."""
    out = []
    dat = work / "naca0012.dat"
    write_dat(dat, "0012", "sharp")
    peer, h = construct2d(dat, C_SIZE, "c")
    size = ["--size", *map(str, C_SIZE), "--spacing", f"bottom={h:.6g}"]
    out.append(
        (
            "NACA 0012 C-grid 320 x 90",
            [str(dat), "--topology", "c", *size, "--farfield", str(FARFIELD)],
            peer,
        )
    )
    for sample in sorted(SAMPLES.glob("*.dat")):
        if sample.stem in ("bullet", "naca0012", "naca0012_sharp"):
            continue  # not an airfoil; the NACA 0012 above
        dat = work / sample.name
        shutil.copy(sample, dat)
        peer, h = construct2d(dat, O_SIZE, "o")
        size = ["--size", *map(str, O_SIZE), "--spacing", f"bottom={h:.6g}"]
        args = [str(dat), "--topology", "o", *size, "--farfield", str(FARFIELD)]
        out.append((f"{sample.stem} O-grid 250 x 80", args, peer))
    return out


def jobs(work: Path, groups: set[str]) -> list[tuple[str, Timers, Timers]]:
    """Each job's name, pinn-mesh's two timers and its peers' (by name), of ``groups``
    (``GROUPS``)."""
    from multiblock_gmsh import drawn

    out = [
        (name, pinn_mesh(args, work / f"{name.split()[0]}.vts"), {"Construct2D": peer})
        for name, args, peer in (airfoil_jobs(work) if "airfoils" in groups else [])
    ]
    if "dictionaries" in groups:
        for case, label in (("pipe", "butterfly pipe"), ("dfg3d", "DFG 3D channel")):
            out.append(dictionary_job(work, case, label))
    if "blocks" not in groups:
        return out
    _, lay = drawn("dfg", DFG_CELL)
    cells = sum((i.shape[0] - 1) * (i.shape[1] - 1) for i in lay.ids)
    dfg = [str(ROOT / "example_data" / "dfg.vtp"), "--blocks"]
    dfg += [str(ROOT / "example_data" / "dfg_blocks.vtp"), "--cell-size", str(DFG_CELL)]
    peers = {
        "blockMesh": block_mesh(work / "dfg", cells, *dfg_blocks(lay)),
        "gmsh": gmsh_timer(lay),
    }
    out.append((f"DFG cylinder, 12 blocks, {cells} cells", pinn_mesh(dfg, work / "dfg.vtm"), peers))
    duct = work / "duct.vtp"
    surface(lambda u, v, w: np.stack([DUCT_LENGTH * u, v, w], axis=-1)).save(duct)
    args = [str(duct), "--size", *(str(n + 1) for n in DUCT_CELLS)]
    corners = ((0, 0), (DUCT_LENGTH, 0), (DUCT_LENGTH, 1), (0, 1))
    box = [(x, y, z) for z in (0, 1) for x, y in corners]
    cells = int(np.prod(DUCT_CELLS))
    peer = block_mesh(work / "duct", cells, box, [(list(range(8)), DUCT_CELLS)], [])
    name = f"square duct, {cells} hexahedra"
    out.append((name, pinn_mesh(args, work / "duct.vts"), {"blockMesh": peer}))
    return out


def dictionary_job(work: Path, case: str, label: str) -> tuple[str, Timers, Timers]:
    """pinn-mesh and blockMesh on one of ``example_data/blockmesh``'s dictionaries."""
    source = ROOT / "example_data" / "blockmesh" / case / "system" / "blockMeshDict"
    folder = work / f"{case}_blockmesh"
    (folder / "system").mkdir(parents=True)
    shutil.copy(source, folder / "system" / "blockMeshDict")
    (folder / "system" / "controlDict").write_text(
        "FoamFile { version 2.0; format ascii; class dictionary; object controlDict; }\n"
        "application blockMesh; startFrom startTime; startTime 0; stopAt endTime;\n"
        "endTime 1; deltaT 1; writeControl timeStep; writeInterval 1;\n"
    )
    env = openfoam_env()
    log = subprocess.run(["blockMesh", "-case", str(folder)], env=env, capture_output=True)
    cells = re.search(rb"nCells:\s*(\d+)", log.stdout)
    name = f"blockMeshDict: {label}, {int(cells.group(1)) if cells else '?'} cells"
    args = [str(source), "--format", "openfoam"]
    peer = {"blockMesh": lambda: seconds(["blockMesh", "-case", str(folder)], env=env)}
    return name, pinn_mesh(args, work / f"{case}_case"), peer


def write_between(page: Path, mark: str, text: str) -> None:
    """Replace what lies between ``mark``'s begin and end markers in ``page`` by ``text``."""
    begin, end = mark.format("begin"), mark.format("end")
    head, rest = page.read_text().split(begin, 1)
    page.write_text(f"{head}{begin}\n{text}\n{end}{rest.split(end, 1)[1]}")


def table(rows: list[tuple[str, str, dict, dict]], runs: int, load: tuple) -> str:
    """The Markdown table: a row a job and peer, the median wall times and their ratios, then
    the median CPU times and their ratio (the default's to the peer's)."""
    lines = [
        f"Medians of {runs} runs a tool, alternating; load average {load[0]:.1f} before, "
        f"{load[1]:.1f} after, on 2 shared cores.\nWall seconds, then CPU seconds (user and "
        "system).",
        "",
        "| job | peer | pinn-mesh (s) | `--method elliptic` (s) | peer (s) | ratio | "
        "elliptic's ratio | CPU: pinn-mesh, elliptic, peer (s) | CPU ratio |",
        "|---|---|---:|---:|---:|---:|---:|---:|---:|",
    ]
    for name, peer, t, c in rows:
        lines.append(
            f"| {name} | {peer} | {t['default']:.2f} | {t['elliptic']:.2f} | {t['peer']:.2f} | "
            f"{t['default'] / t['peer']:.1f}x | {t['elliptic'] / t['peer']:.1f}x | "
            f"{c['default']:.2f}, {c['elliptic']:.2f}, {c['peer']:.2f} | "
            f"{c['default'] / c['peer']:.1f}x |"
        )
    return "\n".join(lines)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--runs", type=int, default=3, help="runs of each tool on each job")
    parser.add_argument("--out", type=Path, help="the page whose PEERS table to replace")
    parser.add_argument(
        "--only", choices=GROUPS, action="append", help="these groups of jobs (default: all)"
    )
    opts = parser.parse_args()
    if opts.out and opts.only:
        parser.error("--out replaces the whole table: run every group (no --only)")
    before = os.getloadavg()[0]
    rows = []
    with tempfile.TemporaryDirectory(prefix="pinn-mesh-peers-") as scratch:
        for name, ours, peers in jobs(Path(scratch), set(opts.only or GROUPS)):
            timers = {**ours, **peers}
            times = {key: [] for key in timers}
            for _ in range(opts.runs):
                for key, timer in timers.items():
                    times[key].append(timer())
            wall = {key: statistics.median(w for w, _ in t) for key, t in times.items()}
            cpu = {key: statistics.median(c for _, c in t) for key, t in times.items()}
            print(name, "wall", {k: round(v, 2) for k, v in wall.items()}, flush=True)
            print(name, "CPU", {k: round(v, 2) for k, v in cpu.items()}, flush=True)
            for peer in peers:
                rows.append((name, peer, {**wall, "peer": wall[peer]}, {**cpu, "peer": cpu[peer]}))
    text = table(rows, opts.runs, (before, os.getloadavg()[0]))
    print(text)
    if opts.out:
        write_between(opts.out, MARK, text)


if __name__ == "__main__":
    main()
