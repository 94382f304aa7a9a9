"""What ``--blocks auto`` does with every domain of ``benchmarks/autoblock_domains.py`` and
the domains users bring (sharp-cornered bodies in channels, a round U-bend, steeper tees, and
those of ``benchmarks/autoblock_users.py``),
with and without a wall spacing: each run is either a clean grid or a one-line refusal.

Usage: ``.venv/bin/python benchmarks/autoblock_outcomes.py [--out docs/blocking.md]
[--domains NAME ...]``

Each domain is written to a ``.vtp`` (outer ring and holes) and meshed by the command line
in-process (``routes.cli.main``, the path every route takes: ``job.run`` checks that the
grid covers the domain drawn, every sharp corner a node, and has no fold) with
``--blocks auto --method elliptic --cell-size H`` (an eighth of a channel's width; the
Y-branches' ``autoblock.FINER``), once as it is and once with ``--spacing boundary=S``,
written as an OpenFOAM case and checked by OpenFOAM's ``checkMesh``. A run is ``clean``
when it exits 0 and checkMesh says "Mesh OK."; ``refused`` when it exits 2 with one line on
stderr; anything else (a grid written that checkMesh fails, an error of more than one line,
a crash) is ``BAD``. With ``--out`` the table replaces the part of that file between the
two AUTOBLOCK-OUTCOMES markers. Times: one run each, on whatever machine runs it.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import os
import re
import subprocess
import sys
import tempfile
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np
from autoblock import CELLS_ACROSS, FINER
from autoblock_domains import REPORT, TUNING, Domain, _a, tee_upstream
from autoblock_users import REPORT as USERS_REPORT
from autoblock_users import TUNING as USERS_TUNING
from vtkmodules.util.numpy_support import numpy_to_vtk
from vtkmodules.vtkCommonCore import vtkPoints
from vtkmodules.vtkCommonDataModel import vtkCellArray, vtkPolyData
from vtkmodules.vtkIOXML import vtkXMLPolyDataWriter

from pinn_engine.routes.cli import main

SPACING = 0.01  # the wall spacing of the second run (the issue's own: a tenth of a cell)
MARK = "<!-- AUTOBLOCK-OUTCOMES {} -->"  # the markers round the table in --out
NACA_POINTS = 61  # points per surface of the NACA 0012 in a channel


def _channel() -> np.ndarray:
    return _a((-3, -2), (6, -2), (6, 2), (-3, 2))


def diamond() -> Domain:
    """A square of side 1 turned 45 degrees (its corners on the channel's axes)."""
    r = 0.5 * np.sqrt(2.0)
    return [_channel(), _a((r, 0), (0, r), (-r, 0), (0, -r))], []


def triangle() -> Domain:
    """An equilateral wedge of side 1 pointing upstream."""
    return [_channel(), _a((-0.5, 0), (0.37, -0.5), (0.37, 0.5))], []


def naca_channel() -> Domain:
    """A NACA 0012 of chord 1 (sharp trailing edge) at zero incidence."""
    x = 0.5 * (1 - np.cos(np.linspace(0, np.pi, NACA_POINTS)))
    y = 0.6 * (0.2969 * np.sqrt(x) - 0.126 * x - 0.3516 * x**2 + 0.2843 * x**3 - 0.1036 * x**4)
    y[-1] = 0.0  # a sharp trailing edge
    upper = np.column_stack([x, y])[::-1]
    lower = np.column_stack([x, -y])[1:-1]
    return [_channel(), np.vstack([upper, lower])], []


def round_u_bend() -> Domain:
    """A channel of width 1 turning back through a half annulus (radii 0.5 and 1.5)."""
    t = np.linspace(-np.pi / 2, np.pi / 2, 33)
    outer = np.column_stack([4 + 1.5 * np.cos(t), 1.5 * np.sin(t)])
    inner = np.column_stack([4 + 0.5 * np.cos(t), 0.5 * np.sin(t)])[::-1]
    ring = np.vstack([_a((0, -1.5)), outer, _a((0, 1.5), (0, 0.5)), inner, _a((0, -0.5))])
    return [ring], []


def tee_steep() -> Domain:
    """The upstream-leaning tee with its branch at 60 degrees from the vertical."""
    up = 2.0 * _a(-np.sin(np.pi / 3), np.cos(np.pi / 3))
    left, right = _a(2.5, 1.0), _a(3.5, 1.0)
    return [np.array([(0, 0), (8, 0), (8, 1), right, right + up, left + up, left, (0, 1)])], []


USERS: dict[str, Callable[[], Domain]] = {
    "square turned 45 in channel": diamond,
    "wedge in channel": triangle,
    "NACA 0012 in channel": naca_channel,
    "round U-bend": round_u_bend,
    "tee, branch leaning 60 upstream": tee_steep,
    "tee, branch leaning 45 upstream": tee_upstream,
}
DOMAINS = {**TUNING, **REPORT, **USERS, **USERS_TUNING, **USERS_REPORT}


def _write(rings: list[np.ndarray], path: Path) -> None:
    poly, points, cells = vtkPolyData(), vtkPoints(), vtkCellArray()
    pts = np.vstack(rings)
    points.SetData(numpy_to_vtk(np.column_stack([pts, np.zeros(len(pts))]), deep=True))
    start = 0
    for ring in rings:
        ids = list(range(start, start + len(ring)))
        cells.InsertNextCell(len(ids) + 1, [*ids, ids[0]])
        start += len(ring)
    poly.SetPoints(points)
    poly.SetLines(cells)
    writer = vtkXMLPolyDataWriter()
    writer.SetFileName(str(path))
    writer.SetInputData(poly)
    writer.Write()


def _checkmesh(case: Path) -> str:
    env = dict(os.environ)
    env.setdefault("WM_PROJECT_DIR", "/usr/share/openfoam")
    out = subprocess.run(
        ["checkMesh", "-case", str(case)], capture_output=True, text=True, env=env
    ).stdout
    if "Mesh OK." in out:
        return "Mesh OK"
    failed = re.findall(r"\*\*\*([^\n]*)", out)
    return "; ".join(f.strip() for f in failed) or out.strip().splitlines()[-1]


def run(name: str, spacing: bool, folder: Path) -> dict:
    """One run of the command line on domain ``name``, with or without the wall spacing."""
    rings, _ = DOMAINS[name]()
    boundary = folder / "domain.vtp"
    _write(rings, boundary)
    case = folder / f"case_{int(spacing)}"
    h = FINER.get(name, 1.0 / CELLS_ACROSS)
    argv = [str(boundary), "--blocks", "auto", "--method", "elliptic", "--cell-size", f"{h:g}"]
    argv += ["--spacing", f"boundary={SPACING:g}"] if spacing else []
    argv += ["--format", "openfoam", "-o", str(case), "--report", str(folder / "r.json"), "-q"]
    err = io.StringIO()
    start = time.perf_counter()
    with contextlib.redirect_stderr(err), contextlib.redirect_stdout(io.StringIO()):
        try:
            rc = main(argv)
        except Exception as exc:  # a crash is a finding, not the end of the table
            rc, text = -1, f"{type(exc).__name__}: {exc}"
        else:
            text = err.getvalue().strip()
    seconds = time.perf_counter() - start
    row = {"domain": name, "spacing": spacing, "rc": rc, "seconds": seconds}
    if rc == 0:
        report = json.loads((folder / "r.json").read_text())
        q = report["quality"]
        row |= {
            "blocks": report["blocks"],
            "worst": q["worst_max_angle"],
            "folds": q["folded_cells"],
            "checkmesh": _checkmesh(case),
        }
        row["outcome"] = "clean" if row["checkmesh"] == "Mesh OK" else "BAD"
    else:
        one_line = rc == 2 and text.count("\n") == 0
        text = text.replace(f"{boundary}: ", "")  # the temporary file's name
        row |= {"error": text, "outcome": "refused" if one_line else "BAD"}
    return row


def markdown(rows: list[dict]) -> str:
    lines = [
        MARK.format("BEGIN"),
        "",
        "Regenerate with `.venv/bin/python benchmarks/autoblock_outcomes.py --out "
        f"docs/blocking.md` (`--blocks auto --method elliptic`, the cell size of the table "
        f"above, then the same with `--spacing boundary={SPACING:g}`; checkMesh on the "
        "written OpenFOAM case).",
        "",
        "| domain | wall spacing | outcome | blocks | worst | checkMesh or refusal | time (s) |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        # a refusal's own line (a BAD run's warnings before it are counted, not shown)
        detail = r.get("checkmesh") or r["error"].splitlines()[-1]
        detail = detail.removeprefix("pinn-mesh: error: ")
        blocks = r.get("blocks", "")
        worst = f"{r['worst']:.1f}" if "worst" in r else ""
        wall = f"{SPACING:g}" if r["spacing"] else "none"
        lines.append(
            f"| {r['domain']} | {wall} | {r['outcome']} | "
            f"{blocks} | {worst} | {detail.replace('|', '/')} | {r['seconds']:.1f} |"
        )
    counts = {k: sum(r["outcome"] == k for r in rows) for k in ("clean", "refused", "BAD")}
    lines += ["", f"{counts['clean']} clean, {counts['refused']} refused in one line, "
              f"{counts['BAD']} bad, of {len(rows)} runs.", "", MARK.format("END")]  # fmt: skip
    return "\n".join(lines) + "\n"


def main_() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--domains", nargs="+", default=list(DOMAINS))
    p.add_argument("--out", default=None)
    args = p.parse_args()
    rows = []
    for name in args.domains:
        for spacing in (False, True):
            with tempfile.TemporaryDirectory() as tmp:
                row = run(name, spacing, Path(tmp))
            rows.append(row)
            print(
                f"{name:34s} spacing {'yes' if spacing else 'no ':3s} {row['outcome']:8s} "
                f"{row.get('checkmesh') or row.get('error')} ({row['seconds']:.1f} s)",
                flush=True,
            )
    print(markdown(rows))
    if args.out:
        page = Path(args.out)
        text = page.read_text()
        begin, end = MARK.format("BEGIN"), MARK.format("END")
        if begin in text:
            head, rest = text.split(begin, 1)
            text = head + markdown(rows).rstrip("\n") + rest.split(end, 1)[1]
        else:
            text = text.rstrip("\n") + "\n\n" + markdown(rows)
        page.write_text(text)
        print(f"wrote {page}")


if __name__ == "__main__":
    import torch

    torch.set_num_threads(1)
    sys.exit(main_())
