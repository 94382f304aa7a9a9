"""Six-faced 3D domains (SPEC 11): topology errors, an .stl's faces found at its
sharp edges, face nodes on the surface, orientation and right-handedness of tfi and
elliptic grids, the 3D Winslow equations, and the command line writing a readable .vts."""

from __future__ import annotations

import numpy as np
import pytest
import pyvista as pv
from helpers import ROOT, refused

from pinn_engine.hexa import volume
from pinn_engine.hexa.sharp import faces_at_sharp_edges
from pinn_engine.kinds.hexa.mesh import mesh_surface
from pinn_engine.routes.cli import main
from pinn_engine.settings import HEXA_METHODS, make_settings

DATA = ROOT / "example_data"
EXAMPLES = (  # make_hexa.py's five shapes
    "hexa_bump_box.vtp",
    "hexa_bend.vtp",
    "hexa_twisted_duct.vtp",
    "hexa_nozzle.vtp",
    "hexa_sheared_wavy.vtp",
)
SIZE = (11, 9, 7)  # small and unequal: a swapped index direction shows as a shape error
ON_SURFACE = 1e-6  # SPEC 11: boundary nodes within 1e-6 of the surface's diagonal


def _write(mesh: pv.PolyData, tmp_path, name: str) -> str:
    path = str(tmp_path / name)
    mesh.save(path)
    return path


def _corner_sums(g: np.ndarray) -> np.ndarray:
    """x + y + z of the grid's 8 corners (the input's: see the conformity test), (0, 0, 0)
    first."""
    return np.array([g[a, b, c].sum() for a in (0, -1) for b in (0, -1) for c in (0, -1)])


def test_open_surface_is_refused(tmp_path, capsys):
    mesh = pv.read(DATA / "hexa_bump_box.vtp")
    mesh = mesh.remove_cells([0])
    out = tmp_path / "o.vts"
    err = refused(capsys, [_write(mesh, tmp_path, "open.vtp"), "-o", str(out)], out)
    assert "not closed: 3 open edges" in err


def test_wrong_face_count_is_refused(tmp_path, capsys):
    mesh = pv.read(DATA / "hexa_bump_box.vtp")
    ids = np.asarray(mesh.cell_data["FaceId"]).copy()
    ids[ids == 5] = 4
    mesh.cell_data["FaceId"] = ids
    out = tmp_path / "o.vts"
    err = refused(capsys, [_write(mesh, tmp_path, "five.vtp"), "-o", str(out)], out)
    assert "5 FaceId values found" in err


def test_face_with_a_hole_is_refused(tmp_path, capsys):
    mesh = pv.read(DATA / "hexa_bump_box.vtp")
    ids = np.asarray(mesh.cell_data["FaceId"]).copy()
    centres = mesh.cell_centers().points
    floor = np.flatnonzero(ids == 4)  # make_hexa.py's faces: x = 0, x = 2, y = 0, y = 1, floor
    middle = floor[np.linalg.norm(centres[floor, :2] - [1.0, 0.5], axis=1) < 0.2]
    assert middle.size
    ids[middle] = 5  # a patch inside the floor tagged as the top: the floor is an annulus
    mesh.cell_data["FaceId"] = ids
    out = tmp_path / "o.vts"
    err = refused(capsys, [_write(mesh, tmp_path, "hole.vtp"), "-o", str(out)], out)
    assert "face 4 is not a disk (Euler characteristic 0" in err


def test_mgnet_is_refused_naming_the_working_methods(tmp_path, capsys):
    out = tmp_path / "o.vts"
    err = refused(capsys, [str(DATA / EXAMPLES[0]), "--method", "mgnet", "-o", str(out)], out)
    assert "meshed by pinn, tfi, elliptic" in err


def test_tfi_reproduces_a_trilinear_block():
    i, j, k = np.meshgrid(*(np.linspace(0, 1, n) for n in SIZE), indexing="ij")
    exact = np.stack([2 * i + 0.3 * j * k, j + 0.2 * i, k - 0.1 * i * j], axis=-1)
    boundary = exact.copy()
    boundary[1:-1, 1:-1, 1:-1] = 0.0
    np.testing.assert_allclose(volume.tfi(boundary), exact, atol=1e-12)


@pytest.fixture(scope="module", params=[(f, m) for f in EXAMPLES for m in HEXA_METHODS])
def result(request):
    name, method = request.param
    return name, method, mesh_surface(str(DATA / name), make_settings(method, size=SIZE))


def test_grids_are_right_handed_and_unfolded(result):
    _, _, r = result
    assert r.grid.shape == (*SIZE, 3)
    assert r.cells["ScaledJacobian"].min() > 0.5
    assert r.cells["Folded"].sum() == 0
    assert (r.cells["MaxIncludedAngle"] >= r.cells["MinIncludedAngle"]).all()


def test_orientation_follows_spec_11(result):
    g = result[2].grid
    assert _corner_sums(g).argmin() == 0
    leaving = [g[-1, 0, 0], g[0, -1, 0], g[0, 0, -1]] - g[0, 0, 0]
    leaving /= np.linalg.norm(leaving, axis=1, keepdims=True)
    assert leaving[:, 0].argmax() == 0
    assert np.linalg.det(leaving) > 0


