"""SPEC 14 on every route and every 2D kind: pyvista's ``adapt=(dataset, "ARRAY")``, the
VTK filters' Field input (port and array, as ParaView connects a reader's output), a batch
manifest's option; a body's wall and cut and a multi-block grid's corners and shared
nodes kept."""

from __future__ import annotations

import json

import numpy as np
import pytest
import pyvista as pv
from helpers import EXAMPLES
from test_adapt import front, image, write
from vtkmodules.util.numpy_support import vtk_to_numpy

from pinn_engine.adapt import Field
from pinn_engine.adapt.error import interpolation_error
from pinn_engine.adapt.nodes import node_graph
from pinn_engine.quality import cell_quality
from pinn_engine.routes.algorithm import PinnMeshAlgorithm
from pinn_engine.routes.pyvista_accessor import pinn_mesh, pinn_mesh_blocks


def wavy_field():
    return pv.wrap(image(front, (-0.3, -0.4), (4.4, 2.5)))


@pytest.mark.slow
def test_pyvista_adapt_keeps_the_grid_and_adds_the_monitor():
    boundary = pv.read(EXAMPLES / "wavy.vtp")
    plain = pinn_mesh(boundary, size=(21, 11), method="elliptic")
    grid = pinn_mesh(boundary, size=(21, 11), method="elliptic", adapt=(wavy_field(), "p"))
    assert grid.dimensions == plain.dimensions
    assert "Monitor" in grid.point_data
    p0, p1 = plain.points.reshape(11, 21, 3), grid.points.reshape(11, 21, 3)
    assert np.array_equal(p0[[0, 0, -1, -1], [0, -1, 0, -1]], p1[[0, 0, -1, -1], [0, -1, 0, -1]])
    report = json.loads(grid.field_data["Report"][0])["adaptation"]
    assert report["interpolation_error"]["after"] < report["interpolation_error"]["before"]
    with pytest.raises(ValueError, match="the arrays there are: p"):
        pinn_mesh(boundary, size=(21, 11), method="tfi", adapt=(wavy_field(), "T"))
    with pytest.raises(ValueError, match="give \\(dataset"):
        pinn_mesh(boundary, size=(21, 11), method="tfi", adapt=wavy_field())


def test_the_filters_field_input_takes_any_dataset_and_its_array():
    """As ParaView connects a reader's output (here an unstructured grid with a cell
    array and another array first) to the Field port and picks the array."""
    data = wavy_field().cast_to_unstructured_grid().point_data_to_cell_data()
    data.cell_data["other"] = np.zeros(data.n_cells)
    alg = PinnMeshAlgorithm(route="pyvista")
    alg.SetMethod("elliptic")
    alg.SetGridSize(21, 11)
    alg.SetInputDataObject(0, pv.read(EXAMPLES / "wavy.vtp"))
    alg.SetInputDataObject(alg.FIELD_PORT, data)
    alg.SetAdaptArray("0", "2", "0", "1", "p")  # ParaView's array selection: name last
    alg.SetAdaptStrength(10.0)
    alg.Update()
    assert alg.GetLastException() is None
    out = alg.GetOutput()
    assert out.GetPointData().GetArray("Monitor") is not None
    report = json.loads(out.GetFieldData().GetAbstractArray("Report").GetValue(0))
    assert report["adaptation"]["array"] == "p" and report["adaptation"]["strength"] == 10.0


