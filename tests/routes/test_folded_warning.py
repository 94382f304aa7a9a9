"""A 2D grid with folded cells is never handed over: it is refused in one line.

TFI folds cells on the L-shaped ``concave`` example and on none of ``fig2``: the command
line exits 2 and writes nothing, the VTK algorithm (ParaView filter) reports an error and
produces no grid, the pyvista route raises ``InputError``; the fix is in each route's words.
The warning text (``folded_cells_warning``) stays for the routes' warnings of 3D grids; no
training involved.
"""

from __future__ import annotations

import inspect
import json
import re
import warnings

import pytest
import pyvista as pv
from helpers import EXAMPLES, ROOT, OutputMessages
from vtkmodules.vtkIOXML import vtkXMLPolyDataReader

import pinn_engine
from pinn_engine.errors import FoldedCellsWarning, InputError, folded_cells_warning
from pinn_engine.io.pipeline import load_boundary
from pinn_engine.kinds.four_sided.mesher import Mesher
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.cli import build_parser, main
from pinn_engine.routes.panel import PANELS
from pinn_engine.routes.pyvista_accessor import pinn_mesh
from pinn_engine.settings import METHODS, Settings, make_settings

FOLDED, UNFOLDED = EXAMPLES / "concave.vtp", EXAMPLES / "fig2.vtp"


@pytest.fixture(scope="module")
def folded() -> int:
    """Folded cells of the 41 x 21 TFI grid of the concave example (13 when written)."""
    result = Mesher(make_settings("tfi")).fit(load_boundary(FOLDED)).predict(41, 21)
    count = result.quality["folded_cells"]
    assert count > 0
    return count


def report(
    method: str, folded_cells: int = 3, elliptic_folds: int | None = None, **settings
) -> dict:
    """A report as ``Mesher.predict`` makes it; ``elliptic_folds``: a warm-started PINN whose
    elliptic grid folds that many cells."""
    out = {
        "method": method,
        "size": [11, 6],
        "quality": {"folded_cells": folded_cells},
        "settings": make_settings(method, **settings).to_dict(),
    }
    if elliptic_folds is not None:
        out["training"] = {"guard": {"elliptic": {"folded_cells": elliptic_folds}}}
    return out


# ---------------------------------------------------------------- the text, in one place


def test_text_gives_the_count_of_all_cells_and_none_when_nothing_is_folded():
    text = folded_cells_warning(report("tfi"), "cli")
    assert text.startswith("3 of 50 cells are folded (a corner's orientation opposes the grid's)")
    assert "the grid is written anyway" in text
    assert folded_cells_warning(report("tfi", 1), "pyvista").startswith("1 of 50 cells is folded")
    assert folded_cells_warning(report("tfi", 0), "cli") is None


CASES = [
    ("tfi", {}),
    ("elliptic", {}),
    ("elliptic", {"elliptic_iterations": 1000}),
    ("pinn", {}),
    ("pinn", {"elliptic_folds": 2}),
    ("mgnet", {}),
]


def test_when_the_elliptic_grid_folds_too_the_hint_says_so():
    text = folded_cells_warning(report("pinn", elliptic_folds=2), "cli")
    assert "elliptic grid on these boundary nodes folds 2 cells as well" in text
    assert "--method" not in text and "--size" in text


@pytest.mark.parametrize(("method", "settings"), CASES)
def test_cli_hint_names_options_that_exist(method, settings):
    text = folded_cells_warning(report(method, **settings), "cli")
    options = build_parser()._option_string_actions
    named = re.findall(r"--[a-z][a-z-]*", text)
    assert named and all(flag in options for flag in named), named
    assert text.endswith("--fail-on-folded refuses such grids")
    for value in re.findall(r"--method (\w+)", text):
        assert value in METHODS and value != method


@pytest.mark.parametrize(("method", "settings"), CASES)
def test_pyvista_hint_names_keyword_arguments_that_exist(method, settings):
    text = folded_cells_warning(report(method, **settings), "pyvista")
    assert "the grid is returned anyway" in text and "--" not in text
    keywords = set(inspect.signature(pinn_mesh).parameters) | set(Settings.__dataclass_fields__)
    named = re.findall(r"(\w+)=", text)
    assert named and all(k in keywords for k in named), named


@pytest.mark.parametrize(("method", "settings"), CASES)
def test_paraview_hint_names_labels_of_the_filter_panel(method, settings):
    text = folded_cells_warning(report(method, **settings), "paraview")
    assert "the grid is produced anyway" in text and "--" not in text and "=" not in text
    plugin = (ROOT / "plugin" / "pinn_mesh_plugin.py").read_text()
    labels = set(re.findall(r'label="([^"]+)"', plugin))  # the inputs' and sources' labels
    labels |= set(re.findall(r'name="(\w+)"', plugin))  # no label: ParaView shows the name
    panels = [prop for panel in PANELS.values() for prop in panel]  # the filters' properties
    labels |= {prop.shown or prop.name for prop in panels}
    hint = text.split("; try ", 1)[1]
    named = re.findall(r"[A-Z][\w-]*(?: [A-Z][\w-]*)*", hint)  # capitalised: the labels
    assert named and all(label in labels for label in named), named
    for value in re.findall(r"Method (\w+)", hint):
        assert value in METHODS and value != method


def test_warning_class_is_exported_from_the_package():
    assert pinn_engine.FoldedCellsWarning is FoldedCellsWarning
    assert issubclass(FoldedCellsWarning, UserWarning)


# ---------------------------------------------------------------- command line


def run_cli(argv, capsys) -> tuple[int, str, str]:
    rc = main([str(a) for a in argv])
    captured = capsys.readouterr()
    return rc, captured.out, captured.err