def test_boundary_nodes_lie_on_the_triangles(result):
    name, _, r = result
    surface = pv.read(DATA / name)
    g = r.grid
    faces = [g[0], g[-1], g[:, 0], g[:, -1], g[:, :, 0], g[:, :, -1]]
    nodes = np.concatenate([f.reshape(-1, 3) for f in faces])
    _, closest = surface.find_closest_cell(nodes, return_closest_point=True)
    gap = np.linalg.norm(nodes - closest, axis=1).max()
    assert gap < ON_SURFACE * surface.length
    corners = [g[a, b, c] for a in (0, -1) for b in (0, -1) for c in (0, -1)]
    assert np.linalg.norm(surface.points[:, None] - np.array(corners), axis=2).min(0).max() < 1e-12


def test_elliptic_grid_satisfies_the_3d_winslow_equations(result):
    """The elliptic grid's Winslow residual is below 1e-6 of the TFI grid's on the same faces,
    and so is the default pinn's where its start is that grid (its network cannot win: its
    map is its start); the TFI grid's is not (the check can fail: it is no Winslow grid on
    these shapes)."""
    _, method, r = result
    tfi_residual = np.abs(volume.winslow_residual(volume.tfi(r.grid))).max()
    residual = np.abs(volume.winslow_residual(r.grid)).max()
    start = r.model.info["start"] if method == "pinn" else method
    assert tfi_residual > 0
    assert (residual < 1e-6 * tfi_residual) == (start == "elliptic")


def test_cli_writes_a_readable_vts(tmp_path, capsys):
    out = tmp_path / "bend.vts"
    argv = [str(DATA / "hexa_bend.vtp"), "--size", *map(str, SIZE), "--method", "tfi"]
    assert main([*argv, "-o", str(out)]) == 0
    line = capsys.readouterr().out.strip()
    assert line.startswith("tfi 11x9x7 hexahedral grid, 480 cells") and "0 folded" in line
    grid = pv.read(out)
    assert isinstance(grid, pv.StructuredGrid) and tuple(grid.dimensions) == SIZE
    for name in ("MaxIncludedAngle", "MinIncludedAngle", "ScaledJacobian", "Folded"):
        assert grid.cell_data[name].shape == (480,)
    assert list(grid.field_data["PatchNames"]) == ["imin", "imax", "jmin", "jmax", "kmin", "kmax"]
    vtk_measure = grid.cell_quality("scaled_jacobian").cell_data["scaled_jacobian"]
    np.testing.assert_allclose(grid.cell_data["ScaledJacobian"], vtk_measure)


@pytest.mark.parametrize("angles", [(130, 20, 0), (-75, 0, 160), (10, 200, 45)])
def test_a_rotated_surface_still_gives_a_right_handed_grid(tmp_path, angles):
    surface = pv.read(DATA / "hexa_bend.vtp")
    surface = surface.rotate_z(angles[0]).rotate_x(angles[1]).rotate_y(angles[2])
    path = _write(surface, tmp_path, "rotated.vtp")
    r = mesh_surface(path, make_settings("tfi", size=SIZE))
    assert r.cells["ScaledJacobian"].min() > 0.5 and r.cells["Folded"].sum() == 0
    g = r.grid
    assert _corner_sums(g).argmin() == 0
    leaving = [g[-1, 0, 0], g[0, -1, 0], g[0, 0, -1]] - g[0, 0, 0]
    assert (leaving / np.linalg.norm(leaving, axis=1, keepdims=True))[:, 0].argmax() == 0


def test_a_legacy_vtk_surface_gives_the_same_grid(tmp_path):
    legacy = _write(pv.read(DATA / "hexa_bend.vtp"), tmp_path, "bend.vtk")
    a = mesh_surface(legacy, make_settings("tfi", size=SIZE)).grid
    np.testing.assert_allclose(
        a, mesh_surface(str(DATA / "hexa_bend.vtp"), make_settings("tfi", size=SIZE)).grid
    )


def test_an_stl_gives_the_grid_of_its_tagged_twin():
    """make_hexa.py writes the bend untagged as .stl (single precision): its six faces are
    found at the 90-degree edges, and the grid is the tagged surface's."""
    stl = mesh_surface(str(DATA / "hexa_bend.stl"), make_settings("tfi", size=SIZE)).grid
    tagged = mesh_surface(str(DATA / "hexa_bend.vtp"), make_settings("tfi", size=SIZE)).grid
    np.testing.assert_allclose(stl, tagged, atol=1e-6)


def test_sharp_edges_split_a_cube_whatever_the_triangles_winding():
    cube = pv.Cube().triangulate().subdivide(2)
    tris = np.asarray(cube.faces).reshape(-1, 4)[:, 1:].copy()
    tris[::3] = tris[::3, ::-1]  # a third of the triangles wound the other way
    count, face_of = faces_at_sharp_edges(np.asarray(cube.points), tris)
    assert count == 6 and np.bincount(face_of).tolist() == [len(tris) // 6] * 6
    assert faces_at_sharp_edges(np.asarray(cube.points), tris, angle=95.0)[0] == 1  # one face


@pytest.mark.parametrize(
    ("shape", "found"),
    [(pv.Cylinder(resolution=24), 3), (pv.Tetrahedron(), 4), (pv.Sphere(), 1)],
    ids=["cylinder", "tetrahedron", "sphere"],
)
def test_an_stl_without_six_sharp_faces_is_refused(tmp_path, capsys, shape, found):
    out = tmp_path / "o.vts"
    err = refused(capsys, [_write(shape.triangulate(), tmp_path, "s.stl"), "-o", str(out)], out)
    assert err.endswith(
        f"found {found} faces at edges sharper than 40 degrees; a six-faced domain needs 6 "
        "(try a .vtp whose FaceId cell array tags the six faces)"
    )
