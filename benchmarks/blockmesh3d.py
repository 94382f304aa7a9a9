"""blockMeshDicts meshed by pinn-mesh beside blockMesh (SPEC 15), checkMesh measuring both.

    .venv/bin/python benchmarks/blockmesh3d.py                 # every set
    .venv/bin/python benchmarks/blockmesh3d.py --set report    # one set
    .venv/bin/python benchmarks/blockmesh3d.py --out docs/blockmesh.md   # its table too

Each dictionary is meshed by ``pinn-mesh DICT -o CASE --format openfoam`` (the default:
the better of the Winslow grid and blockMesh's placement) and by blockMesh; checkMesh
measures both. Printed per dictionary: its blocks, whether curved edges are given, cells and
patches (ours / blockMesh's), checkMesh's verdict, its largest and mean
non-orthogonality and largest skewness (ours / blockMesh's), the grid kept, and the CPU
times of the whole commands (``--runs``' medians) with their ratio. A dictionary pinn-mesh
refuses shows its one line.

The sets: ``own`` (``example_data/blockmesh``: the butterfly pipe, the duct bend and the DFG
3D channel), ``tuning`` (OpenFOAM's tutorials the method was tuned on), ``variants`` (the
pipe and the DFG channel with another centre square, grading or blocks along their axis;
tuned on too) and
``report`` (held out: not tuned on). The tutorials are read from OpenFOAM's examples
(``/usr/share/doc/openfoam-examples/examples``, Debian's openfoam package; gzipped ones
unpacked). Needs OpenFOAM (blockMesh, checkMesh).
"""

from __future__ import annotations

import argparse
import gzip
import os
import re
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "example_data" / "blockmesh"))

from make_dictionaries import dfg3d, pipe  # noqa: E402

PINN_MESH = str(Path(sys.executable).with_name("pinn-mesh"))
TUTORIALS = Path("/usr/share/doc/openfoam-examples/examples")
OWN = ROOT / "example_data" / "blockmesh"
SETS = {
    "own": {name: OWN / name / "system" / "blockMeshDict" for name in ("pipe", "bend", "dfg3d")},
    "tuning": {
        "pitzDaily": "incompressible/simpleFoam/pitzDaily",
        "cavity": "incompressible/icoFoam/cavity/cavity",
        "squareBend": "incompressible/simpleFoam/squareBend",
        "TJunction": "incompressible/pimpleFoam/RAS/TJunction",
    },
    "variants": {  # the butterfly pipe drawn otherwise: how robust the gain is
        "pipe, square 0.3 R": lambda: pipe(square=0.3),
        "pipe, square 0.5 R": lambda: pipe(square=0.5),
        "pipe, square 0.6 R": lambda: pipe(square=0.6),
        "pipe, no grading": lambda: pipe(grade=1),
        "pipe, grading 8": lambda: pipe(grade=8),
        "pipe, grading 0.3": lambda: pipe(grade=0.3),
        "pipe, 4 blocks along": lambda: pipe(layers=4),
        "DFG 3D, square 0.15": lambda: dfg3d(s=0.15),
        "DFG 3D, ring grading 0.1": lambda: dfg3d(ring=0.1),
        "DFG 3D, ring grading 1": lambda: dfg3d(ring=1),
        "DFG 3D, 3 blocks along z": lambda: dfg3d(layers=3),
    },
    "report": {
        "pipeCyclic": "incompressible/simpleFoam/pipeCyclic",
        "cylinder (potentialFoam)": "basic/potentialFoam/cylinder",
        "offsetCylinder": "incompressible/nonNewtonianIcoFoam/offsetCylinder",
        "blockMesh pipe": "mesh/blockMesh/pipe",
        "planarContraction": "incompressible/pimpleFoam/laminar/planarContraction",
        "backwardFacingStep2D": "incompressible/simpleFoam/backwardFacingStep2D",
        "injectorPipe": "compressible/rhoSimpleFoam/gasMixing/injectorPipe",
        "sloshingCylinder": "multiphase/interFoam/laminar/sloshingCylinder",
        "squareBendLiq": "compressible/rhoSimpleFoam/squareBendLiq",
    },
}
SYSTEM = ("controlDict", "fvSchemes", "fvSolution")
RUN_LIMIT = 600  # seconds a run may take before it counts as failed
MARK = "<!-- BLOCKMESH3D {} -->"  # the markers round the table in --out


