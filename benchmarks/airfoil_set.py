"""Real airfoil files, O- and C-grids, pinn-mesh beside Construct2D (SPEC 9).

Every ``.dat`` file of a folder (default ``shared/airfoils``: 243 UIUC-derived sections, see
its README) is meshed as an O-grid of 250 x 80 and a C-grid of 300 x 80 nodes, first layer
1e-5 chord, far field 15 chords, by pinn-mesh (``--method``, default the default method) and
by Construct2D at the same sizes, far field and first layer. Each grid is one of:

- ``clean``: no folded cell and no cell of 180 degrees or more (MaxIncludedAngle);
- ``folded`` / ``non-convex``: written with folded cells, or only with cells of 180 or more;
- ``inside-out``: nodes of the first row off the wall lie inside the body;
- ``refused``: pinn-mesh refused the grid (one line, exit 2) or the file;
- ``failed``: Construct2D stopped or wrote no grid.

The files split into a tuning half and a report half by the parity of the SHA-1 of their
name (:func:`half`). Times: pinn-mesh's meshing in this process (no Python or torch start-up),
Construct2D's whole run; their ratio per file, the median over the clean pairs.

    python benchmarks/airfoils.py --set shared/airfoils --construct2d PATH \\
        [--write docs/airfoils.md] [--jobs N]
"""

from __future__ import annotations

import hashlib
import subprocess
import tempfile
import time
import warnings
from collections import Counter
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from pinn_engine.bodies.airfoil import circle, inside_polygon, load_body, naca4, read_dat
from pinn_engine.errors import InputError
from pinn_engine.job import Geometry, Outcome
from pinn_engine.job.cover import covered
from pinn_engine.kinds.body.mesh import mesh_body
from pinn_engine.quality import cell_quality, summary
from pinn_engine.settings import make_settings

# the settings: sizes (ni, nj) per topology, first layer in chords, far field in chords
SIZES = {"o": (250, 80), "c": (300, 80)}
FIRST_LAYER, FAR_FIELD = 1e-5, 15.0
# Construct2D's C-grid puts this many nodes on each side of its wake (its default), the rest on
# the surface; its first layer follows from y+ at a Reynolds number (its menu has no height):
# y+ is scaled from its default 0.9 by the first layer it gives there (calibrated per run)
C2D_WAKE, C2D_YPLUS = 50, 0.9
TIMEOUT = 120  # seconds for one Construct2D run


def half(name: str) -> str:
    """``tuning`` or ``report``: the parity of the SHA-1 of the file's name."""
    return "tuning" if int(hashlib.sha1(name.encode()).hexdigest(), 16) % 2 == 0 else "report"


def verdict(grid: np.ndarray, topology: str, n_wake: int) -> tuple[str, dict]:
    """The grid's class (see the module's docstring) and its figures."""
    q = summary(cell_quality(grid), 0.0)
    ni = grid.shape[1]
    wall = grid[0][n_wake : ni - n_wake]
    row = grid[1][n_wake : ni - n_wake]
    inside = int(inside_polygon(row, wall[:-1] if topology == "o" else wall).sum())
    if inside:
        return "inside-out", q
    if q["folded_cells"]:
        return "folded", q
    return ("non-convex" if q["worst_max_angle"] >= 180 else "clean"), q


def pinn_mesh(path: Path, topology: str, method: str, keep: bool = False) -> dict:
    """pinn-mesh's grid of ``path``: class, figures, seconds, the report's cut (if any), and
    with ``keep`` the grid (nj, ni, 2)."""
    t0 = time.perf_counter()
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", RuntimeWarning)  # a stray warning is a failure
            body = load_body(path)
            ni, nj = SIZES[topology]
            far = circle(body, FAR_FIELD)
            r = mesh_body(
                body,
                far,
                topology,
                method,
                ni,
                nj,
                make_settings(method, lattice=(ni, nj)),
                wall_spacing=FIRST_LAYER * body.chord,
            )
        # the check every written grid passes (job.run's): a grid it refuses is not written
        covered(Outcome("body", None, r.report, [r.points]), Geometry(body=body, far=far))
    except InputError as exc:
        return {"class": "refused", "why": str(exc), "seconds": time.perf_counter() - t0}
    seconds = time.perf_counter() - t0
    kind, q = verdict(r.points, topology, r.report["topology"]["wake_nodes"])
    out = {"class": kind, **q, "seconds": seconds, "cut": r.report["topology"].get("cut")}
    return {**out, "grid": r.points} if keep else out


