"""Fuzz the ``pinn-mesh`` command with random and mutated inputs for a time budget.

Each case writes a boundary file (``.csv``, ``.txt``, ``.vtp`` or ``.vtk``; valid shapes,
damaged shapes and damaged bytes), sometimes an auxiliary-line file and random options, and
runs ``pinn_engine.routes.cli.main`` in-process with ``--method tfi`` or ``elliptic``. A case passes
when the command ends with status 0 and a complete, finite grid whose boundary nodes lie on
the boundary, or with status 2 and one ``pinn-mesh: error:`` line and no output file. Anything
else (an exception escaping ``main``, status 3, a C-level message on stderr, a crash of the
process, a case running past ``--case-timeout``) is a finding: its inputs, options and message
are kept under ``WORKDIR/findings/CASE`` and the run exits with status 1.

Cases run in a worker process that a supervisor restarts after a crash or a hang. Every case
has its own seed (printed with each finding), so ``--replay SEED`` reruns one case.

    .venv/bin/python scripts/fuzz.py --minutes 10            # docs/robustness.md's fuzzing session
    .venv/bin/python scripts/fuzz.py --seconds 60 --seed 7   # a short run
    .venv/bin/python scripts/fuzz.py --replay 7000012        # one case, verbose
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import shutil
import subprocess
import sys
import tempfile
import time
import traceback
from collections import Counter
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
EXAMPLES = ROOT / "example_data"
CASES_PER_SEED = 1_000_000  # case seed = base seed * CASES_PER_SEED + case number


# ---------------------------------------------------------------- shapes


def _side(a, b, n, bump, rng):
    s = np.linspace(0.0, 1.0, n + 1)[:-1]
    d = np.asarray(b) - np.asarray(a)
    normal = np.array([-d[1], d[0]])
    k = rng.integers(1, 3)
    return np.asarray(a) + s[:, None] * d + (bump * np.sin(k * np.pi * s))[:, None] * normal


def quad_ring(rng) -> np.ndarray:
    """A four-sided domain with gently curved sides (valid by construction, mostly)."""
    corners = np.array([[0, 0], [1, 0], [1, 1], [0, 1]], float)
    corners += rng.uniform(-0.2, 0.2, (4, 2))
    corners[:, 0] *= 10 ** rng.uniform(-1, 1)
    parts = [
        _side(
            corners[k],
            corners[(k + 1) % 4],
            int(rng.integers(1, 40)),
            rng.uniform(-0.08, 0.08),
            rng,
        )
        for k in range(4)
    ]
    return np.vstack(parts)


def annulus_ring(rng) -> np.ndarray:
    """An annular sector (a C shape, not star-shaped when it spans more than 180 degrees)."""
    span = rng.uniform(0.3, 1.8) * np.pi
    r0, r1 = 1.0, 1.0 + rng.uniform(0.05, 1.5)
    n = int(rng.integers(8, 80))
    t = np.linspace(0, span, n)
    outer = np.column_stack([r1 * np.cos(t), r1 * np.sin(t)])
    inner = np.column_stack([r0 * np.cos(t), r0 * np.sin(t)])[::-1]
    return np.vstack([outer, inner])


def example_ring(rng) -> np.ndarray:
    from pinn_engine.io.fileio import read_boundary_points

    name = rng.choice(["wavy", "fig2", "concave"])
    return read_boundary_points(EXAMPLES / f"{name}.vtp")[:, :2]


def circle_ring(rng) -> np.ndarray:
    n = int(rng.integers(3, 60))
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    return np.column_stack([np.cos(t), np.sin(t)])


def random_ring(rng) -> np.ndarray:
    return rng.uniform(-1, 1, (int(rng.integers(0, 30)), 2))


SHAPES = [(quad_ring, 5), (annulus_ring, 2), (example_ring, 2), (circle_ring, 1), (random_ring, 1)]


# ---------------------------------------------------------------- mutations


def _mutate_points(p: np.ndarray, rng) -> tuple[np.ndarray, list[str]]:
    notes = []
    for _ in range(int(rng.integers(0, 4))):
        if len(p) == 0:
            break
        k = int(rng.integers(len(p)))
        what = rng.choice(
            [
                "dup",
                "near_dup",
                "drop",
                "swap",
                "nonfinite",
                "reverse",
                "roll",
                "scale",
                "offset",
                "rotate",
                "close",
                "micro",
                "spike",
                "huge",
                "collinear_corner",
                "flatten",
                "jitter",
                "repeat_far",
            ]
        )
        notes.append(str(what))
        if what == "dup":
            p = np.insert(p, k, p[k], axis=0)
        elif what == "near_dup":
            span = float(np.ptp(p, axis=0).max()) or 1.0
            p = np.insert(p, k, p[k] + rng.normal(0, span * 10 ** rng.uniform(-14, -5), 2), axis=0)
        elif what == "drop":
            p = np.delete(p, rng.integers(len(p), size=int(rng.integers(1, 4))), axis=0)
        elif what == "swap":
            j = int(rng.integers(len(p)))
            p = p.copy()
            p[[k, j]] = p[[j, k]]
        elif what == "nonfinite":
            p = p.copy()
            p[k, int(rng.integers(2))] = rng.choice([np.nan, np.inf, -np.inf])
        elif what == "reverse":
            p = p[::-1]
        elif what == "roll":
            p = np.roll(p, k, axis=0)
        elif what == "scale":
            p = p * 10 ** rng.uniform(-9, 12)
        elif what == "offset":
            p = p + rng.uniform(-1, 1, 2) * 10 ** rng.uniform(0, 9)
        elif what == "rotate":
            a = rng.uniform(0, 2 * np.pi)
            p = p @ np.array([[np.cos(a), np.sin(a)], [-np.sin(a), np.cos(a)]])
        elif what == "close":
            p = np.vstack([p, p[:1]])
        elif what == "micro":
            j = (k + 1) % len(p)
            p = np.insert(p, j, p[k] + (p[j] - p[k]) * 10 ** rng.uniform(-9, -3), axis=0)
        elif what == "spike":
            j = (k + 1) % len(p)
            p = np.insert(
                p, j, [p[k] + rng.normal(0, 1, 2) * float(np.ptp(p, axis=0).max()), p[k]], axis=0
            )
        elif what == "huge":
            p = p.copy()
            p[k] = rng.choice([1e308, -1e308, 1e200, 1e-300])
        elif what == "collinear_corner" and len(p) > 2:
            p = p.copy()
            p[k] = 0.5 * (p[k - 1] + p[(k + 1) % len(p)]) + rng.normal(0, 1e-3, 2)
        elif what == "flatten":
            p = p.copy()
            p[:, 1] = p[0, 1]
        elif what == "jitter":
            p = p + rng.normal(0, 10 ** rng.uniform(-12, -2), p.shape) * (
                float(np.ptp(p, axis=0).max()) if len(p) else 1.0
            )
        elif what == "repeat_far" and len(p) > 4:
            p = np.insert(p, int(rng.integers(len(p))), p[k], axis=0)
    return p, notes


def _mutate_bytes(data: bytes, rng) -> bytes:
    b = bytearray(data)
    what = rng.choice(["flip", "truncate", "garbage", "binary", "empty", "dup_chunk"])
    if what == "flip" and b:
        for _ in range(int(rng.integers(1, 8))):
            b[int(rng.integers(len(b)))] = int(rng.integers(256))
    elif what == "truncate" and b:
        b = b[: int(rng.integers(len(b)))]
    elif what == "garbage":
        k = int(rng.integers(len(b) + 1))
        b[k:k] = rng.bytes(int(rng.integers(1, 64)))
    elif what == "binary":
        b = bytearray(rng.bytes(int(rng.integers(1, 4096))))
    elif what == "empty":
        b = bytearray()
    elif what == "dup_chunk" and b:
        k = int(rng.integers(len(b)))
        b[k:k] = b[k : k + int(rng.integers(1, 200))]
    return bytes(b)


# ---------------------------------------------------------------- writers


def _polydata(points: np.ndarray, kind: str, z=None, arrays=None):
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

    n = len(points)
    xyz = np.column_stack([points, np.zeros(n) if z is None else z]) if n else np.zeros((0, 3))
    pts = vtkPoints()
    pts.SetData(numpy_to_vtk(np.ascontiguousarray(xyz, dtype=float), deep=True))
    cells = vtkCellArray()
    if kind == "polygon":
        cells.InsertNextCell(n, list(range(n)))
    elif kind == "closed_line":
        cells.InsertNextCell(n + 1, list(range(n)) + [0])
    elif kind == "open_line":
        cells.InsertNextCell(n, list(range(n)))
    elif kind == "segments":
        for k in range(n):
            cells.InsertNextCell(2, [k, (k + 1) % n])
    elif kind == "two_cells" and n > 2:
        cells.InsertNextCell(n // 2, list(range(n // 2)))
        cells.InsertNextCell(n - n // 2, list(range(n // 2, n)))
    poly = vtkPolyData()
    poly.SetPoints(pts)
    if kind == "polygon":
        poly.SetPolys(cells)
    else:
        poly.SetLines(cells)
    for name, values in (arrays or {}).items():
        arr = numpy_to_vtk(np.ascontiguousarray(values, dtype=float), deep=True)
        arr.SetName(name)
        poly.GetPointData().AddArray(arr)
    return poly


def _write_poly(poly, path: Path, ascii_data: bool = False) -> None:
    from vtkmodules.vtkIOLegacy import vtkPolyDataWriter
    from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

    writer = vtkXMLPolyDataWriter() if path.suffix == ".vtp" else vtkPolyDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(poly)
    if path.suffix == ".vtp" and ascii_data:
        writer.SetDataModeToAscii()
    writer.Write()


def write_boundary(points: np.ndarray, folder: Path, rng) -> tuple[Path, list[str]]:
    notes = []
    ext = str(rng.choice([".csv", ".txt", ".vtp", ".vtk", ".csv", ".vtp"]))
    path = folder / f"boundary{ext}"
    z = None
    if rng.random() < 0.2 and len(points):
        z = np.full(len(points), rng.uniform(-1e5, 1e5))
        if rng.random() < 0.4:
            z = z + rng.normal(0, 10 ** rng.uniform(-12, 1), len(points))
        notes.append("z")
    if ext in (".csv", ".txt"):
        sep = str(rng.choice([",", " ", ";", "\t"])) if ext == ".txt" else ","
        cols = points if z is None else np.column_stack([points, z])
        lines = ["x,y" if z is None else "x,y,z"] if rng.random() < 0.5 else []
        if rng.random() < 0.1:
            lines.insert(0, "# exported by a CAD system")
        fmt = str(rng.choice(["%.17g", "%.6g", "%r"]))
        lines += [
            sep.join((fmt % v) if fmt != "%r" else repr(float(v)) for v in row) for row in cols
        ]
        path.write_text("\n".join(lines) + ("\n" if rng.random() < 0.8 else ""))
    elif len(points) < 3:  # VTK's writers crash on cells of fewer points
        path = path.with_suffix(".csv")
        np.savetxt(path, points, delimiter=",")
    else:
        kind = str(
            rng.choice(
                ["polygon", "closed_line", "segments", "open_line", "two_cells"],
                p=[0.35, 0.35, 0.2, 0.05, 0.05],
            )
        )
        notes.append(kind)
        _write_poly(_polydata(points, kind, z), path, ascii_data=rng.random() < 0.3)
    if rng.random() < 0.12:
        path.write_bytes(_mutate_bytes(path.read_bytes(), rng))
        notes.append("bytes")
    if rng.random() < 0.03:
        new = path.with_suffix(str(rng.choice([".stl", "", ".CSV", ".json"])))
        path.rename(new)
        path = new
        notes.append("rename")
    return path, notes


def write_aux(points: np.ndarray, folder: Path, rng) -> tuple[Path | None, list[str]]:
    """Lines between random points of the ring (often side to side), some mutated."""
    if len(points) < 4 or not np.all(np.isfinite(points)):
        return None, []
    lines, notes = [], []
    n = len(points)
    for _ in range(int(rng.integers(1, 4))):
        i, j = rng.integers(n, size=2)
        a, b = points[i], points[j]
        if rng.random() < 0.5:  # roughly opposite: i and j half a ring apart
            j = (i + n // 2) % n
            b = points[j]
        k = int(rng.integers(2, 12))
        t = np.linspace(0, 1, k)[:, None]
        line = a + t * (b - a)
        if rng.random() < 0.3:
            line = line + rng.normal(0, 0.1, line.shape) * float(np.ptp(points, axis=0).max())
        lines.append(line)
    pts = np.vstack(lines)
    from vtkmodules.util.numpy_support import numpy_to_vtk
    from vtkmodules.vtkCommonCore import vtkPoints
    from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData

    poly = vtkPolyData()
    vp = vtkPoints()
    vp.SetData(numpy_to_vtk(np.column_stack([pts, np.zeros(len(pts))]).copy(), deep=True))
    poly.SetPoints(vp)
    cells = vtkCellArray()
    start = 0
    for line in lines:
        cells.InsertNextCell(len(line), list(range(start, start + len(line))))
        start += len(line)
    poly.SetLines(cells)
    if rng.random() < 0.15:
        for name in rng.choice(["xi", "eta"], size=int(rng.integers(1, 3)), replace=False):
            arr = numpy_to_vtk(rng.uniform(-0.2, 1.2, len(pts)).copy(), deep=True)
            arr.SetName(str(name))
            poly.GetPointData().AddArray(arr)
        notes.append("xi_eta")
    path = folder / str(rng.choice(["aux.vtp", "aux.vtk"]))
    _write_poly(poly, path, ascii_data=rng.random() < 0.3)
    if rng.random() < 0.1:
        path.write_bytes(_mutate_bytes(path.read_bytes(), rng))
        notes.append("aux_bytes")
    return path, notes


def make_case(seed: int, folder: Path) -> tuple[list[str], list[str]]:
    """Inputs in ``folder`` and the argument list of case ``seed``."""
    rng = np.random.default_rng(seed)
    shapes, weights = zip(*SHAPES)
    shape = shapes[rng.choice(len(shapes), p=np.array(weights) / sum(weights))]
    points = shape(rng)
    notes = [shape.__name__]
    points, more = _mutate_points(points, rng)
    notes += more
    boundary, more = write_boundary(points, folder, rng)
    notes += more
    method = str(rng.choice(["tfi", "tfi", "elliptic"]))
    small = 40 if method == "elliptic" else 120
    size = [int(rng.integers(2, small)), int(rng.integers(2, small))]
    if rng.random() < 0.05:
        size[int(rng.integers(2))] = int(rng.choice([1, 0, -5, 30000, 10**9]))
    out = folder / "out" / "grid.vts"
    argv = [str(boundary), "--method", method, "--size", *map(str, size), "-o", str(out), "--quiet"]
    if rng.random() < 0.3:
        aux, more = write_aux(points, folder, rng)
        notes += more
        if aux is not None:
            argv += ["--aux", str(aux)]
    if rng.random() < 0.1:
        argv += ["--corners", *map(str, rng.integers(-2, max(len(points), 1) + 2, size=4))]
    if rng.random() < 0.1:
        argv += ["--fail-on-folded"]
    if rng.random() < 0.15:
        argv += ["--report", str(folder / "out" / "report.json")]
    if method == "elliptic" and rng.random() < 0.3:
        argv += ["--elliptic-iterations", str(int(rng.integers(0, 50)))]
    if rng.random() < 0.03:
        argv += [
            str(
                rng.choice(
                    ["--frobnicate", "--size", "--seed=-3", "--method=foo", "--preset", "--corners"]
                )
            )
        ]
    return argv, notes


# ---------------------------------------------------------------- checking


@contextlib.contextmanager
def _fd2_to(path: Path):
    """Send file descriptor 2 (C-level stderr, e.g. VTK's own printing) to ``path``."""
    sys.stderr.flush()
    saved = os.dup(2)
    with open(path, "wb") as f:
        os.dup2(f.fileno(), 2)
    try:
        yield
    finally:
        sys.stderr.flush()
        os.dup2(saved, 2)
        os.close(saved)


def run_case(seed: int, folder: Path) -> dict:
    """Run one case; returns its outcome with ``problem`` set when it is a finding."""
    from pinn_engine.routes.cli import main

    folder.mkdir(parents=True, exist_ok=True)
    argv, notes = make_case(seed, folder)
    out = folder / "out" / "grid.vts"
    stdout, stderr = io.StringIO(), io.StringIO()
    c_err = folder / "c_stderr.txt"
    start = time.perf_counter()
    problem = None
    rc = None
    with _fd2_to(c_err), contextlib.redirect_stdout(stdout), contextlib.redirect_stderr(stderr):
        try:
            rc = main(argv)
        except SystemExit as exc:  # argparse: usage error
            rc = exc.code if isinstance(exc.code, int) else 2
            if rc != 2:
                problem = f"SystemExit({exc.code!r})"
        except BaseException as exc:  # noqa: BLE001 - the fuzzer's whole point
            problem = f"unhandled {type(exc).__name__}: {exc}"
            stderr.write(traceback.format_exc())
    seconds = time.perf_counter() - start
    err = stderr.getvalue().strip()
    c_text = c_err.read_text(errors="replace").strip() if c_err.exists() else ""
    if problem is None:
        problem = check_outcome(rc, err, out, argv)
    if problem is None and c_text:
        problem = f"C-level stderr output: {c_text[:200]!r}"
    category = err.splitlines()[-1] if err else ""
    category = category.split(":", 3)[-1].strip()[:60] if rc == 2 else f"status {rc}"
    return {
        "seed": seed,
        "argv": argv,
        "notes": notes,
        "rc": rc,
        "stderr": err[-2000:],
        "seconds": round(seconds, 3),
        "problem": problem,
        "category": category,
    }


def check_outcome(rc, err: str, out: Path, argv: list[str]) -> str | None:
    leftovers = [p.name for p in out.parent.glob("*.part*")] if out.parent.exists() else []
    if leftovers:
        return f"temporary files left behind: {leftovers}"
    if rc == 0:
        if not out.is_file():
            return "status 0 but no output file"
        return check_grid(out, argv)
    if rc == 2:
        lines = err.splitlines()
        if "usage:" in err:  # argparse's own two-line message
            return (
                None
                if lines and lines[-1].startswith("pinn-mesh: error:")
                else f"argparse output without an error line: {err[:200]!r}"
            )
        if len(lines) != 1 or not lines[0].startswith("pinn-mesh: error: "):
            return f"status 2 without a one-line error: {err[:300]!r}"
        if out.exists():
            return "status 2 but an output file was written"
        return None
    return f"status {rc}: {err[-300:]!r}"


def check_grid(path: Path, argv: list[str]) -> str | None:
    from vtkmodules.util.numpy_support import vtk_to_numpy
    from vtkmodules.vtkIOXML import vtkXMLStructuredGridReader

    reader = vtkXMLStructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    grid = reader.GetOutput()
    ni, nj = (int(v) for v in argv[argv.index("--size") + 1 : argv.index("--size") + 3])
    extent = tuple(grid.GetExtent())
    if extent != (0, ni - 1, 0, nj - 1, 0, 0):
        return f"grid extent {extent}, expected {(0, ni - 1, 0, nj - 1, 0, 0)}"
    pts = vtk_to_numpy(grid.GetPoints().GetData())
    if not np.all(np.isfinite(pts)):
        return "grid has non-finite points"
    report = json.loads(grid.GetFieldData().GetAbstractArray("Report").GetValue(0))
    dev = report["quality"]["boundary_deviation"]
    if not dev <= 1e-6:
        return f"boundary nodes off the boundary (deviation {dev:g})"
    return None


# ---------------------------------------------------------------- worker and supervisor


def worker(base: int, first: int, deadline: float, workdir: Path) -> None:
    """Run cases ``first, first + 1, ...`` until ``deadline``; one JSON line per case."""
    import warnings

    warnings.simplefilter("ignore")
    log = (workdir / "cases.jsonl").open("a")
    state = workdir / "current"
    number = first
    while time.time() < deadline:
        seed = base * CASES_PER_SEED + number
        state.write_text(str(number))
        folder = Path(tempfile.mkdtemp(prefix=f"case{number}_", dir=workdir / "tmp"))
        result = run_case(seed, folder)
        if result["problem"]:
            keep = workdir / "findings" / str(seed)
            shutil.rmtree(keep, ignore_errors=True)
            shutil.copytree(folder, keep)
            (keep / "finding.json").write_text(json.dumps(result, indent=2))
        shutil.rmtree(folder, ignore_errors=True)
        log.write(json.dumps(result) + "\n")
        log.flush()
        number += 1
    state.write_text("done")


def supervise(base: int, seconds: float, workdir: Path, case_timeout: float) -> int:
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "tmp").mkdir(exist_ok=True)
    (workdir / "cases.jsonl").write_text("")
    deadline = time.time() + seconds
    print(
        f"fuzzing pinn-mesh for {seconds:.0f} s, base seed {base}, work folder {workdir}",
        flush=True,
    )
    number, crashes = 0, []
    state = workdir / "current"
    while time.time() < deadline:
        state.write_text(str(number))
        proc = subprocess.Popen(
            [
                sys.executable,
                __file__,
                "--worker",
                "--seed",
                str(base),
                "--first",
                str(number),
                "--deadline",
                str(deadline),
                "--workdir",
                str(workdir),
            ],
            cwd=ROOT,
        )
        last, since = state.read_text(), time.time()
        while proc.poll() is None:
            time.sleep(0.5)
            now = state.read_text() if state.exists() else last
            if now != last:
                last, since = now, time.time()
            elif time.time() - since > case_timeout:
                proc.kill()
                proc.wait()
                break
        current = state.read_text()
        if current == "done":
            break
        seed = base * CASES_PER_SEED + int(current)
        why = (
            f"exit status {proc.returncode}"
            if proc.returncode not in (None, -9)
            else f"no progress for {case_timeout:.0f} s"
        )
        crashes.append({"seed": seed, "problem": f"worker died or hung ({why})"})
        print(f"  case {seed}: worker died or hung ({why}); restarting", flush=True)
        number = int(current) + 1
    return summarise(workdir, crashes)