def env() -> dict[str, str]:
    out = dict(os.environ)
    out.setdefault("WM_PROJECT_DIR", "/usr/share/openfoam")
    return out


def dictionary(where) -> str | None:
    """A dictionary's text: made by a function, a file, or a tutorial's
    ``system/blockMeshDict`` (or its .gz)."""
    if callable(where):
        return where()
    path = Path(where)
    if not path.is_absolute():
        path = TUTORIALS / path / "system" / "blockMeshDict"
    if path.exists():
        return path.read_text()
    gz = path.with_name(path.name + ".gz")
    return gzip.decompress(gz.read_bytes()).decode() if gz.exists() else None


def checkmesh(case: Path) -> dict:
    """checkMesh's cells, verdict, figures and the patches (name, type, faces) of a case."""
    log = subprocess.run(["checkMesh"], cwd=case, env=env(), capture_output=True, text=True).stdout
    (case / "log.checkMesh").write_text(log)

    def number(pattern):
        found = re.search(pattern, log, re.M)
        return float(found.group(1)) if found else None

    boundary = (case / "constant" / "polyMesh" / "boundary").read_text()
    patches = sorted(re.findall(r"(\w+)\s*\{\s*type\s+(\w+);.*?nFaces\s+(\d+);", boundary, re.S))
    return {
        "cells": number(r"^\s*cells:\s+(\d+)"),
        "ok": "Mesh OK." in log,
        "nonorth": number(r"non-orthogonality Max:\s*([\d.eE+-]+)"),
        "mean": number(r"non-orthogonality Max:\s*[\d.eE+-]+\s+average:\s*([\d.eE+-]+)"),
        "skew": number(r"Max skewness\s*=\s*([\d.eE+-]+)"),
        "patches": patches,
    }


def timed(command: list[str], runs: int, **kwargs) -> tuple[subprocess.CompletedProcess, float]:
    """``command`` run ``runs`` times: its last run and the median of its CPU times (user
    and system, the OS's accounting of the finished process: on shared cores the wall time
    counts the other sessions' load too)."""
    times = []
    for _ in range(runs):
        before = resource.getrusage(resource.RUSAGE_CHILDREN)
        done = subprocess.run(command, capture_output=True, text=True, **kwargs)
        after = resource.getrusage(resource.RUSAGE_CHILDREN)
        times.append(after.ru_utime - before.ru_utime + after.ru_stime - before.ru_stime)
    return done, statistics.median(times)


def run_case(name: str, text: str, work: Path, runs: int) -> dict:
    row: dict = {"case": name}
    ref, ours = work / "blockmesh", work / "pinn"
    (ref / "system").mkdir(parents=True)
    (ref / "system" / "blockMeshDict").write_text(text)
    row["blocks"] = len(re.findall(r"\bhex\s*\(", text))
    row["curved"] = bool(re.search(r"\b(arc|spline|polyLine)\b", text))
    report = work / "report.json"
    proc, row["ours_s"] = timed(
        [PINN_MESH, str(ref / "system" / "blockMeshDict"), "-o", str(ours)]
        + ["--format", "openfoam", "--quiet", "--report", str(report)],
        runs,
        timeout=RUN_LIMIT,
    )
    if proc.returncode:
        line = (proc.stderr.strip().splitlines() or ["?"])[-1]
        row["result"] = "refused: " + line.split("blockMeshDict: ", 1)[-1]  # not the temp path
    for sysfile in SYSTEM:
        source = ours / "system" / sysfile
        if source.exists():
            shutil.copy(source, ref / "system" / sysfile)
        else:
            (ref / "system" / sysfile).write_text(
                "FoamFile { version 2.0; format ascii; class dictionary; object "
                f"{sysfile}; }}\n"
                + (
                    "application blockMesh; startTime 0; endTime 1; deltaT 1;\n"
                    if sysfile == "controlDict"
                    else ""
                )
            )
    done, row["blockmesh_s"] = timed(["blockMesh"], runs, cwd=ref, env=env())
    if done.returncode:
        row["blockmesh"] = "failed"
        return row
    row["ref"] = checkmesh(ref)
    if not proc.returncode:
        import json

        row["ours"] = checkmesh(ours)
        row["kept"] = json.loads(report.read_text())["kept"]
        row["result"] = "Mesh OK" if row["ours"]["ok"] else "checkMesh failed"
    return row


