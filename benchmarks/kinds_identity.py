"""Every domain kind meshed by its default and other methods, and a hash of each grid's points:
a refactoring that must not change behaviour leaves every line of this script's output the same.

    .venv/bin/python benchmarks/kinds_identity.py > before.txt   # before the change
    .venv/bin/python benchmarks/kinds_identity.py > after.txt    # after it
    diff before.txt after.txt                                   # nothing

Each case runs the command line in-process (``routes.cli.main``), so the routes' option
handling is covered too; the hash is of the points of every block of the grid written, in the
written order (SHA-256 of their float64 bytes, first 16 hex digits), beside the exit status.
"""

from __future__ import annotations

import contextlib
import hashlib
import io
import sys
import tempfile
from pathlib import Path

import numpy as np
import torch
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkIOXML import vtkXMLMultiBlockDataReader, vtkXMLStructuredGridReader

from pinn_engine.routes.cli import main

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "example_data"
HARD, HOLD, DICTS = DATA / "hard", DATA / "holdout", DATA / "blockmesh"
SMALL = ["--size", "25", "13"]
TRAIN = ["--epochs", "30", "--lbfgs", "10"]  # a short trained run: the trainer's path

# (name, arguments, output suffix): the four-sided tuning and held-out shapes, a body's O and
# C grids, 2D multi-block, a six-faced 3D surface and a blockMeshDict
CASES: list[tuple[str, list[str], str]] = []
for shape in ("bump", "notch_narrow_deep", "kite_35", "s_duct", "sector_270"):
    for method in ([], ["--method", "elliptic"], ["--method", "tfi"]):
        CASES.append(
            (
                f"tuning {shape} {' '.join(method) or 'default'}",
                [str(HARD / f"{shape}.vtp"), *SMALL, *method],
                ".vts",
            )
        )
CASES += [
    (
        "tuning bump aux default",
        [str(HARD / "bump.vtp"), "--aux", str(HARD / "bump_aux.vtp"), *SMALL],
        ".vts",
    ),
    (
        "tuning notch aux trained",
        [str(HARD / "notch_gauss.vtp"), "--aux", str(HARD / "notch_gauss_aux.vtp"), *SMALL, *TRAIN],
        ".vts",
    ),
    (
        "tuning bump winslow trained",
        [str(HARD / "bump.vtp"), *SMALL, "--objective", "winslow", *TRAIN],
        ".vts",
    ),
    ("tuning bump quality", [str(HARD / "bump.vtp"), *SMALL, "--objective", "quality"], ".vts"),
    ("tuning bump mgnet", [str(HARD / "bump.vtp"), *SMALL, "--method", "mgnet", *TRAIN], ".vts"),
    ("tuning bump spacing", [str(HARD / "bump.vtp"), *SMALL, "--spacing", "bottom=0.01"], ".vts"),
    (
        "tuning bump orthogonal pinn",
        [str(HARD / "bump.vtp"), *SMALL, "--orthogonal", "bottom", *TRAIN],
        ".vts",
    ),
    (
        "tuning bump orthogonal elliptic",
        [str(HARD / "bump.vtp"), *SMALL, "--orthogonal", "bottom", "--method", "elliptic"],
        ".vts",
    ),
]
for shape in ("h00_wavy", "h08_notch_rect", "h09_notch_v"):
    for method in ([], ["--method", "elliptic"]):
        CASES.append(
            (
                f"held-out {shape} {' '.join(method) or 'default'}",
                [str(HOLD / f"{shape}.vtp"), *SMALL, *method],
                ".vts",
            )
        )
for topology, body in (("o", [str(DATA / "naca0012.dat")]), ("c", [str(DATA / "naca4412.dat")])):
    for method in (
        [],
        ["--method", "elliptic"],
        ["--method", "tfi"],
        ["--objective", "winslow", *TRAIN],
    ):
        CASES.append(
            (
                f"airfoil {topology} {' '.join(method) or 'default'}",
                [*body, "--topology", topology, "--size", "41", "17", *method],
                ".vts",
            )
        )
CASES.append(
    ("airfoil naca 0012 c", ["--naca", "0012", "--topology", "c", "--size", "41", "17"], ".vts")
)
CASES.append(
    (
        "airfoil naca4412 c spacing",
        [
            str(DATA / "naca4412.dat"),
            "--topology",
            "c",
            "--size",
            "41",
            "17",
            "--spacing",
            "bottom=0.001",
        ],
        ".vts",
    )
)
for name in ("lshape", "step"):
    for method in ([], ["--method", "tfi"], ["--method", "pinn", "--objective", "winslow", *TRAIN]):
        CASES.append(
            (
                f"blocks {name} {' '.join(method) or 'default'}",
                [str(DATA / f"{name}.vtp"), "--blocks", str(DATA / f"{name}_blocks.vtp"), *method],
                ".vtm",
            )
        )
