"""``pinn-mesh fit`` (SPEC 16): a manifest's members fitted into one model, which meshes a new
member from the command line, from a batch manifest's options and from pyvista."""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest

from pinn_engine.command import main

SIZE = ("21", "11")


def channel(height: float, amplitude: float) -> np.ndarray:
    """A bump-and-roof channel of length 3, counter-clockwise from (0, 0)."""
    x = np.linspace(0.0, 3.0, 61)
    bottom = np.column_stack([x, height * np.exp(-(((x - 1.5) / 0.4) ** 2))])
    top = np.column_stack([x, 1 + amplitude * np.sin(2 * np.pi * x / 3)])[::-1]
    right = np.linspace(bottom[-1], top[0], 11)
    left = np.linspace(top[-1], bottom[0], 11)
    return np.vstack([bottom[:-1], right[:-1], top[:-1], left[:-1]])


def family(folder: Path, shapes: dict[str, tuple[float, float]], options: str) -> Path:
    """Members as .csv boundaries and their manifest."""
    folder.mkdir(parents=True, exist_ok=True)
    with (folder / "members.csv").open("w", newline="") as f:
        rows = csv.writer(f)
        rows.writerow(["name", "input", "aux", "options"])
        for name, (h, a) in shapes.items():
            np.savetxt(folder / f"{name}.csv", channel(h, a), delimiter=",")
            rows.writerow([name, f"{name}.csv", "", options])
    return folder / "members.csv"


TRAIN = {
    f"m{k}": (h, a)
    for k, (h, a) in enumerate((h, a) for h in (0.1, 0.2, 0.3) for a in (0.02, 0.08))
}


@pytest.mark.slow
def test_fit_then_mesh_by_the_model_on_every_route(tmp_path, capsys):
    """The command fits (exit 0, the file written, progress on stderr); the model meshes an
    unseen member from the command line (its size by default), from a batch manifest's
    options and from pyvista, each grid saying family and naming the model."""
    import pyvista as pv

    model = tmp_path / "channels.pt"
    winslow = f"--size {' '.join(SIZE)} --objective winslow"  # a family of Winslow grids
    manifest = family(tmp_path / "train", TRAIN, winslow)
    assert main(["fit", str(manifest), "-o", str(model), "--workers", "1", "--epochs", "20"]) == 0
    out = capsys.readouterr()
    assert model.is_file() and "a family of 6 four-sided grids (21 x 11)" in out.out
    assert "fitting the network" in out.err
    unseen = family(
        tmp_path / "unseen", {"u0": (0.25, 0.05)}, f"--model {model} --objective winslow"
    )
    grid = tmp_path / "u0.vts"
    argv = [str(tmp_path / "unseen" / "u0.csv"), "--model", str(model), "--objective", "winslow"]
    assert main([*argv, "-o", str(grid)]) == 0
    read = pv.read(grid)
    assert read.dimensions == (21, 11, 1)
    assert read.field_data["NetworkResult"][0] == "family"
    assert read.field_data["FamilyModel"][0] == str(model)
    assert main(["batch", str(unseen), "-o", str(tmp_path / "batch"), "--workers", "1"]) == 0
    rows = list(csv.DictReader((tmp_path / "batch" / "summary.csv").open()))
    assert rows[0]["status"] == "ok" and rows[0]["folded_cells"] == "0"
    from pinn_engine.routes.pyvista_accessor import pinn_mesh

    by_pyvista = pinn_mesh(channel(0.25, 0.05), model=str(model), objective="winslow")
    assert by_pyvista.field_data["NetworkResult"][0] == "family"
    np.testing.assert_allclose(by_pyvista.points, read.points, atol=1e-12)


def test_a_fit_of_too_few_members_exits_2_with_one_line(tmp_path, capsys):
    manifest = family(tmp_path, {"a": (0.1, 0.02), "b": (0.2, 0.02)}, "--size 21 11")
    assert main(["fit", str(manifest), "-o", str(tmp_path / "f.pt"), "--workers", "1"]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("pinn-mesh fit: error: 2 of 2 members gave a grid")
    assert not (tmp_path / "f.pt").exists()


def test_a_multiblock_run_with_a_missing_model_is_one_line(tmp_path, capsys):
    """A multi-block domain takes --model (SPEC 16's multi-block families): a missing model
    file is one line naming it, before any solve, and no grid is written."""
    from helpers import EXAMPLES

    argv = [str(EXAMPLES / "lshape.vtp"), "--blocks", str(EXAMPLES / "lshape_blocks.vtp"),
            "--model", "f.pt", "-o", str(tmp_path / "l.vtm")]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "f.pt: family model file not found" in err
    assert not (tmp_path / "l.vtm").exists()


def test_a_multiblock_family_is_fitted_and_meshes_a_member_from_the_command_line(tmp_path):
    """``pinn-mesh fit`` on multi-block members (each row's --blocks file and --cells in its
    options: make_families.py's cylinder family), then a new member by ``--model``: a .vtm
    whose blocks' field data say family and the model's file."""
    import subprocess
    import sys

    import pyvista as pv
    from helpers import EXAMPLES

    make = [sys.executable, str(EXAMPLES / "make_families.py"), str(tmp_path), "--family"]
    subprocess.run([*make, "cylinder", "--train", "3", "--unseen", "1"], check=True)
    folder, model = tmp_path / "cylinder", tmp_path / "cylinder.pt"
    assert main(["fit", str(folder / "train.csv"), "-o", str(model), "--workers", "1"]) == 0
    row = list(csv.DictReader((folder / "unseen.csv").open()))[0]
    grid = tmp_path / "u0.vtm"
    options = row["options"].replace("unseen00_blocks.vtp", str(folder / "unseen00_blocks.vtp"))
    argv = [str(folder / row["input"]), *options.split(), "--model", str(model)]
    assert main([*argv, "-o", str(grid)]) == 0
    block = pv.read(grid)[0]
    assert block.field_data["NetworkResult"][0] == "family"
    assert block.field_data["FamilyModel"][0] == str(model)