def table(rows: list[dict]) -> str:
    def f(v, fmt="{:.2f}"):
        return "-" if v is None else fmt.format(v)

    out = [
        "| dictionary | blocks | curved | result | cells ours / blockMesh | same patches | "
        "max non-orth. ours / blockMesh | mean | max skewness | kept | time ours / blockMesh "
        "(s) | ratio |",
        "|---|---:|---|---|---|---|---|---|---|---|---|---:|",
    ]
    for r in rows:
        ours, ref = r.get("ours", {}), r.get("ref", {})
        same = "-" if not ours else ("yes" if ours["patches"] == ref.get("patches") else "no")
        cells = f"{f(ours.get('cells'), '{:.0f}')} / {f(ref.get('cells'), '{:.0f}')}"
        out.append(
            f"| {r['case']} | {r.get('blocks', '-')} | {'yes' if r.get('curved') else 'no'} | "
            f"{r.get('result', r.get('blockmesh', '-'))} | {cells} | {same} | "
            f"{f(ours.get('nonorth'))} / {f(ref.get('nonorth'))} | "
            f"{f(ours.get('mean'))} / {f(ref.get('mean'))} | "
            f"{f(ours.get('skew'), '{:.3f}')} / {f(ref.get('skew'), '{:.3f}')} | "
            f"{r.get('kept', '-')} | {r['ours_s']:.2f} / {r['blockmesh_s']:.2f} | "
            f"{r['ours_s'] / r['blockmesh_s']:.1f}x |"
        )
    return "\n".join(out)


def compile_package() -> None:
    """The package's bytecode up to date, as an installed package has it: where the shell
    sets PYTHONDONTWRITEBYTECODE=1 each run would otherwise compile every changed module."""
    command = [sys.executable, "-m", "compileall", "-q", str(ROOT / "pinn_engine")]
    subprocess.run(command, check=True, stdout=subprocess.DEVNULL)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--set", choices=tuple(SETS), action="append", help="default: all")
    parser.add_argument("--only", nargs="*", help="dictionary names to run (default all)")
    parser.add_argument("--out", type=Path, help="the page whose BLOCKMESH3D table to replace")
    parser.add_argument("--runs", type=int, default=1, help="runs of each tool (their median)")
    opts = parser.parse_args()
    compile_package()
    before = os.getloadavg()[0]
    rows = []
    with tempfile.TemporaryDirectory(prefix="pinn-mesh-blockmesh3d-") as scratch:
        for set_name in opts.set or SETS:
            for name, where in SETS[set_name].items():
                if opts.only and name not in opts.only:
                    continue
                text = dictionary(where)
                if text is None:
                    print(f"{name}: no dictionary at {where}", flush=True)
                    continue
                folder = Path(scratch) / set_name / re.sub(r"\W+", "_", name)  # OpenFOAM's paths
                rows.append(run_case(name, text, folder, opts.runs))
                rows[-1]["case"] = f"{name} ({set_name})"
                print(table(rows[-1:]).splitlines()[-1], flush=True)
    text = table(rows)
    load = (
        f"CPU seconds (user and system), medians of {opts.runs} runs; load average "
        f"{before:.1f} before, {os.getloadavg()[0]:.1f} after, on 2 shared cores."
    )
    print(text)
    if opts.out:
        begin, end = MARK.format("begin"), MARK.format("end")
        head, rest = opts.out.read_text().split(begin, 1)
        body = f"{load}\n\n{text}"
        opts.out.write_text(f"{head}{begin}\n{body}\n{end}{rest.split(end, 1)[1]}")


if __name__ == "__main__":
    main()