@pytest.mark.slow
def test_a_c_grid_keeps_its_wall_rows_and_wake_cut():
    """A C-grid adapted to a front crossing the wake: the wall and its first row stay, the
    wake cut's two sides stay one line, counts are kept, no fold, worst within + 10."""
    from pinn_engine.adapt.grids import adapt_grids
    from pinn_engine.bodies.airfoil import circle, load_body
    from pinn_engine.kinds.body.mesh import mesh_body
    from pinn_engine.settings import make_settings

    settings = make_settings("elliptic", topology="c", farfield=3.0)
    body = load_body(naca="0012", te="sharp")
    result = mesh_body(body, circle(body, 3.0), "c", "elliptic", 121, 31, settings, 2e-3, None)
    grid = result.points
    wake = result.report["topology"]["wake_nodes"]

    def f(x, y):
        return np.tanh((x - 1.6 - 0.3 * y) / 0.05)

    field = Field(image(f, (-3.5, -3.5), (4.5, 3.5)), "p")
    held = np.zeros(grid.shape[:2], dtype=bool)
    held[:2, wake : grid.shape[1] - wake] = True
    out = adapt_grids([grid], field, 20.0, [held]).grids[0]
    assert out.shape == grid.shape
    assert np.array_equal(out[:2, wake:-wake], grid[:2, wake:-wake])
    assert np.allclose(out[0, :wake], out[0, -wake:][::-1])  # the cut's two sides coincide
    q0, q1 = cell_quality(grid), cell_quality(out)
    assert not q1["Folded"].any()
    assert q1["MaxIncludedAngle"].max() <= q0["MaxIncludedAngle"].max() + 10
    g0, g1 = node_graph([grid]), node_graph([out])
    e0 = interpolation_error(g0.points, g0.cells, lambda p: f(p[:, 0], p[:, 1]))
    e1 = interpolation_error(g1.points, g1.cells, lambda p: f(p[:, 0], p[:, 1]))
    assert e1 < e0


@pytest.mark.slow
def test_multi_block_corners_on_the_boundary_stay_and_shared_nodes_stay_shared():
    boundary = pv.read(EXAMPLES / "lshape.vtp")
    edges = pv.read(EXAMPLES / "lshape_blocks.vtp")

    def f(x, y):
        return np.tanh((np.hypot(x - 0.2, y - 0.2) - 1.0) / 0.05)

    lo, hi = np.array(boundary.bounds[::2][:2]) - 0.1, np.array(boundary.bounds[1::2][:2]) + 0.1
    field = pv.wrap(image(f, lo, hi))
    plain = pinn_mesh_blocks(boundary, edges, cell_size=0.1, method="elliptic")
    adapted = pinn_mesh_blocks(
        boundary, edges, cell_size=0.1, method="elliptic", adapt=(field, "p")
    )
    assert adapted.keys() == plain.keys()
    grids0 = [
        plain[k].points.reshape(*plain[k].dimensions[1::-1], 3)[..., :2] for k in plain.keys()
    ]
    grids1 = [
        adapted[k].points.reshape(*adapted[k].dimensions[1::-1], 3)[..., :2] for k in adapted.keys()
    ]
    graph = node_graph(grids0)
    for g0, g1 in zip(grids0, grids1):
        assert g0.shape == g1.shape
        corners = g0[[0, 0, -1, -1], [0, -1, 0, -1]]
        on_boundary = [
            np.min(np.linalg.norm(boundary.points[:, :2] - c, axis=1)) < 1e-9 for c in corners
        ]
        moved = g1[[0, 0, -1, -1], [0, -1, 0, -1]]
        assert all(np.array_equal(a, b) for a, b, on in zip(corners, moved, on_boundary) if on)
        assert not cell_quality(g1)["Folded"].any()
    merged = node_graph(grids1)
    assert len(merged.points) == len(graph.points)  # every shared node still one node
    e0 = interpolation_error(graph.points, graph.cells, lambda p: f(p[:, 0], p[:, 1]))
    e1 = interpolation_error(merged.points, merged.cells, lambda p: f(p[:, 0], p[:, 1]))
    assert e1 < e0


@pytest.mark.slow
def test_a_batch_manifest_takes_adapt_relative_to_its_folder(tmp_path):
    from pinn_engine.command import main

    folder = tmp_path / "in"
    folder.mkdir()
    write(image(front, (-0.3, -0.4), (4.4, 2.5)), folder / "field.vti")
    options = "--method elliptic --size 21 11 --adapt field.vti:p"
    (folder / "m.csv").write_text(f"name,input,aux,options\nw,{EXAMPLES / 'wavy.vtp'},,{options}\n")
    assert (
        main(["batch", str(folder / "m.csv"), "-o", str(tmp_path / "out"), "--workers", "1"]) == 0
    )
    from vtkmodules.vtkIOXML import vtkXMLStructuredGridReader

    reader = vtkXMLStructuredGridReader()
    reader.SetFileName(str(tmp_path / "out" / "w.vts"))
    reader.Update()
    monitor = reader.GetOutput().GetPointData().GetArray("Monitor")
    assert monitor is not None and vtk_to_numpy(monitor).max() > 1.0
