"""Models saved by the command line and loaded by it: a four-sided model at another size, a
hexahedral one evaluated finer with its faces on the surface; each refused for another
boundary (and the hexahedral one for a method that trains no network)."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES, trained_hexa

from pinn_engine.routes.cli import main
from pinn_engine.routes.cli.outputs import save_model

SIZE = (9, 9, 9)  # the hexahedral network's training size
FINER = (13, 11, 15)  # unequal: a swapped direction in the evaluation shows as a shape error
ON_SURFACE = 1e-6  # SPEC 11: boundary nodes within 1e-6 of the surface's diagonal


@pytest.mark.slow  # a training saved by one command and loaded by another
def test_cli_pinn_with_save_and_load(tmp_path, capsys):
    model = tmp_path / "m.pt"
    args = [
        str(EXAMPLES / "wavy.vtp"),
        "--aux",
        str(EXAMPLES / "wavy_aux.vtp"),
        "--epochs",
        "60",
        "--lbfgs",
        "5",
        "--quiet",
    ]
    assert main(args + ["-o", str(tmp_path / "a.vts"), "--save-model", str(model)]) == 0
    assert (
        main(
            [
                str(EXAMPLES / "wavy.vtp"),
                "--load-model",
                str(model),
                "--size",
                "101",
                "51",
                "-o",
                str(tmp_path / "b.vts"),
                "--quiet",
            ]
        )
        == 0
    )
    assert (tmp_path / "b.vts").stat().st_size > 0
    # a model for another boundary is refused with a clear error
    assert (
        main(
            [str(EXAMPLES / "fig2.vtp"), "--load-model", str(model), "-o", str(tmp_path / "c.vts")]
        )
        == 2
    )
    assert "different boundary" in capsys.readouterr().err


@pytest.fixture(scope="module")
def saved_model(tmp_path_factory) -> str:
    """The bump box's trained network (``helpers.trained_hexa``, its guard keeping a network state),
    saved as the command line saves a model, into a folder to be made."""
    model, _ = trained_hexa("hexa_bump_box.vtp", SIZE)
    assert model.info["result"] == "network"
    path = tmp_path_factory.mktemp("model") / "m" / "bump.pt"
    save_model(model, str(path), [])
    return str(path)


def test_saved_model_evaluates_finer_with_faces_on_the_surface(saved_model, tmp_path, capsys):
    surface, out, start = EXAMPLES / "hexa_bump_box.vtp", tmp_path / "fine.vts", tmp_path / "s.vts"
    argv = [str(surface), "--size", *map(str, FINER)]
    assert main([*argv, "--load-model", saved_model, "-o", str(out)]) == 0
    assert "pinn 13x11x15 hexahedral grid" in capsys.readouterr().out
    grid = pv.read(out)
    assert tuple(grid.dimensions) == FINER and grid.cell_data["Folded"].sum() == 0
    assert grid.field_data["NetworkResult"][0] == "network"
    # the network is evaluated: the default run (its start, untrained) differs inside
    assert main([*argv, "--quiet", "-o", str(start)]) == 0
    assert pv.read(start).field_data["NetworkResult"][0] == "start"
    assert not np.allclose(grid.points, pv.read(start).points, atol=0, rtol=1e-9)
    g = np.asarray(grid.points).reshape(*FINER[::-1], 3).transpose(2, 1, 0, 3)
    faces = [g[0], g[-1], g[:, 0], g[:, -1], g[:, :, 0], g[:, :, -1]]
    nodes = np.concatenate([f.reshape(-1, 3) for f in faces])
    mesh = pv.read(surface)
    _, closest = mesh.find_closest_cell(nodes, return_closest_point=True)
    assert np.linalg.norm(nodes - closest, axis=1).max() < ON_SURFACE * mesh.length


def test_a_model_of_another_surface_or_method_is_refused(saved_model, tmp_path, capsys):
    bend, out = str(EXAMPLES / "hexa_bend.vtp"), tmp_path / "b.vts"
    assert main([bend, "--load-model", saved_model, "-o", str(out)]) == 2
    assert "trained for a different surface" in capsys.readouterr().err and not out.exists()
    assert main([bend, "--method", "tfi", "--load-model", saved_model, "-o", str(out)]) == 2
    assert "--method tfi trains no network" in capsys.readouterr().err and not out.exists()