@pytest.mark.parametrize("fail", [[], ["--fail-on-folded"]])
def test_cli_refuses_a_folded_grid_in_one_line_and_writes_nothing(folded, fail, tmp_path, capsys):
    out = tmp_path / "g.vts"
    rc, stdout, err = run_cli([FOLDED, "--method", "tfi", "-o", out, *fail], capsys)
    assert rc == 2 and not out.exists() and not list(tmp_path.iterdir()) and stdout == ""
    lines = err.strip().splitlines()
    assert len(lines) == 1, err
    assert lines[0] == (
        f"pinn-mesh: error: {FOLDED}: the grid is not written: {folded} of 800 cells are "
        "folded (a corner's orientation opposes the grid's); try --method elliptic"
    )


@pytest.mark.parametrize(("boundary", "method"), [(UNFOLDED, "tfi"), (FOLDED, "elliptic")])
def test_cli_no_warning_without_folded_cells(boundary, method, tmp_path, capsys):
    rc, _, err = run_cli(
        [boundary, "--method", method, "-o", tmp_path / "g.vts", "--quiet"], capsys
    )
    assert rc == 0 and err == ""


# ---------------------------------------------------------------- VTK algorithm, ParaView


def algorithm(path, method: str) -> tuple[PinnMeshAlgorithm, vtkXMLPolyDataReader]:
    reader = vtkXMLPolyDataReader()
    reader.SetFileName(str(path))
    alg = PinnMeshAlgorithm()
    alg.SetInputConnection(0, reader.GetOutputPort())
    alg.SetMethod(method)
    return alg, reader  # keep the reader alive with the algorithm


def test_algorithm_refuses_a_folded_grid_in_the_panels_words(folded):
    alg, _reader = algorithm(FOLDED, "tfi")
    with OutputMessages(alg, "ErrorEvent"):
        alg.Update()
    error = alg.GetLastError()
    assert f"{folded} of 800 cells are folded" in error and "try Method elliptic" in error
    assert "--" not in error and alg.GetOutput().GetNumberOfPoints() == 0
    # the next update without folded cells clears it
    alg.SetMethod("elliptic")
    alg.Update()
    assert alg.GetLastError() == "" and alg.GetOutput().GetNumberOfPoints() == 41 * 21


def test_algorithm_no_warning_without_folded_cells():
    alg, _reader = algorithm(UNFOLDED, "tfi")
    with OutputMessages(alg, "WarningEvent") as messages:
        alg.Update()
    assert alg.GetOutput().GetNumberOfPoints() == 41 * 21
    assert alg.GetLastWarning() == "" and messages.lines == [] and messages.events == []


# ---------------------------------------------------------------- pyvista


def test_pyvista_function_and_accessor_refuse_a_folded_grid(folded):
    boundary = pv.read(FOLDED)
    with pytest.raises(InputError, match=f"{folded} of 800 cells are folded") as caught:
        pinn_mesh(boundary, method="tfi")
    assert 'method="elliptic"' in str(caught.value) and "--" not in str(caught.value)
    with pytest.raises(InputError, match="1 of 50 cells is folded"):
        boundary.pinn_mesh(method="tfi", size=(11, 6))


@pytest.mark.parametrize("kind", ["hexa", "blocks"])
def test_pyvista_hexa_and_blocks_warn_at_the_callers_line(kind, monkeypatch):
    """Neither example folds, so the filter's report is made to count 2 folded cells: the
    function and the accessor warn at this file's line, through the package's frames."""
    from pinn_engine.routes.hexa_algorithm import PinnHexaAlgorithm
    from pinn_engine.routes.multiblock_algorithm import PinnMultiBlockAlgorithm
    from pinn_engine.routes.pyvista_accessor import pinn_mesh_blocks, pinn_mesh_hexa

    cls = PinnHexaAlgorithm if kind == "hexa" else PinnMultiBlockAlgorithm
    made = cls.GetOutput

    def folded_output(self):
        data = made(self)
        block = data if kind == "hexa" else data.GetBlock(0)
        report = block.GetFieldData().GetAbstractArray("Report")
        figures = json.loads(report.GetValue(0))
        (figures if kind == "hexa" else figures["multiblock"])["quality"]["folded_cells"] = 2
        report.SetValue(0, json.dumps(figures))
        return data

    monkeypatch.setattr(cls, "GetOutput", folded_output)
    if kind == "hexa":
        surface = pv.read(EXAMPLES / "hexa_bend.vtp")
        calls = (
            lambda: pinn_mesh_hexa(surface, size=(5, 5, 5), method="tfi"),
            lambda: surface.pinn_mesh(size=(5, 5, 5), method="tfi"),
        )
    else:
        boundary, edges = pv.read(EXAMPLES / "lshape.vtp"), pv.read(EXAMPLES / "lshape_blocks.vtp")
        calls = (
            lambda: pinn_mesh_blocks(boundary, edges, cell_size=0.2, method="tfi"),
            lambda: boundary.pinn_mesh(blocks=edges, cell_size=0.2, method="tfi"),
        )
    for call in calls:
        with pytest.warns(FoldedCellsWarning, match=r"^2 of \d+ cells are folded") as record:
            call()
        assert [w.filename for w in record] == [__file__]


@pytest.mark.parametrize(("boundary", "method"), [(UNFOLDED, "tfi"), (FOLDED, "elliptic")])
def test_pyvista_no_warning_without_folded_cells(boundary, method):
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        grid = pv.read(boundary).pinn_mesh(method=method)
    assert grid.n_cells == 800 and int(grid.cell_data["Folded"].sum()) == 0
