"""Grids adapted to a field (SPEC 14): the option on the command line, the topology kept
(counts, corners, patches, a body's wall and cut, multi-block corners and shared nodes), the
guard, and the one-line refusals of a field that does not cover the domain and of an array
that does not exist."""

from __future__ import annotations

import json

import numpy as np
import pytest
from helpers import EXAMPLES, refused
from vtkmodules.util.numpy_support import numpy_to_vtk, vtk_to_numpy
from vtkmodules.vtkCommonDataModel import vtkImageData
from vtkmodules.vtkIOXML import vtkXMLImageDataWriter, vtkXMLStructuredGridReader

from pinn_engine.adapt import Field
from pinn_engine.adapt.error import interpolation_error
from pinn_engine.adapt.grids import GUARD_DEGREES, adapt_grids
from pinn_engine.adapt.nodes import node_graph
from pinn_engine.classical.elliptic import winslow_solve
from pinn_engine.quality import cell_quality
from pinn_engine.routes.cli import main

FINE = 301  # the field's image, points a side


def image(f, lo, hi, name="p", cells=False) -> vtkImageData:
    """``f(x, y)`` on a FINE x FINE image over the box ``lo``..``hi`` (as point data, or at
    the cell centres as cell data)."""
    im = vtkImageData()
    im.SetDimensions(FINE, FINE, 1)
    im.SetOrigin(lo[0], lo[1], 0.0)
    h = ((hi[0] - lo[0]) / (FINE - 1), (hi[1] - lo[1]) / (FINE - 1))
    im.SetSpacing(h[0], h[1], 1.0)
    n = FINE - 1 if cells else FINE
    shift = 0.5 if cells else 0.0
    x, y = np.meshgrid(lo[0] + (np.arange(n) + shift) * h[0], lo[1] + (np.arange(n) + shift) * h[1])
    arr = numpy_to_vtk(np.ascontiguousarray(f(x.ravel(), y.ravel())), deep=True)
    arr.SetName(name)
    (im.GetCellData() if cells else im.GetPointData()).AddArray(arr)
    return im


def write(im: vtkImageData, path) -> str:
    w = vtkXMLImageDataWriter()
    w.SetFileName(str(path))
    w.SetInputData(im)
    w.Write()
    return str(path)


def front(x, y):
    """A sharp curved front across the wavy example (its box: -0.15..4.2, -0.25..2.3)."""
    return np.tanh((np.hypot(x - 0.3, y - 0.1) - 2.3) / 0.08)


def read(path):
    r = vtkXMLStructuredGridReader()
    r.SetFileName(str(path))
    r.Update()
    return r.GetOutput()


def square(n: int = 21) -> np.ndarray:
    x, y = np.meshgrid(np.linspace(0, 1, n), np.linspace(0, 1, n))
    return winslow_solve(np.stack([x, y], axis=-1))[0]


@pytest.mark.slow
def test_command_line_adapts_a_four_sided_grid_keeping_its_topology(tmp_path):
    field = write(image(front, (-0.3, -0.4), (4.4, 2.5)), tmp_path / "field.vti")
    base = ["pinn-mesh", str(EXAMPLES / "wavy.vtp"), "--method", "elliptic", "--size", "41", "21"]
    assert main([*base[1:], "--quiet", "-o", str(tmp_path / "plain.vts")]) == 0
    argv = [*base[1:], "--quiet", "--adapt", f"{field}:p", "--report", str(tmp_path / "r.json")]
    assert main([*argv, "--patch", "bottom=wall", "-o", str(tmp_path / "adapted.vts")]) == 0
    plain, adapted = read(tmp_path / "plain.vts"), read(tmp_path / "adapted.vts")
    assert adapted.GetExtent() == plain.GetExtent() == (0, 40, 0, 20, 0, 0)
    p0 = vtk_to_numpy(plain.GetPoints().GetData()).reshape(21, 41, 3)
    p1 = vtk_to_numpy(adapted.GetPoints().GetData()).reshape(21, 41, 3)
    for j, i in ((0, 0), (0, -1), (-1, 0), (-1, -1)):
        assert np.array_equal(p0[j, i], p1[j, i])
    assert np.abs(p1 - p0).max() > 0.05  # the nodes moved
    names = adapted.GetFieldData().GetAbstractArray("PatchNames")
    assert [names.GetValue(k) for k in range(4)] == ["wall", "right", "top", "left"]
    monitor = vtk_to_numpy(adapted.GetPointData().GetArray("Monitor"))
    assert monitor.shape == (41 * 21,) and monitor.min() >= 1.0 and monitor.max() > 2.0
    report = json.loads((tmp_path / "r.json").read_text())["adaptation"]
    assert report["worst_max_angle"]["after"] <= report["worst_max_angle"]["before"] + 10
    assert report["folded_cells"]["after"] == 0
    error = report["interpolation_error"]
    assert error["after"] <= 0.5 * error["before"]
    cv = report["equidistribution_cv"]
    assert cv["after"] < cv["before"]
    # the analytic field's own interpolation error is cut in half too
    grid0, grid1 = p0[..., :2], p1[..., :2]
    g0 = node_graph([grid0])
    g1 = node_graph([grid1])
    e0 = interpolation_error(g0.points, g0.cells, lambda p: front(p[:, 0], p[:, 1]))
    e1 = interpolation_error(g1.points, g1.cells, lambda p: front(p[:, 0], p[:, 1]))
    assert e1 <= 0.5 * e0


