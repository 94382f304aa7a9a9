"""The hold-out hard shapes: a deterministic generator, valid committed
files with their four corners found, and the benchmark's checks able to fail."""

from __future__ import annotations

import copy
import json
import sys

import numpy as np
import pytest
from helpers import ROOT

from pinn_engine.io.fileio import read_boundary_points
from pinn_engine.io.pipeline import load_boundary

HOLDOUT = ROOT / "example_data" / "holdout"
sys.path.insert(0, str(ROOT / "example_data"))
sys.path.insert(0, str(ROOT / "benchmarks"))
import holdout  # noqa: E402
import make_holdout_shapes as gen  # noqa: E402

MANIFEST = json.loads((HOLDOUT / "manifest.json").read_text())
# one of each family, and the draws that were redrawn (a rejection changes the stream's use)
REGENERATED = (0, 12, 20, 28, 40, 44)


def test_manifest_lists_the_committed_files():
    assert MANIFEST["seed"] == gen.SEED
    names = sorted(p.stem for p in HOLDOUT.glob("*.vtp"))
    assert names == sorted(MANIFEST["shapes"])
    assert len(names) == sum(gen.FAMILY_COUNTS.values()) >= 40


def test_generator_is_deterministic(tmp_path):
    written = gen.main(tmp_path, list(REGENERATED))
    assert len(written) == len(REGENERATED)
    for name, record in written.items():
        again = read_boundary_points(tmp_path / f"{name}.vtp")
        committed = read_boundary_points(HOLDOUT / f"{name}.vtp")
        np.testing.assert_allclose(again, committed, rtol=0, atol=1e-9)
        assert record == MANIFEST["shapes"][name]


@pytest.mark.parametrize("name", sorted(MANIFEST["shapes"]))
def test_committed_shape_loads_with_its_drawn_corners(name):
    boundary = load_boundary(HOLDOUT / f"{name}.vtp")
    found = boundary.frame.to_user(boundary.corner_points())
    drawn = np.array(MANIFEST["shapes"][name]["corners"])
    assert len(boundary.corners) == 4
    # the same four points, whichever the loader calls the first
    distance = np.linalg.norm(found[:, None] - drawn[None], axis=2).min(axis=1)
    assert distance.max() < 1e-6 * boundary.frame.scale


def _record() -> dict:
    """A made-up record that passes every check: the pinn grids match or beat the references."""
    grid = {"mean_max_angle": 100.0, "worst_max_angle": 150.0, "folded_cells": 0}
    return {
        "tfi": {**grid, "mean_max_angle": 105.0, "worst_max_angle": 160.0, "floor": 120.0},
        "elliptic": dict(grid),
        "pinn": {**grid, "mean_max_angle": 100.4, "worst_max_angle": 151.9},
        "quality": {**grid, "worst_max_angle": 140.0},
        "walls": {"deviation": 1.5, "folded": 0, "mean": 101.0, "worst": 150.0},
    }


def test_checks_accept_a_passing_record():
    assert holdout.passes(_record()) == {"pinn": True, "walls": True, "quality": True}


@pytest.mark.parametrize(
    "method, field, value",
    [
        ("pinn", "mean_max_angle", 100.6),  # elliptic + 0.5 exceeded
        ("pinn", "worst_max_angle", 152.1),  # elliptic worst + 2 exceeded
        ("pinn", "folded_cells", 1),  # folds where the elliptic grid does not
        ("walls", "deviation", 2.1),  # more than 2 degrees off normal
        ("walls", "folded", 1),
        ("quality", "folded_cells", 1),
        ("quality", "mean_max_angle", 100.6),
        ("quality", "worst_max_angle", 155.0),  # not below the elliptic grid's, above floor
    ],
)
def test_checks_reject_a_failing_record(method, field, value):
    record = copy.deepcopy(_record())
    record[method][field] = value
    verdict = holdout.passes(record)
    assert verdict[method] is False
    assert all(v for m, v in verdict.items() if m != method)