def read_p3d(path: Path) -> np.ndarray:
    tok = path.read_text().split()
    ni, nj = int(tok[0]), int(tok[1])
    v = np.array(tok[2 : 2 + 2 * ni * nj], dtype=float)
    return np.stack([v[: ni * nj].reshape(nj, ni), v[ni * nj :].reshape(nj, ni)], axis=-1)


def construct2d(
    exe: str, path: Path, topology: str, yplus: float, work: Path, keep: bool = False
) -> dict:
    """Construct2D's grid of ``path`` at the topology's size: class, figures, seconds, and
    with ``keep`` the grid (nj, ni, 2)."""
    ni, nj = SIZES[topology]
    nsrf = ni if topology == "o" else ni - 2 * C2D_WAKE
    topo = "OGRD" if topology == "o" else "CGRD"
    menu = (
        f"SOPT\nNSRF\n{nsrf}\nRADI\n{FAR_FIELD}\nNWKE\n{C2D_WAKE}\nQUIT\n"
        f"VOPT\nJMAX\n{nj}\nYPLS\n{yplus}\nTOPO\n{topo}\nQUIT\nGRID\nSMTH\nQUIT\n"
    )
    dat = work / "foil.dat"
    try:  # Construct2D reads a name line and x y rows: the points pinn-mesh reads, in order
        xy, name = read_dat(path)
    except InputError as exc:
        return {"class": "failed", "why": str(exc), "seconds": 0.0}
    dat.write_text(f"{name}\n" + "".join(f"{x:.10f} {y:.10f}\n" for x, y in xy))
    out = dat.with_suffix(".p3d")
    out.unlink(missing_ok=True)
    t0 = time.perf_counter()
    try:
        run = subprocess.run(
            [exe, dat.name], input=menu, text=True, cwd=work, capture_output=True, timeout=TIMEOUT
        )
    except subprocess.TimeoutExpired:
        return {"class": "failed", "why": "timed out", "seconds": TIMEOUT}
    seconds = time.perf_counter() - t0
    if run.returncode or not out.exists():
        return {"class": "failed", "why": f"exit {run.returncode}", "seconds": seconds}
    g = read_p3d(out)
    if not np.isfinite(g).all():
        return {"class": "failed", "why": "non-finite nodes", "seconds": seconds}
    n_wake = 0
    if topology == "c":
        row = g[0]
        same = np.all(np.isclose(row, row[::-1], atol=1e-12), axis=1)
        n_wake = int(np.argmin(same[: len(row) // 2])) - 1
    kind, q = verdict(g, topology, max(n_wake, 0))
    return {"class": kind, **q, "seconds": seconds, **({"grid": g} if keep else {})}


def calibrate(exe: str, work: Path) -> float:
    """The y+ that gives Construct2D a first layer of ``FIRST_LAYER`` chords, from its
    first layer at ``C2D_YPLUS`` on NACA 0012 (proportional to y+ at a Reynolds number)."""
    dat = work / "naca0012.dat"
    dat.write_text("NACA 0012\n" + "".join(f"{x:.8f} {y:.8f}\n" for x, y in naca4("0012")))
    construct2d(exe, dat, "o", C2D_YPLUS, work)
    g = read_p3d(work / "foil.p3d")
    h = float(np.median(np.linalg.norm(g[1] - g[0], axis=1)))
    return C2D_YPLUS * FIRST_LAYER / h


def run(
    folder: Path,
    exe: str,
    method: str,
    only: str | None = None,
    limit: int | None = None,
    shard: tuple[int, int] = (0, 1),
) -> list[dict]:
    """Every file of ``folder`` (of the half ``only`` if given; the first ``limit`` if
    given; of those, every ``shard[1]``-th from the ``shard[0]``-th), both topologies, both
    tools."""
    files = sorted(folder.glob("*.dat"))
    if only:
        files = [f for f in files if half(f.name) == only]
    files = files[:limit][shard[0] :: shard[1]]
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        work = Path(tmp)
        yplus = calibrate(exe, work)
        for f in files:
            for topology in SIZES:
                ours = pinn_mesh(f, topology, method)
                peer = construct2d(exe, f, topology, yplus, work)
                rows.append(
                    {
                        "file": f.name,
                        "half": half(f.name),
                        "topology": topology,
                        "pinn": ours,
                        "c2d": peer,
                    }
                )
                print(
                    f"{f.name:32s} {topology} pinn-mesh {ours['class']:10s} "
                    f"{ours.get('worst_max_angle', float('nan')):6.1f} {ours['seconds']:5.2f} s | "
                    f"Construct2D {peer['class']:10s} "
                    f"{peer.get('worst_max_angle', float('nan')):6.1f} {peer['seconds']:5.2f} s",
                    flush=True,
                )
    return rows


def run_in_processes(
    folder: Path, exe: str, method: str, only: str | None, limit: int | None, jobs: int
) -> list[dict]:
    """:func:`run` split over ``jobs`` processes (every ``jobs``-th file each), the rows in
    :func:`run`'s order; each file's times are still taken in one process."""
    with ProcessPoolExecutor(max_workers=jobs) as pool:
        parts = pool.map(
            run, *zip(*[(folder, exe, method, only, limit, (k, jobs)) for k in range(jobs)])
        )
        rows = [r for part in parts for r in part]
    return sorted(rows, key=lambda r: (r["file"], list(SIZES).index(r["topology"])))


def table(rows: list[dict], method: str) -> list[str]:
    """The Markdown table of pass rates per half and the list of failures."""
    out = [
        f"| half | files | topology | pinn-mesh ({method}) clean | Construct2D clean | "
        "pinn-mesh inside-out | pinn-mesh refused | pinn-mesh folded or non-convex | "
        "median worst angle (pinn-mesh / Construct2D) | median time ratio |",
        "|---|---|---|---|---|---|---|---|---|---|",
    ]
    for part in ("tuning", "report"):
        for topology in SIZES:
            sel = [r for r in rows if r["half"] == part and r["topology"] == topology]
            if not sel:
                continue
            ours = Counter(r["pinn"]["class"] for r in sel)
            peer = Counter(r["c2d"]["class"] for r in sel)
            n = len(sel)
            worst = [
                np.median([r[k]["worst_max_angle"] for r in sel if "worst_max_angle" in r[k]])
                for k in ("pinn", "c2d")
            ]
            ratio = np.median(
                [
                    r["pinn"]["seconds"] / r["c2d"]["seconds"]
                    for r in sel
                    if r["pinn"]["class"] == "clean" and r["c2d"]["class"] != "failed"
                ]
            )
            share = 100 * ours["clean"] / n
            out.append(
                f"| {part} | {n} | {topology.upper()} | {ours['clean']} ({share:.1f} %) "
                f"| {peer['clean']} ({100 * peer['clean'] / n:.1f} %) | {ours['inside-out']} | "
                f"{ours['refused']} | {ours['folded'] + ours['non-convex']} | "
                f"{worst[0]:.1f} / {worst[1]:.1f} | {ratio:.2f} |"
            )
    out.append("")
    out.append("pinn-mesh's grids that are not clean, and why:")
    out.append("")
    for r in rows:
        p = r["pinn"]
        if p["class"] == "clean":
            continue
        why = p.get("why") or (
            f"{p['folded_cells']} folded cells, worst {p['worst_max_angle']:.1f} degrees"
        )
        out.append(
            f"- {r['file']} ({r['half']}), {r['topology'].upper()}-grid: {p['class']}: {why} "
            f"(Construct2D: {r['c2d']['class']})"
        )
    cuts = sorted({r["file"] for r in rows if r["pinn"].get("cut")})
    out.append("")
    out.append(
        f"Surfaces crossing near the trailing edge, cut at the crossing (SPEC 9): "
        f"{', '.join(cuts) or 'none'}."
    )
    return out