@pytest.mark.slow
def test_boundary_nodes_stay_on_their_side(tmp_path):
    """Boundary nodes slide along their own side: on the drawn boundary, in order."""
    from pinn_engine.geometry.boundary import Boundary
    from pinn_engine.io.fileio import read_boundary_points

    boundary = Boundary.from_points(read_boundary_points(EXAMPLES / "wavy.vtp"))
    field = Field(image(front, (-0.3, -0.4), (4.4, 2.5)), "p")
    from pinn_engine.kinds.four_sided.mesher import Mesher
    from pinn_engine.settings import make_settings

    grid = Mesher(make_settings("elliptic", lattice=(41, 21))).fit(boundary).predict(41, 21)
    out = adapt_grids([grid.points], field).grids[0]
    sides = [out[0], out[:, -1], out[-1], out[:, 0]]
    unit = boundary.frame.to_unit(np.vstack(sides))
    assert boundary.deviation(unit).max() < 1e-3
    for before, after in zip([grid.points[0], grid.points[-1]], [out[0], out[-1]]):
        order = np.argsort(before[:, 0])
        assert np.all(np.diff(after[order, 0]) > 0)


@pytest.mark.slow
def test_guard_adapts_less_where_the_worst_cell_would_pass_its_bound():
    grid = square(13)
    oblique = Field(image(lambda x, y: np.tanh((x + y - 1.0) / 0.01), (0, 0), (1, 1)), "p")
    out = adapt_grids([grid], oblique, strength=50.0)
    q = cell_quality(out.grids[0])
    worst0 = cell_quality(grid)["MaxIncludedAngle"].max()
    assert q["MaxIncludedAngle"].max() <= worst0 + GUARD_DEGREES + 1e-9
    assert not q["Folded"].any()
    assert out.report["adapted_less"]


def test_cell_arrays_and_vectors_by_their_magnitude():
    def u(x, y):
        return np.column_stack([3 * x, 4 * x, 0 * x])

    field = Field(image(u, (0, 0), (1, 1), name="U", cells=True), "U")
    values, inside = field.probe(np.array([[0.5, 0.5], [0.25, 0.75]]))
    assert np.allclose(field.sample(np.array([[0.5, 0.5], [0.25, 0.75]])), values, atol=1e-2)
    assert inside.all()
    assert np.allclose(values, [2.5, 1.25], atol=1e-2)


def test_an_array_that_does_not_exist_is_refused_naming_the_arrays_there(capsys, tmp_path):
    field = write(image(front, (-0.3, -0.4), (4.4, 2.5)), tmp_path / "field.vti")
    out = tmp_path / "x.vts"
    argv = [str(EXAMPLES / "wavy.vtp"), "--method", "tfi", "--adapt", f"{field}:U", "-o"]
    err = refused(capsys, [*argv, str(out)], out)
    assert "has no array 'U'; the arrays there are: p (point)" in err


def test_a_field_that_does_not_cover_the_domain_is_refused(capsys, tmp_path):
    field = write(image(front, (0, 0), (2, 1)), tmp_path / "half.vti")
    out = tmp_path / "x.vts"
    argv = [str(EXAMPLES / "wavy.vtp"), "--method", "tfi", "--adapt", f"{field}:p", "-o"]
    err = refused(capsys, [*argv, str(out)], out)
    assert "does not cover the domain" in err


@pytest.mark.parametrize("spec", ["field.vti", "field.vti:"])
def test_adapt_needs_file_and_array(capsys, tmp_path, spec):
    out = tmp_path / "x.vts"
    argv = [str(EXAMPLES / "wavy.vtp"), "--adapt", spec, "-o", str(out)]
    assert "write FILE:ARRAY" in refused(capsys, argv, out)


def test_the_forms_are_tried_in_the_order_of_their_first_solves_error():
    """Each form's first solve is made before any try is guarded, and the forms are tried
    least error first (the best grid early bounds the others' guard)."""
    from pinn_engine.adapt.grids import FORMS
    from pinn_engine.adapt.parametric import ParameterSpace

    grid = square(13)
    field = Field(image(front, (-1, -1), (2, 2)), "p")
    out = adapt_grids([grid], field, strength=20.0)
    graph = node_graph([grid])
    space = ParameterSpace(graph, field.sample, out.report["worst_max_angle"]["limit"])
    errors = {}
    for curvature, isotropic, joined in FORMS:
        name = ("curvature " if curvature else "") + ("isotropic" if isotropic else "anisotropic")
        solved = space.solve(np.full(len(graph.points), 20.0), isotropic, False, curvature, joined)
        errors[name] = interpolation_error(solved.points, graph.cells, field.sample)
    tried = list(dict.fromkeys(t["form"] for t in out.report["tries"]))
    assert tried == sorted(errors, key=errors.get)
    assert tried != list(errors)  # this field's order is not the forms' own
