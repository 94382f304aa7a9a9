"""One contract for every domain kind, as scikit-learn's estimator checks are one for every
estimator: the kinds of the registry (``job.KINDS``: the four-sided block, the O- and
C-grids around a body, the multi-block domain, the hexahedral grid and a blockMeshDict's
blocks) go through the command line, and the same
checks run on what comes out: the grids' arrays (SPEC 3 and 11), the report, and the
warnings."""

from __future__ import annotations

import contextlib
import io
import json

import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES

from pinn_engine import job
from pinn_engine.routes.cli import main

CELL_ARRAYS = ("MaxIncludedAngle", "MinIncludedAngle", "ScaledJacobian", "Folded")
FIGURES = ("mean_max_angle", "worst_max_angle", "worst_min_angle", "folded_cells")
QUICK = ["--lbfgs", "10"]  # a short training: the contract is about the output, not its quality

# each case: its input arguments (small grids), the output's suffix, its index arrays
KINDS = {
    "four-sided": (
        [str(EXAMPLES / "fig2.vtp"), "--aux", str(EXAMPLES / "fig2_aux.vtp"), "--size", "21", "11"],
        ".vts",
        ("i", "j"),
    ),
    "o-grid": (["--naca", "0012", "--topology", "o", "--size", "41", "17"], ".vts", ("i", "j")),
    "c-grid": (["--naca", "0012", "--topology", "c", "--size", "61", "17"], ".vts", ("i", "j")),
    "multi-block": (
        [str(EXAMPLES / "lshape.vtp"), "--blocks", str(EXAMPLES / "lshape_blocks.vtp")]
        + ["--cell-size", "0.25"],
        ".vtm",
        ("i", "j"),
    ),
    "hexahedral": (
        [str(EXAMPLES / "hexa_bump_box.vtp"), "--size", "7", "7", "7"],
        ".vts",
        ("i", "j", "k"),
    ),
    "blockMeshDict": (
        [str(EXAMPLES / "blockmesh" / "bend" / "system" / "blockMeshDict")],
        ".vtm",
        ("i", "j", "k"),
    ),
}
# the registered kind (``job.KINDS``) each case is
REGISTERED = {
    "four-sided": "four-sided",
    "o-grid": "body",
    "c-grid": "body",
    "multi-block": "blocks",
    "hexahedral": "hexa",
    "blockMeshDict": "dictionary",
}
# the 3D kinds take no --lbfgs yet
UNTRAINED = {"hexahedral", "blockMeshDict"}
METHODS = ["elliptic", pytest.param("pinn", marks=pytest.mark.slow)]


@pytest.fixture(scope="module", params=sorted(KINDS))
def kind(request):
    return request.param


@pytest.fixture(scope="module", params=METHODS)
def run(kind, request, tmp_path_factory):
    """The kind meshed by the method from the command line, once for the three checks: its
    grids, its report and what it wrote on stderr."""
    args, suffix, index = KINDS[kind]
    folder = tmp_path_factory.mktemp("contract")
    out, report = folder / f"grid{suffix}", folder / "report.json"
    quick = request.param == "pinn" and kind not in UNTRAINED
    method = ["--method", request.param] + (QUICK if quick else [])
    with contextlib.redirect_stderr(io.StringIO()) as err:
        assert main([*args, *method, "-o", str(out), "--report", str(report), "--quiet"]) == 0
    data = pv.read(out)
    grids = list(data) if isinstance(data, pv.MultiBlock) else [data]
    return request.param, index, grids, json.loads(report.read_text()), err.getvalue()


def _figures(grids: list) -> dict[str, float]:
    """The quality figures of SPEC 6 computed from the grids' own cell arrays."""
    largest = np.concatenate([g.cell_data["MaxIncludedAngle"] for g in grids])
    smallest = np.concatenate([g.cell_data["MinIncludedAngle"] for g in grids])
    folded = np.concatenate([g.cell_data["Folded"] for g in grids])
    return {
        "mean_max_angle": float(largest.mean()),
        "worst_max_angle": float(largest.max()),
        "worst_min_angle": float(smallest.min()),
        "folded_cells": int(folded.sum()),
    }


def test_the_grids_carry_the_arrays_of_spec_3_and_11(run):
    """Structured grids with the four cell arrays (a value a cell, the smallest angle under
    the largest, Folded 0 or 1), the structured indices as point arrays, and the method and
    figures of their own cells as field data."""
    method, index, grids, _, _ = run
    for grid in grids:
        assert isinstance(grid, pv.StructuredGrid)
        for name in CELL_ARRAYS:
            assert grid.cell_data[name].shape == (grid.n_cells,), name
        assert np.all(grid.cell_data["MinIncludedAngle"] <= grid.cell_data["MaxIncludedAngle"])
        assert set(np.unique(grid.cell_data["Folded"])) <= {0, 1}
        for axis, name in enumerate(index):  # i fastest, then j, then k
            nodes = np.asarray(grid.point_data[name]).reshape(grid.dimensions[::-1])
            assert np.array_equal(nodes, np.indices(grid.dimensions[::-1])[2 - axis]), name
        assert str(grid.field_data["Method"][0]) == method
        own = _figures([grid])
        for name in FIGURES:
            assert grid.field_data[name][0] == pytest.approx(own[name], abs=1e-9), name
        json.loads(str(grid.field_data["Report"][0]))


def test_the_report_says_the_method_and_the_figures_of_the_whole_grid(run):
    """The report (``--report``) names the method, its quality figures are those of all the
    grids' cells together, and a pinn run says what its training did."""
    method, _, grids, report, _ = run
    assert report["method"] == method
    whole = _figures(grids)
    for name in FIGURES:
        assert report["quality"][name] == pytest.approx(whole[name], abs=1e-9), name
    if method == "pinn":  # each grid's (one a block) kept state, and a kept start moved no node
        training = report["training"]
        entries = training["blocks"] if "blocks" in training else [training]
        for entry in entries:
            assert entry["result"] in ("network", "start")
            assert (entry["result"] == "start") == (entry["largest_node_move"] == 0.0)
            assert "skipped" not in entry or entry["result"] == "start"
        if "blocks" in training:
            kept = sum(entry["result"] == "network" for entry in entries)
            assert training["network_blocks"] == kept


def test_a_warning_comes_exactly_with_folded_cells(run):
    """The command warns (a ``pinn-mesh: warning:`` line, even with --quiet) when and only
    when the grid has folded cells: none of these small examples folds, so none warns."""
    _, _, grids, report, err = run
    folded = _figures(grids)["folded_cells"]
    assert folded == report["quality"]["folded_cells"] == 0
    assert ("pinn-mesh: warning:" in err) == (folded > 0)


def test_the_contract_covers_every_registered_kind():
    """A kind added to the registry is one case here too: the cases are every kind of
    ``job.KINDS``, no more."""
    assert set(REGISTERED) == set(KINDS)
    assert set(REGISTERED.values()) == set(job.KINDS)
