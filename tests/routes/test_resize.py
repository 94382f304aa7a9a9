"""A size change of a grid whose network is trained (kinds.four_sided.resize): the network
trained at one size evaluated at another under that size's guard, in pyvista and in the VTK
algorithm that ParaView runs; where the guard fails, that size's own training."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES

import pinn_engine
from pinn_engine.kinds.four_sided import problem
from pinn_engine.routes.algorithm import PinnMeshAlgorithm

# a network that trains (lines to follow under the Winslow objective), briefly
TRAINED = {"objective": "winslow", "lbfgs_iterations": 20}


@pytest.fixture
def fig2():
    return pv.read(EXAMPLES / "fig2.vtp"), pv.read(EXAMPLES / "fig2_aux.vtp")


@pytest.fixture
def passing(monkeypatch):
    """A guard this brief training's grid passes at 41 x 21 (its mean is 0.23-0.27 degrees
    above the start's there, by the iterations run, against the guard's 0.25): the forward
    pass kept, which these tests are about."""
    monkeypatch.setattr(problem, "GUARD_TOL", (0.5, 1.0))


def boundary_nodes(grid: pv.StructuredGrid, every: int = 1) -> np.ndarray:
    """The nodes of the grid's four sides, every ``every``-th of each."""
    ni, nj, _ = grid.dimensions
    p = grid.points.reshape(nj, ni, 3)[::every, ::every]
    return np.concatenate([p[0], p[-1], p[:, 0], p[:, -1]])


def test_pyvista_size_change_is_a_forward_pass_under_the_guard(fig2, passing):
    boundary, aux = fig2
    coarse = boundary.pinn_mesh(aux=aux, size=(21, 11), **TRAINED)
    fine = boundary.pinn_mesh(aux=aux, size=(41, 21), **TRAINED)
    assert boundary.pinn_mesh.trainings == 1  # the 21 x 11 network, not a new one
    report = pinn_engine.report(fine)
    resize = report["resized"]
    assert resize["result"] == "network" and resize["trained_at"] == [21, 11]
    assert resize["size"] == [41, 21] and resize["guard"]["lattice"] == [41, 21]
    network, start = resize["guard"]["network"], resize["guard"]["start"]
    mean_tol, worst_tol = problem.GUARD_TOL
    assert network["worst_max_angle"] <= start["worst_max_angle"] + worst_tol
    assert network["mean_max_angle"] <= start["mean_max_angle"] + mean_tol
    assert report["quality"]["folded_cells"] == 0
    assert report["quality"]["worst_max_angle"] == pytest.approx(network["worst_max_angle"])
    assert "trained at 21 x 11, evaluated at 41 x 21" in report["choice"]
    # the boundary nodes of the trained sides (hard mode): the coarse grid's every other one
    # (its lines' ends among them), the rest on the drawn boundary
    np.testing.assert_allclose(boundary_nodes(fine, 2), boundary_nodes(coarse), atol=1e-12)
    assert report["quality"]["boundary_deviation"] < 1e-12
    assert "resized" not in pinn_engine.report(coarse)
    again = boundary.pinn_mesh(aux=aux, size=(21, 11), **TRAINED)  # the cached network
    np.testing.assert_array_equal(again.points, coarse.points)


def test_a_size_the_guard_refuses_trains_anew(fig2, monkeypatch):
    boundary, aux = fig2
    boundary.pinn_mesh(aux=aux, size=(21, 11), **TRAINED)
    # no grid passes: the size change's guard, and every state of the new size's training
    monkeypatch.setattr(problem, "GUARD_TOL", (-90.0, -90.0))
    fine = boundary.pinn_mesh(aux=aux, size=(41, 21), **TRAINED)
    assert boundary.pinn_mesh.trainings == 2
    report = pinn_engine.report(fine)
    assert report["resized"]["result"] == "trained anew"
    assert report["resized"]["why"] == "outside the guard's bounds"
    assert report["training"]["guard"]["lattice"] == [41, 21]  # the new size's own run
    assert "the network trained at 21 x 11 failed this size's guard" in report["choice"]


def test_paraview_algorithm_grid_size_change_keeps_the_network(passing):
    alg = PinnMeshAlgorithm()
    for port, name in ((0, "fig2.vtp"), (1, "fig2_aux.vtp")):
        reader = pv.get_reader(EXAMPLES / name).reader
        alg.AddInputConnection(port, reader.GetOutputPort())
        alg._keep = [*getattr(alg, "_keep", []), reader]
    for name, value in TRAINED.items():
        alg.SetSetting(name, value)
    alg.SetGridSize(21, 11)
    alg.Update()
    assert alg.GetTrained() and alg.GetTrainingCount() == 1
    alg.SetGridSize(41, 21)
    alg.Update()
    assert not alg.GetTrained() and alg.GetTrainingCount() == 1
    grid = pv.wrap(alg.GetOutput())
    assert grid.dimensions == (41, 21, 1)
    assert pinn_engine.report(grid)["resized"]["result"] == "network"
    assert "evaluated at 41 x 21" in alg.GetLastSummary()