def summarise(workdir: Path, crashes: list[dict]) -> int:
    results = [
        json.loads(line)
        for line in (workdir / "cases.jsonl").read_text().splitlines()
        if line.strip()
    ]
    findings = [r for r in results if r["problem"]] + crashes
    rc = Counter(str(r["rc"]) for r in results)
    print(
        f"{len(results)} cases in {sum(r['seconds'] for r in results):.0f} s of meshing: "
        + ", ".join(f"status {k}: {v}" for k, v in sorted(rc.items()))
    )
    print("most common errors:")
    for text, count in Counter(r["category"] for r in results if r["rc"] == 2).most_common(12):
        print(f"  {count:5d}  {text}")
    slowest = max(results, key=lambda r: r["seconds"], default=None)
    if slowest:
        print(f"slowest case: seed {slowest['seed']}, {slowest['seconds']:.1f} s")
    if findings:
        print(f"{len(findings)} FINDINGS (inputs under {workdir / 'findings'}):")
        for f in findings[:30]:
            print(f"  seed {f['seed']}: {f['problem'][:300]}")
        return 1
    print("no findings: every case ended with a good grid or a clean one-line error")
    return 0


def replay(seed: int) -> int:
    folder = Path(tempfile.mkdtemp(prefix=f"fuzz_replay_{seed}_"))
    result = run_case(seed, folder)
    print(json.dumps(result, indent=2))
    print(f"inputs kept in {folder}")
    return 1 if result["problem"] else 0


