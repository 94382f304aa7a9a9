"""Quality arrays equal VTK's vtkMeshQuality (Verdict) on distorted, non-convex, folded cells."""

from __future__ import annotations

import numpy as np
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkFiltersVerdict import vtkMeshQuality

from pinn_engine import quality
from pinn_engine.classical.tfi import node_params
from pinn_engine.io.vtkgrid import structured_grid
from pinn_engine.quality import cell_quality, folded_cells, included_angles


def distorted_grid(seed: int, amount: float) -> np.ndarray:
    rng = np.random.default_rng(seed)
    xi, eta = np.meshgrid(node_params(12), node_params(9))
    grid = np.stack([3 * xi, 2 * eta], axis=-1)
    return grid + amount * rng.normal(size=grid.shape) * [3 / 11, 2 / 8]


def vtk_angles(grid: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    out = []
    for measure in ("SetQuadQualityMeasureToMaxAngle", "SetQuadQualityMeasureToMinAngle"):
        mq = vtkMeshQuality()
        mq.SetInputData(structured_grid(grid))
        getattr(mq, measure)()
        mq.Update()
        out.append(vtk_to_numpy(mq.GetOutput().GetCellData().GetArray("Quality")))
    return out[0], out[1]


def test_angles_equal_vtk_mesh_quality():
    kinds = {"convex": 0, "nonconvex": 0, "folded": 0}
    for seed, amount in [(0, 0.05), (1, 0.25), (2, 0.45), (3, 0.7)]:
        grid = distorted_grid(seed, amount)
        max_a, min_a = included_angles(grid)
        vmax, vmin = vtk_angles(grid)
        np.testing.assert_allclose(max_a.ravel(), vmax, atol=1e-9)
        np.testing.assert_allclose(min_a.ravel(), vmin, atol=1e-9)
        folded = folded_cells(grid).ravel()
        kinds["folded"] += int(folded.sum())
        kinds["nonconvex"] += int(((vmax > 180) & ~folded).sum() + ((vmax > 180) & folded).sum())
        kinds["convex"] += int((vmax < 180).sum())
    # the sample really covers distorted, non-convex and folded cells
    assert kinds["convex"] > 50 and kinds["nonconvex"] > 5 and kinds["folded"] > 5


def test_output_arrays_are_the_quality_arrays():
    grid = distorted_grid(4, 0.3)
    sg = structured_grid(grid)
    cd = sg.GetCellData()
    max_a, min_a = included_angles(grid)
    np.testing.assert_array_equal(vtk_to_numpy(cd.GetArray("MaxIncludedAngle")), max_a.ravel())
    np.testing.assert_array_equal(vtk_to_numpy(cd.GetArray("MinIncludedAngle")), min_a.ravel())
    assert sg.GetExtent() == (0, 11, 0, 8, 0, 0)


def test_folded_cell_is_counted():
    xi, eta = np.meshgrid(node_params(4), node_params(4))
    grid = np.stack([xi, eta], axis=-1)
    grid[1, 1] = [0.8, 0.8]  # an interior node pushed past the next one, at (2/3, 2/3)
    # the three cells beyond the node fold; the one behind it stays convex
    expected = np.array([[0, 1, 0], [1, 1, 0], [0, 0, 0]], dtype=bool)
    np.testing.assert_array_equal(folded_cells(grid), expected)
    assert folded_cells(np.stack([xi, eta], axis=-1)).sum() == 0


def test_bands_on_several_threads_equal_one_pass_with_the_global_orientation(monkeypatch):
    grid = distorted_grid(5, 0.3)
    grid[6:] = grid[6:, ::-1]  # the top rows are mirrored: folded against the whole grid
    whole = quality._Cells(grid)
    expected = whole.quality(whole.orientation)
    assert 0 < expected["Folded"].sum() < expected["Folded"].size / 2
    monkeypatch.setattr(quality, "BAND_CELLS", 10)
    monkeypatch.setattr(quality.os, "cpu_count", lambda: 4)
    banded = cell_quality(grid)
    assert set(banded) == set(expected)
    for name, values in expected.items():
        np.testing.assert_array_equal(banded[name], values, err_msg=name)


def test_guard_figures_are_the_summary_of_the_quality_arrays(monkeypatch):
    # guard_figures computes MaxIncludedAngle and Folded alone: the same figures as the full
    # arrays' summary, on distorted, folded and degenerate cells and on the banded path
    grids = [distorted_grid(seed, amount) for seed, amount in [(6, 0.05), (7, 0.45), (8, 0.7)]]
    grids[2][3, 4] = grids[2][3, 5]  # a zero-length edge: degenerate cells
    for grid in grids + [grids[1][::-1]]:
        whole = quality.summary(cell_quality(grid), 0.0)
        expected = {k: whole[k] for k in ("mean_max_angle", "worst_max_angle", "folded_cells")}
        assert quality.guard_figures(grid) == expected
    assert quality.guard_figures(grids[2])["folded_cells"] > 0
    monkeypatch.setattr(quality, "BAND_CELLS", 10)
    monkeypatch.setattr(quality.os, "cpu_count", lambda: 2)
    assert quality.guard_figures(grids[1]) == {
        k: quality.summary(cell_quality(grids[1]), 0.0)[k] for k in expected
    }