CASES.append(
    (
        "blocks lshape aux",
        [
            str(DATA / "lshape.vtp"),
            "--blocks",
            str(DATA / "lshape_blocks.vtp"),
            "--aux",
            str(DATA / "lshape_aux.vtp"),
        ],
        ".vtm",
    )
)
CASES.append(
    (
        "blocks step auto",
        [str(DATA / "step.vtp"), "--blocks", "auto", "--method", "elliptic"],
        ".vtm",
    )
)
HEXA = ["--size", "9", "8", "7"]
for name in ("hexa_bend", "hexa_bump_box"):
    for method in ([], ["--method", "elliptic"], ["--method", "tfi"], ["--orthogonal", "kmin"]):
        CASES.append(
            (
                f"hexa {name} {' '.join(method) or 'default'}",
                [str(DATA / f"{name}.vtp"), *HEXA, *method],
                ".vts",
            )
        )
CASES.append(
    (
        "hexa bump spacing trained",
        [str(DATA / "hexa_bump_box.vtp"), *HEXA, "--spacing", "kmin=0.02"],
        ".vts",
    )
)
CASES.append(
    ("hexa bend stl", [str(DATA / "hexa_bend.stl"), *HEXA, "--method", "elliptic"], ".vts")
)
for name in ("pipe", "bend"):
    CASES.append(
        (f"blockMeshDict {name} default", [str(DICTS / name / "system" / "blockMeshDict")], ".vtm")
    )


def points_hash(path: Path) -> str:
    """The hash of every block's points of the grid written at ``path``."""
    if path.suffix == ".vtm":
        reader = vtkXMLMultiBlockDataReader()
    else:
        reader = vtkXMLStructuredGridReader()
    reader.SetFileName(str(path))
    reader.Update()
    data = reader.GetOutput()
    digest = hashlib.sha256()

    def add(block) -> None:
        if block is None:
            return
        if hasattr(block, "GetNumberOfBlocks"):
            for k in range(block.GetNumberOfBlocks()):
                add(block.GetBlock(k))
        elif block.GetPoints() is not None:
            digest.update(
                np.ascontiguousarray(vtk_to_numpy(block.GetPoints().GetData()), float).tobytes()
            )

    add(data)
    return digest.hexdigest()[:16]


def run_case(args: list[str], suffix: str, out: Path) -> str:
    target = out / f"grid{suffix}"
    with (
        contextlib.redirect_stdout(io.StringIO()),
        contextlib.redirect_stderr(io.StringIO()) as err,
    ):
        try:
            code = main([*args, "-q", "-o", str(target)])
        except SystemExit as stop:
            code = stop.code
    if target.exists():
        return f"exit {code} {points_hash(target)}"
    return f"exit {code} no grid: {err.getvalue().strip().splitlines()[-1:]}"


def main_() -> None:
    torch.set_num_threads(1)
    only = sys.argv[1:]
    with tempfile.TemporaryDirectory() as tmp:
        for k, (name, args, suffix) in enumerate(CASES):
            if only and not any(word in name for word in only):
                continue
            out = Path(tmp) / str(k)
            out.mkdir()
            print(f"{name}: {run_case(args, suffix, out)}", flush=True)
        # a six-faced model saved and evaluated again
        out = Path(tmp) / "model"
        out.mkdir()
        model = out / "hexa.pt"
        base = [str(DATA / "hexa_bump_box.vtp"), *HEXA]
        if not only or any("model" in w for w in only):
            for name, extra in (("trained", ["--spacing", "kmin=0.02"]), ("start", [])):
                saved = [*base, *extra, "--save-model", str(model)]
                print(f"hexa {name} save-model: {run_case(saved, '.vts', out)}")
                loaded = [*base, "--load-model", str(model)]
                print(f"hexa {name} load-model: {run_case(loaded, '.vts', out)}")
            quad = out / "quad.pt"
            two = [str(HARD / "bump.vtp"), *SMALL, "--objective", "winslow", *TRAIN]
            print(
                f"four-sided save-model: {run_case([*two, '--save-model', str(quad)], '.vts', out)}"
            )
            print(
                f"four-sided load-model: {run_case([*two, '--load-model', str(quad)], '.vts', out)}"
            )


if __name__ == "__main__":
    main_()
