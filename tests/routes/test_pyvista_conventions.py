"""The pyvista route as pyvista users expect it, through the documented API only
(``PolyData.pinn_mesh``, ``pinn_engine.report``, ``pinn_engine.save``): every bad input a
``ValueError`` (a misspelt keyword a ``TypeError``: test_pyvista_public.py), pyvista's
``progress_bar``, the report as a dict, and solver files written by one public call."""

from __future__ import annotations

import inspect
import json
import re

import h5py
import pytest
import pyvista as pv
from helpers import EXAMPLES

import pinn_engine
from pinn_engine.settings import Settings

SMALL = (11, 6)  # nodes: quick, and unequal so that a swap would show


@pytest.fixture
def boundary() -> pv.PolyData:
    return pv.read(EXAMPLES / "fig2.vtp")


@pytest.mark.parametrize(
    ("keywords", "message"),
    [
        ({"method": "TFI2"}, r"^method 'TFI2': use pinn, mgnet, tfi, elliptic$"),
        ({"size": (1, 5)}, r"^size=\(1, 5\): each side must have 2"),
        ({"size": (5, 5, 5)}, r"three sizes need a six-faced surface .* give size=\(ni, nj\)$"),
        ({"cell_size": 0.1}, r"^cell_size= applies to multi-block domains \(with blocks=\)$"),
        ({"corners": (0, 1, 2)}, r"^corners: give four point indices"),
    ],
)
def test_every_bad_input_is_a_value_error_in_one_line(boundary, keywords, message):
    with pytest.raises(ValueError, match=message) as caught:
        boundary.pinn_mesh(method=keywords.pop("method", "tfi"), **keywords)
    assert isinstance(caught.value, pinn_engine.InputError)
    text = str(caught.value)
    assert "\n" not in text and "Settings" not in text and "__init__" not in text


def test_a_surface_without_face_ids_given_two_sizes_is_told_to_give_three():
    surface = pv.read(EXAMPLES / "hexa_bend.stl")  # an STL: no FaceId array
    with pytest.raises(ValueError, match=r"^size=\(21, 21\): a six-faced surface takes three"):
        surface.pinn_mesh(size=(21, 21))


def test_a_bad_curve_is_a_value_error_too():
    open_line = pv.Line((0, 0, 0), (1, 0, 0))
    with pytest.raises(ValueError, match="close"):
        open_line.pinn_mesh(size=SMALL, method="tfi")


def test_the_keywords_are_explicit_and_documented():
    call = pv.PolyData.pinn_mesh.__call__
    parameters = inspect.signature(call).parameters
    doc = inspect.getdoc(call)
    for name in ("aux", "size", "method", "blocks", "patches", "progress_bar", "adam_epochs"):
        assert name in parameters and re.search(rf"^{name}\b", doc, re.MULTILINE), name
    assert parameters["progress_bar"].default is False  # pyvista's filters' default
    assert "help(pinn_mesh)" not in doc and "are those of" not in doc


def test_the_documented_training_defaults_are_the_real_ones():
    doc = inspect.getdoc(pv.PolyData.pinn_mesh.__call__)
    defaults = Settings()
    assert (
        f"default {defaults.adam_epochs} Adam epochs and {defaults.lbfgs_iterations} L-BFGS"
        in " ".join(doc.split())
    )


def test_progress_bar_shows_pyvista_s_bar(boundary, capsys):
    grid = boundary.pinn_mesh(size=SMALL, method="elliptic", progress_bar=True)
    assert grid.dimensions == (*SMALL, 1)
    bar = capsys.readouterr().err
    assert "PINN Structured Mesh" in bar and "100%" in bar
    boundary.pinn_mesh(size=SMALL, method="elliptic")
    assert "100%" not in capsys.readouterr().err  # silent by default, as pyvista's filters


def test_the_report_is_a_dict_and_stays_in_the_field_data(boundary, tmp_path):
    grid = boundary.pinn_mesh(size=SMALL, method="elliptic")
    report = pinn_engine.report(grid)
    assert report == json.loads(grid.field_data["Report"][0])  # kept for files
    assert report["size"] == list(SMALL) and report["quality"]["folded_cells"] == 0
    assert boundary.pinn_mesh.report == report
    grid.save(tmp_path / "g.vts")
    assert pinn_engine.report(pv.read(tmp_path / "g.vts")) == report
    with pytest.raises(ValueError, match="no Report field data"):
        pinn_engine.report(pv.ImageData(dimensions=(2, 2, 2)))


def test_save_writes_su2_and_cgns_with_the_patches(boundary, tmp_path):
    grid = boundary.pinn_mesh(size=SMALL, method="tfi", patches={"bottom": "wall"})
    su2 = pinn_engine.save(grid, tmp_path / "g.su2", patches={"top": "lid"})  # names anew
    text = open(su2).read()
    assert sorted(re.findall(r"MARKER_TAG=\s*(\S+)", text)) == ["bottom", "left", "lid", "right"]
    assert re.search(r"NELEM=\s*50\b", text)  # (11 - 1) x (6 - 1) cells
    cgns = pinn_engine.save(grid, tmp_path / "g.cgns")
    with h5py.File(cgns, "r") as f:
        assert f["Base/Zone/ data"][()][0].tolist() == list(SMALL)
        assert set(f["Base/Zone/ZoneBC"]) == {"wall", "right", "top", "left"}