def main(argv: list[str] | None = None) -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    budget = p.add_mutually_exclusive_group()
    budget.add_argument("--seconds", type=float, help="time budget in seconds")
    budget.add_argument("--minutes", type=float, help="time budget in minutes")
    p.add_argument("--seed", type=int, default=None, help="base seed (default: from the clock)")
    p.add_argument(
        "--workdir",
        type=Path,
        default=None,
        help="folder for the case log and findings (default: a new temp folder)",
    )
    p.add_argument(
        "--case-timeout",
        type=float,
        default=120.0,
        help="a case running longer than this is a finding (hang)",
    )
    p.add_argument("--replay", type=int, metavar="CASE_SEED", help="rerun one case")
    p.add_argument("--worker", action="store_true", help=argparse.SUPPRESS)
    p.add_argument("--first", type=int, default=0, help=argparse.SUPPRESS)
    p.add_argument("--deadline", type=float, default=0.0, help=argparse.SUPPRESS)
    args = p.parse_args(argv)
    sys.path.insert(0, str(ROOT))
    if args.replay is not None:
        return replay(args.replay)
    base = args.seed if args.seed is not None else int(time.time()) % 100_000
    if args.worker:
        worker(base, args.first, args.deadline, args.workdir)
        return 0
    seconds = args.seconds if args.seconds is not None else 60.0 * (args.minutes or 1.0)
    workdir = args.workdir or Path(tempfile.mkdtemp(prefix="pinn_mesh_fuzz_"))
    return supervise(base, seconds, workdir, args.case_timeout)


if __name__ == "__main__":
    sys.exit(main())
